//! The GNG3D paper's error measures: vertex-to-nearest-vertex E_avg/E_max and area difference E_sur.

use crate::frame::Frame;
use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use mesh::TriMesh;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The paper's vertex errors, in squared model units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct VertexErrors {
    /// Mean over original vertices of the squared distance to the nearest simplified vertex.
    pub e_avg: f64,
    /// Maximum over original vertices of the squared distance to the nearest simplified vertex.
    pub e_max: f64,
}

/// A kd-tree over simplified vertices, reusable for many E_avg/E_max evaluations. The tree
/// holds the points scaled by a power of two near their diagonal (and centred when they lie
/// off the origin), so its f32 squared distances neither underflow nor overflow at any model
/// scale.
pub struct NearestVertexIndex {
    frame: Frame,
    points: Vec<Vec3>,
    tree: Option<ImmutableKdTree<f32, 3>>,
}

impl NearestVertexIndex {
    /// Index the given simplified vertex positions.
    pub fn new(simplified: &[Vec3]) -> NearestVertexIndex {
        NearestVertexIndex::in_frame(simplified, Frame::of_points(simplified, &[]))
    }

    /// Index `simplified` held in `frame`.
    fn in_frame(simplified: &[Vec3], frame: Frame) -> NearestVertexIndex {
        let local: Vec<[f32; 3]> = simplified
            .iter()
            .map(|&p| frame.to_frame(p).as_vec3().to_array())
            .collect();
        // Construction only fails for an empty slice, which is represented as `None`.
        let tree = ImmutableKdTree::new_from_slice(&local).ok();
        NearestVertexIndex {
            frame,
            points: simplified.to_vec(),
            tree,
        }
    }

    /// Squared distance from `p` to the nearest indexed vertex (model units², computed in f64
    /// from the two f32 points) and that vertex's index (`None` when the index is empty).
    pub fn nearest(&self, p: Vec3) -> Option<(f64, u32)> {
        let q = self.frame.to_frame(p).as_vec3();
        let n = self
            .tree
            .as_ref()?
            .query(&q.to_array())
            .nearest_one::<SquaredEuclidean<f32>>()
            .execute();
        let d2 = |i: usize| (p.as_dvec3() - self.points[i].as_dvec3()).length_squared();
        let item = if n.distance.is_finite() {
            n.item as usize
        } else {
            // Beyond the f32 range of the frame: an exact scan.
            (0..self.points.len()).min_by(|&a, &b| d2(a).total_cmp(&d2(b)))?
        };
        Some((d2(item), item as u32))
    }
}

/// E_avg and E_max of `original` vertices against `simplified` vertices (both plain point sets).
///
/// Returns `None` when either set is empty. Distances are exact squared Euclidean distances
/// between f32 points, accumulated in f64; the result is independent of thread count. The
/// nearest vertices are searched in a frame scaled to the original's extent, so the figures
/// hold at any model scale.
pub fn vertex_errors(original: &[Vec3], simplified: &[Vec3]) -> Option<VertexErrors> {
    if original.is_empty() || simplified.is_empty() {
        return None;
    }
    let index = NearestVertexIndex::in_frame(simplified, Frame::of_points(original, simplified));
    let (sum, max) = original
        .par_chunks(4096)
        .map(|chunk| {
            let mut sum = 0.0f64;
            let mut max = 0.0f64;
            for &p in chunk {
                let (d, _) = index.nearest(p)?;
                sum += d;
                max = max.max(d);
            }
            Some((sum, max))
        })
        .collect::<Option<Vec<_>>>()?
        .into_iter()
        .fold((0.0, 0.0f64), |(s, m), (cs, cm)| (s + cs, m.max(cm)));
    Some(VertexErrors {
        e_avg: sum / original.len() as f64,
        e_max: max,
    })
}

/// The paper's area error: `E_sur = S_K − S_A` (original minus simplified surface area), kept
/// signed in `e_sur_signed` and absolute in `e_sur_abs` so the two are never confused.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SurfaceError {
    /// Signed area difference `S_K − S_A`, squared model units (positive: the simplified mesh
    /// lost area).
    pub e_sur_signed: f64,
    /// `|S_K − S_A|`, squared model units.
    pub e_sur_abs: f64,
    /// `|S_K − S_A| / S_K` (0 when the original has no area).
    pub e_sur_relative: f64,
    /// Original surface area `S_K`.
    pub original_area: f64,
    /// Simplified surface area `S_A`.
    pub simplified_area: f64,
}

/// Surface area in f64, skipping faces with out-of-range indices.
fn checked_area(mesh: &TriMesh) -> f64 {
    let p = &mesh.positions;
    mesh.triangles
        .iter()
        .filter_map(|t| {
            let a = p.get(t[0] as usize)?.as_dvec3();
            let b = p.get(t[1] as usize)?.as_dvec3();
            let c = p.get(t[2] as usize)?.as_dvec3();
            Some(0.5 * (b - a).cross(c - a).length())
        })
        .sum()
}

/// E_sur of `simplified` against `original` (areas accumulated in f64).
pub fn surface_error(original: &TriMesh, simplified: &TriMesh) -> SurfaceError {
    let s_k = checked_area(original);
    let s_a = checked_area(simplified);
    let e_sur = s_k - s_a;
    SurfaceError {
        e_sur_signed: e_sur,
        e_sur_abs: e_sur.abs(),
        e_sur_relative: if s_k > 0.0 { e_sur.abs() / s_k } else { 0.0 },
        original_area: s_k,
        simplified_area: s_a,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surface_error_of_scaled_sphere() {
        let m = mesh::procedural::icosphere(2);
        let scaled = TriMesh::new(
            m.positions.iter().map(|p| *p * 0.5).collect(),
            m.triangles.clone(),
        );
        let e = surface_error(&m, &scaled);
        // Scaling by 1/2 quarters the area.
        assert!((e.e_sur_signed - 0.75 * m.area()).abs() < 1e-9 * m.area());
        assert!((e.e_sur_relative - 0.75).abs() < 1e-9);
        let back = surface_error(&scaled, &m);
        assert!((back.e_sur_signed + 3.0 * scaled.area()).abs() < 1e-9 * m.area());
        assert_eq!(back.e_sur_abs, -back.e_sur_signed);
    }

    fn brute(original: &[Vec3], simplified: &[Vec3]) -> VertexErrors {
        let d: Vec<f64> = original
            .iter()
            .map(|p| {
                simplified
                    .iter()
                    .map(|q| (p.as_dvec3() - q.as_dvec3()).length_squared())
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        VertexErrors {
            e_avg: d.iter().sum::<f64>() / d.len() as f64,
            e_max: d.iter().cloned().fold(0.0, f64::max),
        }
    }

    #[test]
    fn matches_brute_force_on_pseudo_random_points() {
        let mut state = 0x2545F4914F6CDD1Du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let original: Vec<Vec3> = (0..3000)
            .map(|_| Vec3::new(next(), next(), next()))
            .collect();
        let simplified: Vec<Vec3> = (0..200)
            .map(|_| Vec3::new(next(), next(), next()))
            .collect();
        let fast = vertex_errors(&original, &simplified).unwrap();
        let slow = brute(&original, &simplified);
        assert!((fast.e_avg - slow.e_avg).abs() <= 1e-9 * slow.e_avg.max(1e-12));
        assert_eq!(fast.e_max, slow.e_max);
    }

    #[test]
    fn identical_sets_have_zero_error_and_empty_sets_none() {
        let pts = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let e = vertex_errors(&pts, &pts).unwrap();
        assert_eq!(e.e_avg, 0.0);
        assert_eq!(e.e_max, 0.0);
        assert!(vertex_errors(&pts, &[]).is_none());
        assert!(vertex_errors(&[], &pts).is_none());
    }
}

//! Triangle shape quality: per-triangle minimum angle and aspect ratio
//! `R / (2r)` (circumradius over twice the inradius: 1 for an equilateral triangle, growing
//! without bound as the triangle flattens).

use mesh::TriMesh;
use serde::{Deserialize, Serialize};

/// Upper edges of the aspect-ratio histogram bins; the last bin is open-ended.
const ASPECT_EDGES: [f64; 6] = [1.5, 2.0, 3.0, 5.0, 10.0, 100.0];

/// One aspect-ratio histogram bin `[from, to)`; `to = None` is unbounded (incl. degenerate).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AspectBin {
    /// Inclusive lower edge.
    pub from: f64,
    /// Exclusive upper edge, `None` for the last bin.
    pub to: Option<f64>,
    /// Triangles in the bin.
    pub count: usize,
}

/// Shape statistics of all triangles of a mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TriangleQuality {
    /// Number of triangles.
    pub faces: usize,
    /// Triangles with zero area or a zero-length edge (excluded from the angle/aspect figures
    /// except the last histogram bin).
    pub degenerate: usize,
    /// Smallest minimum angle over non-degenerate triangles, degrees.
    pub min_angle_degrees: f64,
    /// Mean of the per-triangle minimum angle, degrees (60 for all-equilateral).
    pub mean_min_angle_degrees: f64,
    /// Median of the per-triangle minimum angle over non-degenerate triangles, degrees (the
    /// lower middle value for an even count; 0 when there is none).
    pub median_min_angle_degrees: f64,
    /// Share of non-degenerate triangles with a minimum angle below 10°.
    pub below_10_degrees: f64,
    /// Share of non-degenerate triangles with a minimum angle below 20° (a common "bad
    /// triangle" threshold in meshing).
    pub below_20_degrees: f64,
    /// Share of non-degenerate triangles with a minimum angle below 30°.
    pub below_30_degrees: f64,
    /// Mean aspect ratio `R/(2r)` over non-degenerate triangles.
    pub mean_aspect_ratio: f64,
    /// Largest aspect ratio over non-degenerate triangles.
    pub max_aspect_ratio: f64,
    /// Histogram of aspect ratios (degenerate triangles in the last bin).
    pub aspect_histogram: Vec<AspectBin>,
}

/// Minimum interior angle (degrees) and aspect ratio of a triangle with the given corners, or
/// `None` when it is degenerate.
fn shape(a: glam::DVec3, b: glam::DVec3, c: glam::DVec3) -> Option<(f64, f64)> {
    let (la, lb, lc) = ((b - c).length(), (c - a).length(), (a - b).length());
    let s = 0.5 * (la + lb + lc);
    let (x, y, z) = (s - la, s - lb, s - lc);
    let area2 = (b - a).cross(c - a).length(); // twice the area
    if !(la > 0.0 && lb > 0.0 && lc > 0.0 && area2 > 0.0 && x > 0.0 && y > 0.0 && z > 0.0) {
        return None;
    }
    // Angle opposite the shortest side via atan2(|cross|, dot): accurate for slivers too.
    let angle = |p: glam::DVec3, q: glam::DVec3, r: glam::DVec3| {
        let (u, v) = (q - p, r - p);
        u.cross(v).length().atan2(u.dot(v)).to_degrees()
    };
    let min_angle = angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b));
    let aspect = la * lb * lc / (8.0 * x * y * z);
    aspect.is_finite().then_some((min_angle, aspect))
}

/// Triangle shape statistics of `mesh` (faces must index valid vertices; others are skipped).
pub fn triangle_quality(mesh: &TriMesh) -> TriangleQuality {
    let mut degenerate = 0usize;
    let mut n = 0usize;
    let mut min_angle = f64::INFINITY;
    let mut sum_angle = 0.0;
    let mut below10 = 0usize;
    let mut below20 = 0usize;
    let mut angles: Vec<f64> = Vec::with_capacity(mesh.triangles.len());
    let mut below30 = 0usize;
    let mut sum_aspect = 0.0;
    let mut max_aspect = 0.0f64;
    let mut bins = vec![0usize; ASPECT_EDGES.len() + 1];
    for t in &mesh.triangles {
        let corner = |v: u32| mesh.positions.get(v as usize).map(|p| p.as_dvec3());
        let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
            degenerate += 1;
            continue;
        };
        match shape(a, b, c) {
            None => {
                degenerate += 1;
                bins[ASPECT_EDGES.len()] += 1;
            }
            Some((angle, aspect)) => {
                n += 1;
                min_angle = min_angle.min(angle);
                sum_angle += angle;
                below10 += usize::from(angle < 10.0);
                below20 += usize::from(angle < 20.0);
                angles.push(angle);
                below30 += usize::from(angle < 30.0);
                sum_aspect += aspect;
                max_aspect = max_aspect.max(aspect);
                let bin = ASPECT_EDGES
                    .iter()
                    .position(|&e| aspect < e)
                    .unwrap_or(ASPECT_EDGES.len());
                bins[bin] += 1;
            }
        }
    }
    let share = |k: usize| if n > 0 { k as f64 / n as f64 } else { 0.0 };
    let aspect_histogram = bins
        .iter()
        .enumerate()
        .map(|(i, &count)| AspectBin {
            from: if i == 0 { 1.0 } else { ASPECT_EDGES[i - 1] },
            to: ASPECT_EDGES.get(i).copied(),
            count,
        })
        .collect();
    let median = if angles.is_empty() {
        0.0
    } else {
        let mid = (angles.len() - 1) / 2;
        *angles.select_nth_unstable_by(mid, f64::total_cmp).1
    };
    TriangleQuality {
        faces: mesh.triangles.len(),
        degenerate,
        min_angle_degrees: if n > 0 { min_angle } else { 0.0 },
        mean_min_angle_degrees: if n > 0 { sum_angle / n as f64 } else { 0.0 },
        median_min_angle_degrees: median,
        below_10_degrees: share(below10),
        below_20_degrees: share(below20),
        below_30_degrees: share(below30),
        mean_aspect_ratio: if n > 0 { sum_aspect / n as f64 } else { 0.0 },
        max_aspect_ratio: max_aspect,
        aspect_histogram,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn known_triangles() {
        let h = 3f32.sqrt() / 2.0;
        let mesh = TriMesh::new(
            vec![
                // Equilateral.
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.5, h, 0.0),
                // Right isosceles: min angle 45°, R = hyp/2 = √2/2, r = (2 - √2)/2.
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::new(0.0, 1.0, 1.0),
                // Collinear (degenerate).
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::new(1.0, 0.0, 2.0),
                Vec3::new(2.0, 0.0, 2.0),
            ],
            vec![[0, 1, 2], [3, 4, 5], [6, 7, 8]],
        );
        let q = triangle_quality(&mesh);
        assert_eq!(q.faces, 3);
        assert_eq!(q.degenerate, 1);
        assert!((q.min_angle_degrees - 45.0).abs() < 1e-4);
        assert!((q.mean_min_angle_degrees - 52.5).abs() < 1e-4);
        let right = (2f64.sqrt() / 2.0) / (2.0 - 2f64.sqrt());
        assert!((q.max_aspect_ratio - right).abs() < 1e-5);
        assert!((q.mean_aspect_ratio - (1.0 + right) / 2.0).abs() < 1e-5);
        // Both the equilateral (1) and the right isosceles (~1.21) are in [1, 1.5).
        assert!(right < 1.5);
        assert_eq!(q.aspect_histogram[0].count, 2);
        assert_eq!(q.aspect_histogram[0].from, 1.0);
        assert_eq!(q.aspect_histogram.iter().map(|b| b.count).sum::<usize>(), 3);
        assert_eq!(q.aspect_histogram.last().unwrap().count, 1);
        assert_eq!(q.aspect_histogram.last().unwrap().to, None);
        assert_eq!(q.below_10_degrees, 0.0);
        // Two non-degenerate triangles (60°, 45°): the lower middle value is 45°.
        assert!((q.median_min_angle_degrees - 45.0).abs() < 1e-4);
        assert_eq!(q.below_20_degrees, 0.0);
    }

    #[test]
    fn median_and_share_below_20_degrees_match_a_direct_count() {
        // A fan of slivers and fat triangles with known minimum angles.
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        let mut expected = Vec::new();
        for (k, &deg) in [5.0f64, 15.0, 25.0, 35.0, 45.0].iter().enumerate() {
            // Isosceles with apex angle `deg` (< 60°, so it is the minimum angle).
            let half = (deg / 2.0).to_radians();
            let z = k as f32 * 3.0;
            let base = positions.len() as u32;
            positions.push(glam::Vec3::new(0.0, 0.0, z));
            positions.push(glam::Vec3::new(half.cos() as f32, half.sin() as f32, z));
            positions.push(glam::Vec3::new(half.cos() as f32, -half.sin() as f32, z));
            triangles.push([base, base + 1, base + 2]);
            expected.push(deg);
        }
        let q = triangle_quality(&TriMesh::new(positions, triangles));
        assert!((q.median_min_angle_degrees - 25.0).abs() < 1e-3, "{q:?}");
        assert!((q.below_20_degrees - 2.0 / 5.0).abs() < 1e-12);
        assert!((q.below_10_degrees - 1.0 / 5.0).abs() < 1e-12);
    }
}

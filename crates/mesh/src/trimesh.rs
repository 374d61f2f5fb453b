//! The shared triangle mesh type and its basic geometric queries.

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

/// Axis-aligned bounding box in model units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (min = +inf, max = -inf); growing it by any point gives that point.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// Smallest box holding all `points` (`EMPTY` for none).
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> Aabb {
        points.into_iter().fold(Aabb::EMPTY, |b, p| b.grown(*p))
    }

    /// This box extended to contain `p`.
    pub fn grown(self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// True when no point has been added.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// Edge lengths (zero for an empty box).
    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// Length of the diagonal in model units (0 for an empty box), computed in f64.
    pub fn diagonal(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        // Subtract in f64: near ±f32::MAX the f32 extent overflows to infinity.
        (self.max.as_dvec3() - self.min.as_dvec3()).length()
    }

    /// Centre point.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
}

/// An indexed triangle mesh: `f32` positions and counter-clockwise `u32` triangles.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TriMesh {
    /// Vertex positions in model units.
    pub positions: Vec<Vec3>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// A mesh from positions and triangles (no validation; see [`crate::sampling::validate`]).
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> TriMesh {
        TriMesh {
            positions,
            triangles,
        }
    }

    /// Number of vertex records (including unreferenced ones).
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.triangles.len()
    }

    /// One past the largest vertex index the triangles use (0 without triangles): the length of
    /// a per-vertex table that every corner can index, whatever `positions` holds.
    pub(crate) fn index_bound(&self) -> usize {
        self.triangles
            .iter()
            .flatten()
            .max()
            .map_or(0, |&m| m as usize + 1)
    }

    /// The three corner positions of triangle `face`.
    #[inline]
    pub fn triangle(&self, face: usize) -> [Vec3; 3] {
        let [a, b, c] = self.triangles[face];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// The three corners of triangle `face` in f64.
    #[inline]
    pub fn triangle_f64(&self, face: usize) -> [DVec3; 3] {
        let [a, b, c] = self.triangle(face);
        [a.as_dvec3(), b.as_dvec3(), c.as_dvec3()]
    }

    /// Area of triangle `face` in squared model units, computed in f64.
    #[inline]
    pub fn triangle_area(&self, face: usize) -> f64 {
        let [a, b, c] = self.triangle_f64(face);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Total surface area in squared model units (f64 accumulation).
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|f| self.triangle_area(f))
            .sum()
    }

    /// Bounding box of all vertex records.
    pub fn bounding_box(&self) -> Aabb {
        Aabb::from_points(&self.positions)
    }

    /// Bounding box of the vertices referenced by at least one triangle.
    pub fn referenced_bounding_box(&self) -> Aabb {
        let mut used = vec![false; self.positions.len()];
        for t in &self.triangles {
            for &v in t {
                used[v as usize] = true;
            }
        }
        Aabb::from_points(
            self.positions
                .iter()
                .zip(&used)
                .filter(|(_, u)| **u)
                .map(|(p, _)| p),
        )
    }

    /// Diagonal of the bounding box of referenced vertices, in model units.
    pub fn bbox_diagonal(&self) -> f64 {
        self.referenced_bounding_box().diagonal()
    }

    /// Unit normal of each triangle (zero for degenerate triangles).
    pub fn face_normals(&self) -> Vec<Vec3> {
        (0..self.triangles.len())
            .map(|f| {
                let [a, b, c] = self.triangle_f64(f);
                (b - a).cross(c - a).normalize_or_zero().as_vec3()
            })
            .collect()
    }

    /// Area-weighted unit vertex normals (zero for unreferenced vertices).
    pub fn vertex_normals(&self) -> Vec<Vec3> {
        let mut acc = vec![DVec3::ZERO; self.positions.len()];
        for (f, t) in self.triangles.iter().enumerate() {
            let [a, b, c] = self.triangle_f64(f);
            // The cross product's length is twice the area: area weighting for free.
            let n = (b - a).cross(c - a);
            for &v in t {
                acc[v as usize] += n;
            }
        }
        acc.into_iter()
            .map(|n| n.normalize_or_zero().as_vec3())
            .collect()
    }

    /// Signed enclosed volume (positive for outward-oriented closed meshes), in cubed model units.
    pub fn signed_volume(&self) -> f64 {
        (0..self.triangles.len())
            .map(|f| {
                let [a, b, c] = self.triangle_f64(f);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square() -> TriMesh {
        TriMesh::new(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn square_area_bbox_normals() {
        let m = unit_square();
        assert!((m.area() - 1.0).abs() < 1e-12);
        assert!((m.bbox_diagonal() - 2f64.sqrt()).abs() < 1e-6);
        for n in m.face_normals() {
            assert_eq!(n, Vec3::Z);
        }
        for n in m.vertex_normals() {
            assert!((n - Vec3::Z).length() < 1e-6);
        }
    }

    #[test]
    fn unreferenced_vertices_do_not_count_in_bbox() {
        let mut m = unit_square();
        m.positions.push(Vec3::splat(100.0));
        assert!((m.bbox_diagonal() - 2f64.sqrt()).abs() < 1e-6);
        assert!(m.bounding_box().diagonal() > 100.0);
    }

    #[test]
    fn empty_box_has_zero_diagonal() {
        assert_eq!(Aabb::EMPTY.diagonal(), 0.0);
        assert!(Aabb::EMPTY.is_empty());
    }
}

//! The original's faces by output cell and the closest point on them: the placement's cell
//! lists, the closest-point search over a list, and [`Surface`], the closest-point queries of
//! the deviation repair (every vertex its own cell).

use super::fan_search::LargeLists;
use glam::DVec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use mesh::TriMesh;
use mesh::geometry::{box_distance2, closest_point_triangle};
use std::num::NonZeroUsize;

/// The original faces of each output vertex's cell: `of(o)` (see [`cell_faces`]).
pub(crate) type CellFaces = mesh::topology::VertexFaces;

/// Step 1: the original faces with a corner owned by each output vertex (each face once per
/// distinct owner), grouped by a counting sort over the owners.
pub(crate) fn cell_faces(original: &TriMesh, owner: &[u32], outputs: usize) -> CellFaces {
    CellFaces::grouped(outputs, original.triangles.len(), |f| {
        original.triangles[f].map(|v| owner[v as usize])
    })
}

/// The closest point to `p` on the original `faces`, starting from the bound `best` (squared
/// distance, point); faces whose bounding box is no nearer than the best so far are skipped
/// (on igea at 1 % a cell has ~300 faces and nearly all are culled by the box test).
pub(crate) fn closest_on_faces(
    original: &TriMesh,
    faces: &[u32],
    p: DVec3,
    mut best: (f64, DVec3),
) -> (f64, DVec3) {
    for &f in faces {
        let [a, b, c] =
            original.triangles[f as usize].map(|v| original.positions[v as usize].as_dvec3());
        if box_distance2(p, a, b, c) >= best.0 {
            continue;
        }
        let q = closest_point_triangle(p, a, b, c);
        let d = (q - p).length_squared();
        if d < best.0 {
            best = (d, q);
        }
    }
    best
}

/// Closest-point queries against the original surface: a kd-tree over its vertices and the
/// faces around each vertex ([`cell_faces`] with every vertex its own cell); each query searches
/// the faces around its `neighbours` nearest vertices.
pub(crate) struct Surface<'a> {
    original: &'a TriMesh,
    tree: ImmutableKdTree<f64, 3>,
    faces: CellFaces,
    /// Trees of the vertices of high valence ([`super::fan_search`]: a fan-triangulated cap's hub
    /// has thousands of faces, and every query near it searched them all).
    large: LargeLists,
    neighbours: NonZeroUsize,
}

impl<'a> Surface<'a> {
    pub(crate) fn new(original: &'a TriMesh, neighbours: NonZeroUsize) -> Option<Surface<'a>> {
        let points: Vec<[f64; 3]> = original
            .positions
            .iter()
            .map(|p| p.as_dvec3().to_array())
            .collect();
        let tree = ImmutableKdTree::<f64, 3>::new_from_slice(&points).ok()?;
        let n = original.positions.len();
        let itself: Vec<u32> = (0..n as u32).collect();
        let faces = cell_faces(original, &itself, n);
        let large = LargeLists::new(
            n,
            |v| faces.of(v),
            |v| original.positions[v].as_dvec3(),
            |f| original.triangle_f64(f as usize),
        );
        Some(Surface {
            original,
            tree,
            faces,
            large,
            neighbours,
        })
    }

    /// Distance from `p` to the original and the closest point found.
    pub(crate) fn closest(&self, p: DVec3) -> (f64, DVec3) {
        let hits = self
            .tree
            .query(&p.to_array())
            .nearest_n::<SquaredEuclidean<f64>>(self.neighbours)
            .execute();
        let mut best = (f64::INFINITY, p);
        for hit in hits {
            let v = hit.item as usize;
            // A vertex without faces still bounds the distance.
            if hit.distance < best.0 {
                best = (hit.distance, self.original.positions[v].as_dvec3());
            }
            best = match self.large.tree(v) {
                Some(tree) => {
                    let mut found = (best.0, u32::MAX, best.1);
                    tree.nearest(p, &mut found, |f| {
                        Some(self.original.triangle_f64(f as usize))
                    });
                    (found.0, found.2)
                }
                None => closest_on_faces(self.original, self.faces.of(v), p, best),
            };
        }
        (best.0.sqrt(), best.1)
    }

    /// Distance from `p` to the original.
    pub(crate) fn distance(&self, p: DVec3) -> f64 {
        self.closest(p).0
    }
}

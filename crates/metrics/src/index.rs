//! [`SurfaceDistanceIndex`]: exact closest-point queries on a triangle mesh through an obvhs BVH.
//!
//! obvhs 0.4 only offers ray/box/point traversals, so the index walks obvhs's public `Bvh2`
//! node array itself: nearest child first, subtrees pruned when their box is farther than the
//! best triangle found so far. Candidates are scored in f32 with the exact region-based
//! point–triangle routine (slivers in f64, see [`Scoring`]); the winner is re-evaluated in f64.
//!
//! The slivers of a fan-like mesh (many long thin triangles whose boxes overlap, e.g. 100k
//! triangles around one hub) are held in a second tree bounded by oriented slabs as well as
//! boxes ([`crate::sliver`]), searched after the box tree; an ordinary mesh has no such tree,
//! and its searches and answers are those of the box tree alone.
//!
//! The index holds its mesh in a [`Frame`] (centred, scaled by a power of two near the
//! diagonal), so the f32 search neither underflows on a model in 1e-25 units nor overflows on
//! one in 1e15 units; queries are mapped into the frame and answers back into model units.

use crate::MetricsError;
use crate::closest::{
    PackedTriangle, closest_point_triangle, is_degenerate, squared_distance_f32,
    squared_distance_f64, squared_distance_segments_f32,
};
use crate::frame::Frame;
use crate::sliver::{SliverTree, sliver_faces};
use crate::walk::{self, Node};
use glam::{DVec3, Vec3, Vec3A};
use mesh::TriMesh;
use obvhs::aabb::Aabb as BvhAabb;
use obvhs::bvh2::{Bvh2, reinsertion::ReinsertionOptimizer};
use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};
use serde::{Deserialize, Serialize};

/// Sentinel for "no triangle".
pub(crate) const NO_SLOT: u32 = u32::MAX;

/// Result of a closest-point query.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ClosestPoint {
    /// Euclidean distance to the surface, in model units.
    pub distance: f64,
    /// The closest point on the surface.
    pub point: DVec3,
    /// Index of the triangle holding the closest point (in the indexed mesh).
    pub face: u32,
}

/// A BVH over one mesh's triangles answering exact closest-point queries; build once, query
/// many times from any number of threads (`Sync`). Works at any model scale: the mesh is held
/// translated to its bounding box's centre and scaled by a power of two near its diagonal, and
/// answers come back in model units.
pub struct SurfaceDistanceIndex {
    /// The frame the triangles are held in.
    frame: Frame,
    /// The box tree over the ordinary triangles (all of an ordinary mesh's); `None` when all are
    /// slivers.
    bvh: Option<Bvh2>,
    /// The tree over the slivers of a fan-like mesh (see [`crate::sliver`]), after the box
    /// tree's slots.
    slivers: Option<SliverTree>,
    /// Triangles in BVH primitive order (leaf ranges are contiguous), in frame coordinates.
    triangles: Vec<PackedTriangle>,
    /// How each packed triangle is scored in the search (see [`Scoring`]).
    scoring: Vec<Scoring>,
    /// Original face index of each packed triangle.
    faces: Vec<u32>,
    /// Packed slot of each original face.
    slots: Vec<u32>,
    /// Unit face normals by original face index (zero for degenerate faces).
    normals: Vec<Vec3>,
}

/// How the search scores a triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scoring {
    /// The f32 region-based routine.
    Regions,
    /// Degenerate: the closest of its three edges, in f32.
    Segments,
    /// A sliver: in f64 ([`squared_distance_f64`]). The f32 routine's region tests and plane
    /// lose precision with the triangle's aspect `κ = L² / (2·area)` (`L`: its longest edge):
    /// its worst error at points near random slivers of length 1 was 1.4e-7 at κ = 4, 2.1e-6
    /// at 64, 8.7e-6 at 256, 3.4e-5 at 1024 and 1.9e-4 at 4096; on the slivers of a 100k fan
    /// (QEM's hub on the rim: length 2, 1e-3 wide) a point 2e-3 beside a triangle scored as
    /// inside it (squared distance 0), the search kept that triangle, and the fan's Hausdorff
    /// distance came out 3.4e-3 instead of 2.9e-6.
    Exact,
}

/// Triangles with `κ > SLIVER_ASPECT` are scored in f64: below it the f32 routine stays within
/// the 2e-5 of the triangle's length that it is tested to (`f32_path_agrees_with_f64`). No
/// triangle of the shared meshes or of their QEM 10 % outputs comes above it (casting's and
/// fandisk's 10 % have one each above 256, igea's seven above 64), so their results are
/// unchanged; a fan of 3,300 triangles or more around a centred hub is all above it.
const SLIVER_ASPECT: f64 = 512.0;

/// The limit of `κ` in a mesh with a sliver tree (a fan-like mesh; the tree's own slivers are
/// all scored in f64): the f32 routine's errors stay below 5.3e-7 of the triangle's length.
const FAN_ASPECT: f64 = 16.0;

impl Scoring {
    /// The scoring of triangle `abc`: f64 above aspect `limit`.
    fn of(a: DVec3, b: DVec3, c: DVec3, limit: f64) -> Scoring {
        if is_degenerate(a, b, c) {
            return Scoring::Segments;
        }
        let longest2 = (b - a)
            .length_squared()
            .max((c - b).length_squared())
            .max((a - c).length_squared());
        if longest2 > limit * (b - a).cross(c - a).length() {
            Scoring::Exact
        } else {
            Scoring::Regions
        }
    }
}

/// A closest point in frame units: the distance and the face.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameHit {
    pub distance: f64,
    pub point: DVec3,
    pub face: u32,
}

impl std::fmt::Debug for SurfaceDistanceIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SurfaceDistanceIndex")
            .field("faces", &self.faces.len())
            .field("nodes", &self.bvh.as_ref().map_or(0, |b| b.nodes.len()))
            .field(
                "sliver_nodes",
                &self.slivers.as_ref().map_or(0, SliverTree::node_count),
            )
            .finish()
    }
}

impl SurfaceDistanceIndex {
    /// Indexes all triangles of `mesh` (degenerate ones included: a sliver still has a closest
    /// point). Fails when the mesh has no triangles, bad indices or non-finite coordinates.
    pub fn new(mesh: &TriMesh) -> Result<SurfaceDistanceIndex, MetricsError> {
        crate::validate_mesh(mesh, "target")?;
        SurfaceDistanceIndex::in_frame(mesh, Frame::of_mesh(mesh))
    }

    /// Indexes `mesh` (already validated) held in `frame`, e.g. the frame of the other mesh of
    /// a pair, so both directions of a distance are measured in one frame. The caller checks
    /// that the mesh lies within [`crate::frame::MAX_SPAN`] of the frame.
    pub(crate) fn in_frame(
        mesh: &TriMesh,
        frame: Frame,
    ) -> Result<SurfaceDistanceIndex, MetricsError> {
        if mesh.triangles.is_empty() {
            return Err(MetricsError::NoTriangles { mesh: "target" });
        }
        let mesh = &frame.apply(mesh);
        // Fans of long thin triangles get their own tree (see `sliver`); the rest, all of an
        // ordinary mesh, the box tree.
        let slivers = sliver_faces((0..mesh.triangles.len()).map(|f| mesh.triangle(f)));
        let ordinary: Vec<u32> = if slivers.is_empty() {
            (0..mesh.triangles.len() as u32).collect()
        } else {
            let mut is_sliver = vec![false; mesh.triangles.len()];
            for &f in &slivers {
                is_sliver[f as usize] = true;
            }
            (0..mesh.triangles.len() as u32)
                .filter(|&f| !is_sliver[f as usize])
                .collect()
        };
        let bvh = (!ordinary.is_empty()).then(|| {
            let boxes: Vec<BvhAabb> = ordinary
                .iter()
                .map(|&f| {
                    let [a, b, c] = mesh.triangle(f as usize);
                    BvhAabb::new(Vec3A::from(a.min(b).min(c)), Vec3A::from(a.max(b).max(c)))
                })
                .collect();
            let indices: Vec<u32> = (0..boxes.len() as u32).collect();
            let mut bvh = PlocBuilder::with_capacity(boxes.len()).build(
                PlocSearchDistance::Low,
                &boxes,
                indices,
                SortPrecision::U64,
                2,
            );
            ReinsertionOptimizer::default().run(&mut bvh, 0.02, None);
            // One triangle per leaf: collapsing leaves cost more build time than it saved in
            // queries (measured on igea: leaves of 1, 2, 4, 8 gave the same query time within
            // 10 %).
            bvh
        });
        // Faces in slot order: the box tree's leaves, then the sliver tree's.
        let mut faces: Vec<u32> = bvh.as_ref().map_or_else(Vec::new, |bvh| {
            bvh.primitive_indices
                .iter()
                .map(|&i| ordinary[i as usize])
                .collect()
        });
        let sliver_tree = (!slivers.is_empty()).then(|| {
            let triangles: Vec<[Vec3; 3]> =
                slivers.iter().map(|&f| mesh.triangle(f as usize)).collect();
            let (tree, order) = SliverTree::build(&triangles, faces.len() as u32);
            faces.extend(order.iter().map(|&i| slivers[i as usize]));
            tree
        });

        let n = faces.len();
        // A fan-like mesh is measured against itself or a flat copy, at distances a million
        // times below its slivers' length: its slivers, and any thin triangle, are scored in
        // f64 (see `Scoring`).
        let (aspect_limit, first_sliver) = match sliver_tree {
            None => (SLIVER_ASPECT, n),
            Some(_) => (FAN_ASPECT, n - slivers.len()),
        };
        let mut triangles = Vec::with_capacity(n);
        let mut scoring = Vec::with_capacity(n);
        let mut slots = vec![NO_SLOT; mesh.triangles.len()];
        for (slot, &face) in faces.iter().enumerate() {
            let [a, b, c] = mesh.triangle(face as usize);
            triangles.push(PackedTriangle {
                a: a.into(),
                b: b.into(),
                c: c.into(),
            });
            scoring.push(if slot >= first_sliver {
                Scoring::of(a.as_dvec3(), b.as_dvec3(), c.as_dvec3(), 0.0)
            } else {
                Scoring::of(a.as_dvec3(), b.as_dvec3(), c.as_dvec3(), aspect_limit)
            });
            slots[face as usize] = slot as u32;
        }
        Ok(SurfaceDistanceIndex {
            frame,
            faces,
            bvh,
            slivers: sliver_tree,
            triangles,
            scoring,
            slots,
            normals: mesh.face_normals(),
        })
    }

    /// Number of indexed triangles.
    pub fn face_count(&self) -> usize {
        self.slots.len()
    }

    /// Unit normal of indexed face `face` (zero for degenerate faces).
    pub fn face_normal(&self, face: u32) -> Vec3 {
        self.normals[face as usize]
    }

    /// The frame the index measures in.
    pub(crate) fn frame(&self) -> &Frame {
        &self.frame
    }

    /// A frame hit in model units.
    fn to_model(&self, hit: FrameHit) -> ClosestPoint {
        ClosestPoint {
            distance: hit.distance * self.frame.scale(),
            point: self.frame.to_model(hit.point),
            face: hit.face,
        }
    }

    /// The nearest slot to frame point `q` by the f32 search, or by an exact scan of every
    /// triangle when the search finds none (a point beyond the f32 range of the frame).
    pub(crate) fn nearest_or_scan(&self, q: DVec3, hint: u32, stack: &mut Vec<(u32, f32)>) -> u32 {
        let slot = self.nearest_slot(Vec3A::from(q.as_vec3()), hint, f32::INFINITY, stack);
        if slot != NO_SLOT {
            return slot;
        }
        (0..self.triangles.len() as u32)
            .min_by(|&a, &b| {
                self.exact(q, a)
                    .distance
                    .total_cmp(&self.exact(q, b).distance)
            })
            .unwrap_or(0)
    }

    /// Closest point on the surface to `p`.
    pub fn closest(&self, p: Vec3) -> ClosestPoint {
        let mut stack = Vec::with_capacity(64);
        let q = self.frame.to_frame(p);
        let slot = self.nearest_or_scan(q, NO_SLOT, &mut stack);
        self.to_model(self.exact(q, slot))
    }

    /// Closest point on the surface to `p` if one lies within `max_distance`, else `None`.
    pub fn closest_within(&self, p: Vec3, max_distance: f64) -> Option<ClosestPoint> {
        let mut stack = Vec::with_capacity(64);
        let bound = bound_f32(max_distance / self.frame.scale());
        let q = self.frame.to_frame(p);
        let slot = self.nearest_slot(Vec3A::from(q.as_vec3()), NO_SLOT, bound, &mut stack);
        (slot != NO_SLOT)
            .then(|| self.to_model(self.exact(q, slot)))
            .filter(|c| c.distance <= max_distance)
    }

    /// Closest points for many query points (sequential; reuses one traversal stack and starts
    /// each search from the previous answer, which is fast when neighbouring queries are close).
    pub fn closest_many(&self, points: &[Vec3]) -> Vec<ClosestPoint> {
        let mut stack = Vec::with_capacity(64);
        let mut hint = NO_SLOT;
        points
            .iter()
            .map(|&p| {
                let q = self.frame.to_frame(p);
                hint = self.nearest_or_scan(q, hint, &mut stack);
                self.to_model(self.exact(q, hint))
            })
            .collect()
    }

    /// Exact (f64) closest point on packed triangle `slot` to frame point `q`, in frame units.
    #[inline]
    pub(crate) fn exact(&self, q: DVec3, slot: u32) -> FrameHit {
        let t = &self.triangles[slot as usize];
        let c = closest_point_triangle(q, t.a.as_dvec3(), t.b.as_dvec3(), t.c.as_dvec3());
        FrameHit {
            distance: (q - c).length(),
            point: c,
            face: self.faces[slot as usize],
        }
    }

    /// f32 squared distance from `p` to packed triangle `slot`.
    #[inline(always)]
    fn triangle_d2(&self, p: Vec3A, slot: usize) -> f32 {
        let t = &self.triangles[slot];
        match self.scoring[slot] {
            Scoring::Regions => squared_distance_f32(p, t),
            Scoring::Segments => squared_distance_segments_f32(p, t),
            Scoring::Exact => {
                let (a, b, c) = (t.a.as_dvec3(), t.b.as_dvec3(), t.c.as_dvec3());
                squared_distance_f64(p.as_dvec3(), a, b, c) as f32
            }
        }
    }

    /// Nearest packed triangle to frame point `p` with squared distance (frame units) below
    /// `bound2` (f32), starting from `hint` (a packed slot or [`NO_SLOT`]); returns [`NO_SLOT`]
    /// when nothing is that close.
    pub(crate) fn nearest_slot(
        &self,
        p: Vec3A,
        hint: u32,
        bound2: f32,
        stack: &mut Vec<(u32, f32)>,
    ) -> u32 {
        let mut best = NO_SLOT;
        let mut best_d2 = bound2;
        if hint != NO_SLOT {
            let d2 = self.triangle_d2(p, hint as usize);
            if d2 < best_d2 {
                best_d2 = d2;
                best = hint;
            }
        }
        if let Some(bvh) = &self.bvh {
            let nodes = &bvh.nodes;
            (best, best_d2) = walk::nearest(
                best,
                best_d2,
                stack,
                |i| Node {
                    first: nodes[i].first_index as usize,
                    count: nodes[i].prim_count as usize,
                },
                |i| {
                    let b = nodes[i].aabb();
                    let d = (b.min - p).max(p - b.max).max(Vec3A::ZERO);
                    d.length_squared()
                },
                |slot| self.triangle_d2(p, slot),
            );
        }
        if let Some(tree) = &self.slivers {
            (best, _) = tree.search(p, best, best_d2, stack, |slot| self.triangle_d2(p, slot));
        }
        best
    }
}

/// A squared f32 search bound slightly above `max_distance²` (so rounding never drops a hit;
/// the exact f64 distance is checked afterwards). Infinite for non-finite or huge inputs.
pub(crate) fn bound_f32(max_distance: f64) -> f32 {
    let b = (max_distance * max_distance * (1.0 + 1e-5)) as f32;
    if b.is_finite() { b } else { f32::INFINITY }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mesh::procedural::{icosphere, torus};
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    fn brute(mesh: &TriMesh, p: Vec3) -> f64 {
        (0..mesh.face_count())
            .map(|f| {
                let [a, b, c] = mesh.triangle_f64(f);
                (p.as_dvec3() - closest_point_triangle(p.as_dvec3(), a, b, c)).length()
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn bvh_queries_match_brute_force() {
        let mut rng = Pcg64Mcg::seed_from_u64(1);
        for mesh in [icosphere(3), torus(1.0, 0.3, 40, 16)] {
            let index = SurfaceDistanceIndex::new(&mesh).unwrap();
            let points: Vec<Vec3> = (0..2000)
                .map(|_| {
                    Vec3::new(
                        rng.random_range(-1.6..1.6),
                        rng.random_range(-1.6..1.6),
                        rng.random_range(-1.6..1.6),
                    )
                })
                .collect();
            let many = index.closest_many(&points);
            for (p, hit) in points.iter().zip(&many) {
                let single = index.closest(*p);
                let b = brute(&mesh, *p);
                assert!(
                    (single.distance - b).abs() <= 1e-6 * (1.0 + b),
                    "{single:?} vs {b}"
                );
                assert!((hit.distance - b).abs() <= 1e-6 * (1.0 + b));
                let [x, y, z] = mesh.triangle_f64(single.face as usize);
                let on = closest_point_triangle(single.point, x, y, z);
                assert!((on - single.point).length() < 1e-9);
                match index.closest_within(*p, b * 0.99) {
                    None => {}
                    Some(c) => panic!("found {c:?} closer than the true distance {b}"),
                }
                assert!(index.closest_within(*p, b * 1.01 + 1e-9).is_some());
            }
        }
    }

    /// A fan of `n` slivers (hub at the centre, rim on the unit circle), optionally with its
    /// hub on the rim (where QEM's collapses leave it: slivers twice as long, to the far side)
    /// and tilted out of the axis planes.
    fn fan_mesh(n: u32, hub_on_rim: bool, tilted: bool) -> TriMesh {
        let mut m = mesh::procedural::fan(n);
        if hub_on_rim {
            m.positions[0] = m.positions[1];
            m.triangles.retain(|t| !t.contains(&1));
        }
        if tilted {
            let r = glam::Mat3::from_euler(glam::EulerRot::XYZ, 0.3, 0.7, 1.1);
            for p in &mut m.positions {
                *p = r * *p + Vec3::new(0.25, -0.5, 0.125);
            }
        }
        m
    }

    /// Points on the faces of `m` (the samples of a distance measure on an identical or
    /// coplanar mesh), some lifted off it, and some anywhere around it.
    fn points_on(m: &TriMesh, count: usize, rng: &mut Pcg64Mcg) -> Vec<Vec3> {
        (0..count)
            .map(|i| {
                let [a, b, c] = m.triangle(rng.random_range(0..m.face_count()));
                let (mut u, mut v) = (rng.random_range(0.0..1.0f32), rng.random_range(0.0..1.0));
                if u + v > 1.0 {
                    (u, v) = (1.0 - u, 1.0 - v);
                }
                let on = a + (b - a) * u + (c - a) * v;
                match i % 4 {
                    0 | 1 => on,
                    2 => on + Vec3::new(1e-4, -2e-4, 3e-4),
                    _ => Vec3::new(
                        rng.random_range(-1.5..1.5),
                        rng.random_range(-1.5..1.5),
                        rng.random_range(-1.5..1.5),
                    ),
                }
            })
            .collect()
    }

    #[test]
    fn fans_match_brute_force() {
        // Slivers of aspect 1270 and more: the f32 scoring called points up to 1e-3 beside
        // such a sliver inside it (a 100k fan's metrics were 1000 times the true distance),
        // and their boxes overlap (the sliver tree).
        let mut rng = Pcg64Mcg::seed_from_u64(7);
        let mut meshes = Vec::new();
        for hub_on_rim in [false, true] {
            for tilted in [false, true] {
                meshes.push(fan_mesh(8000, hub_on_rim, tilted));
            }
        }
        // Both trees: the caps' slivers and the sides (upright: ordinary boxes).
        meshes.push(mesh::procedural::fan_capped_cylinder(8000));
        for mesh in meshes {
            let index = SurfaceDistanceIndex::new(&mesh).unwrap();
            assert!(index.slivers.is_some());
            // (A fan's slivers along the axes have thin boxes: the box tree takes them.)
            assert!(
                index.bvh.is_some() || mesh.face_count() < 32_000,
                "{index:?}"
            );
            assert!(index.scoring.iter().all(|&s| s != Scoring::Regions));
            let points = points_on(&mesh, 1500, &mut rng);
            let many = index.closest_many(&points);
            for (p, hit) in points.iter().zip(&many) {
                let b = brute(&mesh, *p);
                let single = index.closest(*p);
                assert!(
                    (single.distance - b).abs() <= 1e-7 * (1.0 + b),
                    "{single:?} vs {b}"
                );
                assert!(
                    (hit.distance - b).abs() <= 1e-7 * (1.0 + b),
                    "{hit:?} vs {b}"
                );
                let [x, y, z] = mesh.triangle_f64(single.face as usize);
                assert!(
                    (closest_point_triangle(single.point, x, y, z) - single.point).length() < 1e-9
                );
                assert!(index.closest_within(*p, b * 0.99 - 1e-9).is_none());
                assert!(index.closest_within(*p, b * 1.01 + 1e-9).is_some());
            }
        }
    }

    #[test]
    fn ordinary_meshes_have_no_sliver_tree() {
        for mesh in [
            icosphere(4),
            torus(1.0, 0.3, 40, 16),
            mesh::procedural::fan(12),
        ] {
            let index = SurfaceDistanceIndex::new(&mesh).unwrap();
            assert!(index.slivers.is_none() && index.bvh.is_some());
            assert!(index.scoring.iter().all(|&s| s == Scoring::Regions));
        }
    }

    #[test]
    fn single_triangle_and_empty_mesh() {
        let tri = TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
        let index = SurfaceDistanceIndex::new(&tri).unwrap();
        let c = index.closest(Vec3::new(0.25, 0.25, 2.0));
        assert!((c.distance - 2.0).abs() < 1e-12);
        // One sliver on the diagonal: the sliver tree alone, one leaf.
        let sliver = TriMesh::new(
            vec![Vec3::ZERO, Vec3::ONE, Vec3::new(1.0, 1.0, 0.999)],
            vec![[0, 1, 2]],
        );
        let index = SurfaceDistanceIndex::new(&sliver).unwrap();
        assert!(index.bvh.is_none() && index.slivers.is_some());
        let c = index.closest(Vec3::new(1.0, 0.0, 0.0));
        assert!((c.distance - brute(&sliver, Vec3::X)).abs() < 1e-9, "{c:?}");
        let empty = TriMesh::new(vec![Vec3::ZERO], vec![]);
        assert!(SurfaceDistanceIndex::new(&empty).is_err());
    }
}

//! The sliver tree: a bounding-volume tree for long thin triangles whose axis-aligned boxes
//! overlap massively, the faces of a fan (a hub with 100k triangles to a rim, a fan-triangulated
//! CAD cap): each sliver's box covers up to half of the square its length spans, so a point on
//! such a fan lay in the boxes of ~13 % of the triangles, none of them pruned by the box-only
//! search, and the index's PLOC build merged only a pair or two per pass over chains of
//! monotonically growing boxes (quadratic: 9-12 s for a 100k fan).
//!
//! [`SurfaceDistanceIndex`](crate::SurfaceDistanceIndex) moves the slivers here only when they
//! matter: a triangle is a sliver when its box's half area is more than [`SLIVER_RATIO`] times
//! its own area, and the slivers get this tree only when their boxes' half areas add up to at
//! least [`SLIVER_OVERLAP`] times the mesh's area (a point near the surface lies in that many
//! sliver boxes on average). No mesh of the shared set comes near that (0.4 at most, the fan of
//! 100k faces 10,133), so ordinary meshes keep their one box tree and their results bit for bit.
//!
//! Each node is bounded by its box AND by a box oriented along its triangles (the dominant
//! direction of their longest edges, their dominant normal made perpendicular to it, and the
//! third axis) AND by the two sides of its wedge (the slabs perpendicular, in the oriented box's
//! plane, to the two extreme directions of the longest edges). A node of neighbouring slivers of
//! a fan (a wedge from the hub) thus has a bound as narrow as the wedge all along it, whatever
//! the wedge's direction (the oriented box alone is as wide at the hub as at the rim, and a
//! point near the hub lay in the boxes of 1/r wedges of each level). The lower bound of a node's
//! distance is the largest of the four; the tree is split at the median of the triangles'
//! centroids along their widest axis, which for a fan cuts the rim's circle into arcs. On the
//! 100k fan a query visits 16-19 nodes and scores 3 triangles.

use crate::walk;
use glam::{DMat3, DVec2, DVec3, Vec3, Vec3A, Vec4};

/// A triangle whose bounding box's half area exceeds this many times its own area is a sliver.
/// Ordinary scans and their simplifications have a handful of such triangles (the shared meshes
/// at most 0.4 of their area in such boxes, most under 0.05).
pub(crate) const SLIVER_RATIO: f64 = 16.0;

/// The slivers get their own tree when their boxes' half areas add up to at least this many
/// times the area of the whole mesh.
pub(crate) const SLIVER_OVERLAP: f64 = 1.0;

/// Triangles per leaf (at most): the 100k fan's queries took 1.7-2.1 s with 1, 1.6-1.9 s with
/// 2, 1.5-1.8 s with 4 and 1.6-1.7 s with 8 (one thread).
const LEAF: usize = 4;

/// Padding of the oriented extents, in frame units (frames hold a mesh within about a unit):
/// the f32 projections of a query point are off by ~1e-7 of its distance from the frame's
/// centre; the pad keeps the oriented bound below the true distance near the mesh.
const PAD: f64 = 1e-6;

/// The faces of `triangles` (frame coordinates) that get the sliver tree, in face order; empty
/// when the slivers are too few to matter (see the module docs).
pub(crate) fn sliver_faces(triangles: impl Iterator<Item = [Vec3; 3]>) -> Vec<u32> {
    let mut faces = Vec::new();
    let mut sliver_half_area = 0.0;
    let mut area = 0.0;
    for (f, [a, b, c]) in triangles.enumerate() {
        let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
        let tri_area = 0.5 * (b - a).cross(c - a).length();
        let e = a.max(b).max(c) - a.min(b).min(c);
        let half_area = e.x * e.y + e.y * e.z + e.z * e.x;
        area += tri_area;
        if half_area > SLIVER_RATIO * tri_area {
            faces.push(f as u32);
            sliver_half_area += half_area;
        }
    }
    if sliver_half_area < SLIVER_OVERLAP * area {
        faces.clear();
    }
    faces
}

/// A node: its bounding slabs, and either a leaf's slots (`count > 0`) or its children `first`
/// and `first + 1`. Eight slabs in two groups of four lanes: `[x, y, z, s]` (the box, and the
/// wedge's first side) and `[u, v, w, t]` (the oriented box, and the wedge's second side).
#[derive(Debug, Clone, Copy)]
struct Node {
    /// The slabs' unit normals, by coordinate.
    nx: [Vec4; 2],
    ny: [Vec4; 2],
    nz: [Vec4; 2],
    /// The slabs' extents along their normals.
    lo: [Vec4; 2],
    hi: [Vec4; 2],
    first: u32,
    count: u32,
}

impl Node {
    /// A lower bound of the squared distance from `p` to the node's triangles: the largest of
    /// the box's, the oriented box's and the wedge's sides' distances.
    #[inline(always)]
    fn distance2_bound(&self, p: Vec3A) -> f32 {
        let (x, y, z) = (Vec4::splat(p.x), Vec4::splat(p.y), Vec4::splat(p.z));
        let outside = |g: usize| {
            let t = self.nx[g] * x + self.ny[g] * y + self.nz[g] * z;
            (self.lo[g] - t).max(t - self.hi[g]).max(Vec4::ZERO)
        };
        let (a, b) = (outside(0), outside(1));
        let sides = a.w.max(b.w);
        a.truncate()
            .length_squared()
            .max(b.truncate().length_squared())
            .max(sides * sides)
    }
}

/// The tree over the slivers (see the module docs). Its leaves hold contiguous slots of the
/// index, from the `base` given to [`SliverTree::build`].
#[derive(Debug)]
pub(crate) struct SliverTree {
    nodes: Vec<Node>,
}

/// A triangle's build data.
#[derive(Clone, Copy)]
struct Item {
    centroid: DVec3,
    /// Longest edge, as a vector.
    edge: DVec3,
    /// Normal scaled by twice the area.
    normal: DVec3,
    /// Index into the build's triangle list.
    index: u32,
}

impl SliverTree {
    /// Builds the tree over `triangles` (frame coordinates; at least one), to be stored from
    /// slot `base` on. Returns the tree and the order of the slots: slot `base + i` holds
    /// `triangles[order[i]]`.
    pub(crate) fn build(triangles: &[[Vec3; 3]], base: u32) -> (SliverTree, Vec<u32>) {
        let mut items: Vec<Item> = triangles
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let [a, b, c] = t.map(|v| v.as_dvec3());
                let edges = [b - a, c - b, a - c];
                let edge = edges.into_iter().fold(DVec3::ZERO, |m, e| {
                    if e.length_squared() > m.length_squared() {
                        e
                    } else {
                        m
                    }
                });
                Item {
                    centroid: (a + b + c) / 3.0,
                    edge,
                    normal: (b - a).cross(c - a),
                    index: i as u32,
                }
            })
            .collect();
        let mut nodes = vec![bound(&[], triangles); 1 + descendants(items.len())];
        let (root, rest) = nodes.split_at_mut(1);
        fill(&mut root[0], rest, 1, &mut items, base, triangles);
        let order = items.iter().map(|it| it.index).collect();
        (SliverTree { nodes }, order)
    }

    /// Number of nodes.
    pub(crate) fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The nearest slot of the tree closer than `best_d2` (else `best`) with its squared
    /// distance (`triangle_d2`: the squared distance from the query point `p` to a slot): the
    /// same walk as the index's box tree.
    #[inline(always)]
    pub(crate) fn search(
        &self,
        p: Vec3A,
        best: u32,
        best_d2: f32,
        stack: &mut Vec<(u32, f32)>,
        triangle_d2: impl Fn(usize) -> f32,
    ) -> (u32, f32) {
        let nodes = &self.nodes;
        walk::nearest(
            best,
            best_d2,
            stack,
            |i| walk::Node {
                first: nodes[i].first as usize,
                count: nodes[i].count as usize,
            },
            |i| nodes[i].distance2_bound(p),
            triangle_d2,
        )
    }
}

/// Number of nodes below a node of `items` items: the median splits make the tree's shape a
/// function of the count, so subtrees are built into their places in parallel.
fn descendants(items: usize) -> usize {
    2 * leaves(items).0 - 2
}

/// The numbers of leaves of trees over `items` and `items + 1` items, in O(log items): the
/// halves of `2k` are `k, k` and of `2k + 1` are `k, k + 1`.
fn leaves(items: usize) -> (usize, usize) {
    if items <= LEAF {
        // `LEAF + 1` items split into two leaves.
        return (1, if items < LEAF { 1 } else { 2 });
    }
    let (k, k1) = leaves(items / 2);
    if items.is_multiple_of(2) {
        (2 * k, k + k1)
    } else {
        (k + k1, 2 * k1)
    }
}

/// Subtrees of more items are built in parallel.
const PARALLEL_ITEMS: usize = 4096;

/// Builds the subtree of `items` (slots from `base`): its root into `node`, its descendants
/// into `below`, which starts at node index `offset`: the children pair, then the left child's
/// descendants, then the right's.
fn fill(
    node: &mut Node,
    below: &mut [Node],
    offset: usize,
    items: &mut [Item],
    base: u32,
    triangles: &[[Vec3; 3]],
) {
    *node = bound(items, triangles);
    if items.len() <= LEAF {
        node.first = base;
        node.count = items.len() as u32;
        return;
    }
    // Split at the median of the centroids along their widest axis.
    let (lo, hi) = items
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), it| {
            (lo.min(it.centroid), hi.max(it.centroid))
        });
    let axis = (hi - lo).max_position();
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |x, y| x.centroid[axis].total_cmp(&y.centroid[axis]));
    node.first = offset as u32;
    let (pair, below) = below.split_at_mut(2);
    let (left_below, right_below) = below.split_at_mut(descendants(mid));
    let (left_items, right_items) = items.split_at_mut(mid);
    let [left, right] = pair else { unreachable!() };
    let right_offset = offset + 2 + left_below.len();
    let right_base = base + mid as u32;
    if mid >= PARALLEL_ITEMS {
        rayon::join(
            || fill(left, left_below, offset + 2, left_items, base, triangles),
            || {
                let (below, items) = (right_below, right_items);
                fill(right, below, right_offset, items, right_base, triangles)
            },
        );
    } else {
        fill(left, left_below, offset + 2, left_items, base, triangles);
        fill(
            right,
            right_below,
            right_offset,
            right_items,
            right_base,
            triangles,
        );
    }
}

/// The bounding slabs of `items` (leaf fields unset): the box; the oriented box along the
/// dominant direction `u` of their longest edges and their dominant normal `v` (made
/// perpendicular to `u`); and the wedge: the two slabs perpendicular, in the `u, v` plane, to
/// the extreme directions of the longest edges about `u` (a fan's wedge of slivers lies between
/// its two outer spokes, so these bound a point beside the wedge near the hub, where the
/// oriented box is as wide as at the rim).
fn bound(items: &[Item], triangles: &[[Vec3; 3]]) -> Node {
    // Dominant directions: the principal eigenvectors of the longest edges' and the normals'
    // tensors (sign-free, so opposite edges of a fan's two halves do not cancel).
    let mut edges = DMat3::ZERO;
    let mut normals = DMat3::ZERO;
    let (mut edge0, mut normal0) = (DVec3::ZERO, DVec3::ZERO);
    for it in items {
        edges += outer(it.edge);
        normals += outer(it.normal);
        edge0 += if it.edge.dot(edge0) < 0.0 {
            -it.edge
        } else {
            it.edge
        };
        normal0 += if it.normal.dot(normal0) < 0.0 {
            -it.normal
        } else {
            it.normal
        };
    }
    let u = principal(edges, edge0).unwrap_or(DVec3::X);
    let n = principal(normals, normal0).unwrap_or(DVec3::Z);
    let v = (n - u * n.dot(u))
        .try_normalize()
        .unwrap_or_else(|| u.any_orthonormal_vector());
    let w = u.cross(v).normalize();
    // The wedge: the longest edges' extreme directions about `u` in the `u, w` plane (the
    // plane of a flat fan: `v` is its normal), each edge taken in the direction along `u`, as
    // `(along u, along w)`; `a` turns before `b` when `a × b > 0`.
    let (mut low, mut high) = ((1.0f64, 0.0f64), (1.0f64, 0.0f64));
    for it in items {
        let e = if it.edge.dot(u) < 0.0 {
            -it.edge
        } else {
            it.edge
        };
        let e = (e.dot(u), e.dot(w));
        if e.0 * low.1 - e.1 * low.0 > 0.0 {
            low = e;
        }
        if high.0 * e.1 - high.1 * e.0 > 0.0 {
            high = e;
        }
    }
    // The unit normal of a side, perpendicular to its direction in the plane.
    let side = |(along, across): (f64, f64)| (w * along - u * across).try_normalize().unwrap_or(w);
    // Rounded to f32 first: the extents are those of the normals the queries use.
    let [u, v, w, s, t] = [u, v, w, side(low), side(high)].map(|d| d.as_vec3().as_dvec3());
    let oriented = DMat3::from_cols(u, v, w).transpose();
    let (mut min, mut max) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    let (mut sides_lo, mut sides_hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for it in items {
        for p in triangles[it.index as usize] {
            min = min.min(p);
            max = max.max(p);
            let p = p.as_dvec3();
            let along = oriented * p;
            lo = lo.min(along);
            hi = hi.max(along);
            let across = DVec2::new(s.dot(p), t.dot(p));
            sides_lo = sides_lo.min(across);
            sides_hi = sides_hi.max(across);
        }
    }
    // The box's slabs are exact; the others are padded for the rounding of the projections.
    let (lo, hi) = ((lo - PAD).as_vec3(), (hi + PAD).as_vec3());
    let (sides_lo, sides_hi) = ((sides_lo - PAD).as_vec2(), (sides_hi + PAD).as_vec2());
    let lanes = |a: Vec3, x: f32| Vec4::new(a.x, a.y, a.z, x);
    let [u, v, w, s, t] = [u, v, w, s, t].map(|d| d.as_vec3());
    Node {
        nx: [Vec4::new(1.0, 0.0, 0.0, s.x), Vec4::new(u.x, v.x, w.x, t.x)],
        ny: [Vec4::new(0.0, 1.0, 0.0, s.y), Vec4::new(u.y, v.y, w.y, t.y)],
        nz: [Vec4::new(0.0, 0.0, 1.0, s.z), Vec4::new(u.z, v.z, w.z, t.z)],
        lo: [lanes(min, sides_lo.x), lanes(lo, sides_lo.y)],
        hi: [lanes(max, sides_hi.x), lanes(hi, sides_hi.y)],
        first: 0,
        count: 0,
    }
}

/// `v vᵀ`.
fn outer(v: DVec3) -> DMat3 {
    DMat3::from_cols(v * v.x, v * v.y, v * v.z)
}

/// The principal eigenvector of the symmetric positive semi-definite `m` by power iteration
/// from `start` (or from each axis when `start` has no component along it); `None` for a zero
/// matrix.
fn principal(m: DMat3, start: DVec3) -> Option<DVec3> {
    let mut v = start.try_normalize().unwrap_or(DVec3::X);
    if (m * v).length_squared() == 0.0 {
        v = [DVec3::X, DVec3::Y, DVec3::Z].into_iter().max_by(|a, b| {
            (m * *a)
                .length_squared()
                .total_cmp(&(m * *b).length_squared())
        })?;
    }
    for _ in 0..32 {
        let next = (m * v).try_normalize()?;
        let step = (next - v).length_squared();
        v = next;
        if step < 1e-24 {
            break;
        }
    }
    Some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_counts_match_the_splits() {
        fn naive(items: usize) -> usize {
            if items <= LEAF {
                0
            } else {
                2 + naive(items / 2) + naive(items - items / 2)
            }
        }
        for items in (1..2000).chain([65_535, 65_536, 65_537, 100_000]) {
            assert_eq!(descendants(items), naive(items), "{items}");
        }
    }

    #[test]
    fn bounds_hold_their_triangles() {
        // A wedge of slivers, tilted: every vertex (and points on the triangles) is at bound 0,
        // points beside the wedge near the hub are at their distance from its sides.
        let rotation = glam::Mat3::from_euler(glam::EulerRot::XYZ, 0.3, 0.7, 1.1);
        let rim = |i: u32| {
            let a = 0.2 + 0.001 * f64::from(i);
            rotation * Vec3::new(a.cos() as f32, a.sin() as f32, 0.0)
        };
        let triangles: Vec<[Vec3; 3]> = (0..50).map(|i| [Vec3::ZERO, rim(i), rim(i + 1)]).collect();
        let (tree, order) = SliverTree::build(&triangles, 0);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..50).collect::<Vec<u32>>());
        let root = &tree.nodes[0];
        for t in &triangles {
            for p in [t[0], t[1], t[2], (t[0] + t[1] + t[2]) / 3.0] {
                assert_eq!(root.distance2_bound(p.into()), 0.0);
            }
        }
        // Half-way out along the wedge's bisector, then 0.01 to the side in its plane.
        let mid = (rim(0) + rim(50)) * 0.25;
        let across = rotation * Vec3::Z;
        let beside = mid + mid.cross(across).normalize() * 0.05;
        let d = root.distance2_bound(beside.into()).sqrt();
        let wedge_half = 0.5 * 0.05 * 0.5; // half the wedge's width at half its length
        assert!(d > 0.05 - wedge_half - 1e-3 && d <= 0.05, "{d}");
    }
}

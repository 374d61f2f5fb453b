//! The closest face to a point among the fans of a few output vertices: the search that the
//! refit (assigning a sample to a face) and the detail rounds (a point's distance to the mesh)
//! share.
//!
//! Most fans hold ~6 faces and are scanned face by face, with a bounding-box bound that skips
//! most exact tests. A vertex of high valence (the hub of a fan-triangulated CAD cap, where a
//! cylinder of 16k segments gives the output a vertex with thousands of faces) made that scan
//! quadratic: every sample of the cap tested every face of the hub's fan (issue: a 64k-face
//! fan-capped cylinder took 137 s at 50 %, horse 6 s). Fans above [`LARGE_FAN`] faces get a
//! small tree instead, searched nearest bound first, so a query visits the groups of faces
//! that can be nearer than the best face found so far.
//!
//! The faces of a fan all meet at its vertex and are long and thin (slivers from the hub to
//! the rim), so their bounding boxes overlap: a point of a flat cap lay in the boxes of a
//! quarter of the hub's faces. The tree groups the faces by their direction from the vertex
//! and bounds each group by a cone from the vertex (axis, half-angle, length) as well as by
//! its box; the distance to the cone is what separates the slivers (4,000 segments at 50 %:
//! detail rounds and refit 6.3 s with the scan, 1.8 s with boxes alone, 0.7 s with cones).
//! With the same trees for the flips' assignment, the repair's and the attached vertices'
//! searches of the original, the 16k-segment cylinder at 50 % takes 3.6-3.8 s, horse
//! (97k faces) 4.9-6.8 s in the same alternating runs (137 s before).
//!
//! The answer is at the same distance as the scan's; among faces at exactly that distance
//! (a point on the shared edge of two faces) each keeps the first it finds, the scan in face
//! order, the tree nearest box first.

use glam::DVec3;
use mesh::geometry::{box_distance2, closest_point_triangle};

/// Fans (and face lists) with more faces than this get a tree. Ordinary meshes never reach it (valence 6 on
/// average, rarely above 12), so their searches, and outputs, are unchanged.
pub(crate) const LARGE_FAN: usize = 32;

/// Faces per leaf of a fan's tree.
const LEAF_FACES: usize = 4;

/// No face / no tree.
const NONE: u32 = u32::MAX;

/// A fan's bounding-box tree: node `0` is the root; a node with `count > 0` is a leaf over
/// `faces[first..first + count]`, otherwise its children are `first` and `first + 1`.
/// A bounding tree over a list of faces for exact closest-face queries (see the module docs).
pub(crate) struct FaceTree {
    apex: DVec3,
    nodes: Vec<TreeNode>,
    faces: Vec<u32>,
}

#[derive(Clone, Copy, Default)]
struct TreeNode {
    lo: DVec3,
    hi: DVec3,
    /// The group's cone from the fan's vertex: unit axis, cosine and sine of the half-angle
    /// (`cos_half` ≤ 0: no cone bound), and the farthest corner's distance.
    axis: DVec3,
    cos_half: f64,
    sin_half: f64,
    length: f64,
    first: u32,
    count: u32,
}

impl TreeNode {
    /// A lower bound of the squared distance from `q` to the node's faces (`apex`: the fan's
    /// vertex).
    #[inline]
    fn distance2_bound(&self, q: DVec3, apex: DVec3) -> f64 {
        let in_box = (q.clamp(self.lo, self.hi) - q).length_squared();
        let v = q - apex;
        let dist = v.length();
        // At the apex, or a NaN: the box alone.
        if dist.is_nan() || dist <= 0.0 {
            return in_box;
        }
        // Beyond the cone's length.
        let mut bound = (dist - self.length).max(0.0);
        if self.cos_half > 0.0 {
            let cos_a = (v.dot(self.axis) / dist).clamp(-1.0, 1.0);
            if cos_a < self.cos_half {
                // Outside the cone by the angle a - half: the distance to its surface is
                // dist * sin(a - half), or dist once that angle passes 90°.
                let sin_a = (1.0 - cos_a * cos_a).sqrt();
                let cos_gap = cos_a * self.cos_half + sin_a * self.sin_half;
                let sin_gap = sin_a * self.cos_half - cos_a * self.sin_half;
                bound = bound.max(if cos_gap <= 0.0 { dist } else { dist * sin_gap });
            }
        }
        in_box.max(bound * bound)
    }
}

/// Trees for the lists of faces (fans, cells) longer than [`LARGE_FAN`]; shorter lists are
/// scanned by their users.
pub(crate) struct LargeLists {
    /// Per list: its tree in `trees`, or [`NONE`]; empty when no list is large.
    tree_of: Vec<u32>,
    trees: Vec<FaceTree>,
}

impl LargeLists {
    /// Trees for the lists `0..count` (`list(i)`, gathered around `apex(i)`) that are large.
    pub(crate) fn new<'l>(
        count: usize,
        list: impl Fn(usize) -> &'l [u32],
        apex: impl Fn(usize) -> DVec3,
        corners: impl Fn(u32) -> [DVec3; 3],
    ) -> LargeLists {
        let mut tree_of = Vec::new();
        let mut trees = Vec::new();
        for i in 0..count {
            let faces = list(i);
            if faces.len() > LARGE_FAN {
                if tree_of.is_empty() {
                    tree_of = vec![NONE; count];
                }
                tree_of[i] = trees.len() as u32;
                trees.push(FaceTree::new(apex(i), faces, &corners));
            }
        }
        LargeLists { tree_of, trees }
    }

    /// The tree of list `i`, if it has one.
    pub(crate) fn tree(&self, i: usize) -> Option<&FaceTree> {
        match self.tree_of.get(i) {
            Some(&t) if t != NONE => Some(&self.trees[t as usize]),
            _ => None,
        }
    }
}

/// The fans of the output vertices with their trees, for positions fixed during the searches.
pub(crate) struct FanSearch<'a> {
    fans: &'a [Vec<u32>],
    triangles: &'a [[u32; 3]],
    positions: &'a [DVec3],
    large: LargeLists,
}

impl<'a> FanSearch<'a> {
    /// Builds the trees of the large fans (none on ordinary meshes).
    pub(crate) fn new(
        fans: &'a [Vec<u32>],
        triangles: &'a [[u32; 3]],
        positions: &'a [DVec3],
    ) -> FanSearch<'a> {
        let large = LargeLists::new(
            fans.len(),
            |v| &fans[v],
            |v| positions[v],
            |f| corners(triangles, positions, f),
        );
        FanSearch {
            fans,
            triangles,
            positions,
            large,
        }
    }

    /// The closest face to `q` in the fans of `around` (distinct vertices): squared distance,
    /// face (`u32::MAX` when the fans are empty) and closest point. A face in the fans of two
    /// of them is measured once, with the first one's fan.
    pub(crate) fn nearest(&self, q: DVec3, around: &[u32]) -> (f64, u32, DVec3) {
        let mut best = (f64::INFINITY, NONE, DVec3::ZERO);
        for (k, &w) in around.iter().enumerate() {
            let earlier = &around[..k];
            let seen_before = |t: &[u32; 3]| earlier.iter().any(|e| t.contains(e));
            if let Some(tree) = self.large.tree(w as usize) {
                tree.nearest(q, &mut best, |f| {
                    let t = self.triangles[f as usize];
                    (!seen_before(&t)).then(|| corners(self.triangles, self.positions, f))
                });
                continue;
            }
            for &f in &self.fans[w as usize] {
                let t = self.triangles[f as usize];
                if seen_before(&t) {
                    continue;
                }
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                // A face whose bounding box is no nearer than the best so far cannot win.
                if box_distance2(q, a, b, c) >= best.0 {
                    continue;
                }
                let p = closest_point_triangle(q, a, b, c);
                let d = (p - q).length_squared();
                if d < best.0 {
                    best = (d, f, p);
                }
            }
        }
        best
    }
}

fn corners(triangles: &[[u32; 3]], positions: &[DVec3], f: u32) -> [DVec3; 3] {
    triangles[f as usize].map(|i| positions[i as usize])
}

impl FaceTree {
    /// A tree over `faces` (with their `corners`), grouped by their direction from `apex`: for
    /// a fan its vertex, for another list of faces a point they gather around (any point gives
    /// correct bounds; a far one gives wide cones). Median splits along the longest axis of
    /// the box of the faces' directions.
    pub(crate) fn new(apex: DVec3, faces: &[u32], corners: impl Fn(u32) -> [DVec3; 3]) -> FaceTree {
        let mut nodes = Vec::with_capacity(2 * faces.len().div_ceil(LEAF_FACES));
        // (direction of the centroid from the apex, face): sorted in place by the splits.
        let mut faces: Vec<(DVec3, u32)> = faces
            .iter()
            .map(|&f| {
                let d = (corners(f).iter().sum::<DVec3>() / 3.0 - apex).normalize_or_zero();
                (d, f)
            })
            .collect();
        nodes.push(TreeNode::default());
        // (node, range of `faces`) still to be split.
        let mut stack = vec![(0usize, 0usize, faces.len())];
        while let Some((node, start, end)) = stack.pop() {
            let slice = &mut faces[start..end];
            let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            let (mut dlo, mut dhi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            let mut sum = DVec3::ZERO;
            for &(d, f) in slice.iter() {
                for p in corners(f) {
                    lo = lo.min(p);
                    hi = hi.max(p);
                    sum += (p - apex).normalize_or_zero();
                }
                dlo = dlo.min(d);
                dhi = dhi.max(d);
            }
            let axis = sum.normalize_or_zero();
            let (mut cos_half, mut length) = (1.0f64, 0.0f64);
            for &(_, f) in slice.iter() {
                for p in corners(f) {
                    let v = p - apex;
                    let len = v.length();
                    if len > 0.0 {
                        cos_half = cos_half.min(v.dot(axis) / len);
                        length = length.max(len);
                    }
                }
            }
            if axis == DVec3::ZERO {
                cos_half = -1.0;
            }
            let mut bounds = TreeNode {
                lo,
                hi,
                axis,
                cos_half,
                sin_half: (1.0 - cos_half * cos_half).max(0.0).sqrt(),
                length,
                first: start as u32,
                count: slice.len() as u32,
            };
            if slice.len() <= LEAF_FACES {
                nodes[node] = bounds;
                continue;
            }
            let extent = dhi - dlo;
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = slice.len() / 2;
            slice.select_nth_unstable_by(mid, |x, y| {
                x.0[axis].total_cmp(&y.0[axis]).then(x.1.cmp(&y.1))
            });
            let left = nodes.len();
            nodes.push(TreeNode::default());
            nodes.push(TreeNode::default());
            bounds.first = left as u32;
            bounds.count = 0;
            nodes[node] = bounds;
            stack.push((left, start, start + mid));
            stack.push((left + 1, start + mid, end));
        }
        FaceTree {
            apex,
            nodes,
            faces: faces.into_iter().map(|(_, f)| f).collect(),
        }
    }

    /// Lowers `best` (squared distance, face, closest point) to the nearest face of the tree to
    /// `q` that `corners` gives corners for (`None`: left out). Nearer bound first; groups whose
    /// bound is no nearer than the best are skipped.
    pub(crate) fn nearest(
        &self,
        q: DVec3,
        best: &mut (f64, u32, DVec3),
        corners: impl Fn(u32) -> Option<[DVec3; 3]>,
    ) {
        let box_d2 = |n: &TreeNode| n.distance2_bound(q, self.apex);
        let mut stack: [u32; 64] = [0; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            // `>=`, as the scan: on a flat fan a point on it is at distance 0 from every box
            // around it, and `>` would visit them all.
            if box_d2(node) >= best.0 {
                continue;
            }
            if node.count > 0 {
                let (first, count) = (node.first as usize, node.count as usize);
                for &f in &self.faces[first..first + count] {
                    let Some([a, b, c]) = corners(f) else {
                        continue;
                    };
                    if box_distance2(q, a, b, c) >= best.0 {
                        continue;
                    }
                    let p = closest_point_triangle(q, a, b, c);
                    let d = (p - q).length_squared();
                    if d < best.0 {
                        *best = (d, f, p);
                    }
                }
                continue;
            }
            let (l, r) = (node.first, node.first + 1);
            let (dl, dr) = (
                box_d2(&self.nodes[l as usize]),
                box_d2(&self.nodes[r as usize]),
            );
            // Push the farther child first so the nearer one is searched first. A median-split
            // tree of n faces is about log2(n / LEAF_FACES) deep, far below the stack's size.
            let (near, far) = if dl <= dr { (l, r) } else { (r, l) };
            stack[top] = far;
            stack[top + 1] = near;
            top += 2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat fan of `n` slivers around a hub at the origin, tilted out of the axis planes.
    fn tilted_fan(n: usize) -> (Vec<[u32; 3]>, Vec<DVec3>) {
        let tilt = |p: DVec3| DVec3::new(p.x, p.y + 0.3 * p.x, p.z + 0.5 * p.y);
        let mut positions = vec![DVec3::ZERO];
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            positions.push(tilt(DVec3::new(a.cos(), a.sin(), 0.0)));
        }
        let triangles = (0..n as u32)
            .map(|i| [0, 1 + i, 1 + (i + 1) % n as u32])
            .collect();
        (triangles, positions)
    }

    /// The tree finds what scanning every face finds: the same squared distance, for points around, above and far from a hub of 500
    /// faces, with and without an earlier fan taking some faces.
    #[test]
    fn large_fans_find_the_scans_face() {
        let (triangles, positions) = tilted_fan(500);
        let n = positions.len();
        let fans = crate::surface::fans(&triangles, n);
        let search = FanSearch::new(&fans, &triangles, &positions);
        assert_eq!(search.large.trees.len(), 1, "the hub's fan gets a tree");
        let mut rng = 12345u64;
        let mut next = || {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for i in 0..2000 {
            let q = DVec3::new(next(), next(), next()) * if i % 4 == 0 { 3.0 } else { 1.0 };
            for around in [vec![0u32], vec![7, 0], vec![250, 251, 0]] {
                let got = search.nearest(q, &around);
                // Reference: every face of the fans, in order, the first of equals.
                let mut want = (f64::INFINITY, NONE);
                for (k, &w) in around.iter().enumerate() {
                    for &f in &fans[w as usize] {
                        let t = triangles[f as usize];
                        if around[..k].iter().any(|e| t.contains(e)) {
                            continue;
                        }
                        let [a, b, c] = t.map(|i| positions[i as usize]);
                        let d = (closest_point_triangle(q, a, b, c) - q).length_squared();
                        if d < want.0 {
                            want = (d, f);
                        }
                    }
                }
                assert_eq!(got.0, want.0, "distance at {q:?} around {around:?}");
                let [a, b, c] = triangles[got.1 as usize].map(|i| positions[i as usize]);
                assert_eq!(
                    (closest_point_triangle(q, a, b, c) - q).length_squared(),
                    got.0
                );
            }
        }
    }

    /// Small fans get no tree, so ordinary meshes search as before.
    #[test]
    fn small_fans_are_scanned() {
        let (triangles, positions) = tilted_fan(LARGE_FAN);
        let fans = crate::surface::fans(&triangles, positions.len());
        let search = FanSearch::new(&fans, &triangles, &positions);
        assert!(search.large.trees.is_empty());
        let (d, f, _) = search.nearest(DVec3::new(0.5, 0.01, 0.2), &[0]);
        assert!(d.is_finite() && f != NONE);
    }
}

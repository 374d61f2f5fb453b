//! Non-edge vertex pairs (Garland & Heckbert 1997, §3): [`close_pairs`] finds, for every vertex,
//! its closest other vertices within the threshold `t` with a k-d tree, and [`VirtualPairs`]
//! keeps them per vertex while the contraction merges vertices.

use glam::DVec3;

/// Marks the end of a linked list.
const NONE: u32 = u32::MAX;

/// Points per leaf of the k-d tree.
const LEAF: usize = 8;

/// Pairs `(u, v)`, `u < v`, of used vertices with `|p_u − p_v| < t`, at most `max_per_vertex` (the
/// closest; on equal distances, those found first) per vertex `u`; the caller filters out pairs
/// that are already mesh edges.
///
/// A nearest-neighbour search in a k-d tree over the used vertices, pruned by the distance of the
/// `max_per_vertex`-th closest found so far: the work does not grow with `t`. (Until issue 33 a
/// uniform grid of cell size `t` compared every vertex with every other in its 27 cells, all
/// pairs once `t` spans the mesh: `--threshold 1e30` on a 100k-vertex sphere took 38-53 s, igea
/// at 64 % of its diagonal 68-105 s.)
pub fn close_pairs(pos: &[DVec3], used: &[bool], t: f64, max_per_vertex: usize) -> Vec<[u32; 2]> {
    if t.is_nan() || t <= 0.0 || max_per_vertex == 0 {
        return Vec::new();
    }
    let tree = KdTree::new(pos, used);
    let t2 = t * t;
    let mut pairs = Vec::new();
    let mut near: Vec<(f64, u32)> = Vec::new();
    for (u, &p) in pos.iter().enumerate() {
        if !used[u] {
            continue;
        }
        near.clear();
        tree.nearest(p, u as u32, t2, max_per_vertex, &mut near);
        for &(_, v) in &near {
            let u = u as u32;
            pairs.push(if u < v { [u, v] } else { [v, u] });
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// A k-d tree over a point set, stored implicitly: the node of the index range `lo..hi` (more
/// than [`LEAF`] points) splits at `mid = (lo + hi) / 2`, the points of `order[lo..mid]` at or
/// below `split[mid]` on axis `axis[mid]` and those of `order[mid..hi]` at or above it (each
/// position is the middle of one node at most).
struct KdTree<'a> {
    pos: &'a [DVec3],
    /// Point indices in tree order.
    order: Vec<u32>,
    /// Split axis of the node whose middle is at this position of `order`.
    axis: Vec<u8>,
    /// Split coordinate of that node.
    split: Vec<f64>,
}

impl<'a> KdTree<'a> {
    /// The tree of the points `i` with `used[i]`.
    fn new(pos: &'a [DVec3], used: &[bool]) -> Self {
        let order: Vec<u32> = (0..pos.len() as u32)
            .filter(|&i| used[i as usize])
            .collect();
        let mut tree = KdTree {
            pos,
            axis: vec![0; order.len()],
            split: vec![0.0; order.len()],
            order,
        };
        let len = tree.order.len();
        tree.build(0, len);
        tree
    }

    fn build(&mut self, lo: usize, hi: usize) {
        if hi - lo <= LEAF {
            return;
        }
        let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for &i in &self.order[lo..hi] {
            min = min.min(self.pos[i as usize]);
            max = max.max(self.pos[i as usize]);
        }
        let extent = max - min;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let mid = (lo + hi) / 2;
        let pos = self.pos;
        self.order[lo..hi].select_nth_unstable_by(mid - lo, |&a, &b| {
            pos[a as usize][axis]
                .total_cmp(&pos[b as usize][axis])
                .then(a.cmp(&b))
        });
        self.axis[mid] = axis as u8;
        self.split[mid] = pos[self.order[mid] as usize][axis];
        self.build(lo, mid);
        self.build(mid, hi);
    }

    /// The at most `k` points other than `skip` closest to `p` with squared distance below `t2`,
    /// as `(squared distance, index)` in increasing order, into `near` (cleared by the caller).
    fn nearest(&self, p: DVec3, skip: u32, t2: f64, k: usize, near: &mut Vec<(f64, u32)>) {
        self.search(0, self.order.len(), p, skip, t2, k, near);
    }

    /// Squared distance a point must beat to enter `near`.
    #[inline]
    fn bound(t2: f64, k: usize, near: &[(f64, u32)]) -> f64 {
        if near.len() < k { t2 } else { near[k - 1].0 }
    }

    #[allow(clippy::too_many_arguments)]
    fn search(
        &self,
        lo: usize,
        hi: usize,
        p: DVec3,
        skip: u32,
        t2: f64,
        k: usize,
        near: &mut Vec<(f64, u32)>,
    ) {
        if hi - lo <= LEAF {
            for &i in &self.order[lo..hi] {
                let d2 = self.pos[i as usize].distance_squared(p);
                if i != skip && d2 < Self::bound(t2, k, near) {
                    // Sorted insertion; the list never holds more than k entries.
                    let at = near.partition_point(|&(e, _)| e <= d2);
                    if near.len() == k {
                        near.pop();
                    }
                    near.insert(at, (d2, i));
                }
            }
            return;
        }
        let mid = (lo + hi) / 2;
        let axis = self.axis[mid] as usize;
        let delta = p[axis] - self.split[mid];
        // The side of the split that holds `p` first, then the other if the plane is close enough.
        let (first, second) = if delta <= 0.0 {
            ((lo, mid), (mid, hi))
        } else {
            ((mid, hi), (lo, mid))
        };
        self.search(first.0, first.1, p, skip, t2, k, near);
        if delta * delta < Self::bound(t2, k, near) {
            self.search(second.0, second.1, p, skip, t2, k, near);
        }
    }
}

/// Linked lists of the non-edge pairs of each (representative) vertex, plus a union-find that
/// resolves the vertex a pair's far end has been merged into.
pub(crate) struct VirtualPairs {
    merged: mesh::topology::UnionFind,
    /// First node of each vertex's list ([`NONE`] when empty).
    pub(crate) head: Vec<u32>,
    tail: Vec<u32>,
    /// Next node of the same list ([`NONE`] at the end).
    pub(crate) next: Vec<u32>,
    /// Node `2p + s` belongs to pair `p` on side `s`; `other` is the vertex on the other side.
    pub(crate) other: Vec<u32>,
}

impl VirtualPairs {
    /// The lists of `pairs` over `vertices` vertices, each vertex its own representative.
    pub(crate) fn new(vertices: usize, pairs: &[[u32; 2]]) -> Self {
        let mut vp = VirtualPairs {
            merged: mesh::topology::UnionFind::new(vertices),
            head: vec![NONE; vertices],
            tail: vec![NONE; vertices],
            next: vec![NONE; pairs.len() * 2],
            other: Vec::with_capacity(pairs.len() * 2),
        };
        for (p, &[u, v]) in pairs.iter().enumerate() {
            vp.other.push(v);
            vp.other.push(u);
            vp.append(u as usize, (2 * p) as u32);
            vp.append(v as usize, (2 * p + 1) as u32);
        }
        vp
    }

    /// Whether `node` ends a list.
    #[inline]
    pub(crate) fn is_end(node: u32) -> bool {
        node == NONE
    }

    fn append(&mut self, v: usize, node: u32) {
        if self.head[v] == NONE {
            self.head[v] = node;
        } else {
            self.next[self.tail[v] as usize] = node;
        }
        self.tail[v] = node;
    }

    /// The vertex `v` has been merged into (itself if it is alive), with path halving.
    pub(crate) fn find(&mut self, v: u32) -> u32 {
        self.merged.find(v)
    }

    /// Vertex `b` merged into `a`: union, and concatenate `b`'s list onto `a`'s.
    pub(crate) fn merge(&mut self, a: usize, b: usize) {
        self.merged.merge_into(a as u32, b as u32);
        if self.head[b] == NONE {
            return;
        }
        if self.head[a] == NONE {
            self.head[a] = self.head[b];
        } else {
            self.next[self.tail[a] as usize] = self.head[b];
        }
        self.tail[a] = self.tail[b];
        self.head[b] = NONE;
        self.tail[b] = NONE;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_exactly_the_close_pairs() {
        let pos: Vec<DVec3> = (0..40)
            .map(|i| {
                DVec3::new(
                    (i % 7) as f64 * 0.3,
                    (i / 7) as f64 * 0.45,
                    (i % 3) as f64 * 0.2,
                )
            })
            .collect();
        let used = vec![true; pos.len()];
        let t = 0.5;
        let got = close_pairs(&pos, &used, t, usize::MAX);
        let mut want = Vec::new();
        for u in 0..pos.len() {
            for v in u + 1..pos.len() {
                if pos[u].distance(pos[v]) < t {
                    want.push([u as u32, v as u32]);
                }
            }
        }
        assert!(!want.is_empty());
        assert_eq!(got, want);
    }

    /// The pairs of every vertex with its `k` closest others within `t`, by brute force.
    fn brute_force(pos: &[DVec3], t: f64, k: usize) -> Vec<[u32; 2]> {
        let mut pairs = Vec::new();
        for u in 0..pos.len() {
            let mut near: Vec<(f64, usize)> = (0..pos.len())
                .filter(|&v| v != u && pos[u].distance(pos[v]) < t)
                .map(|v| (pos[u].distance_squared(pos[v]), v))
                .collect();
            near.sort_by(|a, b| a.0.total_cmp(&b.0));
            for &(_, v) in near.iter().take(k) {
                pairs.push([u.min(v) as u32, u.max(v) as u32]);
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }

    #[test]
    fn the_closest_pairs_match_brute_force_for_any_threshold() {
        // Random points (no equal distances) in a flat slab, as on a surface; thresholds from
        // below the spacing to far beyond the diagonal (issue 33: 1e30 was quadratic).
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        let pos: Vec<DVec3> = (0..1500)
            .map(|_| DVec3::new(next(), next(), 0.05 * next()))
            .collect();
        let mut used = vec![true; pos.len()];
        used[7] = false;
        for t in [0.01, 0.03, 0.1, 0.5, 2.0, 1e30] {
            for k in [1, 8] {
                let got = close_pairs(&pos, &used, t, k);
                // Brute force over the used points only, mapped back to their indices.
                let index: Vec<usize> = (0..pos.len()).filter(|&i| used[i]).collect();
                let sub: Vec<DVec3> = index.iter().map(|&i| pos[i]).collect();
                let want: Vec<[u32; 2]> = brute_force(&sub, t, k)
                    .into_iter()
                    .map(|[a, b]| [index[a as usize] as u32, index[b as usize] as u32])
                    .collect();
                assert_eq!(got, want, "t = {t}, k = {k}");
            }
        }
        // Coincident points: each pairs with k of the others, and nothing is quadratic.
        let same = vec![DVec3::splat(0.5); 20_000];
        let got = close_pairs(&same, &vec![true; same.len()], 1e30, 8);
        assert!(
            got.len() >= same.len() && got.len() <= 8 * same.len(),
            "{}",
            got.len()
        );
    }

    #[test]
    fn merged_lists_reach_every_pair_through_the_representative() {
        // Pairs 0-3, 1-3, 2-4; then 1 merges into 0 and 4 into 3.
        let mut vp = VirtualPairs::new(5, &[[0, 3], [1, 3], [2, 4]]);
        vp.merge(0, 1);
        vp.merge(3, 4);
        let walk = |vp: &mut VirtualPairs, v: usize| {
            let mut out = Vec::new();
            let mut node = vp.head[v];
            while !VirtualPairs::is_end(node) {
                let o = vp.other[node as usize];
                out.push(vp.find(o));
                node = vp.next[node as usize];
            }
            out
        };
        assert_eq!(walk(&mut vp, 0), vec![3, 3]);
        assert_eq!(walk(&mut vp, 3), vec![0, 0, 2]);
        assert!(walk(&mut vp, 1).is_empty() && walk(&mut vp, 4).is_empty());
        assert_eq!((vp.find(1), vp.find(4), vp.find(2)), (0, 3, 2));
    }
}

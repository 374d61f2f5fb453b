//! Non-edge vertex pairs (Garland & Heckbert 1997, §3): [`close_pairs`] finds the pairs closer than
//! the threshold `t` with a uniform grid of cell size `t`, and [`VirtualPairs`] keeps them per
//! vertex while the contraction merges vertices.

use glam::DVec3;
use std::collections::HashMap;

/// Marks the end of a linked list.
const NONE: u32 = u32::MAX;

/// Pairs `(u, v)`, `u < v`, of used vertices with `|p_u − p_v| < t`, at most `max_per_vertex` (the
/// closest) per vertex `u`; the caller filters out pairs that are already mesh edges.
pub fn close_pairs(pos: &[DVec3], used: &[bool], t: f64, max_per_vertex: usize) -> Vec<[u32; 2]> {
    if t.is_nan() || t <= 0.0 || max_per_vertex == 0 {
        return Vec::new();
    }
    let cell_of = |p: DVec3| -> [i64; 3] {
        let c = (p / t).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    };
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (i, &p) in pos.iter().enumerate() {
        if used[i] {
            grid.entry(cell_of(p)).or_default().push(i as u32);
        }
    }
    let t2 = t * t;
    let mut pairs = Vec::new();
    let mut near: Vec<(f64, u32)> = Vec::new();
    for (u, &p) in pos.iter().enumerate() {
        if !used[u] {
            continue;
        }
        near.clear();
        let c = cell_of(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(cell) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &v in cell {
                        let d2 = pos[v as usize].distance_squared(p);
                        if v as usize != u && d2 < t2 {
                            near.push((d2, v));
                        }
                    }
                }
            }
        }
        if near.len() > max_per_vertex {
            near.select_nth_unstable_by(max_per_vertex, |x, y| x.0.total_cmp(&y.0));
            near.truncate(max_per_vertex);
        }
        for &(_, v) in &near {
            let u = u as u32;
            pairs.push(if u < v { [u, v] } else { [v, u] });
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// Linked lists of the non-edge pairs of each (representative) vertex, plus a union-find that
/// resolves the vertex a pair's far end has been merged into.
pub(crate) struct VirtualPairs {
    parent: Vec<u32>,
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
            parent: (0..vertices as u32).collect(),
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
    pub(crate) fn find(&mut self, mut v: u32) -> u32 {
        while self.parent[v as usize] != v {
            let g = self.parent[self.parent[v as usize] as usize];
            self.parent[v as usize] = g;
            v = g;
        }
        v
    }

    /// Vertex `b` merged into `a`: union, and concatenate `b`'s list onto `a`'s.
    pub(crate) fn merge(&mut self, a: usize, b: usize) {
        self.parent[b] = a as u32;
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

//! Phase-2 cleanup (option (b)): remove non-manifold fins (keep the two best-supported faces of
//! every edge with more than two) and close small boundary loops by ear clipping.

use super::{Candidate, edge_key, half_edges};
use glam::Vec3;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

/// On every edge with more than two faces keep the best-supported face and the best-supported
/// face traversing the edge the other way (else the next best); drop the rest. Repeats until no
/// such edge is left. Returns the number of faces dropped.
pub(super) fn remove_fins(faces: &mut Vec<Candidate>, nodes: &[Vec3]) -> usize {
    let mut dropped_total = 0;
    for _ in 0..8 {
        let mut by_edge: Vec<((u32, u32), u32)> = Vec::with_capacity(faces.len() * 3);
        for (f, c) in faces.iter().enumerate() {
            for (a, b) in half_edges(c.tri) {
                by_edge.push((edge_key(a, b), f as u32));
            }
        }
        by_edge.sort_unstable();
        let mut drop = vec![false; faces.len()];
        let mut any = false;
        let mut i = 0;
        while i < by_edge.len() {
            let mut j = i;
            while j < by_edge.len() && by_edge[j].0 == by_edge[i].0 {
                j += 1;
            }
            if j - i > 2 {
                let (ea, eb) = by_edge[i].0;
                let mut group: Vec<u32> = by_edge[i..j].iter().map(|x| x.1).collect();
                // Best support first; ties: larger area (less sliver-like), then index.
                group.sort_by(|&x, &y| {
                    let (cx, cy) = (faces[x as usize], faces[y as usize]);
                    cy.support
                        .cmp(&cx.support)
                        .then(tri_area(nodes, cy.tri).total_cmp(&tri_area(nodes, cx.tri)))
                        .then(x.cmp(&y))
                });
                let forward = |f: u32| half_edges(faces[f as usize].tri).contains(&(ea, eb));
                let first = group[0];
                let dir0 = forward(first);
                let second = group[1..]
                    .iter()
                    .copied()
                    .find(|&g| forward(g) != dir0)
                    .unwrap_or(group[1]);
                for &g in &group {
                    if g != first && g != second && !drop[g as usize] {
                        drop[g as usize] = true;
                        any = true;
                    }
                }
            }
            i = j;
        }
        if !any {
            break;
        }
        let before = faces.len();
        let mut k = 0;
        faces.retain(|_| {
            k += 1;
            !drop[k - 1]
        });
        dropped_total += before - faces.len();
    }
    dropped_total
}

/// Area of a triangle of nodes (f64).
fn tri_area(nodes: &[Vec3], t: [u32; 3]) -> f64 {
    let [a, b, c] = t.map(|v| nodes[v as usize].as_dvec3());
    0.5 * (b - a).cross(c - a).length()
}

/// Close boundary loops of at most `max_edges` edges by ear clipping (shortest new diagonal
/// first, never creating an edge that already exists). A loop with at least half of its nodes
/// `on_border` (their cells hold vertices of an original border) is a hole of the input and
/// stays open: closing it put faces across the stanford-bunny's base holes, which set its
/// Hausdorff max (8-15× QEM's). Returns (loops closed, faces added).
pub(super) fn fill_holes(
    faces: &mut Vec<Candidate>,
    nodes: &[Vec3],
    on_border: &[bool],
    max_edges: usize,
) -> (usize, usize) {
    let mut directed: HashSet<(u32, u32)> =
        HashSet::with_capacity_and_hasher(faces.len() * 3, Default::default());
    let mut undirected: HashMap<(u32, u32), u32> =
        HashMap::with_capacity_and_hasher(faces.len() * 3, Default::default());
    let mut keys: HashSet<[u32; 3]> =
        HashSet::with_capacity_and_hasher(faces.len(), Default::default());
    for c in faces.iter() {
        for (a, b) in half_edges(c.tri) {
            directed.insert((a, b));
            *undirected.entry(edge_key(a, b)).or_insert(0) += 1;
        }
        let mut k = c.tri;
        k.sort_unstable();
        keys.insert(k);
    }
    // Boundary half-edges: an edge with one face, oriented as in that face.
    let mut next: HashMap<u32, u32> = HashMap::default();
    let mut ambiguous: HashSet<u32> = HashSet::default();
    let mut boundary: Vec<(u32, u32)> = directed
        .iter()
        .copied()
        .filter(|&(a, b)| undirected[&edge_key(a, b)] == 1)
        .collect();
    boundary.sort_unstable();
    for &(a, b) in &boundary {
        if next.insert(a, b).is_some() {
            ambiguous.insert(a);
        }
    }
    let mut visited: HashSet<u32> = HashSet::default();
    let (mut holes, mut added) = (0, 0);
    for &(start, _) in &boundary {
        if visited.contains(&start) || ambiguous.contains(&start) {
            continue;
        }
        // Trace the loop.
        let mut lp = vec![start];
        let mut v = next[&start];
        let mut ok = true;
        while v != start {
            if ambiguous.contains(&v) || lp.len() > max_edges || !next.contains_key(&v) {
                ok = false;
                break;
            }
            lp.push(v);
            v = next[&v];
        }
        for &u in &lp {
            visited.insert(u);
        }
        if !ok || lp.len() < 3 || lp.len() > max_edges {
            continue;
        }
        let border = lp
            .iter()
            .filter(|&&u| on_border.get(u as usize).copied().unwrap_or(false))
            .count();
        if 2 * border >= lp.len() {
            continue;
        }
        if let Some(tris) = clip_ears(&lp, nodes, &undirected, &keys) {
            holes += 1;
            added += tris.len();
            for t in tris {
                for (a, b) in half_edges(t) {
                    *undirected.entry(edge_key(a, b)).or_insert(0) += 1;
                }
                let mut k = t;
                k.sort_unstable();
                keys.insert(k);
                faces.push(Candidate { tri: t, support: 0 });
            }
        }
    }
    (holes, added)
}

/// Triangulate boundary loop `lp` (half-edges lp[i] -> lp[i+1] belong to existing faces), with
/// faces oriented against the loop. `None` when no valid triangulation is found.
fn clip_ears(
    lp: &[u32],
    nodes: &[Vec3],
    undirected: &HashMap<(u32, u32), u32>,
    keys: &HashSet<[u32; 3]>,
) -> Option<Vec<[u32; 3]>> {
    let mut ring: Vec<u32> = lp.to_vec();
    let mut new_edges: HashSet<(u32, u32)> = HashSet::default();
    let mut out = Vec::with_capacity(lp.len() - 2);
    while ring.len() > 3 {
        let n = ring.len();
        let mut best: Option<(f32, usize)> = None;
        for i in 0..n {
            let (p, q) = (ring[(i + n - 1) % n], ring[(i + 1) % n]);
            let key = edge_key(p, q);
            if undirected.contains_key(&key) || new_edges.contains(&key) {
                continue;
            }
            let d = (nodes[p as usize] - nodes[q as usize]).length_squared();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, i));
            }
        }
        let (_, i) = best?;
        let (p, v, q) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
        out.push([q, v, p]);
        new_edges.insert(edge_key(p, q));
        ring.remove(i);
    }
    let t = [ring[2], ring[1], ring[0]];
    let mut k = t;
    k.sort_unstable();
    if keys.contains(&k) {
        return None;
    }
    out.push(t);
    Some(out)
}

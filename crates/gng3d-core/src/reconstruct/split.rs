//! Phase-2 topology repair (option (f)): split the cells that cannot give a faithful mesh.
//!
//! The concordance rule needs every cell (the original vertices labelled with one node) to be a
//! topological disc, small enough that the faces around it see three distinct labels. On thin
//! parts it is not: a cow's leg or tail is a tube a few vertices round, a node trained there
//! sits on the tube's axis and its cell wraps the whole circumference (an annulus, Euler
//! characteristic 0), so every face of the tube maps to a degenerate triple and the leg comes
//! back as a chain of unreferenced nodes, detached from the body (cow at 10 %: 8 components and
//! 11 boundary edges from a one-piece closed input; at 25 %: 3 components).
//!
//! Steps, repeated for a few rounds by the caller until nothing is bad:
//! 1. **Find bad cells**: a cell whose induced sub-complex of the original has Euler
//!    characteristic V − E + F ≠ 1 (not a disc: an annulus around a tube, a cell enclosing
//!    another), and the cells along a hole the mapping made (an output boundary edge whose ends
//!    are not both on an original border, or a face the cleanup added to close such a hole).
//! 2. **Split each bad cell** in two, or three when it is not a disc: seeds at the cell's vertex
//!    nearest to its node, then by farthest-point sampling over the cell; every vertex of the
//!    cell goes to the seed nearest along the original's edges (a multi-source Dijkstra inside
//!    the cell), so every part stays edge-connected. The first part keeps the node, the others
//!    become new nodes; every node moves to its part's centroid.
//!
//! It adds nodes, so the output has more vertices than the network: it is for oversampled runs,
//! whose decimation brings the count back to the target while keeping the repaired topology.

use super::{Candidate, OriginalTables};
use glam::Vec3;
use mesh::TriMesh;
use mesh::topology::EdgeTable;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Step 1: the nodes whose cells are not discs or line a hole the mapping made, sorted, with
/// the number of parts to split each into: three for a cell that is not a disc (an annulus
/// split in two gives a tube two cells round, which still maps to back-to-back faces; in three
/// it maps to a tube), two otherwise. `faces` are the mapped (and cleaned) candidates for the
/// current `labels`.
pub(crate) fn bad_cells(
    original: &TriMesh,
    tables: &OriginalTables,
    labels: &[u32],
    node_count: usize,
    faces: &[Candidate],
    on_border: &[bool],
) -> Vec<(u32, u8)> {
    // Euler characteristic of each cell's induced sub-complex, as V − E + F.
    let mut euler = vec![0i64; node_count];
    let mut size = vec![0u32; node_count];
    for &l in labels {
        if l != u32::MAX {
            euler[l as usize] += 1;
            size[l as usize] += 1;
        }
    }
    for &[a, b] in &tables.edges.edges {
        let l = labels[a as usize];
        if l != u32::MAX && l == labels[b as usize] {
            euler[l as usize] -= 1;
        }
    }
    for t in &original.triangles {
        let l = labels[t[0] as usize];
        if l != u32::MAX && l == labels[t[1] as usize] && l == labels[t[2] as usize] {
            euler[l as usize] += 1;
        }
    }
    let mut bad = vec![false; node_count];
    for c in 0..node_count {
        // A cell of one vertex cannot be split; its neighbours can.
        bad[c] = size[c] >= 2 && euler[c] != 1;
    }
    // Holes of the mapping: boundary edges of the candidates away from the original's borders,
    // and the faces the cleanup put over such holes (support 0).
    let candidates = TriMesh::new(
        vec![Vec3::ZERO; node_count],
        faces.iter().map(|c| c.tri).collect(),
    );
    let table = EdgeTable::new(&candidates);
    for e in 0..table.len() {
        let [a, b] = table.edges[e];
        if table.is_boundary(e) && !(on_border[a as usize] && on_border[b as usize]) {
            bad[a as usize] = true;
            bad[b as usize] = true;
        }
    }
    for c in faces.iter().filter(|c| c.support == 0) {
        for &v in &c.tri {
            bad[v as usize] = true;
        }
    }
    // Pinches: a node whose faces form more than one fan joins two sheets at a point (the
    // cow's tail at 10 % hung from the body by one vertex, every cell a disc, no hole).
    for (v, &fans) in mesh::topology::vertex_fan_counts(&candidates, &table)
        .iter()
        .enumerate()
    {
        if fans > 1 {
            bad[v] = true;
        }
    }
    (0..node_count as u32)
        .filter(|&c| bad[c as usize] && size[c as usize] >= 2)
        .map(|c| (c, if euler[c as usize] == 1 { 2 } else { 3 }))
        .collect()
}

/// Step 2: split each cell of `bad` in two (see the module docs), appending the new nodes to
/// `nodes` and `node_comp` and relabelling their vertices; at most `budget` new nodes. Returns
/// how many were added.
pub(crate) fn split_cells(
    original: &TriMesh,
    tables: &OriginalTables,
    labels: &mut [u32],
    nodes: &mut Vec<Vec3>,
    node_comp: &mut Vec<u32>,
    bad: &[(u32, u8)],
    budget: usize,
) -> usize {
    let n = original.positions.len();
    let positions = &original.positions;
    let (offset, nbrs) = (&tables.adjacency.offset, &tables.adjacency.nbrs);
    // Members of every cell, CSR by label (counting sort).
    let node_count = nodes.len();
    let mut start = vec![0usize; node_count + 1];
    for &l in labels.iter() {
        if l != u32::MAX {
            start[l as usize + 1] += 1;
        }
    }
    for c in 0..node_count {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut members = vec![0u32; start[node_count]];
    for (v, &l) in labels.iter().enumerate() {
        if l != u32::MAX {
            members[fill[l as usize]] = v as u32;
            fill[l as usize] += 1;
        }
    }
    // Dijkstra state, reset per cell for its members only.
    let mut dist = vec![f32::INFINITY; n];
    let mut side = vec![0u8; n];
    let mut heap: BinaryHeap<Reverse<(u32, u32, u8)>> = BinaryHeap::new();
    let mut seeds: Vec<u32> = Vec::new();
    let mut sums: Vec<(Vec3, u32)> = Vec::new();
    let mut added = 0;
    for &(c, parts) in bad {
        if added >= budget {
            break;
        }
        let cell = &members[start[c as usize]..start[c as usize + 1]];
        if cell.len() < 2 {
            continue;
        }
        // Seeds by farthest-point sampling from the cell's vertex nearest to its node.
        let parts = (parts as usize).min(budget - added + 1).min(cell.len());
        seeds.clear();
        let node = nodes[c as usize];
        // The next seed: the cell's vertex farthest from the seeds so far.
        let farthest = |seeds: &[u32]| {
            let gap = |v: u32| {
                seeds
                    .iter()
                    .map(|&s| (positions[v as usize] - positions[s as usize]).length_squared())
                    .fold(f32::INFINITY, f32::min)
            };
            cell.iter()
                .copied()
                .map(|v| (gap(v), v))
                .filter(|x| x.0 > 0.0)
                .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
        };
        // The first seed is the vertex nearest to the node.
        let Some(first) = cell.iter().copied().min_by(|&a, &b| {
            (positions[a as usize] - node)
                .length_squared()
                .total_cmp(&(positions[b as usize] - node).length_squared())
                .then(a.cmp(&b))
        }) else {
            continue;
        };
        seeds.push(first);
        while seeds.len() < parts {
            match farthest(&seeds) {
                Some((_, v)) => seeds.push(v),
                None => break,
            }
        }
        if seeds.len() < 2 {
            continue;
        }
        // Multi-source Dijkstra inside the cell; distances as f32 bits (non-negative floats
        // order like their bit patterns), ties broken by vertex index for determinism.
        heap.clear();
        for (s, &seed) in seeds.iter().enumerate() {
            dist[seed as usize] = 0.0;
            side[seed as usize] = s as u8;
            heap.push(Reverse((0f32.to_bits(), seed, s as u8)));
        }
        while let Some(Reverse((d_bits, v, s))) = heap.pop() {
            let d = f32::from_bits(d_bits);
            if d > dist[v as usize] || (d == dist[v as usize] && side[v as usize] != s) {
                continue;
            }
            let p = positions[v as usize];
            for &w in &nbrs[offset[v as usize]..offset[v as usize + 1]] {
                if labels[w as usize] != c {
                    continue;
                }
                let nd = d + (positions[w as usize] - p).length();
                if nd < dist[w as usize] {
                    dist[w as usize] = nd;
                    side[w as usize] = s;
                    heap.push(Reverse((nd.to_bits(), w, s)));
                }
            }
        }
        // Part 0 keeps the node, the others become new nodes; every node moves to its part's
        // centroid. Vertices no seed reached (none when cells are connected) stay in part 0.
        sums.clear();
        sums.resize(seeds.len(), (Vec3::ZERO, 0u32));
        for &v in cell {
            let s = if dist[v as usize].is_finite() {
                side[v as usize] as usize
            } else {
                0
            };
            sums[s].0 += positions[v as usize];
            sums[s].1 += 1;
        }
        let first_new = nodes.len() as u32;
        for &v in cell {
            if dist[v as usize].is_finite() && side[v as usize] > 0 {
                labels[v as usize] = first_new + side[v as usize] as u32 - 1;
            }
            dist[v as usize] = f32::INFINITY;
            side[v as usize] = 0;
        }
        nodes[c as usize] = sums[0].0 / sums[0].1.max(1) as f32;
        for &(sum, count) in &sums[1..] {
            nodes.push(sum / count.max(1) as f32);
            node_comp.push(node_comp[c as usize]);
        }
        added += seeds.len() - 1;
    }
    added
}

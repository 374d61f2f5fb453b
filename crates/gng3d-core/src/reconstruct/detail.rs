//! Phase-2 detail nodes (option (g)): give a node of its own to the places where the network's
//! mesh stays farthest from the original, then build the mesh again.
//!
//! A Growing Neural Gas spreads its nodes by signal density, not by error: a scan's spike, the
//! tip of an ear or a CAD corner gets no more nodes than the flat surface around it, and the
//! node that wins it sits at its cell's centroid. Quadric placement and the refit pull the
//! surface towards such a place but cannot reach it with the vertices they have, so the
//! symmetric Hausdorff max of GNG3D-Q was 2.23× QEM's (survey median) while its mean distance
//! was 1.18×; with three rounds of this step 1.47× and 1.06× (docs/notes/gngq.md, "Detail
//! nodes"). The tail it removes is sparse: on gargoyle-10k at 50 % the 55 original vertices
//! farther than half the maximum from the mesh lay at 50 places.
//!
//! Steps:
//! 1. **Deviation**: the distance to the mesh built so far of every original vertex and every
//!    original edge's midpoint (a thin ridge or a crease can leave every vertex on the mesh and
//!    its edges off it: on gargoyle-10k the worst point was a midpoint, 2.6e-3 from the mesh,
//!    where no vertex was farther than 9.4e-4), an edge's counted at both ends. Measured over the
//!    faces around the output vertices of the point's own cells and their neighbours' (an upper
//!    bound of the true distance; with the own cells only, the median Hausdorff ratio of 16
//!    runs was 2.06 instead of 1.74: the bound was too loose and chose the wrong cells). A
//!    cheaper bound over the own cells' fans comes first, and only the points whose bound can
//!    reach the floor of step 2 are measured in full. At most
//!    [`MAX_POINTS_PER_OUTPUT_VERTEX`] points per output vertex, at a fixed stride.
//! 2. **Choose**: the farthest vertex of each cell; the cells ordered by that distance, those
//!    above [`MIN_DEVIATION_SHARE`] × the largest kept, at most `budget` of them (one per cell
//!    per round, so a long crease gets nodes along it rather than all at one end).
//! 3. **Insert**: a new node at each chosen vertex's position; its cell grows from that vertex
//!    over the original's edges through the vertices nearer to it than to their own node (so the
//!    cell is connected, and only the neighbourhood of the new node is relabelled).
//!
//! It adds nodes, so the output has more vertices than the network: like the topology repair it
//! is for oversampled runs, whose decimation brings the count back to the target. The
//! decimation then sees the new vertex as the sharp feature it is and keeps it.

use super::OriginalTables;
use glam::{DVec3, Vec3};
use mesh::TriMesh;

/// Most detail nodes a round adds, as a share of the mesh's vertices. On large meshes
/// [`MIN_DEVIATION_SHARE`] stops a round first (gargoyle-10k at 50 %: 0.05 and 0.1 chose the
/// same 267 nodes); on nine runs with small outputs 0.02 / 0.03 / 0.05 gave a median Hausdorff
/// ratio to QEM of 1.32 / 1.46 / 1.23 and the same E_avg wins.
pub(crate) const NODES_PER_ROUND: f64 = 0.05;

/// A cell is chosen only when its farthest vertex is at least this share of the farthest
/// chosen one: a budget that is larger than the places that need it then goes unused rather
/// than into flat regions the decimation removes again (0.4 instead: the same medians on nine
/// runs).
pub(crate) const MIN_DEVIATION_SHARE: f64 = 0.25;

/// At most about this many points (original vertices and edge midpoints) are measured per
/// output vertex, at a fixed stride: at low output ratios (igea at 1 %: 33 original vertices and
/// 100 edges per output vertex) every point took 0.21 s a round, and the places that need a
/// node there are wider than one original vertex.
pub(crate) const MAX_POINTS_PER_OUTPUT_VERTEX: usize = 16;

/// Below this many original vertices per thread the deviations stay on one thread.
const MIN_VERTICES_PER_THREAD: usize = 8_192;

/// Steps 1-2: up to `budget` original vertices, the farthest of their cells from the mesh
/// (`positions`, `triangles`), farthest first. `owner[v]` is the output vertex of original
/// vertex `v` (`u32::MAX`: none).
pub(crate) fn farthest_vertices(
    original: &TriMesh,
    tables: &OriginalTables,
    owner: &[u32],
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    budget: usize,
    threads: usize,
) -> Vec<u32> {
    if budget == 0 || triangles.is_empty() {
        return Vec::new();
    }
    let outputs = positions.len();
    let fans = crate::surface::fans(triangles, outputs);
    let pos: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
    let adjacency = &tables.adjacency;
    // Squared distance from `q` to the faces around the output vertices in `around`
    // (crate::fan_search: each face once, a bounding-box bound before the exact test, a tree
    // for high-valence fans). The bound cut detail rounds of gargoyle-10k at 50 % 0.22 ->
    // 0.12 s, stanford-bunny at 10 % 0.16 -> 0.11 s (medians of 5 alternating runs).
    let search = crate::surface::fan_search::FanSearch::new(&fans, triangles, &pos);
    let distance_to_fans = |q: DVec3, around: &[u32]| search.nearest(q, around).0;
    // The output vertices whose fans hold the closest face to a point near original vertices
    // `ends` (their own cells and their neighbours'; at most 16).
    let cells_around = |ends: &[u32], around: &mut [u32; 16]| {
        let mut count = 0;
        for &v in ends {
            let v = v as usize;
            let neighbours = &adjacency.nbrs[adjacency.offset[v]..adjacency.offset[v + 1]];
            for &n in std::iter::once(&(v as u32)).chain(neighbours) {
                let w = owner[n as usize];
                if w != u32::MAX && count < around.len() && !around[..count].contains(&w) {
                    around[count] = w;
                    count += 1;
                }
            }
        }
        count
    };
    // Step 1: the points measured are the original vertices and the midpoints of the original
    // edges (a thin ridge or a crease can leave every vertex on the mesh and its edges off it);
    // point `k < V` is vertex `k`, point `V + e` the midpoint of edge `e`, counted at both ends.
    let vertex_count = original.positions.len();
    let edges = &tables.edges.edges;
    let ends_of = |k: usize| -> [u32; 2] {
        if k < vertex_count {
            [k as u32; 2]
        } else {
            edges[k - vertex_count]
        }
    };
    let point = |k: usize| -> Option<(DVec3, [u32; 2])> {
        let ends = ends_of(k);
        if owner[ends[0] as usize] == u32::MAX || owner[ends[1] as usize] == u32::MAX {
            return None;
        }
        let [a, b] = ends.map(|v| original.positions[v as usize].as_dvec3());
        Some((0.5 * (a + b), ends))
    };
    // A cheap upper bound first (the fans of the ends' own cells: 6-12 faces), then the
    // distance over the neighbours' cells too, for the points whose bound can still reach the
    // floor (a lower bound of the floor comes from the point with the largest bound): on igea
    // at 1 % the full search on every point took 0.21 s a round.
    let all_points = vertex_count + edges.len();
    let stride = all_points
        .div_ceil(MAX_POINTS_PER_OUTPUT_VERTEX * outputs)
        .max(1);
    let points = all_points.div_ceil(stride);
    let point = |k: usize| point(k * stride);
    let upper = crate::parallel::map_indexed(points, threads, MIN_VERTICES_PER_THREAD, |k| {
        point(k).map_or(0.0, |(q, ends)| {
            let own = [owner[ends[0] as usize], owner[ends[1] as usize]];
            let d = distance_to_fans(q, &own[..if own[0] == own[1] { 1 } else { 2 }]);
            if d.is_finite() { d } else { 0.0 }
        })
    });
    let refine = |k: usize| {
        point(k).map_or(0.0, |(q, ends)| {
            let mut around = [u32::MAX; 16];
            let count = cells_around(
                if ends[0] == ends[1] {
                    &ends[..1]
                } else {
                    &ends
                },
                &mut around,
            );
            let d = distance_to_fans(q, &around[..count]);
            if d.is_finite() { d } else { 0.0 }
        })
    };
    let Some(top) = (0..points).max_by(|&a, &b| upper[a].total_cmp(&upper[b]).then(b.cmp(&a)))
    else {
        return Vec::new();
    };
    let floor_at_least = refine(top) * MIN_DEVIATION_SHARE * MIN_DEVIATION_SHARE;
    let candidates: Vec<usize> = (0..points)
        .filter(|&k| upper[k] > 0.0 && upper[k] >= floor_at_least)
        .collect();
    // Step 2: the farthest vertex of each cell, cells by that distance; only the cells that
    // can still be chosen are measured in full (`choose`).
    choose(
        &candidates,
        &upper,
        |k| ends_of(k * stride),
        owner,
        outputs,
        refine,
        budget,
    )
}

/// Step 2 without measuring every candidate: the cells in the order of their farthest vertex
/// (squared distance descending, vertex ascending), those at least [`MIN_DEVIATION_SHARE`] of
/// the farthest, at most `budget`, as if every candidate point had been measured. A cell's
/// candidates are measured (`refine`) only when the largest of their upper bounds (`upper`,
/// ≥ `refine`) tops every other cell's bound or measured distance; a point counts at its ends
/// (`ends`), in the cells `owner` gives them. The same choice as measuring all of them
/// ([`choose_measuring_all`], the test's reference) with a fraction of the measurements: on
/// stanford-bunny at 50 % a round has 124k candidate points for 1,300 chosen cells.
fn choose(
    candidates: &[usize],
    upper: &[f64],
    ends: impl Fn(usize) -> [u32; 2],
    owner: &[u32],
    outputs: usize,
    refine: impl Fn(usize) -> f64,
    budget: usize,
) -> Vec<u32> {
    use std::cmp::Ordering;
    // Candidates of each cell (CSR by cell; a point with both ends in one cell once).
    let cells_of = |i: usize| {
        let [a, b] = ends(candidates[i]).map(|v| owner[v as usize]);
        (a, (b != a).then_some(b))
    };
    let mut start = vec![0usize; outputs + 1];
    for i in 0..candidates.len() {
        let (a, b) = cells_of(i);
        start[a as usize + 1] += 1;
        if let Some(b) = b {
            start[b as usize + 1] += 1;
        }
    }
    for o in 0..outputs {
        start[o + 1] += start[o];
    }
    let mut fill = start.clone();
    let mut members = vec![0usize; start[outputs]];
    for i in 0..candidates.len() {
        let (a, b) = cells_of(i);
        for o in std::iter::once(a).chain(b) {
            members[fill[o as usize]] = i;
            fill[o as usize] += 1;
        }
    }
    // A heap entry: (value, exact, vertex, cell). Larger values first; at equal values an
    // upper bound before a measured cell (it may measure the same with a smaller vertex);
    // measured cells of equal value by vertex, smaller first.
    #[derive(PartialEq)]
    struct Entry(f64, bool, u32, u32);
    impl Eq for Entry {}
    impl Ord for Entry {
        fn cmp(&self, other: &Self) -> Ordering {
            self.0
                .total_cmp(&other.0)
                .then(other.1.cmp(&self.1))
                .then(other.2.cmp(&self.2))
        }
    }
    impl PartialOrd for Entry {
        fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
            Some(self.cmp(other))
        }
    }
    let mut heap = std::collections::BinaryHeap::new();
    for o in 0..outputs {
        let bound = members[start[o]..start[o + 1]]
            .iter()
            .map(|&i| upper[candidates[i]])
            .fold(0.0f64, f64::max);
        if bound > 0.0 {
            heap.push(Entry(bound, false, u32::MAX, o as u32));
        }
    }
    let mut measured = vec![f64::NAN; candidates.len()];
    let mut chosen = Vec::new();
    let mut floor = None;
    while let Some(Entry(value, exact, vertex, cell)) = heap.pop() {
        if floor.is_some_and(|f| value < f) || chosen.len() == budget {
            break;
        }
        if exact {
            floor.get_or_insert(value * MIN_DEVIATION_SHARE * MIN_DEVIATION_SHARE);
            chosen.push(vertex);
            continue;
        }
        // Measure the cell: each of its vertices at the largest distance of the points at it.
        let mut best = (0.0f64, u32::MAX);
        for &i in &members[start[cell as usize]..start[cell as usize + 1]] {
            if measured[i].is_nan() {
                measured[i] = refine(candidates[i]);
            }
            for v in ends(candidates[i]) {
                if owner[v as usize] == cell {
                    let d = measured[i];
                    if d > best.0 || (d == best.0 && d > 0.0 && v < best.1) {
                        best = (d, v);
                    }
                }
            }
        }
        if best.0 > 0.0 {
            heap.push(Entry(best.0, true, best.1, cell));
        }
    }
    chosen
}

/// [`choose`] by measuring every candidate (the reference of its test).
#[cfg(test)]
fn choose_measuring_all(
    candidates: &[usize],
    ends: impl Fn(usize) -> [u32; 2],
    owner: &[u32],
    outputs: usize,
    refine: impl Fn(usize) -> f64,
    budget: usize,
) -> Vec<u32> {
    let mut deviation = vec![0.0f64; owner.len()];
    for &k in candidates {
        let d = refine(k);
        for v in ends(k) {
            deviation[v as usize] = deviation[v as usize].max(d);
        }
    }
    let mut farthest = vec![(0.0f64, u32::MAX); outputs];
    for (v, &o) in owner.iter().enumerate() {
        if o != u32::MAX && deviation[v] > farthest[o as usize].0 {
            farthest[o as usize] = (deviation[v], v as u32);
        }
    }
    let mut cells: Vec<(f64, u32)> = farthest.into_iter().filter(|c| c.0 > 0.0).collect();
    cells.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let Some(&(largest, _)) = cells.first() else {
        return Vec::new();
    };
    let floor = largest * MIN_DEVIATION_SHARE * MIN_DEVIATION_SHARE; // squared distances
    cells
        .into_iter()
        .take_while(|c| c.0 >= floor)
        .take(budget)
        .map(|c| c.1)
        .collect()
}

/// Step 3: a new node at each vertex of `chosen`, appended to `nodes` and `node_comp`, and the
/// vertices nearer to it than to their own node, connected to it, relabelled.
pub(crate) fn insert_nodes(
    original: &TriMesh,
    tables: &OriginalTables,
    chosen: &[u32],
    labels: &mut [u32],
    nodes: &mut Vec<Vec3>,
    node_comp: &mut Vec<u32>,
) {
    let adjacency = &tables.adjacency;
    let mut stack: Vec<u32> = Vec::new();
    for &seed in chosen {
        let old = labels[seed as usize];
        if old == u32::MAX {
            continue;
        }
        let node = nodes.len() as u32;
        let at = original.positions[seed as usize];
        nodes.push(at);
        node_comp.push(node_comp[old as usize]);
        labels[seed as usize] = node;
        stack.clear();
        stack.push(seed);
        while let Some(v) = stack.pop() {
            let v = v as usize;
            for &w in &adjacency.nbrs[adjacency.offset[v]..adjacency.offset[v + 1]] {
                let l = labels[w as usize];
                if l == node || l == u32::MAX {
                    continue;
                }
                let p = original.positions[w as usize];
                if (p - at).length_squared() < (p - nodes[l as usize]).length_squared() {
                    labels[w as usize] = node;
                    stack.push(w);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lazy choice equals measuring every candidate, on random cells, points, bounds and
    /// distances, with ties (distances on a coarse grid) and several budgets; and it measures
    /// fewer.
    #[test]
    fn choosing_lazily_equals_measuring_every_candidate() {
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut next = |n: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % n
        };
        let (mut lazy_calls, mut all_calls) = (0, 0);
        for case in 0..300 {
            let outputs = 1 + next(30) as usize;
            let vertices = outputs + next(120) as usize;
            let owner: Vec<u32> = (0..vertices)
                .map(|_| {
                    if next(10) == 0 {
                        u32::MAX
                    } else {
                        next(outputs as u64) as u32
                    }
                })
                .collect();
            let owned: Vec<u32> = (0..vertices as u32)
                .filter(|&v| owner[v as usize] != u32::MAX)
                .collect();
            if owned.is_empty() {
                continue;
            }
            let points = 1 + next(300) as usize;
            let ends: Vec<[u32; 2]> = (0..points)
                .map(|_| {
                    let a = owned[next(owned.len() as u64) as usize];
                    let b = if next(3) == 0 {
                        a
                    } else {
                        owned[next(owned.len() as u64) as usize]
                    };
                    [a, b]
                })
                .collect();
            let levels = if case % 2 == 0 { 4 } else { 1000 };
            let refined: Vec<f64> = (0..points).map(|_| next(levels) as f64).collect();
            let upper: Vec<f64> = refined.iter().map(|&r| r + next(3) as f64).collect();
            let candidates: Vec<usize> = (0..points).filter(|&k| upper[k] > 0.0).collect();
            for budget in [0, 1, 2, 5, outputs] {
                let calls = std::cell::Cell::new(0);
                let lazy = choose(
                    &candidates,
                    &upper,
                    |k| ends[k],
                    &owner,
                    outputs,
                    |k| {
                        calls.set(calls.get() + 1);
                        refined[k]
                    },
                    budget,
                );
                let all = choose_measuring_all(
                    &candidates,
                    |k| ends[k],
                    &owner,
                    outputs,
                    |k| refined[k],
                    budget,
                );
                assert_eq!(lazy, all, "case {case}, budget {budget}");
                assert!(calls.get() <= candidates.len());
                lazy_calls += calls.get();
                all_calls += candidates.len();
            }
        }
        assert!(lazy_calls < all_calls, "{lazy_calls} of {all_calls}");
    }
}

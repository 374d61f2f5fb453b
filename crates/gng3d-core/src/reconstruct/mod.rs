//! Phase 2: reconstruction by "concordance". Every original vertex is labelled with its nearest
//! node; every original face becomes the triple of its corners' labels. Degenerate triples are
//! dropped, duplicates (in either orientation) merged, and optional passes filter by GNG edges,
//! remove non-manifold fins and fill small holes; then every node that no triangle references is
//! attached, the output vertices are placed ([`placement`]) and edges flipped toward
//! the surface ([`flip`]).
//!
//! The steps and their order are [`crate::pipeline`]'s; this module holds the steps of the
//! reconstruction proper (labelling, connected cells, face mapping, cleanup, attachment) with
//! the cell splits ([`split`], option (f)) and the detail nodes ([`detail`], option (g)).
//!
//! The original's edge table and vertex adjacency depend on the original alone: a
//! [`crate::Trainer`] builds them on a helper thread while it trains and hands them over with its
//! distinct points and components; the pipeline builds them on a second thread while it labels
//! when no trainer did. Labelling, placement and the flips' point assignment are independent per vertex and
//! run on all cores ([`crate::parallel`]); every result is the same for any thread count.

use crate::domain::Pieces;
use crate::params::{OppositeFaces, ReconstructionParams};
pub use crate::report::ReconstructionReport;
use crate::surface::{kd_tree, label_with_threads, nearest};
use glam::Vec3;
use kiddo::ImmutableKdTree;
use mesh::TriMesh;
use mesh::topology::UnionFind;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

pub(crate) mod attach;
mod cleanup;
pub(crate) mod detail;
pub(crate) mod flip;
pub(crate) mod placement;
pub(crate) mod refit;
pub(crate) mod split;

/// Most rounds of option (f) (map, split the bad cells, map again). The cow at 10 % needs 7, the
/// thin torus of the tests 4; the shared meshes at 5-25 % settle within 8.
pub(crate) const SPLIT_ROUNDS: usize = 8;

/// Most nodes option (f) adds, as a share of the original's vertices that have no node (the
/// thin torus of the tests needs 5.5 new nodes per node; the cow at 5 % 0.9).
pub(crate) const SPLIT_BUDGET: f64 = 0.5;

pub(crate) use attach::Attachment;
use cleanup::{fill_holes, remove_fins};

/// Result of phase 2.
#[derive(Debug, Clone)]
pub struct Reconstruction {
    /// The simplified mesh; its vertices are the referenced nodes (moved by the placement).
    pub mesh: TriMesh,
    /// For each output vertex, the index of the node it came from.
    pub node_of_vertex: Vec<u32>,
    /// What each step did.
    pub report: ReconstructionReport,
}

/// Component-aware labels: each node belongs to the connected piece of the original holding
/// its nearest vertex (by majority over its connected group of GNG edges, which never span two
/// pieces when the trainer trains each piece on its own), and each vertex takes the nearest
/// node of its own piece (`u32::MAX` for unreferenced vertices and pieces without nodes). Two
/// nearby pieces then never share a node, and a piece's faces are never stitched to another's.
/// Returns the labels and the piece of each node.
pub(crate) fn labels_and_node_components(
    original: &TriMesh,
    input: &Pieces,
    nodes: &[Vec3],
    edges: &[[u32; 2]],
    threads: usize,
) -> (Vec<u32>, Vec<u32>) {
    let (ids, distinct, comp, count) = (&input.ids, &input.distinct, &input.comp, input.count);
    if count <= 1 || nodes.is_empty() {
        let mut labels = label_with_threads(&original.positions, nodes, threads);
        for (l, &i) in labels.iter_mut().zip(ids) {
            if i == u32::MAX {
                *l = u32::MAX;
            }
        }
        return (labels, vec![0; nodes.len()]);
    }
    let Some(points) = kd_tree(distinct) else {
        return (
            vec![u32::MAX; original.positions.len()],
            vec![0; nodes.len()],
        );
    };
    let nearest_comp: Vec<u32> = nodes
        .iter()
        .map(|&p| comp[nearest(&points, p) as usize])
        .collect();
    // Majority vote over GNG-connected groups (union-find over the edges).
    // Roots serve only as group keys, and the vote's tie rule does not depend on the order of
    // the map, so any union order gives the same components.
    let mut groups = UnionFind::new(nodes.len());
    for e in edges {
        groups.union(e[0], e[1]);
    }
    let mut votes: HashMap<(u32, u32), u32> = HashMap::default();
    for (i, &c) in nearest_comp.iter().enumerate() {
        *votes.entry((groups.find(i as u32), c)).or_insert(0) += 1;
    }
    let mut group_comp: HashMap<u32, (u32, u32)> = HashMap::default();
    for (&(g, c), &n) in &votes {
        let e = group_comp.entry(g).or_insert((c, n));
        if n > e.1 || (n == e.1 && c < e.0) {
            *e = (c, n);
        }
    }
    let mut by_comp: Vec<Vec<u32>> = vec![Vec::new(); count];
    let mut node_comp = vec![0u32; nodes.len()];
    for i in 0..nodes.len() as u32 {
        let g = groups.find(i);
        let c = group_comp[&g].0;
        by_comp[c as usize].push(i);
        node_comp[i as usize] = c;
    }
    let trees: Vec<Option<ImmutableKdTree<f64, 3>>> = by_comp
        .iter()
        .map(|members| {
            let pts: Vec<Vec3> = members.iter().map(|&i| nodes[i as usize]).collect();
            kd_tree(&pts)
        })
        .collect();
    let labels = original
        .positions
        .iter()
        .zip(ids)
        .map(|(&p, &i)| {
            if i == u32::MAX {
                return u32::MAX;
            }
            let c = comp[i as usize] as usize;
            match &trees[c] {
                Some(t) => by_comp[c][nearest(t, p) as usize],
                None => u32::MAX,
            }
        })
        .collect();
    (labels, node_comp)
}

/// What phase 2 needs from the original alone: its edge table (borders, boundary quadrics) and
/// its vertex adjacency (connected cells). A [`crate::Trainer`] builds them on a helper thread
/// while the network trains; [`crate::Snapshot::reconstruct`] builds them next to the
/// labelling.
#[derive(Debug, Clone)]
pub(crate) struct OriginalTables {
    pub edges: mesh::topology::EdgeTable,
    pub adjacency: VertexAdjacency,
}

impl OriginalTables {
    /// Tables of `original`.
    pub(crate) fn of(original: &TriMesh) -> OriginalTables {
        OriginalTables {
            edges: mesh::topology::EdgeTable::new(original),
            adjacency: VertexAdjacency::of(original),
        }
    }
}

/// Vertex adjacency of a mesh (CSR): each vertex's neighbours through its faces
/// ([`mesh::topology::VertexFaces`]); duplicates are harmless.
#[derive(Debug, Clone)]
pub(crate) struct VertexAdjacency {
    pub offset: Vec<usize>,
    pub nbrs: Vec<u32>,
}

impl VertexAdjacency {
    fn of(original: &TriMesh) -> VertexAdjacency {
        // Each face's other two corners, in corner order, around each vertex's faces.
        let faces = mesh::topology::VertexFaces::new(&original.triangles, original.positions.len());
        let offset: Vec<usize> = faces.start.iter().map(|&s| 2 * s as usize).collect();
        let mut nbrs = Vec::with_capacity(2 * faces.faces.len());
        for v in 0..faces.len() {
            for &f in faces.of(v) {
                let t = original.triangles[f as usize];
                let k = t.iter().position(|&u| u as usize == v).unwrap_or(0);
                nbrs.extend([t[(k + 1) % 3], t[(k + 2) % 3]]);
            }
        }
        VertexAdjacency { offset, nbrs }
    }
}

/// Make every node's cell (the original vertices labelled with it) edge-connected on the
/// original mesh: keep the component holding the vertex closest to the node and give the other
/// vertices, by breadth-first growth, the label of an adjacent vertex whose node is closest.
/// Returns the number of vertices relabelled.
pub(crate) fn make_cells_connected(
    original: &TriMesh,
    tables: &OriginalTables,
    nodes: &[Vec3],
    labels: &mut [u32],
) -> usize {
    let adjacency = &tables.adjacency;
    let n = original.positions.len();
    if nodes.is_empty() || n == 0 {
        return 0;
    }
    let (offset, nbrs) = (&adjacency.offset, &adjacency.nbrs);
    let neighbours = |v: usize| &nbrs[offset[v]..offset[v + 1]];
    // Anchor of each node: its labelled vertex nearest to it.
    let mut anchor = vec![(f32::INFINITY, u32::MAX); nodes.len()];
    for (v, &l) in labels.iter().enumerate() {
        if l == u32::MAX || offset[v] == offset[v + 1] {
            continue;
        }
        let d = (original.positions[v] - nodes[l as usize]).length_squared();
        if d < anchor[l as usize].0 {
            anchor[l as usize] = (d, v as u32);
        }
    }
    // The part of each cell connected to its anchor (what a flood from the anchor reaches) is
    // the anchor's component of the edges whose ends share a label: union-find over the unique
    // edges visits each edge once, where a flood over the adjacency lists visits each twice per
    // face (igea: 19 → 6 ms). Vertices elsewhere are orphans.
    let mut parts = UnionFind::new(n);
    for &[a, b] in &tables.edges.edges {
        let l = labels[a as usize];
        if l != u32::MAX && l == labels[b as usize] {
            parts.union(a, b);
        }
    }
    let mut keep = vec![false; n];
    for v in 0..n {
        let l = labels[v];
        if l != u32::MAX {
            let a = anchor[l as usize].1;
            keep[v] = a != u32::MAX && parts.find(v as u32) == parts.find(a);
        }
    }
    let mut queue: std::collections::VecDeque<u32> = std::collections::VecDeque::new();
    for v in 0..n {
        if !keep[v] && offset[v] != offset[v + 1] && neighbours(v).iter().any(|&w| keep[w as usize])
        {
            queue.push_back(v as u32);
        }
    }
    let mut relabelled = 0;
    while let Some(v) = queue.pop_front() {
        let v = v as usize;
        if keep[v] {
            continue;
        }
        let p = original.positions[v];
        let best = neighbours(v)
            .iter()
            .filter(|&&w| keep[w as usize])
            .map(|&w| labels[w as usize])
            .min_by(|&a, &b| {
                (nodes[a as usize] - p)
                    .length_squared()
                    .total_cmp(&(nodes[b as usize] - p).length_squared())
                    .then(a.cmp(&b))
            });
        if let Some(l) = best {
            if labels[v] != l {
                relabelled += 1;
            }
            labels[v] = l;
            keep[v] = true;
            for &w in neighbours(v) {
                if !keep[w as usize] {
                    queue.push_back(w);
                }
            }
        }
    }
    relabelled
}

/// Key of an undirected edge.
#[inline]
fn edge_key(a: u32, b: u32) -> (u32, u32) {
    if a < b { (a, b) } else { (b, a) }
}

/// A candidate output triangle with its support (how many original faces mapped to it).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Candidate {
    pub tri: [u32; 3],
    /// Original faces mapping to the triple in the kept orientation.
    pub support: u32,
}

/// Map the original faces to label triples, merge duplicates, resolve orientation and run
/// options (a) and (b); sets the face counts of `report`. Returns the candidates and, per
/// node, whether its cell holds a vertex of an original border.
pub(crate) fn map_faces(
    original: &TriMesh,
    original_edges: &mesh::topology::EdgeTable,
    labels: &[u32],
    nodes: &[Vec3],
    edges: &[[u32; 2]],
    params: &ReconstructionParams,
    report: &mut ReconstructionReport,
) -> (Vec<Candidate>, Vec<bool>) {
    report.degenerate_faces = 0;
    report.duplicate_faces = 0;
    report.opposite_faces = 0;
    // Map faces to triples, merge duplicates by sorted key with per-orientation votes.
    // Orientation sign: +1 when the triple rotated to start at its smallest label is ascending.
    // Sized for the output (a closed mesh of N vertices has ~2N faces), not the input: at 1 %
    // almost every original face is degenerate, and a table for all 269k of igea's was ~5 MB
    // allocated and faulted in for ~5k entries.
    let mut index: HashMap<[u32; 3], usize> = HashMap::with_capacity_and_hasher(
        (2 * nodes.len() + 16).min(original.triangles.len()),
        Default::default(),
    );
    let mut triples: Vec<([u32; 3], [u32; 2])> = Vec::new(); // (first seen triple, votes [+, -])
    for t in &original.triangles {
        let l = t.map(|v| labels[v as usize]);
        if l[0] == l[1] || l[1] == l[2] || l[0] == l[2] || l.contains(&u32::MAX) {
            report.degenerate_faces += 1;
            continue;
        }
        let mut key = l;
        key.sort_unstable();
        let rot = rotate_min_first(l);
        let positive = rot == key;
        let slot = *index.entry(key).or_insert_with(|| {
            triples.push((l, [0, 0]));
            triples.len() - 1
        });
        triples[slot].1[usize::from(!positive)] += 1;
    }
    let mut faces: Vec<Candidate> = Vec::with_capacity(triples.len());
    for (first, votes) in triples {
        let [pos, neg] = votes;
        if pos > 0 && neg > 0 && params.opposite_faces == OppositeFaces::DropBoth {
            report.opposite_faces += (pos + neg) as usize;
            continue;
        }
        let first_positive = {
            let mut key = first;
            key.sort_unstable();
            rotate_min_first(first) == key
        };
        // Majority orientation; ties keep the first-seen one.
        let keep_positive = if pos == neg {
            first_positive
        } else {
            pos > neg
        };
        let (kept, other) = if keep_positive {
            (pos, neg)
        } else {
            (neg, pos)
        };
        report.duplicate_faces += (kept - 1) as usize;
        report.opposite_faces += other as usize;
        let tri = if keep_positive == first_positive {
            first
        } else {
            [first[0], first[2], first[1]]
        };
        faces.push(Candidate {
            tri,
            support: pos + neg,
        });
    }

    if params.require_gng_edges {
        let set: HashSet<(u32, u32)> = edges.iter().map(|e| edge_key(e[0], e[1])).collect();
        let before = faces.len();
        faces.retain(|c| {
            let [a, b, d] = c.tri;
            set.contains(&edge_key(a, b))
                && set.contains(&edge_key(b, d))
                && set.contains(&edge_key(d, a))
        });
        report.non_gng_faces = before - faces.len();
    }

    // Nodes whose cell holds a vertex of an original border: a hole of the output along them
    // is a hole of the input, and is kept open.
    let mut on_border = vec![false; nodes.len()];
    for e in 0..original_edges.len() {
        if original_edges.is_boundary(e) {
            for v in original_edges.edges[e] {
                if let Some(&l) = labels.get(v as usize)
                    && l != u32::MAX
                {
                    on_border[l as usize] = true;
                }
            }
        }
    }

    if params.cleanup {
        report.fin_faces = remove_fins(&mut faces, nodes);
        if params.max_hole_edges >= 3 {
            let (holes, added) = fill_holes(&mut faces, nodes, &on_border, params.max_hole_edges);
            report.holes_filled = holes;
            report.fill_faces = added;
        }
    }

    (faces, on_border)
}

/// The cyclic rotation of `t` that starts at its smallest entry.
#[inline]
fn rotate_min_first(t: [u32; 3]) -> [u32; 3] {
    if t[0] < t[1] && t[0] < t[2] {
        t
    } else if t[1] < t[2] {
        [t[1], t[2], t[0]]
    } else {
        [t[2], t[0], t[1]]
    }
}

/// Directed edges of a triangle.
#[inline]
fn half_edges(t: [u32; 3]) -> [(u32, u32); 3] {
    [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Placement;

    /// Phase 2 of the network `nodes` (with GNG `edges`) over `original`.
    fn reconstruct(
        original: &TriMesh,
        nodes: &[Vec3],
        edges: &[[u32; 2]],
        params: &ReconstructionParams,
    ) -> Reconstruction {
        let snap = crate::Snapshot {
            positions: nodes.to_vec(),
            edges: edges.to_vec(),
            ..Default::default()
        };
        snap.reconstruct(original, params)
    }

    #[test]
    fn identity_nodes_reproduce_the_mesh() {
        let m = mesh::procedural::icosphere(2);
        let r = reconstruct(&m, &m.positions, &[], &ReconstructionParams::default());
        assert_eq!(r.mesh.face_count(), m.face_count());
        assert_eq!(r.report.degenerate_faces, 0);
        assert!(r.report.topology.closed && r.report.topology.manifold);
        assert_eq!(r.report.topology.genus, Some(0));
        assert!((r.mesh.signed_volume() - m.signed_volume()).abs() < 1e-9);
    }

    /// A node that wins no vertex (here one far outside the sphere) is attached, and it is put
    /// on the triangle it split, for the paper's placement and for GNG3D-Q's, instead of
    /// staying where training left it (which set the Hausdorff max at 50 % targets).
    #[test]
    fn attached_node_moves_onto_the_triangle_it_splits() {
        let m = mesh::procedural::icosphere(2);
        let mut nodes = m.positions.clone();
        nodes.push(Vec3::new(0.1, 0.2, 4.0));
        for placement in [Placement::Node, Placement::Quadric] {
            let params = ReconstructionParams {
                placement,
                flip_edges: false,
                ..ReconstructionParams::default()
            };
            let r = reconstruct(&m, &nodes, &[], &params);
            assert_eq!(r.mesh.vertex_count(), nodes.len(), "{placement:?}");
            assert_eq!(r.report.attached_nodes, 1, "{placement:?}");
            let v = r
                .node_of_vertex
                .iter()
                .position(|&n| n as usize == nodes.len() - 1)
                .expect("the far node is an output vertex");
            let radius = r.mesh.positions[v].length();
            // Inside a face of the unit icosphere (level 2): between its inradius and 1.
            assert!(
                (0.9..=1.0 + 1e-5).contains(&radius),
                "{placement:?}: {radius}"
            );
            assert!(r.report.topology.closed && r.report.topology.manifold);
            assert_eq!(r.report.degenerate_faces, 0);
        }
    }

    /// Distance from `p` to the nearest triangle of `m` (brute force).
    fn distance_to_mesh(m: &TriMesh, p: Vec3) -> f64 {
        (0..m.face_count())
            .map(|f| {
                let [a, b, c] = m.triangle_f64(f);
                let q = p.as_dvec3();
                (mesh::geometry::closest_point_triangle(q, a, b, c) - q).length()
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn detail_nodes_reach_a_spike_the_network_missed() {
        // A unit sphere with one vertex pulled out to radius 1.4 (a scan's spike), and nodes
        // at the vertices of a coarser sphere, none at the spike: its cell's node sits on the
        // sphere and the plain mesh passes ~0.4 below the tip.
        let mut m = mesh::procedural::icosphere(4);
        let nodes = mesh::procedural::icosphere(2).positions;
        let spike = (0..m.vertex_count())
            .find(|&v| nodes.iter().all(|n| n.distance(m.positions[v]) > 0.05))
            .unwrap();
        m.positions[spike] *= 1.4;
        let tip = m.positions[spike];
        let plain = reconstruct(&m, &nodes, &[], &ReconstructionParams::default());
        assert_eq!(plain.report.detail_nodes, 0);
        let missed = distance_to_mesh(&plain.mesh, tip);
        assert!(missed > 0.25, "plain mesh {missed} from the tip");
        let params = ReconstructionParams {
            detail_rounds: 2,
            ..ReconstructionParams::default()
        };
        let r = reconstruct(&m, &nodes, &[], &params);
        let reached = distance_to_mesh(&r.mesh, tip);
        assert!(reached < 0.1 * missed, "{reached} vs {missed}");
        // Few nodes (the spike, not the smooth sphere), each one a vertex, topology kept.
        assert!((1..=10).contains(&r.report.detail_nodes), "{:?}", r.report);
        assert_eq!(r.mesh.vertex_count(), nodes.len() + r.report.detail_nodes);
        let t = &r.report.topology;
        assert!(t.closed && t.manifold && t.genus == Some(0), "{t:?}");
        // Deterministic.
        assert_eq!(reconstruct(&m, &nodes, &[], &params).mesh, r.mesh);
    }

    /// Option (f) on a thin tube: nodes on the core circle of a thin torus each win a ring of
    /// the tube (an annulus), so every face maps to a degenerate triple and the plain mapping
    /// loses the surface; splitting the non-disc cells, and then the cells along the holes the
    /// mapping made, gives back a closed manifold of genus 1 in one piece.
    #[test]
    fn splitting_bad_cells_rebuilds_a_thin_tube() {
        let m = mesh::procedural::torus(1.0, 0.06, 64, 8);
        let core: Vec<Vec3> = (0..32)
            .map(|k| {
                let a = k as f32 / 32.0 * std::f32::consts::TAU;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let plain = reconstruct(&m, &core, &[], &ReconstructionParams::default());
        assert_eq!(plain.report.split_cells, 0);
        assert!(
            !(plain.report.topology.closed && plain.report.topology.genus == Some(1)),
            "{:?}",
            plain.report.topology
        );
        let params = ReconstructionParams {
            split_bad_cells: true,
            ..ReconstructionParams::default()
        };
        let r = reconstruct(&m, &core, &[], &params);
        let t = &r.report.topology;
        assert!(t.closed && t.manifold, "{t:?}");
        assert_eq!((t.components, t.genus), (1, Some(1)), "{t:?}");
        assert!(r.report.split_cells > 0 && r.report.split_cells <= m.vertex_count() / 2);
        assert_eq!(r.mesh.vertex_count(), core.len() + r.report.split_cells);
        // Every vertex near the tube: a tube three or four vertices round, fitted to a round
        // one, has its corners outside it (here up to 1.4 radii).
        for p in &r.mesh.positions {
            let ring = (p.truncate().length() - 1.0).hypot(p.z);
            assert!(ring < 0.1, "{p} is {ring} from the core circle");
        }
    }

    /// A hole of the input (here the 1-ring of vertex 0 removed) is kept open, while the same
    /// loop, when it is not along an original border (a hole the mapping made), is closed by
    /// `fill_holes` with faces oriented like their neighbours.
    #[test]
    fn input_holes_stay_open_and_mapping_holes_are_filled() {
        let m = mesh::procedural::icosphere(2);
        let mut holed = m.clone();
        holed.triangles.retain(|t| !t.contains(&0));
        let r = reconstruct(
            &holed,
            &holed.positions,
            &[],
            &ReconstructionParams::default(),
        );
        assert_eq!(r.report.holes_filled, 0);
        // 5 edges, or 6 when the unreferenced node 0 is attached on the loop.
        assert!(
            r.report.topology.boundary_edges >= 5,
            "{:?}",
            r.report.topology
        );

        let mut faces: Vec<Candidate> = holed
            .triangles
            .iter()
            .map(|&tri| Candidate { tri, support: 1 })
            .collect();
        let before = faces.len();
        let not_border = vec![false; holed.positions.len()];
        let (holes, added) = fill_holes(&mut faces, &holed.positions, &not_border, 8);
        assert_eq!((holes, added), (1, 3));
        assert_eq!(faces.len(), before + 3);
        let filled = TriMesh::new(
            holed.positions.clone(),
            faces.iter().map(|c| c.tri).collect(),
        );
        let topology = mesh::topology::analyze(&filled);
        assert!(topology.closed && topology.manifold);
        assert!(filled.signed_volume() > 0.0);
        // The same loop along an original border stays open.
        let border = vec![true; holed.positions.len()];
        let mut faces: Vec<Candidate> = holed
            .triangles
            .iter()
            .map(|&tri| Candidate { tri, support: 1 })
            .collect();
        assert_eq!(fill_holes(&mut faces, &holed.positions, &border, 8), (0, 0));
    }
}

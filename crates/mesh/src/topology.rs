//! Topology report: edges, boundary loops, non-manifold elements, components, Euler
//! characteristic and genus, plus the reusable [`EdgeTable`] adjacency and a [`UnionFind`].
//!
//! Definitions follow `shared/meshes/README.md`: edges are unique undirected triangle edges; a
//! boundary edge has one incident face, a non-manifold edge three or more; boundary loops are
//! the connected components of the boundary-edge graph; a non-manifold vertex has incident faces
//! forming more than one edge-connected fan; χ = V_referenced − E + F; genus is
//! `(2C − χ' − b) / 2` with χ' computed after splitting every vertex into its fans and C the
//! number of components of that split surface (faces connected through shared edges).
//! Edges are grouped by a counting sort on their smaller endpoint, so the analysis is O(F + V)
//! apart from sorting the half-edges around each vertex.

use crate::TriMesh;
use serde::{Deserialize, Serialize};

/// Disjoint-set forest with path halving and union by size.
#[derive(Debug, Clone)]
pub struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    /// `n` singleton sets.
    pub fn new(n: usize) -> UnionFind {
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    /// Make this `n` singleton sets again, reusing the storage.
    pub fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
        self.size.clear();
        self.size.resize(n, 1);
    }

    /// Representative of `x`'s set.
    #[inline(always)]
    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    /// Make `into`'s set the representative of `from`'s: after it `find(from) == find(into)`
    /// and the root of `into` stays a root (for callers whose representative must be a given
    /// vertex, as in pair contraction). True when they were different.
    #[inline(always)]
    pub fn merge_into(&mut self, into: u32, from: u32) -> bool {
        let (ra, rb) = (self.find(into), self.find(from));
        if ra == rb {
            return false;
        }
        self.parent[rb as usize] = ra;
        self.size[ra as usize] += self.size[rb as usize];
        true
    }

    /// Merge the sets of `a` and `b`; true when they were different.
    #[inline(always)]
    pub fn union(&mut self, a: u32, b: u32) -> bool {
        let (mut ra, mut rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        if self.size[ra as usize] < self.size[rb as usize] {
            std::mem::swap(&mut ra, &mut rb);
        }
        self.parent[rb as usize] = ra;
        self.size[ra as usize] += self.size[rb as usize];
        true
    }
}

/// The faces around each vertex in CSR form: vertex `v`'s faces are
/// `faces[start[v]..start[v + 1]]`, in face order. The one vertex → face builder of the
/// workspace (QEM's preparation, GNG3D-Q's fans and cells).
///
/// ```
/// use gng3d_mesh::{procedural, topology::VertexFaces};
/// let sphere = procedural::icosphere(1);
/// let around = VertexFaces::new(&sphere.triangles, sphere.positions.len());
/// // every face is listed once at each of its three corners
/// assert_eq!(around.faces.len(), 3 * sphere.triangles.len());
/// assert!(around.of(0).iter().all(|&f| sphere.triangles[f as usize].contains(&0)));
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct VertexFaces {
    /// Start of each vertex's list in `faces` (length: vertex count + 1).
    pub start: Vec<u32>,
    /// Face indices, grouped by vertex.
    pub faces: Vec<u32>,
}

impl VertexFaces {
    /// The faces around each of `vertex_count` vertices (every index must be below it).
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize) -> VertexFaces {
        VertexFaces::grouped(vertex_count, triangles.len(), |f| triangles[f])
    }

    /// Faces `0..face_count` grouped by the keys `keys(f)` (each below `key_count`), in face
    /// order: a face is listed under each distinct key of its three, and `u32::MAX` keys are
    /// skipped. With `keys(f)` a face's corners this is [`VertexFaces::new`]; with the corners'
    /// owners (a vertex → cell map) it gives the faces touching each cell.
    pub fn grouped(
        key_count: usize,
        face_count: usize,
        keys: impl Fn(usize) -> [u32; 3],
    ) -> VertexFaces {
        let distinct = |f: usize| {
            let k = keys(f);
            [
                k[0],
                if k[1] != k[0] { k[1] } else { u32::MAX },
                if k[2] != k[0] && k[2] != k[1] {
                    k[2]
                } else {
                    u32::MAX
                },
            ]
        };
        let mut start = vec![0u32; key_count + 1];
        for f in 0..face_count {
            for k in distinct(f) {
                if k != u32::MAX {
                    start[k as usize + 1] += 1;
                }
            }
        }
        for k in 0..key_count {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut faces = vec![0u32; start[key_count] as usize];
        for f in 0..face_count {
            for k in distinct(f) {
                if k != u32::MAX {
                    faces[fill[k as usize] as usize] = f as u32;
                    fill[k as usize] += 1;
                }
            }
        }
        VertexFaces { start, faces }
    }

    /// The faces of vertex (or key) `v`.
    #[inline]
    pub fn of(&self, v: usize) -> &[u32] {
        &self.faces[self.start[v] as usize..self.start[v + 1] as usize]
    }

    /// Number of vertices (keys).
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// True for no vertices.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// One editable list per vertex (for passes that change faces as they go).
    pub fn to_lists(&self) -> Vec<Vec<u32>> {
        (0..self.len()).map(|v| self.of(v).to_vec()).collect()
    }
}

/// Unique undirected edges of a triangle mesh with their incident faces.
///
/// Edge `e` joins `edges[e] = [a, b]` with `a < b`; edges are sorted. The faces around edge `e`
/// are `corners(e)` / 3, and `face_edges[f][i]` is the edge from corner `i` to corner `(i+1)%3`
/// of face `f`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EdgeTable {
    /// Endpoints of each unique edge, smaller index first, sorted.
    pub edges: Vec<[u32; 2]>,
    /// `offsets[e]..offsets[e+1]` indexes `edge_corners` for edge `e` (length edges + 1).
    pub offsets: Vec<u32>,
    /// Half-edge ids `3 * face + i` grouped by edge; face = id / 3.
    pub edge_corners: Vec<u32>,
    /// For each face, the edge index of its three sides (side i: corner i → corner i+1).
    pub face_edges: Vec<[u32; 3]>,
}

impl EdgeTable {
    /// Build the table from the 3F half-edges: a counting sort by the smaller endpoint, then a
    /// sort of each (small) bucket by the larger endpoint. O(F + V) plus the bucket sorts;
    /// no allocation per edge. Vertex indices beyond the largest used one cost nothing.
    pub fn new(mesh: &TriMesh) -> EdgeTable {
        let f = mesh.triangles.len();
        let n = mesh.index_bound();
        // bucket_start[v]..bucket_start[v + 1]: half-edges whose smaller endpoint is v.
        let mut bucket_start = vec![0u32; n + 1];
        for t in &mesh.triangles {
            for i in 0..3 {
                bucket_start[t[i].min(t[(i + 1) % 3]) as usize + 1] += 1;
            }
        }
        for v in 0..n {
            bucket_start[v + 1] += bucket_start[v];
        }
        // Each half-edge packed as (larger endpoint << 32) | half-edge id, so sorting a bucket
        // orders it by edge, and by half-edge id within an edge.
        let mut packed = vec![0u64; 3 * f];
        let mut fill: Vec<u32> = bucket_start[..n].to_vec();
        for (fi, t) in mesh.triangles.iter().enumerate() {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                let slot = &mut fill[a.min(b) as usize];
                packed[*slot as usize] = ((a.max(b) as u64) << 32) | (3 * fi + i) as u64;
                *slot += 1;
            }
        }
        drop(fill);
        let mut edges = Vec::with_capacity(3 * f / 2 + 1);
        let mut offsets = Vec::with_capacity(3 * f / 2 + 2);
        let mut edge_corners = Vec::with_capacity(3 * f);
        let mut face_edges = vec![[0u32; 3]; f];
        for v in 0..n {
            let bucket = &mut packed[bucket_start[v] as usize..bucket_start[v + 1] as usize];
            bucket.sort_unstable();
            let mut last = u32::MAX;
            for &p in bucket.iter() {
                let (other, corner) = ((p >> 32) as u32, p as u32);
                if other != last {
                    offsets.push(edge_corners.len() as u32);
                    edges.push([v as u32, other]);
                    last = other;
                }
                let e = (edges.len() - 1) as u32;
                face_edges[corner as usize / 3][corner as usize % 3] = e;
                edge_corners.push(corner);
            }
        }
        offsets.push(edge_corners.len() as u32);
        EdgeTable {
            edges,
            offsets,
            edge_corners,
            face_edges,
        }
    }

    /// Number of unique edges.
    pub fn len(&self) -> usize {
        self.edges.len()
    }

    /// True when the mesh has no edges.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty()
    }

    /// Number of faces incident to edge `e`.
    #[inline]
    pub fn face_count(&self, e: usize) -> usize {
        (self.offsets[e + 1] - self.offsets[e]) as usize
    }

    /// Half-edge ids (`3 * face + side`) of edge `e`.
    #[inline]
    pub fn corners(&self, e: usize) -> &[u32] {
        &self.edge_corners[self.offsets[e] as usize..self.offsets[e + 1] as usize]
    }

    /// Faces incident to edge `e`.
    pub fn faces(&self, e: usize) -> impl Iterator<Item = u32> + '_ {
        self.corners(e).iter().map(|c| c / 3)
    }

    /// True when edge `e` has exactly one incident face.
    #[inline]
    pub fn is_boundary(&self, e: usize) -> bool {
        self.face_count(e) == 1
    }
}

/// Topological summary of a triangle mesh (see the module docs for the definitions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct TopologyReport {
    /// Vertex records, including unreferenced ones.
    pub vertices: usize,
    /// Vertices used by at least one face.
    pub referenced_vertices: usize,
    /// Triangles.
    pub faces: usize,
    /// Unique undirected edges.
    pub edges: usize,
    /// Edges with exactly one incident face.
    pub boundary_edges: usize,
    /// Connected components of the boundary-edge graph.
    pub boundary_loops: usize,
    /// Edges with three or more incident faces.
    pub non_manifold_edges: usize,
    /// Vertices whose incident faces form more than one edge-connected fan.
    pub non_manifold_vertices: usize,
    /// Connected components of faces joined through shared edges.
    pub components: usize,
    /// χ = referenced vertices − edges + faces.
    pub euler_characteristic: i64,
    /// χ after splitting every non-manifold vertex into its fans.
    pub euler_characteristic_split: i64,
    /// `(2C − χ' − b) / 2`; None with non-manifold edges or when the formula is not an integer.
    pub genus: Option<i64>,
    /// No boundary edges.
    pub closed: bool,
    /// No non-manifold edges or vertices.
    pub manifold: bool,
}

/// Marker for "no edge" in per-corner edge pairs.
const NO_EDGE: u32 = u32::MAX;

/// Compute the [`TopologyReport`] of `mesh`. Faces must index valid vertices.
pub fn analyze(mesh: &TriMesh) -> TopologyReport {
    analyze_with(mesh, &EdgeTable::new(mesh))
}

/// Number of edge-connected fans of faces around each vertex of `mesh` (0 for a vertex no
/// face uses, 1 for a manifold vertex, more at a pinch where sheets meet at a point). `table`
/// is the mesh's [`EdgeTable`]. A corner repeating its face's vertex (degenerate face) forms a
/// fan of its own.
pub fn vertex_fan_counts(mesh: &TriMesh, table: &EdgeTable) -> Vec<u32> {
    let v = mesh.positions.len();
    let f = mesh.triangles.len();
    // For each vertex, the corners at it (counting sort, ascending corner id), each stored as
    // the two edges meeting there: side `i` and side `i - 1` of its face.
    let mut corner_start = vec![0u32; v + 1];
    for t in &mesh.triangles {
        for &i in t {
            corner_start[i as usize + 1] += 1;
        }
    }
    for i in 0..v {
        corner_start[i + 1] += corner_start[i];
    }
    let mut corner_edges = vec![[NO_EDGE; 2]; 3 * f];
    let mut fill: Vec<u32> = corner_start[..v].to_vec();
    for (t, sides) in mesh.triangles.iter().zip(&table.face_edges) {
        for i in 0..3 {
            let slot = &mut fill[t[i] as usize];
            if !t[..i].contains(&t[i]) {
                corner_edges[*slot as usize] = [sides[i], sides[(i + 2) % 3]];
            }
            *slot += 1;
        }
    }
    drop(fill);

    // Fans: around each vertex, its corners joined through the edges they share, found with a
    // pairwise scan with fan labels (up to 32 corners), or a sorted union-find local to the
    // vertex beyond that.
    let mut counts = vec![0u32; v];
    let mut local = UnionFind::new(0);
    let mut edge_and_corner: Vec<u64> = Vec::new();
    for (vertex, count) in counts.iter_mut().enumerate() {
        let corners =
            &corner_edges[corner_start[vertex] as usize..corner_start[vertex + 1] as usize];
        let k = corners.len();
        if k == 0 {
            continue;
        }
        let mut fans = k;
        if k <= 32 {
            // Fan labels: merging two fans relabels the second one (k is small).
            let mut label: [u8; 32] = std::array::from_fn(|j| j as u8);
            for (j, a) in corners.iter().enumerate() {
                if a[0] == NO_EDGE {
                    continue;
                }
                for (l, b) in corners.iter().enumerate().skip(j + 1) {
                    let shared = a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
                    let (keep, merge) = (label[j], label[l]);
                    if shared && b[0] != NO_EDGE && keep != merge {
                        fans -= 1;
                        for x in &mut label[..k] {
                            if *x == merge {
                                *x = keep;
                            }
                        }
                    }
                }
            }
        } else {
            local.reset(k);
            edge_and_corner.clear();
            for (j, sides) in corners.iter().enumerate() {
                if sides[0] != NO_EDGE {
                    edge_and_corner.extend(sides.iter().map(|&e| ((e as u64) << 32) | j as u64));
                }
            }
            edge_and_corner.sort_unstable();
            for w in edge_and_corner.windows(2) {
                if w[0] >> 32 == w[1] >> 32 && local.union(w[0] as u32, w[1] as u32) {
                    fans -= 1;
                }
            }
        }
        *count = fans as u32;
    }
    counts
}

/// [`analyze`] with a prebuilt [`EdgeTable`] of the same mesh.
pub fn analyze_with(mesh: &TriMesh, table: &EdgeTable) -> TopologyReport {
    let v = mesh.positions.len();
    let f = mesh.triangles.len();
    let fan_counts = vertex_fan_counts(mesh, table);
    let referenced_vertices = fan_counts.iter().filter(|&&n| n > 0).count();
    let fans_total: i64 = fan_counts.iter().map(|&n| n as i64).sum();
    let non_manifold_vertices = fan_counts.iter().filter(|&&n| n > 1).count();
    let mut boundary_edges = 0;
    let mut non_manifold_edges = 0;
    let mut boundary_graph = UnionFind::new(v);
    let mut on_boundary = vec![false; v];
    // Faces joined through edges. With one fan per vertex, all faces at a vertex are joined,
    // so joining the two vertices of every edge (V elements rather than F) gives the same
    // components; otherwise faces are joined directly.
    let join_vertices = non_manifold_vertices == 0;
    let mut joined = UnionFind::new(if join_vertices { v } else { f });
    for e in 0..table.len() {
        let corners = table.corners(e);
        match corners.len() {
            1 => {
                boundary_edges += 1;
                let [a, b] = table.edges[e];
                boundary_graph.union(a, b);
                on_boundary[a as usize] = true;
                on_boundary[b as usize] = true;
            }
            2 => {}
            _ => non_manifold_edges += 1,
        }
        if join_vertices {
            let [a, b] = table.edges[e];
            joined.union(a, b);
        } else {
            let first = corners[0] / 3;
            for &c in &corners[1..] {
                joined.union(first, c / 3);
            }
        }
    }
    let boundary_loops = (0..v as u32)
        .filter(|&i| on_boundary[i as usize] && boundary_graph.find(i) == i)
        .count();
    let components = if join_vertices {
        (0..v as u32)
            .filter(|&i| fan_counts[i as usize] > 0 && joined.find(i) == i)
            .count()
    } else {
        (0..f as u32).filter(|&i| joined.find(i) == i).count()
    };

    let edges = table.len() as i64;
    let euler = referenced_vertices as i64 - edges + f as i64;
    let euler_split = fans_total - edges + f as i64;
    let twice_genus = 2 * components as i64 - euler_split - boundary_loops as i64;
    let genus = (non_manifold_edges == 0 && twice_genus % 2 == 0).then_some(twice_genus / 2);
    TopologyReport {
        vertices: v,
        referenced_vertices,
        faces: f,
        edges: table.len(),
        boundary_edges,
        boundary_loops,
        non_manifold_edges,
        non_manifold_vertices,
        components,
        euler_characteristic: euler,
        euler_characteristic_split: euler_split,
        genus,
        closed: boundary_edges == 0,
        manifold: non_manifold_edges == 0 && non_manifold_vertices == 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::previous_topology;
    use crate::procedural::{icosphere, torus};
    use glam::Vec3;

    #[test]
    fn vertex_faces_match_a_scan() {
        // Independent computation: for each vertex, scan every face for it.
        let mesh = torus(1.0, 0.3, 12, 8);
        let around = VertexFaces::new(&mesh.triangles, mesh.positions.len());
        assert_eq!(around.len(), mesh.positions.len());
        for v in 0..mesh.positions.len() {
            let scan: Vec<u32> = (0..mesh.triangles.len() as u32)
                .filter(|&f| mesh.triangles[f as usize].contains(&(v as u32)))
                .collect();
            assert_eq!(around.of(v), &scan[..], "vertex {v}");
        }
        // Grouped by keys: repeated keys list a face once, u32::MAX keys are skipped.
        let keys = [[0, 0, 1], [2, u32::MAX, 2], [1, 2, 0]];
        let grouped = VertexFaces::grouped(3, keys.len(), |f| keys[f]);
        assert_eq!(grouped.of(0), &[0, 2]);
        assert_eq!(grouped.of(1), &[0, 2]);
        assert_eq!(grouped.of(2), &[1, 2]);
        assert_eq!(grouped.to_lists(), vec![vec![0, 2], vec![0, 2], vec![1, 2]]);
    }

    #[test]
    fn merge_into_keeps_the_given_representative() {
        let mut sets = UnionFind::new(6);
        // Union by size would make 1's root (the larger set) the representative.
        assert!(sets.union(1, 2));
        assert!(sets.merge_into(0, 1));
        assert_eq!((sets.find(1), sets.find(2)), (0, 0));
        assert!(sets.merge_into(5, 0));
        assert!((0..3).all(|v| sets.find(v) == 5));
        assert!(!sets.merge_into(2, 5));
    }

    #[test]
    fn icosphere_is_closed_genus_zero() {
        let m = icosphere(2);
        let r = analyze(&m);
        assert_eq!(r.edges, 3 * m.face_count() / 2);
        assert_eq!(r.euler_characteristic, 2);
        assert_eq!(r.genus, Some(0));
        assert_eq!(r.components, 1);
        assert!(r.closed && r.manifold);
    }

    #[test]
    fn torus_has_genus_one() {
        let r = analyze(&torus(1.0, 0.3, 24, 12));
        assert_eq!(r.euler_characteristic, 0);
        assert_eq!(r.genus, Some(1));
    }

    #[test]
    fn two_triangles_form_an_open_disc() {
        let m = TriMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y, Vec3::splat(3.0)],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        let r = analyze(&m);
        assert_eq!((r.vertices, r.referenced_vertices), (5, 4));
        assert_eq!((r.edges, r.boundary_edges, r.boundary_loops), (5, 4, 1));
        assert_eq!(r.genus, Some(0));
        assert!(!r.closed);
    }

    #[test]
    fn two_spheres_touching_at_a_vertex() {
        // Second sphere shares vertex 0 of the first: one pinch vertex, two fans there.
        let a = icosphere(1);
        let mut positions = a.positions.clone();
        let n = positions.len() as u32;
        positions.extend(a.positions.iter().map(|p| *p + Vec3::new(0.0, 0.0, 0.0)));
        let mut triangles = a.triangles.clone();
        triangles.extend(
            a.triangles
                .iter()
                .map(|t| t.map(|i| if i == 0 { 0 } else { i + n })),
        );
        let r = analyze(&TriMesh::new(positions, triangles));
        assert_eq!(r.non_manifold_vertices, 1);
        assert_eq!(r.non_manifold_edges, 0);
        assert_eq!(r.components, 2);
        assert_eq!(r.euler_characteristic, 3);
        assert_eq!(r.euler_characteristic_split, 4);
        assert_eq!(r.genus, Some(0));
        assert!(!r.manifold);
    }

    #[test]
    fn three_faces_on_an_edge_are_non_manifold() {
        let m = TriMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::NEG_Y],
            vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        );
        let r = analyze(&m);
        assert_eq!(r.non_manifold_edges, 1);
        assert_eq!(r.genus, None);
        let t = EdgeTable::new(&m);
        let e = t.edges.iter().position(|e| *e == [0, 1]).unwrap();
        assert_eq!(t.face_count(e), 3);
        assert_eq!(t.faces(e).collect::<Vec<_>>(), vec![0, 1, 2]);
        for (f, fe) in t.face_edges.iter().enumerate() {
            for i in 0..3 {
                let tri = m.triangles[f];
                let (a, b) = (tri[i].min(tri[(i + 1) % 3]), tri[i].max(tri[(i + 1) % 3]));
                assert_eq!(t.edges[fe[i] as usize], [a, b]);
            }
        }
    }

    /// Random soups over few vertices: many shared, non-manifold and degenerate faces.
    fn random_soup(seed: u64, vertices: u32, faces: usize) -> TriMesh {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
        let positions = (0..vertices).map(|i| Vec3::splat(i as f32)).collect();
        let triangles = (0..faces)
            .map(|_| std::array::from_fn(|_| rng.random_range(0..vertices)))
            .collect();
        TriMesh::new(positions, triangles)
    }

    #[test]
    fn matches_the_sort_based_reference() {
        let mut meshes = vec![
            TriMesh::default(),
            icosphere(3),
            torus(1.0, 0.3, 24, 12),
            crate::procedural::blob(),
        ];
        // Two disjoint spheres, one of them with a face removed (manifold, two components).
        let sphere = icosphere(2);
        let n = sphere.positions.len() as u32;
        let mut positions = sphere.positions.clone();
        positions.extend(sphere.positions.iter().map(|p| *p + Vec3::X * 3.0));
        let mut triangles = sphere.triangles.clone();
        triangles.extend(sphere.triangles[1..].iter().map(|t| t.map(|i| i + n)));
        meshes.push(TriMesh::new(positions, triangles));
        for seed in 0..200 {
            let vertices = 3 + (seed % 40) as u32;
            meshes.push(random_soup(seed, vertices, 1 + (seed as usize * 7) % 90));
        }
        for (k, m) in meshes.iter().enumerate() {
            assert_eq!(
                EdgeTable::new(m),
                previous_topology::edge_table(m),
                "mesh {k}"
            );
            assert_eq!(analyze(m), previous_topology::analyze(m), "mesh {k}");
        }
    }
}

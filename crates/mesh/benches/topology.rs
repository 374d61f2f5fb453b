//! `topology::analyze` against its previous implementation (one global sort of all half-edge
//! keys, then a global union-find over the 3F corners), timed in the same run on the same mesh:
//! igea.ply and igea-1m.ply from `GNG3D_MESHES` (failing under `CI` without them), else a
//! 327,680-face icosphere.
//!
//! Run: `GNG3D_MESHES=/work/shared/meshes cargo bench -p mesh --bench topology`.

// The crate's own `fixtures` module (behind the `fixtures` feature for other crates).
#[path = "../src/fixtures.rs"]
#[allow(dead_code, unused_imports)]
mod fixtures;
use criterion::{Criterion, criterion_group, criterion_main};
use mesh::TriMesh;
use std::hint::black_box;
use std::time::Duration;

/// The implementation before the counting-sort rewrite, verbatim apart from visibility.
mod previous {
    use mesh::TriMesh;
    use mesh::topology::{EdgeTable, TopologyReport, UnionFind};

    /// Edge table by sorting all packed half-edge keys at once (the previous implementation).
    pub fn edge_table(mesh: &TriMesh) -> EdgeTable {
        let f = mesh.triangles.len();
        let mut half: Vec<(u64, u32)> = Vec::with_capacity(3 * f);
        for (fi, t) in mesh.triangles.iter().enumerate() {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                let key = ((a.min(b) as u64) << 32) | a.max(b) as u64;
                half.push((key, (3 * fi + i) as u32));
            }
        }
        half.sort_unstable();
        let mut edges = Vec::with_capacity(3 * f / 2 + 1);
        let mut offsets = Vec::with_capacity(3 * f / 2 + 2);
        let mut edge_corners = Vec::with_capacity(3 * f);
        let mut face_edges = vec![[0u32; 3]; f];
        let mut last = u64::MAX;
        for &(key, corner) in &half {
            if key != last {
                offsets.push(edge_corners.len() as u32);
                edges.push([(key >> 32) as u32, key as u32]);
                last = key;
            }
            let e = (edges.len() - 1) as u32;
            face_edges[corner as usize / 3][corner as usize % 3] = e;
            edge_corners.push(corner);
        }
        offsets.push(edge_corners.len() as u32);
        EdgeTable {
            edges,
            offsets,
            edge_corners,
            face_edges,
        }
    }

    /// The previous global corner union-find implementation, kept as an independent check.
    pub fn analyze(mesh: &TriMesh) -> TopologyReport {
        let table = &edge_table(mesh);
        let v = mesh.positions.len();
        let f = mesh.triangles.len();
        let mut referenced = vec![false; v];
        for t in &mesh.triangles {
            for &i in t {
                referenced[i as usize] = true;
            }
        }
        let referenced_vertices = referenced.iter().filter(|&&r| r).count();

        let mut boundary_edges = 0;
        let mut non_manifold_edges = 0;
        let mut boundary_graph = UnionFind::new(v);
        let mut on_boundary = vec![false; v];
        let mut faces_uf = UnionFind::new(f);
        // Corners 3*face+i; corners of the same vertex joined across shared edges form fans.
        let mut fans_uf = UnionFind::new(3 * f);
        let corner_of = |face: u32, vertex: u32| -> u32 {
            let t = mesh.triangles[face as usize];
            let i = t.iter().position(|&x| x == vertex).unwrap_or(0);
            3 * face + i as u32
        };
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
            let [a, b] = table.edges[e];
            let first = corners[0] / 3;
            for &c in &corners[1..] {
                let face = c / 3;
                faces_uf.union(first, face);
                fans_uf.union(corner_of(first, a), corner_of(face, a));
                fans_uf.union(corner_of(first, b), corner_of(face, b));
            }
        }
        let boundary_loops = (0..v as u32)
            .filter(|&i| on_boundary[i as usize] && boundary_graph.find(i) == i)
            .count();
        let components = (0..f as u32).filter(|&i| faces_uf.find(i) == i).count();
        let mut fans_at = vec![0u32; v];
        let mut fans_total = 0i64;
        for c in 0..3 * f as u32 {
            if fans_uf.find(c) == c {
                fans_total += 1;
                fans_at[mesh.triangles[c as usize / 3][c as usize % 3] as usize] += 1;
            }
        }
        let non_manifold_vertices = fans_at.iter().filter(|&&n| n > 1).count();
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
}

/// The benchmark meshes and their names: igea and igea-1m from `GNG3D_MESHES`, else an icosphere.
fn inputs() -> Vec<(TriMesh, String)> {
    let Some(d) = fixtures::shared_meshes_dir("igea.ply") else {
        return vec![(mesh::procedural::icosphere(7), "icosphere7".to_string())];
    };
    ["igea", "igea-1m"]
        .into_iter()
        .filter(|name| d.join(format!("{name}.ply")).is_file())
        .map(|name| {
            let path = d.join(format!("{name}.ply"));
            let mesh = mesh::io::load(&path).expect("load mesh").mesh;
            (mesh, name.to_string())
        })
        .collect()
}

fn bench_topology(c: &mut Criterion) {
    for (mesh, name) in inputs() {
        assert_eq!(mesh::topology::analyze(&mesh), previous::analyze(&mesh));
        let mut group = c.benchmark_group(format!("topology/{name}"));
        group
            .sample_size(10)
            .measurement_time(Duration::from_secs(4));
        group.bench_function("analyze", |b| {
            b.iter(|| mesh::topology::analyze(black_box(&mesh)))
        });
        group.bench_function("previous", |b| {
            b.iter(|| previous::analyze(black_box(&mesh)))
        });
        group.finish();
    }
}

criterion_group!(benches, bench_topology);
criterion_main!(benches);

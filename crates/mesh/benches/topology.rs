//! `topology::analyze` against its previous implementation (one global sort of all half-edge
//! keys, then a global union-find over the 3F corners), timed in the same run on the same mesh:
//! igea.ply and igea-1m.ply from `GNG3D_MESHES` (failing under `CI` without them), else a
//! 327,680-face icosphere.
//!
//! Run: `GNG3D_MESHES=/work/shared/meshes cargo bench -p gng3d-mesh --bench topology`.

// Published as gng3d-mesh; this file keeps the workspace's name for it.
extern crate gng3d_mesh as mesh;

// The crate's own `fixtures` module (behind the `fixtures` feature for other crates).
#[path = "../src/fixtures.rs"]
#[allow(dead_code, unused_imports)]
mod fixtures;
use criterion::{Criterion, criterion_group, criterion_main};
use mesh::TriMesh;
use std::hint::black_box;
use std::time::Duration;

/// The implementation before the counting-sort rewrite, verbatim apart from visibility.
use fixtures::previous_topology as previous;

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

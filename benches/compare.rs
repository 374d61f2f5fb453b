//! End-to-end benchmark: `compare` (QEM + GNG3D + all metrics) on gargoyle-10k, plus each
//! stage alone so the share of each is visible in one run.

use criterion::{Criterion, criterion_group, criterion_main};
use gng3d::experiment::compare::{CompareParams, compare};
use gng3d::mesh::TriMesh;
use std::time::Duration;

fn gargoyle() -> Option<TriMesh> {
    let dir = gng3d::mesh::fixtures::shared_meshes_dir("gargoyle-10k.obj")?;
    let loaded = gng3d::mesh::io::load(&dir.join("gargoyle-10k.obj")).expect("gargoyle-10k.obj");
    Some(gng3d::mesh::clean::prepare(&loaded.mesh.into()).0.mesh)
}

fn bench(c: &mut Criterion) {
    let Some(mesh) = gargoyle() else { return };
    let target = mesh.vertex_count() / 2;
    let params = CompareParams::new(target);
    let mut group = c.benchmark_group("compare_gargoyle10k");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    group.bench_function("end_to_end", |b| {
        b.iter(|| compare(&mesh, &params).expect("compare"))
    });
    // Each method as `compare` runs it: the job's run of its request.
    let model = gng3d::mesh::Model::from(mesh.clone());
    let qem = gng3d::job::Request {
        method: gng3d::job::Method::Qem,
        ..params.request.clone()
    };
    group.bench_function("qem_only", |b| {
        b.iter(|| gng3d::job::run(&model, &qem, &mut ()).expect("qem"))
    });
    group.bench_function("gng_only", |b| {
        b.iter(|| gng3d::job::run(&model, &params.request, &mut ()).expect("gng"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

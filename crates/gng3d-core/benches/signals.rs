//! Training throughput (signals/s) of the grid search against a naive linear scan at 1k, 10k and
//! 50k nodes on armadillo, and the paper protocol on gargoyle-10k (phase 1 + 2).
//! Armadillo has 43k vertices, so the throughput groups use area-weighted surface signals
//! (`SignalSource::Surface`) at every size for comparability; `vertices/10000` shows the
//! paper's vertex signals at 10k nodes.
//! Meshes come from `GNG3D_MESHES`; without it the bench is skipped (fails when `CI` is set).
//!
//! `GNG3D_MESHES=/work/shared/meshes cargo bench -p gng3d-core --bench signals`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use gng3d_core::{GngParams, SearchStrategy, SignalSource, Trainer};
use mesh::TriMesh;
use std::time::Duration;

fn load(name: &str) -> Option<TriMesh> {
    let dir = mesh::fixtures::shared_meshes_dir(name)?;
    let loaded = mesh::io::load(&dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    Some(mesh::clean::prepare(&loaded.mesh.into()).0.mesh)
}

/// A trainer on `mesh` grown to `nodes` nodes, with a budget large enough not to finish.
fn grown(mesh: &TriMesh, nodes: usize, source: SignalSource) -> Trainer {
    let mut params = GngParams::for_target(nodes);
    params.signal_source = source;
    params.lambda = Some(20);
    params.max_signals = Some(u64::MAX / 4);
    let mut t = Trainer::new(&mesh.clone().into(), params).expect("trainer");
    while t.node_count() < nodes {
        t.step(100_000);
    }
    // Settle a few epochs at the target.
    t.step(20 * nodes as u64);
    t
}

fn signals(c: &mut Criterion) {
    let Some(armadillo) = load("armadillo.obj") else {
        return;
    };
    let mut group = c.benchmark_group("signals_armadillo");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
    for nodes in [1_000usize, 10_000, 50_000] {
        let mut grid = grown(&armadillo, nodes, SignalSource::Surface);
        let mut linear = grid.clone();
        linear.set_search_strategy(SearchStrategy::LinearScan);
        let batch = 100_000u64;
        group.throughput(Throughput::Elements(batch));
        group.bench_function(format!("grid/{nodes}"), |b| b.iter(|| grid.step(batch)));
        // The scan is O(nodes) per signal: keep its batches short.
        let batch = (20_000_000 / nodes as u64).max(200);
        group.throughput(Throughput::Elements(batch));
        group.bench_function(format!("linear/{nodes}"), |b| b.iter(|| linear.step(batch)));
    }
    let mut vertices = grown(&armadillo, 10_000, SignalSource::Vertices);
    group.throughput(Throughput::Elements(100_000));
    group.bench_function("vertices/10000", |b| b.iter(|| vertices.step(100_000)));
    group.finish();
}

fn gargoyle_protocol(c: &mut Criterion) {
    let Some(gargoyle) = load("gargoyle-10k.obj") else {
        return;
    };
    // The paper's protocol: 30 epochs of |V| signals, target = half the vertices.
    let params = GngParams::for_target(gargoyle.vertex_count() / 2);
    let mut group = c.benchmark_group("gargoyle_protocol");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(5));
    group.bench_function("phase1+2", |b| {
        b.iter(|| {
            let mut trainer =
                Trainer::new(&gargoyle.clone().into(), params.clone()).expect("trainer");
            while !trainer.is_finished() {
                trainer.step(u64::MAX);
            }
            gng3d_core::finish(&trainer, |_| {}).expect("finish")
        })
    });
    group.finish();
}

criterion_group!(benches, signals, gargoyle_protocol);
criterion_main!(benches);

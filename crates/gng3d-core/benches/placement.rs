//! GNG3D-Q phase-2 passes on trained networks: reconstruction with the paper's node placement
//! (baseline), with quadric placement, with quadric placement plus edge flips, and with all
//! three plus the surface refit (the default), on
//! armadillo at 10 % and igea at 1 % (the speed target). Divide the difference to the
//! baseline by the output size for "ms per 10k output vertices".
//! Meshes come from `GNG3D_MESHES`; without it the bench is skipped (fails when `CI` is set).
//!
//! `GNG3D_MESHES=/work/shared/meshes cargo bench -p gng3d-core --bench placement`

use criterion::{Criterion, criterion_group, criterion_main};
use gng3d_core::{GngParams, Placement, ReconstructionParams, Trainer};
use std::time::Duration;

fn bench(c: &mut Criterion) {
    for (name, ratio) in [("armadillo.obj", 0.1), ("igea.ply", 0.01)] {
        let Some(dir) = mesh::fixtures::shared_meshes_dir(name) else {
            return;
        };
        let loaded = mesh::io::load(&dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let original = mesh::clean::prepare(&loaded.mesh.into()).0.mesh;
        let target = (original.vertex_count() as f64 * ratio).round() as usize;
        let mut params = GngParams::for_target(target);
        params.max_signals = Some(20 * original.vertex_count() as u64);
        let mut trainer = Trainer::new(&original.clone().into(), params).expect("trainer");
        while !trainer.is_finished() {
            trainer.step(u64::MAX);
        }
        let mut group = c.benchmark_group(format!(
            "reconstruct_{}",
            name.split('.').next().unwrap_or(name)
        ));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(4));
        for (label, placement, flip_edges, refit) in [
            ("node", Placement::Node, false, false),
            ("quadric", Placement::Quadric, false, false),
            ("quadric_flip", Placement::Quadric, true, false),
            ("quadric_flip_refit", Placement::Quadric, true, true),
        ] {
            let rp = ReconstructionParams {
                placement,
                flip_edges,
                refit,
                ..ReconstructionParams::default()
            };
            let out = trainer.reconstruct(&rp).mesh.vertex_count();
            group.bench_function(format!("{label}/{out}v"), |b| {
                b.iter(|| trainer.reconstruct(&rp))
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! Criterion bench `qem`: `qem::simplify` next to `meshopt::simplify` (meshoptimizer) on the same
//! input and target, armadillo and igea at 10 % and 1 % of the faces. Before the criterion groups
//! it prints a summary with the best-of-N time ratio qem / meshopt measured in the same run.
//! Meshes come from `GNG3D_MESHES`.
//!
//! Group `hostile-fan` (issue 33, generated, needs no shared mesh): a flat fan of 1,000,000
//! triangles around one hub next to an ordinary grid of the same size (999,698 faces), both at
//! 10 %; the summary prints the time ratio fan / grid (`cargo bench -p gng3d-qem -- hostile`).

// Published as gng3d-qem; this file keeps the workspace's name for it.
extern crate gng3d_qem as qem;

use criterion::{Criterion, criterion_group, criterion_main};
use mesh::{Model, TriMesh};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// (file, prepared model) for the bench inputs.
fn inputs() -> Vec<(&'static str, Model)> {
    let Some(dir) = mesh::fixtures::shared_meshes_dir("igea.ply") else {
        return Vec::new();
    };
    ["armadillo.obj", "igea.ply"]
        .into_iter()
        .map(|name| {
            let loaded = mesh::io::load(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
            (name, mesh::clean::prepare(&loaded.mesh.into()).0)
        })
        .collect()
}

fn run_qem(m: &Model, faces: usize) -> usize {
    let params = qem::QemParams::with_target(qem::Target::Faces(faces));
    qem::simplify(m, &params).expect("qem").0.mesh.face_count()
}

fn run_meshopt(m: &TriMesh, indices: &[u32], faces: usize) -> usize {
    let adapter = meshopt::VertexDataAdapter::new(meshopt::typed_to_bytes(&m.positions), 12, 0)
        .expect("adapter");
    meshopt::simplify(
        indices,
        &adapter,
        faces * 3,
        f32::MAX,
        meshopt::SimplifyOptions::None,
        None,
    )
    .len()
        / 3
}

fn best_of(runs: usize, mut f: impl FnMut() -> usize) -> (Duration, usize) {
    let mut best = Duration::MAX;
    let mut out = 0;
    for _ in 0..runs {
        let t = Instant::now();
        out = black_box(f());
        best = best.min(t.elapsed());
    }
    (best, out)
}

/// Issue 33: the 1M-triangle fan against a grid of the same size, both at 10 %.
fn bench_fan(c: &mut Criterion) {
    let fan = Model::from(mesh::procedural::fan(1_000_000));
    let grid = Model::from(mesh::procedural::unit_square_grid(707)); // 999,698 faces
    let (tf, ff) = best_of(5, || run_qem(&fan, fan.mesh.face_count() / 10));
    let (tg, fg) = best_of(5, || run_qem(&grid, grid.mesh.face_count() / 10));
    println!(
        "qem on a fan of {} triangles around one hub vs a grid of {} (best of 5, 10 %): fan {:.4} s ({ff} faces), grid {:.4} s ({fg} faces), ratio {:.2}",
        fan.mesh.face_count(),
        grid.mesh.face_count(),
        tf.as_secs_f64(),
        tg.as_secs_f64(),
        tf.as_secs_f64() / tg.as_secs_f64()
    );
    let mut group = c.benchmark_group("hostile-fan-10pct");
    group.sample_size(10);
    for (name, m) in [("fan-1m", &fan), ("grid-1m", &grid)] {
        let faces = m.mesh.face_count() / 10;
        group.bench_function(name, |b| b.iter(|| run_qem(black_box(m), faces)));
    }
    group.finish();
}

fn bench(c: &mut Criterion) {
    let inputs = inputs();
    println!("qem vs meshopt (best of 5, same process):");
    for (name, model) in &inputs {
        let m = &model.mesh;
        let indices: Vec<u32> = m.triangles.iter().flatten().copied().collect();
        for pct in [10usize, 1] {
            let faces = m.face_count() * pct / 100;
            let (tq, fq) = best_of(5, || run_qem(model, faces));
            let (tm, fm) = best_of(5, || run_meshopt(m, &indices, faces));
            println!(
                "  {name} {} -> {faces} faces ({pct}%): qem {:.4} s ({fq} faces), meshopt {:.4} s ({fm} faces), ratio {:.2}",
                m.face_count(),
                tq.as_secs_f64(),
                tm.as_secs_f64(),
                tq.as_secs_f64() / tm.as_secs_f64()
            );
        }
    }
    for (name, model) in &inputs {
        let m = &model.mesh;
        let indices: Vec<u32> = m.triangles.iter().flatten().copied().collect();
        for pct in [10usize, 1] {
            let faces = m.face_count() * pct / 100;
            let mut group = c.benchmark_group(format!(
                "{}-{pct}pct",
                name.split('.').next().unwrap_or(name)
            ));
            group.sample_size(10);
            group.bench_function("qem", |b| b.iter(|| run_qem(black_box(model), faces)));
            group.bench_function("meshopt", |b| {
                b.iter(|| run_meshopt(black_box(m), &indices, faces))
            });
            group.finish();
        }
    }
}

criterion_group!(benches, bench_fan, bench);
criterion_main!(benches);

//! Criterion bench `attributes`: `qem::simplify` of a model with attributes next to meshoptimizer's
//! `meshopt_simplifyWithAttributes` on the same input and face target (10 % and 20 % of the
//! faces), on the textured and coloured assets: spot (`GNG3D_MESHES`, real UVs), the fandisk
//! atlas (xatlas UVs and normals) and the knight with vertex colours (`tests/assets`). All
//! attribute weights are 0 for both, the library default here.
//!
//! meshoptimizer gets what it takes: one vertex per wedge (position and attributes, f32) and the
//! corners as indices, built before timing; ours gets the model (mesh and `Attributes`), prepared as
//! the CLI does (`mesh::clean::prepare`). Before the criterion groups it prints
//! the best of 15 alternating calls of each and the ratio ours / meshoptimizer's
//! (`cargo bench -p gng3d-qem --bench attributes`).
//!
//! Larger textured meshes (not in the repository) join the alternating comparison, best of 5,
//! when `GNG3D_ATTRIBUTE_MESHES` lists them (comma-separated files), e.g. the xatlas atlases of
//! igea and igea-1m that `tests/assets/make_assets.py --large DIR` writes; run them with
//! `RAYON_NUM_THREADS=1`, as meshoptimizer runs on one thread (our set-up is parallel from
//! 8,192 vertices).

// Published as gng3d-qem; this file keeps the workspace's name for it.
extern crate gng3d_qem as qem;

use criterion::{Criterion, criterion_group, criterion_main};
use mesh::Model;
#[path = "../examples/common/wedge_buffers.rs"]
mod wedge_buffers;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use wedge_buffers::{WedgeBuffers, wedge_buffers};

/// One input: ours (the model with its attributes, and its mesh alone) and meshoptimizer's
/// (its wedge buffers).
struct Input {
    name: String,
    /// From `GNG3D_ATTRIBUTE_MESHES`: compared in fewer calls, and left out of the criterion
    /// groups.
    large: bool,
    model: Model,
    plain: Model,
    meshopt: WedgeBuffers,
}

fn inputs() -> Vec<Input> {
    let assets = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets");
    let mut files = vec![
        ("fandisk_atlas", assets.join("fandisk_atlas.obj")),
        ("knight_colors", assets.join("knight_colors.ply")),
    ];
    match mesh::fixtures::shared_meshes_dir("spot.obj") {
        Some(dir) => files.insert(0, ("spot", dir.join("spot.obj"))),
        None => println!("SKIPPED spot: GNG3D_MESHES does not hold spot.obj"),
    }
    let files = files
        .into_iter()
        .map(|(name, path)| (name.to_string(), path, false));
    let large = std::env::var("GNG3D_ATTRIBUTE_MESHES").unwrap_or_default();
    let large = large.split(',').filter(|p| !p.is_empty()).map(|p| {
        let path = PathBuf::from(p);
        let name = path
            .file_stem()
            .map_or(p.to_string(), |s| s.to_string_lossy().into_owned());
        (name, path, true)
    });
    files
        .chain(large)
        .map(|(name, path, large)| {
            let loaded = mesh::io::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let model = mesh::clean::prepare(&loaded.into()).0;
            let (mesh, attributes) = (
                model.mesh,
                model.attributes.expect("the asset has attributes"),
            );
            let meshopt = wedge_buffers(&mesh, &attributes);
            Input {
                name,
                large,
                plain: Model::from(mesh.clone()),
                model: Model {
                    attributes: Some(attributes),
                    ..Model::from(mesh)
                },
                meshopt,
            }
        })
        .collect()
}

fn run_qem(input: &Input, faces: usize) -> usize {
    let params = qem::QemParams::with_target(qem::Target::Faces(faces));
    let (out, _) = qem::simplify(&input.model, &params).expect("qem");
    out.mesh.face_count()
}

/// The same mesh without its attributes: the floor an attribute run cannot go below.
fn run_qem_positions(input: &Input, faces: usize) -> usize {
    let params = qem::QemParams::with_target(qem::Target::Faces(faces));
    qem::simplify(&input.plain, &params)
        .expect("qem")
        .0
        .mesh
        .face_count()
}

fn run_meshopt(input: &Input, faces: usize) -> usize {
    input.meshopt.simplify(faces)
}

/// Best of `runs` alternating calls of `f` and `g`.
fn alternate(
    runs: usize,
    mut f: impl FnMut() -> usize,
    mut g: impl FnMut() -> usize,
) -> [(Duration, usize); 2] {
    let mut best = [(Duration::MAX, 0); 2];
    for _ in 0..runs {
        for (i, h) in [&mut f as &mut dyn FnMut() -> usize, &mut g]
            .into_iter()
            .enumerate()
        {
            let t = Instant::now();
            let out = black_box(h());
            best[i] = (best[i].0.min(t.elapsed()), out);
        }
    }
    best
}

fn bench(c: &mut Criterion) {
    let inputs = inputs();
    println!(
        "qem with attributes vs meshoptimizer simplifyWithAttributes (best of 15 alternating calls, 5 for GNG3D_ATTRIBUTE_MESHES):"
    );
    if inputs.iter().any(|i| i.large) && rayon::current_num_threads() > 1 {
        println!(
            "  (GNG3D_ATTRIBUTE_MESHES with {} threads: ours sets up in parallel; \
             RAYON_NUM_THREADS=1 compares one thread with one)",
            rayon::current_num_threads()
        );
    }
    for input in &inputs {
        let runs = if input.large { 5 } else { 15 };
        for pct in [10usize, 20] {
            let faces = input.model.mesh.face_count() * pct / 100;
            let [(tq, fq), (tm, fm)] =
                alternate(runs, || run_qem(input, faces), || run_meshopt(input, faces));
            let [(tp, _), (tm2, _)] = alternate(
                runs,
                || run_qem_positions(input, faces),
                || run_meshopt(input, faces),
            );
            println!(
                "  {} {} -> {faces} faces ({pct}%): qem {:.3} ms ({fq} faces), meshopt {:.3} ms ({fm} faces), ratio {:.2}; qem without the attributes {:.3} ms, ratio {:.2}",
                input.name,
                input.model.mesh.face_count(),
                tq.as_secs_f64() * 1e3,
                tm.as_secs_f64() * 1e3,
                tq.as_secs_f64() / tm.as_secs_f64(),
                tp.as_secs_f64() * 1e3,
                tp.as_secs_f64() / tm2.as_secs_f64()
            );
        }
    }
    for input in inputs.iter().filter(|i| !i.large) {
        let faces = input.model.mesh.face_count() / 10;
        let mut group = c.benchmark_group(format!("attributes-{}-10pct", input.name));
        group.sample_size(20);
        group.bench_function("qem", |b| b.iter(|| run_qem(black_box(input), faces)));
        group.bench_function("meshopt", |b| {
            b.iter(|| run_meshopt(black_box(input), faces))
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

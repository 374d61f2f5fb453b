//! Symmetric Hausdorff distance of igea (268,686 triangles) against a ~27k-triangle QEM
//! simplification at 1M samples per direction, plus its parts (BVH build, sampling).
//!
//! Peer: MeshLab's `get_hausdorff_distance` through pymeshlab, timed in the same run when
//! `GNG3D_PYMESHLAB` names a Python interpreter that can `import pymeshlab` (same meshes, the same
//! total samples per direction: all vertices plus `samplenum` edge and `samplenum` face points).
//! Meshes come from `GNG3D_MESHES` (skipped without it, failing under `CI`).

use criterion::{Criterion, criterion_group, criterion_main};
use mesh::TriMesh;
use mesh::sampling::{StratifiedParams, sample_stratified};
use metrics::{HausdorffParams, SurfaceDistanceIndex, hausdorff};
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Samples per direction.
const SAMPLES: usize = 1_000_000;
/// Face count of the simplified mesh (10 % of igea).
const TARGET_FACES: usize = 26_869;

/// igea and its QEM simplification (also written to a temporary OBJ for the MeshLab peer).
fn inputs(dir: &Path) -> (TriMesh, TriMesh) {
    let original = mesh::io::load(&dir.join("igea.ply"))
        .expect("load igea.ply")
        .mesh;
    let params = qem::QemParams::with_target(qem::Target::Faces(TARGET_FACES));
    let original = mesh::Model::from(original);
    let (simplified, _) = qem::simplify(&original, &params).expect("qem simplify");
    (original.mesh, simplified.mesh)
}

/// Times pymeshlab's symmetric Hausdorff distance (both one-sided calls) on the same meshes and
/// sample counts; returns seconds per symmetric evaluation (best of `runs`).
fn meshlab_seconds(
    python: &Path,
    original: &Path,
    simplified: &Path,
    per_kind: [usize; 2],
) -> Option<f64> {
    let script = format!(
        r#"
import time, pymeshlab
ms = pymeshlab.MeshSet()
ms.load_new_mesh({o:?})
ms.load_new_mesh({s:?})
best = None
for _ in range(3):
    t = time.perf_counter()
    f = ms.get_hausdorff_distance(sampledmesh=0, targetmesh=1, samplevert=True, sampleedge=True, sampleface=True, samplenum={n0})
    b = ms.get_hausdorff_distance(sampledmesh=1, targetmesh=0, samplevert=True, sampleedge=True, sampleface=True, samplenum={n1})
    dt = time.perf_counter() - t
    best = dt if best is None else min(best, dt)
print(best, f["n_samples"], b["n_samples"], f["max"], b["max"])
"#,
        o = original.display().to_string(),
        s = simplified.display().to_string(),
        n0 = per_kind[0],
        n1 = per_kind[1],
    );
    let out = std::process::Command::new(python)
        .arg("-c")
        .arg(script)
        .output()
        .ok()?;
    if !out.status.success() {
        eprintln!("pymeshlab failed: {}", String::from_utf8_lossy(&out.stderr));
        return None;
    }
    let text = String::from_utf8_lossy(&out.stdout);
    eprintln!(
        "pymeshlab (best of 3): seconds, n_fwd, n_bwd, max_fwd, max_bwd = {}",
        text.trim()
    );
    text.split_whitespace().next()?.parse().ok()
}

fn bench(c: &mut Criterion) {
    let Some(dir) = mesh::fixtures::shared_meshes_dir("igea.ply") else {
        return;
    };
    let (original, simplified) = inputs(&dir);
    eprintln!(
        "igea: {} faces; simplified: {} faces; {} threads",
        original.face_count(),
        simplified.face_count(),
        rayon::current_num_threads()
    );
    let params = HausdorffParams::with_samples(SAMPLES);
    let h = hausdorff(&original, &simplified, &params).unwrap();
    eprintln!(
        "forward max {:.3e} mean {:.3e} ({} samples); backward max {:.3e} mean {:.3e} ({} samples)",
        h.forward.max,
        h.forward.mean,
        h.forward.samples,
        h.backward.max,
        h.backward.mean,
        h.backward.samples
    );

    let mut group = c.benchmark_group("hausdorff");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    group.bench_function("igea_vs_27k_1M_samples_symmetric", |b| {
        b.iter(|| hausdorff(black_box(&original), black_box(&simplified), &params).unwrap())
    });
    group.bench_function("build_index_igea", |b| {
        b.iter(|| SurfaceDistanceIndex::new(black_box(&original)).unwrap())
    });
    group.bench_function("sample_igea_1M", |b| {
        let plan = StratifiedParams {
            total: SAMPLES,
            ..Default::default()
        };
        b.iter(|| sample_stratified(black_box(&original), &plan, 1).unwrap())
    });
    group.finish();

    if let Some(python) = std::env::var_os("GNG3D_PYMESHLAB").map(PathBuf::from) {
        let tmp = std::env::temp_dir().join(format!("gng3d-bench-{}", std::process::id()));
        std::fs::create_dir_all(&tmp).unwrap();
        let simplified_path = tmp.join("igea-qem.ply");
        mesh::io::save(&simplified.clone().into(), &simplified_path).expect("save simplified mesh");
        // Same totals per direction as ours: all vertices + samplenum edges + samplenum faces.
        let per_kind = [
            (SAMPLES - h.forward.vertex_samples) / 2,
            (SAMPLES - h.backward.vertex_samples) / 2,
        ];
        if let Some(peer) =
            meshlab_seconds(&python, &dir.join("igea.ply"), &simplified_path, per_kind)
        {
            let start = std::time::Instant::now();
            let runs = 5;
            for _ in 0..runs {
                black_box(hausdorff(&original, &simplified, &params).unwrap());
            }
            let ours = start.elapsed().as_secs_f64() / runs as f64;
            eprintln!(
                "ours {ours:.3} s vs MeshLab {peer:.3} s per symmetric 1M-sample evaluation: {:.1}x faster; {:.2} M samples/s",
                peer / ours,
                2.0 * SAMPLES as f64 / ours / 1e6
            );
        }
        let _ = std::fs::remove_dir_all(&tmp);
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

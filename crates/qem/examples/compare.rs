//! Time `qem::simplify` against `meshopt::simplify` on one mesh:
//! `REPS=N cargo run --release -p gng3d-qem --example compare -- MESH RATIO [OUT.obj]`; the two
//! alternate call by call and best / median wall times, their ratios and per-thread on-CPU times
//! are printed.

mod common;

use common::{meshopt_adapter, meshopt_simplify};
use std::time::Instant;

/// On-CPU seconds of this thread (Linux schedstat), robust against a loaded machine.
fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| {
            s.split_whitespace()
                .next()
                .and_then(|t| t.parse::<f64>().ok())
        })
        .map_or(0.0, |ns| ns * 1e-9)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = std::path::Path::new(args.get(1).expect("usage: compare MESH RATIO [OUT]"));
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(7);
    let ratio: f64 = args.get(2).map_or(0.1, |s| s.parse().expect("ratio"));
    let loaded = mesh::io::load(path).expect("load");
    let model = mesh::clean::prepare(&loaded.mesh.into()).0;
    let m = &model.mesh;
    let target = ((m.face_count() as f64) * ratio).round() as usize;
    let params = gng3d_qem::QemParams::with_target(gng3d_qem::Target::Faces(target));
    let indices: Vec<u32> = m.triangles.iter().flatten().copied().collect();
    let adapter = meshopt_adapter(&m.positions);
    // qem and meshopt alternate, so that both see the same machine load.
    let (mut wall, mut wall_mo) = (Vec::new(), Vec::new());
    let (mut best_cpu, mut best_mo_cpu) = (f64::INFINITY, f64::INFINITY);
    let mut result = None;
    let mut mo_faces = 0;
    for _ in 0..reps {
        let t = Instant::now();
        let c = cpu_seconds();
        let r = gng3d_qem::simplify(&model, &params).expect("qem");
        wall.push(t.elapsed().as_secs_f64());
        best_cpu = best_cpu.min(cpu_seconds() - c);
        result = Some(r);
        let t = Instant::now();
        let c = cpu_seconds();
        let r = meshopt_simplify(&indices, &adapter, target);
        wall_mo.push(t.elapsed().as_secs_f64());
        best_mo_cpu = best_mo_cpu.min(cpu_seconds() - c);
        mo_faces = r.len() / 3;
    }
    let (out, report) = result.expect("ran");
    let out = out.mesh;
    let best = wall.iter().copied().fold(f64::INFINITY, f64::min);
    let best_mo = wall_mo.iter().copied().fold(f64::INFINITY, f64::min);
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (med, med_mo) = (median(&mut wall), median(&mut wall_mo));
    println!(
        "qem: {} -> {} faces, {} verts, {:.4} s  {:?}",
        m.face_count(),
        out.face_count(),
        out.vertex_count(),
        best,
        report
    );
    println!(
        "meshopt: {} faces, {:.4} s; ratio qem/meshopt = {:.2}",
        mo_faces,
        best_mo,
        best / best_mo
    );
    println!(
        "wall: best qem {best:.4} s, meshopt {best_mo:.4} s, ratio {:.3}; median qem {med:.4} s, meshopt {med_mo:.4} s, ratio {:.3}",
        best / best_mo,
        med / med_mo
    );
    println!(
        "cpu: qem {best_cpu:.4} s, meshopt {best_mo_cpu:.4} s, ratio {:.2}",
        best_cpu / best_mo_cpu
    );
    if let Some(o) = args.get(3) {
        mesh::io::save(&out.clone().into(), std::path::Path::new(o)).expect("save");
    }
}

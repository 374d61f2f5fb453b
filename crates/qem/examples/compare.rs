//! Time `qem::simplify` against `meshopt::simplify` on one mesh:
//! `cargo run --release -p qem --example compare -- MESH RATIO [OUT.obj]`.

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
    let (m, _) = mesh::clean::prepare(&loaded.mesh);
    let target = ((m.face_count() as f64) * ratio).round() as usize;
    let params = qem::QemParams::with_target(qem::Target::Faces(target));
    let mut best = f64::INFINITY;
    let mut best_cpu = f64::INFINITY;
    let mut best_mo_cpu = f64::INFINITY;
    let mut result = None;
    for _ in 0..reps {
        let t = Instant::now();
        let c = cpu_seconds();
        let r = qem::simplify(&m, &params).expect("qem");
        best = best.min(t.elapsed().as_secs_f64());
        best_cpu = best_cpu.min(cpu_seconds() - c);
        result = Some(r);
    }
    let (out, report) = result.expect("ran");
    println!(
        "qem: {} -> {} faces, {} verts, {:.4} s  {:?}",
        m.face_count(),
        out.face_count(),
        out.vertex_count(),
        best,
        report
    );
    let indices: Vec<u32> = m.triangles.iter().flatten().copied().collect();
    let adapter = meshopt::VertexDataAdapter::new(meshopt::typed_to_bytes(&m.positions), 12, 0)
        .expect("adapter");
    let mut best_mo = f64::INFINITY;
    let mut mo_faces = 0;
    for _ in 0..reps {
        let t = Instant::now();
        let c = cpu_seconds();
        let r = meshopt::simplify(
            &indices,
            &adapter,
            target * 3,
            f32::MAX,
            meshopt::SimplifyOptions::None,
            None,
        );
        best_mo = best_mo.min(t.elapsed().as_secs_f64());
        best_mo_cpu = best_mo_cpu.min(cpu_seconds() - c);
        mo_faces = r.len() / 3;
    }
    println!(
        "meshopt: {} faces, {:.4} s; ratio qem/meshopt = {:.2}",
        mo_faces,
        best_mo,
        best / best_mo
    );
    println!(
        "cpu: qem {best_cpu:.4} s, meshopt {best_mo_cpu:.4} s, ratio {:.2}",
        best_cpu / best_mo_cpu
    );
    if let Some(o) = args.get(3) {
        mesh::io::save(&out, std::path::Path::new(o)).expect("save");
    }
}

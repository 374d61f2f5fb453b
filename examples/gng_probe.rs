//! Measure GNG3D on mesh files: `cargo run --release --example gng_probe -- RATIO FILE...`
//! prints phase timings, signals/s, vertex errors and output topology per file.

use gng3d_core::{GngOptions, GngTarget, simplify};
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let ratio: f64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(0.5);
    for file in &args[1..] {
        let loaded = match mesh::io::load(Path::new(file)) {
            Ok(l) => l,
            Err(e) => {
                eprintln!("{file}: {e}");
                continue;
            }
        };
        let m = mesh::clean::prepare(&loaded.mesh.into()).0.mesh;
        let input = mesh::topology::analyze(&m);
        let target = ((m.vertex_count() as f64) * ratio).round() as usize;
        // The network's mesh itself (no oversampling), as the probe has always measured it.
        let mut options = GngOptions {
            oversample: Some(1.0),
            ..GngOptions::for_target(GngTarget::Vertices(target))
        };
        if let Ok(s) = std::env::var("GNG_SEED") {
            options.seed = s.parse().unwrap_or(1);
        }
        match simplify(&m.clone().into(), &options) {
            Ok(r) => {
                let t = &r.report.reconstruction.topology;
                let e = metrics::vertex_errors(&m.positions, &r.mesh.positions).unwrap();
                let diag2 = m.bbox_diagonal().powi(2);
                let rr = &r.report.reconstruction;
                println!(
                    "{:<22} V={:>6} g_in={:?} target={:>6} out V={:>6} F={:>6} | train {:.3}s ({:.2} M sig/s, {} sig) rec {:.3}s | bnd={} nm_e={} nm_v={} comp={} genus={:?} closed={} manifold={} | relab={} deg={} dup={} opp={} fins={} holes={} | e_avg/d2={:.2e}",
                    Path::new(file).file_name().unwrap().to_string_lossy(),
                    m.vertex_count(),
                    input.genus,
                    target,
                    r.mesh.vertex_count(),
                    r.mesh.face_count(),
                    r.report.training.seconds,
                    r.report.training.signals as f64 / r.report.training.seconds / 1e6,
                    r.report.training.signals,
                    rr.seconds,
                    t.boundary_edges,
                    t.non_manifold_edges,
                    t.non_manifold_vertices,
                    t.components,
                    t.genus,
                    t.closed,
                    t.manifold,
                    rr.relabelled_vertices,
                    rr.degenerate_faces,
                    rr.duplicate_faces,
                    rr.opposite_faces,
                    rr.fin_faces,
                    rr.holes_filled,
                    e.e_avg / diag2,
                );
            }
            Err(e) => println!("{file}: error: {e}"),
        }
    }
}

//! Quality vs signal budget of GNG3D: `cargo run --release --example gng_budget -- RATIO
//! SPN_LIST FILE...` (SPN_LIST comma-separated signals per node; `paper` = 30 epochs). Prints
//! per mesh and budget the symmetric Hausdorff distance and mean surface distance (percent of
//! the bounding-box diagonal, 100k samples per direction) and the paper's E_avg.

use gng3d_core::{GngOptions, GngTarget, simplify};
use metrics::{HausdorffParams, hausdorff};
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let ratio: f64 = args[0].parse().expect("ratio");
    let budgets: Vec<String> = args[1].split(',').map(str::to_string).collect();
    let hp = HausdorffParams {
        samples: Some(100_000),
        ..HausdorffParams::default()
    };
    for file in &args[2..] {
        let loaded = mesh::io::load(Path::new(file)).expect("load");
        let m = mesh::clean::prepare(&loaded.mesh.into()).0.mesh;
        let target = ((m.vertex_count() as f64) * ratio).round() as usize;
        let name = Path::new(file).file_name().unwrap().to_string_lossy();
        for b in &budgets {
            // The network's mesh itself (no oversampling).
            let mut p = GngOptions {
                oversample: Some(1.0),
                ..GngOptions::for_target(GngTarget::Vertices(target))
            };
            if b == "paper" {
                p.epochs = Some(gng3d_core::tuning::PAPER_EPOCHS);
            } else {
                p.max_signals = Some((b.parse::<f64>().expect("spn") * target as f64) as u64);
            }
            let r = simplify(&m.clone().into(), &p).expect("gng");
            let h = hausdorff(&m, &r.mesh, &hp).expect("hausdorff");
            let e = metrics::vertex_errors(&m.positions, &r.mesh.positions).expect("errors");
            let d = h.bbox_diagonal;
            println!(
                "{name:<22} ratio={ratio} spn={b:>6} signals={:>9} V={:>6} | H={:.4}% mean={:.5}% E_avg/d2={:.3e} | train {:.3}s rec {:.3}s",
                r.report.training.signals,
                r.mesh.vertex_count(),
                100.0 * h.max / d,
                100.0 * h.mean / d,
                e.e_avg / (d * d),
                r.report.training.seconds,
                r.report.reconstruction.seconds,
            );
        }
    }
}

//! Vertex count, topology and time of GNG3D on mesh files at given ratios:
//! `cargo run --release -p gng3d-core --example counts -- RATIOS FILE...` (RATIOS comma
//! separated, e.g. `0.1,0.25,0.5`). Env: GNG_SPN (signals per node), GNG_EPOCHS, GNG_TIME,
//! GNG_SEED.

use gng3d_core::{GngOptions, GngTarget, simplify};
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let ratios: Vec<f64> = args[0].split(',').filter_map(|r| r.parse().ok()).collect();
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f64>().ok());
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
        for &ratio in &ratios {
            let target = ((m.vertex_count() as f64) * ratio).round() as usize;
            // The network's mesh itself (no oversampling), as this example has always measured.
            let mut params = GngOptions {
                oversample: Some(1.0),
                ..GngOptions::for_target(GngTarget::Vertices(target))
            };
            if let Some(spn) = env("GNG_SPN") {
                params.max_signals = Some((spn * target as f64) as u64);
            }
            params.epochs = env("GNG_EPOCHS");
            params.time_limit_seconds = env("GNG_TIME");
            if let Some(seed) = env("GNG_SEED") {
                params.seed = seed as u64;
            }
            let name = Path::new(file).file_name().unwrap().to_string_lossy();
            match simplify(&m.clone().into(), &params) {
                Ok(r) => {
                    let t = &r.report.reconstruction.topology;
                    println!(
                        "{name:<24} in: V={:>7} closed={} manifold={} comps={} | target={:>6} out={:>6} {} attached={} closed={} manifold={} comps={} | train {:.3}s rec {:.3}s sig={} grown@{:?} | {:?}",
                        m.vertex_count(),
                        input.closed,
                        input.manifold,
                        input.components,
                        target,
                        r.mesh.vertex_count(),
                        if r.mesh.vertex_count() == target {
                            "EXACT"
                        } else {
                            "short"
                        },
                        r.report.reconstruction.attached_nodes,
                        t.closed,
                        t.manifold,
                        t.components,
                        r.report.training.seconds,
                        r.report.reconstruction.seconds,
                        r.report.training.signals,
                        r.report.training.growth_seconds,
                        r.report
                            .warnings
                            .iter()
                            .map(|w| w.to_string())
                            .collect::<Vec<_>>(),
                    );
                }
                Err(e) => println!("{name:<24} target={target}: error: {e}"),
            }
        }
    }
}

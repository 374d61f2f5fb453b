//! Steady-state training throughput at a given node count:
//! `cargo run --release -p gng3d-core --example throughput -- MESH NODES SIGNALS [linear]`.
//! Prints wall-clock and process CPU time per signal.

use gng3d_core::{GngParams, SearchStrategy, Trainer};
use std::path::Path;
use std::time::Instant;

/// User + system CPU seconds of this process (Linux), 0 elsewhere.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit(')')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let m = mesh::io::load(Path::new(&args[0])).expect("load").mesh;
    let m = mesh::clean::prepare(&m.into()).0.mesh;
    let nodes: usize = args[1].parse().expect("nodes");
    let signals: u64 = args[2].parse().expect("signals");
    let mut params = GngParams::for_target(nodes);
    params.lambda = Some(20);
    params.max_signals = Some(u64::MAX / 4);
    let mut t = Trainer::new(&m.clone().into(), params).expect("trainer");
    while t.node_count() < nodes {
        t.step(100_000);
    }
    t.step(20 * nodes as u64);
    if args.get(3).map(String::as_str) == Some("linear") {
        t.set_search_strategy(SearchStrategy::LinearScan);
    }
    let before = t.stats();
    let (w0, c0) = (Instant::now(), cpu_seconds());
    t.step(signals);
    let (w, c) = (w0.elapsed().as_secs_f64(), cpu_seconds() - c0);
    println!(
        "{nodes} nodes: {signals} signals, wall {w:.3} s ({:.2} M/s), cpu {c:.3} s ({:.2} M/s), edges {}, insertions {}, removed inactive {} isolated {}",
        signals as f64 / w / 1e6,
        signals as f64 / c.max(1e-9) / 1e6,
        t.edge_count(),
        t.stats().insertions - before.insertions,
        t.stats().removed_inactive - before.removed_inactive,
        t.stats().removed_isolated - before.removed_isolated,
    );
}

//! Times the phases of `gng3d info` on one mesh: load, edge table, topology analysis.
//!
//! Usage: `cargo run --release -p gng3d-mesh --example topology_timing -- MESH [REPEATS]`.
//! Prints the minimum wall time of each phase over REPEATS runs (default 5), in seconds.

use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().ok_or("usage: topology_timing MESH [REPEATS]")?);
    let repeats: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(5);
    let (mut load, mut table, mut analyze) = (f64::MAX, f64::MAX, f64::MAX);
    let mut report = None;
    for _ in 0..repeats {
        let t0 = Instant::now();
        let loaded = gng3d_mesh::io::load(&path)?;
        let t1 = Instant::now();
        let edges = gng3d_mesh::topology::EdgeTable::new(&loaded.mesh);
        let t2 = Instant::now();
        let r = gng3d_mesh::topology::analyze_with(&loaded.mesh, &edges);
        let t3 = Instant::now();
        load = load.min((t1 - t0).as_secs_f64());
        table = table.min((t2 - t1).as_secs_f64());
        analyze = analyze.min((t3 - t2).as_secs_f64());
        report = Some(r);
    }
    println!("{report:?}");
    println!(
        "load {load:.4} s, edge table {table:.4} s, analyze_with {analyze:.4} s (min of {repeats})"
    );
    Ok(())
}

//! `viewer [MESH] [--target N] [--quit-after SECS --screenshot PATH]`: the gng3d desktop viewer.

use clap::Parser;
use std::path::PathBuf;

/// GNG3D training next to QEM, with live error plots.
#[derive(Parser, Debug)]
#[command(name = "viewer", version, about)]
struct Args {
    /// Mesh to open (OBJ, PLY or STL); without it a built-in procedural model is shown.
    mesh: Option<PathBuf>,
    /// Vertex target for GNG3D and QEM.
    #[arg(long)]
    target: Option<usize>,
    /// GNG3D training time limit in seconds.
    #[arg(long)]
    time_limit: Option<f64>,
    /// Seed of the training signals.
    #[arg(long)]
    seed: Option<u64>,
    /// Start with training paused.
    #[arg(long)]
    paused: bool,
    /// Close the window after this many seconds (for automation).
    #[arg(long, value_name = "SECS")]
    quit_after: Option<f64>,
    /// Save a PNG screenshot of the window just before quitting (with --quit-after).
    #[arg(long, value_name = "PATH")]
    screenshot: Option<PathBuf>,
    /// Print frame rate and training throughput when quitting.
    #[arg(long)]
    stats: bool,
}

fn main() {
    let args = Args::parse();
    let options = viewer::ViewerOptions {
        path: args.mesh,
        quit_after: args.quit_after,
        screenshot: args.screenshot,
        target: args.target,
        time_limit: args.time_limit,
        seed: args.seed,
        paused: args.paused,
        print_stats: args.stats || args.quit_after.is_some(),
    };
    if let Err(e) = viewer::run(options) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

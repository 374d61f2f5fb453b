//! `viewer [MESH] [--target N] [--watch SECS] [--quit-after SECS --screenshot PATH]`: the gng3d
//! desktop viewer.

use clap::Parser;
use std::path::PathBuf;

/// GNG3D training next to QEM, with live error plots.
#[derive(Parser, Debug)]
#[command(name = "viewer", version, about)]
struct Args {
    /// Mesh to open (OBJ, PLY, STL, glTF or GLB); without it a built-in procedural model is
    /// shown. A model with texture coordinates and a base-colour texture (OBJ map_Kd, glTF
    /// baseColorTexture, PNG) is drawn with it on the original and both outputs (Display's
    /// "texture" switch, T).
    mesh: Option<PathBuf>,
    /// Vertex target for GNG3D and QEM.
    #[arg(long)]
    target: Option<usize>,
    /// GNG3D maximum running time in seconds (training and the steps after it), > 0.
    // Negative numbers reach the option's own check ("-1" is not taken for a flag).
    #[arg(long, value_name = "SECS", allow_negative_numbers = true)]
    time_limit: Option<f64>,
    /// Seed of the training signals.
    #[arg(long)]
    seed: Option<u64>,
    /// GNG3D signal budget (default: 150 signals per target vertex, spread over the watched run).
    #[arg(long)]
    max_signals: Option<u64>,
    /// λ: signals between node insertions (default: automatic).
    #[arg(long)]
    lambda: Option<u32>,
    /// Length of the watched run in seconds, training and the steps after it: the signal budget
    /// is spread over the training's share so the network visibly grows (default 12; 0 = as fast
    /// as possible).
    #[arg(long, value_name = "SECS", allow_negative_numbers = true)]
    watch: Option<f64>,
    /// Reconstruct and measure the neural mesh every N signals (default |V|, the paper's
    /// protocol; 0 = only at the end).
    #[arg(long, value_name = "N")]
    checkpoint_every: Option<u64>,
    /// Train without a window, at full speed, with the window's defaults (target, budget,
    /// checkpoints), until the run's final mesh is built or --quit-after SECS have passed; then
    /// print one line: nodes, signals, mean signals/s, training and run seconds (the throughput
    /// baseline).
    #[arg(long)]
    headless: bool,
    /// Start with training paused.
    #[arg(long)]
    paused: bool,
    /// Close the window (or end --headless) after this many seconds (for automation).
    #[arg(long, value_name = "SECS", allow_negative_numbers = true)]
    quit_after: Option<f64>,
    /// Save a PNG screenshot of the window just before quitting (with --quit-after).
    #[arg(long, value_name = "PATH")]
    screenshot: Option<PathBuf>,
    /// Window size in points, e.g. 1280x720 (default 1600x900).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    window: Option<[f32; 2]>,
    /// Start with the parameter panel open or closed (default: open where the window is at
    /// least 1350 points wide and tall enough for the plots with it, e.g. 1600x900 but not
    /// 1366x768).
    #[arg(long, value_name = "open|closed", value_parser = parse_open)]
    controls: Option<bool>,
    /// Print frame rate and training throughput when quitting.
    #[arg(long)]
    stats: bool,
}

/// Parse `open` / `closed`.
fn parse_open(text: &str) -> Result<bool, String> {
    match text {
        "open" => Ok(true),
        "closed" => Ok(false),
        _ => Err(format!("expected open or closed, got {text:?}")),
    }
}

/// Parse `WIDTHxHEIGHT` (points).
fn parse_size(text: &str) -> Result<[f32; 2], String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got {text:?}"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<f32>()
            .ok()
            .filter(|v| v.is_finite() && *v >= 100.0 && *v <= 16384.0)
            .ok_or_else(|| format!("bad window size {text:?} (each side 100..16384)"))
    };
    Ok([parse(w)?, parse(h)?])
}

/// Leave one core to the training thread when the renderer is Mesa's software rasterizer
/// (llvmpipe/lavapipe), which otherwise starts one raster thread per core and competes with
/// training for every core. A user's own `LP_NUM_THREADS` wins; GPU drivers ignore the variable.
fn share_cores_with_software_rasterizer() {
    if std::env::var_os("LP_NUM_THREADS").is_some() {
        return;
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    // SAFETY: called first thing in `main`, before any other thread exists, so nothing can read
    // the environment concurrently.
    unsafe { std::env::set_var("LP_NUM_THREADS", cores.saturating_sub(1).max(1).to_string()) };
}

/// On an X display with no usable Wayland session (no `WAYLAND_DISPLAY`, no valid
/// `XDG_RUNTIME_DIR`: Xvfb, ssh -X, CI), Mesa's Vulkan device-select layer still tries a Wayland
/// connection to find the default GPU, and libwayland prints "error: XDG_RUNTIME_DIR is invalid
/// or not set in the environment." four times per start (issue 37). There is no Wayland
/// compositor to ask, so the layer is switched off (`NODEVICE_SELECT=1`, Mesa's own switch);
/// wgpu still chooses the adapter. A user's own setting wins.
fn quiet_wayland_probe_on_x11() {
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    let runtime_dir_valid =
        std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir());
    if set("DISPLAY")
        && !set("WAYLAND_DISPLAY")
        && !set("WAYLAND_SOCKET")
        && !runtime_dir_valid
        && std::env::var_os("NODEVICE_SELECT").is_none()
    {
        // SAFETY: called first thing in `main`, before any other thread exists.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}

fn main() {
    share_cores_with_software_rasterizer();
    quiet_wayland_probe_on_x11();
    let args = Args::parse();
    let options = viewer::ViewerOptions {
        path: args.mesh,
        quit_after: args.quit_after,
        screenshot: args.screenshot,
        target: args.target,
        time_limit: args.time_limit,
        seed: args.seed,
        max_signals: args.max_signals,
        lambda: args.lambda,
        watch_seconds: args.watch,
        checkpoint_every: args.checkpoint_every,
        paused: args.paused,
        print_stats: args.stats || args.quit_after.is_some(),
        window_size: args.window,
        controls: args.controls,
    };
    // A file given on the command line that cannot be opened is an error with a non-zero exit,
    // before any window: never the built-in model standing in for it. (Files opened from the
    // window later show their error in the status line and keep the current model.)
    if let Some(path) = &options.path
        && let Err(e) = viewer::engine::load_mesh(path)
    {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
    if args.headless && options.screenshot.is_some() {
        eprintln!("error: invalid option --screenshot: --headless has no window to capture");
        std::process::exit(1);
    }
    if args.headless {
        match viewer::run_headless(&options) {
            Ok(summary) => println!("{summary}"),
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
        }
        return;
    }
    if let Err(e) = viewer::run(options) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

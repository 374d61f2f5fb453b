//! `gng3d simplify --method gng`: GNG3D training with a progress bar on stderr, then
//! reconstruction; the result is written atomically.

use super::SimplifyArgs;
use anyhow::{Context, bail};
use gng3d_core::{GngOptions, GngTarget, GngWarning, Trainer};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::ops::ControlFlow;
use std::time::Instant;

/// The `--json` summary.
#[derive(Debug, Serialize)]
struct Summary {
    method: &'static str,
    vertices: usize,
    faces: usize,
    /// Training signals processed (the paper's iterations).
    iterations: u64,
    /// Wall time of training plus reconstruction, seconds (loading and saving excluded).
    seconds: f64,
    training_seconds: f64,
    /// Requested vertex count; `vertices` equals it unless `warnings` says why not.
    target_vertices: usize,
    /// Trained nodes (k × N when oversampled).
    nodes: usize,
    /// Oversampling factor k (1: the network's mesh is the output).
    oversample: f64,
    /// Vertices of the network's mesh before the QEM decimation (equals `vertices` when k = 1).
    network_vertices: usize,
    /// Vertex placement used ("Node": the paper, "Project", "Quadric": GNG3D-Q).
    placement: gng3d_core::Placement,
    /// Where the training signals came from ("Vertices": the paper, "Surface", "Curvature").
    signals: gng3d_core::SignalSource,
    /// Whether the edge-flip pass ran.
    flips: bool,
    /// Whether the surface refit ran (quadric placement with refit on).
    refit: bool,
    /// Rounds of detail nodes (oversampled runs; 0: none).
    detail_rounds: usize,
    /// Nodes those rounds added where the mesh stayed farthest from the original.
    detail_nodes: usize,
    /// Whether the tangential relaxation after the decimation is on (it runs only when the
    /// network's mesh was decimated).
    relax: bool,
    /// Vertices it moved toward the original vertices they stand for.
    relaxed_vertices: usize,
    /// Whether the deviation repair after the decimation is on (it runs only when the
    /// network's mesh was decimated).
    repair_deviations: bool,
    /// Vertices it moved back onto the original.
    deviation_moves: usize,
    /// Edges it flipped.
    deviation_flips: usize,
    /// The steps after training that ran, in order: name, build round, seconds and what each
    /// changed (the pipeline of `gng3d_core::pipeline`).
    steps: Vec<gng3d_core::StepRecord>,
    /// Machine-readable reasons why the output differs from the request (empty when exact).
    warnings: Vec<GngWarning>,
    closed: bool,
    manifold: bool,
    genus: Option<i64>,
    boundary_edges: usize,
    non_manifold_edges: usize,
}

/// The user's GNG3D options from the command line (the mapping to `GngParams` is
/// `GngOptions::resolve`, shared with `compare`, `reproduce` and the viewer).
fn options(args: &SimplifyArgs) -> anyhow::Result<GngOptions> {
    let target = match (args.vertices, args.ratio) {
        (Some(n), _) => GngTarget::Vertices(n),
        (None, Some(r)) => GngTarget::VertexRatio(r),
        (None, None) => bail!("give a target with --vertices N or --ratio R"),
    };
    let mut options = GngOptions {
        target,
        time_limit_seconds: args.time_limit,
        seed: args.seed,
        ..GngOptions::default()
    };
    args.gng.apply(&mut options);
    Ok(options)
}

/// Simplify with GNG3D.
pub fn run(args: &SimplifyArgs) -> anyhow::Result<()> {
    if args.faces.is_some() {
        bail!("--faces applies to QEM only; use --vertices or --ratio with --method gng");
    }
    let options = options(args)?;
    // Everything that does not need the mesh is checked before loading it.
    options.validate().context("GNG3D options")?;
    let input = crate::cli::load_prepared(&args.input, args.no_weld)?;
    let params = options
        .resolve(&input)
        .with_context(|| format!("GNG3D on {}", args.input.display()))?;
    let start = Instant::now();
    let mut trainer = Trainer::new(&input, params.clone())
        .with_context(|| format!("GNG3D on {}", args.input.display()))?;
    let budget = trainer.stats().max_signals;
    let bar = ProgressBar::new(budget);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} signals {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    // The bar moves every 5 % of the budget: each `step` call runs the parts' rounds on
    // threads it starts, and at 0.5 % a call (igea at 1 %: 2,000 signals, ~0.6 ms) starting
    // them cost a third of the gain.
    trainer.train((budget / 20).clamp(1_000, 2_000_000), |p| {
        bar.set_position(p.signals.min(budget));
        bar.set_message(format!("{} nodes", p.nodes));
        ControlFlow::Continue(())
    });
    // The steps after training, named on the bar as they finish.
    bar.set_message("reconstructing");
    let result = gng3d_core::finish(&trainer, |step| {
        bar.set_message(format!("{} done", step.step));
    });
    bar.finish_and_clear();
    // Same checks and warnings as gng3d_core::simplify: no mesh is an error, never exit 0.
    let result = result.with_context(|| format!("GNG3D on {}", args.input.display()))?;
    let seconds = start.elapsed().as_secs_f64();
    let stats = trainer.stats();
    crate::cli::save_checked(&result.mesh, &args.output, "GNG3D")
        .with_context(|| format!("GNG3D on {}", args.input.display()))?;
    for w in &result.report.warnings {
        eprintln!("warning: {w}");
    }
    let t = &result.report.reconstruction.topology;
    let summary = Summary {
        method: "gng",
        vertices: result.mesh.vertex_count(),
        faces: result.mesh.face_count(),
        iterations: stats.signals,
        seconds,
        training_seconds: stats.seconds,
        target_vertices: result.report.target_vertices,
        nodes: trainer.node_count(),
        oversample: options.oversample_factor(),
        network_vertices: result.report.network_vertices,
        placement: params.reconstruction.placement,
        signals: params.signal_source,
        flips: params.reconstruction.flip_edges,
        refit: params.reconstruction.refits(),
        detail_rounds: params.reconstruction.detail_rounds,
        detail_nodes: result.report.reconstruction.detail_nodes,
        relax: params.reconstruction.relax,
        relaxed_vertices: result.report.reconstruction.relaxed_vertices,
        repair_deviations: params.reconstruction.repair_deviations,
        deviation_moves: result.report.reconstruction.deviation_moves,
        deviation_flips: result.report.reconstruction.deviation_flips,
        steps: result.report.steps.clone(),
        warnings: result.report.warnings.clone(),
        closed: t.closed,
        manifold: t.manifold,
        genus: t.genus,
        boundary_edges: t.boundary_edges,
        non_manifold_edges: t.non_manifold_edges,
    };
    if args.json {
        return crate::cli::print_json(&summary);
    }
    outln!(
        "{} -> {}: {} vertices, {} faces, {} signals in {:.3} s ({}); closed: {}, manifold: {}, genus: {}",
        args.input.display(),
        args.output.display(),
        summary.vertices,
        summary.faces,
        summary.iterations,
        summary.seconds,
        stats.stop.unwrap_or(gng3d_core::StopReason::Completed),
        summary.closed,
        summary.manifold,
        summary.genus.map_or("undefined".into(), |g| g.to_string()),
    );
    Ok(())
}

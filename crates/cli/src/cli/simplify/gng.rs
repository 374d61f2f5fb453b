//! `gng3d simplify --method gng`: GNG3D training with a progress bar on stderr, then
//! reconstruction; the result is written atomically.

use super::SimplifyArgs;
use anyhow::{Context, bail};
use gng3d_core::{GngOptions, GngSummary, GngTarget, Trainer};
use indicatif::ProgressStyle;
use std::ops::ControlFlow;
use std::time::Instant;

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
    if args.faces.is_some() || args.face_ratio.is_some() || args.lods.is_some() {
        bail!(
            "--faces, --face-ratio and --lods apply to QEM only; use --vertices or --ratio with --method gng"
        );
    }
    if args.max_error.is_some() || args.attribute_weights.is_some() {
        bail!("--max-error and --attribute-weights apply to QEM only; use --method qem");
    }
    if args.lock_border {
        bail!(
            "--lock-border applies to QEM only (GNG3D places every output vertex anew); use --method qem"
        );
    }
    let options = options(args)?;
    // Everything that does not need the mesh is checked before loading it.
    options.validate().context("GNG3D options")?;
    let (input, extras) = super::attributes::load(&args.input, args.no_weld, &[&args.output])?;
    let params = options
        .resolve(&input)
        .with_context(|| format!("GNG3D on {}", args.input.display()))?;
    let start = Instant::now();
    // With attributes whose seams the output's triangles are to follow (Trainer::with_attributes).
    let trainer = match &extras.attributes {
        Some(a) => Trainer::with_attributes(&input, a, params.clone()),
        None => Trainer::new(&input, params.clone()),
    };
    let mut trainer = trainer.with_context(|| format!("GNG3D on {}", args.input.display()))?;
    let budget = trainer.stats().max_signals;
    // Progress on stderr (a terminal, no --json): signals while training, then the steps after
    // it, counted and named as they run (GNG3D-Q spends most of a run there).
    let bar = crate::cli::progress::bar(
        budget,
        "{spinner} [{elapsed_precise}] {bar:20} {pos}/{len} signals {msg}",
        args.json,
    );
    // The bar moves every 5 % of the budget: each `step` call runs the parts' rounds on
    // threads it starts, and at 0.5 % a call (igea at 1 %: 2,000 signals, ~0.6 ms) starting
    // them cost a third of the gain.
    trainer.train((budget / 20).clamp(1_000, 2_000_000), |p| {
        bar.set_position(p.signals.min(budget));
        bar.set_message(format!("{} nodes", p.nodes));
        ControlFlow::Continue(())
    });
    let plan = trainer.plan().steps().to_vec();
    let running = |i: usize| {
        plan.get(i).map_or_else(String::new, |s| match s.round {
            0 => s.step.to_string(),
            r => format!("{}, round {r}", s.step),
        })
    };
    bar.set_message(running(0));
    bar.set_length(plan.len() as u64);
    bar.set_position(0);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:20} {pos}/{len} steps after training, now: {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    // Steps left out (a time limit, a detail round that found nothing) report nothing: each
    // record moves the bar to its place in the plan.
    let mut next = 0;
    let result = gng3d_core::finish(&trainer, |record| {
        if let Some(j) = plan
            .get(next..)
            .unwrap_or(&[])
            .iter()
            .position(|s| s.step == record.step && s.round == record.round)
        {
            next += j + 1;
        }
        bar.set_position(next as u64);
        bar.set_message(running(next));
    });
    bar.finish_and_clear();
    // Same checks and warnings as gng3d_core::simplify: no mesh is an error, never exit 0.
    let result = result.with_context(|| format!("GNG3D on {}", args.input.display()))?;
    let seconds = start.elapsed().as_secs_f64();
    let stats = trainer.stats();
    // The input's attributes from its surface at the output's corners.
    let attributes = super::attributes::transfer(&input, &extras, &result.mesh);
    let kept = super::attributes::save(
        &result.mesh,
        attributes.as_ref(),
        &extras,
        &args.output,
        "GNG3D",
    )
    .with_context(|| format!("GNG3D on {}", args.input.display()))?;
    for w in &result.report.warnings {
        eprintln!("warning: {w}");
    }
    let summary = GngSummary::new(
        "gng",
        &trainer,
        options.oversample_factor(),
        &result,
        seconds,
    );
    if args.json {
        return crate::cli::print_json(&super::attributes::WithAttributes {
            summary: &summary,
            attributes: &kept,
        });
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

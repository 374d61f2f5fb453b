//! `gng3d simplify --method qem`: Garland–Heckbert quadric error simplification; the result is
//! written atomically.

use super::SimplifyArgs;
use anyhow::{Context, bail};
use qem::{QemParams, QemReport, Target};
use serde::Serialize;

/// The `--json` summary.
#[derive(Debug, Serialize)]
struct Summary {
    method: &'static str,
    vertices: usize,
    faces: usize,
    /// Wall time of the simplification, seconds (loading, cleaning and saving excluded).
    seconds: f64,
    /// Full simplification report (collapses, max quadric error, stop reason, ...).
    report: QemReport,
}

/// Simplify with QEM.
pub fn run(args: &SimplifyArgs) -> anyhow::Result<()> {
    if args.time_limit.is_some() || args.gng.any() {
        bail!(
            "--time-limit, --epochs, --signals, --placement, --no-flips, --no-refit, --no-relax, --no-deviation-repair, --oversample and --detail-rounds apply to --method gng only"
        );
    }
    let target = match (args.vertices, args.faces, args.ratio) {
        (Some(n), _, _) => Target::Vertices(n),
        (None, Some(n), _) => Target::Faces(n),
        (None, None, Some(r)) => {
            if !(r > 0.0 && r <= 1.0) {
                bail!("--ratio must be in (0, 1], got {r}");
            }
            Target::Ratio(r)
        }
        (None, None, None) => bail!("give a target with --vertices N, --faces N or --ratio R"),
    };
    if !(args.threshold >= 0.0 && args.threshold.is_finite()) {
        bail!(
            "--threshold must be a finite distance >= 0, got {}",
            args.threshold
        );
    }
    let input = crate::cli::load_prepared(&args.input, args.no_weld)?;
    let params = QemParams {
        target,
        pair_threshold: args.threshold,
        ..QemParams::default()
    };
    let (simplified, report) = qem::simplify(&input, &params)
        .with_context(|| format!("simplifying {}", args.input.display()))?;
    crate::cli::save_checked(&simplified, &args.output, "QEM")
        .with_context(|| format!("QEM on {}", args.input.display()))?;
    if args.json {
        crate::cli::print_json(&Summary {
            method: "qem",
            vertices: report.vertices,
            faces: report.faces,
            seconds: report.seconds,
            report,
        })?;
    } else {
        if let Some(shortfall) = report.shortfall(target) {
            eprintln!("warning: {shortfall}");
        }
        let t = mesh::topology::analyze(&simplified);
        outln!(
            "qem: {} -> {} vertices, {} -> {} faces, {} collapses in {:.3} s -> {}; closed: {}, manifold: {}, genus: {}",
            report.input_vertices,
            report.vertices,
            report.input_faces,
            report.faces,
            report.collapses,
            report.seconds,
            args.output.display(),
            t.closed,
            t.manifold,
            t.genus.map_or("undefined".into(), |g| g.to_string()),
        );
    }
    Ok(())
}

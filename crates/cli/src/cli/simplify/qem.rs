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

const NO_TARGET: &str = "give a target with --vertices N, --ratio R, --faces N or --face-ratio R";

/// Simplify with QEM.
pub fn run(args: &SimplifyArgs) -> anyhow::Result<()> {
    if args.time_limit.is_some() || args.gng.any() {
        bail!(
            "--time-limit, --epochs, --signals, --placement, --no-flips, --no-refit, --no-relax, --no-deviation-repair, --oversample and --detail-rounds apply to --method gng only"
        );
    }
    if args.vertices.is_none()
        && args.faces.is_none()
        && args.ratio.is_none()
        && args.face_ratio.is_none()
    {
        bail!(NO_TARGET);
    }
    if !(args.threshold >= 0.0 && args.threshold.is_finite()) {
        bail!(
            "--threshold must be a finite distance >= 0, got {}",
            args.threshold
        );
    }
    let (input, extras) = super::attributes::load(&args.input, args.no_weld)?;
    // --ratio is a share of the vertices, as for GNG3D: the library's one mapping.
    let target = match (args.vertices, args.faces, args.ratio, args.face_ratio) {
        (Some(n), ..) => Target::Vertices(n),
        (None, Some(n), ..) => Target::Faces(n),
        (None, None, Some(r), _) => Target::Vertices(
            gng3d_core::GngTarget::VertexRatio(r)
                .vertex_count(&input)
                .context("--ratio")?,
        ),
        (None, None, None, Some(r)) => Target::Ratio(r),
        (None, None, None, None) => bail!(NO_TARGET),
    };
    let params = QemParams {
        target,
        pair_threshold: args.threshold,
        ..QemParams::default()
    };
    let progress = crate::cli::progress::spinner(args.json);
    progress.set_message("QEM: contracting vertex pairs");
    let simplified = super::attributes::simplify_qem(&input, &extras, &params, args.lock_border);
    progress.finish_and_clear();
    let (simplified, attributes, report) =
        simplified.with_context(|| format!("simplifying {}", args.input.display()))?;
    let kept = super::attributes::save(
        &simplified,
        attributes.as_ref(),
        &extras,
        &args.output,
        "QEM",
    )
    .with_context(|| format!("QEM on {}", args.input.display()))?;
    if args.json {
        crate::cli::print_json(&super::attributes::WithAttributes {
            summary: &Summary {
                method: "qem",
                vertices: report.vertices,
                faces: report.faces,
                seconds: report.seconds,
                report,
            },
            attributes: &kept,
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

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

const NO_TARGET: &str = "give a target with --vertices N, --ratio R, --faces N or --face-ratio R, or a bound with --max-error E";

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
        && args.lods.is_none()
        && args.max_error.is_none()
    {
        bail!(NO_TARGET);
    }
    if let Some(lods) = &args.lods {
        check_lods(lods)?;
    }
    if !(args.threshold >= 0.0 && args.threshold.is_finite()) {
        bail!(
            "--threshold must be a finite distance >= 0, got {}",
            args.threshold
        );
    }
    // Everything that does not need the mesh is checked before loading it, by the library.
    let params = params(args)?;
    // --max-error alone first, so its error names the flag (the library's rule and words).
    QemParams {
        max_relative_error: args.max_error,
        ..QemParams::default()
    }
    .validate()
    .context("--max-error")?;
    params.validate().context("QEM options")?;
    // Every file the run writes (each --lods level) is checked against the input's files
    // before any work.
    let outputs: Vec<std::path::PathBuf> = match &args.lods {
        Some(lods) => (1..=lods.len())
            .map(|k| lod_path(&args.output, k))
            .collect(),
        None => vec![args.output.clone()],
    };
    let outputs: Vec<&std::path::Path> = outputs.iter().map(|p| p.as_path()).collect();
    let (input, extras) = super::attributes::load(&args.input, args.no_weld, &outputs)?;
    if let Some(lods) = &args.lods {
        return run_lods(args, &params, input, extras, lods);
    }
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
        // --max-error alone: no size bound.
        (None, None, None, None) if args.max_error.is_some() => Target::Faces(0),
        (None, None, None, None) => bail!(NO_TARGET),
    };
    let (simplified, _, report, kept) =
        simplify_to(args, &params, &input, &extras, target, &args.output, None)?;
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
        // With --max-error alone there is no size to fall short of.
        if let Some(shortfall) = report
            .shortfall(target)
            .filter(|_| target != Target::Faces(0))
        {
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
        if let Some(e) = report.max_relative_error {
            outln!("qem: largest contraction error {e:.3e} of the bounding-box diagonal");
        }
    }
    Ok(())
}

/// The QEM parameters of `args` (the target is set per run): `--threshold`, `--max-error`,
/// `--attribute-weights`.
fn params(args: &SimplifyArgs) -> anyhow::Result<QemParams> {
    let mut params = QemParams {
        pair_threshold: args.threshold,
        max_relative_error: args.max_error,
        ..QemParams::default()
    };
    if let Some(list) = &args.attribute_weights {
        params.attribute_weights = attribute_weights(list)?;
    }
    Ok(params)
}

/// `--attribute-weights uv=W,normal=W,color=W`: any of the three names, each at most once; the
/// others keep their defaults. The values are checked with the other options by
/// `QemParams::validate`.
fn attribute_weights(list: &str) -> anyhow::Result<qem::AttributeWeights> {
    let mut w = qem::AttributeWeights::default();
    let mut seen = Vec::new();
    for item in list.split(',') {
        let Some((name, value)) = item.split_once('=') else {
            bail!("--attribute-weights: expected NAME=W (uv, normal or color), got {item:?}");
        };
        let name = name.trim();
        let value: f64 = value.trim().parse().map_err(|_| {
            anyhow::anyhow!("--attribute-weights: {name}={value:?} is not a number")
        })?;
        let slot = match name {
            "uv" => &mut w.uv,
            "normal" => &mut w.normal,
            "color" | "colour" => &mut w.color,
            _ => bail!("--attribute-weights: unknown attribute {name:?} (uv, normal or color)"),
        };
        if seen.contains(&name) {
            bail!("--attribute-weights: {name} given twice");
        }
        seen.push(name);
        *slot = value;
    }
    Ok(w)
}

/// One QEM run of `gng3d simplify`: `input` to `target` (its attributes kept, the border
/// locked with `--lock-border`), written to `path`; `level` names the `--lods` level in errors.
fn simplify_to(
    args: &SimplifyArgs,
    params: &QemParams,
    input: &mesh::TriMesh,
    extras: &super::attributes::Extras,
    target: Target,
    path: &std::path::Path,
    level: Option<usize>,
) -> anyhow::Result<(
    mesh::TriMesh,
    Option<mesh::attributes::Attributes>,
    QemReport,
    super::attributes::Kept,
)> {
    let params = QemParams {
        target,
        ..params.clone()
    };
    let progress = crate::cli::progress::spinner(args.json);
    progress.set_message("QEM: contracting vertex pairs");
    let simplified = super::attributes::simplify_qem(input, extras, &params, args.lock_border);
    progress.finish_and_clear();
    let (simplified, attributes, report) = simplified.with_context(|| match level {
        Some(k) => format!("simplifying {} (level {k})", args.input.display()),
        None => format!("simplifying {}", args.input.display()),
    })?;
    let kept = super::attributes::save(&simplified, attributes.as_ref(), extras, path, "QEM")
        .with_context(|| format!("QEM on {}", args.input.display()))?;
    Ok((simplified, attributes, report, kept))
}

/// `--lods`: each share in (0, 1], strictly decreasing.
fn check_lods(lods: &[f64]) -> anyhow::Result<()> {
    if lods.is_empty() {
        bail!("--lods needs at least one share, e.g. --lods 0.5,0.25,0.1");
    }
    if let Some(r) = lods.iter().find(|r| !(**r > 0.0 && **r <= 1.0)) {
        bail!("--lods: each share must be in (0, 1], got {r}");
    }
    if lods.windows(2).any(|w| w[1] >= w[0]) {
        bail!(
            "--lods: the shares must decrease (each level is made from the one before), got {lods:?}"
        );
    }
    Ok(())
}

/// Where level `k` (from 1) of `--lods` goes: OUT's name with `-lod<k>` before the extension.
fn lod_path(output: &std::path::Path, k: usize) -> std::path::PathBuf {
    let stem = output.file_stem().unwrap_or_default().to_string_lossy();
    let name = match output.extension() {
        Some(ext) => format!("{stem}-lod{k}.{}", ext.to_string_lossy()),
        None => format!("{stem}-lod{k}"),
    };
    output.with_file_name(name)
}

/// One level of `--lods` in the `--json` output.
#[derive(Debug, Serialize)]
struct Level {
    /// The share of the input's vertices asked for.
    ratio: f64,
    /// Where it was written.
    output: std::path::PathBuf,
    vertices: usize,
    faces: usize,
    /// Wall time of this level's simplification, seconds.
    seconds: f64,
    /// The level's report (its `max_error`: the largest quadric error of a contraction made
    /// for this level, model units⁴).
    report: QemReport,
    /// What was kept of the input's attributes.
    attributes: super::attributes::Kept,
}

/// The fewest vertices a `--lods` level may ask for: one triangle.
const MIN_LEVEL_VERTICES: usize = 3;

/// `--lods`: each level simplified from the one before (attributes carried), written as it is
/// made; one line per level (or a `--json` list).
fn run_lods(
    args: &SimplifyArgs,
    params: &QemParams,
    input: mesh::TriMesh,
    extras: super::attributes::Extras,
    lods: &[f64],
) -> anyhow::Result<()> {
    let mut levels = Vec::new();
    // Each level's vertex count is a share of the input's, as --ratio.
    let wanted = lods
        .iter()
        .map(|&r| gng3d_core::GngTarget::VertexRatio(r).vertex_count(&input))
        .collect::<Result<Vec<_>, _>>()
        .context("--lods")?;
    // A level below a triangle's vertices would be run as a target nothing can reach.
    if let Some((k, (r, &n))) = lods
        .iter()
        .zip(&wanted)
        .enumerate()
        .find(|(_, (_, n))| **n < MIN_LEVEL_VERTICES)
    {
        let available = gng3d_core::GngTarget::VertexRatio(1.0).vertex_count(&input)?;
        bail!(
            "--lods: level {}'s share {r:?} gives {n} of the {available} vertices of {}; a \
             level needs at least {MIN_LEVEL_VERTICES} vertices (one triangle)",
            k + 1,
            args.input.display(),
        );
    }
    let (mut current, mut current_extras) = (input, extras);
    for (k, (&ratio, &wanted)) in lods.iter().zip(&wanted).enumerate() {
        let path = lod_path(&args.output, k + 1);
        let (simplified, attributes, report, kept) = simplify_to(
            args,
            params,
            &current,
            &current_extras,
            Target::Vertices(wanted),
            &path,
            Some(k + 1),
        )?;
        // As for a single run: a level that stops short of its target says so.
        if let Some(shortfall) = report.shortfall(Target::Vertices(wanted)) {
            eprintln!("warning: level {} ({}): {shortfall}", k + 1, path.display());
        }
        if !args.json {
            outln!(
                "qem lod{}: {} -> {} vertices, {} faces, max quadric error {:.3e}, {:.3} s -> {}",
                k + 1,
                report.input_vertices,
                report.vertices,
                report.faces,
                report.max_error,
                report.seconds,
                path.display()
            );
        }
        levels.push(Level {
            ratio,
            output: path,
            vertices: report.vertices,
            faces: report.faces,
            seconds: report.seconds,
            report,
            attributes: kept,
        });
        current_extras = super::attributes::Extras {
            attributes,
            materials: current_extras.materials,
            origin: current_extras.origin,
        };
        current = simplified;
    }
    if args.json {
        #[derive(Serialize)]
        struct Lods<'a> {
            method: &'static str,
            levels: &'a [Level],
        }
        crate::cli::print_json(&Lods {
            method: "qem",
            levels: &levels,
        })?;
    }
    Ok(())
}

//! `gng3d simplify --lods`: a chain of QEM levels of detail in one run, each simplified from the
//! one before (attributes carried), each written as it is made — the job's steps
//! (`job::load`, `job::run`, `job::save`) once per level.

use super::SimplifyArgs;
use anyhow::{Context, bail};
use job::{Request, Target};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The fewest vertices a level may ask for: one triangle.
const MIN_LEVEL_VERTICES: usize = 3;

/// `--lods`: each share in (0, 1], strictly decreasing.
pub(super) fn check(lods: &[f64]) -> anyhow::Result<()> {
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

/// Where level `k` (from 1) goes: OUT's name with `-lod<k>` before the extension.
fn level_path(output: &Path, k: usize) -> PathBuf {
    let stem = output.file_stem().unwrap_or_default().to_string_lossy();
    let name = match output.extension() {
        Some(ext) => format!("{stem}-lod{k}.{}", ext.to_string_lossy()),
        None => format!("{stem}-lod{k}"),
    };
    output.with_file_name(name)
}

/// One level in the `--json` output: the share asked for, where it went, and the job's summary
/// with its `attributes` object.
#[derive(Serialize)]
struct Level {
    ratio: f64,
    output: PathBuf,
    #[serde(flatten)]
    summary: serde_json::Value,
}

/// Run the chain.
pub(super) fn run(args: &SimplifyArgs, request: &Request, lods: &[f64]) -> anyhow::Result<()> {
    // Every file the run writes is checked against the input's files before any work.
    let paths: Vec<PathBuf> = (1..=lods.len())
        .map(|k| level_path(&args.output, k))
        .collect();
    let outputs: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
    crate::process::working_on(&args.input);
    let loaded = job::load(&args.input, request, &outputs).map_err(crate::cli::job_error)?;
    for w in &loaded.warnings {
        eprintln!("warning: {}: {w}", args.input.display());
    }
    // Each level's vertex count is a share of the input's, as --ratio.
    let wanted = lods
        .iter()
        .map(|&r| gng3d_core::GngTarget::VertexRatio(r).vertex_count(&loaded.model.mesh))
        .collect::<Result<Vec<_>, _>>()
        .context("--lods")?;
    // A level below a triangle's vertices would be run as a target nothing can reach.
    if let Some((k, (r, &n))) = lods
        .iter()
        .zip(&wanted)
        .enumerate()
        .find(|(_, (_, n))| **n < MIN_LEVEL_VERTICES)
    {
        let available = gng3d_core::GngTarget::VertexRatio(1.0).vertex_count(&loaded.model.mesh)?;
        bail!(
            "--lods: level {}'s share {r:?} gives {n} of the {available} vertices of {}; a \
             level needs at least {MIN_LEVEL_VERTICES} vertices (one triangle)",
            k + 1,
            args.input.display(),
        );
    }
    let mut levels = Vec::new();
    let mut current = loaded.model;
    for (k, ((&ratio, &wanted), path)) in lods.iter().zip(&wanted).zip(&paths).enumerate() {
        let level = Request {
            target: Target::Vertices(wanted),
            ..request.clone()
        };
        let mut bar = super::progress::JobBar::new(args.json);
        let outcome = job::run(&current, &level, &mut bar);
        bar.finish();
        let outcome = outcome
            .map_err(crate::cli::job_error)
            .with_context(|| format!("simplifying {} (level {})", args.input.display(), k + 1))?;
        let kept = job::save(&outcome.model, path)
            .map_err(crate::cli::job_error)
            .with_context(|| format!("QEM on {}", args.input.display()))?;
        for w in &kept.dropped {
            eprintln!("warning: {}: {w}", path.display());
        }
        // As for a single run: a level that stops short of its target says so.
        for w in &outcome.warnings {
            eprintln!("warning: level {} ({}): {w}", k + 1, path.display());
        }
        if !args.json {
            outln!("lod{} -> {}: {}", k + 1, path.display(), outcome.line());
        }
        let done = job::FileOutcome {
            outcome,
            kept,
            file_counts: (loaded.file_vertices, loaded.file_faces),
        };
        levels.push(Level {
            ratio,
            output: path.clone(),
            summary: done.to_json(),
        });
        current = done.outcome.model;
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

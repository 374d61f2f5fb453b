//! `gng3d reproduce`: the paper's checkpoint protocol on one mesh, or a survey of a folder.

use anyhow::Context;
use clap::Args;
use gng3d::experiment::reproduce::{Progress, ReproduceParams, Stage, reproduce_with_attributes};
use gng3d::experiment::survey::{SurveyParams, SurveyRow, survey_mesh_with_attributes};
use gng3d::report::paper::{
    terminal_attribute_legend, terminal_attribute_table, terminal_legend, terminal_table,
    write_reproduction,
};
use gng3d::report::survey::{terminal_summary, write_survey};
use indicatif::{ProgressBar, ProgressStyle};
use metrics::HausdorffParams;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Arguments of `gng3d reproduce`.
#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// Input mesh (.obj, .ply, .stl, .gltf, .glb).
    #[arg(required_unless_present = "all")]
    pub input: Option<PathBuf>,
    /// Survey every mesh in this folder at 10/25/50 % of its vertices instead of one mesh: the
    /// paper's GNG3D, GNG3D-Q and QEM, with the verdict per metric (summary.md, summary.csv,
    /// summary.json and charts in --out).
    #[arg(long, value_name = "DIR", conflicts_with = "input")]
    pub all: Option<PathBuf>,
    /// Training length in epochs of |V| signals (one checkpoint per epoch).
    #[arg(long, default_value_t = 30)]
    pub epochs: u64,
    /// GNG3D target as a fraction of the original vertex count.
    #[arg(long, default_value_t = 0.5)]
    pub target_ratio: f64,
    /// Output folder (default: reproduce-<mesh> or survey).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Surface samples per direction for every Hausdorff distance (and attribute deviation).
    #[arg(long, default_value_t = 100_000)]
    pub samples: usize,
    /// Random seed for GNG3D and the surface sampler.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// With --all: skip meshes with more faces than this.
    #[arg(long)]
    pub max_faces: Option<usize>,
    /// Side of the texture, in texels, that UV deviations are given in (inputs with texture
    /// coordinates; an input with texture coordinates, normals or colours gets
    /// attribute-deviation columns).
    #[arg(long, default_value_t = 1024)]
    pub texture_size: u32,
    /// UV distance above which a sample counts as off (inputs with texture coordinates).
    #[arg(long, default_value_t = 0.05)]
    pub uv_threshold: f64,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into_owned())
}

/// A bar of `len` units labelled `what` (drawn only on a terminal without --json; it ticks on
/// its own, so a long mesh or checkpoint still shows time passing).
fn bar(len: u64, what: &str, json: bool) -> ProgressBar {
    let bar = super::progress::bar(len, "{msg} [{bar:30}] {pos}/{len} {elapsed}", json);
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:30}] {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}

/// Run `gng3d reproduce`.
pub fn run(args: ReproduceArgs) -> anyhow::Result<()> {
    match (&args.input, &args.all) {
        (_, Some(dir)) => run_all(&args, dir),
        (Some(input), None) => run_one(&args, input),
        (None, None) => anyhow::bail!("give a mesh or --all DIR"),
    }
}

/// Checks what can be checked before loading anything.
fn check_args(args: &ReproduceArgs) -> anyhow::Result<()> {
    HausdorffParams::with_samples(args.samples)
        .validate()
        .context("--samples")?;
    gng3d::experiment::reproduce::check_epochs(args.epochs)
        .map_err(|e| anyhow::anyhow!("--epochs: {e}"))?;
    if !(args.target_ratio > 0.0 && args.target_ratio <= 1.0) {
        anyhow::bail!(
            "--target-ratio must be in (0, 1], got {}",
            args.target_ratio
        );
    }
    attribute_params(args).validate()?;
    Ok(())
}

/// The attribute-deviation settings of both modes (used for inputs with attributes).
fn attribute_params(args: &ReproduceArgs) -> metrics::AttributeParams {
    metrics::AttributeParams {
        samples: Some(args.samples),
        seed: args.seed,
        texture_size: args.texture_size,
        uv_threshold: args.uv_threshold,
    }
}

fn run_one(args: &ReproduceArgs, input: &Path) -> anyhow::Result<()> {
    check_args(args)?;
    // The output folder exists and takes files before the (long) training and evaluation.
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("reproduce-{}", stem(input))));
    super::prepare_output_folder(&dir)?;
    let (original, attributes) = load_with_attributes(input)?;
    let mut params = ReproduceParams {
        epochs: args.epochs,
        target_ratio: args.target_ratio,
        hausdorff: HausdorffParams::with_samples(args.samples),
        attributes: attribute_params(args),
        ..Default::default()
    };
    params.seed = args.seed;
    params.hausdorff.seed = args.seed;
    // One bar, re-labelled per stage: evaluation is most of the run, so it counts too.
    let progress = bar(args.epochs, "training GNG3D  ", args.json);
    let on_progress = |p: Progress| {
        let what = match p.stage {
            Stage::Training => "training GNG3D  ",
            Stage::Evaluating => "evaluating GNG3D",
            Stage::Qem => "QEM + evaluation",
        };
        if progress.message() != what {
            progress.set_message(what);
        }
        // Length and position together: never a redraw showing "30/16".
        progress.update(|state| {
            state.set_len(p.total);
            state.set_pos(p.done);
        });
    };
    let report = reproduce_with_attributes(&original, attributes.as_ref(), &params, on_progress)
        .with_context(|| format!("reproducing on {}", input.display()))?;
    progress.finish_and_clear();
    let name = stem(input);
    let written = write_reproduction(&report, &name, &dir)?;
    if args.json {
        return super::print_json(&report);
    }
    // The full table (faces, E_sur, QEM at the target) is in table.md / table.csv.
    out!("{}", terminal_table(&report).to_text());
    out!("{}", terminal_legend(&report));
    if let Some(table) = terminal_attribute_table(&report) {
        out!("\n{}", table.to_text());
        out!("{}", terminal_attribute_legend(&report));
    }
    outln!(
        "training {:.2} s, evaluation {:.2} s, total {:.2} s; wrote {} files to {}",
        report.seconds.training,
        report.seconds.evaluation,
        report.seconds.total,
        written.len(),
        dir.display()
    );
    Ok(())
}

fn run_all(args: &ReproduceArgs, dir: &Path) -> anyhow::Result<()> {
    check_args(args)?;
    let mut files: Vec<PathBuf> = Vec::new();
    for entry in
        std::fs::read_dir(dir).with_context(|| format!("reading folder {}", dir.display()))?
    {
        match entry {
            Ok(e) if mesh::io::Format::from_path(&e.path()).is_some() => files.push(e.path()),
            Ok(_) => {}
            // Said, not silently left out.
            Err(e) => eprintln!("warning: {}: an entry cannot be read: {e}", dir.display()),
        }
    }
    files.sort();
    if files.is_empty() {
        anyhow::bail!(
            "{}: no .obj, .ply, .stl, .gltf or .glb files",
            dir.display()
        );
    }
    let mut params = SurveyParams {
        epochs: args.epochs,
        hausdorff: HausdorffParams::with_samples(args.samples),
        ..Default::default()
    };
    params.seed = args.seed;
    params.hausdorff.seed = args.seed;
    params.attributes = attribute_params(args);
    // The output folder exists before the (long) survey starts.
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("survey"));
    super::prepare_output_folder(&out)?;
    let progress = bar(files.len() as u64, "meshes", args.json);
    let results: Vec<(String, anyhow::Result<Vec<SurveyRow>>)> = files
        .par_iter()
        .map(|path| {
            let name = path
                .file_name()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
            let rows = (|| {
                let (original, attributes) = load_with_attributes(path)?;
                if let Some(m) = args.max_faces.filter(|&m| original.face_count() > m) {
                    // Said, not silently left out of the table.
                    anyhow::bail!(
                        "skipped: {} faces, more than --max-faces {m}",
                        original.face_count()
                    );
                }
                survey_mesh_with_attributes(&name, &original, attributes.as_ref(), &params)
                    .with_context(|| format!("surveying {}", path.display()))
            })();
            progress.inc(1);
            (name, rows)
        })
        .collect();
    progress.finish_and_clear();
    let mut rows = Vec::new();
    let mut skipped = Vec::new();
    for (name, r) in results {
        match r {
            Ok(r) => rows.extend(r),
            Err(e) => {
                eprintln!("warning: {name}: {e:#}");
                skipped.push((name, format!("{e:#}")));
            }
        }
    }
    if rows.is_empty() {
        eprintln!("warning: no mesh in {} could be surveyed", dir.display());
    }
    let written = write_survey(&rows, &skipped, args.epochs, &out)?;
    if args.json {
        return super::print_json(&rows);
    }
    if !rows.is_empty() {
        out!("{}", terminal_summary(&rows));
    }
    outln!(
        "wrote {} files to {} (summary.md: the verdict and every run; summary.csv: every measure)",
        written.len(),
        out.display()
    );
    Ok(())
}

/// An input of either mode, cleaned (`super::load_input`, `job::load`), with its normals, texture
/// coordinates and colours following the cleaning (`None` without any): every method keeps them
/// and their deviation is measured. Materials are not used (a warning).
fn load_with_attributes(
    path: &Path,
) -> anyhow::Result<(mesh::TriMesh, Option<mesh::attributes::Attributes>)> {
    let input = super::load_input(path, true)?;
    // Nothing to train on or sample: said here, not as a signal budget of 0 or after training.
    let faces = input.mesh.face_count();
    if faces == 0 {
        anyhow::bail!(
            "{}: the mesh has no usable faces after cleaning (every face is degenerate or a \
             duplicate once exact duplicate vertices are welded)",
            path.display()
        );
    }
    let area = input.mesh.area();
    if area.is_nan() || area <= 0.0 {
        anyhow::bail!(
            "{}: the mesh has no usable faces after cleaning (its {faces} faces all have zero \
             area)",
            path.display()
        );
    }
    if input.has_materials {
        eprintln!(
            "warning: {}: materials not used: this command measures positions, normals, texture \
             coordinates and colours (`gng3d simplify` keeps materials)",
            path.display()
        );
    }
    Ok((input.mesh, input.attributes))
}

//! Command-line definitions (clap) and dispatch to one module per subcommand.

mod batch;
mod compare;
mod image;
mod info;
mod metrics;
mod progress;
mod reproduce;
mod simplify;

use clap::{Parser, Subcommand};

/// Simplify triangle meshes with GNG3D and QEM, and measure the results.
#[derive(Debug, Parser)]
#[command(name = "gng3d", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Let models read the files they name outside their own folder (`../textures/`, absolute
    /// paths): for trusted models only. By default a model reads only regular files inside its
    /// folder and what points elsewhere is skipped with a warning. Outputs stay inside the
    /// output's folder either way.
    #[arg(long, global = true)]
    allow_outside_references: bool,
}

#[derive(Debug, Subcommand)]
// Every subcommand takes negative numbers as values (`--max-error -0.001`), so that the
// validators name the problem instead of clap's "unexpected argument '-0' found".
enum Command {
    /// Print vertex/face counts, topology, area and size of a mesh.
    #[command(allow_negative_numbers = true)]
    Info(info::InfoArgs),
    /// Simplify a mesh with QEM or GNG3D and write the result.
    #[command(allow_negative_numbers = true)]
    Simplify(simplify::SimplifyArgs),
    /// Compare an original and a simplified mesh: paper errors and Hausdorff distance.
    #[command(allow_negative_numbers = true)]
    Metrics(metrics::MetricsArgs),
    /// Simplify with QEM and GNG3D to the same vertex count and measure both.
    #[command(allow_negative_numbers = true)]
    Compare(compare::CompareArgs),
    /// Run the paper's checkpoint protocol on a mesh, or survey a folder of meshes.
    #[command(allow_negative_numbers = true)]
    Reproduce(reproduce::ReproduceArgs),
    /// Simplify a folder or a manifest of meshes: sharded, N at a time, one JSON line per file.
    #[command(allow_negative_numbers = true)]
    Batch(batch::BatchArgs),
}

/// Where GNG3D places each output vertex (`gng3d_core::Placement`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum PlacementArg {
    /// At the trained node, as published (inside curved surfaces, off creases).
    Node,
    /// At the closest point of the original surface to the node.
    Project,
    /// At the minimiser of the cell's Garland–Heckbert quadrics (GNG3D-Q, the default).
    Quadric,
}

impl From<PlacementArg> for gng3d_core::Placement {
    fn from(p: PlacementArg) -> Self {
        match p {
            PlacementArg::Node => gng3d_core::Placement::Node,
            PlacementArg::Project => gng3d_core::Placement::Project,
            PlacementArg::Quadric => gng3d_core::Placement::Quadric,
        }
    }
}

/// GNG3D-Q's triangle-shape pass after the decimation (`gng3d_core::Shape`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum ShapeArg {
    /// No pass (the default without the flag).
    Off,
    /// Rounder triangles where that keeps the distance to the original (`--shape` alone).
    Fit,
    /// The remeshers' triangles, at a cost in distance.
    Round,
}

impl From<ShapeArg> for gng3d_core::Shape {
    fn from(s: ShapeArg) -> Self {
        match s {
            ShapeArg::Off => gng3d_core::Shape::Off,
            ShapeArg::Fit => gng3d_core::Shape::Fit,
            ShapeArg::Round => gng3d_core::Shape::Round,
        }
    }
}

/// Where GNG3D's training signals come from (`gng3d_core::SignalSource`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum SignalsArg {
    /// Original vertices, uniformly (the paper; the default).
    Vertices,
    /// Points uniform over the surface area.
    Surface,
    /// Surface points, faces weighted up (1-4x) by the curvature across their edges.
    Curvature,
}

impl From<SignalsArg> for gng3d_core::SignalSource {
    fn from(s: SignalsArg) -> Self {
        match s {
            SignalsArg::Vertices => gng3d_core::SignalSource::Vertices,
            SignalsArg::Surface => gng3d_core::SignalSource::Surface,
            SignalsArg::Curvature => gng3d_core::SignalSource::Curvature,
        }
    }
}

/// GNG3D / GNG3D-Q options shared by `simplify --method gng` and `compare`. The defaults are
/// GNG3D-Q (quadric placement, edge flips, a signal budget that follows the output size);
/// `--placement node --no-flips --epochs 30` is the paper's method and protocol (node placement
/// has no refit).
#[derive(Debug, Clone, clap::Args)]
pub(crate) struct GngVariantArgs {
    /// GNG3D vertex placement: node (the paper), project (onto the surface) or quadric
    /// (GNG3D-Q, default).
    #[arg(long, value_enum)]
    pub placement: Option<PlacementArg>,
    /// GNG3D: skip the error-driven edge-flip pass after reconstruction (the paper has none).
    #[arg(long)]
    pub no_flips: bool,
    /// GNG3D: skip the surface refit after the flips (GNG3D-Q with quadric placement only: the
    /// vertices are moved so that the triangles fit the original).
    #[arg(long)]
    pub no_refit: bool,
    /// GNG3D-Q: skip the tangential relaxation (help text: [`help::no_relax`]).
    #[arg(long, help = help::no_relax())]
    pub no_relax: bool,
    /// GNG3D-Q: skip the deviation repair (help text: [`help::no_deviation_repair`]).
    #[arg(long, help = help::no_deviation_repair())]
    pub no_deviation_repair: bool,
    /// GNG3D signal budget in epochs (help text: [`help::epochs`]).
    #[arg(long, help = help::epochs())]
    pub epochs: Option<f64>,
    /// GNG3D training signals: vertices (the paper, default), surface (uniform over the area) or
    /// curvature (surface, weighted towards creases and curved parts).
    #[arg(long, value_enum)]
    pub signals: Option<SignalsArg>,
    /// GNG3D-Q oversampling factor (help text: [`help::oversample`]).
    #[arg(long, help = help::oversample())]
    pub oversample: Option<f64>,
    /// GNG3D-Q rounds of detail nodes (help text: [`help::detail_rounds`]).
    #[arg(long, help = help::detail_rounds())]
    pub detail_rounds: Option<usize>,
    /// GNG3D-Q: the triangle-shape pass after the decimation (help text: [`help::shape`]).
    #[arg(
        long,
        value_enum,
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "fit",
        help = help::shape()
    )]
    pub shape: Option<ShapeArg>,
    /// GNG3D-Q: CAD creases kept as output edges (help text: [`help::creases`]).
    #[arg(long, help = help::creases())]
    pub creases: bool,
}

impl GngVariantArgs {
    /// The variant these flags ask for (`job::GngVariant`; mapped onto the library's options
    /// by the job, in one place).
    pub fn variant(&self) -> job::GngVariant {
        let off = |flag: bool| flag.then_some(false);
        let on = |flag: bool| flag.then_some(true);
        job::GngVariant {
            placement: self.placement.map(Into::into),
            flips: off(self.no_flips),
            refit: off(self.no_refit),
            relax: off(self.no_relax),
            deviation_repair: off(self.no_deviation_repair),
            epochs: self.epochs,
            signals: self.signals.map(Into::into),
            oversample: self.oversample,
            detail_rounds: self.detail_rounds,
            shape: self.shape.map(Into::into),
            creases: on(self.creases),
        }
    }
}

/// The target of `--vertices N`, `--faces N`, `--ratio R` or `--face-ratio R` (clap lets one
/// through): the one mapping of the target flags of `simplify` and `compare` (which takes the
/// first and the third). `None` when none is given.
pub(crate) fn target(
    vertices: Option<usize>,
    faces: Option<usize>,
    ratio: Option<f64>,
    face_ratio: Option<f64>,
) -> Option<job::Target> {
    match (vertices, faces, ratio, face_ratio) {
        (Some(n), ..) => Some(job::Target::Vertices(n)),
        (None, Some(n), ..) => Some(job::Target::Faces(n)),
        (None, None, Some(r), _) => Some(job::Target::Ratio(r)),
        (None, None, None, Some(r)) => Some(job::Target::FaceRatio(r)),
        (None, None, None, None) => None,
    }
}

/// The request of `method` to `target` with the flags of a GNG3D run that `simplify` and
/// `compare` share (`--seed`, `--time-limit`, the variant); the other fields keep the job's
/// defaults. Not yet validated: the caller sets its own flags first.
pub(crate) fn gng_request(
    method: job::Method,
    target: job::Target,
    seed: u64,
    time_limit: Option<f64>,
    gng: &GngVariantArgs,
) -> job::Request {
    job::Request {
        seed,
        time_limit,
        gng: gng.variant(),
        ..job::Request::new(target).with_method(method)
    }
}

/// A job error as the command line shows it: the options named by their flags, the rest with
/// its causes (the OS's reason behind a file that cannot be read).
pub(crate) fn job_error(e: job::JobError) -> anyhow::Error {
    match e {
        job::JobError::Option { .. }
        | job::JobError::NotForMethod { .. }
        | job::JobError::NotWithPartition { .. } => {
            anyhow::anyhow!(e.message(job::Spelling::Flags))
        }
        e => anyhow::Error::new(e),
    }
}

/// Run the parsed command.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    // Set on every run (also in process, as the tests call it again and again).
    mesh::io::set_reference_scope(if cli.allow_outside_references {
        mesh::io::ReferenceScope::Anywhere
    } else {
        mesh::io::ReferenceScope::ModelFolder
    });
    match cli.command {
        Command::Info(args) => info::run(args),
        Command::Simplify(args) => simplify::run(args),
        Command::Metrics(args) => metrics::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Reproduce(args) => reproduce::run(args),
        Command::Batch(args) => batch::run(args),
    }
}

/// Print `value` as pretty JSON on stdout; a closed stdout (e.g. `| head`) is not an error.
pub(crate) fn print_json<T: serde::Serialize>(value: &T) -> anyhow::Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    write_stdout(format_args!("{text}"), true)
}

/// Write `args` (and a newline) to stdout and flush: a write error is an error naming stdout
/// (a full disk, a closed file), except a closed pipe (`gng3d info m.obj | head -1`).
pub(crate) fn write_stdout(args: std::fmt::Arguments<'_>, newline: bool) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let written = out
        .write_fmt(args)
        .and_then(|()| {
            if newline {
                out.write_all(b"\n")
            } else {
                Ok(())
            }
        })
        .and_then(|()| out.flush());
    match written {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(anyhow::anyhow!("writing the output to stdout failed: {e}"))
        }
        _ => Ok(()),
    }
}

/// A mesh file as [`load_input`] returns it.
pub(crate) struct Input {
    /// The mesh.
    pub mesh: mesh::TriMesh,
    /// Its normals, texture coordinates, colours and per-face materials (`None` without any),
    /// fitting `mesh`: what `job::load` keeps.
    pub attributes: Option<mesh::attributes::Attributes>,
    /// Its materials, as the file gives them.
    pub materials: Option<mesh::attributes::Materials>,
    /// Whether the file has materials: a library, or per-face material indices.
    pub has_materials: bool,
}

/// Loads a mesh file for the commands that measure meshes (`metrics`, `compare`, `reproduce`)
/// with `job::load`, the loader of `simplify` and its rule (the attributes kept when there are
/// any), welded and cleaned with `weld` (`mesh::clean::prepare`, the attributes following);
/// loader warnings on stderr (the errors name the file).
pub(crate) fn load_input(path: &std::path::Path, weld: bool) -> anyhow::Result<Input> {
    crate::process::working_on(path);
    let request = job::Request {
        weld,
        ..job::Request::new(job::Target::Ratio(1.0))
    };
    let loaded = job::load(path, &request, &[]).map_err(job_error)?;
    for w in &loaded.warnings {
        eprintln!("warning: {}: {w}", path.display());
    }
    let model = loaded.model;
    let has_materials = model.materials.is_some()
        || model
            .attributes
            .as_ref()
            .is_some_and(|a| a.face_material.is_some());
    Ok(Input {
        mesh: model.mesh,
        attributes: model.attributes,
        materials: model.materials,
        has_materials,
    })
}

/// The names of `attributes` (materials aside) as the warnings write them.
pub(crate) fn attributes_in_words(attributes: &mesh::attributes::Attributes) -> Vec<&'static str> {
    attributes
        .kinds()
        .into_iter()
        .filter(|&kind| kind != mesh::AttributeKind::Materials)
        .map(attribute_in_words)
        .collect()
}

/// Creates the output folder `dir` (and its parents) and checks that it takes new files, before
/// any long work.
pub(crate) fn prepare_output_folder(dir: &std::path::Path) -> anyhow::Result<()> {
    use anyhow::Context;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    mesh::io::check_writable(&dir.join("probe"))
        .with_context(|| format!("{}: cannot write output files there", dir.display()))?;
    Ok(())
}

/// Writes a mesh `method` produced (positions and triangles) with the job's one checked save
/// (`job::save`: a known extension, a folder that takes it, triangles, read back, atomic).
pub(crate) fn save_checked(
    mesh: &mesh::TriMesh,
    path: &std::path::Path,
    method: &str,
) -> anyhow::Result<()> {
    use anyhow::Context;
    job::save(&mesh::Model::from(mesh.clone()), path)
        .map_err(job_error)
        .with_context(|| format!("{method} output"))?;
    Ok(())
}

/// Writes `bytes` to `path` atomically (`mesh::io::write_atomic`).
pub(crate) fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> anyhow::Result<()> {
    mesh::io::write_atomic(path, bytes)?;
    Ok(())
}

/// Help texts that quote the library's policy numbers, made from the constants themselves so
/// the help cannot drift from what the code does.
mod help {
    use gng3d_core::tuning;

    /// A share as a percentage ("30 %").
    fn percent(share: f64) -> String {
        format!("{} %", share * 100.0)
    }

    pub(super) fn no_relax() -> String {
        format!(
            "GNG3D-Q: skip the tangential relaxation after the decimation of oversampled runs \
             (each vertex moved half-way toward the centroid of the original vertices it stands \
             for; on by default for outputs of at most {} of the input's vertices)",
            percent(tuning::RELAX_MAX_RATIO)
        )
    }

    pub(super) fn no_deviation_repair() -> String {
        format!(
            "GNG3D-Q: skip the deviation repair after the decimation of oversampled runs \
             (vertices standing off the original moved back onto it, edges spanning a groove of \
             it flipped, where the output is farthest from it; on by default for outputs of at \
             least {} of the input's vertices)",
            percent(tuning::DETAIL_MIN_RATIO)
        )
    }

    // The costs and gains of `--shape` and `--creases` are measurements (docs/notes/shape.md,
    // docs/notes/creases.md), not constants of the code: quoted here as measured.
    pub(super) fn shape() -> String {
        "GNG3D-Q: even out the triangles after the decimation (flips toward valence 6, \
         tangential smoothing). `--shape` (fit): only where the faces stay as close to the \
         original, median smallest angle 37-41° → 40-43°, triangles under 20° 2-6 % → 0.6-2.7 \
         %, mean distance 0.86-1.08× QEM's, ~25 % more time; `--shape=round`: 43-47° and \
         0-1.6 % for 1.05-1.5× QEM's mean distance (docs/notes/shape.md)"
            .to_string()
    }

    pub(super) fn creases() -> String {
        "GNG3D-Q: on a CAD part (sharp edges ≥ 2 % of its edges) cut and decimate along its \
         creases, kept only where no farther from the original; measured: fandisk at 10 % \
         Hausdorff ×0.77, no gain on rocker-arm or casting, up to 2× the time on CAD parts \
         (docs/notes/creases.md)"
            .to_string()
    }

    pub(super) fn epochs() -> String {
        format!(
            "GNG3D signal budget in epochs of |V| signals (the paper's protocol: {}), instead of \
             the default budget {} × N for N output vertices",
            tuning::PAPER_EPOCHS,
            tuning::DEFAULT_SIGNALS_PER_NODE
        )
    }

    pub(super) fn oversample() -> String {
        format!(
            "GNG3D-Q oversampling factor k in [1, 4]: train k × N nodes, then decimate the mesh \
             to N with QEM (error first). Default {} with quadric placement, 1 (off) otherwise. \
             Oversampled runs train each piece of at least {} nodes as two halves on two threads \
             (the same result on any number of cores)",
            tuning::DEFAULT_OVERSAMPLE,
            tuning::SPLIT_MIN_NODES
        )
    }

    pub(super) fn detail_rounds() -> String {
        format!(
            "GNG3D-Q rounds of detail nodes (0-{}) in oversampled runs: nodes added where the mesh \
             stays farthest from the original, then the mesh rebuilt. Default {} for outputs of \
             at least {} of the input's vertices, 0 below",
            tuning::MAX_DETAIL_ROUNDS,
            tuning::DEFAULT_DETAIL_ROUNDS,
            percent(tuning::DETAIL_MIN_RATIO)
        )
    }
}

/// An attribute kind as the warnings write it.
pub(crate) fn attribute_in_words(kind: mesh::AttributeKind) -> &'static str {
    match kind {
        mesh::AttributeKind::Uv0 => "texture coordinates",
        mesh::AttributeKind::Uv1 => "second texture coordinates",
        mesh::AttributeKind::Colors => "vertex colours",
        other => other.name(),
    }
}

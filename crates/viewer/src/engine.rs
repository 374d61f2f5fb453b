//! The one adapter between the viewer and the algorithm crates (gng3d-core, qem, metrics, mesh
//! I/O). Everything the UI and the worker threads need from them goes through this module, so an
//! API change there touches only this file.

use crate::error::{Result, ViewerError};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::path::Path;

/// GNG3D parameters as edited in the UI.
pub type TrainParams = gng3d_core::GngParams;
/// Where GNG training signals come from.
pub type SignalSourceKind = gng3d_core::SignalSource;
/// A cheap copy of the live network: node positions and GNG edges.
pub type NetworkSnapshot = gng3d_core::Snapshot;
/// One step of the pipeline after training (label, map faces, …, decimate).
pub type PipelineStep = gng3d_core::Step;
/// A step of the run's plan with its build round.
pub type PlannedStep = gng3d_core::PlannedStep;
/// A finished step: its seconds and what it changed.
pub type StepRecord = gng3d_core::StepRecord;

/// Every signal source, in menu order, with its label.
pub const SIGNAL_SOURCES: [(SignalSourceKind, &str); 3] = [
    (SignalSourceKind::Vertices, "original vertices (paper)"),
    (SignalSourceKind::Surface, "surface samples"),
    (SignalSourceKind::Curvature, "curvature-weighted surface"),
];

/// Label of a signal source.
pub fn signal_source_label(source: SignalSourceKind) -> &'static str {
    SIGNAL_SOURCES
        .iter()
        .find(|(s, _)| *s == source)
        .map_or("?", |(_, l)| l)
}

/// Every vertex placement of the reconstruction, in menu order, with its label.
pub const PLACEMENTS: [(gng3d_core::Placement, &str); 3] = [
    (gng3d_core::Placement::Node, "node position (paper)"),
    (gng3d_core::Placement::Project, "projected to surface"),
    (gng3d_core::Placement::Quadric, "quadric (GNG3D-Q)"),
];

/// Label of a vertex placement.
pub fn placement_label(placement: gng3d_core::Placement) -> &'static str {
    PLACEMENTS
        .iter()
        .find(|(p, _)| *p == placement)
        .map_or("?", |(_, l)| l)
}

/// Which method a run's parameters train: the paper's GNG3D, GNG3D-Q (the library's default),
/// or neither (steps switched one by one in the panel).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// GNG3D as published: nodes are the vertices, no flips, refit, relaxation or repair, a
    /// budget of 30 epochs (`GngParams::paper`, `gng3d compare --paper`).
    Paper,
    /// GNG3D-Q: the library's and the CLI's default (`gng3d simplify --method gng`).
    Q,
    /// Steps switched by hand: neither of the two.
    Custom,
}

impl Method {
    /// The method of `params`.
    pub fn of(params: &TrainParams) -> Method {
        let defaults = gng3d_core::GngParams::default();
        if params.reconstruction == gng3d_core::ReconstructionParams::paper()
            && params.epochs == Some(gng3d_core::tuning::PAPER_EPOCHS)
        {
            Method::Paper
        } else if params.reconstruction == defaults.reconstruction && params.epochs.is_none() {
            Method::Q
        } else {
            Method::Custom
        }
    }

    /// Its name in titles and legends.
    pub fn name(self) -> &'static str {
        match self {
            Method::Paper => "GNG3D (paper)",
            Method::Q => "GNG3D-Q",
            Method::Custom => "GNG3D (custom)",
        }
    }

    /// `params` switched to `self` (`Custom` leaves them as they are). A budget the user set
    /// (`--max-signals`) wins over the paper's 30 epochs, as on the CLI.
    pub fn apply(self, params: &mut TrainParams) {
        match self {
            Method::Paper => {
                params.reconstruction = gng3d_core::ReconstructionParams::paper();
                params.epochs = Some(gng3d_core::tuning::PAPER_EPOCHS);
            }
            Method::Q => {
                params.reconstruction = gng3d_core::GngParams::default().reconstruction;
                params.epochs = None;
            }
            Method::Custom => {}
        }
    }
}

/// Default parameters for `target_vertices` nodes.
pub fn default_params(target_vertices: usize) -> TrainParams {
    TrainParams::for_target(target_vertices)
}

/// A running GNG3D training session.
pub struct Engine {
    trainer: gng3d_core::Trainer,
    /// The finished network's reconstruction, once built: the network no longer changes, and
    /// a second run of the pipeline would find the run's deadline passed and leave its
    /// optional steps out.
    finished: Option<Reconstruction>,
}

impl Engine {
    /// Start training on `mesh` (already cleaned) with `params` as edited in the UI, whose
    /// `target_vertices` is the output count N. The user-level fields are resolved against the
    /// mesh by `GngOptions::resolve`, the one rule of the CLI and the library (GNG3D-Q trains an
    /// oversampled network and decimates it to N); the UI's low-level knobs (α, decay, edge
    /// age, removal window, search) are then taken as edited.
    ///
    /// With `attributes` whose seams the output is to follow, the run is
    /// `Trainer::new`'s with them, as `gng3d simplify --method gng` runs it.
    pub fn new(
        mesh: &TriMesh,
        attributes: Option<&Attributes>,
        params: &TrainParams,
    ) -> Result<Engine> {
        let options = gng3d_core::GngOptions {
            target: gng3d_core::GngTarget::Vertices(params.target_vertices),
            time_limit_seconds: params.time_limit.map(|t| t.as_secs_f64()),
            seed: params.seed,
            max_signals: params.max_signals,
            epochs: params.epochs,
            lambda: params.lambda,
            eps_winner: Some(params.eps_winner),
            eps_neighbour: Some(params.eps_neighbour),
            signal_source: params.signal_source,
            reconstruction: params.reconstruction.clone(),
            oversample: None,
            detail_rounds: None,
            threads: params.threads,
        };
        let resolved = options
            .resolve(mesh)
            .map_err(|e| ViewerError::Gng(e.to_string()))?;
        let resolved = TrainParams {
            alpha: params.alpha,
            error_decay: params.error_decay,
            max_edge_age: params.max_edge_age,
            removal_window: params.removal_window,
            search: params.search,
            ..resolved
        };
        let model = mesh::Model {
            attributes: attributes.cloned(),
            ..mesh.clone().into()
        };
        gng3d_core::Trainer::new(&model, resolved)
            .map(|trainer| Engine {
                trainer,
                finished: None,
            })
            .map_err(|e| ViewerError::Gng(e.to_string()))
    }

    /// The signal budget this run resolved to (the crate's default when none was given).
    pub fn max_signals(&self) -> u64 {
        self.trainer.stats().max_signals
    }

    /// Present up to `signals` more training signals; returns how many were presented.
    pub fn step(&mut self, signals: u64) -> u64 {
        self.trainer.step(signals)
    }

    /// Whether training has reached its budget or limits.
    pub fn is_finished(&self) -> bool {
        self.trainer.is_finished()
    }

    /// Signals presented so far.
    pub fn signals(&self) -> u64 {
        self.trainer.signals()
    }

    /// Copy of the network for display.
    pub fn snapshot(&self) -> NetworkSnapshot {
        self.trainer.snapshot()
    }

    /// The steps the finished network's reconstruction runs, in order (the run's plan, less
    /// what its time limit left out before it started).
    pub fn plan(&self) -> Vec<PlannedStep> {
        self.trainer.plan().steps().to_vec()
    }

    /// The steps the run's parameters plan without a time limit (`Plan::of`): [`Engine::plan`]
    /// is this list less what the time limit left out before the run started.
    pub fn full_plan(&self) -> Vec<PlannedStep> {
        self.trainer.full_plan().steps().to_vec()
    }

    /// The run's time limit (training and the steps after it), if any.
    pub fn time_limit(&self) -> Option<std::time::Duration> {
        self.trainer.params().time_limit
    }

    /// With a time limit: the wall time from the start of the run at which training stops so
    /// that the steps after it fit (`Trainer::training_limit`).
    pub fn training_limit(&self) -> Option<std::time::Duration> {
        self.trainer.training_limit()
    }

    /// The run's time limit and its training limit, when it has a limit.
    pub fn limits(&self) -> Option<(std::time::Duration, std::time::Duration)> {
        self.time_limit().zip(self.training_limit())
    }

    /// Signals after which the network holds its nodes: λ × the node target (one insertion
    /// every λ signals from a pair of nodes per part), at most the budget.
    pub fn growth_signals(&self) -> u64 {
        let lambda = self.trainer.stats().lambda.max(1);
        (lambda.saturating_mul(self.trainer.node_target() as u64)).min(self.max_signals())
    }

    /// Nodes the network holds now, and the nodes it aims for.
    pub fn nodes(&self) -> (usize, usize) {
        (self.trainer.node_count(), self.trainer.node_target())
    }

    /// Whether the network holds the nodes it aims for (growth is over).
    pub fn holds_target(&self) -> bool {
        self.trainer.node_count() >= self.trainer.node_target()
    }

    /// Leave a pause of `idle` out of the run's clock (`Trainer::discount`): the time limit
    /// counts the time the run was going, not the time the user had it paused.
    pub fn discount(&mut self, idle: std::time::Duration) {
        self.trainer.discount(idle);
    }

    /// End training now (`Trainer::cancel_token`): the network stays as it is and
    /// [`Engine::reconstruct`] runs the finished network's pipeline on it.
    pub fn stop(&mut self) {
        self.trainer.cancel_token().cancel();
        // The trainer notices the cancel at the top of its next step.
        self.trainer.step(1);
    }

    /// Wall time since the run started ([`Engine::new`]).
    pub fn run_elapsed(&self) -> std::time::Duration {
        self.trainer.run_elapsed()
    }

    /// Build a triangle mesh from the current network with the pipeline the CLI runs
    /// (`gng3d_core::finish`: decimated to the output count when the network is oversampled);
    /// `on_step` sees each step of that pipeline as it finishes.
    /// While training runs, a checkpoint's preview (`Trainer::preview`) skips the detail rounds:
    /// each costs about one more reconstruction, and with three of them the default watched run
    /// of gargoyle-10k at 25 % (12 s asked) was at 68 % of its signals after 20 s; `on_step` is
    /// not called for it. The finished network gets the full pipeline, and with it the run's
    /// warnings (why the mesh has another vertex count than the target, what was dropped), as
    /// the CLI prints them; a preview has none (a network still growing is short of the target
    /// by design).
    ///
    /// The finished network's reconstruction is built once: later calls return it again
    /// without running the pipeline ([`Engine::has_final`]).
    pub fn reconstruct(&mut self, on_step: impl FnMut(&StepRecord)) -> Result<Reconstruction> {
        if let Some(done) = &self.finished {
            return Ok(done.clone());
        }
        let full = self.trainer.is_finished();
        let result = if full {
            gng3d_core::finish(&self.trainer, on_step)
        } else {
            self.trainer.preview()
        };
        result
            .map(|result| {
                let warnings = &result.report.warnings;
                let cut_for_time = warnings.iter().any(|w| {
                    matches!(
                        w,
                        gng3d_core::GngWarning::StepSkippedForTime { .. }
                            | gng3d_core::GngWarning::OversamplingSkippedForTime { .. }
                            | gng3d_core::GngWarning::TimeLimitBelowMinimum { .. }
                            | gng3d_core::GngWarning::TimeLimitBeforeTarget { .. }
                    )
                });
                Reconstruction {
                    mesh: result.mesh,
                    warnings: warnings.iter().map(|w| w.to_string()).collect(),
                    cut_for_time,
                    full,
                }
            })
            .inspect(|reconstruction| {
                if full {
                    self.finished = Some(reconstruction.clone());
                }
            })
            .map_err(|e| ViewerError::Gng(e.to_string()))
    }

    /// Whether the finished network's reconstruction is built (the next
    /// [`Engine::reconstruct`] returns it without running the pipeline).
    pub fn has_final(&self) -> bool {
        self.finished.is_some()
    }
}

/// What [`Engine::reconstruct`] built.
#[derive(Debug, Clone)]
pub struct Reconstruction {
    /// The mesh.
    pub mesh: TriMesh,
    /// The run's warnings, as the CLI prints them (finished network only).
    pub warnings: Vec<String>,
    /// Whether the time limit cut anything (steps, oversampling, training before the target),
    /// or is below the run's minimum.
    pub cut_for_time: bool,
    /// Whether this was the finished network's full pipeline (not a preview).
    pub full: bool,
}

/// QEM simplification of `mesh` to `target_vertices` vertices, with the CLI's note when it
/// stopped above the target ([`qem::QemReport::shortfall`]: holes, small pieces).
pub fn qem_simplify(mesh: &TriMesh, target_vertices: usize) -> Result<(TriMesh, Option<String>)> {
    let (out, _, note) = qem_simplify_with_attributes(mesh, None, target_vertices)?;
    Ok((out, note))
}

/// [`qem_simplify`] keeping `attributes` (of `mesh`'s corners) through the contractions: the
/// job every front end runs (`job::run` with QEM to a vertex count), so the viewer's QEM is
/// `gng3d simplify --method qem`'s.
pub fn qem_simplify_with_attributes(
    mesh: &TriMesh,
    attributes: Option<&Attributes>,
    target_vertices: usize,
) -> Result<(TriMesh, Option<Attributes>, Option<String>)> {
    let model = mesh::Model {
        attributes: attributes.cloned(),
        ..mesh::Model::from(mesh.clone())
    };
    let request =
        job::Request::new(job::Target::Vertices(target_vertices)).with_method(job::Method::Qem);
    let outcome =
        job::run(&model, &request, &mut ()).map_err(|e| ViewerError::Qem(e.to_string()))?;
    let note = outcome.warnings.into_iter().next();
    Ok((outcome.model.mesh, outcome.model.attributes, note))
}

/// Surface samples per direction for the Hausdorff distance (keeps one evaluation to about a
/// second on a 2-core machine; `gng3d metrics --samples 200000` measures the same pair with the
/// same numbers, since both go through [`metrics::Evaluator`]).
pub const HAUSDORFF_SAMPLES: usize = 200_000;

/// The metrics parameters of every viewer evaluation.
pub fn metrics_params() -> metrics::MetricsParams {
    metrics::MetricsParams {
        hausdorff: metrics::HausdorffParams::with_samples(HAUSDORFF_SAMPLES),
    }
}

/// Errors and triangle shape of a simplified mesh against the original: what the plots and the
/// table show, for GNG3D and QEM alike (a compact copy of the fields of
/// [`metrics::Evaluation`] the viewer displays).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Evaluation {
    /// Vertices of the simplified mesh.
    pub vertices: usize,
    /// Faces of the simplified mesh.
    pub faces: usize,
    /// The paper's E_avg: mean squared distance from each original vertex to its nearest
    /// simplified vertex, squared model units.
    pub e_avg: f64,
    /// The paper's E_max: the largest of those squared distances, squared model units.
    pub e_max: f64,
    /// The paper's E_sur, signed like the CLI's: Area(original) − Area(simplified), squared
    /// model units (positive: the simplified mesh lost area).
    pub e_sur: f64,
    /// Symmetric Hausdorff distance (the larger of the two one-sided maxima), model units
    /// (`None` when it could not be computed).
    pub hausdorff: Option<f64>,
    /// Mean surface distance (Metro's mean of the two directions), model units.
    pub hausdorff_mean: Option<f64>,
    /// Median over triangles of the smallest interior angle, degrees (60 = all equilateral).
    pub median_min_angle_degrees: f64,
    /// Share of triangles whose smallest angle is under 20°, 0–1.
    pub below_20_degrees: f64,
    /// Attribute deviation, when the original and the simplified mesh have attributes.
    pub attributes: Option<AttributeFigures>,
}

/// The attribute deviation the table shows (a compact copy of fields of
/// [`metrics::AttributeDeviation`]: samples on the simplified mesh against the original, the
/// direction `gng3d compare` reports); `None` where the attribute is not in both meshes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AttributeFigures {
    /// Mean UV distance in texels of a `texture_size`² texture.
    pub uv_texels_mean: Option<f64>,
    /// Share (0–1) of the samples whose UV distance is above `uv_threshold`.
    pub uv_over_threshold: Option<f64>,
    /// Mean angle between the normals, degrees.
    pub normal_degrees_mean: Option<f64>,
    /// Mean colour distance (linear RGB, channels 0–1).
    pub color_mean: Option<f64>,
    /// Texels per UV unit.
    pub texture_size: u32,
    /// UV threshold, UV units.
    pub uv_threshold: f64,
}

impl AttributeFigures {
    /// The displayed fields of a [`metrics::AttributeDeviation`].
    pub fn from_metrics(a: &metrics::AttributeDeviation) -> AttributeFigures {
        let b = &a.backward;
        AttributeFigures {
            uv_texels_mean: b.uv0.map(|u| u.texels.mean),
            uv_over_threshold: b.uv0.map(|u| u.over_threshold),
            normal_degrees_mean: b.normals.map(|n| n.mean_degrees),
            color_mean: b.colors.map(|c| c.mean),
            texture_size: a.texture_size,
            uv_threshold: a.uv_threshold,
        }
    }
}

/// The attribute-deviation parameters of every viewer evaluation: `gng3d compare`'s defaults
/// (10 × the larger face count of samples per direction, 1024-texel texture, 0.05 UV).
pub fn attribute_params() -> metrics::AttributeParams {
    metrics::AttributeParams::default()
}

impl Evaluation {
    /// The displayed fields of a full [`metrics::Evaluation`].
    pub fn from_metrics(e: &metrics::Evaluation) -> Evaluation {
        Evaluation {
            vertices: e.meshes.simplified.referenced_vertices,
            faces: e.meshes.simplified.faces,
            e_avg: e.e_avg,
            e_max: e.e_max,
            e_sur: e.e_sur_signed,
            hausdorff: Some(e.hausdorff.max),
            hausdorff_mean: Some(e.hausdorff.mean),
            median_min_angle_degrees: e.quality.simplified.median_min_angle_degrees,
            below_20_degrees: e.quality.simplified.below_20_degrees,
            attributes: None,
        }
    }
}

/// The viewer's one evaluation of `simplified` against `original` (runs on the calling thread;
/// the session calls it from a background job): [`metrics::Evaluator`] with
/// [`metrics_params`], the same code and numbers as the CLI's `metrics`/`compare`.
pub fn evaluate(original: &TriMesh, simplified: &TriMesh) -> Result<Evaluation> {
    let evaluation = metrics::Evaluator::new(original, &metrics_params())
        .and_then(|evaluator| evaluator.evaluate(simplified))
        .map_err(|e| ViewerError::Metrics(e.to_string()))?;
    Ok(Evaluation::from_metrics(&evaluation))
}

/// [`evaluate`] plus the attribute deviation ([`metrics::attribute_deviation`] with
/// [`attribute_params`]) when both `original_attributes` and `simplified_attributes` are given.
pub fn evaluate_with_attributes(
    original: &TriMesh,
    original_attributes: Option<&Attributes>,
    simplified: &TriMesh,
    simplified_attributes: Option<&Attributes>,
) -> Result<Evaluation> {
    let mut evaluation = evaluate(original, simplified)?;
    if let (Some(a), Some(b)) = (original_attributes, simplified_attributes) {
        let deviation =
            metrics::attribute_deviation(original, a, simplified, b, &attribute_params())
                .map_err(|e| ViewerError::Metrics(e.to_string()))?;
        evaluation.attributes = Some(AttributeFigures::from_metrics(&deviation));
    }
    Ok(evaluation)
}

/// GNG3D's output with attributes taken from the original surface, as `gng3d simplify
/// --method gng` does ([`mesh::transfer::transfer_attributes`]), then
/// [`evaluate_with_attributes`]; without `original_attributes`, [`evaluate`].
pub fn evaluate_reconstruction(
    original: &TriMesh,
    original_attributes: Option<&Attributes>,
    reconstruction: &TriMesh,
) -> Result<Evaluation> {
    let transferred = original_attributes
        .map(|a| mesh::transfer::transfer_attributes(original, a, reconstruction));
    evaluate_with_attributes(
        original,
        original_attributes,
        reconstruction,
        transferred.as_ref(),
    )
}

/// E_avg/E_max (squared model units) of the live network's nodes against the original
/// vertices, for the live plot; `None` without nodes.
pub fn network_errors(original: &TriMesh, nodes: &[glam::Vec3]) -> Option<(f64, f64)> {
    metrics::vertex_errors(&original.positions, nodes).map(|e| (e.e_avg, e.e_max))
}

/// A mesh loaded from disk plus non-fatal warnings.
pub struct Loaded {
    /// The cleaned mesh the algorithms see (welded, no degenerate/duplicate faces, no
    /// unreferenced vertices).
    pub mesh: TriMesh,
    /// Human-readable loader and cleaning notes.
    pub warnings: Vec<String>,
    /// The mesh's normals, texture coordinates and colours, following the cleaning (`None`
    /// when the file has none): kept by QEM, transferred to GNG3D's output, and measured.
    pub attributes: Option<Attributes>,
}

/// `e`'s message and its causes ("cannot read file: No such file or directory"), without the
/// file name it starts with (the viewer's error names the file).
fn with_causes(e: &dyn std::error::Error, path: &Path) -> String {
    let mut message = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        message = format!("{message}: {cause}");
        source = cause.source();
    }
    message
        .trim_start_matches(&format!("{}: ", path.display()))
        .to_string()
}

/// Load a mesh file (OBJ, PLY, STL, glTF, GLB) for display and training: the job's load
/// (`job::load`, the CLI's: welded and cleaned, its attributes following).
pub fn load_mesh(path: &Path) -> Result<Loaded> {
    let request = job::Request::new(job::Target::Ratio(1.0));
    let loaded = job::load(path, &request, &[]).map_err(|e| ViewerError::Load {
        path: path.to_path_buf(),
        message: with_causes(&e, path),
    })?;
    let mut warnings: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    let o = loaded.model.origin;
    if o != glam::DVec3::ZERO {
        // The viewer keeps one f32 mesh: a far model is shown and saved recentred, said here.
        warnings.push(format!(
            "the model lies far from its coordinates' origin: shown and saved moved by \
             ({}, {}, {}) (gng3d simplify keeps the coordinates)",
            -o.x, -o.y, -o.z
        ));
    }
    let mesh = loaded.model.mesh;
    let dropped = loaded.file_vertices.saturating_sub(mesh.vertex_count());
    if dropped > 0 {
        warnings.push(format!(
            "cleaned: {dropped} vertices welded or unreferenced removed"
        ));
    }
    if mesh.face_count() == 0 {
        return Err(ViewerError::Load {
            path: path.to_path_buf(),
            message: "the mesh has no usable faces".into(),
        });
    }
    Ok(Loaded {
        mesh,
        warnings,
        attributes: loaded.model.attributes,
    })
}

/// Save a mesh; the format follows the extension (obj, ply, stl).
pub fn save_mesh(mesh: &TriMesh, path: &Path) -> Result<()> {
    mesh::io::save(&mesh.clone().into(), path)
        .map(|_| ())
        .map_err(|e| ViewerError::Save {
            path: path.to_path_buf(),
            message: e
                .to_string()
                .trim_start_matches(&format!("{}: ", path.display()))
                .to_string(),
        })
}

/// The built-in model shown without a file argument.
pub fn default_model() -> (String, TriMesh) {
    ("blob (procedural)".into(), mesh::procedural::blob())
}

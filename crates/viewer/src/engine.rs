//! The one adapter between the viewer and the algorithm crates (gng3d-core, qem, metrics, mesh
//! I/O). Everything the UI and the worker threads need from them goes through this module, so an
//! API change there touches only this file.

use crate::error::{Result, ViewerError};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::path::Path;
use std::sync::Arc;

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

/// Every vertex placement of the reconstruction, in menu order, with its label.
pub const PLACEMENTS: [(gng3d_core::Placement, &str); 3] = [
    (gng3d_core::Placement::Node, "node position (paper)"),
    (gng3d_core::Placement::Project, "projected to surface"),
    (gng3d_core::Placement::Quadric, "quadric (GNG3D-Q)"),
];

/// Every setting of GNG3D-Q's triangle-shape pass, in menu order, with its label.
pub const SHAPES: [(gng3d_core::Shape, &str); 3] = [
    (gng3d_core::Shape::Off, "off"),
    (gng3d_core::Shape::Fit, "fit (same distance)"),
    (gng3d_core::Shape::Round, "round (remeshers')"),
];

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

/// A running GNG3D training session: the job's run ([`job::GngRun`], the CLI's options
/// resolution, trainer and run after training), stepped here round by round for the live view.
pub struct Engine {
    run: job::GngRun,
    /// The finished network's reconstruction, once built: the network no longer changes, and
    /// a second run of the pipeline would find the run's deadline passed and leave its
    /// optional steps out.
    finished: Option<Reconstruction>,
}

/// The job's request of the parameters edited in the UI: the method (the paper's GNG3D or
/// GNG3D-Q), the output count N, the seed, the time limit and the threads, as `gng3d simplify
/// --method gng --vertices N` asks them.
pub fn request(params: &TrainParams) -> job::Request {
    job::Request {
        method: match Method::of(params) {
            Method::Paper => job::Method::Paper,
            _ => job::Method::Gng,
        },
        seed: params.seed,
        time_limit: params.time_limit.map(|t| t.as_secs_f64()),
        threads: params.threads,
        ..job::Request::new(job::Target::Vertices(params.target_vertices))
    }
}

impl Engine {
    /// Start training on `model` (already cleaned; with attributes the output's triangles
    /// follow their seams) with `params` as edited in the UI, whose `target_vertices` is the
    /// output count N: [`request`]'s run ([`job::GngRun::tuned`]), the UI's budget, λ, learning
    /// rates, signal source and step switches over the request's options before their one
    /// resolution against the mesh (GNG3D-Q trains an oversampled network and decimates it to
    /// N), its low-level knobs (α, decay, edge age, removal window, search) then taken as
    /// edited.
    pub fn new(model: &mesh::Model, params: &TrainParams) -> Result<Engine> {
        job::GngRun::tuned(
            model,
            &request(params),
            |o| {
                o.max_signals = params.max_signals;
                o.epochs = params.epochs;
                o.lambda = params.lambda;
                o.eps_winner = Some(params.eps_winner);
                o.eps_neighbour = Some(params.eps_neighbour);
                o.signal_source = params.signal_source;
                o.reconstruction = params.reconstruction.clone();
            },
            |p| {
                p.alpha = params.alpha;
                p.error_decay = params.error_decay;
                p.max_edge_age = params.max_edge_age;
                p.removal_window = params.removal_window;
                p.search = params.search;
            },
        )
        .map(|run| Engine {
            run,
            finished: None,
        })
        .map_err(|e| ViewerError::Gng(e.to_string()))
    }

    fn trainer(&self) -> &gng3d_core::Trainer {
        self.run.trainer()
    }

    /// The signal budget this run resolved to (the crate's default when none was given).
    pub fn max_signals(&self) -> u64 {
        self.trainer().stats().max_signals
    }

    /// Present up to `signals` more training signals; returns how many were presented.
    pub fn step(&mut self, signals: u64) -> u64 {
        self.run.trainer_mut().step(signals)
    }

    /// Whether training has reached its budget or limits.
    pub fn is_finished(&self) -> bool {
        self.trainer().is_finished()
    }

    /// Signals presented so far.
    pub fn signals(&self) -> u64 {
        self.trainer().signals()
    }

    /// Copy of the network for display.
    pub fn snapshot(&self) -> NetworkSnapshot {
        self.trainer().snapshot()
    }

    /// The steps the finished network's reconstruction runs, in order (the run's plan, less
    /// what its time limit left out before it started).
    pub fn plan(&self) -> Vec<PlannedStep> {
        self.trainer().plan().steps().to_vec()
    }

    /// The steps the run's parameters plan without a time limit (`Plan::of`): [`Engine::plan`]
    /// is this list less what the time limit left out before the run started.
    pub fn full_plan(&self) -> Vec<PlannedStep> {
        self.trainer().full_plan().steps().to_vec()
    }

    /// The run's time limit (training and the steps after it), if any.
    pub fn time_limit(&self) -> Option<std::time::Duration> {
        self.trainer().params().time_limit
    }

    /// With a time limit: the wall time from the start of the run at which training stops so
    /// that the steps after it fit (`Trainer::training_limit`).
    pub fn training_limit(&self) -> Option<std::time::Duration> {
        self.trainer().training_limit()
    }

    /// The run's time limit and its training limit, when it has a limit.
    pub fn limits(&self) -> Option<(std::time::Duration, std::time::Duration)> {
        self.time_limit().zip(self.training_limit())
    }

    /// Signals after which the network holds its nodes: λ × the node target (one insertion
    /// every λ signals from a pair of nodes per part), at most the budget.
    pub fn growth_signals(&self) -> u64 {
        let lambda = self.trainer().stats().lambda.max(1);
        (lambda.saturating_mul(self.trainer().node_target() as u64)).min(self.max_signals())
    }

    /// Nodes the network holds now, and the nodes it aims for.
    pub fn nodes(&self) -> (usize, usize) {
        (self.trainer().node_count(), self.trainer().node_target())
    }

    /// Whether the network holds the nodes it aims for (growth is over).
    pub fn holds_target(&self) -> bool {
        self.trainer().node_count() >= self.trainer().node_target()
    }

    /// Leave a pause of `idle` out of the run's clock (`Trainer::discount`): the time limit
    /// counts the time the run was going, not the time the user had it paused.
    pub fn discount(&mut self, idle: std::time::Duration) {
        self.run.trainer_mut().discount(idle);
    }

    /// End training now (`Trainer::cancel_token`): the network stays as it is and
    /// [`Engine::reconstruct`] runs the finished network's pipeline on it.
    pub fn stop(&mut self) {
        self.trainer().cancel_token().cancel();
        // The trainer notices the cancel at the top of its next step.
        self.step(1);
    }

    /// Wall time since the run started ([`Engine::new`]).
    pub fn run_elapsed(&self) -> std::time::Duration {
        self.trainer().run_elapsed()
    }

    /// Build a triangle mesh from the current network. The finished network gets the job's
    /// run after training ([`job::GngRun::finish`], the CLI's: decimated to the output count
    /// when the network is oversampled, the attributes taken from the original's surface) and
    /// with it the job's [`job::Outcome`] (the model `gng3d simplify` saves, its summary and
    /// warnings); `on_step` sees each step of that pipeline as it finishes.
    /// While training runs, a checkpoint's preview (`Trainer::preview`) skips the detail rounds:
    /// each costs about one more reconstruction, and with three of them the default watched run
    /// of gargoyle-10k at 25 % (12 s asked) was at 68 % of its signals after 20 s; `on_step` is
    /// not called for it, and it has no warnings (a network still growing is short of the
    /// target by design) and no attributes.
    ///
    /// The finished network's reconstruction is built once: later calls return it again
    /// without running the pipeline ([`Engine::has_final`]).
    pub fn reconstruct(&mut self, on_step: impl FnMut(&StepRecord)) -> Result<Reconstruction> {
        if let Some(done) = &self.finished {
            return Ok(done.clone());
        }
        let gng = |e: &dyn std::fmt::Display| ViewerError::Gng(e.to_string());
        if !self.is_finished() {
            let preview = self.trainer().preview().map_err(|e| gng(&e))?;
            return Ok(Reconstruction {
                mesh: Arc::new(preview.mesh),
                outcome: None,
                cut_for_time: cut_for_time(&preview.report.warnings),
            });
        }
        let outcome = self.run.finish(None, on_step).map_err(|e| gng(&e))?;
        let cut = match &outcome.summary {
            job::Summary::Gng(s) => cut_for_time(&s.warnings),
            _ => false,
        };
        let done = Reconstruction {
            mesh: Arc::new(outcome.model.mesh.clone()),
            outcome: Some(Arc::new(outcome)),
            cut_for_time: cut,
        };
        self.finished = Some(done.clone());
        Ok(done)
    }

    /// Whether the finished network's reconstruction is built (the next
    /// [`Engine::reconstruct`] returns it without running the pipeline).
    pub fn has_final(&self) -> bool {
        self.finished.is_some()
    }
}

/// Whether `warnings` say the time limit cut anything (steps, oversampling, training before
/// the target), or is below the run's minimum.
fn cut_for_time(warnings: &[gng3d_core::GngWarning]) -> bool {
    warnings.iter().any(|w| {
        matches!(
            w,
            gng3d_core::GngWarning::StepSkippedForTime { .. }
                | gng3d_core::GngWarning::OversamplingSkippedForTime { .. }
                | gng3d_core::GngWarning::TimeLimitBelowMinimum { .. }
                | gng3d_core::GngWarning::TimeLimitBeforeTarget { .. }
        )
    })
}

/// What [`Engine::reconstruct`] built.
#[derive(Debug, Clone)]
pub struct Reconstruction {
    /// The mesh.
    pub mesh: Arc<TriMesh>,
    /// The finished network's outcome: the output model (attributes, materials, origin), the
    /// summary and the warnings, as `gng3d simplify` has them (`None` for a preview).
    pub outcome: Option<Arc<job::Outcome>>,
    /// Whether the time limit cut anything (steps, oversampling, training before the target),
    /// or is below the run's minimum.
    pub cut_for_time: bool,
}

/// QEM simplification of `model` to `target_vertices` vertices: the job every front end runs
/// (`job::run` with QEM to a vertex count, attributes kept through the contractions), so the
/// viewer's QEM is `gng3d simplify --method qem`'s; the outcome's warnings hold the CLI's note
/// when it stopped above the target ([`qem::QemReport::shortfall`]: holes, small pieces).
pub fn qem_simplify(model: &mesh::Model, target_vertices: usize) -> Result<job::Outcome> {
    let request =
        job::Request::new(job::Target::Vertices(target_vertices)).with_method(job::Method::Qem);
    job::run(model, &request, &mut ()).map_err(|e| ViewerError::Qem(e.to_string()))
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

/// A GNG3D reconstruction evaluated: [`evaluate_with_attributes`] with the `attributes` the
/// run gave it (the finished network's, from [`job::GngRun::finish`]); a checkpoint's preview
/// has none, and takes them from the original surface here ([`mesh::transfer::transfer_attributes`],
/// as the finish does), once.
pub fn evaluate_reconstruction(
    original: &TriMesh,
    original_attributes: Option<&Attributes>,
    reconstruction: &TriMesh,
    attributes: Option<&Attributes>,
) -> Result<Evaluation> {
    let transferred = match (attributes, original_attributes) {
        (None, Some(a)) => Some(mesh::transfer::transfer_attributes(
            original,
            a,
            reconstruction,
        )),
        _ => None,
    };
    evaluate_with_attributes(
        original,
        original_attributes,
        reconstruction,
        attributes.or(transferred.as_ref()),
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
    /// The model's materials and origin, without its mesh and attributes: the place the
    /// outputs are saved in ([`mesh::Model::with_mesh`]), as `gng3d simplify` saves them.
    pub place: mesh::Model,
    /// The base-colour texture of its materials, decoded, when it has texture coordinates to
    /// map it by (see `base_color`).
    pub texture: Option<metrics::Texture>,
}

/// The decoded base-colour texture of `place`'s materials when `attributes` have UV0
/// ([`metrics::Texture::load`], the CLI's loader of `--image-error`); one that cannot be read
/// or decoded is a note in `warnings`, and the model is shown without it.
fn base_color(
    place: &mesh::Model,
    attributes: Option<&Attributes>,
    warnings: &mut Vec<String>,
) -> Option<metrics::Texture> {
    attributes?.uv0.as_ref()?;
    let found = mesh::io::base_color_texture(place.materials.as_ref()?)?;
    metrics::Texture::load(&found)
        .map_err(|e| {
            warnings.push(format!(
                "the texture of material {}: {e}; shown without it",
                found.material
            ))
        })
        .ok()
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
        // The viewer keeps one f32 mesh: a far model is shown recentred, said here.
        warnings.push(format!(
            "the model lies far from its coordinates' origin: shown moved by ({}, {}, {}) \
             (saved in its own coordinates, as gng3d simplify saves it)",
            -o.x, -o.y, -o.z
        ));
    }
    let mut place = loaded.model;
    let mesh = std::mem::take(&mut place.mesh);
    let attributes = place.attributes.take();
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
    let texture = base_color(&place, attributes.as_ref(), &mut warnings);
    Ok(Loaded {
        mesh,
        warnings,
        attributes,
        place,
        texture,
    })
}

/// Save `model` with the job's checked writer ([`job::save`], `gng3d simplify`'s: the same
/// bytes for the same model); the format follows the extension.
pub fn save_model(model: &mesh::Model, path: &Path) -> Result<()> {
    job::save(model, path)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The viewer's GNG3D run, stepped in uneven batches as the live view steps it, saves the
    /// bytes `gng3d simplify --method gng --vertices N` writes for the same file: one options
    /// resolution, one finish, the attributes transferred once (by the job's finish).
    #[test]
    fn a_stepped_run_saves_the_clis_bytes() {
        let input =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/knight_colors.ply");
        let loaded = load_mesh(&input).unwrap();
        assert!(loaded.attributes.is_some());
        let options = crate::ViewerOptions {
            target: Some(120),
            ..Default::default()
        };
        let params = crate::session::train_params(&options).unwrap();
        let model = mesh::Model {
            mesh: loaded.mesh,
            attributes: loaded.attributes,
            ..loaded.place
        };
        let mut engine = Engine::new(&model, &params).unwrap();
        let mut n = 1;
        while !engine.is_finished() {
            engine.step(n);
            n = n * 7 % 10_007 + 1;
        }
        let outcome = engine.reconstruct(|_| {}).unwrap().outcome.unwrap();
        let dir = std::env::temp_dir().join(format!("viewer-engine-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (viewer, cli) = (dir.join("viewer.ply"), dir.join("cli.ply"));
        save_model(&outcome.model, &viewer).unwrap();
        job::simplify_file(&input, &cli, &request(&params), |_| {}, &mut ()).unwrap();
        assert_eq!(
            std::fs::read(&viewer).unwrap(),
            std::fs::read(&cli).unwrap()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

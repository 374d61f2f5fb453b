//! GNG3D mesh simplification (Álvarez, Noguera, Tortosa, Zamora 2007): a Growing Neural Gas is
//! trained on signals drawn from the original mesh (phase 1, [`Trainer`]), then the simplified
//! faces are rebuilt by labelling every original vertex with its nearest node (phase 2, the
//! [`Plan`] of [`Step`]s that [`finish`] runs).
//!
//! Training is fast in the manner of Fišer, Faigl and Kulich 2013: nearest and second-nearest
//! nodes come from a uniform grid that grows with the network, errors decay lazily through a
//! global scale factor, edge ages are derived from win counters, and nodes live in flat arrays
//! with a free list and inline adjacency, so a signal costs no allocation and no O(|A|) work.
//!
//! # One call
//!
//! [`simplify`] does both phases with the options the `gng3d` CLI has (GNG3D-Q: quadric
//! placement, an oversampled network decimated by QEM to exactly the vertex count asked for):
//!
//! ```
//! use gng3d_core::{GngOptions, GngTarget, simplify};
//! let sphere = mesh::procedural::icosphere(3); // 642 vertices
//! let options = GngOptions { seed: 7, ..GngOptions::for_target(GngTarget::Vertices(200)) };
//! let result = simplify(&sphere.into(), &options).unwrap();
//! assert_eq!(result.mesh.vertex_count(), 200); // exactly the count asked for
//! assert!(result.report.warnings.is_empty());
//! for step in &result.report.steps {
//!     println!("{:<18} {:>8.4} s  {} {}", step.step, step.seconds, step.changed, step.step.changes());
//! }
//! ```
//!
//! # Options and parameters
//!
//! Two structs describe a run, one for people and one for the algorithm:
//!
//! - [`GngOptions`] is what a front end exposes (the `gng3d` CLI's `simplify`, `compare` and
//!   `reproduce`, the viewer, headless runs), in user units: a [`GngTarget`] (a vertex count or
//!   a share of the input's vertices), seconds as `f64`, a seed, a budget, the oversampling
//!   factor. Every field left at `None` takes the library's default when the options are
//!   resolved.
//! - [`GngParams`] is every knob of the algorithm ([`Trainer::new`] takes it): the paper's
//!   λ, ε_b, ε_n, α, d, a_max and μ, the signal budget, the [`SignalSource`], the nearest-node
//!   search, the reconstruction's options ([`ReconstructionParams`], with the [`Placement`] of
//!   the output vertices) and the oversampled network's size.
//!
//! [`GngOptions::resolve`] is the one place that turns options into parameters, against the
//! input mesh (ratios and epochs are shares of its vertices): it validates every option up
//! front (NaN, negative or zero time limits, ratios outside (0, 1], zero λ, zero budgets,
//! out-of-range targets) and returns one [`GngError::Parameter`] naming the offending one
//! ([`GngParameter`]) before any training starts, then applies the rules that depend on the
//! input: the oversampling (1.5× the output's vertices for GNG3D-Q, decimated back by QEM), the
//! detail rounds (outputs of at least 5 % of the input's vertices), the relaxation (outputs of
//! at most 30 %) and the training of large pieces as two halves (pieces of at least 512 nodes).
//! Fields that [`GngOptions`] does not expose keep the [`GngParams`] defaults.
//!
//! ```
//! use gng3d_core::{GngError, GngOptions, GngParameter, GngTarget, Placement};
//! let sphere = mesh::procedural::icosphere(3); // 642 vertices
//! let options = GngOptions {
//!     target: GngTarget::VertexRatio(0.25), // a quarter of the input's vertices
//!     time_limit_seconds: Some(2.0),
//!     ..GngOptions::default()
//! };
//! let params = options.resolve(&sphere).unwrap();
//! assert_eq!(params.target_vertices, 161);
//! assert_eq!(params.network_vertices, Some(242)); // GNG3D-Q: trained 1.5x, decimated to 161
//! assert_eq!(params.reconstruction.placement, Placement::Quadric);
//!
//! // The published method: node placement, 30 epochs, no oversampling.
//! let paper = GngOptions::paper(GngTarget::Vertices(161)).resolve(&sphere).unwrap();
//! assert_eq!((paper.network_vertices, paper.max_signals), (None, Some(30 * 642)));
//! assert_eq!(paper.reconstruction.placement, Placement::Node);
//!
//! let bad = GngOptions { time_limit_seconds: Some(-1.0), ..GngOptions::default() };
//! let err = bad.resolve(&sphere).unwrap_err();
//! assert!(matches!(err, GngError::Parameter { parameter: GngParameter::TimeLimit, .. }));
//! assert!(err.to_string().contains("time limit"));
//! ```
//!
//! [`GngParams::paper`] and [`GngOptions::paper`] give the published GNG3D (its budget and its
//! reconstruction, [`ReconstructionParams::paper`]); the defaults of both structs are GNG3D-Q.
//!
//! # Step by step
//!
//! A viewer that draws the network while it learns drives the [`Trainer`] itself, then calls
//! [`finish`] for what [`simplify`] gives:
//!
//! ```
//! use gng3d_core::{GngParams, Trainer};
//! use std::ops::ControlFlow;
//! let torus = mesh::procedural::torus(1.0, 0.3, 48, 24);
//! let mut trainer = Trainer::new(&torus.into(), GngParams::for_target(300)).unwrap();
//! trainer.step(5_000);
//! let snap = trainer.snapshot(); // compact positions + edges
//! assert_eq!(snap.positions.len(), trainer.node_count());
//! let cancel = trainer.cancel_token(); // Clone + Send: stop from another thread
//! trainer.train(10_000, |p| {
//!     if p.signals > 1_000_000 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
//! });
//! assert!(trainer.is_finished() && !cancel.is_cancelled());
//! let result = gng3d_core::finish(&trainer, |step| println!("{} done", step.step)).unwrap();
//! assert_eq!(result.mesh.vertex_count(), 300);
//! ```
//!
//! # Threads
//!
//! A run uses at most [`GngOptions::threads`] threads, the caller's included (training rounds
//! of the pieces, the steps after training, a helper that builds the original's tables while
//! training runs): by default the machine's available parallelism, at most 4; `Some(1)` starts
//! none. The output is the same for any count. The QEM decimation of GNG3D-Q runs in rayon's
//! global pool (set it with `RAYON_NUM_THREADS`, or call [`simplify`] inside
//! `rayon::ThreadPool::install`).
//!
//! # Features
//!
//! - `serde` (default): `Serialize`/`Deserialize` for the options, the parameters and the
//!   snapshots, `Serialize` for the reports.
//!
//! glam, whose `Vec3` is in the API, is re-exported as [`glam`].

mod clock;
mod domain;
mod error;
mod finish;
mod options;
mod parallel;
mod params;
mod pipeline;
mod reconstruct;
mod report;
mod run;
mod surface;
mod train;
mod trainer;
#[doc(hidden)]
pub mod tuning;

pub use error::{GngError, GngParameter};
pub use glam;
/// The workspace's cancel flag ([`finish_cancellable`]; also [`CancelToken`], training's).
pub use mesh::cancel::Cancel;
pub use options::{GngOptions, GngTarget};
pub use params::{
    GngParams, OppositeFaces, Placement, ReconstructionParams, SearchStrategy, Shape, SignalSource,
};
pub use pipeline::{Plan, PlannedStep, Step, StepRecord};
pub use reconstruct::{Reconstruction, ReconstructionReport};
pub use report::{GngReport, GngSummary, GngWarning};
pub use train::{CancelToken, Progress, Snapshot, StopReason, TrainingStats};
pub use trainer::{Trainer, training_round};

use glam::Vec3;
use mesh::TriMesh;
use std::ops::ControlFlow;

/// Output of [`simplify`] and [`finish`].
#[derive(Debug, Clone)]
pub struct GngResult {
    /// The simplified mesh (original orientation).
    pub mesh: TriMesh,
    /// The output's attributes, taken from the original's surface at its corners
    /// (`mesh::transfer::transfer_attributes`), when the trainer's model has attributes
    /// ([`finish`] and [`finish_cancellable`]; a [`Trainer::preview`] has none).
    pub attributes: Option<mesh::attributes::Attributes>,
    /// All trained node positions.
    pub nodes: Vec<Vec3>,
    /// What happened in both phases, including why the vertex count differs from the target
    /// when it does.
    pub report: GngReport,
}

/// Simplify `model` with GNG3D to the options' vertex count: resolve the options
/// ([`GngOptions::resolve`]), train in the rounds every front end uses
/// ([`Trainer::train_to_end`]), then run the pipeline after training ([`finish`]). With default
/// options this is `gng3d simplify --method gng`: the same mesh for the same seed.
///
/// With attributes (normals, texture coordinates, colours, materials; they must fit the mesh)
/// the output's triangles follow their seams and its corners take the original's values at
/// their place, on their side of the seams ([`GngResult::attributes`]; see [`Trainer::new`]).
///
/// The input should be welded (e.g. `mesh::clean::prepare`); signals use distinct vertex
/// positions either way. On a closed manifold input that can hold N vertices the output has
/// exactly N; otherwise [`GngReport::warnings`] says why not. Errors are returned for unusable
/// input or options and for results with no mesh (fewer than three nodes, no triangle), never
/// panics.
pub fn simplify(model: &mesh::Model, options: &GngOptions) -> Result<GngResult, GngError> {
    let mut trainer = Trainer::new(model, options.resolve(&model.mesh)?)?;
    trainer.train_to_end(|_| ControlFlow::Continue(()));
    finish(&trainer, |_| {})
}

/// The run after training, on a trained (or stopped) `trainer`: the steps of its
/// [`Trainer::plan`] (see [`Step`]), the checks and the warnings, and the output's attributes
/// when the trainer's model has some ([`GngResult::attributes`]). `on_step` sees each step as it
/// finishes (a front end's progress). Front ends that drive the trainer themselves (progress
/// bars, viewers) call this to get what [`simplify`] gives.
///
/// When the output holds the requested count, warnings about the *network's* count (capacity,
/// time limit, unattached nodes) are dropped: the user's target was met. A closed input that
/// gives an open output says so ([`GngWarning::OpenedHoles`]).
pub fn finish(trainer: &Trainer, on_step: impl FnMut(&StepRecord)) -> Result<GngResult, GngError> {
    let snap = trainer.snapshot();
    trainer.run_plan(&snap, trainer.plan(), None, on_step)
}

/// [`finish`] that another thread can stop: when `cancel` is set the run ends at its next check
/// (before each step, in the decimation's QEM passes) with [`GngError::Cancelled`], never a
/// partial mesh. The trainer's own [`Trainer::cancel_token`] stops training, not this: a
/// trainer stopped early still gives its mesh. Not cancelled, the result is [`finish`]'s.
pub fn finish_cancellable(
    trainer: &Trainer,
    cancel: &Cancel,
    on_step: impl FnMut(&StepRecord),
) -> Result<GngResult, GngError> {
    let snap = trainer.snapshot();
    trainer.run_plan(&snap, trainer.plan(), Some(cancel), on_step)
}

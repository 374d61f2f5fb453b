//! GNG3D mesh simplification (Álvarez, Noguera, Tortosa, Zamora 2007): a Growing Neural Gas is
//! trained on signals drawn from the original mesh (phase 1, [`Trainer`]), then the simplified
//! faces are rebuilt by labelling every original vertex with its nearest node (phase 2,
//! [`reconstruct`]).
//!
//! Training is fast in the manner of Fišer, Faigl and Kulich 2013: nearest and second-nearest
//! nodes come from a uniform grid that grows with the network, errors decay lazily through a
//! global scale factor, edge ages are derived from win counters, and nodes live in flat arrays
//! with a free list and inline adjacency, so a signal costs no allocation and no O(|A|) work.
//!
//! One call does both phases with the options the `gng3d` CLI has (GNG3D-Q: quadric placement,
//! an oversampled network decimated by QEM to exactly the vertex count asked for):
//!
//! ```
//! use gng3d_core::{GngOptions, GngTarget, simplify};
//! let sphere = mesh::procedural::icosphere(3); // 642 vertices
//! let options = GngOptions { seed: 7, ..GngOptions::for_target(GngTarget::Vertices(200)) };
//! let result = simplify(&sphere, &options).unwrap();
//! assert_eq!(result.mesh.vertex_count(), 200); // exactly the count asked for
//! assert!(result.report.warnings.is_empty());
//! for step in &result.report.steps {
//!     println!("{:<18} {:>8.4} s  {} {}", step.step, step.seconds, step.changed, step.step.changes());
//! }
//! ```
//!
//! Step-wise use, e.g. for a viewer that draws the network while it learns:
//!
//! ```
//! use gng3d_core::{GngParams, Trainer};
//! use std::ops::ControlFlow;
//! let torus = mesh::procedural::torus(1.0, 0.3, 48, 24);
//! let mut trainer = Trainer::new(&torus, GngParams::for_target(300)).unwrap();
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

pub mod decimate;
pub mod deviation;
mod domain;
mod error;
mod fan_search;
pub mod features;
pub mod flip;
mod grid;
mod network;
mod options;
mod parallel;
mod params;
pub mod pipeline;
pub mod placement;
mod reconstruct;
pub mod refit;
pub mod relax;
mod report;
mod trainer;

pub use domain::{MIN_COMPONENT_NODES, SPLIT_MIN_NODES, STRAY_RADII};
pub use error::GngError;
pub use options::{
    DEFAULT_DETAIL_ROUNDS, DEFAULT_OVERSAMPLE, DETAIL_MIN_RATIO, GngOptions, GngTarget,
    MAX_DETAIL_ROUNDS, MAX_SIGNALS, MAX_SURFACE_NODES_PER_VERTEX, RELAX_MAX_RATIO,
};
pub use params::{
    DEFAULT_SIGNALS_PER_NODE, GngParams, OppositeFaces, PAPER_EPOCHS, Placement,
    ReconstructionParams, SearchStrategy, SignalSource,
};
pub use pipeline::{Plan, Step, StepRecord};
pub use reconstruct::{
    Reconstruction, ReconstructionReport, label_vertices, label_vertices_by_component, reconstruct,
};
pub use report::{GngReport, GngWarning};
pub use trainer::{
    CancelToken, GROWTH_SHARE_OF_TIME_LIMIT, Progress, Snapshot, StopReason, Trainer, TrainingStats,
};

use glam::Vec3;
use mesh::TriMesh;

/// Output of [`simplify`] and [`finish`].
#[derive(Debug, Clone)]
pub struct GngResult {
    /// The simplified mesh (original orientation).
    pub mesh: TriMesh,
    /// All trained node positions.
    pub nodes: Vec<Vec3>,
    /// What happened in both phases, including why the vertex count differs from the target
    /// when it does.
    pub report: GngReport,
}

/// Simplify `mesh` with GNG3D to the options' vertex count: resolve the options
/// ([`GngOptions::resolve`]), train ([`Trainer`]), then run the pipeline after training
/// ([`finish`]). With default options this is `gng3d simplify --method gng`: the same mesh
/// for the same seed.
///
/// The input should be welded (e.g. `mesh::clean::prepare`); signals use distinct vertex
/// positions either way. On a closed manifold input that can hold N vertices the output has
/// exactly N; otherwise [`GngReport::warnings`] says why not. Errors are returned for unusable
/// input or options and for results with no mesh (fewer than three nodes, no triangle), never
/// panics.
pub fn simplify(mesh: &TriMesh, options: &GngOptions) -> Result<GngResult, GngError> {
    let mut trainer = Trainer::new(mesh, options.resolve(mesh)?)?;
    while !trainer.is_finished() {
        trainer.step(u64::MAX);
    }
    finish(&trainer, |_| {})
}

/// The run after training, on a trained (or stopped) `trainer`: the steps of its
/// [`Trainer::plan`] ([`pipeline`]), the checks and the warnings. `on_step` sees each step as it
/// finishes (a front end's progress). Front ends that drive the trainer themselves (progress
/// bars, viewers) call this to get what [`simplify`] gives.
///
/// When the output holds the requested count, warnings about the *network's* count (capacity,
/// time limit, unattached nodes) are dropped: the user's target was met. A closed input that
/// gives an open output says so ([`GngWarning::OpenedHoles`]).
pub fn finish(trainer: &Trainer, on_step: impl FnMut(&StepRecord)) -> Result<GngResult, GngError> {
    let snap = trainer.snapshot();
    trainer.run_plan(&snap, trainer.plan(), on_step)
}

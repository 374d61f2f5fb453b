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
//! One call does both phases:
//!
//! ```
//! use gng3d_core::{GngParams, simplify};
//! let sphere = mesh::procedural::icosphere(3); // 642 vertices
//! let mut params = GngParams::for_target(200);
//! params.seed = 7;
//! let result = simplify(&sphere, &params).unwrap();
//! assert_eq!(result.nodes.len(), 200);
//! assert_eq!(result.mesh.vertex_count(), 200); // every node is a vertex
//! assert!(result.report.warnings.is_empty());
//! assert!(result.mesh.face_count() > 300);
//! println!("{} signals in {:.3} s", result.report.training.signals, result.report.seconds);
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
//! let rec = trainer.reconstruct(&trainer.params().reconstruction.clone());
//! assert!(rec.mesh.face_count() > 0);
//! ```

pub mod deviation;
mod domain;
mod error;
pub mod features;
pub mod flip;
mod grid;
mod network;
mod options;
mod parallel;
mod params;
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
    MAX_DETAIL_ROUNDS, RELAX_MAX_RATIO,
};
pub use params::{
    DEFAULT_SIGNALS_PER_NODE, GngParams, OppositeFaces, PAPER_EPOCHS, Placement,
    ReconstructionParams, SearchStrategy, SignalSource,
};
pub use reconstruct::{
    Reconstruction, ReconstructionReport, label_vertices, label_vertices_by_component, reconstruct,
};
pub use report::{GngReport, GngWarning};
pub use trainer::{
    CancelToken, GROWTH_SHARE_OF_TIME_LIMIT, Progress, Snapshot, StopReason, Trainer, TrainingStats,
};

use glam::Vec3;
use mesh::TriMesh;
use std::time::Instant;

/// Output of [`simplify`].
#[derive(Debug, Clone)]
pub struct GngResult {
    /// The simplified mesh: one vertex per trained node (original orientation).
    pub mesh: TriMesh,
    /// All trained node positions.
    pub nodes: Vec<Vec3>,
    /// What happened in both phases, including why the vertex count differs from the target
    /// when it does.
    pub report: GngReport,
}

/// A decimator for oversampled runs ([`GngParams::decimate_to`]): brings a mesh down to
/// `target_vertices` vertices, error first, keeping its topology (the `gng3d` facade's
/// `qem_decimator` is Garland–Heckbert QEM). The error is a sentence for the user.
pub type Decimator<'a> = &'a dyn Fn(&TriMesh, usize) -> Result<TriMesh, String>;

/// Simplify `mesh` with GNG3D: train to `params.target_vertices` nodes, then reconstruct.
///
/// The input should be welded (e.g. `mesh::clean::prepare`); signals use distinct vertex
/// positions either way. On a closed manifold input that can hold N nodes the output has
/// exactly N vertices; otherwise [`GngReport::warnings`] says why not. Errors are returned for
/// unusable input or parameters and for results with no mesh (fewer than three nodes, no
/// triangle), never panics. Oversampled parameters ([`GngParams::decimate_to`]) need
/// [`simplify_with`].
pub fn simplify(mesh: &TriMesh, params: &GngParams) -> Result<GngResult, GngError> {
    simplify_with(mesh, params, None)
}

/// [`simplify`] with a decimator for oversampled parameters (GNG3D-Q's last step: the
/// network's mesh of `target_vertices` vertices is decimated to `decimate_to`).
pub fn simplify_with(
    mesh: &TriMesh,
    params: &GngParams,
    decimator: Option<Decimator<'_>>,
) -> Result<GngResult, GngError> {
    if params.decimate_to.is_some() && decimator.is_none() {
        return Err(GngError::NoDecimator);
    }
    let start = Instant::now();
    let mut trainer = Trainer::new(mesh, params.clone())?;
    while !trainer.is_finished() {
        trainer.step(u64::MAX);
    }
    finish_with(&trainer, start, decimator)
}

/// Phase 2 on a trained (or stopped) `trainer`, with the checks and warnings of [`simplify`];
/// `start` is when the run began (for [`GngReport::seconds`]). Front ends that drive the
/// trainer themselves (progress bars, viewers) call this to get the same result.
pub fn finish(trainer: &Trainer, start: Instant) -> Result<GngResult, GngError> {
    finish_with(trainer, start, None)
}

/// [`finish`] with a decimator for oversampled parameters ([`GngParams::decimate_to`]): the
/// network's mesh is decimated to that many vertices when it has more. When the output then
/// holds the requested count, warnings about the *network's* count (capacity, time limit,
/// unattached nodes) are dropped: the user's target was met.
pub fn finish_with(
    trainer: &Trainer,
    start: Instant,
    decimator: Option<Decimator<'_>>,
) -> Result<GngResult, GngError> {
    finish_with_reconstruction(trainer, start, decimator, &trainer.params().reconstruction)
}

/// [`finish_with`] with other phase-2 options than the trainer's, e.g. a viewer's quick
/// preview of a network still in training (no detail rounds). Options that add nodes
/// (`split_bad_cells`, `detail_rounds`) are for oversampled runs only.
pub fn finish_with_reconstruction(
    trainer: &Trainer,
    start: Instant,
    decimator: Option<Decimator<'_>>,
    reconstruction: &ReconstructionParams,
) -> Result<GngResult, GngError> {
    let stats = trainer.stats();
    let snap = trainer.snapshot();
    if snap.positions.len() < 3 {
        return Err(GngError::TooFewNodes {
            nodes: snap.positions.len(),
            stop: stats.stop,
        });
    }
    let params = trainer.params();
    let mut rec = trainer.reconstruct_snapshot(&snap, reconstruction);
    if rec.mesh.face_count() == 0 {
        return Err(GngError::EmptyMesh {
            nodes: snap.positions.len(),
        });
    }
    let mut warnings = trainer.warnings();
    if rec.report.unreferenced_nodes > 0 {
        warnings.push(GngWarning::UnattachedNodes {
            nodes: rec.report.unreferenced_nodes,
        });
    }
    let network_vertices = rec.mesh.vertex_count();
    let target_vertices = params.decimate_to.unwrap_or(params.target_vertices);
    if let Some(n) = params.decimate_to {
        let decimate = decimator.ok_or(GngError::NoDecimator)?;
        if network_vertices > n {
            rec.mesh = decimate(&rec.mesh, n).map_err(|reason| GngError::Decimation { reason })?;
            let TriMesh {
                positions,
                triangles,
            } = &mut rec.mesh;
            // (h) The decimation placed its vertices for the surface; relax them toward the
            // original vertices they stand for.
            if reconstruction.relax {
                let relaxed = relax::relax(positions, triangles, trainer.original());
                rec.report.relaxed_vertices = relaxed.moves;
            }
            // (i) Then bring back what stands farthest off the original.
            if reconstruction.repair_deviations {
                let repaired = deviation::repair(positions, triangles, trainer.original());
                rec.report.deviation_moves = repaired.moves;
                rec.report.deviation_flips = repaired.flips;
            }
            rec.report.topology = mesh::topology::analyze(&rec.mesh);
            if rec.mesh.vertex_count() > n {
                warnings.push(GngWarning::DecimationStopped {
                    vertices: rec.mesh.vertex_count(),
                    target: n,
                });
            }
        }
        if rec.mesh.vertex_count() == n {
            warnings.retain(|w| {
                !matches!(
                    w,
                    GngWarning::TargetAboveCapacity { .. }
                        | GngWarning::TimeLimitBeforeTarget { .. }
                        | GngWarning::UnattachedNodes { .. }
                )
            });
        }
    }
    let report = GngReport {
        training: stats,
        target_vertices,
        network_vertices,
        vertices: rec.mesh.vertex_count(),
        faces: rec.mesh.face_count(),
        reconstruction: rec.report,
        seconds: start.elapsed().as_secs_f64(),
        warnings,
    };
    Ok(GngResult {
        mesh: rec.mesh,
        nodes: snap.positions,
        report,
    })
}

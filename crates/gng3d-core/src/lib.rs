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
//! assert!(result.mesh.vertex_count() <= 200);
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

mod error;
pub mod features;
pub mod flip;
mod grid;
mod network;
mod params;
pub mod placement;
mod reconstruct;
mod trainer;

pub use error::GngError;
pub use params::{
    GngParams, OppositeFaces, Placement, ReconstructionParams, SearchStrategy, SignalSource,
};
pub use reconstruct::{Reconstruction, ReconstructionReport, label_vertices, reconstruct};
pub use trainer::{CancelToken, Progress, Snapshot, StopReason, Trainer, TrainingStats};

use glam::Vec3;
use mesh::TriMesh;
use serde::Serialize;
use std::time::Instant;

/// Output of [`simplify`].
#[derive(Debug, Clone)]
pub struct GngResult {
    /// The simplified mesh (referenced nodes only, original orientation).
    pub mesh: TriMesh,
    /// All trained node positions, including nodes the reconstruction left unreferenced.
    pub nodes: Vec<Vec3>,
    /// What happened in both phases.
    pub report: GngReport,
}

/// Report of a [`simplify`] run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GngReport {
    /// Phase-1 counters.
    pub training: TrainingStats,
    /// Phase-2 counts and output topology.
    pub reconstruction: ReconstructionReport,
    /// Output vertex count.
    pub vertices: usize,
    /// Output face count.
    pub faces: usize,
    /// Wall time of both phases, seconds.
    pub seconds: f64,
}

/// Simplify `mesh` with GNG3D: train to `params.target_vertices` nodes, then reconstruct.
///
/// The input should be welded (e.g. `mesh::clean::prepare`); signals use distinct vertex
/// positions either way. Errors are returned for unusable input or parameters, never panics.
pub fn simplify(mesh: &TriMesh, params: &GngParams) -> Result<GngResult, GngError> {
    let start = Instant::now();
    let mut trainer = Trainer::new(mesh, params.clone())?;
    while !trainer.is_finished() {
        trainer.step(u64::MAX);
    }
    let snap = trainer.snapshot();
    let rec = reconstruct(mesh, &snap.positions, &snap.edges, &params.reconstruction);
    let report = GngReport {
        training: trainer.stats(),
        vertices: rec.mesh.vertex_count(),
        faces: rec.mesh.face_count(),
        reconstruction: rec.report,
        seconds: start.elapsed().as_secs_f64(),
    };
    Ok(GngResult {
        mesh: rec.mesh,
        nodes: snap.positions,
        report,
    })
}

//! What the passes made of one prepared mesh ([`Run`]) and the report made of it ([`report`]).

use crate::{QemReport, StopReason};
use mesh::TriMesh;
use std::time::Instant;

/// The report of `run` on an input of `input_vertices` referenced vertices and `input_faces`
/// usable faces, started at `started`.
pub(super) fn report(
    run: &Run,
    input_vertices: usize,
    input_faces: usize,
    started: Instant,
) -> QemReport {
    QemReport {
        input_vertices,
        input_faces,
        collapses: run.collapses,
        vertices: run.mesh.positions.len(),
        faces: run.mesh.triangles.len(),
        max_error: run.max_error,
        seconds: started.elapsed().as_secs_f64(),
        target_reached: run.stop_reason == StopReason::TargetReached,
        stop_reason: run.stop_reason,
        rejected: run.rejected,
        virtual_pairs: run.virtual_pairs,
        passes: run.passes,
        max_relative_error: run.max_relative_error,
        fixed_seam_vertices: run.fixed_seam_vertices,
    }
}

/// What the passes made of one prepared mesh.
pub(super) struct Run {
    /// The simplified mesh, model units.
    pub(super) mesh: TriMesh,
    /// Contractions performed.
    pub(super) collapses: usize,
    /// Contractions rejected by the topology / normal checks.
    pub(super) rejected: usize,
    /// Largest cost of a performed contraction, model units⁴.
    pub(super) max_error: f64,
    /// Contraction passes.
    pub(super) passes: usize,
    /// Why the loop ended.
    pub(super) stop_reason: StopReason,
    /// Non-edge pairs found.
    pub(super) virtual_pairs: usize,
    /// With `max_relative_error`: the largest relative error of a performed contraction.
    pub(super) max_relative_error: Option<f64>,
    /// Output vertices that are fixed seam vertices (attribute runs; 0 otherwise).
    pub(super) fixed_seam_vertices: usize,
}

impl Run {
    /// `mesh` as it is (nothing was left to do).
    pub(super) fn unchanged(mesh: TriMesh) -> Run {
        Run {
            mesh,
            collapses: 0,
            rejected: 0,
            max_error: 0.0,
            passes: 0,
            stop_reason: StopReason::NoValidPairs,
            virtual_pairs: 0,
            max_relative_error: None,
            fixed_seam_vertices: 0,
        }
    }
}

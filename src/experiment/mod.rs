//! The paper's experiment as a library: [`compare`] runs QEM and GNG3D to the same vertex
//! count and measures both; [`reproduce`] follows the paper's checkpoint protocol.

pub mod compare;
pub mod reproduce;
pub mod survey;

use mesh::TriMesh;
use metrics::{Hausdorff, HausdorffParams, SurfaceDistanceIndex};
use serde::{Deserialize, Serialize};

/// Why an experiment could not run.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// QEM failed.
    #[error("QEM: {0}")]
    Qem(#[from] qem::QemError),
    /// GNG3D failed.
    #[error("GNG3D: {0}")]
    Gng(#[from] gng3d_core::GngError),
    /// A metric could not be computed.
    #[error("metrics: {0}")]
    Metrics(#[from] metrics::MetricsError),
    /// The requested target does not fit the mesh.
    #[error("{0}")]
    BadTarget(String),
}

/// The errors the paper reports plus the symmetric surface distance, for one simplified mesh.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PaperRow {
    /// Vertices of the simplified mesh.
    pub vertices: usize,
    /// Faces of the simplified mesh.
    pub faces: usize,
    /// Mean squared distance from original vertices to the nearest simplified vertex.
    pub e_avg: f64,
    /// Max squared distance from original vertices to the nearest simplified vertex.
    pub e_max: f64,
    /// Original area minus simplified area (signed, squared model units).
    pub e_sur: f64,
    /// Symmetric Hausdorff distance (model units).
    pub hausdorff_max: f64,
    /// Mean surface distance over both directions (model units).
    pub hausdorff_mean: f64,
    /// RMS surface distance over both directions (model units).
    pub hausdorff_rms: f64,
}

/// A reusable evaluator of [`PaperRow`]s against one original mesh (its BVH is built once).
pub struct PaperEvaluator<'a> {
    original: &'a TriMesh,
    index: SurfaceDistanceIndex,
    hausdorff: HausdorffParams,
}

impl<'a> PaperEvaluator<'a> {
    /// Index `original`; `hausdorff` sets the surface sampling of every evaluation.
    pub fn new(
        original: &'a TriMesh,
        hausdorff: HausdorffParams,
    ) -> Result<PaperEvaluator<'a>, ExperimentError> {
        Ok(PaperEvaluator {
            original,
            index: SurfaceDistanceIndex::new(original)?,
            hausdorff,
        })
    }

    /// Paper errors and symmetric surface distance of `simplified`.
    pub fn evaluate(&self, simplified: &TriMesh) -> Result<PaperRow, ExperimentError> {
        let vertex = metrics::vertex_errors(&self.original.positions, &simplified.positions)
            .ok_or_else(|| ExperimentError::BadTarget("simplified mesh has no vertices".into()))?;
        let surface = metrics::surface_error(self.original, simplified);
        let h: Hausdorff = if simplified.face_count() == 0 {
            return Err(ExperimentError::Metrics(
                metrics::MetricsError::NoTriangles { mesh: "simplified" },
            ));
        } else {
            let simplified_index = SurfaceDistanceIndex::new(simplified)?;
            metrics::hausdorff_indexed(
                self.original,
                &self.index,
                simplified,
                &simplified_index,
                &self.hausdorff,
            )?
        };
        Ok(PaperRow {
            vertices: simplified.vertex_count(),
            faces: simplified.face_count(),
            e_avg: vertex.e_avg,
            e_max: vertex.e_max,
            e_sur: surface.e_sur,
            hausdorff_max: h.max,
            hausdorff_mean: h.mean,
            hausdorff_rms: h.rms,
        })
    }
}

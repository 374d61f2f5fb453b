//! The paper's experiment as a library: [`compare`] runs QEM and GNG3D to the same vertex
//! count and measures both; [`reproduce`] follows the paper's checkpoint protocol.

pub mod compare;
pub mod reproduce;
pub mod survey;

use mesh::TriMesh;
use mesh::attributes::Attributes;
use metrics::{Evaluator, HausdorffParams, MetricsParams};
use serde::{Deserialize, Serialize};

/// Why an experiment could not run.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    // The wrapped errors are sources (printed after the prefix by `{:#}` / error chains), so the
    // messages do not repeat them.
    /// QEM failed.
    #[error("QEM")]
    Qem(#[from] qem::QemError),
    /// GNG3D failed.
    #[error("GNG3D")]
    Gng(#[from] gng3d_core::GngError),
    /// A metric could not be computed.
    #[error("metrics")]
    Metrics(#[from] metrics::MetricsError),
    /// A method returned a mesh without triangles (never measured or written).
    #[error("{method} produced an empty mesh ({vertices} vertices, no triangles)")]
    EmptyOutput {
        /// "GNG3D" or "QEM".
        method: &'static str,
        /// Vertices it returned.
        vertices: usize,
    },
    /// The requested target does not fit the mesh.
    #[error("{0}")]
    BadTarget(String),
}

/// The errors the paper reports plus the symmetric surface distance and triangle quality, for
/// one simplified mesh: a projection of [`metrics::Evaluation`] (the one evaluation record).
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
    /// Original area minus simplified area, **signed** (squared model units); tables rank by
    /// its absolute value.
    pub e_sur_signed: f64,
    /// Symmetric Hausdorff distance (model units).
    pub hausdorff_max: f64,
    /// Mean surface distance over both directions (model units; MeshLab's all-sample mean).
    pub hausdorff_mean: f64,
    /// RMS surface distance over both directions (model units).
    pub hausdorff_rms: f64,
    /// Area-weighted mean surface distance, averaged over both directions (model units): the
    /// headline mean, `(1/A)∫d dA`, independent of how many samples went to vertices and edges.
    pub hausdorff_area_mean: f64,
    /// Median over triangles of the smallest interior angle, degrees (60 = equilateral).
    pub median_min_angle_degrees: f64,
    /// Share of triangles whose smallest angle is below 20°.
    pub below_20_degrees: f64,
}

impl PaperRow {
    /// The row's columns taken from a full evaluation.
    pub fn from_evaluation(e: &metrics::Evaluation) -> PaperRow {
        let h = &e.hausdorff;
        PaperRow {
            vertices: e.meshes.simplified.referenced_vertices,
            faces: e.meshes.simplified.faces,
            e_avg: e.e_avg,
            e_max: e.e_max,
            e_sur_signed: e.e_sur_signed,
            hausdorff_max: h.max,
            hausdorff_mean: h.mean,
            hausdorff_rms: h.rms,
            hausdorff_area_mean: 0.5 * (h.forward.area_mean + h.backward.area_mean),
            median_min_angle_degrees: e.quality.simplified.median_min_angle_degrees,
            below_20_degrees: e.quality.simplified.below_20_degrees,
        }
    }
}

/// A reusable evaluator of [`PaperRow`]s against one original mesh: a [`metrics::Evaluator`]
/// (the original is indexed once).
pub struct PaperEvaluator {
    evaluator: Evaluator,
}

impl PaperEvaluator {
    /// Index `original`; `hausdorff` sets the surface sampling of every evaluation.
    pub fn new(
        original: &TriMesh,
        hausdorff: HausdorffParams,
    ) -> Result<PaperEvaluator, ExperimentError> {
        Ok(PaperEvaluator {
            evaluator: Evaluator::new(original, &MetricsParams { hausdorff })?,
        })
    }

    /// Paper errors, symmetric surface distance and triangle quality of `simplified`.
    pub fn evaluate(&self, simplified: &TriMesh) -> Result<PaperRow, ExperimentError> {
        Ok(PaperRow::from_evaluation(
            &self.evaluator.evaluate(simplified)?,
        ))
    }
}

/// QEM as `gng3d simplify --method qem` runs it: keeping `attributes` through its contractions
/// when there are some (`qem::simplify` of a model with attributes, whose seams also shape the
/// geometry), positions only otherwise. The one policy of `compare` and the survey (and the
/// viewer's).
pub(crate) fn qem_as_simplify(
    original: &TriMesh,
    attributes: Option<&Attributes>,
    params: &qem::QemParams,
) -> Result<(TriMesh, Option<Attributes>), ExperimentError> {
    let model = mesh::Model {
        attributes: attributes.cloned(),
        ..mesh::Model::from(original.clone())
    };
    let (out, _) = qem::simplify(&model, params)?;
    Ok((out.mesh, out.attributes))
}

/// GNG3D as `gng3d simplify --method gng` runs it: with `attributes`, triangles that follow
/// their seams and values from the original (`gng3d_core::simplify` of a model with attributes);
/// positions only otherwise.
pub(crate) fn gng_as_simplify(
    original: &TriMesh,
    attributes: Option<&Attributes>,
    options: &gng3d_core::GngOptions,
) -> Result<(gng3d_core::GngResult, Option<Attributes>), ExperimentError> {
    let model = mesh::Model {
        attributes: attributes.cloned(),
        ..original.clone().into()
    };
    let mut result = gng3d_core::simplify(&model, options)?;
    let kept = result.attributes.take();
    Ok((result, kept))
}

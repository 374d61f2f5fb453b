//! The paper's experiment as a library: [`compare`] runs QEM and GNG3D to the same vertex
//! count and measures both; [`reproduce`] follows the paper's checkpoint protocol; [`survey`]
//! runs GNG3D, GNG3D-Q and QEM over meshes and ratios. Every simplification is the job's one
//! run (`job::run`, as `gng3d simplify` runs it), except the protocol's checkpoints, which
//! reconstruct the network as it trains.

pub mod compare;
pub mod reproduce;
pub mod survey;

use job::{GngVariant, Method, Request, Target};
use mesh::attributes::Attributes;
use mesh::{Model, TriMesh};
use metrics::{AttributeDeviation, AttributeParams, Evaluator, HausdorffParams, MetricsParams};
use serde::{Deserialize, Serialize};

/// Why an experiment could not run.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    // The wrapped errors are sources (printed after the prefix by `{:#}` / error chains), so the
    // messages do not repeat them.
    /// The job (a QEM or GNG3D run) refused its request or failed.
    #[error(transparent)]
    Job(#[from] job::JobError),
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

/// The attribute deviation of `mesh` (with the attributes a run `kept`) against `original`
/// with `attributes`, measured with `params`: `None` unless both sides have attributes and the
/// original's have values to compare (materials alone have none).
pub(crate) fn deviation(
    original: &TriMesh,
    attributes: Option<&Attributes>,
    mesh: &TriMesh,
    kept: Option<&Attributes>,
    params: &AttributeParams,
) -> Result<Option<AttributeDeviation>, metrics::MetricsError> {
    match (attributes.filter(|a| a.has_values()), kept) {
        (Some(a), Some(b)) => Ok(Some(metrics::attribute_deviation(
            original, a, mesh, b, params,
        )?)),
        _ => Ok(None),
    }
}

/// The model a run takes: `original` with `attributes` (cloned once per experiment).
pub(crate) fn model(original: &TriMesh, attributes: Option<&Attributes>) -> Model {
    Model {
        attributes: attributes.cloned(),
        ..Model::from(original.clone())
    }
}

/// `request` run on `model` as `gng3d simplify` runs it: the job's one run (`job::run`), so
/// QEM keeps the attributes through its contractions (its seams also shape the geometry) and
/// GNG3D's triangles follow their seams and take the original's values. The one run of
/// `compare`, `reproduce` and the survey. The output mesh and its attributes (when the model
/// has some), and the run's warnings (a target not reached, ...).
pub(crate) fn run(
    model: &Model,
    request: &Request,
) -> Result<(TriMesh, Option<Attributes>, Vec<String>), ExperimentError> {
    let outcome = job::run(model, request, &mut ())?;
    Ok((
        outcome.model.mesh,
        outcome.model.attributes,
        outcome.warnings,
    ))
}

/// QEM to `vertices` vertices with `request`'s seed, threads and QEM options (its GNG3D
/// variant and time limit left out): the QEM side of every comparison.
pub(crate) fn qem_request(request: &Request, vertices: usize) -> Request {
    Request {
        method: Method::Qem,
        target: Target::Vertices(vertices),
        time_limit: None,
        gng: GngVariant::default(),
        ..request.clone()
    }
}

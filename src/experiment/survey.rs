//! `reproduce --all`: GNG3D (the paper's method and protocol), GNG3D-Q (the library
//! defaults: quadric placement, edge flips, output-sized signal budget) and QEM on many meshes
//! at several vertex ratios, with a winner per metric.
//!
//! Steps per mesh and ratio: train and reconstruct GNG3D as published; run QEM to GNG3D's
//! output vertex count; run GNG3D-Q; run QEM to GNG3D-Q's output vertex count (both GNG
//! variants hold the exact count on closed manifolds, so the two QEM runs usually coincide in
//! count, but each comparison is at equal vertex count by construction); measure all four.
//!
//! Every method is the job's one run (`job::run`), as `gng3d simplify --method paper|gng|qem`
//! runs it, so the figures are those of the files a user gets. An original with attributes
//! (normals, texture coordinates, colours: [`survey_mesh_with_attributes`]) keeps them: QEM
//! through its contractions (its seams shape the geometry), both GNG3D variants' triangles
//! follow the seams and take the original's values. Each output's attribute deviation
//! ([`metrics::attribute_deviation`]) is in [`SurveyRow::attributes`]. `gng3d compare` and the
//! viewer follow the same policy.

use super::{ExperimentError, PaperEvaluator, PaperRow};
use job::{GngVariant, Method, Request, Target};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use metrics::{AttributeDeviation, AttributeParams, HausdorffParams};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Parameters of [`survey_mesh`].
#[derive(Debug, Clone)]
pub struct SurveyParams {
    /// Target vertex counts as fractions of the original vertex count.
    pub ratios: Vec<f64>,
    /// GNG3D training length in epochs of |V| signals.
    pub epochs: u64,
    /// The random seed of both GNG3D runs (the job's [`job::DEFAULT_SEED`] by default).
    pub seed: u64,
    /// Surface sampling of the Hausdorff distance.
    pub hausdorff: HausdorffParams,
    /// Attribute-deviation settings, used for originals with attributes.
    pub attributes: AttributeParams,
}

impl Default for SurveyParams {
    fn default() -> Self {
        SurveyParams {
            ratios: vec![0.1, 0.25, 0.5],
            epochs: 30,
            seed: job::DEFAULT_SEED,
            hausdorff: HausdorffParams::with_samples(200_000),
            attributes: AttributeParams::default(),
        }
    }
}

/// One mesh at one ratio: both methods' measures and the output topology.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SurveyRow {
    /// Mesh name (file name).
    pub mesh: String,
    /// Target ratio of vertices.
    pub ratio: f64,
    /// Welded original vertex count.
    pub original_vertices: usize,
    /// Genus of the original (None when undefined).
    pub original_genus: Option<i64>,
    /// GNG3D's measures.
    pub gng: PaperRow,
    /// QEM's measures at GNG3D's output vertex count.
    pub qem: PaperRow,
    /// GNG3D output: edge-manifold without boundary.
    pub gng_closed_manifold: bool,
    /// GNG3D output genus.
    pub gng_genus: Option<i64>,
    /// QEM output genus.
    pub qem_genus: Option<i64>,
    /// GNG3D seconds (both phases).
    pub gng_seconds: f64,
    /// QEM seconds.
    pub qem_seconds: f64,
    /// GNG3D-Q's measures (library defaults).
    pub gngq: PaperRow,
    /// QEM's measures at GNG3D-Q's output vertex count.
    pub qem_at_gngq: PaperRow,
    /// GNG3D-Q output: edge-manifold without boundary.
    pub gngq_closed_manifold: bool,
    /// GNG3D-Q output genus.
    pub gngq_genus: Option<i64>,
    /// GNG3D-Q seconds (both phases).
    pub gngq_seconds: f64,
    /// Each output's attribute deviation, when the original has attributes (absent from the
    /// JSON otherwise, so a positions-only survey's files are as before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attributes: Option<SurveyAttributes>,
}

/// The attribute deviation of each output of one [`SurveyRow`] against the original.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SurveyAttributes {
    /// GNG3D's (attributes transferred from the original surface).
    pub gng: AttributeDeviation,
    /// QEM's at GNG3D's output vertex count (attributes kept through the contractions).
    pub qem: AttributeDeviation,
    /// GNG3D-Q's (attributes transferred from the original surface).
    pub gngq: AttributeDeviation,
    /// QEM's at GNG3D-Q's output vertex count.
    pub qem_at_gngq: AttributeDeviation,
}

/// Run GNG3D, GNG3D-Q and QEM on `original` (welded) at every ratio of `params`.
pub fn survey_mesh(
    name: &str,
    original: &TriMesh,
    params: &SurveyParams,
) -> Result<Vec<SurveyRow>, ExperimentError> {
    survey_mesh_with_attributes(name, original, None, params)
}

/// [`survey_mesh`] for an original with `attributes` (which must fit it; `None`: positions
/// only, exactly [`survey_mesh`]): every method keeps them (see the module docs) and each
/// row's [`SurveyRow::attributes`] holds every output's attribute deviation, measured with
/// `params.attributes`.
pub fn survey_mesh_with_attributes(
    name: &str,
    original: &TriMesh,
    attributes: Option<&Attributes>,
    params: &SurveyParams,
) -> Result<Vec<SurveyRow>, ExperimentError> {
    let n = original.vertex_count();
    // Both methods need a tetrahedron's worth of vertices; smaller meshes are skipped (the
    // caller warns and carries on with the other meshes).
    if n < 4 {
        return Err(ExperimentError::BadTarget(format!(
            "the mesh has {n} vertices; the survey needs at least 4"
        )));
    }
    crate::experiment::reproduce::check_epochs(params.epochs)
        .map_err(ExperimentError::BadTarget)?;
    if attributes.is_some() {
        params.attributes.validate()?;
    }
    let evaluator = PaperEvaluator::new(original, params.hausdorff)?;
    let deviation = |mesh: &TriMesh, kept: &Option<Attributes>| {
        super::deviation(
            original,
            attributes,
            mesh,
            kept.as_ref(),
            &params.attributes,
        )
    };
    let topo = mesh::topology::analyze(original);
    let model = super::model(original, attributes);
    // Wall-clock seconds of the job's run of `request`, with its mesh and attributes.
    let timed = |request: &Request| {
        let t = Instant::now();
        let (mesh, kept, _) = super::run(&model, request)?;
        Ok::<_, ExperimentError>((mesh, kept, t.elapsed().as_secs_f64()))
    };
    let mut rows = Vec::new();
    for &ratio in &params.ratios {
        let target = ((n as f64 * ratio).round() as usize).clamp(4, n);
        // The paper's GNG3D with the protocol's budget.
        let paper = Request {
            seed: params.seed,
            gng: GngVariant {
                epochs: Some(params.epochs as f64),
                ..GngVariant::default()
            },
            ..Request::new(Target::Vertices(target)).with_method(Method::Paper)
        };
        let (gng_mesh, gng_kept, gng_seconds) = timed(&paper)?;
        // QEM gets exactly GNG3D's output vertex count (reconstruction may drop a few nodes).
        let (qem_mesh, qem_kept, qem_seconds) =
            timed(&super::qem_request(&paper, gng_mesh.vertex_count().max(4)))?;
        // GNG3D-Q with the defaults a user of `simplify --method gng` gets.
        let gngq = Request {
            seed: params.seed,
            ..Request::new(Target::Vertices(target)).with_method(Method::Gng)
        };
        let (gngq_mesh, gngq_kept, gngq_seconds) = timed(&gngq)?;
        let qem_deviation = deviation(&qem_mesh, &qem_kept)?;
        let qem_at_gngq_attributes;
        let qem_at_gngq = if gngq_mesh.vertex_count() == gng_mesh.vertex_count() {
            qem_at_gngq_attributes = qem_deviation.clone();
            evaluator.evaluate(&qem_mesh)?
        } else {
            let qem = super::qem_request(&gngq, gngq_mesh.vertex_count().max(4));
            let (mesh, kept, _) = super::run(&model, &qem)?;
            qem_at_gngq_attributes = deviation(&mesh, &kept)?;
            evaluator.evaluate(&mesh)?
        };
        let deviations = match (
            deviation(&gng_mesh, &gng_kept)?,
            qem_deviation,
            deviation(&gngq_mesh, &gngq_kept)?,
            qem_at_gngq_attributes,
        ) {
            (Some(gng), Some(qem), Some(gngq), Some(qem_at_gngq)) => Some(SurveyAttributes {
                gng,
                qem,
                gngq,
                qem_at_gngq,
            }),
            _ => None,
        };
        let gqt = mesh::topology::analyze(&gngq_mesh);
        let gt = mesh::topology::analyze(&gng_mesh);
        let qt = mesh::topology::analyze(&qem_mesh);
        rows.push(SurveyRow {
            mesh: name.to_string(),
            ratio,
            original_vertices: n,
            original_genus: topo.genus,
            gng: evaluator.evaluate(&gng_mesh)?,
            qem: evaluator.evaluate(&qem_mesh)?,
            gng_closed_manifold: gt.closed && gt.manifold,
            gng_genus: gt.genus,
            qem_genus: qt.genus,
            gng_seconds,
            qem_seconds,
            gngq: evaluator.evaluate(&gngq_mesh)?,
            qem_at_gngq,
            gngq_closed_manifold: gqt.closed && gqt.manifold,
            gngq_genus: gqt.genus,
            gngq_seconds,
            attributes: deviations,
        });
    }
    Ok(rows)
}

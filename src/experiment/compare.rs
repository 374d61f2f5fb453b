//! QEM and GNG3D simplified to the same vertex count, with every metric for both.

use super::ExperimentError;
use gng3d_core::GngOptions;
use job::{Method, Request, Target};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use metrics::{AttributeParams, MetricsParams, MetricsReport};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Parameters of [`compare`].
#[derive(Debug, Clone)]
pub struct CompareParams {
    /// GNG3D's run as the job takes it: the method ([`Method::Gng`], or [`Method::Paper`] for
    /// the published GNG3D), the target (a vertex count or a share of the vertices), the seed,
    /// the time limit and the variant. QEM runs to the same vertex count with the same seed and
    /// threads (`gng3d compare` maps its flags onto it as `gng3d simplify` does).
    pub request: Request,
    /// Metric settings (surface sampling).
    pub metrics: MetricsParams,
    /// Attribute-deviation settings, used when [`compare_with_attributes`] is given attributes.
    pub attributes: AttributeParams,
}

impl CompareParams {
    /// Defaults for both methods at `target_vertices` (GNG3D-Q as `gng3d simplify --method
    /// gng` runs it).
    pub fn new(target_vertices: usize) -> CompareParams {
        CompareParams::with_target(Target::Vertices(target_vertices))
    }

    /// Defaults for both methods at `target`: a vertex count, or a share of the input's
    /// vertices ([`Target::Ratio`], the same count for both methods).
    pub fn with_target(target: Target) -> CompareParams {
        CompareParams::for_request(Request::new(target).with_method(Method::Gng))
    }

    /// GNG3D's run `request` against QEM, measured with the default settings.
    pub fn for_request(request: Request) -> CompareParams {
        CompareParams {
            request,
            metrics: MetricsParams::default(),
            attributes: AttributeParams::default(),
        }
    }
}

/// One method's result and measurements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodRun {
    /// "qem" or "gng".
    pub method: String,
    /// Output vertices.
    pub vertices: usize,
    /// Output faces.
    pub faces: usize,
    /// Simplification wall time, seconds.
    pub seconds: f64,
    /// Every metric against the original.
    pub metrics: MetricsReport,
}

/// What [`compare`] measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompareReport {
    /// Vertices of the original.
    pub original_vertices: usize,
    /// Faces of the original.
    pub original_faces: usize,
    /// Requested vertex count (a share of the vertices resolved on the original).
    pub target_vertices: usize,
    /// QEM's run.
    pub qem: MethodRun,
    /// GNG3D's run.
    pub gng: MethodRun,
    /// Which GNG3D ran, in words (placement, flips, refit, signal budget), e.g. "GNG3D-Q:
    /// quadric placement, edge flips, surface refit, default signal budget".
    pub gng_variant: String,
    /// GNG3D's vertex placement.
    pub gng_placement: gng3d_core::Placement,
    /// Whether GNG3D's edge-flip pass ran.
    pub gng_flips: bool,
    /// Whether GNG3D's surface refit ran (quadric placement with the refit on).
    pub gng_refit: bool,
    /// What differs from the request: a method that stopped short of the target (QEM's
    /// shortfall moves GNG3D to QEM's count, so both are measured at the same count), or
    /// counts that still differ (the verdicts then compare unequal counts).
    #[serde(default)]
    pub warnings: Vec<String>,
}

/// `options`' variant in words: "GNG3D (paper: ...)" for node placement without flips,
/// "GNG3D-Q (...)" otherwise.
pub fn variant_label(options: &GngOptions) -> String {
    use gng3d_core::Placement;
    let r = &options.reconstruction;
    let placement = match r.placement {
        Placement::Node => "node placement",
        Placement::Project => "projected placement",
        Placement::Quadric => "quadric placement",
    };
    let flips = if r.flip_edges {
        "edge flips"
    } else {
        "no flips"
    };
    let budget = match (options.epochs, options.max_signals) {
        (Some(e), _) => format!("{e} epochs of |V| signals"),
        (None, Some(s)) => format!("{s} signals"),
        (None, None) => "default signal budget".to_string(),
    };
    let refit = if r.refits() { ", surface refit" } else { "" };
    let oversample = if options.oversample_factor() > 1.0 {
        format!(", {}x nodes decimated by QEM", options.oversample_factor())
    } else {
        String::new()
    };
    let detail = match options.detail_rounds {
        Some(0) => ", no detail nodes".to_string(),
        Some(r) if options.oversample_factor() > 1.0 => format!(", {r} rounds of detail nodes"),
        _ => String::new(),
    };
    let relax = if options.oversample_factor() > 1.0 && !r.relax {
        ", no relaxation"
    } else {
        ""
    };
    let repair = if options.oversample_factor() > 1.0 && !r.repair_deviations {
        ", no deviation repair"
    } else {
        ""
    };
    let shape = match r.shape {
        _ if options.oversample_factor() <= 1.0 => "",
        gng3d_core::Shape::Off => "",
        gng3d_core::Shape::Fit => ", shape pass (fit)",
        gng3d_core::Shape::Round => ", shape pass (round)",
    };
    let creases = if r.creases { ", creases" } else { "" };
    let signals = match options.signal_source {
        gng3d_core::SignalSource::Vertices => "",
        gng3d_core::SignalSource::Surface => ", surface signals",
        gng3d_core::SignalSource::Curvature => ", curvature-weighted signals",
    };
    let name = if r.placement == Placement::Node && !r.flip_edges {
        "GNG3D (paper)"
    } else {
        "GNG3D-Q"
    };
    format!(
        "{name}: {placement}, {flips}{refit}, {budget}{signals}{oversample}{detail}{relax}{shape}{repair}{creases}"
    )
}

/// The report plus both simplified meshes.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// Measurements.
    pub report: CompareReport,
    /// QEM's mesh.
    pub qem_mesh: TriMesh,
    /// GNG3D's mesh.
    pub gng_mesh: TriMesh,
    /// QEM's attributes (kept through its contractions), when the input had some.
    pub qem_attributes: Option<Attributes>,
    /// GNG3D's attributes (transferred from the original surface), when the input had some.
    pub gng_attributes: Option<Attributes>,
}

/// Simplify `original` (expected welded) with both methods to `params.request`'s target and
/// measure both. The methods run one after the other so their timings do not interfere.
pub fn compare(original: &TriMesh, params: &CompareParams) -> Result<Comparison, ExperimentError> {
    compare_with_progress(original, params, |_| {})
}

/// A stage of [`compare_with_progress`], named as it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CompareStage {
    /// QEM simplifies.
    Qem,
    /// GNG3D trains and runs the steps after training.
    Gng,
    /// Both meshes are measured.
    Metrics,
}

impl std::fmt::Display for CompareStage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            CompareStage::Qem => "QEM",
            CompareStage::Gng => "GNG3D: training and the steps after it",
            CompareStage::Metrics => "measuring both meshes",
        })
    }
}

/// [`compare`], calling `on_stage` as each stage starts (a front end's progress line).
pub fn compare_with_progress(
    original: &TriMesh,
    params: &CompareParams,
    on_stage: impl FnMut(CompareStage),
) -> Result<Comparison, ExperimentError> {
    compare_with_attributes(original, None, params, on_stage)
}

/// [`compare_with_progress`] for an original with `attributes` (which must fit it): both
/// methods run as `gng3d simplify` runs them (QEM keeps them through its contractions, GNG3D's
/// triangles follow the seams and take the original's values), and each method's [`MetricsReport::attributes`] holds the
/// attribute deviation ([`metrics::attribute_deviation`] with `params.attributes`). Without
/// attributes this is [`compare_with_progress`].
pub fn compare_with_attributes(
    original: &TriMesh,
    attributes: Option<&Attributes>,
    params: &CompareParams,
    mut on_stage: impl FnMut(CompareStage),
) -> Result<Comparison, ExperimentError> {
    let request = &params.request;
    if !request.method.is_gng() {
        return Err(ExperimentError::BadTarget(format!(
            "compare runs GNG3D against QEM: the request's method must be 'gng' or 'paper', got '{}'",
            request.method
        )));
    }
    // Every option is checked before either method runs.
    request.validate()?;
    let options = request.gng_options()?;
    let n = options.target.vertex_count(original)?;
    if n < 4 || n > original.vertex_count() {
        return Err(ExperimentError::BadTarget(format!(
            "target of {n} vertices is outside 4..={} (the mesh's vertex count)",
            original.vertex_count()
        )));
    }
    options.resolve(original)?;
    params.metrics.hausdorff.validate()?;
    if attributes.is_some() {
        params.attributes.validate()?;
    }
    let model = super::model(original, attributes);
    on_stage(CompareStage::Qem);
    let t = Instant::now();
    let (qem_mesh, qem_attributes, mut warnings) =
        super::run(&model, &super::qem_request(request, n))?;
    let qem_seconds = t.elapsed().as_secs_f64();

    on_stage(CompareStage::Gng);
    let t = Instant::now();
    // GNG3D to the count QEM got (a share resolved once): the target, or where QEM stopped
    // short of it, so that every verdict compares equal counts.
    let reached = qem_mesh.vertex_count();
    let gng_vertices = if reached != n && (4..=original.vertex_count()).contains(&reached) {
        warnings.push(format!(
            "GNG3D runs to QEM's {reached} vertices (not {n}) so both are compared at the same count"
        ));
        reached
    } else {
        n
    };
    let gng_request = Request {
        target: Target::Vertices(gng_vertices),
        ..request.clone()
    };
    let (gng_mesh, gng_attributes, gng_warnings) = super::run(&model, &gng_request)?;
    let gng_seconds = t.elapsed().as_secs_f64();
    warnings.extend(gng_warnings);
    if gng_mesh.vertex_count() != qem_mesh.vertex_count() {
        warnings.push(format!(
            "QEM has {} vertices and GNG3D {}: the 'better' column compares unequal counts",
            qem_mesh.vertex_count(),
            gng_mesh.vertex_count()
        ));
    }
    for (method, mesh) in [("QEM", &qem_mesh), ("GNG3D", &gng_mesh)] {
        if mesh.face_count() == 0 {
            return Err(ExperimentError::EmptyOutput {
                method,
                vertices: mesh.vertex_count(),
            });
        }
    }

    on_stage(CompareStage::Metrics);
    let measure = |mesh: &TriMesh, kept: Option<&Attributes>| {
        let mut report = metrics::evaluate(original, mesh, &params.metrics)?;
        report.attributes = super::deviation(original, attributes, mesh, kept, &params.attributes)?;
        Ok::<_, metrics::MetricsError>(report)
    };
    let (qem_metrics, gng_metrics) = rayon::join(
        || measure(&qem_mesh, qem_attributes.as_ref()),
        || measure(&gng_mesh, gng_attributes.as_ref()),
    );
    let run = |method: &str, mesh: &TriMesh, seconds: f64, metrics: MetricsReport| MethodRun {
        method: method.into(),
        vertices: mesh.vertex_count(),
        faces: mesh.face_count(),
        seconds,
        metrics,
    };
    Ok(Comparison {
        report: CompareReport {
            original_vertices: original.vertex_count(),
            original_faces: original.face_count(),
            target_vertices: n,
            qem: run("qem", &qem_mesh, qem_seconds, qem_metrics?),
            gng: run("gng", &gng_mesh, gng_seconds, gng_metrics?),
            gng_variant: variant_label(&options),
            gng_placement: options.reconstruction.placement,
            gng_flips: options.reconstruction.flip_edges,
            gng_refit: options.reconstruction.refits(),
            warnings,
        },
        qem_mesh,
        gng_mesh,
        qem_attributes,
        gng_attributes,
    })
}

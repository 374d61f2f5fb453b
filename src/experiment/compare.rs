//! QEM and GNG3D simplified to the same vertex count, with every metric for both.

use super::ExperimentError;
use gng3d_core::GngParams;
use mesh::TriMesh;
use metrics::{MetricsParams, MetricsReport};
use qem::{QemParams, Target};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Parameters of [`compare`].
#[derive(Debug, Clone)]
pub struct CompareParams {
    /// Vertex count both methods aim for.
    pub target_vertices: usize,
    /// GNG3D parameters (`target_vertices` is overwritten).
    pub gng: GngParams,
    /// QEM parameters (`target` is overwritten).
    pub qem: QemParams,
    /// Metric settings (surface sampling).
    pub metrics: MetricsParams,
}

impl CompareParams {
    /// Defaults for both methods at `target_vertices`.
    pub fn new(target_vertices: usize) -> CompareParams {
        CompareParams {
            target_vertices,
            gng: GngParams::for_target(target_vertices),
            qem: QemParams::with_target(Target::Vertices(target_vertices)),
            metrics: MetricsParams::default(),
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
    /// Requested vertex count.
    pub target_vertices: usize,
    /// QEM's run.
    pub qem: MethodRun,
    /// GNG3D's run.
    pub gng: MethodRun,
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
}

/// Simplify `original` (expected welded) with both methods to `params.target_vertices` and
/// measure both. The methods run one after the other so their timings do not interfere.
pub fn compare(original: &TriMesh, params: &CompareParams) -> Result<Comparison, ExperimentError> {
    let n = params.target_vertices;
    if n < 4 || n > original.vertex_count() {
        return Err(ExperimentError::BadTarget(format!(
            "target of {n} vertices is outside 4..={} (the mesh's vertex count)",
            original.vertex_count()
        )));
    }
    let mut qp = params.qem.clone();
    qp.target = Target::Vertices(n);
    let t = Instant::now();
    let (qem_mesh, _) = qem::simplify(original, &qp)?;
    let qem_seconds = t.elapsed().as_secs_f64();

    let mut gp = params.gng.clone();
    gp.target_vertices = n;
    let t = Instant::now();
    let gng = gng3d_core::simplify(original, &gp)?;
    let gng_seconds = t.elapsed().as_secs_f64();

    let (qem_metrics, gng_metrics) = rayon::join(
        || metrics::evaluate(original, &qem_mesh, &params.metrics),
        || metrics::evaluate(original, &gng.mesh, &params.metrics),
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
            gng: run("gng", &gng.mesh, gng_seconds, gng_metrics?),
        },
        qem_mesh,
        gng_mesh: gng.mesh,
    })
}

/// Which side a lower-is-better value favours: "QEM", "GNG3D" or "tie".
pub fn winner(qem: f64, gng: f64) -> &'static str {
    let scale = qem.abs().max(gng.abs());
    if (qem - gng).abs() <= 1e-9 * scale {
        "tie"
    } else if qem < gng {
        "QEM"
    } else {
        "GNG3D"
    }
}

/// The comparison as a table of metric rows with QEM, GNG3D and the winner.
pub fn comparison_table(report: &CompareReport) -> crate::report::table::Table {
    use crate::report::paper::sci;
    let mut t = crate::report::table::Table::new(["measure", "QEM", "GNG3D", "better"]);
    let (q, g) = (&report.qem, &report.gng);
    let (qm, gm) = (&q.metrics, &g.metrics);
    let mut num = |name: &str, a: f64, b: f64, lower_better: bool| {
        let w = if lower_better { winner(a, b) } else { "" };
        t.push([name.to_string(), sci(a), sci(b), w.to_string()]);
    };
    num("E_avg (sq. units)", qm.e_avg, gm.e_avg, true);
    num("E_max (sq. units)", qm.e_max, gm.e_max, true);
    num("|E_sur| (sq. units)", qm.e_sur_abs, gm.e_sur_abs, true);
    num("Hausdorff max", qm.hausdorff.max, gm.hausdorff.max, true);
    num("Hausdorff mean", qm.hausdorff.mean, gm.hausdorff.mean, true);
    num("Hausdorff RMS", qm.hausdorff.rms, gm.hausdorff.rms, true);
    num(
        "Hausdorff max / diagonal",
        qm.hausdorff.relative.max,
        gm.hausdorff.relative.max,
        true,
    );
    num(
        "normal deviation mean (deg)",
        qm.normal_deviation.forward.mean_degrees,
        gm.normal_deviation.forward.mean_degrees,
        true,
    );
    let mut int =
        |name: &str, a: String, b: String| t.push([name.to_string(), a, b, String::new()]);
    int("vertices", q.vertices.to_string(), g.vertices.to_string());
    int("faces", q.faces.to_string(), g.faces.to_string());
    int(
        "seconds",
        format!("{:.3}", q.seconds),
        format!("{:.3}", g.seconds),
    );
    let (qt, gt) = (&qm.topology.simplified, &gm.topology.simplified);
    int(
        "boundary edges",
        qt.boundary_edges.to_string(),
        gt.boundary_edges.to_string(),
    );
    int(
        "non-manifold edges",
        qt.non_manifold_edges.to_string(),
        gt.non_manifold_edges.to_string(),
    );
    let genus = |g: Option<i64>| g.map_or("-".to_string(), |g| g.to_string());
    int("genus", genus(qt.genus), genus(gt.genus));
    int(
        "min angle (deg)",
        format!("{:.2}", qm.quality.simplified.min_angle_degrees),
        format!("{:.2}", gm.quality.simplified.min_angle_degrees),
    );
    t
}

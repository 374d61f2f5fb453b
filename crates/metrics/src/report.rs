//! The one evaluation record of the workspace: [`MetricsReport`] (alias [`Evaluation`]), made
//! by an [`Evaluator`] that indexes the original once and measures any number of simplified
//! meshes against it, or by [`evaluate`] for a single pair. The CLI (`metrics`, `compare`,
//! `reproduce`), the experiment tables and the viewer all read their E_avg / E_max / E_sur,
//! surface distances, normal deviation and triangle quality from here, with the one sampling
//! rule of [`crate::HausdorffParams`] (`samples: None` = 10 × the larger face count, capped at
//! [`crate::MAX_SAMPLES_PER_DIRECTION`] / 2), so the same pair and parameters give the same
//! numbers in every front end.
//!
//! Distances are searched in the original's frame (scaled by a power of two near its bounding-box
//! diagonal, centred when it lies off the origin), so a pair gives the same figures relative to
//! its size in 1e-25 or in 1e15 model units; every figure is reported in model units (squared
//! for E_avg/E_max and areas). A simplified mesh more than [`crate::MAX_SPAN`] original diagonals
//! away is refused ([`MetricsError::CoordinateRange`]).

use crate::SurfaceDistanceIndex;
use crate::frame::Frame;
use crate::hausdorff::{
    Hausdorff, HausdorffParams, NormalDeviation, hausdorff_full, hausdorff_pipelined,
};
use crate::paper::{SurfaceError, VertexErrors, surface_error, vertex_errors};
use crate::quality::{TriangleQuality, triangle_quality};
use crate::{MetricsError, check_cancel, validate_mesh};
use glam::Vec3;
use mesh::TriMesh;
use mesh::cancel::Cancel;
use mesh::topology::{TopologyReport, analyze};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Parameters of [`evaluate`].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct MetricsParams {
    /// Sampling of the surface distance.
    pub hausdorff: HausdorffParams,
}

/// Size of one mesh.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeshSummary {
    /// Vertex records (including unreferenced ones).
    pub vertices: usize,
    /// Vertices used by at least one triangle.
    pub referenced_vertices: usize,
    /// Triangles.
    pub faces: usize,
    /// Surface area, squared model units.
    pub area: f64,
    /// Bounding-box diagonal of the referenced vertices, model units.
    pub bbox_diagonal: f64,
}

/// A value for the original and for the simplified mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pair<T> {
    /// Of the original mesh.
    pub original: T,
    /// Of the simplified mesh.
    pub simplified: T,
}

/// Normal deviation in both directions.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NormalDeviations {
    /// Samples on the original, closest faces on the simplified mesh.
    pub forward: NormalDeviation,
    /// Samples on the simplified mesh, closest faces on the original.
    pub backward: NormalDeviation,
}

/// Every metric of a simplification (forward = original → simplified).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MetricsReport {
    /// Paper E_avg: mean squared distance from each referenced original vertex to the nearest
    /// referenced simplified vertex, squared model units.
    pub e_avg: f64,
    /// Paper E_max: the largest of those squared distances, squared model units.
    pub e_max: f64,
    /// Paper E_sur = S_K − S_A (original minus simplified area), squared model units,
    /// **signed**: positive when the simplified mesh lost area.
    pub e_sur_signed: f64,
    /// |E_sur| = |S_K − S_A|, squared model units (what tables rank by).
    pub e_sur_abs: f64,
    /// |E_sur| / S_K.
    pub e_sur_relative: f64,
    /// S_K, the original's surface area, squared model units.
    pub original_area: f64,
    /// S_A, the simplified mesh's surface area, squared model units.
    pub simplified_area: f64,
    /// Metro-style two-sided surface distance (model units, and relative to `bbox_diagonal`).
    pub hausdorff: Hausdorff,
    /// Bounding-box diagonal of the original's referenced vertices, model units.
    pub bbox_diagonal: f64,
    /// Angle between sample normals and closest-face normals, both directions.
    pub normal_deviation: NormalDeviations,
    /// Triangle shape statistics of both meshes.
    pub quality: Pair<TriangleQuality>,
    /// Topology (boundaries, non-manifold elements, genus) of both meshes.
    pub topology: Pair<TopologyReport>,
    /// Sizes of both meshes.
    pub meshes: Pair<MeshSummary>,
    /// Wall-clock time of the evaluation, seconds (the attribute deviation has its own).
    pub seconds: f64,
    /// Deviation of texture coordinates, normals and colours ([`crate::attribute_deviation`]),
    /// when the caller measured it (the original has attributes); not in the JSON otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attributes: Option<crate::AttributeDeviation>,
    /// Image-space error ([`crate::image_error`]), when the caller measured it (`gng3d metrics
    /// --image-error`, `gng3d compare --image-error`); not in the JSON otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image_error: Option<crate::ImageError>,
}

/// The evaluation record (same type as [`MetricsReport`]).
pub type Evaluation = MetricsReport;

/// Positions of the vertices referenced by at least one triangle, in index order.
fn referenced_positions(mesh: &TriMesh) -> Vec<Vec3> {
    let mut used = vec![false; mesh.positions.len()];
    for t in &mesh.triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    mesh.positions
        .iter()
        .zip(&used)
        .filter(|(_, u)| **u)
        .map(|(p, _)| *p)
        .collect()
}

/// Summary of a validated mesh.
fn summary(mesh: &TriMesh, referenced: usize) -> MeshSummary {
    MeshSummary {
        vertices: mesh.vertex_count(),
        referenced_vertices: referenced,
        faces: mesh.face_count(),
        area: mesh.area(),
        bbox_diagonal: mesh.bbox_diagonal(),
    }
}

/// Measures simplified meshes against one original: validates and indexes the original once
/// (BVH for surface distances, referenced vertices, quality, topology, area), then
/// [`Evaluator::evaluate`] costs only the simplified side. `Send + Sync`, so a viewer can keep
/// one per loaded model on a worker thread.
///
/// ```
/// use gng3d_metrics::{Evaluator, HausdorffParams, MetricsParams};
/// let original = mesh::procedural::icosphere(3);
/// let simplified = mesh::procedural::icosphere(1);
/// let params = MetricsParams { hausdorff: HausdorffParams::with_samples(20_000) };
/// let evaluator = Evaluator::new(&original, &params).unwrap();
/// let e = evaluator.evaluate(&simplified).unwrap();
/// assert!(e.e_sur_signed > 0.0); // the coarse sphere lost area
/// assert_eq!(e.e_sur_abs, e.e_sur_signed.abs());
/// assert!(e.hausdorff.max >= e.hausdorff.forward.max.max(e.hausdorff.backward.max));
/// assert!(e.quality.simplified.median_min_angle_degrees > 20.0);
/// ```
pub struct Evaluator {
    original: std::sync::Arc<TriMesh>,
    /// The original's frame, which every evaluation measures in.
    frame: Frame,
    index: SurfaceDistanceIndex,
    points: Vec<Vec3>,
    quality: TriangleQuality,
    topology: TopologyReport,
    summary: MeshSummary,
    params: MetricsParams,
}

impl Evaluator {
    /// Validates `params` and `original` (a copy is kept) and indexes it.
    pub fn new(original: &TriMesh, params: &MetricsParams) -> Result<Evaluator, MetricsError> {
        Evaluator::from_arc(std::sync::Arc::new(original.clone()), params)
    }

    /// As [`Evaluator::new`], sharing an original the caller already holds in an `Arc`.
    pub fn from_arc(
        original: std::sync::Arc<TriMesh>,
        params: &MetricsParams,
    ) -> Result<Evaluator, MetricsError> {
        params.hausdorff.validate()?;
        validate_mesh(&original, "original")?;
        let points = referenced_positions(&original);
        if points.is_empty() {
            return Err(MetricsError::NoTriangles { mesh: "original" });
        }
        let frame = Frame::of_mesh(&original);
        let (index, (quality, topology)) = rayon::join(
            || SurfaceDistanceIndex::in_frame(&original, frame),
            || (triangle_quality(&original), analyze(&original)),
        );
        let index = index.map_err(|e| match e {
            MetricsError::NoTriangles { .. } => MetricsError::NoTriangles { mesh: "original" },
            other => other,
        })?;
        let summary = summary(&original, points.len());
        Ok(Evaluator {
            original,
            frame,
            index,
            points,
            quality,
            topology,
            summary,
            params: *params,
        })
    }

    /// The original mesh.
    pub fn original(&self) -> &TriMesh {
        &self.original
    }

    /// The parameters every evaluation uses.
    pub fn params(&self) -> &MetricsParams {
        &self.params
    }

    /// Every metric of `simplified` against the original. `simplified` needs at least one
    /// triangle, valid indices, finite coordinates, and every vertex within
    /// [`crate::MAX_SPAN`] bounding-box diagonals of the original.
    pub fn evaluate(&self, simplified: &TriMesh) -> Result<Evaluation, MetricsError> {
        let start = Instant::now();
        validate_mesh(simplified, "simplified")?;
        let simplified_points = referenced_positions(simplified);
        if simplified_points.is_empty() {
            return Err(MetricsError::NoTriangles { mesh: "simplified" });
        }
        self.frame.check_span(simplified, "simplified", false)?;
        let simplified_index =
            SurfaceDistanceIndex::in_frame(simplified, self.frame).map_err(|e| match e {
                MetricsError::NoTriangles { .. } => {
                    MetricsError::NoTriangles { mesh: "simplified" }
                }
                other => other,
            })?;
        let (distances, (quality_s, topology_s)) = rayon::join(
            || {
                hausdorff_full(
                    &self.original,
                    &self.index,
                    simplified,
                    &simplified_index,
                    &self.params.hausdorff,
                )
            },
            || (triangle_quality(simplified), analyze(simplified)),
        );
        let (hausdorff, forward_normals, backward_normals) = distances?;
        // Both point sets are non-empty, so vertex_errors returns Some.
        let vertex = vertex_errors(&self.points, &simplified_points)
            .ok_or(MetricsError::NoVertices { mesh: "simplified" })?;
        Ok(assemble(
            (hausdorff, forward_normals, backward_normals),
            vertex,
            surface_error(&self.original, simplified),
            Pair {
                original: self.quality.clone(),
                simplified: quality_s,
            },
            Pair {
                original: self.topology,
                simplified: topology_s,
            },
            Pair {
                original: self.summary,
                simplified: summary(simplified, simplified_points.len()),
            },
            start,
        ))
    }
}

/// Computes every metric of `simplified` against `original` (one-off [`Evaluator`]).
///
/// Both meshes need at least one triangle, valid indices and finite coordinates, and the
/// simplified mesh must lie within [`crate::MAX_SPAN`] bounding-box diagonals of the original.
pub fn evaluate(
    original: &TriMesh,
    simplified: &TriMesh,
    params: &MetricsParams,
) -> Result<MetricsReport, MetricsError> {
    evaluate_with(original, simplified, params, None)
}

/// [`evaluate`] that another thread can stop: once `cancel` is set the call returns
/// [`MetricsError::Cancelled`] at its next check (between the steps, and per batch of a few
/// thousand samples in the surface distance), never a partial report. Not cancelled, the
/// report is [`evaluate`]'s.
pub fn evaluate_cancellable(
    original: &TriMesh,
    simplified: &TriMesh,
    params: &MetricsParams,
    cancel: &Cancel,
) -> Result<MetricsReport, MetricsError> {
    evaluate_with(original, simplified, params, Some(cancel))
}

/// [`evaluate`] and [`evaluate_cancellable`].
fn evaluate_with(
    original: &TriMesh,
    simplified: &TriMesh,
    params: &MetricsParams,
    cancel: Option<&Cancel>,
) -> Result<MetricsReport, MetricsError> {
    let start = Instant::now();
    check_cancel(cancel)?;
    params.hausdorff.validate()?;
    validate_mesh(original, "original")?;
    validate_mesh(simplified, "simplified")?;
    let original_points = referenced_positions(original);
    let simplified_points = referenced_positions(simplified);
    if original_points.is_empty() {
        return Err(MetricsError::NoTriangles { mesh: "original" });
    }
    if simplified_points.is_empty() {
        return Err(MetricsError::NoTriangles { mesh: "simplified" });
    }
    // The pipelined path overlaps the original's index build with sampling; it gives the same
    // numbers as `Evaluator::evaluate` (same samples, same seeds; tested).
    let (hausdorff, forward_normals, backward_normals) =
        hausdorff_pipelined(original, simplified, &params.hausdorff, cancel)?;
    let vertex = vertex_errors(&original_points, &simplified_points)
        .ok_or(MetricsError::NoVertices { mesh: "simplified" })?;
    check_cancel(cancel)?;
    let ((quality_o, quality_s), (topology_o, topology_s)) = rayon::join(
        || (triangle_quality(original), triangle_quality(simplified)),
        || (analyze(original), analyze(simplified)),
    );
    check_cancel(cancel)?;
    let area = surface_error(original, simplified);
    check_cancel(cancel)?;
    Ok(assemble(
        (hausdorff, forward_normals, backward_normals),
        vertex,
        area,
        Pair {
            original: quality_o,
            simplified: quality_s,
        },
        Pair {
            original: topology_o,
            simplified: topology_s,
        },
        Pair {
            original: summary(original, original_points.len()),
            simplified: summary(simplified, simplified_points.len()),
        },
        start,
    ))
}

/// The one place a [`MetricsReport`] is put together from its measured parts (both evaluation
/// paths, [`Evaluator::evaluate`] and [`evaluate`], end here).
fn assemble(
    (hausdorff, forward, backward): (Hausdorff, NormalDeviation, NormalDeviation),
    vertex: VertexErrors,
    area: SurfaceError,
    quality: Pair<TriangleQuality>,
    topology: Pair<TopologyReport>,
    meshes: Pair<MeshSummary>,
    start: Instant,
) -> MetricsReport {
    MetricsReport {
        e_avg: vertex.e_avg,
        e_max: vertex.e_max,
        e_sur_signed: area.e_sur_signed,
        e_sur_abs: area.e_sur_abs,
        e_sur_relative: area.e_sur_relative,
        original_area: area.original_area,
        simplified_area: area.simplified_area,
        bbox_diagonal: hausdorff.bbox_diagonal,
        hausdorff,
        normal_deviation: NormalDeviations { forward, backward },
        quality,
        topology,
        meshes,
        seconds: start.elapsed().as_secs_f64(),
        attributes: None,
        image_error: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mesh::procedural::{icosphere, torus};

    #[test]
    fn evaluate_sphere_against_coarser_sphere() {
        let fine = icosphere(4);
        let coarse = icosphere(2);
        let params = MetricsParams {
            hausdorff: HausdorffParams::with_samples(50_000),
        };
        let r = evaluate(&fine, &coarse, &params).unwrap();
        // Coarse vertices are a subset of the fine ones (same subdivision scheme).
        assert_eq!(
            r.e_avg,
            vertex_errors(&fine.positions, &coarse.positions)
                .unwrap()
                .e_avg
        );
        assert!(
            r.e_sur_signed > 0.0,
            "the coarse inscribed sphere has less area"
        );
        assert!((r.e_sur_signed - (fine.area() - coarse.area())).abs() < 1e-12);
        assert_eq!(r.e_sur_abs, r.e_sur_signed.abs());
        assert!((r.original_area - r.simplified_area - r.e_sur_signed).abs() < 1e-12);
        assert!(r.hausdorff.max > 0.0 && r.hausdorff.max < 0.05);
        // Smooth sphere: normals deviate by at most about one coarse facet angle (~16°).
        assert!(r.normal_deviation.forward.max_degrees < 20.0);
        assert!(r.normal_deviation.forward.mean_degrees > 0.5);
        assert_eq!(r.topology.original.genus, Some(0));
        assert!(r.topology.simplified.closed);
        assert_eq!(r.meshes.simplified.faces, 320);
        let json = serde_json::to_value(&r).unwrap();
        for key in [
            "e_avg",
            "e_max",
            "e_sur_signed",
            "e_sur_abs",
            "bbox_diagonal",
        ] {
            assert!(json[key].is_number(), "{key}");
        }
        for dir in ["forward", "backward"] {
            for key in ["max", "mean", "rms"] {
                assert!(json["hausdorff"][dir][key].is_number());
            }
        }
    }

    #[test]
    fn flipped_faces_show_in_normal_deviation() {
        let m = torus(1.0, 0.3, 32, 16);
        let flipped = TriMesh::new(
            m.positions.clone(),
            m.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
        );
        let params = MetricsParams {
            hausdorff: HausdorffParams::with_samples(20_000),
        };
        let r = evaluate(&m, &flipped, &params).unwrap();
        assert!(r.hausdorff.max < 1e-5);
        assert!(r.normal_deviation.forward.mean_degrees > 179.0);
        assert_eq!(r.topology.original.genus, Some(1));
    }
}

#[cfg(test)]
mod evaluator_tests {
    use super::*;
    use mesh::procedural::{icosphere, torus};

    #[test]
    fn evaluator_gives_the_same_numbers_as_evaluate() {
        let original = torus(1.0, 0.3, 48, 24);
        let params = MetricsParams {
            hausdorff: HausdorffParams::with_samples(30_000),
        };
        let evaluator = Evaluator::new(&original, &params).unwrap();
        for simplified in [torus(1.0, 0.3, 24, 12), torus(1.0, 0.28, 16, 8)] {
            let a = evaluator.evaluate(&simplified).unwrap();
            let b = evaluate(&original, &simplified, &params).unwrap();
            let strip = |mut r: MetricsReport| {
                r.seconds = 0.0;
                r
            };
            assert_eq!(strip(a), strip(b));
        }
    }

    #[test]
    fn bad_sample_counts_are_errors_not_zeros_or_aborts() {
        let m = icosphere(2);
        for samples in [0usize, 10_000_000_000] {
            let params = MetricsParams {
                hausdorff: HausdorffParams::with_samples(samples),
            };
            let e = evaluate(&m, &m, &params).unwrap_err();
            assert!(
                matches!(
                    e,
                    MetricsError::Parameter {
                        name: "samples",
                        ..
                    }
                ),
                "{e}"
            );
            assert!(Evaluator::new(&m, &params).is_err());
            if samples > 0 {
                assert!(e.to_string().contains("50000000"), "{e}");
            }
        }
        let e = evaluate(
            &m,
            &m,
            &MetricsParams {
                hausdorff: HausdorffParams::meshlab(30_000_000),
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("25000000"), "{e}");
    }

    #[test]
    fn meshlab_plan_draws_all_vertices_plus_n_edges_plus_n_faces() {
        let original = icosphere(3); // 642 vertices
        let simplified = icosphere(2); // 162 vertices
        let params = MetricsParams {
            hausdorff: HausdorffParams::meshlab(5_000),
        };
        let r = evaluate(&original, &simplified, &params).unwrap();
        let (f, b) = (&r.hausdorff.forward, &r.hausdorff.backward);
        assert_eq!(f.vertex_samples, 642);
        assert_eq!(b.vertex_samples, 162);
        assert_eq!(f.face_samples, 5_000);
        assert_eq!(b.face_samples, 5_000);
        assert!(f.edge_samples.abs_diff(5_000) <= 16, "{}", f.edge_samples);
        assert!(b.edge_samples.abs_diff(5_000) <= 16, "{}", b.edge_samples);
        assert_eq!(
            f.samples,
            f.vertex_samples + f.edge_samples + f.face_samples
        );
    }
}

//! [`evaluate`]: every metric of a simplification in one serde-serializable [`MetricsReport`].

use crate::hausdorff::{Hausdorff, HausdorffParams, NormalDeviation, hausdorff_pipelined};
use crate::paper::{surface_error, vertex_errors};
use crate::quality::{TriangleQuality, triangle_quality};
use crate::{MetricsError, validate_mesh};
use glam::Vec3;
use mesh::TriMesh;
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
    /// Paper E_sur = S_K − S_A, squared model units (signed).
    pub e_sur: f64,
    /// |E_sur|, squared model units.
    pub e_sur_abs: f64,
    /// |E_sur| / S_K.
    pub e_sur_relative: f64,
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
    /// Wall-clock time of the evaluation, seconds.
    pub seconds: f64,
}

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

/// Computes every metric of `simplified` against `original`.
///
/// Both meshes need at least one triangle, valid indices and finite coordinates.
pub fn evaluate(
    original: &TriMesh,
    simplified: &TriMesh,
    params: &MetricsParams,
) -> Result<MetricsReport, MetricsError> {
    let start = Instant::now();
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
    let (hausdorff, forward_normals, backward_normals) =
        hausdorff_pipelined(original, simplified, &params.hausdorff)?;
    // Both point sets are non-empty, so vertex_errors returns Some.
    let vertex = vertex_errors(&original_points, &simplified_points)
        .ok_or(MetricsError::NoVertices { mesh: "simplified" })?;
    let area = surface_error(original, simplified);
    let ((quality_o, quality_s), (topology_o, topology_s)) = rayon::join(
        || (triangle_quality(original), triangle_quality(simplified)),
        || (analyze(original), analyze(simplified)),
    );
    Ok(MetricsReport {
        e_avg: vertex.e_avg,
        e_max: vertex.e_max,
        e_sur: area.e_sur,
        e_sur_abs: area.e_sur_abs,
        e_sur_relative: area.e_sur_relative,
        bbox_diagonal: hausdorff.bbox_diagonal,
        hausdorff,
        normal_deviation: NormalDeviations {
            forward: forward_normals,
            backward: backward_normals,
        },
        quality: Pair {
            original: quality_o,
            simplified: quality_s,
        },
        topology: Pair {
            original: topology_o,
            simplified: topology_s,
        },
        meshes: Pair {
            original: summary(original, original_points.len()),
            simplified: summary(simplified, simplified_points.len()),
        },
        seconds: start.elapsed().as_secs_f64(),
    })
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
        assert!(r.e_sur > 0.0, "the coarse inscribed sphere has less area");
        assert!((r.e_sur - (fine.area() - coarse.area())).abs() < 1e-12);
        assert!(r.hausdorff.max > 0.0 && r.hausdorff.max < 0.05);
        // Smooth sphere: normals deviate by at most about one coarse facet angle (~16°).
        assert!(r.normal_deviation.forward.max_degrees < 20.0);
        assert!(r.normal_deviation.forward.mean_degrees > 0.5);
        assert_eq!(r.topology.original.genus, Some(0));
        assert!(r.topology.simplified.closed);
        assert_eq!(r.meshes.simplified.faces, 320);
        let json = serde_json::to_value(&r).unwrap();
        for key in ["e_avg", "e_max", "e_sur", "bbox_diagonal"] {
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

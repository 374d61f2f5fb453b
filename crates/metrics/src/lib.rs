//! Error metrics for simplified meshes: the GNG3D paper's E_avg/E_max/E_sur and Metro-style
//! symmetric surface distance, plus normal deviation, triangle quality and topology.
//!
//! - [`vertex_errors`] / [`NearestVertexIndex`]: the paper's vertex-to-nearest-vertex errors
//!   (squared units), usable on bare point sets during training.
//! - [`surface_error`]: the paper's area difference E_sur.
//! - [`hausdorff`]: Metro-style two-sided sampled surface distance (max / mean / RMS per
//!   direction, symmetric Hausdorff), exact closest points through [`SurfaceDistanceIndex`].
//! - [`Evaluator`] / [`evaluate`]: everything above in one serde-serializable record,
//!   [`MetricsReport`] (alias [`Evaluation`]), with the original indexed once.
//!
//! ```
//! use metrics::{HausdorffParams, hausdorff, surface_error, vertex_errors};
//! let fine = mesh::procedural::icosphere(4);
//! let coarse = mesh::procedural::icosphere(2);
//! // The paper's errors: squared vertex-to-nearest-vertex distances, and the area lost.
//! let v = vertex_errors(&fine.positions, &coarse.positions).unwrap();
//! assert!(v.e_max >= v.e_avg && v.e_avg > 0.0);
//! assert!(surface_error(&fine, &coarse).e_sur_signed > 0.0); // inscribed: smaller area
//! // Metro-style distance: the coarse sphere's flat faces sag at most 1 - cos(angle) inside.
//! let h = hausdorff(&fine, &coarse, &HausdorffParams::with_samples(20_000)).unwrap();
//! assert!(h.max > 0.0 && h.max < 0.05 && h.mean < h.max);
//! ```

mod closest;
mod hausdorff;
mod index;
pub mod paper;
mod quality;
mod report;

pub use closest::{closest_point_segment, closest_point_triangle};
pub use hausdorff::{
    DistanceStats, Hausdorff, HausdorffParams, MAX_SAMPLES_PER_DIRECTION, NormalDeviation,
    OneSided, SamplingPlan, hausdorff, hausdorff_indexed, one_sided,
};
pub use index::{ClosestPoint, SurfaceDistanceIndex};
pub use mesh::sampling::{EdgeSampling, FaceSampling};
pub use paper::{NearestVertexIndex, SurfaceError, VertexErrors, surface_error, vertex_errors};
pub use quality::{AspectBin, TriangleQuality, triangle_quality};
pub use report::{
    Evaluation, Evaluator, MeshSummary, MetricsParams, MetricsReport, NormalDeviations, Pair,
    evaluate,
};

use mesh::TriMesh;
use mesh::sampling::SamplingError;

/// Why metrics could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MetricsError {
    /// The mesh has no triangles (a surface distance needs at least one).
    #[error("the {mesh} mesh has no triangles")]
    NoTriangles {
        /// Which mesh ("original", "simplified", "source" or "target").
        mesh: &'static str,
    },
    /// The mesh has no vertices.
    #[error("the {mesh} mesh has no vertices")]
    NoVertices {
        /// Which mesh.
        mesh: &'static str,
    },
    /// A referenced vertex lies so far out that squared distances would overflow the f32
    /// closest-point search (|coordinate| above `limit`).
    #[error(
        "the {mesh} mesh has vertex {vertex} with a coordinate beyond ±{limit:e}; distances that \
         large cannot be measured (rescale the model)"
    )]
    CoordinateRange {
        /// Which mesh.
        mesh: &'static str,
        /// The offending vertex.
        vertex: usize,
        /// Largest accepted |coordinate|, model units.
        limit: f64,
    },
    /// A parameter is out of range.
    #[error("{name}: {message}")]
    Parameter {
        /// The parameter.
        name: &'static str,
        /// What is wrong, with the accepted range.
        message: String,
    },
    /// Every sample of one direction was excluded (no target point within `max_distance`).
    #[error("the {direction} distance has no sample within max_distance ({excluded} excluded)")]
    NoSamplesCounted {
        /// Which direction.
        direction: &'static str,
        /// Samples excluded.
        excluded: usize,
    },
    /// The mesh is malformed (bad index, non-finite coordinate) or has no area to sample.
    #[error("the {mesh} mesh cannot be sampled: {problem}")]
    Invalid {
        /// Which mesh.
        mesh: &'static str,
        /// The underlying problem (in the message, not repeated as an error source).
        problem: SamplingError,
    },
}

/// Largest |coordinate| the distance computations accept, model units: the closest-point
/// search compares squared distances in f32 (max ≈ 3.4e38), so two points may be at most about
/// 1.8e19 apart; 1e18 leaves room for three axes and rounding.
pub const MAX_COORDINATE: f64 = 1e18;

/// Checks indices and coordinates of `mesh`, naming it `which` in the error.
pub(crate) fn validate_mesh(mesh: &TriMesh, which: &'static str) -> Result<(), MetricsError> {
    mesh::sampling::validate(mesh).map_err(|problem| MetricsError::Invalid {
        mesh: which,
        problem,
    })?;
    let limit = MAX_COORDINATE as f32;
    for &v in mesh.triangles.iter().flatten() {
        let p = mesh.positions[v as usize];
        if p.abs().max_element() > limit {
            return Err(MetricsError::CoordinateRange {
                mesh: which,
                vertex: v as usize,
                limit: MAX_COORDINATE,
            });
        }
    }
    Ok(())
}

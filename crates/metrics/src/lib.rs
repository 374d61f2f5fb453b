//! Error metrics for simplified meshes: the GNG3D paper's E_avg/E_max/E_sur and Metro-style
//! symmetric surface distance, plus normal deviation, triangle quality and topology.
//!
//! - [`vertex_errors`] / [`NearestVertexIndex`]: the paper's vertex-to-nearest-vertex errors
//!   (squared units), usable on bare point sets during training.
//! - [`surface_error`]: the paper's area difference E_sur.
//! - [`hausdorff`]: Metro-style two-sided sampled surface distance (max / mean / RMS per
//!   direction, symmetric Hausdorff), exact closest points through [`SurfaceDistanceIndex`].
//! - [`attribute_deviation`]: Metro-style deviation of texture coordinates (UV units and
//!   texels), normals (degrees) and colours (RGB) between the two surfaces, both directions.
//! - [`image_error`]: what a player sees: both meshes rendered (texture, checker, vertex
//!   colours or white, lit) from 14 fixed views by a deterministic CPU rasterizer, compared per
//!   pixel (RMSE, PSNR, share of pixels off, silhouette mismatch).
//! - [`Evaluator`] / [`evaluate`]: everything above in one serde-serializable record,
//!   [`MetricsReport`] (alias [`Evaluation`]), with the original indexed once.
//!
//! ```
//! use gng3d_metrics::{HausdorffParams, hausdorff, surface_error, vertex_errors};
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

mod attributes;
mod closest;
mod frame;
mod hausdorff;
mod index;
pub mod paper;
mod quality;
mod render;
mod report;
mod sliver;
mod walk;

pub use attributes::{
    AngleDeviation, AttributeDeviation, AttributeErrors, AttributeParams, TIE, UvDeviation,
    attribute_deviation,
};
pub use closest::{closest_point_segment, closest_point_triangle};
pub use frame::MAX_SPAN;
pub use hausdorff::{
    DistanceStats, Hausdorff, HausdorffParams, MAX_SAMPLES_PER_DIRECTION, NormalDeviation,
    OneSided, SamplingPlan, hausdorff, hausdorff_indexed, one_sided,
};
pub use index::{ClosestPoint, SurfaceDistanceIndex};
pub use mesh::sampling::{EdgeSampling, FaceSampling};
pub use paper::{NearestVertexIndex, SurfaceError, VertexErrors, surface_error, vertex_errors};
pub use quality::{AspectBin, TriangleQuality, triangle_quality};
pub use render::{
    AMBIENT, CHECKER_SQUARE, CHECKER_VALUES, DIFFERENCE_GAIN, ImageError, ImageErrorParams,
    ImageStats, MAX_IMAGE_SIZE, Shading, Surface, Texture, VIEWS, ViewError, ViewImages,
    image_error, image_error_with_images,
};
pub use report::{
    Evaluation, Evaluator, MeshSummary, MetricsParams, MetricsReport, NormalDeviations, Pair,
    evaluate, evaluate_cancellable,
};

use mesh::TriMesh;
use mesh::cancel::Cancel;
use mesh::sampling::SamplingError;

/// Why metrics could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
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
    /// A vertex lies so far from the other mesh, measured in that mesh's size, that squared
    /// distances would overflow the f32 closest-point search of the frame distances are measured
    /// in (see [`MAX_SPAN`]): more than `limit` bounding-box diagonals of the other mesh (the
    /// original in a pair) away.
    #[error(
        "the {mesh} mesh has vertex {vertex} more than {limit:e} times the other mesh's \
         bounding-box diagonal away from it; distances across such a span cannot be measured \
         (are the two meshes in the same units?)"
    )]
    CoordinateRange {
        /// Which mesh.
        mesh: &'static str,
        /// The offending vertex.
        vertex: usize,
        /// Largest accepted distance, in (power-of-two rounded) bounding-box diagonals.
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
    /// The attributes do not fit their mesh (see [`mesh::attributes::Attributes::validate`]).
    #[error("the attributes of the {mesh} mesh do not fit it: {problem}")]
    Attributes {
        /// Which mesh.
        mesh: &'static str,
        /// What does not fit.
        problem: String,
    },
    /// A texture image cannot be used (unreadable, or not a PNG image).
    #[error("texture {file}: {problem}")]
    Texture {
        /// The image file, or what else it came from.
        file: String,
        /// What is wrong.
        problem: String,
    },
    /// The mesh is malformed (bad index, non-finite coordinate) or has no area to sample.
    #[error("the {mesh} mesh cannot be sampled: {problem}")]
    Invalid {
        /// Which mesh.
        mesh: &'static str,
        /// The underlying problem (in the message, not repeated as an error source).
        problem: SamplingError,
    },
    /// The measurement was stopped through its cancel flag ([`evaluate_cancellable`],
    /// [`Surface::with_cancel`]).
    #[error("the measurement was cancelled")]
    Cancelled,
}

/// [`MetricsError::Cancelled`] when `cancel` is given and set.
pub(crate) fn check_cancel(cancel: Option<&Cancel>) -> Result<(), MetricsError> {
    if cancel.is_some_and(Cancel::is_cancelled) {
        Err(MetricsError::Cancelled)
    } else {
        Ok(())
    }
}

/// Checks indices and that referenced coordinates are finite, naming the mesh `which` in the
/// error. Any finite f32 coordinate is accepted: distances are searched in a frame scaled to
/// the original (see [`MAX_SPAN`] for how far apart two meshes may be).
pub(crate) fn validate_mesh(mesh: &TriMesh, which: &'static str) -> Result<(), MetricsError> {
    mesh::sampling::validate(mesh).map_err(|problem| MetricsError::Invalid {
        mesh: which,
        problem,
    })
}

/// Checks that every vertex record of `mesh`, unreferenced ones included, is finite (what a
/// plan sampling every vertex, [`SamplingPlan::MeshLab`], needs).
pub(crate) fn validate_all_vertices(
    mesh: &TriMesh,
    which: &'static str,
) -> Result<(), MetricsError> {
    match mesh.positions.iter().position(|p| !p.is_finite()) {
        Some(vertex) => Err(MetricsError::Invalid {
            mesh: which,
            problem: SamplingError::NonFinite { vertex },
        }),
        None => Ok(()),
    }
}

//! Error metrics for simplified meshes: the GNG3D paper's E_avg/E_max/E_sur and Metro-style
//! symmetric surface distance, plus normal deviation, triangle quality and topology.
//!
//! - [`vertex_errors`] / [`NearestVertexIndex`]: the paper's vertex-to-nearest-vertex errors
//!   (squared units), usable on bare point sets during training.
//! - [`surface_error`]: the paper's area difference E_sur.
//! - [`hausdorff`]: Metro-style two-sided sampled surface distance (max / mean / RMS per
//!   direction, symmetric Hausdorff), exact closest points through [`SurfaceDistanceIndex`].
//! - [`evaluate`]: everything above in one serde-serializable [`MetricsReport`].

mod closest;
mod hausdorff;
mod index;
pub mod paper;
mod quality;
mod report;

pub use closest::{closest_point_segment, closest_point_triangle};
pub use hausdorff::{
    DistanceStats, Hausdorff, HausdorffParams, NormalDeviation, OneSided, hausdorff,
    hausdorff_indexed, one_sided,
};
pub use index::{ClosestPoint, SurfaceDistanceIndex};
pub use mesh::sampling::{EdgeSampling, FaceSampling};
pub use paper::{NearestVertexIndex, SurfaceError, VertexErrors, surface_error, vertex_errors};
pub use quality::{AspectBin, TriangleQuality, triangle_quality};
pub use report::{MeshSummary, MetricsParams, MetricsReport, NormalDeviations, Pair, evaluate};

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
    /// The mesh is malformed (bad index, non-finite coordinate) or has no area to sample.
    #[error("the {mesh} mesh cannot be sampled: {source}")]
    Invalid {
        /// Which mesh.
        mesh: &'static str,
        /// The underlying problem.
        #[source]
        source: SamplingError,
    },
}

/// Checks indices and coordinates of `mesh`, naming it `which` in the error.
pub(crate) fn validate_mesh(mesh: &TriMesh, which: &'static str) -> Result<(), MetricsError> {
    mesh::sampling::validate(mesh).map_err(|source| MetricsError::Invalid {
        mesh: which,
        source,
    })
}

//! Errors of GNG3D training and simplification.

use crate::trainer::StopReason;
use thiserror::Error;

/// Why GNG3D could not run on the given mesh and parameters.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum GngError {
    /// Fewer than three distinct referenced vertices: nothing to approximate.
    #[error("the mesh has {vertices} distinct referenced vertices; GNG3D needs at least 3")]
    TooFewVertices {
        /// Distinct referenced vertices found.
        vertices: usize,
    },
    /// The target vertex count is below 3, or above the number of distinct input vertices when
    /// signals are drawn from the vertices.
    #[error(
        "target of {target} vertices is out of range: it must be between 3 and the {available} distinct input vertices"
    )]
    Target {
        /// Requested target.
        target: usize,
        /// Distinct referenced vertices of the input.
        available: usize,
    },
    /// A parameter is outside its valid range (see [`crate::GngParams::validate`]).
    #[error("parameter {name} = {value} is out of range (see the GngParams docs for its range)")]
    Parameter {
        /// Field name in `GngParams`.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("face {face} refers to a vertex index beyond the vertex list")]
    BadIndex {
        /// Offending face index.
        face: usize,
    },
    /// A vertex position is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFinite {
        /// Offending vertex index.
        vertex: usize,
    },
    /// Surface signals were requested but every triangle has zero area.
    #[error("surface sampling needs a mesh with positive area")]
    ZeroArea,
    /// Training ended with fewer than three nodes, so there is no mesh (typically a time limit
    /// shorter than the set-up, or a cancel right after the start).
    #[error(
        "training stopped ({stop:?}) with {nodes} nodes, too few for a mesh; give it more time or signals"
    )]
    TooFewNodes {
        /// Nodes when training stopped.
        nodes: usize,
        /// Why it stopped.
        stop: Option<StopReason>,
    },
    /// The reconstruction produced no triangle (e.g. the input is a set of slivers).
    #[error(
        "the reconstruction from {nodes} nodes produced no triangle: the input has no surface GNG3D can rebuild"
    )]
    EmptyMesh {
        /// Trained nodes.
        nodes: usize,
    },
    /// The decimator of an oversampled run failed.
    #[error("decimating the network's mesh failed: {reason}")]
    Decimation {
        /// The decimator's message.
        reason: String,
    },
}

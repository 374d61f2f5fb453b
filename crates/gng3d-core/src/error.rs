//! Errors of GNG3D training and simplification.

use crate::train::StopReason;
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
    /// An option or parameter is outside its valid range ([`crate::GngOptions::validate`],
    /// [`crate::GngParams::validate`]).
    #[error("parameter {parameter} = {value} is out of range: {rule}")]
    Parameter {
        /// Which option or parameter.
        parameter: GngParameter,
        /// The offending value (counts and durations as `f64`).
        value: f64,
        /// The rule it breaks, for a person (e.g. `"must be in (0, 1]"`).
        rule: &'static str,
    },
    /// The attributes given with the mesh do not fit it
    /// ([`mesh::attributes::Attributes::validate`]).
    #[error("the attributes do not fit the mesh: {0}")]
    Attributes(String),
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
    /// The QEM decimation of an oversampled run failed (GNG3D-Q's [`crate::Step::Decimate`]).
    #[error("decimating the network's mesh failed: {0}")]
    Decimation(#[source] qem::QemError),
    /// The steps after training were stopped through the cancel flag given to
    /// [`crate::finish_cancellable`].
    #[error("GNG3D's steps after training were cancelled")]
    Cancelled,
}

/// The option or parameter a [`GngError::Parameter`] names: a field of [`crate::GngOptions`]
/// or [`crate::GngParams`] (`Display` gives the name a person reads, e.g. `time limit`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum GngParameter {
    /// [`crate::GngTarget::VertexRatio`]: in (0, 1].
    TargetRatio,
    /// [`crate::GngOptions::target`] / [`crate::GngParams::target_vertices`] with surface
    /// signals: at most 16 times the input's vertices.
    TargetVertices,
    /// [`crate::GngOptions::time_limit_seconds`] / [`crate::GngParams::time_limit`]: finite, > 0.
    TimeLimit,
    /// [`crate::GngOptions::max_signals`] / [`crate::GngParams::max_signals`]: 1 to 10¹⁰
    /// signals, and not together with `epochs`.
    MaxSignals,
    /// [`crate::GngOptions::epochs`] / [`crate::GngParams::epochs`]: finite, > 0, at most 10¹⁰
    /// signals in all.
    Epochs,
    /// [`crate::GngOptions::lambda`] / [`crate::GngParams::lambda`]: at least 1.
    Lambda,
    /// [`crate::GngOptions::eps_winner`] / [`crate::GngParams::eps_winner`]: in [0, 1].
    EpsWinner,
    /// [`crate::GngOptions::eps_neighbour`] / [`crate::GngParams::eps_neighbour`]: in [0, 1].
    EpsNeighbour,
    /// [`crate::GngOptions::oversample`]: in [1, 4].
    Oversample,
    /// [`crate::GngOptions::detail_rounds`]: at most 8.
    DetailRounds,
    /// [`crate::GngOptions::threads`] / [`crate::GngParams::threads`]: at least 1.
    Threads,
    /// [`crate::GngParams::alpha`]: in [0, 1].
    Alpha,
    /// [`crate::GngParams::error_decay`]: in (0, 1].
    ErrorDecay,
    /// [`crate::GngParams::removal_window`]: finite, ≥ 0.
    RemovalWindow,
    /// [`crate::GngParams::max_edge_age`]: at least 1.
    MaxEdgeAge,
    /// [`crate::GngParams::network_vertices`]: at least `target_vertices`.
    NetworkVertices,
    /// [`crate::ReconstructionParams::max_hole_edges`]: at most 2²⁰.
    MaxHoleEdges,
}

impl GngParameter {
    /// The name a person reads (the `Display` text).
    pub fn name(self) -> &'static str {
        match self {
            GngParameter::TargetRatio => "target ratio",
            GngParameter::TargetVertices => "target vertices",
            GngParameter::TimeLimit => "time limit",
            GngParameter::MaxSignals => "signal budget",
            GngParameter::Epochs => "epochs",
            GngParameter::Lambda => "lambda",
            GngParameter::EpsWinner => "eps_winner",
            GngParameter::EpsNeighbour => "eps_neighbour",
            GngParameter::Oversample => "oversample",
            GngParameter::DetailRounds => "detail rounds",
            GngParameter::Threads => "threads",
            GngParameter::Alpha => "alpha",
            GngParameter::ErrorDecay => "error_decay",
            GngParameter::RemovalWindow => "removal_window",
            GngParameter::MaxEdgeAge => "max_edge_age",
            GngParameter::NetworkVertices => "network_vertices",
            GngParameter::MaxHoleEdges => "reconstruction.max_hole_edges",
        }
    }
}

impl std::fmt::Display for GngParameter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

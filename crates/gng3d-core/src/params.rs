//! Parameters of GNG3D training (phase 1) and reconstruction (phase 2), with documented defaults.

use serde::{Deserialize, Serialize};
use std::time::Duration;

/// Where training signals come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum SignalSource {
    /// Uniformly from the distinct referenced vertex positions (the GNG3D paper; exact duplicate
    /// positions count once, so unwelded input behaves like welded input).
    #[default]
    Vertices,
    /// Area-weighted uniform points on the surface (each signal picks a triangle with probability
    /// proportional to its area, then a uniform point inside it).
    Surface,
    /// Like `Surface`, with each face's area weighted up by the curvature the surface has over
    /// one output edge length (bounded to at most 4×; [`crate::features`]), so curved parts and
    /// creases get more nodes (GNG3D-Q option).
    Curvature,
}

/// Nearest/second-nearest node search used during training.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum SearchStrategy {
    /// Growing uniform grid (Fišer et al. 2013); near O(1) per query.
    #[default]
    Grid,
    /// Naive scan over all nodes, O(|A|) per query; the benchmark baseline.
    LinearScan,
}

/// How faces from the original mesh that map to the same node triple in opposite orientations
/// are resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum OppositeFaces {
    /// Keep one face, oriented like the majority of the original faces that mapped to it.
    #[default]
    KeepMajority,
    /// Drop both: a triple seen with both orientations is a collapsed thin sheet.
    DropBoth,
}

/// Phase-2 (reconstruction) options. The defaults give the "concordance" rule plus the cleanup
/// pass, quadric placement and edge flips (GNG3D-Q); [`ReconstructionParams::paper`] is the
/// published method.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReconstructionParams {
    /// Make every node's cell edge-connected on the original mesh before mapping faces (vertices
    /// cut off from the part of the cell nearest to the node join an adjacent cell). This
    /// prevents one node from joining two sheets of a thin part. Default `true`; `false` gives the
    /// plain nearest-node labels of the paper.
    pub connected_cells: bool,
    /// (a) Keep only triangles whose three nodes are pairwise GNG neighbours. Default `false`.
    pub require_gng_edges: bool,
    /// Resolution of triples seen in both orientations. Default [`OppositeFaces::KeepMajority`].
    pub opposite_faces: OppositeFaces,
    /// (b) Remove non-manifold fins (keep the two best-supported faces of every edge with more
    /// than two) and fill small holes. Default `true`.
    pub cleanup: bool,
    /// (b) Largest boundary loop, in edges, that the cleanup fills. Default 8 (0 disables filling).
    pub max_hole_edges: usize,
    /// (c) Where output vertices go (GNG3D-Q). Default [`Placement::Quadric`];
    /// [`Placement::Node`] is the paper's method.
    pub placement: Placement,
    /// (d) Error-driven edge flips after placement (GNG3D-Q): flip an interior edge when the
    /// two new triangles are clearly closer to the original vertices, keeping orientation,
    /// manifoldness and triangle shape. Default `true`.
    pub flip_edges: bool,
}

// --- GNG3D-Q (placement + flips) -------------------------------------------------------------

/// Where the output vertex of each node is placed (reconstruction option (c)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Placement {
    /// At the trained node (GNG3D as published: the centroid of its signals, which lies inside
    /// curved surfaces and off creases).
    Node,
    /// At the closest point to the node on the original faces touching its cell.
    Project,
    /// At the minimiser of the cell's summed Garland–Heckbert quadrics, solved from the
    /// projected point with small eigenvalues dropped; falls back to the projected point when
    /// that solution is not finite or lies more than two cell radii from the node.
    #[default]
    Quadric,
}

impl ReconstructionParams {
    /// The paper's reconstruction: defaults with node placement and no flips (what
    /// `reproduce` uses for the paper's columns).
    pub fn paper() -> ReconstructionParams {
        ReconstructionParams {
            placement: Placement::Node,
            flip_edges: false,
            ..ReconstructionParams::default()
        }
    }
}

impl Default for ReconstructionParams {
    fn default() -> Self {
        ReconstructionParams {
            connected_cells: true,
            require_gng_edges: false,
            opposite_faces: OppositeFaces::KeepMajority,
            cleanup: true,
            max_hole_edges: 8,
            placement: Placement::Quadric,
            flip_edges: true,
        }
    }
}

/// GNG3D parameters. Use [`GngParams::for_target`] and adjust fields as needed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GngParams {
    /// Target node (= output vertex) count N; insertion stops there and the count is held. At
    /// least 3; with [`SignalSource::Vertices`] at most the number of distinct input vertices.
    pub target_vertices: usize,
    /// λ: signals between insertions. `None` (default) picks
    /// `clamp(max_signals / (2 N), 1, 200)` so growth takes at most half of the signal budget.
    pub lambda: Option<u32>,
    /// ε_b: fraction of the way the winner moves toward each signal. Default 0.05 (Fišer 2013).
    pub eps_winner: f32,
    /// ε_n: fraction of the way the winner's neighbours move. Default 0.0006 (Fišer 2013).
    pub eps_neighbour: f32,
    /// α: factor applied to the errors of q and f at an insertion. Default 0.5 (Fritzke).
    pub alpha: f64,
    /// d: per-signal multiplicative decay of every node's error. Default 0.9995.
    pub error_decay: f64,
    /// a_max: edges older than this many winner steps are removed. Default 100.
    pub max_edge_age: u32,
    /// μ: nodes that won no signal during the last μ·|A| signals are removed (GNG3D).
    /// Default 30 (GNG3DI). 0 disables the rule.
    pub removal_window: f64,
    /// Signal budget. `None` (default) means 30 epochs of the signal-point count (the paper's
    /// protocol: 30 × distinct vertices).
    pub max_signals: Option<u64>,
    /// Wall-clock limit for training (phase 1). Default none.
    pub time_limit: Option<Duration>,
    /// Seed of the PCG random generator; equal seeds give identical results. Default 1.
    pub seed: u64,
    /// Where signals come from. Default [`SignalSource::Vertices`].
    pub signal_source: SignalSource,
    /// Nearest-node search. Default [`SearchStrategy::Grid`].
    pub search: SearchStrategy,
    /// Compute e_avg/e_max of the nodes against the original vertices for every
    /// [`crate::Progress`] report (costs a kd-tree build per report). Default `false`.
    pub track_errors: bool,
    /// Phase-2 options.
    pub reconstruction: ReconstructionParams,
}

impl Default for GngParams {
    fn default() -> Self {
        GngParams {
            target_vertices: 1000,
            lambda: None,
            eps_winner: 0.05,
            eps_neighbour: 0.0006,
            alpha: 0.5,
            error_decay: 0.9995,
            max_edge_age: 100,
            removal_window: 30.0,
            max_signals: None,
            time_limit: None,
            seed: 1,
            signal_source: SignalSource::Vertices,
            search: SearchStrategy::Grid,
            track_errors: false,
            reconstruction: ReconstructionParams::default(),
        }
    }
}

impl GngParams {
    /// Defaults with the given target vertex count.
    pub fn for_target(target_vertices: usize) -> GngParams {
        GngParams {
            target_vertices,
            ..GngParams::default()
        }
    }
}

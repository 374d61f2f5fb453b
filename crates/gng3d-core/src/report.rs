//! What a [`crate::simplify`] run reports: counters of both phases, the requested and delivered
//! vertex counts, and machine-readable warnings for everything that kept the output from being
//! exactly what was asked for.

use crate::train::TrainingStats;
use mesh::topology::TopologyReport;
#[cfg(feature = "serde")]
use serde::Serialize;
use std::fmt;

/// Why the output differs from the request (or what was left out of it). Serialised with a
/// `"kind"` tag in snake case, e.g. `{"kind":"dropped_components","components":3,...}`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
#[non_exhaustive]
pub enum GngWarning {
    /// Vertices farther than 1000 robust radii from their component's median gave no training
    /// signal (scanner outliers, corrupted coordinates).
    StrayVertices {
        /// Distinct vertices left out.
        vertices: usize,
    },
    /// Components too small for 3 nodes of the target (a triangle) were dropped; their share
    /// went to the kept ones.
    DroppedComponents {
        /// Components dropped.
        components: usize,
        /// Distinct vertices in them.
        vertices: usize,
        /// Components kept.
        kept: usize,
    },
    /// The kept components cannot hold the target (with vertex signals a component gets at
    /// most one node per distinct vertex).
    TargetAboveCapacity {
        /// Requested vertex count.
        target: usize,
        /// Most nodes the kept components can hold.
        capacity: usize,
    },
    /// The time limit ended training before the network reached its node count.
    TimeLimitBeforeTarget {
        /// Nodes when the limit struck.
        nodes: usize,
        /// Nodes the schedule aimed for.
        target: usize,
        /// The time limit, seconds.
        limit_seconds: f64,
    },
    /// Nodes that no reconstructed triangle could take (should not happen on closed inputs).
    UnattachedNodes {
        /// Nodes left out of the mesh.
        nodes: usize,
    },
    /// The time limit is below the minimum a run needs (the set-up, the fastest growth to N
    /// nodes and the required steps after it, as estimated); the run is
    /// the fastest one that gives N vertices, and it takes longer than the limit.
    TimeLimitBelowMinimum {
        /// The time limit, seconds.
        limit_seconds: f64,
        /// The estimated minimum, seconds.
        minimum_seconds: f64,
    },
    /// An optional step was left out of some or all of its runs (one per build round) to keep
    /// the time limit.
    StepSkippedForTime {
        /// The step.
        step: crate::Step,
        /// Runs left out.
        skipped: usize,
        /// Runs the run would have had without a time limit.
        planned: usize,
    },
    /// The network was not oversampled, to keep the time limit: it trained N nodes and its mesh
    /// is the output (no decimation).
    OversamplingSkippedForTime {
        /// The nodes the oversampled network would have had.
        network_vertices: usize,
    },
    /// The output has border edges where the input had none: the reconstruction left holes
    /// (the paper's reconstruction does at low ratios; docs/notes/gng.md).
    OpenedHoles {
        /// Border edges of the output.
        boundary_edges: usize,
        /// Border loops (holes) of the output.
        boundary_loops: usize,
    },
    /// The output's pieces or manifoldness differ from the input's: more connected
    /// components, or more non-manifold edges or vertices (a target too coarse for a thin part
    /// joins or splits it). Holes are [`GngWarning::OpenedHoles`].
    TopologyChanged {
        /// Connected components of the input and of the output.
        components: [usize; 2],
        /// Non-manifold edges (three or more faces) of the input and of the output.
        non_manifold_edges: [usize; 2],
        /// Non-manifold vertices of the input and of the output.
        non_manifold_vertices: [usize; 2],
    },
    /// The decimation of an oversampled run's network mesh stopped above the target: no
    /// further contraction keeps the mesh's topology (every hole and every piece keeps at
    /// least three vertices; a scan with many small holes can need more than the target).
    DecimationStopped {
        /// Vertices when the decimation stopped (the output's count).
        vertices: usize,
        /// Requested vertex count.
        target: usize,
    },
    /// The output does not follow the input's attribute seams ([`crate::Step::CutSeams`]):
    /// at this vertex count a decimation that keeps them would stand much farther from the
    /// original than one that does not, or could not reach the count (the seams' ends and
    /// crossings stay), so the output is the one that does not, and its triangles may straddle
    /// seams.
    SeamsNotFollowed {
        /// Mean distance to the original (at vertices, edge midpoints and face centroids) of
        /// the decimation along the seams over that of the one without them; `None`: it could
        /// not reach the count.
        ratio: Option<f64>,
    },
}

impl fmt::Display for GngWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GngWarning::StrayVertices { vertices } => write!(
                f,
                "{vertices} stray vertices (over {} robust radii from their piece) were ignored",
                crate::tuning::STRAY_RADII
            ),
            GngWarning::DroppedComponents {
                components,
                vertices,
                kept,
            } => write!(
                f,
                "{components} small components ({vertices} vertices) were too small for {} nodes and were dropped; {kept} kept",
                crate::tuning::MIN_COMPONENT_NODES
            ),
            GngWarning::TargetAboveCapacity { target, capacity } => write!(
                f,
                "target of {target} vertices cannot be held: the usable components hold at most {capacity}"
            ),
            GngWarning::TimeLimitBeforeTarget {
                nodes,
                target,
                limit_seconds,
            } => write!(
                f,
                "the time limit of {limit_seconds} s ended growth at {nodes} of {target} nodes"
            ),
            GngWarning::UnattachedNodes { nodes } => {
                write!(f, "{nodes} nodes could not be attached to the mesh")
            }
            GngWarning::TimeLimitBelowMinimum {
                limit_seconds,
                minimum_seconds,
            } => write!(
                f,
                "the time limit of {limit_seconds} s is below the {minimum_seconds:.3} s a run needs (growth to the vertex count plus the cheapest reconstruction); this is the fastest run with exactly that count"
            ),
            GngWarning::StepSkippedForTime {
                step,
                skipped,
                planned,
            } => write!(
                f,
                "step {step} was left out of {skipped} of its {planned} runs to keep the time limit"
            ),
            GngWarning::OversamplingSkippedForTime { network_vertices } => write!(
                f,
                "the network was not oversampled ({network_vertices} nodes, then decimated) to keep the time limit"
            ),
            GngWarning::OpenedHoles {
                boundary_edges,
                boundary_loops,
            } => write!(
                f,
                "the input is closed but the output has {boundary_loops} holes ({boundary_edges} border edges)"
            ),
            GngWarning::TopologyChanged {
                components: [ci, co],
                non_manifold_edges: [ei, eo],
                non_manifold_vertices: [vi, vo],
            } => write!(
                f,
                "the output's topology differs from the input's: {co} components (input {ci}), {eo} non-manifold edges (input {ei}), {vo} non-manifold vertices (input {vi})"
            ),
            GngWarning::DecimationStopped { vertices, target } => write!(
                f,
                "the decimation to {target} vertices stopped at {vertices}: no further contraction keeps the mesh's topology (holes and pieces keep three vertices each)"
            ),
            GngWarning::SeamsNotFollowed { ratio: Some(ratio) } => write!(
                f,
                "the output's triangles do not follow the texture seams: at this vertex count keeping them would put the surface {ratio:.1} times as far from the original; more vertices keep them"
            ),
            GngWarning::SeamsNotFollowed { ratio: None } => write!(
                f,
                "the output's triangles do not follow the texture seams: their ends and crossings alone need more vertices than asked for; more vertices keep them"
            ),
        }
    }
}

/// Report of a [`crate::simplify`] run.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct GngReport {
    /// Phase-1 counters.
    pub training: TrainingStats,
    /// Phase-2 counts and output topology.
    pub reconstruction: ReconstructionReport,
    /// Requested output vertex count N.
    pub target_vertices: usize,
    /// Vertices of the network's mesh before decimation (equals `vertices` unless the run was
    /// oversampled, [`crate::GngParams::network_vertices`]).
    pub network_vertices: usize,
    /// Output vertex count (equals `target_vertices` unless `warnings` says why not).
    pub vertices: usize,
    /// Output face count.
    pub faces: usize,
    /// Every step after training that ran, in order, with its time and what it changed.
    pub steps: Vec<crate::StepRecord>,
    /// Wall time of the whole run, seconds, from [`crate::Trainer::new`] to the result.
    pub seconds: f64,
    /// Everything that was dropped or kept the output from `target_vertices` vertices.
    pub warnings: Vec<GngWarning>,
}

/// One GNG3D run in a few flat fields: what `gng3d simplify --method gng --json` prints and
/// what the Python package's `report` holds (both build it here, so their fields cannot drift).
/// Names are lowercase as the CLI's flags are (`"placement": "quadric"`, `"signals":
/// "vertices"`).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct GngSummary {
    /// The method's name in the front end ("gng"; the Python package also says "paper").
    pub method: &'static str,
    /// Vertices of the mesh the run was given (after the front end's weld and cleaning; as
    /// QEM's report counts them).
    pub input_vertices: usize,
    /// Faces of the mesh the run was given.
    pub input_faces: usize,
    /// Output vertex count.
    pub vertices: usize,
    /// Output face count.
    pub faces: usize,
    /// Training signals processed (the paper's iterations).
    pub iterations: u64,
    /// Wall time of training plus the steps after it, seconds (loading and saving excluded).
    pub seconds: f64,
    /// Wall time of training, seconds.
    pub training_seconds: f64,
    /// Requested vertex count; `vertices` equals it unless `warnings` says why not.
    pub target_vertices: usize,
    /// Trained nodes (k × N when oversampled).
    pub nodes: usize,
    /// Oversampling factor k (1: the network's mesh is the output).
    pub oversample: f64,
    /// Vertices of the network's mesh before the QEM decimation (equals `vertices` when k = 1).
    pub network_vertices: usize,
    /// Vertex placement used ("node": the paper, "project", "quadric": GNG3D-Q).
    pub placement: crate::Placement,
    /// Where the training signals came from ("vertices": the paper, "surface", "curvature").
    pub signals: crate::SignalSource,
    /// Whether the edge-flip pass ran.
    pub flips: bool,
    /// Whether the surface refit ran (quadric placement with refit on).
    pub refit: bool,
    /// Rounds of detail nodes (oversampled runs; 0: none).
    pub detail_rounds: usize,
    /// Nodes those rounds added where the mesh stayed farthest from the original.
    pub detail_nodes: usize,
    /// Whether the tangential relaxation after the decimation is on (it runs only when the
    /// network's mesh was decimated).
    pub relax: bool,
    /// Vertices it moved toward the original vertices they stand for.
    pub relaxed_vertices: usize,
    /// Whether the deviation repair after the decimation is on (it runs only when the
    /// network's mesh was decimated).
    pub repair_deviations: bool,
    /// Vertices it moved back onto the original.
    pub deviation_moves: usize,
    /// Edges it flipped.
    pub deviation_flips: usize,
    /// The triangle-shape pass after the decimation ([`crate::ReconstructionParams::shape`];
    /// it runs only when the network's mesh was decimated: step `shape`).
    pub shape: crate::Shape,
    /// Whether CAD creases are on ([`crate::ReconstructionParams::creases`]; they are cut along
    /// only on a CAD part: step `cut_seams`).
    pub creases: bool,
    /// The steps after training that ran, in order: name, build round, seconds and what each
    /// changed ([`crate::Plan`], [`crate::StepRecord`]).
    pub steps: Vec<crate::StepRecord>,
    /// Machine-readable reasons why the output differs from the request (empty when exact).
    pub warnings: Vec<GngWarning>,
    /// The output has no border edge.
    pub closed: bool,
    /// The output is manifold ([`mesh::topology::TopologyReport::manifold`]).
    pub manifold: bool,
    /// Genus of the output (None when undefined).
    pub genus: Option<i64>,
    /// Border edges of the output.
    pub boundary_edges: usize,
    /// Edges of the output with more than two faces.
    pub non_manifold_edges: usize,
}

impl GngSummary {
    /// The summary of `result`, the mesh [`crate::finish`] made from `trainer`'s network;
    /// `oversample` is [`crate::GngOptions::oversample_factor`] of the run's options and
    /// `seconds` the run's wall time as the front end measured it.
    pub fn new(
        method: &'static str,
        trainer: &crate::Trainer,
        oversample: f64,
        result: &crate::GngResult,
        seconds: f64,
    ) -> GngSummary {
        let params = trainer.params();
        let stats = trainer.stats();
        let r = &result.report.reconstruction;
        let t = &r.topology;
        GngSummary {
            method,
            input_vertices: trainer.original().vertex_count(),
            input_faces: trainer.original().face_count(),
            vertices: result.mesh.vertex_count(),
            faces: result.mesh.face_count(),
            iterations: stats.signals,
            seconds,
            training_seconds: stats.seconds,
            target_vertices: result.report.target_vertices,
            nodes: trainer.node_count(),
            oversample,
            network_vertices: result.report.network_vertices,
            placement: params.reconstruction.placement,
            signals: params.signal_source,
            flips: params.reconstruction.flip_edges,
            refit: params.reconstruction.refits(),
            detail_rounds: params.reconstruction.detail_rounds,
            detail_nodes: r.detail_nodes,
            relax: params.reconstruction.relax,
            relaxed_vertices: r.relaxed_vertices,
            repair_deviations: params.reconstruction.repair_deviations,
            deviation_moves: r.deviation_moves,
            deviation_flips: r.deviation_flips,
            shape: params.reconstruction.shape,
            creases: params.reconstruction.creases,
            steps: result.report.steps.clone(),
            warnings: result.report.warnings.clone(),
            closed: t.closed,
            manifold: t.manifold,
            genus: t.genus,
            boundary_edges: t.boundary_edges,
            non_manifold_edges: t.non_manifold_edges,
        }
    }
}

/// Face counts removed or added by each reconstruction step, and the output topology.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct ReconstructionReport {
    /// Faces of the original mesh.
    pub original_faces: usize,
    /// Original vertices moved to a neighbouring cell to make every node's cell edge-connected.
    pub relabelled_vertices: usize,
    /// Original faces whose corners fell on fewer than three distinct nodes.
    pub degenerate_faces: usize,
    /// Original faces dropped because another face mapped to the same node triple with the same
    /// orientation.
    pub duplicate_faces: usize,
    /// Original faces dropped because their triple was also produced with the opposite
    /// orientation (counted per dropped face).
    pub opposite_faces: usize,
    /// Triangles dropped by option (a) because a pair of their nodes is not a GNG edge.
    pub non_gng_faces: usize,
    /// Triangles dropped by the cleanup pass on edges with more than two faces.
    pub fin_faces: usize,
    /// Boundary loops closed by the cleanup pass.
    pub holes_filled: usize,
    /// Triangles added to close those loops.
    pub fill_faces: usize,
    /// Nodes added by option (f), splitting cells that broke the topology (0 unless
    /// [`crate::ReconstructionParams::split_bad_cells`]).
    pub split_cells: usize,
    /// Rounds of option (f) that split at least one cell.
    pub split_rounds: usize,
    /// Nodes added by option (g) where the mesh stayed farthest from the original (0 unless
    /// [`crate::ReconstructionParams::detail_rounds`]).
    pub detail_nodes: usize,
    /// Nodes that no mapped triangle referenced and that were inserted into the nearest
    /// output triangle (edge or face split) so that every node is an output vertex.
    pub attached_nodes: usize,
    /// Nodes that ended up in no triangle and were dropped (0 unless the mesh has no triangle
    /// near them).
    pub unreferenced_nodes: usize,
    /// Output vertices moved by the placement (option (c); 0 for `Placement::Node`).
    pub placed_vertices: usize,
    /// Edges flipped by option (d).
    pub flipped_edges: usize,
    /// Vertex moves of the surface refit, option (e), summed over its iterations.
    pub refit_moves: usize,
    /// Vertices moved by the tangential relaxation of the decimated mesh, option (h) (0 without
    /// a decimation).
    pub relaxed_vertices: usize,
    /// Vertices moved back onto the original by the deviation repair of the decimated mesh,
    /// option (i) (0 without a decimation).
    pub deviation_moves: usize,
    /// Edges flipped by the deviation repair, option (i).
    pub deviation_flips: usize,
    /// Output vertex count.
    pub vertices: usize,
    /// Output face count.
    pub faces: usize,
    /// Topology of the output.
    pub topology: TopologyReport,
    /// Time spent, seconds.
    pub seconds: f64,
}

impl ReconstructionReport {
    /// A report with every counter at zero, for an original of `original_faces` faces.
    pub(crate) fn empty(original_faces: usize) -> ReconstructionReport {
        ReconstructionReport {
            original_faces,
            relabelled_vertices: 0,
            degenerate_faces: 0,
            duplicate_faces: 0,
            opposite_faces: 0,
            non_gng_faces: 0,
            fin_faces: 0,
            holes_filled: 0,
            fill_faces: 0,
            split_cells: 0,
            split_rounds: 0,
            detail_nodes: 0,
            attached_nodes: 0,
            unreferenced_nodes: 0,
            placed_vertices: 0,
            flipped_edges: 0,
            refit_moves: 0,
            relaxed_vertices: 0,
            deviation_moves: 0,
            deviation_flips: 0,
            vertices: 0,
            faces: 0,
            topology: mesh::topology::analyze(&mesh::TriMesh::default()),
            seconds: 0.0,
        }
    }
}

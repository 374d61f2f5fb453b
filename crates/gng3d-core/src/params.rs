//! Parameters of GNG3D training (phase 1) and reconstruction (phase 2), with documented defaults.

use crate::error::{GngError, GngParameter};
#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};
use std::time::Duration;

/// Default signal budget per target node (when neither [`GngParams::max_signals`] nor
/// [`GngParams::epochs`] is set). Chosen from the quality-vs-budget curve in docs/notes/gng.md
/// (re-measured 2026-12-02): on 15 mesh/ratio rows the mean surface distance at 150 is within
/// 1.03× of 400's (median), the Hausdorff max shows no trend with the budget, and the GNG3D-Q
/// survey-style harness gives 1.83 / 1.82 / 1.81× QEM's mean distance at 150 / 250 / 400.
/// Not capped at the paper's 30 epochs: at 50 % of the vertices that cap left 60 signals per
/// node, and 150 instead took GNG3D-Q on four meshes from 2.92× to 2.53× QEM's mean distance
/// and from 35.0° to 37.5° median smallest angle (docs/notes/gng.md, "Uncapped budget, shape flips").
///
/// Per *output* vertex: an oversampled run ([`GngParams::network_vertices`]) spreads the same budget
/// over its larger network (100 per node at the default 1.5×). Against 150 per network node,
/// measured 2026-12-03 over 42 survey runs (all but igea-1m): median GNG3D-Q / QEM mean
/// distance 1.077 → 1.087, Hausdorff 1.33 → 1.20, E_avg / E_max / triangle-quality wins 40 /
/// 39 / 38 → 40 / 40 / 39; igea → 2,686 over five seeds: Hausdorff 1.43-2.67× (median 1.58)
/// → 1.47-2.61× (median 1.55) QEM's, mean distance +1.2 %, and a third less training time.
pub const DEFAULT_SIGNALS_PER_NODE: f64 = 150.0;

/// Epochs of the GNG3D paper's protocol (30 passes over the input vertices), for
/// [`GngParams::epochs`].
pub const PAPER_EPOCHS: f64 = 30.0;

/// Where training signals come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum SignalSource {
    /// Uniformly from the distinct referenced vertex positions (the GNG3D paper; exact duplicate
    /// positions count once, so unwelded input behaves like welded input).
    #[default]
    #[cfg_attr(feature = "serde", serde(alias = "Vertices"))]
    Vertices,
    /// Area-weighted uniform points on the surface (each signal picks a triangle with probability
    /// proportional to its area, then a uniform point inside it).
    #[cfg_attr(feature = "serde", serde(alias = "Surface"))]
    Surface,
    /// Like `Surface`, with each face's area weighted up by the curvature the surface has over
    /// one output edge length (bounded to at most 4×), so curved parts and
    /// creases get more nodes (GNG3D-Q option).
    #[cfg_attr(feature = "serde", serde(alias = "Curvature"))]
    Curvature,
}

/// Nearest/second-nearest node search used during training.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum SearchStrategy {
    /// Growing uniform grid (Fišer et al. 2013); near O(1) per query.
    #[default]
    #[cfg_attr(feature = "serde", serde(alias = "Grid"))]
    Grid,
    /// Naive scan over all nodes, O(|A|) per query; the benchmark baseline.
    #[cfg_attr(feature = "serde", serde(alias = "LinearScan"))]
    LinearScan,
}

/// How faces from the original mesh that map to the same node triple in opposite orientations
/// are resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
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
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
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
    /// (e) Surface refit after the flips (GNG3D-Q, [`Placement::Quadric`] only): move the output
    /// vertices so that the triangles, not only their corners, fit sampled points of the
    /// original (point-to-plane, kept near each vertex's cell quadric). Default `true`.
    pub refit: bool,
    /// (f) Split the cells that cannot give a faithful mesh (not a topological disc, e.g. an
    /// annulus around a thin tube; or along a hole the mapping made) and map again, for a few
    /// rounds. It adds nodes, so the mesh has more vertices than the network: it is for
    /// oversampled runs, whose decimation brings the count back: [`crate::GngOptions::resolve`]
    /// sets it, on when it oversamples and off otherwise (so that un-decimated runs keep the
    /// exact count). Default `false`.
    #[cfg_attr(feature = "serde", serde(default))]
    pub split_bad_cells: bool,
    /// (g) Rounds of detail nodes: build the mesh, add a node at the original vertex farthest
    /// from it in each of the worst cells (at most 5 % of the mesh's vertices a round), build
    /// again. It adds nodes like (f), so it is for oversampled runs: [`crate::GngOptions::resolve`]
    /// sets it (3 when it oversamples for an output of at least 5 % of the input's vertices, 0
    /// otherwise). Default 0 (off).
    #[cfg_attr(feature = "serde", serde(default))]
    pub detail_rounds: usize,
    /// (h) Tangential relaxation of the decimated mesh (oversampled runs only, after the
    /// decimation, [`crate::Step::Relax`]): each vertex moves half-way toward the centroid of the
    /// original vertices nearest to it, along the directions in which their faces are flat, so
    /// that it stands for them as the paper's nodes do (E_avg). Default `true`; it does
    /// nothing without a decimation, and [`crate::GngOptions::resolve`] turns it off for outputs of
    /// more than 30 % of the input's vertices.
    #[cfg_attr(feature = "serde", serde(default = "default_true"))]
    pub relax: bool,
    /// (i) Deviation repair of the decimated mesh (oversampled runs only, after the decimation
    /// and the relaxation, [`crate::Step::RepairDeviations`]): vertices standing off the
    /// original surface move back onto it and edges spanning a groove of it flip, where the
    /// output is farthest from the original. Default `true`; it does nothing without a decimation, and
    /// [`crate::GngOptions::resolve`] turns it off for outputs of less than 5 % of the input's
    /// vertices (like the detail rounds).
    #[cfg_attr(feature = "serde", serde(default = "default_true"))]
    pub repair_deviations: bool,
    /// (j) CAD creases: when the input's feature edges (dihedral angle above 45°) are a CAD
    /// part's share of its edges, the network's mesh is cut along them and decimated along
    /// them ([`crate::Step::CutSeams`]), so that crease lines and corners are output edges and
    /// vertices; that decimation is kept only where its largest distance to the original is
    /// not above the plain one's. Default `false`: measured (docs/notes/creases.md) it pays on
    /// a clean box (corners and edges exact) and on fandisk at 10 % (Hausdorff ×0.77), not on
    /// rocker-arm, casting or fandisk at 2 %, and it costs up to twice the time on the CAD
    /// parts (both decimations run) and 5× on a cylinder with fan caps.
    #[cfg_attr(feature = "serde", serde(default))]
    pub creases: bool,
    /// (k) Triangle shape of the decimated mesh (oversampled runs only, after the relaxation,
    /// [`crate::Step::Shape`]): edges flip toward valence 6 and vertices slide toward the
    /// centroid of their one-ring, along their tangent plane and back onto the original
    /// surface (keeping its offset from it), so that the decimation's slivers round out.
    /// [`Shape::Off`] by default; [`Shape`] gives the measured trade-off of each setting. It
    /// does nothing without a decimation.
    #[cfg_attr(feature = "serde", serde(default))]
    pub shape: Shape,
}

/// The triangle-shape pass after the decimation ([`ReconstructionParams::shape`]): the one
/// knob along the trade-off between the remeshers' triangles and the surface distance.
/// Measured on armadillo, igea and the bunny at 2 and 10 % of the vertices, one run each
/// (docs/results.md, 2026-12-08 "GNG3D-Q, ACVD and Instant Meshes"; docs/notes/shape.md), as
/// median smallest angle / share of triangles under 20° / mean distance × QEM's: `Off` 37-41° /
/// 1.7-5.6 % / 0.83-1.02; `Fit` 39.5-43.4° / 0.6-2.7 % / 0.86-1.08 at the same Hausdorff
/// distance except igea (1.48 → 1.67 × QEM's at 10 %); `Round` 43-47° / 0.0-1.6 % / 1.05-1.52,
/// Hausdorff up to 2.8 × QEM's. ACVD: 47-51° / 0 %, at 2.2-3.6 × GNG3D-Q's mean distance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Shape {
    /// No pass: the decimation's triangles (default).
    #[default]
    Off,
    /// Rounder triangles where that keeps the surface: a smoothing move is taken only when the
    /// faces around the vertex stay about as close to the original as they were.
    Fit,
    /// The remeshers' triangles: every smoothing move the triangles allow, at a cost in
    /// surface distance.
    Round,
}

/// Serde default of fields added after `true`-defaulted files were written.
#[cfg(feature = "serde")]
fn default_true() -> bool {
    true
}

// --- GNG3D-Q (placement + flips) -------------------------------------------------------------

/// Where the output vertex of each node is placed (reconstruction option (c)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Placement {
    /// At the trained node (GNG3D as published: the centroid of its signals, which lies inside
    /// curved surfaces and off creases).
    #[cfg_attr(feature = "serde", serde(alias = "Node"))]
    Node,
    /// At the closest point to the node on the original faces touching its cell.
    #[cfg_attr(feature = "serde", serde(alias = "Project"))]
    Project,
    /// At the minimiser of the cell's summed Garland–Heckbert quadrics, solved from the
    /// projected point with small eigenvalues dropped; falls back to the projected point when
    /// that solution is not finite or lies more than two cell radii from the node.
    #[default]
    #[cfg_attr(feature = "serde", serde(alias = "Quadric"))]
    Quadric,
}

impl ReconstructionParams {
    /// Whether the surface refit runs: it is asked for and the placement is
    /// [`Placement::Quadric`] (it needs the cells' quadrics; the other placements skip it).
    pub fn refits(&self) -> bool {
        self.refit && self.placement == Placement::Quadric
    }

    /// The paper's reconstruction: defaults with node placement and no flips (what
    /// `reproduce` uses for the paper's columns).
    pub fn paper() -> ReconstructionParams {
        ReconstructionParams {
            placement: Placement::Node,
            flip_edges: false,
            refit: false,
            relax: false,
            repair_deviations: false,
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
            refit: true,
            split_bad_cells: false,
            detail_rounds: 0,
            relax: true,
            repair_deviations: true,
            creases: false,
            shape: Shape::Off,
        }
    }
}

/// GNG3D parameters. Use [`GngParams::for_target`] and adjust fields as needed.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct GngParams {
    /// The output's vertex count N. The network holds N nodes (or
    /// [`GngParams::network_vertices`] when oversampled) and every one is an output vertex. At
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
    /// Signal budget as an explicit count; overrides [`GngParams::epochs`]. Default `None`.
    pub max_signals: Option<u64>,
    /// Signal budget in epochs of the signal-point count (distinct input vertices): the GNG3D
    /// paper's protocol is `Some(30.0)` ([`PAPER_EPOCHS`]). `None` (default) makes the budget
    /// follow the output instead: [`DEFAULT_SIGNALS_PER_NODE`] × the output's vertex count
    /// (`target_vertices`, also when oversampled; more than the paper's
    /// 30 epochs above 20 % of the vertices, where 30 epochs starve the network).
    pub epochs: Option<f64>,
    /// Wall-clock limit of the whole run, from [`crate::Trainer::new`] to the returned mesh
    /// (training, reconstruction and every step after it). The steps after training are
    /// estimated first and training gets what they leave; optional steps, then the
    /// oversampling, are left out when the time is short
    /// ([`crate::GngWarning::StepSkippedForTime`]), never the exact vertex count. Default none.
    pub time_limit: Option<Duration>,
    /// Seed of the PCG random generator; equal seeds give identical results. Default 1.
    pub seed: u64,
    /// Where signals come from. Default [`SignalSource::Vertices`].
    pub signal_source: SignalSource,
    /// Nearest-node search. Default [`SearchStrategy::Grid`].
    pub search: SearchStrategy,
    /// Phase-2 options.
    pub reconstruction: ReconstructionParams,
    /// Oversampling (GNG3D-Q): the network is trained to this many nodes (more than
    /// `target_vertices`), reconstructed, then decimated error first (QEM) to
    /// `target_vertices`. `None` (default): the network has `target_vertices` nodes and its mesh
    /// is the output. Set through [`crate::GngOptions::oversample`].
    pub network_vertices: Option<usize>,
    /// Train each piece of at least 512 nodes as two networks, one per
    /// half of its points (cut at the median of its longest axis), on two threads where the
    /// machine has them; the result is the same for any thread count. The reconstruction
    /// labels across the cut, so the output has no seam. Default `false` (one network per
    /// piece, as published); [`crate::GngOptions::resolve`] (GNG3D-Q) turns it on.
    pub split_training: bool,
    /// Most threads a run uses, the caller's included ([`crate::GngOptions::threads`]): training
    /// rounds, the steps after training and the helper that builds the original's tables while
    /// training runs. `None` (default): the machine's available parallelism, at most 4 (the
    /// steps are memory bound beyond that); `Some(1)`: no thread is started, all work runs on
    /// the caller's thread. The output is the same for any count. GNG3D-Q's QEM decimation
    /// runs in rayon's global pool, which this does not bound (`RAYON_NUM_THREADS`, or call
    /// inside `rayon::ThreadPool::install`).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub threads: Option<usize>,
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
            epochs: None,
            time_limit: None,
            seed: 1,
            signal_source: SignalSource::Vertices,
            search: SearchStrategy::Grid,
            reconstruction: ReconstructionParams::default(),
            network_vertices: None,
            split_training: false,
            threads: None,
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

    /// Nodes the network is trained to: [`GngParams::network_vertices`] when oversampled, else
    /// `target_vertices`.
    pub fn network_target(&self) -> usize {
        self.network_vertices.unwrap_or(self.target_vertices)
    }

    /// Whether the network's mesh is decimated to the output count (oversampled).
    pub fn decimates(&self) -> bool {
        self.network_vertices.is_some()
    }

    /// The published GNG3D (Álvarez et al. 2007) for `target_vertices` output vertices: a
    /// signal budget of 30 epochs of the input's vertices and the paper's reconstruction
    /// ([`ReconstructionParams::paper`]: vertices at the trained nodes, no flips, refit,
    /// relaxation or repair), one network of exactly that many nodes (no oversampling). What
    /// `gng3d reproduce` runs for the paper's columns; [`GngParams::for_target`] is GNG3D-Q's
    /// defaults without the oversampling that [`crate::GngOptions::resolve`] adds.
    pub fn paper(target_vertices: usize) -> GngParams {
        GngParams {
            epochs: Some(PAPER_EPOCHS),
            reconstruction: ReconstructionParams::paper(),
            ..GngParams::for_target(target_vertices)
        }
    }

    /// Check every parameter on its own (finite, positive, in range); the error names the
    /// parameter ([`GngParameter`]). Checks that need the mesh (target against the vertex
    /// count) are done by [`crate::Trainer::new`], which also calls this.
    pub fn validate(&self) -> Result<(), GngError> {
        let bad = |parameter, value: f64, rule| {
            Err(GngError::Parameter {
                parameter,
                value,
                rule,
            })
        };
        let unit = "must be in [0, 1]";
        check_range(
            GngParameter::EpsWinner,
            self.eps_winner as f64,
            0.0,
            1.0,
            unit,
        )?;
        check_range(
            GngParameter::EpsNeighbour,
            self.eps_neighbour as f64,
            0.0,
            1.0,
            unit,
        )?;
        check_range(GngParameter::Alpha, self.alpha, 0.0, 1.0, unit)?;
        check_range(
            GngParameter::ErrorDecay,
            self.error_decay,
            f64::MIN_POSITIVE,
            1.0,
            "must be in (0, 1]",
        )?;
        check_range(
            GngParameter::RemovalWindow,
            self.removal_window,
            0.0,
            f64::MAX,
            "must be a finite number >= 0",
        )?;
        if self.lambda == Some(0) {
            return bad(GngParameter::Lambda, 0.0, "must be at least 1");
        }
        if self.max_edge_age == 0 {
            return bad(GngParameter::MaxEdgeAge, 0.0, "must be at least 1");
        }
        if let Some(n) = self.network_vertices
            && n < self.target_vertices
        {
            return bad(
                GngParameter::NetworkVertices,
                n as f64,
                "must be at least target_vertices",
            );
        }
        if self.max_signals == Some(0) {
            return bad(GngParameter::MaxSignals, 0.0, "must be at least 1 signal");
        }
        if let Some(e) = self.epochs
            && !(e.is_finite() && e > 0.0)
        {
            return bad(GngParameter::Epochs, e, "must be a finite number > 0");
        }
        if self.time_limit.is_some_and(|t| t.is_zero()) {
            return bad(GngParameter::TimeLimit, 0.0, "must be more than 0 seconds");
        }
        if self.threads == Some(0) {
            return bad(GngParameter::Threads, 0.0, "must be at least 1");
        }
        if self.reconstruction.max_hole_edges > 1 << 20 {
            return bad(
                GngParameter::MaxHoleEdges,
                self.reconstruction.max_hole_edges as f64,
                "must be at most 2^20",
            );
        }
        Ok(())
    }
}

/// `Ok` when `value` is finite and within `[lo, hi]`, else a [`GngError::Parameter`].
fn check_range(
    parameter: GngParameter,
    value: f64,
    lo: f64,
    hi: f64,
    rule: &'static str,
) -> Result<(), GngError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(GngError::Parameter {
            parameter,
            value,
            rule,
        })
    }
}

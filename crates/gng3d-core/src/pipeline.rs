//! Phase 2 and everything after it, written once: a [`Plan`] (the ordered [`Step`]s, built
//! from the parameters in one place, [`Plan::of`]) and one driver that runs it, one line per
//! step. The trainer hands over its network and stops there; [`crate::finish`], the viewer's
//! previews and [`crate::Snapshot::reconstruct`] all run this driver.
//!
//! The steps are listed, in the order they run, on [`Step`].
//!
//! Each step that ran is a [`StepRecord`] in [`crate::GngReport::steps`] (and in `gng3d
//! simplify --json`): its time and what it changed.

use crate::domain::Pieces;
use crate::params::{GngParams, ReconstructionParams};
use crate::reconstruct::{self, Attachment, Candidate, OriginalTables, ReconstructionReport};
use crate::report::GngWarning;
use glam::Vec3;
use mesh::TriMesh;
use mesh::cancel::Cancel;
use mesh::quadric::Quadric;
#[cfg(feature = "serde")]
use serde::Serialize;
use std::borrow::Cow;
use std::time::{Duration, Instant};

/// One step of the pipeline after training ([`crate::finish`],
/// [`crate::Trainer::reconstruct`]).
///
/// The steps, in the order they run (those a plan leaves out are named in [`Plan::of`]; each
/// that ran is a [`StepRecord`] in [`crate::GngReport::steps`] and in `gng3d simplify --json`):
///
/// | step | what it does |
/// |---|---|
/// | [`Step::Label`] | every original vertex takes its nearest node of its own piece |
/// | [`Step::ConnectCells`] | each node's cell (its vertices) is made edge-connected |
/// | [`Step::MapFaces`] | original faces become label triples; duplicates merged, orientation voted, fins removed, small holes filled |
/// | [`Step::SplitBadCells`] | cells that are not discs or line a new hole get new nodes; faces mapped again (≤ 8 rounds) |
/// | [`Step::Attach`] | nodes no face uses are inserted into the nearest face; unused nodes compacted away |
/// | [`Step::Place`] | output vertices placed (node, projection or cell quadric) |
/// | [`Step::Flip`] | edges flipped toward the original surface |
/// | [`Step::Refit`] | vertices refitted so the triangles, not only the corners, fit the surface |
/// | [`Step::DetailRound`] | new nodes where the mesh stays farthest from the original; the build steps above run again |
/// | [`Step::CutSeams`] | with an input whose attributes have seams: the network's mesh is cut along them |
/// | [`Step::Decimate`] | the oversampled network's mesh is decimated (QEM) to the output count |
/// | [`Step::Relax`] | decimated vertices relax toward the original vertices they stand for |
/// | [`Step::RepairDeviations`] | vertices standing off the original move back; edges across grooves flip |
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
#[non_exhaustive]
pub enum Step {
    /// Label every original vertex with its nearest node (component-aware).
    Label,
    /// Make every node's cell edge-connected on the original.
    ConnectCells,
    /// Map the original faces to node triples and clean them up (reconstruction options (a),
    /// (b)).
    MapFaces,
    /// Split the cells that broke the topology and map again (option (f)).
    SplitBadCells,
    /// Attach every node no face uses; compact to the referenced nodes.
    Attach,
    /// Place the output vertices (option (c)).
    Place,
    /// Error-driven edge flips (option (d)).
    Flip,
    /// Surface refit (option (e)).
    Refit,
    /// One round of detail nodes (option (g)); the build steps run again after it.
    DetailRound,
    /// The network's mesh cut along the original's attribute seams, for a decimation that
    /// keeps them (inputs with seams only: [`crate::Trainer::with_attributes`]).
    CutSeams,
    /// QEM decimation of an oversampled network's mesh to the output count.
    Decimate,
    /// Tangential relaxation of the decimated mesh (option (h)).
    Relax,
    /// Deviation repair of the decimated mesh (option (i)).
    RepairDeviations,
}

impl Step {
    /// The step's name as `--json` writes it (`"map_faces"`).
    pub fn name(self) -> &'static str {
        match self {
            Step::Label => "label",
            Step::ConnectCells => "connect_cells",
            Step::MapFaces => "map_faces",
            Step::SplitBadCells => "split_bad_cells",
            Step::Attach => "attach",
            Step::Place => "place",
            Step::Flip => "flip",
            Step::Refit => "refit",
            Step::DetailRound => "detail_round",
            Step::CutSeams => "cut_seams",
            Step::Decimate => "decimate",
            Step::Relax => "relax",
            Step::RepairDeviations => "repair_deviations",
        }
    }

    /// What [`StepRecord::changed`] counts for this step.
    pub fn changes(self) -> &'static str {
        match self {
            Step::Label => "original vertices labelled",
            Step::ConnectCells => "vertices relabelled",
            Step::MapFaces => "faces mapped",
            Step::SplitBadCells => "nodes added",
            Step::Attach => "nodes attached",
            Step::Place => "vertices moved",
            Step::Flip => "edges flipped",
            Step::Refit => "vertex moves",
            Step::DetailRound => "nodes added",
            Step::CutSeams => "vertices added on seams",
            Step::Decimate => "vertices removed",
            Step::Relax => "vertices moved",
            Step::RepairDeviations => "vertex moves and flips",
        }
    }
}

impl Step {
    /// Whether the step works on the network's finished mesh (not part of a build round).
    fn after_build(self) -> bool {
        matches!(
            self,
            Step::CutSeams | Step::Decimate | Step::Relax | Step::RepairDeviations
        )
    }

    /// Whether every run needs this step for an exact vertex count (the rest may be left out
    /// when time runs short: [`crate::GngWarning::StepSkippedForTime`]).
    pub fn is_required(self) -> bool {
        matches!(
            self,
            Step::Label
                | Step::ConnectCells
                | Step::MapFaces
                | Step::Attach
                | Step::Place
                | Step::Decimate
        )
    }

    /// Estimated seconds of this step in build `round` of a run of these `sizes`: a cost per
    /// original vertex plus one per vertex of the mesh it works on (the network's mesh of that
    /// round; the output for the relaxation and the repair). Fitted (weighted least squares on
    /// the relative error) to the step records of `gng3d simplify --method gng --json` on the
    /// 14 shared meshes at 1, 10 and 50 %, with and without a time limit (252 runs): the
    /// optional steps at 1.25× the fit (a run should use its time), the required ones at the
    /// 90th percentile of measured / fitted (they decide the minimum and cannot be left out);
    /// docs/notes/anytime.md has the table. A budget, not a promise: the driver scales it by
    /// what the steps so far really took.
    fn estimate(self, sizes: Sizes, round: usize) -> f64 {
        // (µs per original vertex, µs per vertex of the mesh the step works on)
        let (per_original, per_vertex) = match self {
            Step::Label => (0.15, 0.33),
            Step::ConnectCells => (0.04, 0.03),
            Step::MapFaces => (0.012, 1.0),
            Step::SplitBadCells => (0.05, 0.3),
            Step::Attach => (0.003, 0.7),
            Step::Place => (0.29, 1.0),
            Step::Flip => (0.15, 2.6),
            Step::Refit => (0.25, 7.7),
            Step::DetailRound => (0.67, 2.2),
            // Not fitted like the others: the cut plus what the decimation costs more after it
            // (QEM's attribute path, the plain decimation beside it, both measured against the
            // original), from spot and the fandisk atlas at 5-20 % (8-25 ms on 2,930 and 6,475
            // original vertices, 220-1,100 network vertices, on a loaded 2-core machine).
            Step::CutSeams => (1.0, 15.0),
            Step::Decimate => (0.0, 0.62),
            Step::Relax => (0.03, 2.3),
            Step::RepairDeviations => (0.5, 9.2),
        };
        let vertices = match self {
            Step::Relax | Step::RepairDeviations => sizes.output,
            _ => network_at(sizes.network, round),
        };
        (per_original * sizes.original as f64 + per_vertex * vertices as f64) * 1e-6
    }
}

/// The cuts a short time limit makes, in order, least quality per second first. Measured on
/// six meshes at 10 and 50 % (`gng3d compare --samples 100000`; docs/notes/anytime.md, "What
/// each step buys"), as the geometric mean over the runs of the mean distance and Hausdorff
/// lost per share of the run's time saved:
/// 1. the flips and refits of the builds before the last (the detail rounds' builds): 30 % of
///    the time for a 2.5 % *lower* mean distance and an 18 % higher Hausdorff;
/// 2. the detail rounds, the last first (all three: 66 % of the time, ×1.21 mean distance,
///    ×2.13 Hausdorff);
/// 3. the flips (11 %; ×0.986 mean, ×1.08 Hausdorff) and the refit (27 %; ×1.055, ×1.12) of
///    the last build;
/// 4. the deviation repair (9 %; ×1.004, ×1.35), the relaxation and the cell splits (≤ 2 %
///    each: the relaxation is what wins E_avg, the splits keep thin parts attached);
/// 5. the seam cut of an input with attribute seams (geometry unchanged; without it the
///    output's triangles straddle the seams: docs/notes/attributes.md, "Seams that follow the
///    original's");
/// 6. then the oversampling (72 %; ×1.60, ×2.67).
pub(crate) const CUT_ORDER: [Cut; 9] = [
    Cut::DetailBuilds,
    Cut::Step(Step::DetailRound),
    Cut::Step(Step::Flip),
    Cut::Step(Step::Refit),
    Cut::Step(Step::RepairDeviations),
    Cut::Step(Step::Relax),
    Cut::Step(Step::SplitBadCells),
    Cut::Step(Step::CutSeams),
    Cut::Oversampling,
];

/// One cut of [`CUT_ORDER`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub(crate) enum Cut {
    /// The flips and refits of every build but the last.
    DetailBuilds,
    /// Every run of an optional step; for [`Step::DetailRound`] the last round.
    Step(Step),
    /// The oversampling: the network trains N nodes and its mesh is the output.
    Oversampling,
}

impl std::fmt::Display for Step {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A step of a [`Plan`] with the build it belongs to: round 0 is the first build, round r the
/// build after the r-th [`Step::DetailRound`] (the decimation and what follows it belong to the
/// last).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct PlannedStep {
    /// The step.
    pub step: Step,
    /// Its build round.
    pub round: usize,
}

/// The ordered steps of a run after training.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Plan {
    steps: Vec<PlannedStep>,
}

impl Plan {
    /// The plan of a run with these reconstruction options, decimated to the output count when
    /// `decimates` (an oversampled network). The one place that decides which steps run:
    /// - [`Step::ConnectCells`] with `connected_cells`;
    /// - the build ([`Step::MapFaces`], [`Step::SplitBadCells`] with `split_bad_cells`,
    ///   [`Step::Attach`], [`Step::Place`], [`Step::Flip`] with `flip_edges`, [`Step::Refit`]
    ///   when [`ReconstructionParams::refits`]) once, then once more after each of the
    ///   `detail_rounds` [`Step::DetailRound`]s;
    /// - [`Step::Decimate`], then [`Step::Relax`] and [`Step::RepairDeviations`] when asked
    ///   for, only when `decimates`.
    ///
    /// For an input whose attributes have seams, [`Plan::with_seams`].
    pub fn of(params: &ReconstructionParams, decimates: bool) -> Plan {
        Plan::with_seams(params, decimates, false)
    }

    /// [`Plan::of`], and with `seams` (the input's attributes have seams:
    /// [`crate::Trainer::with_attributes`]) [`Step::CutSeams`] then [`Step::Decimate`] after the
    /// last build whether or not `decimates`: the cut adds vertices, the decimation takes the
    /// mesh back to the output count along the seams.
    pub fn with_seams(params: &ReconstructionParams, decimates: bool, seams: bool) -> Plan {
        let mut steps = Vec::new();
        let mut add = |step, round| steps.push(PlannedStep { step, round });
        add(Step::Label, 0);
        if params.connected_cells {
            add(Step::ConnectCells, 0);
        }
        let detail_rounds = params.detail_rounds;
        for round in 0..=detail_rounds {
            if round > 0 {
                add(Step::DetailRound, round);
            }
            add(Step::MapFaces, round);
            if params.split_bad_cells {
                add(Step::SplitBadCells, round);
            }
            add(Step::Attach, round);
            add(Step::Place, round);
            if params.flip_edges {
                add(Step::Flip, round);
            }
            if params.refits() {
                add(Step::Refit, round);
            }
        }
        if seams {
            add(Step::CutSeams, detail_rounds);
        }
        if decimates || seams {
            add(Step::Decimate, detail_rounds);
        }
        if decimates {
            let last = detail_rounds;
            if params.relax {
                add(Step::Relax, last);
            }
            if params.repair_deviations {
                add(Step::RepairDeviations, last);
            }
        }
        Plan { steps }
    }

    /// The steps in the order they run.
    pub fn steps(&self) -> &[PlannedStep] {
        &self.steps
    }

    /// Whether the plan has `step`.
    pub fn contains(&self, step: Step) -> bool {
        self.steps.iter().any(|s| s.step == step)
    }

    /// This plan without the flips and refits of the builds before the last.
    fn lean_detail_builds(&self) -> Plan {
        let last = self.steps.iter().map(|s| s.round).max().unwrap_or(0);
        let steps = self
            .steps
            .iter()
            .filter(|s| s.round == last || !matches!(s.step, Step::Flip | Step::Refit))
            .copied()
            .collect();
        Plan { steps }
    }

    /// How many times the plan runs `step`.
    pub fn count(&self, step: Step) -> usize {
        self.steps.iter().filter(|s| s.step == step).count()
    }

    /// This plan without `step`: every round of it, or for [`Step::DetailRound`] the last
    /// round (the detail round and the build after it).
    fn without(&self, step: Step) -> Plan {
        let last = self
            .steps
            .iter()
            .filter(|s| s.step == Step::DetailRound)
            .map(|s| s.round)
            .max();
        let steps = self
            .steps
            .iter()
            .filter(|s| match (step, last) {
                (Step::DetailRound, Some(last)) => s.round != last || s.step.after_build(),
                _ => s.step != step,
            })
            .copied()
            .collect();
        Plan { steps }
    }

    /// Estimated seconds of the planned steps from `from` (an index into [`Plan::steps`]) on,
    /// `required_only` or all, for a run of these `sizes`.
    fn estimate(&self, from: usize, required_only: bool, sizes: Sizes) -> f64 {
        self.steps[from.min(self.steps.len())..]
            .iter()
            .filter(|s| !required_only || s.step.is_required())
            .map(|s| s.step.estimate(sizes, s.round))
            .sum()
    }
}

/// What a run's step costs depend on.
#[derive(Debug, Clone, Copy)]
struct Sizes {
    /// Vertices of the original.
    original: usize,
    /// Nodes of the trained network.
    network: usize,
    /// Vertices of the output.
    output: usize,
}

impl Sizes {
    /// Seconds of the work after the last step (the output's topology, the checks), per
    /// original and output vertex (measured with the steps: 0.1-0.4 µs per original vertex).
    fn finish(self) -> f64 {
        FIXED_SECONDS + 0.3e-6 * self.original as f64 + 0.3e-6 * self.output as f64
    }
}

/// Vertices of the network's mesh in build `round`: each detail round adds at most
/// [`crate::reconstruct::detail::NODES_PER_ROUND`] of them.
fn network_at(network: usize, round: usize) -> usize {
    (network as f64 * (1.0 + crate::reconstruct::detail::NODES_PER_ROUND * round as f64)) as usize
}

/// Estimated seconds of the training set-up ([`crate::Trainer::new`]: distinct points,
/// pieces, frames, grids) per original vertex, and of the fastest growth to a network of N
/// nodes (one insertion per signal) per node. Measured in docs/notes/anytime.md.
const SETUP_SECONDS_PER_VERTEX: f64 = 0.35e-6;
const GROWTH_SECONDS_PER_NODE: f64 = 1.8e-6;

/// The decimation along the seams ([`Step::CutSeams`]) is kept when its mean distance to the
/// original (at vertices, edge midpoints and centroids) is at most this many times that of the
/// decimation without them; otherwise the output does not follow the seams
/// ([`GngWarning::SeamsNotFollowed`]).
pub(crate) const SEAM_DISTANCE_RATIO: f64 = 1.5;

/// Fixed cost of a run (threads started, result checked): ~1 ms on the smallest meshes.
const FIXED_SECONDS: f64 = 2e-3;

/// The estimated minimum is this much above the sum of its estimates: on the fastest runs of
/// the 14 shared meshes at 1, 10 and 50 % the sum was 0.87-2.3× short of the measured time
/// before the fit above (docs/notes/anytime.md); the minimum is a promise to the user.
const MINIMUM_MARGIN: f64 = 1.3;

/// The training a time limit leaves room for is at least this many times the fastest growth:
/// the rest refines the network (a network stopped right after growth has its last nodes
/// where they were inserted, between older ones).
const MIN_TRAINING_OVER_GROWTH: f64 = 3.0;

/// Share of a time limit the plan and the driver aim at: 5 % under it, less a millisecond,
/// so that the noise of a shared machine (a few ms on the smallest meshes) stays within it.
pub(crate) fn aim_seconds(limit: Duration) -> f64 {
    (limit.as_secs_f64() * 0.95 - 1e-3).max(0.0)
}

/// What a run's time limit buys (see [`plan_for_time`]).
#[derive(Debug, Clone)]
pub(crate) struct TimePlan {
    /// The parameters to train with (without oversampling when the time is short).
    pub params: GngParams,
    /// The steps after training for these parameters without a time limit (what the plan's
    /// cuts are counted against).
    pub full: Plan,
    /// The steps after training.
    pub plan: Plan,
    /// Runs of each optional step the plan left out for time.
    pub cut_runs: Vec<(Step, usize)>,
    /// Wall time from the start of the run at which training stops (once the network holds
    /// its nodes); `None`: no limit.
    pub training_limit: Option<Duration>,
    /// What was left out for time, and whether the limit is below the minimum.
    pub warnings: Vec<GngWarning>,
}

/// Share a run's time limit between the training and the steps after it: the plan's steps
/// are estimated ([`Step::estimate`]); while the training would get less than
/// [`MIN_TRAINING_OVER_GROWTH`] times its fastest growth, optional steps are left out in
/// [`CUT_ORDER`], and then the oversampling. The training gets what the remaining plan leaves
/// (the driver still checks each optional step against the clock: [`run`]).
///
/// The minimum a run needs is the set-up, the fastest growth to N nodes and the required steps
/// of a run that is not oversampled; below it the warning
/// [`GngWarning::TimeLimitBelowMinimum`] says so, and the run is that fastest run (growth is
/// never cut short: the vertex count stays exact).
pub(crate) fn plan_for_time(params: GngParams, original: usize, seams: bool) -> TimePlan {
    let plan = Plan::with_seams(&params.reconstruction, params.decimates(), seams);
    let Some(limit) = params.time_limit else {
        return TimePlan {
            params,
            full: plan.clone(),
            plan,
            cut_runs: Vec::new(),
            training_limit: None,
            warnings: Vec::new(),
        };
    };
    let limit_seconds = limit.as_secs_f64();
    // What the plan aims at: a little under the limit, for the noise of a loaded machine.
    let aim = aim_seconds(limit);
    let setup = FIXED_SECONDS + SETUP_SECONDS_PER_VERTEX * original as f64;
    let training_needs = |network: usize| {
        setup + GROWTH_SECONDS_PER_NODE * network as f64 * MIN_TRAINING_OVER_GROWTH
    };
    let mut params = params;
    let mut plan = plan;
    let mut oversampling_cut = None;
    let sizes = |params: &GngParams| Sizes {
        original,
        network: params.network_target(),
        output: params.target_vertices,
    };
    let fits = |params: &GngParams, plan: &Plan| {
        let sizes = sizes(params);
        training_needs(sizes.network) + plan.estimate(0, false, sizes) + sizes.finish() <= aim
    };
    // Runs of each step the cuts removed.
    let mut cut_runs: Vec<(Step, usize)> = Vec::new();
    let mut count_cut = |step: Step, runs: usize| {
        if runs == 0 {
            return;
        }
        match cut_runs.iter_mut().find(|(s, _)| *s == step) {
            Some((_, n)) => *n += runs,
            None => cut_runs.push((step, runs)),
        }
    };
    let mut cuts = CUT_ORDER.iter().copied().peekable();
    while !fits(&params, &plan) {
        let Some(&cut) = cuts.peek() else {
            break;
        };
        let before = plan.clone();
        match cut {
            Cut::DetailBuilds => plan = plan.lean_detail_builds(),
            Cut::Step(step) => plan = plan.without(step),
            Cut::Oversampling => {
                if let Some(network_vertices) = params.network_vertices {
                    // The network trains N nodes instead and its mesh is the output: no
                    // decimation, no cell splits or detail nodes (they would break the count).
                    oversampling_cut = Some(network_vertices);
                    params = params.not_oversampled();
                    let full = Plan::with_seams(&params.reconstruction, false, seams);
                    // What was cut stays cut.
                    plan = Plan {
                        steps: full
                            .steps
                            .iter()
                            .filter(|s| before.count(s.step) > 0 || s.step.is_required())
                            .copied()
                            .collect(),
                    };
                }
            }
        }
        match cut {
            Cut::DetailBuilds => {
                for step in [Step::Flip, Step::Refit] {
                    count_cut(step, before.count(step) - plan.count(step));
                }
            }
            Cut::Step(step) => count_cut(step, before.count(step) - plan.count(step)),
            Cut::Oversampling => {}
        }
        // A detail round is cut one at a time; every other cut once.
        if plan == before || cut != Cut::Step(Step::DetailRound) {
            cuts.next();
        }
    }
    let full = Plan::with_seams(&params.reconstruction, params.decimates(), seams);
    let mut warnings: Vec<GngWarning> = Vec::new();
    if let Some(network_vertices) = oversampling_cut {
        warnings.push(GngWarning::OversamplingSkippedForTime { network_vertices });
    }
    let n = params.target_vertices;
    let fastest = Sizes {
        original,
        network: n,
        output: n,
    };
    let minimum = MINIMUM_MARGIN
        * (setup
            + GROWTH_SECONDS_PER_NODE * n as f64
            + Plan::with_seams(
                &params.clone().not_oversampled().reconstruction,
                false,
                seams,
            )
            .estimate(0, true, fastest)
            + fastest.finish());
    // (The limit went through a Duration: nanoseconds.)
    if limit_seconds < minimum - 1e-9 {
        warnings.insert(
            0,
            GngWarning::TimeLimitBelowMinimum {
                limit_seconds,
                minimum_seconds: minimum,
            },
        );
    }
    let after = plan.estimate(0, false, sizes(&params)) + sizes(&params).finish();
    let training_limit = Some(Duration::from_secs_f64((aim - after).max(0.0)));
    TimePlan {
        params,
        full,
        plan,
        cut_runs,
        training_limit,
        warnings,
    }
}

/// A step that ran: how long it took and what it changed.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct StepRecord {
    /// The step.
    pub step: Step,
    /// Its build round ([`PlannedStep::round`]).
    pub round: usize,
    /// Wall time, seconds.
    pub seconds: f64,
    /// What it changed, counted in [`Step::changes`].
    pub changed: usize,
}

/// What the pipeline works on: the original with what training already knows of it.
pub(crate) struct Input<'a> {
    /// The mesh being simplified.
    pub original: &'a TriMesh,
    /// Its distinct points and components.
    pub pieces: &'a Pieces,
    /// Its edge table and vertex adjacency, when a helper thread already built them.
    pub tables: Option<&'a OriginalTables>,
    /// The trained nodes (world coordinates) and GNG edges.
    pub nodes: &'a [Vec3],
    /// GNG edges between `nodes`.
    pub edges: &'a [[u32; 2]],
    /// The reconstruction options.
    pub params: &'a ReconstructionParams,
    /// The output count of an oversampled run or one with seams (the decimation's target).
    pub decimate_to: Option<usize>,
    /// Each original triangle's side of the seams, when the input's attributes have seams
    /// (its chart, [`mesh::attributes::Attributes::charts`], or finer: `seams::seam_sides`):
    /// [`Step::CutSeams`] cuts along their borders.
    pub charts: Option<&'a [u32]>,
    /// Most threads the steps use, the caller's included ([`crate::parallel::threads`]).
    pub threads: usize,
}

/// The pipeline's result.
pub(crate) struct Output {
    /// The final mesh.
    pub mesh: TriMesh,
    /// For each vertex of the network's mesh (before any decimation), its node.
    pub node_of_vertex: Vec<u32>,
    /// Counters of the reconstruction (the network's mesh) and the topology of the output.
    pub report: ReconstructionReport,
    /// Every step that ran.
    pub steps: Vec<StepRecord>,
    /// Runs of optional steps left out to keep the deadline (a detail round left out counts
    /// the later ones too).
    pub skipped: Vec<Step>,
    /// The decimation did not follow the seams ([`GngWarning::SeamsNotFollowed`]'s ratio).
    pub seams_not_followed: Option<Option<f64>>,
}

/// The reconstruction alone of `input` (its options as given, no decimation, no deadline):
/// [`crate::reconstruct`] and [`crate::Trainer::reconstruct`].
pub(crate) fn reconstruct_only(input: &Input<'_>) -> crate::Reconstruction {
    let out = run(input, &Plan::of(input.params, false), None, None, |_| {})
        .expect("a plan without a decimation cannot fail");
    crate::Reconstruction {
        mesh: out.mesh,
        node_of_vertex: out.node_of_vertex,
        report: out.report,
    }
}

/// Run `plan` on `input`; `on_step` sees each step's record as it finishes. Errors are the
/// decimator's, and [`qem::QemError::Cancelled`] when `cancel` is set: it is looked at before
/// each step, after the last, and by the decimation's QEM runs.
///
/// With a `deadline`, each optional step runs only when its estimate and the estimates of the
/// required steps after it fit in the time left, all scaled by how long the steps so far took
/// against their estimates (a loaded or slower machine); a detail round counts with the build
/// after it, and when it is left out so are the later rounds. Left-out steps are in
/// [`Output::skipped`].
pub(crate) fn run(
    input: &Input<'_>,
    plan: &Plan,
    deadline: Option<Instant>,
    cancel: Option<&Cancel>,
    mut on_step: impl FnMut(&StepRecord),
) -> Result<Output, qem::QemError> {
    let start = Instant::now();
    let cancelled = || cancel.is_some_and(Cancel::is_cancelled);
    let mut work = Work::new(input);
    work.cancel = cancel.cloned();
    let mut steps = Vec::with_capacity(plan.steps().len());
    let mut skipped = Vec::new();
    // Build rounds after this one are not run: a detail round found nothing to add (or was
    // left out for time), so the mesh of this round is the last build.
    let mut last_round = usize::MAX;
    let mut build_seconds = 0.0;
    let sizes = Sizes {
        original: input.original.positions.len(),
        network: input.nodes.len(),
        output: input.decimate_to.unwrap_or(input.nodes.len()),
    };
    // Seconds the steps so far took, and their estimates.
    let (mut spent, mut estimated) = (0.0f64, 0.0f64);
    for (i, &PlannedStep { step, round }) in plan.steps().iter().enumerate() {
        if round > last_round && !step.after_build() {
            continue;
        }
        if cancelled() {
            return Err(qem::QemError::Cancelled);
        }
        if let Some(deadline) = deadline
            && !step.is_required()
        {
            // Slower than estimated (a loaded machine) scales the estimates up; faster does
            // not scale them down (the required steps' estimates are generous on purpose).
            let scale = if estimated > 0.0 {
                (spent / estimated).clamp(1.0, 4.0)
            } else {
                1.0
            };
            let own = if step == Step::DetailRound {
                plan.steps()[i..]
                    .iter()
                    .take_while(|s| s.round == round && !s.step.after_build())
                    .map(|s| s.step.estimate(sizes, round))
                    .sum()
            } else {
                step.estimate(sizes, round)
            };
            let rest = plan.estimate(i + 1, true, sizes) + sizes.finish();
            let left = deadline
                .saturating_duration_since(Instant::now())
                .as_secs_f64();
            // A step that can stop early stops where the rest still fits.
            work.step_deadline =
                deadline.checked_sub(Duration::from_secs_f64((rest * scale).min(left)));
            if (own + rest) * scale > left {
                if step == Step::DetailRound {
                    last_round = round - 1;
                    let later = plan.steps()[i..]
                        .iter()
                        .filter(|s| s.step == Step::DetailRound)
                        .count();
                    skipped.extend(std::iter::repeat_n(step, later));
                } else {
                    skipped.push(step);
                }
                continue;
            }
        }
        let t = Instant::now();
        let changed = match step {
            Step::Label => work.label(),
            Step::ConnectCells => work.connect_cells(),
            Step::MapFaces => work.map_faces(),
            Step::SplitBadCells => work.split_bad_cells(),
            Step::Attach => work.attach(),
            Step::Place => work.place(),
            Step::Flip => work.flip(),
            Step::Refit => work.refit(),
            Step::DetailRound => match work.detail_round() {
                0 => {
                    last_round = round - 1;
                    0
                }
                added => added,
            },
            Step::CutSeams => {
                work.end_build(start, build_seconds);
                work.cut_seams()
            }
            Step::Decimate => {
                if !work.build_ended {
                    work.end_build(start, build_seconds);
                }
                work.decimate()?
            }
            Step::Relax => work.relax(),
            Step::RepairDeviations => work.repair_deviations(),
        };
        let seconds = t.elapsed().as_secs_f64();
        if !step.after_build() {
            build_seconds += seconds;
        }
        spent += seconds;
        estimated += step.estimate(sizes, round);
        let record = StepRecord {
            step,
            round,
            seconds,
            changed,
        };
        on_step(&record);
        steps.push(record);
    }
    if cancelled() {
        return Err(qem::QemError::Cancelled);
    }
    if !work.build_ended {
        work.end_build(start, build_seconds);
    }
    Ok(work.output(steps, skipped))
}

/// The state the steps pass along.
struct Work<'a> {
    original: &'a TriMesh,
    pieces: &'a Pieces,
    tables: Option<Cow<'a, OriginalTables>>,
    gng_edges: &'a [[u32; 2]],
    params: &'a ReconstructionParams,
    decimate_to: Option<usize>,
    /// The original's chart of each triangle, when it has seams.
    charts: Option<&'a [u32]>,
    /// After [`Step::CutSeams`]: the chart of each triangle of the mesh (until a decimation
    /// that could not keep the seams).
    triangle_charts: Option<Vec<u32>>,
    /// After [`Step::CutSeams`]: the network's mesh before the cut, for the decimation's
    /// comparison.
    uncut: Option<TriMesh>,
    /// The original's closest-point grid, once built ([`Step::CutSeams`]).
    grid: Option<mesh::transfer::FaceGrid<'a>>,
    /// The decimation did not follow the seams: the ratio of [`GngWarning::SeamsNotFollowed`].
    seams_not_followed: Option<Option<f64>>,
    /// Most threads the steps use, the caller's included.
    threads: usize,
    /// Node of each original vertex (`u32::MAX`: none).
    labels: Vec<u32>,
    /// Piece of each node.
    node_comp: Vec<u32>,
    /// Trained nodes plus those the split and detail steps added, where training left them.
    nodes: Vec<Vec3>,
    /// Mapped faces in node indices.
    faces: Vec<Candidate>,
    /// Per node: whether its cell holds a vertex of an original border.
    on_border: Vec<bool>,
    /// Split rounds of the current build.
    split_rounds: usize,
    /// Attached nodes, in output indices.
    attachments: Vec<Attachment>,
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    node_of_vertex: Vec<u32>,
    /// Output vertex of each original vertex (`u32::MAX`: none).
    owner: Vec<u32>,
    /// Cell quadrics of the placement (for the refit).
    quadrics: Vec<Quadric>,
    report: ReconstructionReport,
    /// Whether the last build is done (its counts are in the report).
    build_ended: bool,
    /// Whether the decimation removed vertices (the relaxation and the repair run only then).
    decimated: bool,
    /// When the current step should end to leave the rest of the plan its time (steps that
    /// can stop early: the deviation repair between its rounds).
    step_deadline: Option<Instant>,
    /// The run's cancel flag, handed to the decimation's QEM runs.
    cancel: Option<Cancel>,
}

impl<'a> Work<'a> {
    fn new(input: &Input<'a>) -> Work<'a> {
        Work {
            original: input.original,
            pieces: input.pieces,
            tables: input.tables.map(Cow::Borrowed),
            gng_edges: input.edges,
            params: input.params,
            decimate_to: input.decimate_to,
            charts: input.charts,
            triangle_charts: None,
            uncut: None,
            grid: None,
            seams_not_followed: None,
            threads: input.threads,
            labels: Vec::new(),
            node_comp: Vec::new(),
            nodes: input.nodes.to_vec(),
            faces: Vec::new(),
            on_border: Vec::new(),
            split_rounds: 0,
            attachments: Vec::new(),
            positions: Vec::new(),
            triangles: Vec::new(),
            node_of_vertex: Vec::new(),
            owner: Vec::new(),
            quadrics: Vec::new(),
            report: ReconstructionReport::empty(input.original.triangles.len()),
            build_ended: false,
            decimated: false,
            step_deadline: None,
            cancel: None,
        }
    }

    /// [`Step::Label`]. When no helper thread built the original's tables, they are built on a
    /// second thread while this one labels (igea, 134k vertices: ~45 ms off the critical path);
    /// otherwise all cores label.
    fn label(&mut self) -> usize {
        let (original, pieces) = (self.original, self.pieces);
        let (nodes, edges) = (&self.nodes[..], self.gng_edges);
        let (labels, node_comp) = if self.tables.is_some() {
            reconstruct::labels_and_node_components(original, pieces, nodes, edges, self.threads)
        } else if self.threads <= 1 {
            let labelled =
                reconstruct::labels_and_node_components(original, pieces, nodes, edges, 1);
            self.tables = Some(Cow::Owned(OriginalTables::of(original)));
            labelled
        } else {
            let (labelled, tables) = std::thread::scope(|scope| {
                let tables = scope.spawn(|| OriginalTables::of(original));
                let labelled =
                    reconstruct::labels_and_node_components(original, pieces, nodes, edges, 1);
                // A panic on the table thread is a bug; rebuilding here keeps phase 2 alive.
                let tables = tables
                    .join()
                    .unwrap_or_else(|_| OriginalTables::of(original));
                (labelled, tables)
            });
            self.tables = Some(Cow::Owned(tables));
            labelled
        };
        self.labels = labels;
        self.node_comp = node_comp;
        self.labels.iter().filter(|&&l| l != u32::MAX).count()
    }

    /// [`Step::ConnectCells`].
    fn connect_cells(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let moved =
            reconstruct::make_cells_connected(self.original, tables, &self.nodes, &mut self.labels);
        self.report.relabelled_vertices += moved;
        moved
    }

    /// [`Step::MapFaces`]: the first mapping of a build.
    fn map_faces(&mut self) -> usize {
        self.split_rounds = 0;
        self.map_again();
        self.faces.len()
    }

    fn map_again(&mut self) {
        let tables = self.tables.as_deref().expect("labelled");
        let (faces, on_border) = reconstruct::map_faces(
            self.original,
            &tables.edges,
            &self.labels,
            &self.nodes,
            self.gng_edges,
            self.params,
            &mut self.report,
        );
        self.faces = faces;
        self.on_border = on_border;
    }

    /// [`Step::SplitBadCells`]: up to [`reconstruct::SPLIT_ROUNDS`] rounds of split-and-map;
    /// the new nodes of all builds together stay within [`reconstruct::SPLIT_BUDGET`] of the
    /// original's vertices without a node.
    fn split_bad_cells(&mut self) -> usize {
        let budget = (self
            .original
            .positions
            .len()
            .saturating_sub(self.nodes.len()) as f64
            * reconstruct::SPLIT_BUDGET) as usize;
        let mut added_here = 0;
        while self.split_rounds < reconstruct::SPLIT_ROUNDS {
            let tables = self.tables.as_deref().expect("labelled");
            let bad = reconstruct::split::bad_cells(
                self.original,
                tables,
                &self.labels,
                self.nodes.len(),
                &self.faces,
                &self.on_border,
            );
            let added = reconstruct::split::split_cells(
                self.original,
                tables,
                &mut self.labels,
                &mut self.nodes,
                &mut self.node_comp,
                &bad,
                budget.saturating_sub(self.report.split_cells),
            );
            if added == 0 {
                break;
            }
            self.report.split_cells += added;
            self.report.split_rounds += 1;
            self.split_rounds += 1;
            added_here += added;
            self.map_again();
        }
        added_here
    }

    /// [`Step::Attach`]: nodes no face uses are inserted into the nearest face (moved onto it,
    /// in a copy: `nodes` stay where training left them for the detail rounds' labels), then
    /// the referenced nodes become the output vertices, in node order.
    fn attach(&mut self) -> usize {
        let mut nodes = self.nodes.clone();
        let attachments = reconstruct::attach::attach_unreferenced(
            &mut self.faces,
            &mut nodes,
            self.gng_edges,
            self.original,
            &self.labels,
            &self.node_comp,
        );
        self.report.attached_nodes = attachments.len();
        let mut remap = vec![u32::MAX; nodes.len()];
        for c in &self.faces {
            for &v in &c.tri {
                remap[v as usize] = 0;
            }
        }
        self.node_of_vertex.clear();
        self.positions.clear();
        for (i, r) in remap.iter_mut().enumerate() {
            if *r == 0 {
                *r = self.positions.len() as u32;
                self.positions.push(nodes[i]);
                self.node_of_vertex.push(i as u32);
            }
        }
        self.report.unreferenced_nodes = nodes.len() - self.positions.len();
        self.triangles = self
            .faces
            .iter()
            .map(|c| c.tri.map(|v| remap[v as usize]))
            .collect();
        // Attached nodes, in output indices, follow their split triangles in the placement.
        self.attachments = attachments
            .iter()
            .map(|a| Attachment {
                node: remap[a.node as usize],
                corners: a.corners.map(|c| remap[c as usize]),
                weights: a.weights,
            })
            .collect();
        self.owner = crate::placement::owners(&self.labels, &self.node_of_vertex, nodes.len());
        attachments.len()
    }

    /// [`Step::Place`].
    fn place(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let placed = crate::placement::place(
            self.original,
            &tables.edges,
            &self.owner,
            self.params.placement,
            &self.attachments,
            &mut self.positions,
            self.threads,
        );
        self.quadrics = placed.quadrics;
        self.report.placed_vertices = placed.moved;
        placed.moved
    }

    /// [`Step::Flip`].
    fn flip(&mut self) -> usize {
        let flips = crate::flip::flip_edges(
            &self.positions,
            &mut self.triangles,
            &self.original.positions,
            &self.owner,
            self.threads,
        );
        self.report.flipped_edges = flips.flips;
        flips.flips
    }

    /// [`Step::Refit`], after the flips: it fits the final triangles (before them, measured on
    /// four meshes at 10 % and 50 %: 4-6 % more mean distance and a higher Hausdorff max in 7
    /// of 8).
    fn refit(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let refit = crate::refit::refit(
            &mut self.positions,
            &self.triangles,
            self.original,
            &tables.edges,
            &self.owner,
            &self.quadrics,
            self.threads,
        );
        self.report.refit_moves = refit.moves;
        refit.moves
    }

    /// [`Step::DetailRound`]: new nodes at the original vertices farthest from the mesh built
    /// so far; 0 when there is none to add (the last build is then the network's mesh).
    fn detail_round(&mut self) -> usize {
        let budget =
            (reconstruct::detail::NODES_PER_ROUND * self.positions.len() as f64).ceil() as usize;
        let tables = self.tables.as_deref().expect("labelled");
        let chosen = reconstruct::detail::farthest_vertices(
            self.original,
            tables,
            &self.owner,
            &self.positions,
            &self.triangles,
            budget,
            self.threads,
        );
        if chosen.is_empty() {
            return 0;
        }
        reconstruct::detail::insert_nodes(
            self.original,
            tables,
            &chosen,
            &mut self.labels,
            &mut self.nodes,
            &mut self.node_comp,
        );
        if self.params.connected_cells {
            self.report.relabelled_vertices += reconstruct::make_cells_connected(
                self.original,
                tables,
                &self.nodes,
                &mut self.labels,
            );
        }
        self.report.detail_nodes += chosen.len();
        chosen.len()
    }

    /// The network's mesh is done: its counts go to the report.
    fn end_build(&mut self, start: Instant, build_seconds: f64) {
        self.build_ended = true;
        self.report.vertices = self.positions.len();
        self.report.faces = self.triangles.len();
        // Phase 2 proper (the decimation and what follows are not counted).
        self.report.seconds = build_seconds.min(start.elapsed().as_secs_f64());
    }

    /// [`Step::CutSeams`]: the network's mesh cut along the original's seams
    /// ([`crate::seams::cut`]).
    fn cut_seams(&mut self) -> usize {
        let Some(charts) = self.charts else {
            return 0;
        };
        let original = self.original;
        let grid = self
            .grid
            .get_or_insert_with(|| mesh::transfer::FaceGrid::new(original));
        let uncut = TriMesh::new(
            std::mem::take(&mut self.positions),
            std::mem::take(&mut self.triangles),
        );
        let cut = crate::seams::cut(
            self.original,
            grid,
            charts,
            &uncut.positions,
            &uncut.triangles,
            self.threads,
        );
        self.uncut = Some(uncut);
        self.positions = cut.positions;
        self.triangles = cut.triangles;
        self.triangle_charts = (cut.added + cut.snapped > 0).then_some(cut.charts);
        cut.added + cut.snapped
    }

    /// Vertices of the mesh between triangles of different charts (on a seam), when the mesh
    /// follows the seams: the relaxation leaves them where they are (its moves are along the
    /// surface, off the seam), the deviation repair flips no edge between two of them.
    fn seam_vertices(&self) -> Option<Vec<bool>> {
        let charts = self.triangle_charts.as_ref()?;
        let mut first = vec![u32::MAX; self.positions.len()];
        let mut seam = vec![false; self.positions.len()];
        for (t, &c) in self.triangles.iter().zip(charts) {
            for &v in t {
                let f = &mut first[v as usize];
                if *f == u32::MAX {
                    *f = c;
                } else if *f != c {
                    seam[v as usize] = true;
                }
            }
        }
        Some(seam)
    }

    /// [`Step::Decimate`]: error first down to the output count, when the network's mesh has
    /// more vertices; along the seams after [`Step::CutSeams`]
    /// ([`crate::decimate::decimate_along_seams`]).
    fn decimate(&mut self) -> Result<usize, qem::QemError> {
        let Some(n) = self.decimate_to else {
            return Ok(0);
        };
        if self.positions.len() <= n {
            return Ok(0);
        }
        let mesh = TriMesh::new(
            std::mem::take(&mut self.positions),
            std::mem::take(&mut self.triangles),
        );
        let before = mesh.vertex_count();
        let cancel = self.cancel.as_ref();
        let out = match (self.triangle_charts.take(), self.uncut.take()) {
            (Some(charts), Some(uncut)) => {
                let (along, charts) =
                    crate::decimate::decimate_along_seams(&mesh, &charts, n, cancel)?;
                // The same count without the seams, from the mesh before the cut: kept when
                // the seams would cost too much of the surface (SEAM_DISTANCE_RATIO).
                let plain = if uncut.vertex_count() > n {
                    crate::decimate::decimate(&uncut, n, cancel)?
                } else {
                    uncut
                };
                let original = self.original;
                let grid = self
                    .grid
                    .get_or_insert_with(|| mesh::transfer::FaceGrid::new(original));
                // (No charts: the decimation along the seams could not reach the count.)
                let ratio = charts.as_ref().map(|_| {
                    let (along_mean, _) = crate::seams::distance_to(grid, original, &along);
                    let (plain_mean, _) = crate::seams::distance_to(grid, original, &plain);
                    along_mean / plain_mean.max(f64::MIN_POSITIVE)
                });
                if ratio.is_some_and(|r| r <= SEAM_DISTANCE_RATIO) {
                    self.triangle_charts = charts;
                    along
                } else {
                    self.seams_not_followed = Some(ratio);
                    plain
                }
            }
            _ => crate::decimate::decimate(&mesh, n, cancel)?,
        };
        self.decimated = true;
        let TriMesh {
            positions,
            triangles,
        } = out;
        self.positions = positions;
        self.triangles = triangles;
        Ok(before - self.positions.len())
    }

    /// [`Step::Relax`]: the decimation placed its vertices for the surface; relax them toward
    /// the original vertices they stand for.
    fn relax(&mut self) -> usize {
        if !self.decimated {
            return 0;
        }
        let seams = self.seam_vertices();
        let relaxed = crate::relax::relax(
            &mut self.positions,
            &self.triangles,
            self.original,
            seams.as_deref(),
            self.threads,
        );
        self.report.relaxed_vertices = relaxed.moves;
        relaxed.moves
    }

    /// [`Step::RepairDeviations`]: then bring back what stands farthest off the original.
    fn repair_deviations(&mut self) -> usize {
        if !self.decimated {
            return 0;
        }
        let seams = self.seam_vertices();
        let repaired = crate::deviation::repair_until(
            &mut self.positions,
            &mut self.triangles,
            self.original,
            seams.as_deref(),
            self.step_deadline,
            self.threads,
        );
        self.report.deviation_moves = repaired.moves;
        self.report.deviation_flips = repaired.flips;
        repaired.moves + repaired.flips
    }

    fn output(mut self, steps: Vec<StepRecord>, skipped: Vec<Step>) -> Output {
        let mesh = TriMesh::new(self.positions, self.triangles);
        self.report.topology = mesh::topology::analyze(&mesh);
        Output {
            mesh,
            node_of_vertex: self.node_of_vertex,
            report: self.report,
            steps,
            skipped,
            seams_not_followed: self.seams_not_followed,
        }
    }
}

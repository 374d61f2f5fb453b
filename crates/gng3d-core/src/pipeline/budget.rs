//! The time budget: what each step is estimated to cost ([`Step::estimate`]) and how a run's
//! time limit is shared between the training and the steps after it ([`plan_for_time`]:
//! optional steps left out in [`CUT_ORDER`]).

use super::plan::{Plan, Step};
use crate::params::GngParams;
use crate::report::GngWarning;
use std::time::Duration;

impl Step {
    /// Estimated seconds of this step in build `round` of a run of these `sizes`: a cost per
    /// original vertex plus one per vertex of the mesh it works on (the network's mesh of that
    /// round; the output for the relaxation and the repair). Fitted (weighted least squares on
    /// the relative error) to the step records of `gng3d simplify --method gng --json` on the
    /// 14 shared meshes at 1, 10 and 50 %, with and without a time limit (252 runs): the
    /// optional steps at 1.25× the fit (a run should use its time), the required ones at the
    /// 90th percentile of measured / fitted (they decide the minimum and cannot be left out);
    /// docs/notes/anytime.md has the table. A budget, not a promise: the driver scales it by
    /// what the steps so far really took.
    pub(super) fn estimate(self, sizes: Sizes, round: usize) -> f64 {
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
            // Not fitted: the closest-point structure of the original (as the repair's) and
            // three rounds over the output; igea at 10 % and the armadillo at 10 % took 0.64 and
            // 0.27 s on a loaded machine (docs/notes/shape.md).
            Step::Shape => (0.5, 20.0),
        };
        let vertices = match self {
            Step::Relax | Step::Shape | Step::RepairDeviations => sizes.output,
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
pub(crate) const CUT_ORDER: [Cut; 10] = [
    Cut::DetailBuilds,
    Cut::Step(Step::DetailRound),
    Cut::Step(Step::Flip),
    Cut::Step(Step::Refit),
    Cut::Step(Step::RepairDeviations),
    Cut::Step(Step::Shape),
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

impl Plan {
    /// Estimated seconds of the planned steps from `from` (an index into [`Plan::steps`]) on,
    /// `required_only` or all, for a run of these `sizes`.
    pub(super) fn estimate(&self, from: usize, required_only: bool, sizes: Sizes) -> f64 {
        self.steps[from.min(self.steps.len())..]
            .iter()
            .filter(|s| !required_only || s.step.is_required())
            .map(|s| s.step.estimate(sizes, s.round))
            .sum()
    }
}

/// What a run's step costs depend on.
#[derive(Debug, Clone, Copy)]
pub(super) struct Sizes {
    /// Vertices of the original.
    pub(super) original: usize,
    /// Nodes of the trained network.
    pub(super) network: usize,
    /// Vertices of the output.
    pub(super) output: usize,
}

impl Sizes {
    /// Seconds of the work after the last step (the output's topology, the checks), per
    /// original and output vertex (measured with the steps: 0.1-0.4 µs per original vertex).
    pub(super) fn finish(self) -> f64 {
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

//! Phase 2 and everything after it, written once: a [`Plan`] (the ordered [`Step`]s, built
//! from the parameters in one place, [`Plan::of`]) and one driver that runs it, one line per
//! step. The trainer hands over its network and stops there; [`crate::finish`], the viewer's
//! previews and [`crate::Snapshot::reconstruct`] all run this driver.
//!
//! The steps are listed, in the order they run, on [`Step`].
//!
//! Each step that ran is a [`StepRecord`] in [`crate::GngReport::steps`] (and in `gng3d
//! simplify --json`): its time and what it changed.

//!
//! The folder holds the plan ([`plan`]: the steps and their order), the time budget
//! ([`budget`]: the steps' estimates and what a time limit leaves out) and the step adapters
//! ([`steps`]: the state the steps pass along, one method per step); this file is the driver.

use crate::domain::Pieces;
use crate::params::ReconstructionParams;
use crate::reconstruct::{OriginalTables, Reconstruction, ReconstructionReport};
use glam::Vec3;
use mesh::TriMesh;
use mesh::cancel::Cancel;
use std::time::{Duration, Instant};

mod budget;
mod plan;
mod steps;

use budget::Sizes;
pub(crate) use budget::{CUT_ORDER, Cut, aim_seconds, plan_for_time};
pub use plan::{Plan, PlannedStep, Step, StepRecord};
use steps::Work;

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
    /// (its chart, [`mesh::attributes::Attributes::charts`], or finer: `seams::split_inner_chains`):
    /// [`Step::CutSeams`] cuts along their borders.
    pub charts: Option<&'a [u32]>,
    /// The original's creases, when it has some (then `charts` follow them too): the cut's and
    /// the decimation's vertices on them are pulled onto them.
    pub creases: Option<&'a crate::finish::creases::Creases>,
    /// Whether `charts` follow attribute seams (else only creases: a decimation that does not
    /// follow them is no warning).
    pub attribute_seams: bool,
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
            Step::Shape => work.shape(),
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

impl crate::Snapshot {
    /// Build the mesh of this network over the `original` mesh it was trained on (phase 2 with
    /// these options as given: no decimation, no time limit), e.g. for checkpoints of a
    /// training. The steps are [`crate::Step`]'s; [`crate::Trainer::reconstruct`] does the same
    /// on the trainer's current network, reusing its tables of the original.
    pub fn reconstruct(&self, original: &TriMesh, params: &ReconstructionParams) -> Reconstruction {
        let pieces = Pieces::of(original);
        let input = Input {
            original,
            pieces: &pieces,
            tables: None,
            nodes: &self.positions,
            edges: &self.edges,
            params,
            decimate_to: None,
            charts: None,
            creases: None,
            attribute_seams: false,
            threads: crate::parallel::threads(None),
        };
        reconstruct_only(&input)
    }
}

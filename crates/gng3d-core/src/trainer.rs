//! The public face of a run, [`Trainer`]: phase 1 step-wise ([`Trainer::step`]) or to
//! completion with a progress observer ([`Trainer::train`]), plus snapshots, previews and
//! cancellation for viewers. It holds the run ([`crate::run`]: the original, the plan, the
//! clock, the warnings) and the networks ([`crate::train`]) and hands each call to the one
//! that does it; the result is assembled in the run.

use crate::GngResult;
use crate::ReconstructionParams;
use crate::error::GngError;
use crate::params::{GngParams, SearchStrategy};
use crate::pipeline::{Plan, StepRecord};
use crate::reconstruct::Reconstruction;
use crate::report::GngWarning;
use crate::run::{Run, Trained};
use crate::train::{CancelToken, Progress, Snapshot, StopReason, Training, TrainingStats};
use mesh::{Model, TriMesh};
use std::ops::ControlFlow;
use std::time::Duration;

/// Signals between two progress reports of GNG3D's training for a signal `budget`: 5 % of it,
/// within 1,000 and 2,000,000 ([`Trainer::train_to_end`]). Training goes in rounds of this
/// size, and the rounds shape the run (each round shares its signals among the network's
/// parts), so every front end uses this one size and gets the same mesh. A progress bar moves
/// every 5 %: each round starts the parts' threads, and at 0.5 % a round (igea at 1 %: 2,000
/// signals, ~0.6 ms) starting them cost a third of the gain.
pub fn training_round(budget: u64) -> u64 {
    (budget / 20).clamp(1_000, 2_000_000)
}

/// Step-wise GNG3D trainer over one mesh. See the crate docs for an example.
///
/// Every connected component of the input with enough mass for 3 nodes (a triangle) is
/// trained by its own network in its own local frame
/// (see the `domain` module), so pieces never share nodes and far-away or huge coordinates do
/// not spoil the grid or f32 precision. With [`GngParams::split_training`] a large component
/// trains as two halves. The parts advance in rounds, side by side on threads, each with its
/// own random stream: the result does not depend on the thread count or on how `step` calls
/// divide the signals.
#[derive(Debug, Clone)]
pub struct Trainer {
    /// The run around the networks: original, plan, clock, warnings.
    run: Run,
    /// The networks and their counters.
    training: Training,
}

impl Trainer {
    /// Validate `params` against `model`'s mesh and set up training (two nodes at random
    /// vertices of every trained component).
    ///
    /// With attributes (normals, texture coordinates, colours, materials; they must fit the
    /// mesh: [`mesh::attributes::Attributes::validate`]) that have seams
    /// ([`mesh::attributes::Attributes::seam_edges`]) the output's triangles follow them: the
    /// plan cuts the network's mesh along the seams and decimates it along them
    /// ([`crate::Step::CutSeams`]), in every run, oversampled or not, and [`crate::finish`]
    /// takes the output's values from the original (`mesh::transfer::transfer_attributes`), never
    /// interpolated across a seam ([`GngResult::attributes`]). Without seams the mesh is the
    /// one without attributes; the vertex count stays exact. The model's materials and origin
    /// are not used.
    pub fn new(model: &Model, params: GngParams) -> Result<Trainer, GngError> {
        let attributes = model.attributes.as_ref();
        if let Some(a) = attributes {
            a.validate(&model.mesh).map_err(GngError::Attributes)?;
        }
        let (run, params, domain) = Run::start(&model.mesh, attributes, params)?;
        let threads = run.threads();
        let training = Training::new(params, domain.pieces, domain.distinct, threads)?;
        Ok(Trainer { run, training })
    }

    /// The parameters in use.
    pub fn params(&self) -> &GngParams {
        &self.training.params
    }

    /// The steps [`crate::finish`] runs after training.
    pub fn plan(&self) -> &Plan {
        self.run.plan()
    }

    /// The steps these parameters have without a time limit: [`Trainer::plan`] is this list
    /// less what the limit left out before the run started.
    pub fn full_plan(&self) -> &Plan {
        self.run.full_plan()
    }

    /// With a time limit, the wall time from the start of the run ([`Trainer::new`]) at which
    /// training stops once the network holds its nodes: the limit less what the plan's steps
    /// need. A front end that paces training (a viewer) paces it to this.
    pub fn training_limit(&self) -> Option<Duration> {
        self.run.clock().training_limit
    }

    /// Wall time since the start of the run ([`Trainer::new`]), less what [`Trainer::discount`]
    /// left out.
    pub fn run_elapsed(&self) -> Duration {
        self.run.clock().started.elapsed()
    }

    /// Leave `idle` out of the run's clock: a front end that paused the run (a viewer) hands
    /// the pause back, so that the time limit counts only the time the run was going.
    pub fn discount(&mut self, idle: Duration) {
        self.run.discount(idle);
    }

    /// The mesh being simplified.
    pub fn original(&self) -> &TriMesh {
        self.run.original()
    }

    /// A token that cancels this trainer from any thread.
    pub fn cancel_token(&self) -> CancelToken {
        self.training.cancel.clone()
    }

    /// Whether training has ended (budget used with the target reached, time limit, cancel).
    pub fn is_finished(&self) -> bool {
        self.training.is_finished()
    }

    /// Signals processed so far.
    pub fn signals(&self) -> u64 {
        self.training.signals
    }

    /// Current node count (all components).
    pub fn node_count(&self) -> usize {
        self.training.node_count()
    }

    /// Node count the trained components aim for: the target, unless
    /// [`Trainer::warnings`] reports that it cannot be held.
    pub fn node_target(&self) -> usize {
        self.training.held_target
    }

    /// Current edge count.
    pub fn edge_count(&self) -> usize {
        self.training.edge_count()
    }

    /// Training time so far.
    pub fn elapsed(&self) -> Duration {
        self.training.elapsed
    }

    /// What was dropped from the input or keeps the network from the target so far.
    pub fn warnings(&self) -> Vec<GngWarning> {
        let mut w = self.run.warnings();
        w.extend(self.training.warnings());
        w
    }

    /// Counters so far.
    pub fn stats(&self) -> TrainingStats {
        self.training.stats()
    }

    /// Switch the nearest-node search (e.g. to compare against the linear-scan baseline).
    pub fn set_search_strategy(&mut self, search: SearchStrategy) {
        self.training.set_search_strategy(search);
    }

    /// Process up to `n` signals (fewer when training ends); returns how many were processed.
    ///
    /// In rounds: the unfinished parts' signal counts after a round are shares of their total
    /// in proportion to the budgets (`round_quotas`), and the parts of a round run side by
    /// side, one thread each (up to the machine's parallelism). A part's result depends only on
    /// its own stream and signal count, and the counts only on the total, so the network after
    /// S signals is the same whatever the rounds, the threads or the `step` calls before.
    pub fn step(&mut self, n: u64) -> u64 {
        self.training.step(n, self.run.clock())
    }

    /// Run to completion, calling `observer` every `every` signals (and once at the end); the
    /// observer may stop training by returning `ControlFlow::Break(())`. The rounds shape the
    /// run: [`Trainer::train_to_end`] trains in the rounds every front end uses.
    pub fn train(&mut self, every: u64, mut observer: impl FnMut(&Progress) -> ControlFlow<()>) {
        let every = every.max(1);
        while !self.is_finished() {
            self.step(every);
            let progress = self.progress();
            if observer(&progress).is_break() {
                if self.training.stop.is_none() {
                    self.training.stop = Some(StopReason::Cancelled);
                }
                break;
            }
        }
    }

    /// [`Trainer::train`] in the rounds every front end uses ([`training_round`] of the signal
    /// budget), so that every front end gets the same mesh: what [`crate::simplify`] and the
    /// `gng3d` CLI train with.
    pub fn train_to_end(&mut self, observer: impl FnMut(&Progress) -> ControlFlow<()>) {
        let every = training_round(self.stats().max_signals);
        self.train(every, observer);
    }

    /// Current progress. Vertex errors of the nodes: `metrics::vertex_errors` on
    /// [`Trainer::snapshot`] positions.
    pub fn progress(&self) -> Progress {
        self.training.progress()
    }

    /// Copy of the network (all components, world coordinates) with compact indices.
    pub fn snapshot(&self) -> Snapshot {
        self.training.snapshot()
    }

    /// The reconstruction alone (no decimation) of the current network with `params`, every
    /// option as given (a tool for experiments: option (f) and (g) add vertices here).
    pub fn reconstruct(&self, params: &ReconstructionParams) -> Reconstruction {
        let snap = self.snapshot();
        crate::pipeline::reconstruct_only(&self.run.pipeline_input(
            &self.training.params,
            &snap,
            params,
        ))
    }

    /// A preview of the current network, e.g. while it trains: the run's plan without its
    /// detail rounds (each costs about one more reconstruction), with [`crate::finish`]'s checks;
    /// no warnings (a network still growing is short of the target by design).
    pub fn preview(&self) -> Result<GngResult, GngError> {
        let snap = self.snapshot();
        self.run.preview(self.handover(&snap))
    }

    /// What the training hands over to the run's end: the network `snap` of it, its
    /// parameters, counters and the warnings so far.
    fn handover<'a>(&'a self, snap: &'a Snapshot) -> Trained<'a> {
        Trained {
            params: &self.training.params,
            snap,
            stats: self.stats(),
            warnings: self.warnings(),
        }
    }

    /// [`crate::finish_cancellable`]: `plan` on `snap`, with the checks and warnings of a run,
    /// stopped with [`GngError::Cancelled`] when `cancel` is set.
    pub(crate) fn run_plan(
        &self,
        snap: &Snapshot,
        plan: &Plan,
        cancel: Option<&CancelToken>,
        on_step: impl FnMut(&StepRecord),
    ) -> Result<GngResult, GngError> {
        self.run.finish(self.handover(snap), plan, cancel, on_step)
    }
}

//! The step strip's state ([`StepStrip`]: the planned steps, their records and the training's
//! seconds), the rows and groups it shows; no texts (`text`), no drawing.

use super::short_name;
use crate::engine::{PipelineStep, PlannedStep, StepRecord};

/// Where one planned step stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepStatus {
    /// Not started yet.
    Pending,
    /// Running now.
    Running,
    /// Finished.
    Done {
        /// Wall time, seconds.
        seconds: f64,
        /// What it changed, counted in [`PipelineStep::changes`].
        changed: usize,
    },
    /// Left out to keep the run's time limit (before the run or while it ran).
    Skipped,
    /// Not needed: a detail round before it found nothing to add (or the pipeline failed).
    NotRun,
}

impl StepStatus {
    /// Whether the step finished.
    pub fn is_done(&self) -> bool {
        matches!(self, StepStatus::Done { .. })
    }
}

/// One planned step and where it stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepRow {
    /// The step.
    pub step: PipelineStep,
    /// Its build round (0: the first build; r: the build after the r-th detail round).
    pub round: usize,
    /// Where it stands.
    pub status: StepStatus,
}

/// Steps shown together in the strip: a single step, or a build round.
#[derive(Debug, Clone, PartialEq)]
pub struct StepGroup {
    /// Short label ("label", "build", "detail 2", "decimate").
    pub label: String,
    /// Its steps, in order.
    pub rows: Vec<StepRow>,
}

impl StepGroup {
    /// The group's status: running while one of its steps runs, pending while all are, done
    /// (with the seconds of its done steps and no count) once one is done and none waits,
    /// otherwise skipped or not run.
    pub fn status(&self) -> StepStatus {
        let any = |f: fn(&StepStatus) -> bool| self.rows.iter().any(|r| f(&r.status));
        if any(|s| *s == StepStatus::Running) {
            StepStatus::Running
        } else if self.rows.iter().all(|r| r.status == StepStatus::Pending) {
            StepStatus::Pending
        } else if any(|s| matches!(s, StepStatus::Done { .. })) {
            if any(|s| *s == StepStatus::Pending) {
                // Between two of its steps (the next one's event has not come yet).
                return StepStatus::Running;
            }
            StepStatus::Done {
                seconds: self.seconds(),
                changed: 0,
            }
        } else if any(|s| *s == StepStatus::Skipped) {
            StepStatus::Skipped
        } else {
            StepStatus::NotRun
        }
    }

    /// Seconds of its finished steps.
    pub fn seconds(&self) -> f64 {
        self.rows
            .iter()
            .map(|r| match r.status {
                StepStatus::Done { seconds, .. } => seconds,
                _ => 0.0,
            })
            .sum()
    }
}

/// Phase of the run the strip shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Phase {
    /// No run yet (or a reset whose plan has not arrived).
    #[default]
    Waiting,
    /// The network trains.
    Training,
    /// The finished network's pipeline runs.
    Pipeline,
    /// The pipeline ended with a mesh.
    Done,
    /// The pipeline failed.
    Failed,
}

/// The run's time limit as the strip shows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunLimit {
    /// Seconds, training and the steps together.
    pub seconds: f64,
    /// Whether it is the watch time (the user set none, or a longer one).
    pub is_watch_time: bool,
    /// The core's estimate of the steps' seconds (the limit less the training limit).
    pub steps_estimate: f64,
}

/// A planned step: the row, and whether the run's plan kept it (the time limit may leave
/// steps out before the run starts).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Planned {
    step: PipelineStep,
    round: usize,
    kept: bool,
}

/// The strip's state for the current session (see the module header).
#[derive(Debug, Clone, Default)]
pub struct StepStrip {
    /// Session the events belong to.
    session: u64,
    phase: Phase,
    planned: Vec<Planned>,
    records: Vec<StepRecord>,
    /// The run's time limit.
    pub limit: Option<RunLimit>,
    /// Running wall time of the training, seconds (pauses excluded, checkpoint previews
    /// included), once it ended.
    pub training_seconds: Option<f64>,
    /// Of it, seconds of checkpoint previews, and how many.
    pub preview_seconds: f64,
    /// Checkpoint previews during training.
    pub previews: u64,
    /// Wall time of the finished pipeline, seconds.
    pub pipeline_seconds: Option<f64>,
    /// Wall time from the run's start to its final mesh, seconds (pauses included).
    pub run_seconds: Option<f64>,
    /// Whether the time limit cut anything from the run (or is below its minimum).
    pub cut_for_time: bool,
}

impl StepStrip {
    /// The phase of the run.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// Forget the run (a reset): events of its session are ignored from now on, until the next
    /// session's plan arrives.
    pub fn clear(&mut self) {
        *self = StepStrip {
            session: self.session,
            ..StepStrip::default()
        };
    }

    /// A run of `session` started: `full_plan` is what its parameters plan, `steps` what it
    /// will run (a subsequence: the rest the time limit left out). Ignored unless `session` is
    /// newer than the one shown (sessions count from 1).
    pub fn start(
        &mut self,
        session: u64,
        full_plan: &[PlannedStep],
        steps: &[PlannedStep],
        limit: Option<RunLimit>,
    ) {
        if session <= self.session {
            return;
        }
        let mut kept = steps.iter().peekable();
        let planned = full_plan
            .iter()
            .map(|p| {
                let keep = kept.peek().is_some_and(|k| **k == *p);
                if keep {
                    kept.next();
                }
                Planned {
                    step: p.step,
                    round: p.round,
                    kept: keep,
                }
            })
            .collect();
        *self = StepStrip {
            session,
            phase: Phase::Training,
            planned,
            limit,
            ..StepStrip::default()
        };
    }

    fn owns(&self, session: u64) -> bool {
        self.phase != Phase::Waiting && session == self.session
    }

    /// The finished network's pipeline starts: its steps so far are forgotten.
    pub fn pipeline_started(
        &mut self,
        session: u64,
        training_seconds: f64,
        preview_seconds: f64,
        previews: u64,
    ) {
        if !self.owns(session) {
            return;
        }
        self.phase = Phase::Pipeline;
        self.records.clear();
        self.training_seconds = Some(training_seconds);
        self.preview_seconds = preview_seconds;
        self.previews = previews;
        self.pipeline_seconds = None;
        self.run_seconds = None;
        self.cut_for_time = false;
    }

    /// A step finished.
    pub fn step_done(&mut self, session: u64, record: StepRecord) {
        if self.owns(session) && self.phase == Phase::Pipeline {
            self.records.push(record);
        }
    }

    /// The pipeline ended.
    pub fn pipeline_done(
        &mut self,
        session: u64,
        pipeline_seconds: f64,
        run_seconds: f64,
        cut_for_time: bool,
        failed: bool,
    ) {
        if !self.owns(session) {
            return;
        }
        self.phase = if failed { Phase::Failed } else { Phase::Done };
        self.pipeline_seconds = Some(pipeline_seconds);
        self.run_seconds = Some(run_seconds);
        self.cut_for_time = cut_for_time;
    }

    /// Every planned step (of the plan without a time limit) and where it stands: the records
    /// are matched in order to the steps the run kept; a kept step the pipeline passed over was
    /// skipped for time, unless a detail round at or before its round found nothing to add (then
    /// it was not run); steps the run's plan left out are skipped.
    pub fn rows(&self) -> Vec<StepRow> {
        let mut rows: Vec<StepRow> = self
            .planned
            .iter()
            .map(|p| StepRow {
                step: p.step,
                round: p.round,
                status: if p.kept {
                    StepStatus::Pending
                } else {
                    StepStatus::Skipped
                },
            })
            .collect();
        // Rounds from which on the builds had nothing to do.
        let empty_round = self
            .records
            .iter()
            .filter(|r| r.step == PipelineStep::DetailRound && r.changed == 0)
            .map(|r| r.round)
            .min();
        let passed_over = |row: &StepRow, failed: bool| {
            let build = !matches!(
                row.step,
                PipelineStep::Decimate
                    | PipelineStep::Relax
                    | PipelineStep::Shape
                    | PipelineStep::RepairDeviations
            );
            let nothing_to_do = build
                && empty_round.is_some_and(|q| {
                    q < row.round || (q == row.round && row.step != PipelineStep::DetailRound)
                });
            if nothing_to_do || failed {
                StepStatus::NotRun
            } else {
                StepStatus::Skipped
            }
        };
        let mut cursor = 0;
        for record in &self.records {
            let found = (cursor..self.planned.len()).find(|&k| {
                let p = &self.planned[k];
                p.kept && p.step == record.step && p.round == record.round
            });
            let Some(k) = found else {
                continue;
            };
            for row in &mut rows[cursor..k] {
                if row.status == StepStatus::Pending {
                    row.status = passed_over(row, false);
                }
            }
            rows[k].status = StepStatus::Done {
                seconds: record.seconds,
                changed: record.changed,
            };
            cursor = k + 1;
        }
        match self.phase {
            Phase::Waiting | Phase::Training => {}
            Phase::Pipeline => {
                if let Some(row) = rows[cursor..]
                    .iter_mut()
                    .find(|r| r.status == StepStatus::Pending)
                {
                    row.status = StepStatus::Running;
                }
            }
            Phase::Done | Phase::Failed => {
                let failed = self.phase == Phase::Failed;
                for row in &mut rows[cursor..] {
                    if row.status == StepStatus::Pending {
                        row.status = passed_over(row, failed);
                    }
                }
            }
        }
        rows
    }

    /// [`StepStrip::rows`] grouped for the strip: the label and the cell connection alone, each
    /// build round together ("build" for the first, "detail r" for the r-th detail round and
    /// the build after it), then the seam cut, the decimation, the relaxation and the repair
    /// alone.
    pub fn groups(&self) -> Vec<StepGroup> {
        let mut groups: Vec<StepGroup> = Vec::new();
        for row in self.rows() {
            let label = match row.step {
                PipelineStep::Label
                | PipelineStep::ConnectCells
                | PipelineStep::CutSeams
                | PipelineStep::Decimate
                | PipelineStep::Relax
                | PipelineStep::Shape
                | PipelineStep::RepairDeviations => short_name(row.step).to_string(),
                _ if row.round == 0 => "build".to_string(),
                _ => format!("detail {}", row.round),
            };
            match groups.last_mut() {
                Some(g) if g.label == label => g.rows.push(row),
                _ => groups.push(StepGroup {
                    label,
                    rows: vec![row],
                }),
            }
        }
        groups
    }

    /// Training plus pipeline, seconds, once the pipeline ended.
    pub fn total_seconds(&self) -> Option<f64> {
        Some(self.training_seconds? + self.pipeline_seconds?)
    }

    /// Whether there is anything to show.
    pub fn is_empty(&self) -> bool {
        self.phase == Phase::Waiting
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::steps::draw::group_tooltip;
    use crate::steps::text::total_text;
    use gng3d_core::{Plan, ReconstructionParams};

    fn record(step: PipelineStep, round: usize, seconds: f64, changed: usize) -> StepRecord {
        StepRecord {
            step,
            round,
            seconds,
            changed,
        }
    }

    /// The GNG3D-Q plan with two detail rounds, oversampled (decimated).
    fn plan() -> Vec<PlannedStep> {
        let params = ReconstructionParams {
            detail_rounds: 2,
            split_bad_cells: true,
            ..ReconstructionParams::default()
        };
        Plan::of(&params, true).steps().to_vec()
    }

    fn names(rows: &[StepRow]) -> Vec<(&'static str, usize)> {
        rows.iter().map(|r| (r.step.name(), r.round)).collect()
    }

    #[test]
    fn plan_and_records_map_to_rows_in_order() {
        let plan = plan();
        let mut strip = StepStrip::default();
        strip.start(3, &plan, &plan, None);
        let rows = strip.rows();
        assert_eq!(rows.len(), plan.len());
        assert!(rows.iter().all(|r| r.status == StepStatus::Pending));
        assert_eq!(rows[0].step, PipelineStep::Label);
        assert_eq!(rows.last().unwrap().step, plan.last().unwrap().step);
        // The pipeline starts: the first step runs.
        strip.pipeline_started(3, 4.0, 0.5, 7);
        assert_eq!(strip.rows()[0].status, StepStatus::Running);
        // Events of another session change nothing.
        strip.step_done(2, record(PipelineStep::Label, 0, 0.5, 9));
        assert_eq!(strip.rows()[0].status, StepStatus::Running);
        strip.step_done(3, record(PipelineStep::Label, 0, 0.031, 43_243));
        let rows = strip.rows();
        assert_eq!(
            rows[0].status,
            StepStatus::Done {
                seconds: 0.031,
                changed: 43_243
            }
        );
        assert_eq!(rows[1].status, StepStatus::Running);
        assert!(rows[2..].iter().all(|r| r.status == StepStatus::Pending));
        assert_eq!(strip.total_seconds(), None);
    }

    #[test]
    fn the_shape_pass_is_a_step_of_its_own_in_the_strip() {
        let params = ReconstructionParams {
            shape: gng3d_core::Shape::Fit,
            ..ReconstructionParams::default()
        };
        let plan = Plan::of(&params, true).steps().to_vec();
        let mut strip = StepStrip::default();
        strip.start(1, &plan, &plan, None);
        strip.pipeline_started(1, 1.0, 0.1, 1);
        for p in &plan {
            strip.step_done(1, record(p.step, p.round, 0.01, 1));
        }
        strip.pipeline_done(1, 0.5, 1.5, false, false);
        let groups = strip.groups();
        let labels: Vec<&str> = groups.iter().map(|g| g.label.as_str()).collect();
        let tail = &labels[labels.len() - 4..];
        assert_eq!(tail, ["decimate", "relax", "shape", "repair"], "{labels:?}");
    }

    #[test]
    fn skipped_and_not_run_steps_are_told_apart() {
        let plan = plan();
        // The time limit left the last round's refit out before the run started.
        let kept: Vec<PlannedStep> = plan
            .iter()
            .copied()
            .filter(|p| !(p.step == PipelineStep::Refit && p.round == 2))
            .collect();
        let mut strip = StepStrip::default();
        strip.start(
            1,
            &plan,
            &kept,
            Some(RunLimit {
                seconds: 12.0,
                is_watch_time: true,
                steps_estimate: 1.5,
            }),
        );
        strip.pipeline_started(1, 9.5, 1.0, 4);
        // Everything of round 0 runs; the flip of round 0 is skipped for time by the driver
        // (no record); detail round 1 adds nodes and its build runs; detail round 2 finds
        // nothing, so its build is not run; the decimation runs, the relaxation is skipped,
        // the deviation repair runs.
        for p in &kept {
            let skip = (p.step == PipelineStep::Flip && p.round == 0)
                || (p.round == 2
                    && p.step != PipelineStep::DetailRound
                    && p.step != PipelineStep::Decimate
                    && p.step != PipelineStep::RepairDeviations)
                || p.step == PipelineStep::Relax;
            if skip {
                continue;
            }
            let changed = if p.step == PipelineStep::DetailRound && p.round == 2 {
                0
            } else {
                10
            };
            strip.step_done(1, record(p.step, p.round, 0.01, changed));
        }
        strip.pipeline_done(1, 2.0, 11.7, true, false);
        assert_eq!(strip.phase(), Phase::Done);
        let rows = strip.rows();
        let status = |step: PipelineStep, round: usize| {
            rows.iter()
                .find(|r| r.step == step && r.round == round)
                .unwrap_or_else(|| panic!("no {step} {round} in {:?}", names(&rows)))
                .status
        };
        let done = StepStatus::Done {
            seconds: 0.01,
            changed: 10,
        };
        assert_eq!(status(PipelineStep::Flip, 0), StepStatus::Skipped);
        assert_eq!(status(PipelineStep::Refit, 0), done);
        assert_eq!(status(PipelineStep::MapFaces, 1), done);
        assert_eq!(
            status(PipelineStep::DetailRound, 2),
            StepStatus::Done {
                seconds: 0.01,
                changed: 0
            }
        );
        assert_eq!(status(PipelineStep::MapFaces, 2), StepStatus::NotRun);
        assert_eq!(status(PipelineStep::Flip, 2), StepStatus::NotRun);
        // Left out before the run: skipped, even though round 2 had nothing to do.
        assert_eq!(status(PipelineStep::Refit, 2), StepStatus::Skipped);
        assert_eq!(status(PipelineStep::Decimate, 2), done);
        assert_eq!(status(PipelineStep::Relax, 2), StepStatus::Skipped);
        assert_eq!(status(PipelineStep::RepairDeviations, 2), done);
        assert_eq!(strip.total_seconds(), Some(11.5));
        assert_eq!(
            total_text(&strip),
            "= 11.5 s (run length 12.0 s)",
            "training 9.5 s + pipeline 2 s"
        );

        // Grouped: label, cells, build, detail 1, detail 2, decimate, relax, repair.
        let groups = strip.groups();
        let labels: Vec<&str> = groups.iter().map(|g| g.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "label", "cells", "build", "detail 1", "detail 2", "decimate", "relax", "repair"
            ]
        );
        let build = &groups[2];
        // map, split, attach, place, refit done (0.01 s each); flip skipped.
        assert!(
            (build.seconds() - 0.05).abs() < 1e-12,
            "{}",
            build.seconds()
        );
        assert!(matches!(build.status(), StepStatus::Done { .. }));
        assert!(matches!(groups[4].status(), StepStatus::Done { .. }));
        assert_eq!(groups[6].status(), StepStatus::Skipped);
        assert!(group_tooltip(build).contains("flip: skipped (time limit)"));
        assert!(group_tooltip(build).contains("map faces: 10 ms — 10 faces mapped"));
    }

    #[test]
    fn a_detail_round_skipped_for_time_skips_its_build_and_a_failure_leaves_the_rest_not_run() {
        let plan = plan();
        let mut strip = StepStrip::default();
        strip.start(5, &plan, &plan, None);
        strip.pipeline_started(5, 1.0, 0.0, 0);
        for p in plan.iter().filter(|p| p.round == 0) {
            strip.step_done(5, record(p.step, p.round, 0.002, 1));
        }
        // Detail round 1 and 2 left out by the driver; the decimation ran, then the run failed.
        strip.step_done(5, record(PipelineStep::Decimate, 2, 0.3, 100));
        // While the pipeline runs, the step after the decimation runs and the rounds it passed
        // over are skipped.
        let rows = strip.rows();
        let relax = rows
            .iter()
            .position(|r| r.step == PipelineStep::Relax)
            .unwrap();
        assert_eq!(rows[relax].status, StepStatus::Running);
        assert!(
            rows.iter()
                .filter(|r| r.round == 1)
                .all(|r| r.status == StepStatus::Skipped)
        );
        strip.pipeline_done(5, 0.5, 1.6, false, true);
        assert_eq!(strip.phase(), Phase::Failed);
        let rows = strip.rows();
        assert_eq!(rows[relax].status, StepStatus::NotRun);
        assert_eq!(
            rows.iter()
                .filter(|r| r.step == PipelineStep::DetailRound)
                .map(|r| r.status)
                .collect::<Vec<_>>(),
            [StepStatus::Skipped, StepStatus::Skipped]
        );
        // A reset forgets the run and ignores its late events until the next plan.
        strip.clear();
        assert!(strip.is_empty());
        strip.pipeline_started(5, 1.0, 0.0, 0);
        assert!(strip.is_empty());
        strip.start(4, &plan, &plan, None);
        assert!(strip.is_empty(), "an older session's plan is ignored");
        strip.start(6, &plan, &plan, None);
        assert_eq!(strip.phase(), Phase::Training);
    }
}

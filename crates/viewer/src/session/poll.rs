//! The per-frame collection of the background threads' results: a finished load, the training
//! thread's events (errors, reconstructions, steps), the checkpoint evaluations and QEM.

use super::{PendingEvaluation, Session};
use crate::engine::{self, Evaluation};
use crate::jobs::Job;
use crate::plots::Checkpoint;
use crate::steps::RunLimit;
use crate::worker::{Event, Speed};
use std::sync::Arc;

/// As fast as possible, evaluations of checkpoints (200k-sample Hausdorff, on their own thread)
/// may keep a core busy at most this share of the wall time: after one that took `d`, the next
/// waits `d · (1 / share − 1)` before it starts. On two cores it otherwise shares the UI's core
/// with the CPU renderer and takes time from training (with armadillo and 10,000 nodes,
/// training ran at 7-8 % of its headless rate).
pub const EVALUATION_TIME_SHARE: f64 = 0.25;

impl Session {
    /// Collect results from the background threads (non-blocking); call once per frame.
    pub fn poll(&mut self) {
        self.poll_loading();
        self.poll_training();
        self.poll_evaluations();
        self.poll_qem();
    }

    fn poll_loading(&mut self) {
        let Some(result) = self.loading.as_ref().and_then(|(_, job)| job.poll()) else {
            return;
        };
        self.loading = None;
        match result.and_then(|r| r) {
            Ok(model) => {
                let summary = format!(
                    "opened {} ({} vertices, {} faces)",
                    model.path.display(),
                    model.mesh.vertex_count(),
                    model.mesh.face_count()
                );
                for w in &model.warnings {
                    self.info(format!("{}: {w}", model.name));
                }
                self.info(summary);
                self.set_model_with_attributes(
                    model.name,
                    model.mesh,
                    model.attributes,
                    model.place,
                    model.texture,
                );
            }
            Err(e) => {
                self.error(format!("could not open {e}"));
                if self.original.face_count() == 0 {
                    let (name, mesh) = engine::default_model();
                    self.set_model(name, Arc::new(mesh));
                }
            }
        }
    }

    fn poll_training(&mut self) {
        self.live = self.trainer.live();
        let session = self.live.session;
        for event in self.trainer.drain_events() {
            match event {
                Event::Errors {
                    session: s,
                    signals,
                    e_avg,
                    e_max,
                } if s == session => self.history.push_errors(signals, e_avg, e_max),
                Event::Reconstructed {
                    session: s,
                    signals,
                    mesh,
                    train_seconds,
                    outcome,
                } if s == session => {
                    if let Some(outcome) = &outcome {
                        for w in &outcome.warnings {
                            self.info(format!("GNG3D warning: {w}"));
                        }
                    }
                    self.evaluation_queue.push_back(PendingEvaluation {
                        session: s,
                        signals,
                        train_seconds,
                        mesh: Arc::clone(&mesh),
                        attributes: outcome
                            .as_ref()
                            .and_then(|o| o.model.attributes.clone().map(Arc::new)),
                    });
                    self.reconstruction = Some(mesh);
                    self.gng_outcome = outcome;
                }
                Event::Failed {
                    session: s,
                    message,
                } if s == session => self.error(format!("GNG3D: {message}")),
                // The strip checks the session itself: a run's plan comes before the training
                // thread publishes the new session number.
                Event::Planned {
                    session: s,
                    full_plan,
                    steps,
                    time_limit,
                    limit_is_watch_time,
                    steps_estimate,
                } => {
                    let limit = time_limit.map(|seconds| RunLimit {
                        seconds,
                        is_watch_time: limit_is_watch_time,
                        steps_estimate: steps_estimate.unwrap_or(0.0),
                    });
                    self.steps.start(s, &full_plan, &steps, limit);
                }
                Event::PipelineStarted {
                    session: s,
                    training_seconds,
                    preview_seconds,
                    previews,
                } => self
                    .steps
                    .pipeline_started(s, training_seconds, preview_seconds, previews),
                Event::Step { session: s, record } => self.steps.step_done(s, record),
                Event::PipelineDone {
                    session: s,
                    cut_for_time,
                    pipeline_seconds,
                    run_seconds,
                    failed,
                } => {
                    self.steps.pipeline_done(
                        s,
                        pipeline_seconds,
                        run_seconds,
                        cut_for_time,
                        failed,
                    );
                    if s == session
                        && cut_for_time
                        && let Some(limit) = self.steps.limit.filter(|l| l.is_watch_time)
                    {
                        self.info(format!(
                            "GNG3D: this run passed twice its run length ({} s), the backstop \
                             that leaves steps out; a longer run length (or as fast as \
                             possible) leaves every step in",
                            limit.seconds
                        ));
                    }
                }
                _ => {}
            }
        }
    }

    /// Evaluations run one at a time, in order: a run with many checkpoints never starts more
    /// evaluation threads than there are cores to spare. Checkpoints that arrive while one is
    /// being evaluated wait; in a watched (paced) run only the newest of several waiting is kept.
    fn poll_evaluations(&mut self) {
        let finished = self
            .evaluating
            .as_ref()
            .and_then(|(_, job)| job.poll())
            .map(|r| match r {
                Ok((e, seconds)) => (e, seconds),
                Err(e) => (Err(e), 0.0),
            });
        if let Some((result, seconds)) = finished
            && let Some((pending, _)) = self.evaluating.take()
        {
            self.last_evaluation = Some((std::time::Instant::now(), seconds));
            match result {
                Ok(e) if pending.session == self.live.session => {
                    let row = checkpoint("GNG3D", pending.signals, &e, pending.train_seconds);
                    self.history.push_reconstruction(row);
                }
                Ok(_) => {}
                Err(e) => self.error(e.to_string()),
            }
        }
        // When the evaluator falls behind (big meshes, a loaded machine, or training as fast as
        // possible), skip to the newest checkpoint, so the table and curves stay live instead of
        // lagging further and further; the final reconstruction is always the newest, so it is
        // always evaluated.
        while self.evaluation_queue.len() > 1 {
            self.evaluation_queue.pop_front();
            self.skipped_evaluations += 1;
        }
        if self.evaluating.is_none()
            && let Some(next) = self.evaluation_queue.pop_front()
        {
            // As fast as possible: a cool-down keeps evaluations within EVALUATION_TIME_SHARE.
            let wait = match (self.speed, self.last_evaluation) {
                (Speed::Unlimited, Some((end, seconds))) => {
                    let cool = seconds * (1.0 / EVALUATION_TIME_SHARE - 1.0);
                    std::time::Duration::from_secs_f64(cool).saturating_sub(end.elapsed())
                }
                _ => std::time::Duration::ZERO,
            };
            let (original, mesh) = (Arc::clone(&self.original), Arc::clone(&next.mesh));
            let (attributes, output_attributes) =
                (self.attributes.clone(), next.attributes.clone());
            let job = Job::spawn_background("evaluation", self.repaint.clone(), move || {
                std::thread::sleep(wait);
                let started = std::time::Instant::now();
                let result = engine::evaluate_reconstruction(
                    &original,
                    attributes.as_deref(),
                    &mesh,
                    output_attributes.as_deref(),
                );
                (result, started.elapsed().as_secs_f64())
            });
            self.evaluating = Some((next, job));
        }
    }

    fn poll_qem(&mut self) {
        let Some(result) = self.qem.pending.as_ref().and_then(Job::poll) else {
            return;
        };
        self.qem.pending = None;
        match result.and_then(|r| r) {
            Ok((outcome, mesh, e)) => {
                let seconds = outcome.summary.seconds();
                self.history.qem = Some(checkpoint("QEM", 0, &e, seconds));
                self.qem.mesh = Some(mesh);
                for note in &outcome.warnings {
                    self.info(note.clone());
                }
                self.qem.outcome = Some(outcome);
            }
            Err(e) => {
                self.qem.mesh = None;
                self.qem.outcome = None;
                self.error(e.to_string());
                self.qem.error = Some(e.to_string());
            }
        }
    }
}

/// A table row from an evaluation.
fn checkpoint(method: &'static str, iteration: u64, e: &Evaluation, seconds: f64) -> Checkpoint {
    Checkpoint {
        method,
        iteration,
        evaluation: *e,
        seconds,
    }
}

//! The viewer's state without any UI: the model, the training thread, the QEM job, the
//! evaluations, the plot history and the messages. The window ([`crate::app`]) draws it and turns
//! clicks into calls here; tests drive it directly, without a window or a GPU.
//!
//! Two single places the rest of the workspace may swap out:
//! - [`train_params`]: start-up options → validated GNG3D parameters (headless and window mode);
//! - [`crate::engine::evaluate`]: the one evaluation of a simplified mesh (table, plots, QEM).
//!
//!
//! `options` turns the start-up options into parameters, `poll` collects the background
//! threads' results each frame; this file holds the [`Session`] and the calls the window makes.

mod options;
mod poll;

pub use options::*;
pub use poll::EVALUATION_TIME_SHARE;

use crate::engine::{self, Evaluation, TrainParams};
use crate::error::{Result, ViewerError};
use crate::io::{self, LoadedModel};
use crate::jobs::Job;
use crate::plots::History;
use crate::steps::{StepStrip, TrainingClock};
use crate::worker::{self, Command, Live, Speed, TrainingJob};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::Arc;
/// Which viewport.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// GNG3D (left).
    Gng,
    /// QEM (right).
    Qem,
}

/// A message shown in the message strip.
#[derive(Debug, Clone)]
pub struct Message {
    /// Text.
    pub text: String,
    /// Whether it is an error (red) or information.
    pub is_error: bool,
}

/// What QEM computed: the job's outcome, its mesh (shown) and its evaluation.
type QemResult = Result<(Arc<job::Outcome>, Arc<TriMesh>, Evaluation)>;

/// The QEM side.
#[derive(Default)]
struct QemState {
    target: usize,
    mesh: Option<Arc<TriMesh>>,
    /// The outcome the mesh is of (what is saved).
    outcome: Option<Arc<job::Outcome>>,
    pending: Option<Job<QemResult>>,
    error: Option<String>,
}

/// An evaluation and the seconds its work took.
type EvaluationResult = (crate::error::Result<Evaluation>, f64);

/// A reconstruction waiting for (or under) evaluation.
struct PendingEvaluation {
    session: u64,
    signals: u64,
    train_seconds: f64,
    mesh: Arc<TriMesh>,
    /// The finished network's attributes (a preview has none).
    attributes: Option<Arc<Attributes>>,
}

/// The training thread's state as one word, for the viewport label and the status bar alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrainingState {
    /// Training runs.
    Training,
    /// Paused by the user (or started with `--paused`).
    Paused,
    /// Reached its budget, target or time limit.
    Finished,
}

impl TrainingState {
    /// Lower-case label.
    pub fn label(self) -> &'static str {
        match self {
            TrainingState::Training => "training",
            TrainingState::Paused => "paused",
            TrainingState::Finished => "finished",
        }
    }
}

/// The viewer's state (see the module header).
pub struct Session {
    options: ViewerOptions,
    repaint: Option<egui::Context>,
    /// Display name of the model.
    pub model_name: String,
    original: Arc<TriMesh>,
    /// The original's normals, texture coordinates and colours (`None` without any): QEM
    /// keeps them, GNG3D's triangles follow their seams and its checkpoints take them from the
    /// original surface (as `gng3d simplify` does), and Table 1 shows both methods' attribute
    /// deviation.
    attributes: Option<Arc<Attributes>>,
    /// The original's materials and origin ([`engine::Loaded::place`]): the outputs' place.
    place: Arc<mesh::Model>,
    /// The base-colour texture of its materials, decoded ([`engine::Loaded::texture`]).
    texture: Option<Arc<metrics::Texture>>,
    loading: Option<(PathBuf, Job<Result<LoadedModel>>)>,
    /// Training parameters for the next reset (edited in the UI).
    pub params: TrainParams,
    /// Parameters of the running session (to show that edits wait for Reset).
    applied: TrainParams,
    /// Training speed (applies at once).
    pub speed: Speed,
    /// Reconstruct every this many signals (0: only at the end and on request; applies at once).
    pub checkpoint_every: u64,
    trainer: worker::Trainer,
    live: Live,
    /// Plot and table data.
    pub history: History,
    /// The run's training and pipeline steps, as they happen.
    pub steps: StepStrip,
    reconstruction: Option<Arc<TriMesh>>,
    /// The finished network's outcome (`None` while the reconstruction is a preview).
    gng_outcome: Option<Arc<job::Outcome>>,
    evaluating: Option<(PendingEvaluation, Job<EvaluationResult>)>,
    /// When the last evaluation finished, and the seconds its own work took (without its
    /// cool-down wait).
    last_evaluation: Option<(std::time::Instant, f64)>,
    evaluation_queue: VecDeque<PendingEvaluation>,
    /// Checkpoints of this run left unevaluated because a newer one was waiting.
    skipped_evaluations: u64,
    qem: QemState,
    /// Recent messages (newest last).
    pub messages: Vec<Message>,
}

impl Session {
    /// Validate `options`, spawn the training thread and open the model (in the background when
    /// it is a file). `repaint` is woken when background work finishes.
    pub fn new(options: ViewerOptions, repaint: Option<egui::Context>) -> Result<Session> {
        let params = train_params(&options)?;
        let trainer = worker::Trainer::spawn();
        if let Some(ctx) = &repaint {
            trainer.set_repaint_context(ctx);
        }
        let mut session = Session {
            speed: speed_for(options.watch_seconds),
            checkpoint_every: 0,
            options,
            repaint,
            model_name: String::new(),
            original: Arc::new(TriMesh::new(Vec::new(), Vec::new())),
            attributes: None,
            place: Arc::default(),
            texture: None,
            loading: None,
            applied: params.clone(),
            params,
            trainer,
            live: Live::default(),
            history: History::default(),
            steps: StepStrip::default(),
            reconstruction: None,
            gng_outcome: None,
            evaluating: None,
            last_evaluation: None,
            evaluation_queue: VecDeque::new(),
            skipped_evaluations: 0,
            qem: QemState::default(),
            messages: Vec::new(),
        };
        match session.options.path.clone() {
            Some(path) => session.open_path(path),
            None => {
                let (name, mesh) = engine::default_model();
                session.set_model(name, Arc::new(mesh));
            }
        }
        Ok(session)
    }

    /// Wake `ctx` when background work finishes (the context that draws may differ from the one
    /// given at construction, e.g. in test harnesses).
    pub fn set_repaint_context(&mut self, ctx: &egui::Context) {
        self.trainer.set_repaint_context(ctx);
        self.repaint = Some(ctx.clone());
    }

    /// The start-up options.
    pub fn options(&self) -> &ViewerOptions {
        &self.options
    }

    /// Replace the model: restart training and QEM on it.
    pub fn set_model(&mut self, name: String, mesh: Arc<TriMesh>) {
        self.set_model_with_attributes(name, mesh, None, Arc::default(), None);
    }

    /// [`Session::set_model`] for a model with `attributes` (of `mesh`'s corners), its
    /// materials and origin (`place`, [`engine::Loaded::place`]) and its decoded base-colour
    /// `texture`.
    pub fn set_model_with_attributes(
        &mut self,
        name: String,
        mesh: Arc<TriMesh>,
        attributes: Option<Arc<Attributes>>,
        place: Arc<mesh::Model>,
        texture: Option<Arc<metrics::Texture>>,
    ) {
        self.model_name = name;
        self.attributes = attributes;
        self.place = place;
        self.texture = texture;
        let n = mesh.vertex_count();
        if self.options.target.is_none() {
            self.params.target_vertices = default_target(n);
        }
        // The paper's protocol: a checkpoint every |V| signals (30 for the default budget).
        self.checkpoint_every = self.options.checkpoint_every.unwrap_or(n as u64);
        self.original = mesh;
        self.qem = QemState::default();
        self.history = History::default();
        // Also starts QEM: its target (0 after the reset above) differs from the parameters'.
        self.reset_training();
    }

    /// The mesh being simplified.
    pub fn original(&self) -> &Arc<TriMesh> {
        &self.original
    }

    /// The original's attributes (`None` without any).
    pub fn attributes(&self) -> Option<&Arc<Attributes>> {
        self.attributes.as_ref()
    }

    /// The base-colour texture of the original's materials (`None` without one, or without
    /// texture coordinates to map it by).
    pub fn texture(&self) -> Option<&Arc<metrics::Texture>> {
        self.texture.as_ref()
    }

    /// The attributes of the GNG3D reconstruction: the finished run's, taken from the
    /// original's surface (a preview has none).
    pub fn reconstruction_attributes(&self) -> Option<&Attributes> {
        self.gng_outcome.as_ref()?.model.attributes.as_ref()
    }

    /// The attributes QEM kept through its contractions.
    pub fn qem_attributes(&self) -> Option<&Attributes> {
        self.qem.outcome.as_ref()?.model.attributes.as_ref()
    }

    /// The latest GNG3D reconstruction, if any.
    pub fn reconstruction(&self) -> Option<&Arc<TriMesh>> {
        self.reconstruction.as_ref()
    }

    /// The QEM result, if any.
    pub fn qem_mesh(&self) -> Option<&Arc<TriMesh>> {
        self.qem.mesh.as_ref()
    }

    /// Whether QEM is computing.
    pub fn qem_pending(&self) -> bool {
        self.qem.pending.is_some()
    }

    /// The vertex target QEM was last asked for.
    pub fn qem_target(&self) -> usize {
        self.qem.target
    }

    /// QEM's last error, if it failed.
    pub fn qem_error(&self) -> Option<&str> {
        self.qem.error.as_deref()
    }

    /// Whether a model is being loaded, and which file.
    pub fn loading(&self) -> Option<&Path> {
        self.loading.as_ref().map(|(p, _)| p.as_path())
    }

    /// Whether a model is being loaded.
    pub fn is_loading(&self) -> bool {
        self.loading.is_some()
    }

    /// Whether a QEM result is shown.
    pub fn has_qem_mesh(&self) -> bool {
        self.qem.mesh.is_some()
    }

    /// Reconstructions waiting for or under evaluation.
    pub fn evaluations_pending(&self) -> usize {
        self.evaluation_queue.len() + usize::from(self.evaluating.is_some())
    }

    /// Checkpoints of this run that were not evaluated because the evaluator fell behind and a
    /// newer one was waiting (a loaded machine, a big mesh): evaluated rows plus these are every
    /// checkpoint the training sent.
    pub fn skipped_evaluations(&self) -> u64 {
        self.skipped_evaluations
    }

    /// The latest state of the training thread.
    pub fn live(&self) -> &Live {
        &self.live
    }

    /// The training's clock for the step strip.
    pub fn training_clock(&self) -> TrainingClock {
        TrainingClock {
            seconds: self.live.run_seconds,
            pace_seconds: self.live.pace_seconds,
            running: self.live.running,
        }
    }

    /// Training, paused or finished (one answer for every label that shows it).
    pub fn training_state(&self) -> TrainingState {
        if self.live.finished {
            TrainingState::Finished
        } else if self.live.running {
            TrainingState::Training
        } else {
            TrainingState::Paused
        }
    }

    /// The parameters of the running session (the method its view is titled with).
    pub fn applied_params(&self) -> &TrainParams {
        &self.applied
    }

    /// Train with `method` (paper GNG3D or GNG3D-Q) from now on: its parameters replace the
    /// step switches and the run restarts with them.
    pub fn switch_method(&mut self, method: engine::Method) {
        method.apply(&mut self.params);
        self.reset_training();
    }

    /// Whether parameters were edited since the running session started (they apply on Reset).
    pub fn params_pending(&self) -> bool {
        self.params != self.applied
    }

    /// Start a new training session with the current parameters (all parameter edits apply
    /// here); recompute QEM when the vertex target changed.
    pub fn reset_training(&mut self) {
        if self.qem.target != self.params.target_vertices {
            self.request_qem();
        }
        self.history.clear_training();
        self.steps.clear();
        self.reconstruction = None;
        self.gng_outcome = None;
        self.evaluation_queue.clear();
        self.skipped_evaluations = 0;
        self.evaluating = None;
        self.applied = self.params.clone();
        if self.original.face_count() == 0 {
            return;
        }
        self.trainer.send(Command::SetSpeed(self.speed));
        self.trainer.send(Command::Reset(Box::new(TrainingJob {
            mesh: Arc::clone(&self.original),
            attributes: self.attributes.clone(),
            place: Arc::clone(&self.place),
            params: self.params.clone(),
            checkpoint_every: (self.checkpoint_every > 0).then_some(self.checkpoint_every),
            autoplay: !self.options.paused,
        })));
    }

    /// Change the speed of the running session.
    pub fn set_speed(&mut self, speed: Speed) {
        if speed != self.speed {
            self.speed = speed;
            self.trainer.send(Command::SetSpeed(speed));
        }
    }

    /// Change the checkpoint interval of the running session (0: off).
    pub fn set_checkpoint_every(&mut self, every: u64) {
        if every != self.checkpoint_every {
            self.checkpoint_every = every;
            self.trainer
                .send(Command::SetCheckpointEvery((every > 0).then_some(every)));
        }
    }

    /// Run or pause training.
    pub fn set_running(&mut self, running: bool) {
        self.options.paused = !running;
        self.trainer.send(Command::SetRunning(running));
    }

    /// Present `signals` signals now.
    pub fn step(&mut self, signals: u64) {
        self.trainer.send(Command::Step(signals));
    }

    /// Reconstruct a mesh from the current network.
    pub fn reconstruct_now(&mut self) {
        self.trainer.send(Command::Reconstruct);
    }

    /// Change the vertex target and apply it at once: restart training and recompute QEM.
    pub fn set_target(&mut self, target: usize) {
        let target = target.max(4);
        if target != self.applied.target_vertices || self.qem.target != target {
            self.params.target_vertices = target;
            self.reset_training();
        }
    }

    fn request_qem(&mut self) {
        if self.original.face_count() == 0 {
            return;
        }
        let target = self.params.target_vertices;
        let original = Arc::clone(&self.original);
        let attributes = self.attributes.clone();
        let place = Arc::clone(&self.place);
        self.qem.target = target;
        self.qem.error = None;
        self.qem.pending = Some(Job::spawn_background(
            "qem",
            self.repaint.clone(),
            move || {
                let model = mesh::Model {
                    mesh: (*original).clone(),
                    attributes: attributes.as_deref().cloned(),
                    ..(*place).clone()
                };
                let outcome = engine::qem_simplify(&model, target)?;
                let evaluation = engine::evaluate_with_attributes(
                    &original,
                    attributes.as_deref(),
                    &outcome.model.mesh,
                    outcome.model.attributes.as_ref(),
                )?;
                let mesh = Arc::new(outcome.model.mesh.clone());
                Ok((Arc::new(outcome), mesh, evaluation))
            },
        ));
    }

    /// Open a mesh file in the background.
    pub fn open_path(&mut self, path: PathBuf) {
        let job = io::spawn_load(path.clone(), self.repaint.clone());
        self.loading = Some((path, job));
    }

    /// Show an information message.
    pub fn info(&mut self, text: impl Into<String>) {
        self.push_message(text.into(), false);
    }

    /// Show an error message (also printed to stderr).
    pub fn error(&mut self, text: impl Into<String>) {
        self.push_message(text.into(), true);
    }

    fn push_message(&mut self, text: String, is_error: bool) {
        if is_error {
            eprintln!("viewer: {text}");
        }
        self.messages.push(Message { text, is_error });
        if self.messages.len() > 6 {
            self.messages.remove(0);
        }
    }

    /// Save the simplified mesh of `side` to `path` (format by extension); the outcome is also
    /// shown in the message strip.
    /// The finished run's model is saved as `gng3d simplify` saves it (its attributes,
    /// materials and origin: the same bytes for the same request); a checkpoint's preview is
    /// saved as a mesh in the original's place.
    pub fn export(&mut self, side: Side, path: &Path) -> Result<()> {
        let (mesh, outcome, what) = match side {
            Side::Gng => (
                self.reconstruction.as_ref(),
                self.gng_outcome.as_ref(),
                "no GNG3D reconstruction",
            ),
            Side::Qem => (
                self.qem.mesh.as_ref(),
                self.qem.outcome.as_ref(),
                "no QEM result",
            ),
        };
        let result = match (outcome, mesh) {
            (Some(outcome), _) => engine::save_model(&outcome.model, path),
            (None, Some(mesh)) => {
                engine::save_model(&self.place.with_mesh((**mesh).clone(), None), path)
            }
            (None, None) => Err(ViewerError::NothingToExport {
                path: path.to_path_buf(),
                what,
            }),
        };
        match &result {
            Ok(()) => self.info(format!("saved {}", path.display())),
            Err(e) => self.error(e.to_string()),
        }
        result
    }

    /// Write the checkpoint table as CSV to `path`, reporting the outcome in the message strip.
    pub fn export_csv(&mut self, path: &Path) -> Result<()> {
        let result = self.history.write_csv(path);
        match &result {
            Ok(()) => self.info(format!("saved {}", path.display())),
            Err(e) => self.error(e.to_string()),
        }
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    fn wait_until(session: &mut Session, what: &str, done: impl Fn(&Session) -> bool) {
        let start = Instant::now();
        while !done(session) {
            assert!(
                start.elapsed() < Duration::from_secs(90),
                "timed out waiting for {what}"
            );
            std::thread::sleep(Duration::from_millis(10));
            session.poll();
        }
    }

    /// Without a window or GPU: a fast run trains, records errors, reconstructs at checkpoints,
    /// evaluates them with the same function as QEM, and the state word is consistent.
    #[test]
    fn session_trains_checkpoints_and_evaluates_without_a_window() {
        let mut session = Session::new(
            ViewerOptions {
                target: Some(150),
                watch_seconds: Some(0.0),
                // 300 epochs of the built-in model's 7,594 vertices: long enough (~1 s in a
                // release build) for time-sampled error points (every ≥ 100 ms) at full speed.
                max_signals: Some(300 * 7_594),
                ..Default::default()
            },
            None,
        )
        .unwrap();
        let vertices = session.original().vertex_count() as u64;
        assert_eq!(
            vertices, 7_594,
            "built-in model changed: update max_signals"
        );
        assert_eq!(
            session.checkpoint_every, vertices,
            "paper protocol: every |V|"
        );
        wait_until(&mut session, "training, QEM and evaluations", |s| {
            s.live().finished && s.has_qem_mesh() && s.evaluations_pending() == 0
        });
        assert_eq!(session.training_state(), TrainingState::Finished);
        let h = &session.history;
        assert!(h.errors.len() >= 2, "{} error points", h.errors.len());
        // A checkpoint every epoch. As fast as possible, checkpoints beyond the time
        // share are skipped and an evaluator that falls behind skips to the newest, so the
        // table has at least the first checkpoint and the final reconstruction.
        assert!(
            h.reconstructions.len() >= 2,
            "{} checkpoints",
            h.reconstructions.len()
        );
        let last = h.reconstructions.last().unwrap();
        let direct =
            engine::evaluate(session.original(), session.reconstruction().unwrap()).unwrap();
        assert_eq!(last.evaluation, direct, "table row = direct evaluation");
        let qem = h.qem.as_ref().unwrap();
        let qem_direct = engine::evaluate(session.original(), session.qem_mesh().unwrap()).unwrap();
        assert_eq!(qem.evaluation, qem_direct);
        assert!(qem.evaluation.vertices <= 150);
        // Signed E_sur: Area(original) − Area(simplified), as the CLI reports it.
        let area = |m: &TriMesh| metrics::surface_error(m, m).original_area;
        let signed = area(session.original()) - area(session.qem_mesh().unwrap());
        assert!((qem.evaluation.e_sur - signed).abs() <= 1e-9 * signed.abs().max(1.0));
    }

    /// A watched run without a time limit of the user's is bounded by its watch time: the
    /// training is paced to leave the steps their time, the strip records every step, and the
    /// final mesh comes within 10 % of the watch time (the core stops at its limit; the pace
    /// leaves the steps 1.25 times their estimate).
    #[test]
    fn a_watched_run_holds_its_length_and_records_its_steps() {
        let watch = 3.0;
        let mut session = Session::new(
            ViewerOptions {
                target: Some(300),
                watch_seconds: Some(watch),
                checkpoint_every: Some(0),
                ..Default::default()
            },
            None,
        )
        .unwrap();
        wait_until(&mut session, "the final mesh", |s| {
            s.steps.phase() == crate::steps::Phase::Done && s.reconstruction().is_some()
        });
        let steps = &session.steps;
        let limit = steps.limit.expect("the watch time is the run's limit");
        assert_eq!(limit.seconds, watch);
        assert!(limit.is_watch_time);
        assert!(
            limit.steps_estimate > 0.0 && limit.steps_estimate < watch,
            "{limit:?}"
        );
        let run = steps.run_seconds.unwrap();
        assert!(
            (0.85 * watch..=1.1 * watch).contains(&run),
            "start to final mesh: {run:.2} s of {watch} s"
        );
        // The training ran for its pace (the watch time less the steps' share), not the whole
        // watch time.
        let training = steps.training_seconds.unwrap();
        let pace = session.live().pace_seconds.expect("paced");
        assert!(pace < watch - limit.steps_estimate, "{pace} {limit:?}");
        assert!(
            training >= pace - 0.05 && training <= pace + 0.3,
            "training {training:.2} s, pace {pace:.2} s"
        );
        let rows = steps.rows();
        let done: f64 = rows
            .iter()
            .map(|r| match r.status {
                crate::steps::StepStatus::Done { seconds, .. } => seconds,
                _ => 0.0,
            })
            .sum();
        assert!(done > 0.0 && done <= steps.pipeline_seconds.unwrap() + 1e-9);
        assert!(
            rows.iter()
                .all(|r| r.status != crate::steps::StepStatus::Pending)
        );
    }

    #[test]
    fn missing_file_is_an_error_message_and_the_built_in_model_stands_in() {
        let mut session = Session::new(
            ViewerOptions {
                path: Some("/nonexistent/model.obj".into()),
                ..Default::default()
            },
            None,
        )
        .unwrap();
        wait_until(&mut session, "the load to fail", |s| !s.is_loading());
        let error = session.messages.iter().find(|m| m.is_error).expect("error");
        assert!(
            error.text.contains("/nonexistent/model.obj"),
            "{}",
            error.text
        );
        assert!(session.original().face_count() > 0);
        let err = session
            .export(Side::Gng, Path::new("/tmp/never-written.obj"))
            .unwrap_err();
        assert!(matches!(err, ViewerError::NothingToExport { .. }), "{err}");
    }
}

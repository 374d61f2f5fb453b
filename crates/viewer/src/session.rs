//! The viewer's state without any UI: the model, the training thread, the QEM job, the
//! evaluations, the plot history and the messages. The window ([`crate::app`]) draws it and turns
//! clicks into calls here; tests drive it directly, without a window or a GPU.
//!
//! Two single places the rest of the workspace may swap out:
//! - [`train_params`]: start-up options → validated GNG3D parameters (headless and window mode);
//! - [`crate::engine::evaluate`]: the one evaluation of a simplified mesh (table, plots, QEM).
//!
//! (About a fifth of this file is its GPU-free tests, the last ~220 lines.)

use crate::engine::{self, Evaluation, TrainParams};
use crate::error::{Result, ViewerError};
use crate::io::{self, LoadedModel};
use crate::jobs::Job;
use crate::plots::{Checkpoint, History};
use crate::steps::{RunLimit, StepStrip, TrainingClock};
use crate::worker::{self, Command, Event, Live, Speed, TrainingJob};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Default length of a watched run, training and the steps after it: the signal budget is
/// spread over the training's share of this many seconds, so the network visibly grows whatever
/// the mesh size (issue 13: "roughly 10–20 s"), and the final mesh comes about this long after
/// the start ([`worker::run_time_limit`], [`worker::pace_seconds`]).
pub const DEFAULT_WATCH_SECONDS: f64 = 12.0;

/// As fast as possible, evaluations of checkpoints (200k-sample Hausdorff, on their own thread)
/// may keep a core busy at most this share of the wall time: after one that took `d`, the next
/// waits `d · (1 / share − 1)` before it starts. On two cores it otherwise shares the UI's core
/// with the CPU renderer and takes time from training (with armadillo and 10,000 nodes,
/// training ran at 7-8 % of its headless rate).
pub const EVALUATION_TIME_SHARE: f64 = 0.25;

/// Start-up options (from the command line).
#[derive(Debug, Clone, Default)]
pub struct ViewerOptions {
    /// Mesh to open (`None`: the built-in procedural model).
    pub path: Option<PathBuf>,
    /// Close the window after this many seconds.
    pub quit_after: Option<f64>,
    /// Save a PNG of the window just before quitting (needs `quit_after`).
    pub screenshot: Option<PathBuf>,
    /// Vertex target for both methods.
    pub target: Option<usize>,
    /// GNG3D time limit, seconds.
    pub time_limit: Option<f64>,
    /// Seed of the training signals.
    pub seed: Option<u64>,
    /// GNG3D signal budget (`None`: the crate's default, `DEFAULT_SIGNALS_PER_NODE` × output vertices).
    pub max_signals: Option<u64>,
    /// λ, signals between insertions (`None`: the crate's automatic choice).
    pub lambda: Option<u32>,
    /// Length of a watched run in seconds (`None`: [`DEFAULT_WATCH_SECONDS`]; 0: as fast as
    /// possible).
    pub watch_seconds: Option<f64>,
    /// Reconstruct and evaluate every this many signals (`None`: every |V| signals, the paper's
    /// protocol; 0: only at the end and on request).
    pub checkpoint_every: Option<u64>,
    /// Start paused instead of training right away.
    pub paused: bool,
    /// Print frame and training statistics to stdout when quitting.
    pub print_stats: bool,
    /// Inner window size in points (default 1600×900).
    pub window_size: Option<[f32; 2]>,
    /// Start with the parameter panel open (`true`) or closed (`false`); `None`: open where
    /// the window is at least 1350 points wide and the plots panel keeps its wanted height
    /// with it ([`crate::app::Panels::for_width`]: 1600×900 yes, 1366×768 no).
    pub controls: Option<bool>,
}

/// The one mapping from user options to GNG3D parameters, shared by the window and headless
/// mode. Rejects values that would panic or silently mean something else (negative or NaN
/// seconds, zero budgets) with an error naming the option.
pub fn train_params(options: &ViewerOptions) -> Result<TrainParams> {
    fn invalid(option: &'static str, problem: impl Into<String>) -> ViewerError {
        ViewerError::InvalidOption {
            option,
            problem: problem.into(),
        }
    }
    let target = options.target.unwrap_or(1000);
    if target < 4 {
        return Err(invalid(
            "--target",
            format!("{target} (at least 4 vertices)"),
        ));
    }
    let gng = gng3d_core::GngOptions {
        target: gng3d_core::GngTarget::Vertices(target),
        time_limit_seconds: options.time_limit,
        max_signals: options.max_signals,
        lambda: options.lambda,
        seed: options
            .seed
            .unwrap_or(gng3d_core::GngParams::default().seed),
        ..gng3d_core::GngOptions::default()
    };
    // The library's one validation of GNG3D options (the CLI uses the same); the option name
    // the user typed is added here, and only the rule of the library's message is kept (no
    // parameter names of the library's, issue 37).
    let flag_and_problem = |e: &gng3d_core::GngError| {
        use gng3d_core::{GngError, GngParameter};
        match e {
            GngError::Parameter {
                parameter,
                value,
                rule,
            } => {
                let flag = match parameter {
                    GngParameter::TimeLimit => "--time-limit",
                    GngParameter::MaxSignals => "--max-signals",
                    GngParameter::Lambda => "--lambda",
                    _ => "--target",
                };
                (flag, format!("{value}: {rule}"))
            }
            other => ("--target", other.to_string()),
        }
    };
    // The input's size is not known yet: the options are checked here (ratios are not offered,
    // so any count will do) and resolved against the mesh when a run starts (`Engine::new`).
    // The step switches the UI shows are the user's choices, not what a resolution against an
    // unknown size would make of them (against usize::MAX every output is under 5 % of the
    // input, which turned the deviation repair off for every run).
    let params = gng.resolve_for_vertex_count(usize::MAX).map_err(|e| {
        let (flag, problem) = flag_and_problem(&e);
        invalid(flag, problem)
    })?;
    let params = TrainParams {
        reconstruction: gng.reconstruction.clone(),
        ..params
    };
    if let Some(seconds) = options.watch_seconds
        && !(seconds.is_finite() && seconds >= 0.0)
    {
        return Err(invalid(
            "--watch",
            format!("{seconds} (seconds >= 0; 0 = as fast as possible)"),
        ));
    }
    if let Some(v) = options.quit_after
        && !(v.is_finite() && v >= 0.0)
    {
        return Err(invalid("--quit-after", format!("{v} (seconds >= 0)")));
    }
    // A scripted screenshot that cannot happen is an error before any window opens, not a
    // message in a window that then exits 0.
    if let Some(path) = &options.screenshot {
        let shown = path.display();
        if options.quit_after.is_none() {
            return Err(invalid(
                "--screenshot",
                format!("{shown}: needs --quit-after SECS (it is taken just before quitting)"),
            ));
        }
        if !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"))
        {
            return Err(invalid(
                "--screenshot",
                format!("{shown}: screenshots are PNG files (give a .png path)"),
            ));
        }
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        if !dir.is_dir() {
            return Err(invalid(
                "--screenshot",
                format!("{shown}: the folder {} does not exist", dir.display()),
            ));
        }
    }
    Ok(params)
}

/// The vertex target of a mesh of `vertices` vertices when the user gave none (window and
/// headless alike): a tenth of the vertices, 200 to 10,000.
pub fn default_target(vertices: usize) -> usize {
    (vertices / 10).clamp(200, 10_000).min(vertices.max(4))
}

/// The training speed the options ask for.
pub fn speed_for(watch_seconds: Option<f64>) -> Speed {
    match watch_seconds.unwrap_or(DEFAULT_WATCH_SECONDS) {
        s if s > 0.0 && s.is_finite() => Speed::Paced { seconds: s },
        _ => Speed::Unlimited,
    }
}

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

/// What QEM computed: the mesh, its evaluation, the seconds it took and a note when it stopped
/// above the target.
type QemResult = Result<(Arc<TriMesh>, Evaluation, f64, Option<String>)>;

/// The QEM side.
#[derive(Default)]
struct QemState {
    target: usize,
    mesh: Option<Arc<TriMesh>>,
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
            loading: None,
            applied: params.clone(),
            params,
            trainer,
            live: Live::default(),
            history: History::default(),
            steps: StepStrip::default(),
            reconstruction: None,
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
        self.set_model_with_attributes(name, mesh, None);
    }

    /// [`Session::set_model`] for a model with `attributes` (of `mesh`'s corners).
    pub fn set_model_with_attributes(
        &mut self,
        name: String,
        mesh: Arc<TriMesh>,
        attributes: Option<Arc<Attributes>>,
    ) {
        self.model_name = name;
        self.attributes = attributes;
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
        self.qem.target = target;
        self.qem.error = None;
        self.qem.pending = Some(Job::spawn_background(
            "qem",
            self.repaint.clone(),
            move || {
                let started = std::time::Instant::now();
                let (mesh, kept, note) =
                    engine::qem_simplify_with_attributes(&original, attributes.as_deref(), target)?;
                let seconds = started.elapsed().as_secs_f64();
                let evaluation = engine::evaluate_with_attributes(
                    &original,
                    attributes.as_deref(),
                    &mesh,
                    kept.as_ref(),
                )?;
                Ok((Arc::new(mesh), evaluation, seconds, note))
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
                self.set_model_with_attributes(model.name, model.mesh, model.attributes);
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
                    warnings,
                } if s == session => {
                    for w in warnings {
                        self.info(format!("GNG3D warning: {w}"));
                    }
                    self.evaluation_queue.push_back(PendingEvaluation {
                        session: s,
                        signals,
                        train_seconds,
                        mesh: Arc::clone(&mesh),
                    });
                    self.reconstruction = Some(mesh);
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
            let attributes = self.attributes.clone();
            let job = Job::spawn_background("evaluation", self.repaint.clone(), move || {
                std::thread::sleep(wait);
                let started = std::time::Instant::now();
                let result =
                    engine::evaluate_reconstruction(&original, attributes.as_deref(), &mesh);
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
            Ok((mesh, e, seconds, note)) => {
                self.history.qem = Some(checkpoint("QEM", 0, &e, seconds));
                self.qem.mesh = Some(mesh);
                if let Some(note) = note {
                    self.info(note);
                }
            }
            Err(e) => {
                self.qem.mesh = None;
                self.error(e.to_string());
                self.qem.error = Some(e.to_string());
            }
        }
    }

    /// Save the simplified mesh of `side` to `path` (format by extension); the outcome is also
    /// shown in the message strip.
    pub fn export(&mut self, side: Side, path: &Path) -> Result<()> {
        let (mesh, what) = match side {
            Side::Gng => (self.reconstruction.clone(), "no GNG3D reconstruction"),
            Side::Qem => (self.qem.mesh.clone(), "no QEM result"),
        };
        let result = match mesh {
            Some(mesh) => io::export_mesh(&mesh, path),
            None => Err(ViewerError::NothingToExport {
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

/// A table row from an evaluation.
fn checkpoint(method: &'static str, iteration: u64, e: &Evaluation, seconds: f64) -> Checkpoint {
    Checkpoint {
        method,
        iteration,
        evaluation: *e,
        seconds,
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

    /// The UI's step switches start as the library's defaults (the deviation repair on):
    /// resolving against an unknown input size must not decide them.
    #[test]
    fn the_step_switches_start_as_the_library_defaults() {
        let params = train_params(&ViewerOptions::default()).unwrap();
        assert_eq!(
            params.reconstruction,
            gng3d_core::ReconstructionParams::default()
        );
        assert!(params.reconstruction.repair_deviations);
    }

    #[test]
    fn bad_options_are_errors_naming_the_option() {
        for (options, flag) in [
            (
                ViewerOptions {
                    time_limit: Some(-1.0),
                    ..Default::default()
                },
                "--time-limit",
            ),
            (
                ViewerOptions {
                    time_limit: Some(f64::NAN),
                    ..Default::default()
                },
                "--time-limit",
            ),
            (
                ViewerOptions {
                    target: Some(2),
                    ..Default::default()
                },
                "--target",
            ),
            (
                ViewerOptions {
                    watch_seconds: Some(f64::INFINITY),
                    ..Default::default()
                },
                "--watch",
            ),
            (
                ViewerOptions {
                    quit_after: Some(-3.0),
                    ..Default::default()
                },
                "--quit-after",
            ),
            (
                ViewerOptions {
                    max_signals: Some(0),
                    ..Default::default()
                },
                "--max-signals",
            ),
        ] {
            let err = train_params(&options).unwrap_err();
            assert!(err.to_string().contains(flag), "{err}");
            assert!(Session::new(options, None).is_err());
        }
        let params = train_params(&ViewerOptions {
            time_limit: Some(2.5),
            target: Some(300),
            seed: Some(9),
            ..Default::default()
        })
        .unwrap();
        assert_eq!(params.time_limit, Some(Duration::from_secs_f64(2.5)));
        assert_eq!((params.target_vertices, params.seed), (300, 9));
        assert_eq!(speed_for(Some(0.0)), Speed::Unlimited);
        assert_eq!(
            speed_for(None),
            Speed::Paced {
                seconds: DEFAULT_WATCH_SECONDS
            }
        );
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

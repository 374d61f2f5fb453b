//! The viewer application: one struct with all immediate-mode state, drawn each frame by
//! [`ViewerApp::show`]. Left viewport: the GNG3D network as it trains (then its reconstruction);
//! right viewport: QEM at the same vertex count; both share one orbit camera.

use crate::engine::{self, TrainParams};
use crate::io::{self, DialogPurpose, Dialogs, LoadedModel};
use crate::plots::{self, Checkpoint, History};
use crate::render::{
    DrawItem, GpuMesh, GpuNetwork, OrbitCamera, SceneRenderer, Shading, ViewTarget,
};
use crate::worker::{
    self, Command, Event, Live, QemOutcome, ReconstructionEvaluation, Session, Speed,
};
use egui::{Color32, RichText};
use egui_wgpu::RenderState;
use mesh::TriMesh;
use std::path::PathBuf;
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// Frame interval while training runs: at most 40 fps, so that on a CPU renderer the UI leaves
/// cores to the training thread.
pub const TRAINING_FRAME_INTERVAL: Duration = Duration::from_millis(25);

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
    /// GNG3D signal budget (`None`: the crate's default, 30 epochs).
    pub max_signals: Option<u64>,
    /// λ, signals between insertions (`None`: the crate's automatic choice).
    pub lambda: Option<u32>,
    /// Start paused instead of training right away.
    pub paused: bool,
    /// Print frame and training statistics to stdout when quitting.
    pub print_stats: bool,
    /// Inner window size in points (default 1600×900).
    pub window_size: Option<[f32; 2]>,
}

/// Which viewport.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// GNG3D (left).
    Gng,
    /// QEM (right).
    Qem,
}

/// Display toggles.
#[derive(Debug, Clone, PartialEq)]
pub struct Display {
    /// Flat or smooth shading of surfaces.
    pub shading: Shading,
    /// Draw mesh edges over surfaces.
    pub wireframe: bool,
    /// Draw the original mesh translucently over both views.
    pub show_original: bool,
    /// Draw the live network (nodes and edges) in the left view.
    pub show_network: bool,
    /// Draw the GNG3D reconstruction in the left view when there is one.
    pub show_gng_mesh: bool,
    /// Node diameter in pixels.
    pub point_px: f32,
    /// Anti-alias the UI's own shapes (egui "feathering"); switching it off saves about 1 ms per
    /// frame on a software renderer.
    pub smooth_ui: bool,
}

impl Default for Display {
    fn default() -> Self {
        Display {
            shading: Shading::Smooth,
            wireframe: false,
            show_original: false,
            show_network: true,
            show_gng_mesh: true,
            point_px: 4.0,
            smooth_ui: true,
        }
    }
}

/// Frame timing statistics.
#[derive(Debug, Clone)]
pub struct FrameStats {
    last: Option<Instant>,
    recent: std::collections::VecDeque<f64>,
    /// Frames since start.
    pub frames: u64,
    /// Frames counted for the run summary (after a 1 s warm-up).
    pub measured_frames: u64,
    /// Time covered by `measured_frames`, seconds.
    pub measured_seconds: f64,
    /// Highest node count seen while measuring.
    pub max_nodes: usize,
    /// Signals/s samples while training ran.
    pub rate_samples: Vec<f64>,
    /// On-CPU seconds of the drawing threads (see [`drawing_cpu_seconds`]) when measuring began.
    cpu_at_measure_start: Option<f64>,
    /// How often each viewport (GNG3D, QEM) was actually redrawn; an unchanged viewport is not.
    pub viewport_redraws: [u64; 2],
}

impl FrameStats {
    fn new() -> FrameStats {
        FrameStats {
            last: None,
            recent: std::collections::VecDeque::with_capacity(128),
            frames: 0,
            measured_frames: 0,
            measured_seconds: 0.0,
            max_nodes: 0,
            rate_samples: Vec::new(),
            cpu_at_measure_start: None,
            viewport_redraws: [0; 2],
        }
    }

    fn tick(&mut self, since_start: f64) {
        let now = Instant::now();
        if let Some(last) = self.last {
            let dt = now.duration_since(last).as_secs_f64();
            if self.recent.len() == 120 {
                self.recent.pop_front();
            }
            self.recent.push_back(dt);
            if since_start > 1.0 {
                self.measured_frames += 1;
                self.measured_seconds += dt;
                if self.measured_frames == 1 {
                    self.cpu_at_measure_start = drawing_cpu_seconds();
                }
            }
        }
        self.frames += 1;
        self.last = Some(now);
    }

    /// Mean frame time over the last 120 frames, milliseconds.
    pub fn frame_ms(&self) -> f64 {
        if self.recent.is_empty() {
            0.0
        } else {
            self.recent.iter().sum::<f64>() / self.recent.len() as f64 * 1000.0
        }
    }

    /// Mean on-CPU time of the drawing threads per frame since measuring began (after the 1 s
    /// warm-up), milliseconds; 0 where unknown.
    pub fn drawing_cpu_ms_per_frame(&self) -> f64 {
        match (self.cpu_at_measure_start, drawing_cpu_seconds()) {
            (Some(start), Some(now)) if self.measured_frames > 1 => {
                (now - start) / (self.measured_frames - 1) as f64 * 1000.0
            }
            _ => 0.0,
        }
    }

    /// Frames per second over the measured period.
    pub fn mean_fps(&self) -> f64 {
        if self.measured_seconds > 0.0 {
            self.measured_frames as f64 / self.measured_seconds
        } else {
            0.0
        }
    }
}

/// One row of the parameter grid: a label, `widget` labelled by it, end of row.
fn param_row(ui: &mut egui::Ui, label: &str, widget: impl egui::Widget) -> egui::Response {
    let label = ui.label(label);
    let response = ui.add(widget).labelled_by(label.id);
    ui.end_row();
    response
}

/// Names of the viewer's own worker threads: everything else in the process draws the UI (the
/// main thread and the software rasterizer's threads).
const WORKER_THREADS: [&str; 5] = [
    "gng-training",
    "qem",
    "evaluation",
    "load-mesh",
    "file-dialog",
];

/// Total on-CPU seconds of the threads that draw (all but [`WORKER_THREADS`]), from
/// `/proc/self/task/*/schedstat`; `None` where that is unavailable (not Linux). Independent of
/// how long the threads waited for a core, so it measures the cost of drawing on a busy machine.
fn drawing_cpu_seconds() -> Option<f64> {
    let tasks = std::fs::read_dir("/proc/self/task").ok()?;
    let mut nanoseconds = 0u64;
    for task in tasks.flatten() {
        let dir = task.path();
        let Ok(comm) = std::fs::read_to_string(dir.join("comm")) else {
            continue;
        };
        if WORKER_THREADS.contains(&comm.trim()) {
            continue;
        }
        if let Some(ns) = std::fs::read_to_string(dir.join("schedstat"))
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        {
            nanoseconds += ns;
        }
    }
    Some(nanoseconds as f64 * 1e-9)
}

/// A message shown in the message strip.
#[derive(Debug, Clone)]
pub struct Message {
    /// Text.
    pub text: String,
    /// Whether it is an error (red) or information.
    pub is_error: bool,
}

/// The QEM side.
#[derive(Default)]
struct QemState {
    target: usize,
    mesh: Option<Arc<TriMesh>>,
    pending: Option<(usize, Receiver<QemOutcome>)>,
    error: Option<String>,
}

/// GPU resources (absent when no wgpu render state is available).
struct Gpu {
    render_state: RenderState,
    scene: SceneRenderer,
    targets: [ViewTarget; 2],
    original: Option<GpuMesh>,
    gng_mesh: Option<GpuMesh>,
    qem_mesh: Option<GpuMesh>,
    network: GpuNetwork,
    network_source: Option<Arc<engine::NetworkSnapshot>>,
}

/// Screenshot-and-quit automation state.
#[derive(Default)]
struct Automation {
    screenshot_requested: bool,
    screenshot_since: Option<Instant>,
    screenshot_result: Arc<Mutex<Option<Result<PathBuf, String>>>>,
    close_sent: bool,
}

/// The viewer application.
pub struct ViewerApp {
    options: ViewerOptions,
    gpu: Option<Gpu>,
    ctx: Option<egui::Context>,
    /// Display name of the model.
    pub model_name: String,
    original: Arc<TriMesh>,
    loading: Option<(PathBuf, Receiver<Result<LoadedModel, String>>)>,
    /// Training parameters used by the next reset.
    pub params: TrainParams,
    /// Train as fast as possible (otherwise `signals_per_frame`).
    pub unlimited_speed: bool,
    /// Signals per frame when not unlimited.
    pub signals_per_frame: u64,
    /// Reconstruct every this many signals (0: only at the end and on request).
    pub checkpoint_every: u64,
    trainer: worker::Trainer,
    live: Live,
    /// Plot and table data.
    pub history: History,
    reconstruction: Option<Arc<TriMesh>>,
    evaluations: (
        Sender<ReconstructionEvaluation>,
        Receiver<ReconstructionEvaluation>,
    ),
    qem: QemState,
    /// The shared camera.
    pub camera: OrbitCamera,
    /// Display toggles.
    pub display: Display,
    /// Recent messages (newest last).
    pub messages: Vec<Message>,
    dialogs: Dialogs,
    /// Frame statistics.
    pub stats: FrameStats,
    started: Instant,
    automation: Automation,
    /// Screen rectangles of the two viewports in the last frame (GNG3D, QEM), in points.
    pub viewport_rects: [Option<egui::Rect>; 2],
    show_plots: bool,
    ctx_bound: bool,
}

impl ViewerApp {
    /// Create the app. `render_state` is eframe's (or a test harness') wgpu state; without it the
    /// viewports stay empty.
    pub fn new(
        ctx: &egui::Context,
        render_state: Option<RenderState>,
        options: ViewerOptions,
    ) -> ViewerApp {
        let gpu = render_state.map(|render_state| {
            let scene = SceneRenderer::new(&render_state.device, render_state.target_format);
            let targets = [
                scene.create_target(&render_state.device, [64, 64]),
                scene.create_target(&render_state.device, [64, 64]),
            ];
            let network = GpuNetwork::new(&render_state.device);
            Gpu {
                render_state,
                scene,
                targets,
                original: None,
                gng_mesh: None,
                qem_mesh: None,
                network,
                network_source: None,
            }
        });
        let trainer = worker::Trainer::spawn();
        trainer.set_repaint_context(ctx);
        let mut params = engine::default_params(options.target.unwrap_or(1000));
        params.time_limit = options
            .time_limit
            .filter(|s| s.is_finite() && *s > 0.0)
            .map(Duration::from_secs_f64);
        if let Some(seed) = options.seed {
            params.seed = seed;
        }
        params.max_signals = options.max_signals;
        params.lambda = options.lambda;
        let mut app = ViewerApp {
            gpu,
            ctx: Some(ctx.clone()),
            model_name: String::new(),
            original: Arc::new(TriMesh::new(Vec::new(), Vec::new())),
            loading: None,
            params,
            unlimited_speed: true,
            signals_per_frame: 200,
            checkpoint_every: 0,
            trainer,
            live: Live::default(),
            history: History::default(),
            reconstruction: None,
            evaluations: mpsc::channel(),
            qem: QemState::default(),
            camera: OrbitCamera::default(),
            display: Display::default(),
            messages: Vec::new(),
            dialogs: Dialogs::default(),
            stats: FrameStats::new(),
            started: Instant::now(),
            automation: Automation::default(),
            viewport_rects: [None, None],
            show_plots: true,
            ctx_bound: false,
            options,
        };
        match app.options.path.clone() {
            Some(path) => {
                app.open_path(path);
            }
            None => {
                let (name, mesh) = engine::default_model();
                app.set_model(name, Arc::new(mesh));
            }
        }
        app
    }

    /// Replace the model: frame the camera, restart training and QEM.
    pub fn set_model(&mut self, name: String, mesh: Arc<TriMesh>) {
        self.model_name = name;
        self.camera = OrbitCamera::framing(&mesh.referenced_bounding_box());
        if self.options.target.is_none() {
            let n = mesh.vertex_count();
            self.params.target_vertices = (n / 10).clamp(200, 10_000).min(n.max(4));
        }
        self.original = mesh;
        if let Some(gpu) = self.gpu.as_mut() {
            gpu.original = Some(GpuMesh::new(&gpu.render_state.device, &self.original));
        }
        self.qem = QemState::default();
        self.history = History::default();
        self.reset_training();
        self.request_qem();
    }

    /// The mesh being simplified.
    pub fn original(&self) -> &Arc<TriMesh> {
        &self.original
    }

    /// Whether a model is being loaded.
    pub fn is_loading(&self) -> bool {
        self.loading.is_some()
    }

    /// Whether a QEM result is shown.
    pub fn has_qem_mesh(&self) -> bool {
        self.qem.mesh.is_some()
    }

    /// The latest state of the training thread.
    pub fn live(&self) -> &Live {
        &self.live
    }

    /// Start a new training session with the current parameters.
    pub fn reset_training(&mut self) {
        self.history.clear_training();
        self.reconstruction = None;
        if let Some(gpu) = self.gpu.as_mut() {
            gpu.gng_mesh = None;
        }
        if self.original.face_count() == 0 {
            return;
        }
        self.trainer.send(Command::SetSpeed(self.speed()));
        self.trainer.send(Command::Reset(Box::new(Session {
            mesh: Arc::clone(&self.original),
            params: self.params.clone(),
            checkpoint_every: (self.checkpoint_every > 0).then_some(self.checkpoint_every),
            autoplay: !self.options.paused,
        })));
    }

    fn speed(&self) -> Speed {
        if self.unlimited_speed {
            Speed::Unlimited
        } else {
            Speed::PerFrame(self.signals_per_frame.max(1))
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

    /// Change the vertex target: restart training and recompute QEM.
    pub fn set_target(&mut self, target: usize) {
        let target = target.max(4);
        if target != self.params.target_vertices || self.qem.target != target {
            self.params.target_vertices = target;
            self.reset_training();
            self.request_qem();
        }
    }

    fn request_qem(&mut self) {
        if self.original.face_count() == 0 {
            return;
        }
        let target = self.params.target_vertices;
        self.qem.target = target;
        self.qem.error = None;
        self.qem.pending = Some((
            target,
            worker::spawn_qem(Arc::clone(&self.original), target, self.ctx.clone()),
        ));
    }

    /// Open a mesh file in the background.
    pub fn open_path(&mut self, path: PathBuf) {
        let rx = io::spawn_load(path.clone(), self.ctx.clone());
        self.loading = Some((path, rx));
    }

    fn info(&mut self, text: impl Into<String>) {
        self.push_message(text.into(), false);
    }

    fn error(&mut self, text: impl Into<String>) {
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

    /// Collect results from background threads (non-blocking).
    fn poll_background(&mut self) {
        if let Some((_, rx)) = &self.loading
            && let Ok(result) = rx.try_recv()
        {
            self.loading = None;
            match result {
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
                    self.set_model(model.name, model.mesh);
                }
                Err(e) => {
                    self.error(format!("could not open: {e}"));
                    if self.original.face_count() == 0 {
                        let (name, mesh) = engine::default_model();
                        self.set_model(name, Arc::new(mesh));
                    }
                }
            }
        }

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
                } if s == session => {
                    if let Some(gpu) = self.gpu.as_mut() {
                        gpu.gng_mesh = Some(GpuMesh::new(&gpu.render_state.device, &mesh));
                    }
                    worker::spawn_evaluation(
                        Arc::clone(&self.original),
                        Arc::clone(&mesh),
                        s,
                        signals,
                        train_seconds,
                        self.evaluations.0.clone(),
                        self.ctx.clone(),
                    );
                    self.reconstruction = Some(mesh);
                }
                Event::Failed {
                    session: s,
                    message,
                } if s == session => self.error(message),
                _ => {}
            }
        }
        while let Ok(done) = self.evaluations.1.try_recv() {
            if done.session == session {
                let e = done.evaluation;
                self.history.push_reconstruction(Checkpoint {
                    method: "GNG3D",
                    iteration: done.signals,
                    vertices: e.vertices,
                    faces: e.faces,
                    e_avg: e.e_avg,
                    e_max: e.e_max,
                    e_sur: e.e_sur,
                    hausdorff: e.hausdorff,
                    seconds: done.train_seconds,
                });
            }
        }

        if let Some((target, rx)) = &self.qem.pending
            && let Ok(outcome) = rx.try_recv()
        {
            let current = *target == self.qem.target;
            self.qem.pending = None;
            if current && outcome.target == self.qem.target {
                match outcome.result {
                    Ok((mesh, e, seconds)) => {
                        if let Some(gpu) = self.gpu.as_mut() {
                            gpu.qem_mesh = Some(GpuMesh::new(&gpu.render_state.device, &mesh));
                        }
                        self.history.qem = Some(Checkpoint {
                            method: "QEM",
                            iteration: 0,
                            vertices: e.vertices,
                            faces: e.faces,
                            e_avg: e.e_avg,
                            e_max: e.e_max,
                            e_sur: e.e_sur,
                            hausdorff: e.hausdorff,
                            seconds,
                        });
                        self.qem.mesh = Some(mesh);
                    }
                    Err(e) => {
                        self.qem.mesh = None;
                        if let Some(gpu) = self.gpu.as_mut() {
                            gpu.qem_mesh = None;
                        }
                        self.error(format!("QEM: {e}"));
                        self.qem.error = Some(e);
                    }
                }
            }
        }

        if let Some((purpose, path)) = self.dialogs.poll()
            && let Some(path) = path
        {
            self.handle_dialog(purpose, path);
        }
    }

    fn handle_dialog(&mut self, purpose: DialogPurpose, path: PathBuf) {
        match purpose {
            DialogPurpose::OpenMesh => self.open_path(path),
            DialogPurpose::ExportGng => {
                let _ = self.export(Side::Gng, &path);
            }
            DialogPurpose::ExportQem => {
                let _ = self.export(Side::Qem, &path);
            }
            DialogPurpose::ExportCsv => match self.history.write_csv(&path) {
                Ok(()) => self.info(format!("saved {}", path.display())),
                Err(e) => self.error(e),
            },
            DialogPurpose::Screenshot => self.request_screenshot(path),
        }
    }

    /// Save the simplified mesh of `side` to `path` (format by extension); the outcome is also
    /// shown in the message strip.
    pub fn export(&mut self, side: Side, path: &std::path::Path) -> Result<(), String> {
        let mesh = match side {
            Side::Gng => self.reconstruction.clone(),
            Side::Qem => self.qem.mesh.clone(),
        };
        let result = match mesh {
            Some(mesh) => io::export_mesh(&mesh, path),
            None => Err(format!("{}: nothing to export yet", path.display())),
        };
        match &result {
            Ok(()) => self.info(format!("saved {}", path.display())),
            Err(e) => self.error(e.clone()),
        }
        result
    }

    /// Save a PNG of the whole window to `path` once the next frame is rendered.
    pub fn request_screenshot(&mut self, path: PathBuf) {
        let Some(ctx) = self.ctx.clone() else {
            return;
        };
        let slot = Arc::clone(&self.automation.screenshot_result);
        let repaint = ctx.clone();
        ctx.request_screenshot(move |image| {
            let result = io::save_png(&image, &path).map(|()| path);
            *slot.lock().unwrap_or_else(PoisonError::into_inner) = Some(result);
            repaint.request_repaint();
        });
        ctx.request_repaint();
    }

    fn automation(&mut self, ctx: &egui::Context) {
        let finished_shot = self
            .automation
            .screenshot_result
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take();
        if let Some(result) = finished_shot {
            match result {
                Ok(path) => self.push_message(format!("saved {}", path.display()), false),
                Err(e) => self.push_message(format!("screenshot failed: {e}"), true),
            }
            if self.automation.screenshot_requested {
                self.automation.screenshot_requested = false;
                self.close(ctx);
            }
        }
        let Some(limit) = self.options.quit_after else {
            return;
        };
        if self.automation.screenshot_requested
            && self
                .automation
                .screenshot_since
                .is_some_and(|t| t.elapsed() > Duration::from_secs(10))
        {
            self.push_message("screenshot timed out after 10 s".into(), true);
            self.automation.screenshot_requested = false;
            self.close(ctx);
        }
        let elapsed = self.started.elapsed().as_secs_f64();
        if elapsed < limit || self.automation.close_sent || self.automation.screenshot_requested {
            ctx.request_repaint_after(Duration::from_millis(50));
            return;
        }
        match self.options.screenshot.clone() {
            Some(path) => {
                self.automation.screenshot_requested = true;
                self.automation.screenshot_since = Some(Instant::now());
                self.request_screenshot(path);
            }
            None => self.close(ctx),
        }
    }

    fn close(&mut self, ctx: &egui::Context) {
        if self.automation.close_sent {
            return;
        }
        self.automation.close_sent = true;
        if self.options.print_stats {
            println!("{}", self.summary());
        }
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    /// One-line run summary (fps, training rate, sizes).
    pub fn summary(&self) -> String {
        let rates = &self.stats.rate_samples;
        let mean_rate = if rates.is_empty() {
            0.0
        } else {
            rates.iter().sum::<f64>() / rates.len() as f64
        };
        format!(
            "viewer stats: model={} frames={} mean_fps={:.1} last_frame_ms={:.1} \
             drawing_cpu_ms_per_frame={:.1} max_nodes={} signals={} mean_signals_per_s={:.0} \
             train_s={:.2} gng_mesh_faces={} qem_faces={}",
            self.model_name,
            self.stats.frames,
            self.stats.mean_fps(),
            self.stats.frame_ms(),
            self.stats.drawing_cpu_ms_per_frame(),
            self.stats.max_nodes,
            self.live.snapshot.signals,
            mean_rate,
            self.live.train_seconds,
            self.reconstruction.as_ref().map_or(0, |m| m.face_count()),
            self.qem.mesh.as_ref().map_or(0, |m| m.face_count()),
        )
    }

    /// Draw one frame.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        if !self.ctx_bound {
            // The context given at construction may not be the one that draws (test harnesses).
            self.ctx = Some(ctx.clone());
            self.trainer.set_repaint_context(&ctx);
            self.ctx_bound = true;
        }
        if ctx.tessellation_options(|o| o.feathering) != self.display.smooth_ui {
            ctx.tessellation_options_mut(|o| o.feathering = self.display.smooth_ui);
        }
        let since_start = self.started.elapsed().as_secs_f64();
        self.stats.tick(since_start);
        self.poll_background();
        if self.live.running {
            self.stats.max_nodes = self.stats.max_nodes.max(self.live.snapshot.positions.len());
            if self.live.signals_per_second > 0.0 && since_start > 1.0 {
                self.stats.rate_samples.push(self.live.signals_per_second);
            }
            if !self.unlimited_speed {
                self.trainer.grant_frame_budget(self.signals_per_frame);
            }
            ctx.request_repaint_after(TRAINING_FRAME_INTERVAL);
        }
        if let Some(path) = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .find_map(|f| Some(f.path().to_path_buf()).filter(|p| !p.as_os_str().is_empty()))
        }) {
            self.open_path(path);
        }

        // Panels paint no background: the window's clear colour is the panel colour
        // (`clear_color`), so a CPU rasterizer does not shade every pixel a second time.
        let bar = egui::Frame::side_top_panel(ui.style()).fill(Color32::TRANSPARENT);
        let central = egui::Frame::central_panel(ui.style()).fill(Color32::TRANSPARENT);
        egui::Panel::top("menu")
            .frame(bar)
            .show(ui, |ui| self.menu_bar(ui));
        egui::Panel::bottom("status")
            .frame(bar)
            .show(ui, |ui| self.status_bar(ui));
        egui::Panel::left("controls")
            .frame(bar)
            .resizable(true)
            .default_size(250.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.controls(ui));
            });
        if self.show_plots {
            egui::Panel::bottom("plots")
                .frame(bar)
                .resizable(true)
                .default_size(290.0)
                .min_size(200.0)
                .show(ui, |ui| self.plots(ui));
        }
        egui::CentralPanel::default()
            .frame(central)
            .show(ui, |ui| self.viewports(ui));
        self.automation(&ctx);
    }

    fn menu_bar(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui.button("Open mesh…").clicked() {
                    self.dialogs.open(DialogPurpose::OpenMesh, "");
                }
                ui.separator();
                if ui
                    .add_enabled(
                        self.reconstruction.is_some(),
                        egui::Button::new("Export GNG3D mesh…"),
                    )
                    .clicked()
                {
                    self.dialogs.open(DialogPurpose::ExportGng, "gng3d.obj");
                }
                if ui
                    .add_enabled(
                        self.qem.mesh.is_some(),
                        egui::Button::new("Export QEM mesh…"),
                    )
                    .clicked()
                {
                    self.dialogs.open(DialogPurpose::ExportQem, "qem.obj");
                }
                if ui.button("Export checkpoint table (CSV)…").clicked() {
                    self.dialogs
                        .open(DialogPurpose::ExportCsv, "checkpoints.csv");
                }
                if ui.button("Save screenshot (PNG)…").clicked() {
                    self.dialogs.open(DialogPurpose::Screenshot, "viewer.png");
                }
                ui.separator();
                if ui.button("Quit").clicked() {
                    ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
                }
            });
            ui.menu_button("View", |ui| {
                ui.radio_value(&mut self.display.shading, Shading::Smooth, "Smooth shading");
                ui.radio_value(&mut self.display.shading, Shading::Flat, "Flat shading");
                ui.checkbox(&mut self.display.wireframe, "Wireframe");
                ui.checkbox(&mut self.display.show_original, "Original overlay");
                ui.checkbox(&mut self.show_plots, "Plots and table");
                ui.checkbox(&mut self.display.smooth_ui, "Anti-aliased UI")
                    .on_hover_text("Off saves about 1 ms per frame on a software renderer");
                if ui.button("Reset camera").clicked() {
                    self.camera = OrbitCamera::framing(&self.original.referenced_bounding_box());
                }
            });
            ui.separator();
            ui.label(RichText::new(&self.model_name).strong());
            ui.label(format!(
                "{} vertices, {} faces",
                self.original.vertex_count(),
                self.original.face_count()
            ));
            if let Some((path, _)) = &self.loading {
                ui.spinner();
                ui.label(format!("loading {} …", path.display()));
            }
        });
    }

    fn status_bar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let snapshot = &self.live.snapshot;
            let state = if self.live.finished {
                "finished"
            } else if self.live.running {
                "training"
            } else {
                "paused"
            };
            ui.label(format!(
                "GNG3D [{state}]: {} nodes, {} edges, {} signals",
                snapshot.positions.len(),
                snapshot.edges.len(),
                snapshot.signals
            ));
            if let Some(m) = &self.reconstruction {
                ui.label(format!(
                    "mesh {} V / {} F",
                    m.vertex_count(),
                    m.face_count()
                ));
            }
            ui.separator();
            match (&self.qem.mesh, &self.qem.pending) {
                (_, Some(_)) => ui.label("QEM: computing…"),
                (Some(m), None) => ui.label(format!(
                    "QEM: {} V / {} F",
                    m.vertex_count(),
                    m.face_count()
                )),
                (None, None) => ui.label("QEM: –"),
            };
            ui.separator();
            ui.label(format!("{:.0} signals/s", self.live.signals_per_second));
            ui.separator();
            let ms = self.stats.frame_ms();
            ui.label(format!(
                "frame {:.1} ms ({:.0} fps)",
                ms,
                if ms > 0.0 { 1000.0 / ms } else { 0.0 }
            ));
        });
        for m in self.messages.iter().rev().take(2) {
            let color = if m.is_error {
                Color32::from_rgb(255, 110, 110)
            } else {
                ui.visuals().weak_text_color()
            };
            ui.label(RichText::new(&m.text).color(color));
        }
    }

    fn controls(&mut self, ui: &mut egui::Ui) {
        ui.heading("Training");
        ui.horizontal(|ui| {
            let running = self.live.running;
            if ui
                .add_enabled(
                    !self.live.finished,
                    egui::Button::new(if running { "Pause" } else { "Play" }),
                )
                .clicked()
            {
                self.set_running(!running);
            }
            if ui
                .button("Step")
                .on_hover_text("present λ signals (100 with auto λ)")
                .clicked()
            {
                self.step(u64::from(self.params.lambda.unwrap_or(100).max(1)));
            }
            if ui
                .button("Reset")
                .on_hover_text("restart with the parameters below")
                .clicked()
            {
                self.reset_training();
            }
        });
        if ui.button("Reconstruct now").clicked() {
            self.reconstruct_now();
        }
        ui.add_space(4.0);
        let mut target = self.params.target_vertices;
        egui::Grid::new("params").num_columns(2).show(ui, |ui| {
            let r = param_row(
                ui,
                "target vertices",
                egui::DragValue::new(&mut target)
                    .range(4..=1_000_000)
                    .speed(10.0),
            );
            if (r.changed() && !r.dragged()) || r.drag_stopped() || r.lost_focus() {
                self.set_target(target);
            } else if r.dragged() {
                self.params.target_vertices = target;
            }

            let label = ui.label("time limit (s)");
            ui.horizontal(|ui| {
                let mut limited = self.params.time_limit.is_some();
                ui.checkbox(&mut limited, "limit");
                let mut seconds = self.params.time_limit.map_or(30.0, |d| d.as_secs_f64());
                ui.add_enabled(
                    limited,
                    egui::DragValue::new(&mut seconds).range(0.1..=3600.0),
                )
                .labelled_by(label.id);
                self.params.time_limit = limited.then(|| Duration::from_secs_f64(seconds));
            });
            ui.end_row();
            let label = ui.label("λ (insert every)");
            ui.horizontal(|ui| {
                let mut auto = self.params.lambda.is_none();
                ui.checkbox(&mut auto, "auto");
                let mut lambda = self.params.lambda.unwrap_or(100);
                ui.add_enabled(!auto, egui::DragValue::new(&mut lambda).range(1..=100_000))
                    .labelled_by(label.id);
                self.params.lambda = (!auto).then_some(lambda);
            });
            ui.end_row();
            param_row(
                ui,
                "ε_b (winner)",
                egui::DragValue::new(&mut self.params.eps_winner)
                    .range(0.0..=1.0)
                    .speed(0.001),
            );
            param_row(
                ui,
                "ε_n (neighbours)",
                egui::DragValue::new(&mut self.params.eps_neighbour)
                    .range(0.0..=1.0)
                    .speed(0.0001)
                    .max_decimals(5),
            );
            param_row(
                ui,
                "α (insertion)",
                egui::DragValue::new(&mut self.params.alpha)
                    .range(0.0..=1.0)
                    .speed(0.01),
            );
            param_row(
                ui,
                "d (error decay)",
                egui::DragValue::new(&mut self.params.error_decay)
                    .range(0.0..=1.0)
                    .speed(0.0001)
                    .max_decimals(5),
            );
            param_row(
                ui,
                "a_max (edge age)",
                egui::DragValue::new(&mut self.params.max_edge_age).range(1..=100_000),
            );
            param_row(
                ui,
                "μ (removal window)",
                egui::DragValue::new(&mut self.params.removal_window).range(0.0..=1000.0),
            )
            .on_hover_text("nodes without a win in the last μ·|A| signals are removed (0: off)");
            param_row(ui, "seed", egui::DragValue::new(&mut self.params.seed));
            let label = ui.label("signal source");
            egui::ComboBox::from_id_salt("signal_source")
                .selected_text(engine::signal_source_label(self.params.signal_source))
                .show_ui(ui, |ui| {
                    for (source, label) in engine::SIGNAL_SOURCES {
                        ui.selectable_value(&mut self.params.signal_source, source, label);
                    }
                })
                .response
                .labelled_by(label.id);
            ui.end_row();
            param_row(
                ui,
                "checkpoint every",
                egui::DragValue::new(&mut self.checkpoint_every)
                    .range(0..=1_000_000_000)
                    .speed(1000.0)
                    .suffix(" signals"),
            )
            .on_hover_text("reconstruct periodically for the table (0: off)");
        });
        ui.horizontal(|ui| {
            let before = self.speed();
            ui.checkbox(&mut self.unlimited_speed, "as fast as possible");
            if !self.unlimited_speed {
                let label = ui.label("signals/frame");
                ui.add(egui::DragValue::new(&mut self.signals_per_frame).range(1..=1_000_000))
                    .labelled_by(label.id);
            }
            if self.speed() != before {
                self.trainer.send(Command::SetSpeed(self.speed()));
            }
        });
        ui.separator();
        ui.heading("Display");
        ui.horizontal(|ui| {
            ui.radio_value(&mut self.display.shading, Shading::Smooth, "smooth");
            ui.radio_value(&mut self.display.shading, Shading::Flat, "flat");
        });
        ui.checkbox(&mut self.display.wireframe, "wireframe");
        ui.checkbox(&mut self.display.show_original, "original overlay");
        ui.checkbox(&mut self.display.show_network, "GNG network");
        ui.checkbox(&mut self.display.show_gng_mesh, "GNG3D reconstruction");
        ui.add(egui::Slider::new(&mut self.display.point_px, 1.0..=12.0).text("node size (px)"));
        if ui.button("Reset camera").clicked() {
            self.camera = OrbitCamera::framing(&self.original.referenced_bounding_box());
        }
        ui.label(
            RichText::new(
                "drag: orbit · right/middle drag or shift: pan · wheel: zoom · double-click: reset",
            )
            .small()
            .weak(),
        );
    }

    fn plots(&mut self, ui: &mut egui::Ui) {
        let height = (ui.available_height() - 26.0).max(100.0);
        let width = ui.available_width();
        let widths = [width * 0.34, width * 0.30, width * 0.36 - 16.0];
        ui.horizontal_top(|ui| {
            ui.allocate_ui(egui::vec2(widths[0], height + 24.0), |ui| {
                ui.vertical(|ui| {
                    ui.label(RichText::new("Vertex errors E_avg, E_max (QEM dashed)").strong());
                    plots::vertex_error_plot(ui, &self.history, height);
                });
            });
            ui.allocate_ui(egui::vec2(widths[1], height + 24.0), |ui| {
                ui.vertical(|ui| {
                    ui.label(RichText::new("E_sur and Hausdorff per reconstruction").strong());
                    plots::surface_error_plot(ui, &self.history, height);
                });
            });
            ui.allocate_ui(egui::vec2(widths[2], height + 24.0), |ui| {
                ui.vertical(|ui| {
                    ui.horizontal(|ui| {
                        ui.label(RichText::new("Checkpoints (Table 1)").strong());
                        if ui.small_button("Export CSV…").clicked() {
                            self.dialogs
                                .open(DialogPurpose::ExportCsv, "checkpoints.csv");
                        }
                    });
                    plots::checkpoint_table(ui, &self.history);
                });
            });
        });
    }

    fn viewports(&mut self, ui: &mut egui::Ui) {
        let full = ui.available_rect_before_wrap();
        let gap = 4.0;
        let half = (full.width() - gap) * 0.5;
        let rects = [
            egui::Rect::from_min_size(full.min, egui::vec2(half, full.height())),
            egui::Rect::from_min_size(
                egui::pos2(full.min.x + half + gap, full.min.y),
                egui::vec2(half, full.height()),
            ),
        ];
        ui.allocate_rect(full, egui::Sense::hover());
        for (i, rect) in rects.iter().enumerate() {
            let response = ui.interact(
                *rect,
                ui.scope_id().with(("viewport", i)),
                egui::Sense::click_and_drag(),
            );
            self.camera_input(ui, &response, rect.height());
        }
        self.viewport_rects = [Some(rects[0]), Some(rects[1])];
        let ppp = ui.ctx().pixels_per_point();
        self.render_viewports(rects.map(|r| {
            [
                (r.width() * ppp).round().max(1.0) as u32,
                (r.height() * ppp).round().max(1.0) as u32,
            ]
        }));
        let painter = ui.painter();
        for (i, rect) in rects.iter().enumerate() {
            match &self.gpu {
                Some(gpu) => {
                    painter.add(gpu.scene.paint_callback(&gpu.targets[i], *rect));
                }
                None => {
                    painter.rect_filled(*rect, 0.0, Color32::from_gray(20));
                    painter.text(
                        rect.center(),
                        egui::Align2::CENTER_CENTER,
                        "no wgpu renderer",
                        egui::FontId::proportional(16.0),
                        Color32::GRAY,
                    );
                }
            }
        }
        let font = egui::FontId::proportional(15.0);
        let snapshot = &self.live.snapshot;
        let left = match &self.reconstruction {
            Some(m) => format!(
                "GNG3D — {} nodes · mesh {} V / {} F",
                snapshot.positions.len(),
                m.vertex_count(),
                m.face_count()
            ),
            None => format!(
                "GNG3D — {} nodes, {} edges (training)",
                snapshot.positions.len(),
                snapshot.edges.len()
            ),
        };
        let right = match (&self.qem.mesh, &self.qem.pending, &self.qem.error) {
            (_, Some(_), _) => format!("QEM — computing {} vertices…", self.qem.target),
            (Some(m), None, _) => format!("QEM — {} V / {} F", m.vertex_count(), m.face_count()),
            (None, None, Some(e)) => format!("QEM — {e}"),
            (None, None, None) => "QEM".into(),
        };
        for (rect, text) in rects.iter().zip([left, right]) {
            painter.text(
                rect.min + egui::vec2(8.0, 6.0),
                egui::Align2::LEFT_TOP,
                text,
                font.clone(),
                Color32::from_gray(230),
            );
        }
    }

    fn camera_input(&mut self, ui: &egui::Ui, response: &egui::Response, height: f32) {
        let delta = response.drag_delta();
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(egui::PointerButton::Primary) && !shift {
            self.camera.orbit(delta.x, delta.y);
        } else if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Primary) && shift)
        {
            self.camera.pan(delta.x, delta.y, height);
        }
        if response.hovered() {
            let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
            if scroll != 0.0 {
                self.camera.zoom((scroll * 0.002).exp());
            }
            if zoom != 1.0 {
                self.camera.zoom(zoom);
            }
        }
        if response.double_clicked() {
            self.camera = OrbitCamera::framing(&self.original.referenced_bounding_box());
        }
    }

    fn render_viewports(&mut self, sizes: [[u32; 2]; 2]) {
        let Some(gpu) = self.gpu.as_mut() else {
            return;
        };
        // Upload the network when the worker published a new snapshot.
        let snapshot = &self.live.snapshot;
        let changed = gpu
            .network_source
            .as_ref()
            .is_none_or(|s| !Arc::ptr_eq(s, snapshot));
        if changed {
            gpu.network.update(
                &gpu.render_state.device,
                &gpu.render_state.queue,
                &snapshot.positions,
                &snapshot.edges,
            );
            gpu.network_source = Some(Arc::clone(snapshot));
        }
        for (target, size) in gpu.targets.iter_mut().zip(sizes) {
            gpu.scene
                .resize_target(&gpu.render_state.device, target, size);
        }
        let d = &self.display;
        let shading = d.shading;
        let wire = [0.02, 0.02, 0.03, 0.55];
        let overlay = [0.45, 0.45, 0.50, 0.28];
        let mut left: Vec<DrawItem<'_>> = Vec::new();
        let gng_mesh_shown = d.show_gng_mesh && gpu.gng_mesh.is_some();
        if let (true, Some(mesh)) = (d.show_gng_mesh, gpu.gng_mesh.as_ref()) {
            left.push(DrawItem::Surface {
                mesh,
                color: [0.85, 0.42, 0.16],
                shading,
            });
            if d.wireframe {
                left.push(DrawItem::Wireframe { mesh, color: wire });
            }
        }
        if d.show_network && !(gng_mesh_shown && self.live.finished) {
            left.push(DrawItem::Network {
                network: &gpu.network,
                node_color: [1.0, 0.55, 0.12],
                edge_color: [0.35, 0.65, 1.0, 0.9],
                point_px: d.point_px,
            });
        }
        let mut right: Vec<DrawItem<'_>> = Vec::new();
        if let Some(mesh) = gpu.qem_mesh.as_ref() {
            right.push(DrawItem::Surface {
                mesh,
                color: [0.20, 0.45, 0.85],
                shading,
            });
            if d.wireframe {
                right.push(DrawItem::Wireframe { mesh, color: wire });
            }
        }
        if let Some(original) = gpu.original.as_ref()
            && (d.show_original || (gpu.qem_mesh.is_none() && self.qem.pending.is_none()))
        {
            // The original also stands in on the right while QEM is unavailable.
            if d.show_original {
                left.push(DrawItem::Overlay {
                    mesh: original,
                    color: overlay,
                });
                right.push(DrawItem::Overlay {
                    mesh: original,
                    color: overlay,
                });
            } else {
                right.push(DrawItem::Surface {
                    mesh: original,
                    color: [0.5, 0.5, 0.55],
                    shading,
                });
            }
        }
        let device = &gpu.render_state.device;
        let queue = &gpu.render_state.queue;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("viewports"),
        });
        let [left_target, right_target] = &mut gpu.targets;
        let drew_left = gpu
            .scene
            .render(queue, &mut encoder, left_target, &self.camera, &left);
        let drew_right = gpu
            .scene
            .render(queue, &mut encoder, right_target, &self.camera, &right);
        self.stats.viewport_redraws[0] += u64::from(drew_left);
        self.stats.viewport_redraws[1] += u64::from(drew_right);
        if drew_left || drew_right {
            queue.submit(std::iter::once(encoder.finish()));
        }
    }

    /// The offscreen colour texture of a viewport (for tests).
    pub fn viewport_texture(&self, side: Side) -> Option<&wgpu::Texture> {
        let gpu = self.gpu.as_ref()?;
        Some(gpu.targets[side as usize].color_texture())
    }
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        // The panels are transparent (see `show`): the clear colour is their background.
        visuals.panel_fill.to_normalized_gamma_f32()
    }
}

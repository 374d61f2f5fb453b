//! The GNG3D training thread: trains at full speed or paced over a chosen wall time, publishes a
//! network snapshot about every 16 ms, measures the live vertex errors densely, reconstructs
//! the neural mesh at checkpoints, and reports each step of the finished network's pipeline as
//! it ends. The UI only ever polls; nothing here blocks a frame.
//!
//! A watched run holds its length as a pacing target, not a hard limit: the training is paced
//! to end where the steps after it have their estimated time left ([`pace_seconds`]), and its
//! growth is paced on its own ([`Pacer`]: a handful of nodes at first, the target after
//! [`GROWTH_TIME_SHARE`] of the training), so the network visibly grows over seconds. The
//! core's time limit is only a backstop ([`SOFT_LIMIT_FACTOR`] × the run length, unless the
//! user set a shorter limit), so a loaded machine makes the run a little longer rather than
//! leaving steps out.
//!
//! This module holds the messages between the UI and the thread and the [`Trainer`] handle;
//! `pacing` the run's schedule, `training` the thread's message loop and the jobs it runs.

mod pacing;
mod training;

pub use pacing::*;
use training::training_loop;

use crate::engine::{NetworkSnapshot, PlannedStep, StepRecord, TrainParams};
use mesh::TriMesh;
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;

/// What a training run works on.
#[derive(Clone)]
pub struct TrainingJob {
    /// The (cleaned) original mesh.
    pub mesh: Arc<TriMesh>,
    /// Its normals, texture coordinates and colours, when it has some: the network's triangles
    /// then follow their seams, as `gng3d simplify --method gng` does.
    pub attributes: Option<Arc<mesh::attributes::Attributes>>,
    /// Its materials and origin: the final mesh's place ([`crate::engine::Loaded::place`]).
    pub place: Arc<mesh::Model>,
    /// Training parameters.
    pub params: TrainParams,
    /// Reconstruct automatically every this many signals (checkpoints for the table).
    pub checkpoint_every: Option<u64>,
    /// Start running immediately.
    pub autoplay: bool,
}

/// Requests from the UI to the training thread.
pub enum Command {
    /// Start a new session (drops the old one).
    Reset(Box<TrainingJob>),
    /// Run / pause.
    SetRunning(bool),
    /// Present this many signals now (while paused).
    Step(u64),
    /// Reconstruct every this many signals from now on (`None`: only at the end and on request).
    SetCheckpointEvery(Option<u64>),
    /// Change the speed.
    SetSpeed(Speed),
    /// Reconstruct a mesh from the current network.
    Reconstruct,
    /// End the thread.
    Shutdown,
}

/// Results sent back to the UI, tagged with the session they belong to.
pub enum Event {
    /// Vertex errors of the current network against the original vertices.
    Errors {
        /// Session number.
        session: u64,
        /// Signals presented when measured.
        signals: u64,
        /// E_avg, squared model units.
        e_avg: f64,
        /// E_max, squared model units.
        e_max: f64,
    },
    /// A mesh reconstructed from the network.
    Reconstructed {
        /// Session number.
        session: u64,
        /// Signals presented when reconstructed.
        signals: u64,
        /// The mesh.
        mesh: Arc<TriMesh>,
        /// Training time so far (seconds, pauses excluded).
        train_seconds: f64,
        /// The finished network's outcome: the model `gng3d simplify` saves, the summary and
        /// the warnings (`None` for a checkpoint's preview, see `Engine::reconstruct`).
        outcome: Option<Arc<job::Outcome>>,
    },
    /// A run started: the steps its finished network's pipeline will run, and its limits.
    Planned {
        /// Session number.
        session: u64,
        /// The steps the run's parameters plan without a time limit, in order
        /// ([`Engine::full_plan`](crate::engine::Engine::full_plan)).
        full_plan: Vec<PlannedStep>,
        /// Those of them the run will run ([`Engine::plan`](crate::engine::Engine::plan); the rest the time limit left out
        /// before the run started).
        steps: Vec<PlannedStep>,
        /// The run's time limit (training and steps), seconds.
        time_limit: Option<f64>,
        /// Whether that limit is the watch time (not one the user set).
        limit_is_watch_time: bool,
        /// With a limit: the core's estimate of the steps' seconds (the limit less the
        /// training limit).
        steps_estimate: Option<f64>,
    },
    /// Training ended and the finished network's pipeline starts (once per run: "Reconstruct
    /// now" on a finished network gets the same mesh again, [`Engine::has_final`](crate::engine::Engine::has_final)).
    PipelineStarted {
        /// Session number.
        session: u64,
        /// Wall time training ran, seconds (pauses excluded; checkpoint previews included).
        training_seconds: f64,
        /// Of it, seconds of checkpoint previews.
        preview_seconds: f64,
        /// Checkpoint previews reconstructed.
        previews: u64,
    },
    /// A step of the finished network's pipeline is done.
    Step {
        /// Session number.
        session: u64,
        /// Its record.
        record: StepRecord,
    },
    /// The finished network's pipeline ended (sent before its [`Event::Reconstructed`]).
    PipelineDone {
        /// Session number.
        session: u64,
        /// Whether the time limit cut anything or is below the run's minimum.
        cut_for_time: bool,
        /// Wall time of the pipeline, seconds.
        pipeline_seconds: f64,
        /// Wall time from the run's start to the final mesh, seconds (pauses included).
        run_seconds: f64,
        /// Whether it failed (then there is no mesh).
        failed: bool,
    },
    /// Something failed (shown in the UI).
    Failed {
        /// Session number.
        session: u64,
        /// What went wrong.
        message: String,
    },
}

/// The latest state of the training thread, read by the UI each frame.
#[derive(Clone, Default)]
pub struct Live {
    /// Session number (increases with every reset).
    pub session: u64,
    /// The network as of the last publish.
    pub snapshot: Arc<NetworkSnapshot>,
    /// Whether training is running.
    pub running: bool,
    /// Whether training reached its target or limits.
    pub finished: bool,
    /// Signals per second over the last second of running.
    pub signals_per_second: f64,
    /// Training time, seconds (pauses excluded).
    pub train_seconds: f64,
    /// The run's signal budget (0 before a run starts).
    pub max_signals: u64,
    /// Checkpoints skipped to keep reconstructions within [`CHECKPOINT_TIME_SHARE`] (as fast
    /// as possible) or the run on pace ([`paced_preview_fits`], watched), and those a late
    /// watched run did not reach because it stopped training at its pace's end.
    pub skipped_checkpoints: u64,
    /// A watched run: points of the vertex-error schedule ([`PACED_ERROR_POINTS`]) left out
    /// because the run was behind it (a loaded machine), reached or not. Measured points plus
    /// these are the whole schedule whatever the machine's speed.
    pub skipped_error_points: u64,
    /// Wall time training has run, seconds (pauses excluded).
    pub run_seconds: f64,
    /// A paced run: the running wall time its signal budget is spread over ([`pace_seconds`]).
    pub pace_seconds: Option<f64>,
}

struct Shared {
    live: Mutex<Live>,
    repaint: Mutex<Option<egui::Context>>,
}

/// Handle to the training thread.
pub struct Trainer {
    commands: Sender<Command>,
    events: Receiver<Event>,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl Trainer {
    /// Spawn the training thread (idle until a [`Command::Reset`]).
    pub fn spawn() -> Trainer {
        let (commands, command_rx) = mpsc::channel();
        let (event_tx, events) = mpsc::channel();
        let shared = Arc::new(Shared {
            live: Mutex::new(Live::default()),
            repaint: Mutex::new(None),
        });
        let thread_shared = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("gng-training".into())
            .spawn(move || training_loop(&command_rx, &event_tx, &thread_shared))
            .ok();
        Trainer {
            commands,
            events,
            shared,
            thread,
        }
    }

    /// Ask the UI to repaint through `ctx` whenever something new is published.
    pub fn set_repaint_context(&self, ctx: &egui::Context) {
        *self
            .shared
            .repaint
            .lock()
            .unwrap_or_else(PoisonError::into_inner) = Some(ctx.clone());
    }

    /// Send a command (ignored if the thread is gone).
    pub fn send(&self, command: Command) {
        let _ = self.commands.send(command);
    }

    /// Latest published state (cheap: the snapshot is shared).
    pub fn live(&self) -> Live {
        self.shared
            .live
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }

    /// Events that arrived since the last call.
    pub fn drain_events(&self) -> Vec<Event> {
        self.events.try_iter().collect()
    }
}

impl Drop for Trainer {
    fn drop(&mut self) {
        let _ = self.commands.send(Command::Shutdown);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

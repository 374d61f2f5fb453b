//! The GNG3D training thread: trains at full speed or paced over a chosen wall time, publishes a
//! network snapshot about every 16 ms, measures the live vertex errors densely, and reconstructs
//! the neural mesh at checkpoints. The UI only ever polls; nothing here blocks a frame.

use crate::engine::{self, Engine, NetworkSnapshot, TrainParams};
use mesh::TriMesh;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender, TryRecvError};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Frame interval while training runs: at most 40 fps, so that on a CPU renderer the UI leaves
/// cores to the training thread.
pub const TRAINING_FRAME_INTERVAL: Duration = Duration::from_millis(25);

/// Live vertex-error measurements per paced run: the signal budget is split into this many
/// equal steps, so the E_avg/E_max curve is dense whatever the mesh size.
pub const PACED_ERROR_POINTS: u64 = 200;

/// As fast as possible, the checkpoint reconstructions (which run on the training thread) may
/// use at most this share of its time; a checkpoint that comes while they are over it is
/// skipped (the table then has fewer rows, each still at a multiple of the interval). Without
/// it, armadillo with a 10,000-node network trained at 7-8 % of its headless rate: one
/// reconstruction (~0.3 s) took longer than the |V| signals between two checkpoints.
pub const CHECKPOINT_TIME_SHARE: f64 = 0.1;

/// How fast training runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Speed {
    /// As many signals as the thread can do.
    Unlimited,
    /// Spread the whole signal budget over this many seconds of (unpaused) wall time, so the
    /// network visibly grows; a slow machine simply takes longer.
    Paced {
        /// Intended run length, seconds (> 0).
        seconds: f64,
    },
}

/// What a training run works on.
#[derive(Clone)]
pub struct TrainingJob {
    /// The (cleaned) original mesh.
    pub mesh: Arc<TriMesh>,
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
        /// The run's warnings (finished network only, see `Engine::reconstruct`).
        warnings: Vec<String>,
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
    /// Checkpoints skipped to keep reconstructions within [`CHECKPOINT_TIME_SHARE`].
    pub skipped_checkpoints: u64,
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

/// Mutable state of the training thread.
struct Training {
    session: u64,
    source: Option<Arc<TriMesh>>,
    engine: Option<Engine>,
    running: bool,
    finished: bool,
    speed: Speed,
    batch: u64,
    checkpoint_every: Option<u64>,
    next_checkpoint: u64,
    train_time: Duration,
    /// Time spent on checkpoint reconstructions since the reset.
    reconstruct_time: Duration,
    /// Checkpoints skipped by [`CHECKPOINT_TIME_SHARE`] since the reset.
    skipped_checkpoints: u64,
    /// Wall time spent running (pauses excluded) since the reset: the clock of a paced run.
    paced_clock: Duration,
    /// When `paced_clock` was last advanced.
    clock_tick: Instant,
    last_publish: Instant,
    last_errors: Instant,
    error_interval: Duration,
    /// Signal count at which a paced run measures the vertex errors next.
    next_error_signals: u64,
    rate_window: (Instant, u64),
    signals_per_second: f64,
    /// The last published snapshot and its session: republished as the same `Arc` while the
    /// network has not changed, so the UI does not redraw an unchanged view.
    published: Option<(u64, Arc<NetworkSnapshot>)>,
}

fn training_loop(commands: &Receiver<Command>, events: &Sender<Event>, shared: &Shared) {
    let mut t = Training {
        session: 0,
        source: None,
        engine: None,
        running: false,
        finished: false,
        speed: Speed::Unlimited,
        batch: 256,
        checkpoint_every: None,
        next_checkpoint: u64::MAX,
        train_time: Duration::ZERO,
        reconstruct_time: Duration::ZERO,
        skipped_checkpoints: 0,
        paced_clock: Duration::ZERO,
        clock_tick: Instant::now(),
        next_error_signals: 0,
        last_publish: Instant::now(),
        published: None,
        last_errors: Instant::now(),
        error_interval: Duration::from_millis(200),
        rate_window: (Instant::now(), 0),
        signals_per_second: 0.0,
    };
    loop {
        let busy = t.running && !t.finished && t.engine.is_some();
        let command = if busy {
            match commands.try_recv() {
                Ok(c) => Some(c),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => return,
            }
        } else {
            match commands.recv_timeout(Duration::from_millis(50)) {
                Ok(c) => Some(c),
                Err(RecvTimeoutError::Timeout) => None,
                Err(RecvTimeoutError::Disconnected) => return,
            }
        };
        if let Some(command) = command {
            match command {
                Command::Shutdown => return,
                Command::Reset(session) => {
                    t.session += 1;
                    t.finished = false;
                    t.train_time = Duration::ZERO;
                    t.reconstruct_time = Duration::ZERO;
                    t.skipped_checkpoints = 0;
                    t.paced_clock = Duration::ZERO;
                    t.next_error_signals = 0;
                    t.signals_per_second = 0.0;
                    t.rate_window = (Instant::now(), 0);
                    t.checkpoint_every = session.checkpoint_every.filter(|&c| c > 0);
                    t.next_checkpoint = t.checkpoint_every.unwrap_or(u64::MAX);
                    match Engine::new(&session.mesh, &session.params) {
                        Ok(engine) => {
                            t.engine = Some(engine);
                            t.running = session.autoplay;
                        }
                        Err(error) => {
                            t.engine = None;
                            t.running = false;
                            let _ = events.send(Event::Failed {
                                session: t.session,
                                message: format!("could not start: {error}"),
                            });
                        }
                    }
                    t.source = Some(session.mesh);
                    publish(&mut t, shared);
                }
                Command::SetRunning(running) => {
                    t.running = running;
                    t.rate_window = (Instant::now(), signals_of(&t));
                    publish(&mut t, shared);
                }
                Command::SetSpeed(speed) => t.speed = speed,
                Command::SetCheckpointEvery(every) => {
                    t.checkpoint_every = every.filter(|&c| c > 0);
                    let signals = signals_of(&t);
                    t.next_checkpoint = t
                        .checkpoint_every
                        .map_or(u64::MAX, |c| (signals / c + 1).saturating_mul(c));
                }
                Command::Step(n) => {
                    if let Some(engine) = t.engine.as_mut() {
                        let started = Instant::now();
                        engine.step(n);
                        t.train_time += started.elapsed();
                        t.finished = engine.is_finished();
                        measure_errors(&mut t, events);
                        publish(&mut t, shared);
                    }
                }
                Command::Reconstruct => reconstruct(&mut t, events),
            }
            continue;
        }
        let now = Instant::now();
        if busy {
            t.paced_clock += now.duration_since(t.clock_tick);
        }
        t.clock_tick = now;
        if busy {
            train_batch(&mut t, shared, events);
        } else if t.last_publish.elapsed() > Duration::from_millis(250) {
            publish(&mut t, shared);
        }
    }
}

fn signals_of(t: &Training) -> u64 {
    t.engine.as_ref().map_or(0, Engine::signals)
}

fn train_batch(t: &mut Training, shared: &Shared, events: &Sender<Event>) {
    let Some(engine) = t.engine.as_mut() else {
        return;
    };
    let budget = engine.max_signals();
    let n = match t.speed {
        Speed::Unlimited => t.batch,
        Speed::Paced { seconds } => {
            // Where a run of `seconds` would be now; the first checkpoint's reconstruction or a
            // slow machine only make the run longer, never a burst.
            let due = (budget as f64 * (t.paced_clock.as_secs_f64() / seconds.max(1e-3)))
                .min(budget as f64) as u64;
            if due >= budget {
                // The pace is done: let the trainer run into its own stop rule (it decides when
                // it is finished, e.g. only on the step after the last budgeted signal).
                t.batch
            } else {
                // Never step past the next scheduled error measurement: a thread that was
                // descheduled for a while catches up in several steps, each measured, so every
                // run gets its `PACED_ERROR_POINTS` points.
                due.saturating_sub(engine.signals())
                    .min(t.batch)
                    .min(t.next_error_signals.saturating_sub(engine.signals()).max(1))
            }
        }
    };
    // Checkpoints land exactly on their signal counts (every |V| signals: the paper's protocol).
    let n = n.min(t.next_checkpoint.saturating_sub(engine.signals()).max(1));
    if n == 0 {
        std::thread::sleep(Duration::from_millis(1));
    } else {
        let started = Instant::now();
        engine.step(n);
        let spent = started.elapsed();
        t.train_time += spent;
        // Aim at ~2 ms per call: commands stay responsive, call overhead stays negligible.
        let per_signal = spent.as_secs_f64() / n as f64;
        if per_signal > 0.0 {
            let ideal = (0.002 / per_signal) as u64;
            t.batch = ideal.clamp(16, 1 << 20);
        }
        t.finished = engine.is_finished();
    }
    let signals = signals_of(t);
    let window = t.rate_window.0.elapsed();
    if window >= Duration::from_millis(500) {
        t.signals_per_second =
            signals.saturating_sub(t.rate_window.1) as f64 / window.as_secs_f64();
        t.rate_window = (Instant::now(), signals);
    }
    let measure = match t.speed {
        // Full speed: a time budget (see `measure_errors`), and always the first batch of a run,
        // so the curve starts where training starts.
        Speed::Unlimited => signals <= n || t.last_errors.elapsed() >= t.error_interval,
        // Paced: a fixed signal schedule, so every run gets the same dense curve.
        Speed::Paced { .. } => signals >= t.next_error_signals,
    };
    if measure || t.finished {
        t.next_error_signals = signals + (budget / PACED_ERROR_POINTS).max(1);
        measure_errors(t, events);
    }
    if signals >= t.next_checkpoint && !t.finished {
        while t.next_checkpoint <= signals {
            t.next_checkpoint = t
                .next_checkpoint
                .saturating_add(t.checkpoint_every.unwrap_or(u64::MAX));
        }
        let within_share = match t.speed {
            // Paced runs sleep between batches: checkpoints only use that slack.
            Speed::Paced { .. } => true,
            Speed::Unlimited => {
                t.reconstruct_time.as_secs_f64()
                    <= CHECKPOINT_TIME_SHARE * t.train_time.as_secs_f64()
            }
        };
        if within_share {
            let started = Instant::now();
            reconstruct(t, events);
            t.reconstruct_time += started.elapsed();
        } else {
            t.skipped_checkpoints += 1;
        }
    }
    if t.finished {
        t.running = false;
        reconstruct(t, events);
        publish(t, shared);
    } else if t.last_publish.elapsed() >= Duration::from_millis(16) {
        publish(t, shared);
    }
}

/// E_avg/E_max of the original vertices against the current nodes; the interval adapts so this
/// takes at most ~5 % of the training thread's time.
fn measure_errors(t: &mut Training, events: &Sender<Event>) {
    let (Some(engine), Some(source)) = (t.engine.as_ref(), t.source.as_ref()) else {
        return;
    };
    let started = Instant::now();
    let snapshot = engine.snapshot();
    if let Some((e_avg, e_max)) = engine::network_errors(source, &snapshot.positions) {
        let _ = events.send(Event::Errors {
            session: t.session,
            signals: snapshot.signals,
            e_avg,
            e_max,
        });
    }
    let cost = started.elapsed();
    t.error_interval = (cost * 20).max(Duration::from_millis(100));
    t.last_errors = Instant::now();
}

fn reconstruct(t: &mut Training, events: &Sender<Event>) {
    let Some(engine) = t.engine.as_mut() else {
        return;
    };
    let signals = engine.signals();
    let event = match engine.reconstruct() {
        Ok((mesh, warnings)) => Event::Reconstructed {
            session: t.session,
            signals,
            mesh: Arc::new(mesh),
            train_seconds: t.train_time.as_secs_f64(),
            warnings,
        },
        Err(error) => Event::Failed {
            session: t.session,
            message: format!("reconstruction failed: {error}"),
        },
    };
    let _ = events.send(event);
}

fn publish(t: &mut Training, shared: &Shared) {
    let snapshot = match (&t.published, t.engine.as_ref()) {
        (Some((session, snapshot)), Some(engine))
            if *session == t.session
                && snapshot.signals == engine.signals()
                && snapshot.finished == engine.is_finished() =>
        {
            Arc::clone(snapshot)
        }
        (_, Some(engine)) => {
            let snapshot = Arc::new(engine.snapshot());
            t.published = Some((t.session, Arc::clone(&snapshot)));
            snapshot
        }
        (_, None) => {
            t.published = None;
            Arc::default()
        }
    };
    {
        let mut live = shared.live.lock().unwrap_or_else(PoisonError::into_inner);
        *live = Live {
            session: t.session,
            snapshot,
            running: t.running,
            finished: t.finished,
            signals_per_second: if t.running { t.signals_per_second } else { 0.0 },
            train_seconds: t.train_time.as_secs_f64(),
            max_signals: t.engine.as_ref().map_or(0, Engine::max_signals),
            skipped_checkpoints: t.skipped_checkpoints,
        };
    }
    t.last_publish = Instant::now();
    if let Some(ctx) = shared
        .repaint
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .as_ref()
    {
        ctx.request_repaint_after(TRAINING_FRAME_INTERVAL);
    }
}

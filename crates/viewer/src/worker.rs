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

use crate::engine::{self, Engine, NetworkSnapshot, PlannedStep, StepRecord, TrainParams};
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
    /// The whole run (training and the steps after it) takes about this many seconds of wall
    /// time, so the network visibly grows: the signal budget is spread over the part of it
    /// that training gets ([`Pacer`]); a slow machine simply takes longer.
    Paced {
        /// Intended run length, seconds (> 0).
        seconds: f64,
    },
}

/// The core's time limit of a watched run is this many times its run length (unless the
/// user's own limit is shorter): a backstop for a machine far slower than the estimates, not
/// the run's length, which the pacing holds ([`pace_seconds`]). With the run length as the hard
/// limit, a loaded machine made the core leave out steps (issue 37).
pub const SOFT_LIMIT_FACTOR: f64 = 2.0;

/// The core's time limit of a run that starts with `speed` and the user's limit `user`, and
/// whether it is the watch time's backstop (`true`) rather than the user's. A watched run that
/// starts playing gets [`SOFT_LIMIT_FACTOR`] × its watch time unless the user's limit is
/// shorter; a run that starts paused or trains as fast as possible keeps the user's limit. The
/// core's limit is wall time from the run's start; pauses are left out of it
/// (`Engine::discount` on resume), so a paused run keeps its steps.
pub fn run_time_limit(
    user: Option<Duration>,
    speed: Speed,
    autoplay: bool,
) -> (Option<Duration>, bool) {
    match speed {
        Speed::Paced { seconds } if autoplay && seconds.is_finite() && seconds > 0.0 => {
            let backstop = Duration::from_secs_f64(SOFT_LIMIT_FACTOR * seconds);
            match user {
                Some(limit) if limit <= backstop => (Some(limit), false),
                _ => (Some(backstop), true),
            }
        }
        _ => (user, false),
    }
}

/// The steps after training get this many times the core's estimate of their time (the time
/// limit less the training limit, which includes the core's own margin under the limit) when
/// the viewer paces the training, and at least [`STEPS_MIN_MARGIN_SHARE`] of the limit more:
/// the core's estimates are fitted to `gng3d simplify` alone on the machine, and in the viewer
/// the steps share the cores with the renderer and the checkpoint evaluations. Paced right up
/// to the training limit, the driver left out all three detail rounds of armadillo (43k
/// vertices) to keep the limit. With 1.25 times the estimate and the floor, the default watched
/// run of each of the 15 shared meshes took 10.6-11.1 s of 12 s from its start to the final
/// mesh, every step run (debug build of the viewer, 2 cores, another process busy on one); with
/// both cores busy elsewhere, the driver still left out a detail round or two on the biggest
/// meshes to keep the length.
pub const STEPS_TIME_FACTOR: f64 = 1.25;

/// Least margin the steps after training get beyond the core's estimate, as a share of the
/// time limit (0.36 s of 12 s): the smallest meshes' steps are estimated at a few ms, and a
/// busy renderer or evaluation can take longer than that from them.
pub const STEPS_MIN_MARGIN_SHARE: f64 = 0.03;

/// Seconds of running wall time a paced run spreads its signal budget over: the watch
/// `seconds`, less the steps after training when the run has a time limit (`limits`: the
/// limit and the training limit, the wall time from the start at which the core stops training
/// so that the steps after it fit; the difference is the core's estimate of the steps). The run
/// aims to end at the watch time or the limit, whichever is first; the steps get
/// [`STEPS_TIME_FACTOR`] times their estimate, and at least [`STEPS_MIN_MARGIN_SHARE`] of that
/// end more (the training ends at once when that is not left).
pub fn pace_seconds(seconds: f64, limits: Option<(Duration, Duration)>) -> f64 {
    match limits {
        None => seconds,
        Some((limit, training_limit)) => {
            let (limit, training_limit) = (limit.as_secs_f64(), training_limit.as_secs_f64());
            let end = seconds.min(limit);
            let steps = (limit - training_limit).max(0.0);
            let margin = ((STEPS_TIME_FACTOR - 1.0) * steps).max(STEPS_MIN_MARGIN_SHARE * end);
            (end - steps - margin).clamp(0.0, seconds)
        }
    }
}

/// Share of a paced training's time its growth gets: the node count rises from a handful to
/// the target over this share of the pace, and the rest of the budget (fine detail, no new
/// nodes) is spread over the remainder. Spread evenly instead, the growth takes as large a
/// share of the time as its signals take of the budget, and a network of a few hundred nodes
/// already looks finished after a second (issue 37).
pub const GROWTH_TIME_SHARE: f64 = 0.6;

/// The growth's signals rise as time to this power over its share of the pace: slowly at first
/// (1 s into the default run, under 10 % of the nodes), and never faster than 1.25 times the
/// run's mean signal rate (with the growth half the budget: 1.5 · 0.5 / 0.6 at its end, and
/// 0.5 / 0.4 after it), so a busy machine keeps the pace. A square took 1.67 times the mean
/// rate late in the growth, and debug builds on a loaded machine fell behind it.
pub const GROWTH_EXPONENT: f64 = 1.5;

/// A paced run's schedule: how many signals it should have presented after how many seconds
/// of running wall time, and back. The growth's signals (`growth`: λ × the node target, the
/// signals at which the network holds its nodes) are spread over the first
/// [`GROWTH_TIME_SHARE`] of the pace, slowly at first (time to the power [`GROWTH_EXPONENT`],
/// so the first second shows a handful of nodes, not a finished shape); the rest evenly over
/// the remainder.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pacer {
    /// The run's signal budget.
    pub budget: u64,
    /// Signals the growth takes (at most the budget).
    pub growth: u64,
    /// Seconds of running wall time the budget is spread over ([`pace_seconds`]).
    pub pace: f64,
}

impl Pacer {
    /// The schedule of a run on `engine` paced to `seconds` of watch time.
    pub fn of(engine: &Engine, seconds: f64) -> Pacer {
        Pacer {
            budget: engine.max_signals(),
            growth: engine.growth_signals(),
            pace: pace_seconds(seconds, engine.limits()),
        }
    }

    /// Share of the pace the growth gets: [`GROWTH_TIME_SHARE`], or all of it when the growth
    /// takes the whole budget.
    fn growth_share(&self) -> f64 {
        if self.growth >= self.budget {
            1.0
        } else {
            GROWTH_TIME_SHARE
        }
    }

    /// Share of the budget the growth takes.
    fn growth_fraction(&self) -> f64 {
        (self.growth.min(self.budget) as f64 / self.budget.max(1) as f64).max(1e-9)
    }

    /// Signals due after `clock` seconds: the whole budget once the pace is over (or at once
    /// for a pace of 0: a limit below the minimum).
    pub fn due(&self, clock: f64) -> u64 {
        if self.pace <= 0.0 {
            return self.budget;
        }
        let u = (clock / self.pace).clamp(0.0, 1.0);
        let (s, g) = (self.growth_share(), self.growth_fraction());
        let f = if u < s {
            g * (u / s).powf(GROWTH_EXPONENT)
        } else {
            g + (1.0 - g) * (u - s) / (1.0 - s).max(1e-9)
        };
        ((self.budget as f64 * f).round() as u64).min(self.budget)
    }

    /// Seconds of the pace at which `signals` are due (the inverse of [`Pacer::due`]).
    pub fn time_of(&self, signals: u64) -> f64 {
        if self.pace <= 0.0 {
            return 0.0;
        }
        let f = (signals as f64 / self.budget.max(1) as f64).clamp(0.0, 1.0);
        let (s, g) = (self.growth_share(), self.growth_fraction());
        let u = if f < g {
            s * (f / g).powf(1.0 / GROWTH_EXPONENT)
        } else {
            s + (f - g) / (1.0 - g).max(1e-9) * (1.0 - s)
        };
        u.min(1.0) * self.pace
    }
}

/// Whether a paced run may reconstruct a checkpoint now: it is on pace (at most
/// [`PREVIEW_LAG_SECONDS`] behind, `lag` seconds) or its previews so far took at most
/// [`PREVIEW_TIME_SHARE`] of its running time (`preview_share`), and a preview as long as the
/// last one (`last_preview` seconds) ends before the training does (`left` seconds of pace
/// left). A preview runs on the training thread: one that makes the run late takes signals from
/// the network (a late run stops training at its pace's end) or time from the steps after it;
/// the share keeps a machine that is always a little behind (a busy one) from showing no
/// checkpoint at all.
pub fn paced_preview_fits(lag: f64, left: f64, last_preview: f64, preview_share: f64) -> bool {
    (lag <= PREVIEW_LAG_SECONDS || preview_share <= PREVIEW_TIME_SHARE) && last_preview < left
}

/// Share of a paced run's running time that checkpoint previews may take while the run is
/// behind its schedule.
pub const PREVIEW_TIME_SHARE: f64 = 0.1;

/// How far (seconds of pace) a paced run may be behind its schedule and still measure a point
/// of the vertex-error curve (a few ms each; the paced growth runs at up to 1.7 times the
/// mean signal rate late in the growth, where a busy machine falls a little behind).
pub const ERROR_POINT_LAG_SECONDS: f64 = 0.5;

/// Share of a paced run's time the vertex-error measurements may take when the run is behind
/// its schedule by more than [`ERROR_POINT_LAG_SECONDS`].
pub const ERROR_POINT_TIME_SHARE: f64 = 0.1;

/// How far (seconds of pace) a paced run may be behind its schedule and still reconstruct a
/// checkpoint.
pub const PREVIEW_LAG_SECONDS: f64 = 0.05;

/// Whether a paced run with a time limit is past the end of its pace (`clock` and `pace`
/// seconds of running wall time) by more than [`PREVIEW_LAG_SECONDS`]: a run on pace has spent
/// its budget by then and finished; a late one stops training there.
pub fn is_late(clock: f64, pace: f64) -> bool {
    clock > pace + PREVIEW_LAG_SECONDS
}

/// What a training run works on.
#[derive(Clone)]
pub struct TrainingJob {
    /// The (cleaned) original mesh.
    pub mesh: Arc<TriMesh>,
    /// Its normals, texture coordinates and colours, when it has some: the network's triangles
    /// then follow their seams, as `gng3d simplify --method gng` does.
    pub attributes: Option<Arc<mesh::attributes::Attributes>>,
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
    /// A run started: the steps its finished network's pipeline will run, and its limits.
    Planned {
        /// Session number.
        session: u64,
        /// The steps the run's parameters plan without a time limit, in order
        /// ([`Engine::full_plan`]).
        full_plan: Vec<PlannedStep>,
        /// Those of them the run will run ([`Engine::plan`]; the rest the time limit left out
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
    /// now" on a finished network gets the same mesh again, [`Engine::has_final`]).
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

/// Mutable state of the training thread.
struct Training {
    session: u64,
    source: Option<Arc<TriMesh>>,
    engine: Option<Engine>,
    running: bool,
    /// When the user paused the run (left out of its clock on resume).
    paused_at: Option<Instant>,
    finished: bool,
    speed: Speed,
    batch: u64,
    checkpoint_every: Option<u64>,
    next_checkpoint: u64,
    train_time: Duration,
    /// Time spent on checkpoint reconstructions since the reset.
    reconstruct_time: Duration,
    /// Checkpoint reconstructions since the reset, and the seconds of the last one.
    previews: u64,
    last_preview: f64,
    /// Checkpoints skipped by [`CHECKPOINT_TIME_SHARE`] since the reset (see [`Live`]).
    skipped_checkpoints: u64,
    /// Points of a paced run's error schedule left out since the reset (see [`Live`]).
    skipped_error_points: u64,
    /// Wall time spent running (pauses excluded) since the reset: the clock of a paced run.
    paced_clock: Duration,
    /// When `paced_clock` was last advanced.
    clock_tick: Instant,
    last_publish: Instant,
    last_errors: Instant,
    error_interval: Duration,
    /// Time spent measuring vertex errors since the reset.
    error_time: Duration,
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
        paused_at: None,
        finished: false,
        speed: Speed::Unlimited,
        batch: 256,
        checkpoint_every: None,
        next_checkpoint: u64::MAX,
        train_time: Duration::ZERO,
        reconstruct_time: Duration::ZERO,
        previews: 0,
        last_preview: 0.0,
        skipped_checkpoints: 0,
        skipped_error_points: 0,
        paced_clock: Duration::ZERO,
        clock_tick: Instant::now(),
        next_error_signals: 0,
        last_publish: Instant::now(),
        published: None,
        last_errors: Instant::now(),
        error_interval: Duration::from_millis(200),
        error_time: Duration::ZERO,
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
                    t.error_time = Duration::ZERO;
                    t.previews = 0;
                    t.last_preview = 0.0;
                    t.skipped_checkpoints = 0;
                    t.skipped_error_points = 0;
                    t.paced_clock = Duration::ZERO;
                    // The run's clock (the core's, from `Engine::new`) and the pace start together.
                    t.clock_tick = Instant::now();
                    t.next_error_signals = 0;
                    t.signals_per_second = 0.0;
                    t.rate_window = (Instant::now(), 0);
                    t.checkpoint_every = session.checkpoint_every.filter(|&c| c > 0);
                    t.next_checkpoint = t.checkpoint_every.unwrap_or(u64::MAX);
                    let (time_limit, limit_is_watch_time) =
                        run_time_limit(session.params.time_limit, t.speed, session.autoplay);
                    let params = TrainParams {
                        time_limit,
                        ..session.params.clone()
                    };
                    match Engine::new(&session.mesh, session.attributes.as_deref(), &params) {
                        Ok(engine) => {
                            let _ = events.send(Event::Planned {
                                session: t.session,
                                full_plan: engine.full_plan(),
                                steps: engine.plan(),
                                // A watched run's length is its watch time (the core's
                                // limit is only its backstop).
                                time_limit: match (limit_is_watch_time, t.speed) {
                                    (true, Speed::Paced { seconds }) => Some(seconds),
                                    _ => engine.time_limit().map(|d| d.as_secs_f64()),
                                },
                                limit_is_watch_time,
                                steps_estimate: engine.limits().map(|(limit, training)| {
                                    limit.saturating_sub(training).as_secs_f64()
                                }),
                            });
                            t.engine = Some(engine);
                            t.running = session.autoplay;
                            // A run that starts paused starts its clock when it first plays.
                            t.paused_at = (!t.running).then(Instant::now);
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
                    // A pause does not count against the run's time limit.
                    match (t.running, running) {
                        (true, false) => t.paused_at = Some(Instant::now()),
                        (false, true) => {
                            if let (Some(at), Some(engine)) =
                                (t.paused_at.take(), t.engine.as_mut())
                            {
                                engine.discount(at.elapsed());
                            }
                        }
                        _ => {}
                    }
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
    // A paced run with a time limit that is late (a loaded machine) ends its training at the
    // pace's end once the network holds its nodes: the steps after it keep their time, and the
    // network loses the signals it is short of, as the core's own limit would take them.
    if let Speed::Paced { seconds } = t.speed
        && let Some(limits) = engine.limits()
        && is_late(
            t.paced_clock.as_secs_f64(),
            pace_seconds(seconds, Some(limits)),
        )
        && engine.holds_target()
    {
        // What the rest of the budget would have had: left out, and counted so.
        let left = budget.saturating_sub(engine.signals());
        t.skipped_error_points += left / (budget / PACED_ERROR_POINTS).max(1);
        if let Some(every) = t.checkpoint_every {
            t.skipped_checkpoints += left / every;
        }
        engine.stop();
        t.finished = true;
    }
    let n = match t.speed {
        Speed::Unlimited => t.batch,
        Speed::Paced { seconds } => {
            // Where a run paced over its training's share of `seconds` (growth first, see
            // `Pacer`) would be now; a
            // checkpoint's reconstruction or a slow machine only make the run late, never a
            // burst (and a run with a time limit is stopped by the core at its limit).
            let due = Pacer::of(engine, seconds).due(t.paced_clock.as_secs_f64());
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
    // A paced run: how far behind its schedule it is (seconds of pace), and the pace left.
    let paced = match (t.speed, t.engine.as_ref()) {
        (Speed::Paced { seconds }, Some(engine)) => {
            let pacer = Pacer::of(engine, seconds);
            let clock = t.paced_clock.as_secs_f64();
            let lag = (clock - pacer.time_of(signals)).max(0.0);
            Some((lag, pacer.pace - clock))
        }
        _ => None,
    };
    let measure = match paced {
        // Full speed: a time budget (see `measure_errors`), and always the first batch of a run,
        // so the curve starts where training starts.
        None => signals <= n || t.last_errors.elapsed() >= t.error_interval,
        // Paced: a fixed signal schedule, so every run gets the same dense curve, as long as
        // the run is on pace (on a big mesh or a loaded machine, 200 measurements may take
        // most of the thread's time: armadillo, 6.6 s of a 10 s pace with another process on
        // one of two cores); a point a late run passes is left out, not taken later.
        // A run behind its schedule still measures while the measurements have taken at most
        // ERROR_POINT_TIME_SHARE of its time (small meshes: a few ms each).
        Some((lag, _)) => {
            signals >= t.next_error_signals
                && (lag <= ERROR_POINT_LAG_SECONDS
                    || t.error_time.as_secs_f64()
                        <= ERROR_POINT_TIME_SHARE * t.paced_clock.as_secs_f64())
        }
    };
    if measure || t.finished {
        measure_errors(t, events);
    }
    let error_step = (budget / PACED_ERROR_POINTS).max(1);
    if measure || t.finished || signals >= t.next_error_signals {
        // Scheduled points passed and not measured (a late run; one batch past the pace's end
        // may pass several).
        if paced.is_some() && signals >= t.next_error_signals {
            let passed = (signals - t.next_error_signals) / error_step + 1;
            t.skipped_error_points += passed - u64::from(measure || t.finished);
        }
        t.next_error_signals = signals + error_step;
    }
    if signals >= t.next_checkpoint && !t.finished {
        while t.next_checkpoint <= signals {
            t.next_checkpoint = t
                .next_checkpoint
                .saturating_add(t.checkpoint_every.unwrap_or(u64::MAX));
        }
        let within_share = match paced {
            // Paced runs sleep between batches: checkpoints only use that slack, while the run
            // is on pace and when they end before the training does.
            Some((lag, left)) => paced_preview_fits(
                lag,
                left,
                t.last_preview,
                t.reconstruct_time.as_secs_f64() / t.paced_clock.as_secs_f64().max(1e-9),
            ),
            None => {
                t.reconstruct_time.as_secs_f64()
                    <= CHECKPOINT_TIME_SHARE * t.train_time.as_secs_f64()
            }
        };
        if within_share {
            let started = Instant::now();
            reconstruct(t, events);
            let spent = started.elapsed();
            t.reconstruct_time += spent;
            t.previews += 1;
            t.last_preview = spent.as_secs_f64();
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
    t.error_time += cost;
    t.error_interval = (cost * 20).max(Duration::from_millis(100));
    t.last_errors = Instant::now();
}

fn reconstruct(t: &mut Training, events: &Sender<Event>) {
    let Some(engine) = t.engine.as_mut() else {
        return;
    };
    let session = t.session;
    let signals = engine.signals();
    // The finished network's pipeline runs once (a second request gets the same mesh).
    let full = engine.is_finished() && !engine.has_final();
    if full {
        let _ = events.send(Event::PipelineStarted {
            session,
            training_seconds: (t.paced_clock + t.clock_tick.elapsed()).as_secs_f64(),
            preview_seconds: t.reconstruct_time.as_secs_f64(),
            previews: t.previews,
        });
    }
    let started = Instant::now();
    let result = engine.reconstruct(|record| {
        let _ = events.send(Event::Step {
            session,
            record: record.clone(),
        });
    });
    if full {
        let _ = events.send(Event::PipelineDone {
            session,
            cut_for_time: result.as_ref().is_ok_and(|r| r.cut_for_time),
            pipeline_seconds: started.elapsed().as_secs_f64(),
            run_seconds: engine.run_elapsed().as_secs_f64(),
            failed: result.is_err(),
        });
    }
    let event = match result {
        Ok(r) => Event::Reconstructed {
            session,
            signals,
            mesh: Arc::new(r.mesh),
            train_seconds: t.train_time.as_secs_f64(),
            warnings: r.warnings,
        },
        Err(error) => Event::Failed {
            session,
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
            skipped_error_points: t.skipped_error_points,
            run_seconds: t.paced_clock.as_secs_f64(),
            pace_seconds: match (t.speed, t.engine.as_ref()) {
                (Speed::Paced { seconds }, Some(engine)) => {
                    Some(pace_seconds(seconds, engine.limits()))
                }
                _ => None,
            },
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

#[cfg(test)]
mod tests {
    use super::*;

    fn secs(s: f64) -> Duration {
        Duration::from_secs_f64(s)
    }

    #[test]
    fn a_watched_run_has_a_backstop_unless_the_user_limit_is_shorter() {
        let watch = Speed::Paced { seconds: 12.0 };
        assert_eq!(SOFT_LIMIT_FACTOR, 2.0, "update the values below");
        assert_eq!(run_time_limit(None, watch, true), (Some(secs(24.0)), true));
        // A shorter limit of the user's wins; a longer one gives way to the backstop.
        assert_eq!(
            run_time_limit(Some(secs(5.0)), watch, true),
            (Some(secs(5.0)), false)
        );
        assert_eq!(
            run_time_limit(Some(secs(30.0)), watch, true),
            (Some(secs(24.0)), true)
        );
        // Started paused, or as fast as possible: the user's limit alone.
        assert_eq!(run_time_limit(None, watch, false), (None, false));
        assert_eq!(
            run_time_limit(Some(secs(30.0)), watch, false),
            (Some(secs(30.0)), false)
        );
        assert_eq!(run_time_limit(None, Speed::Unlimited, true), (None, false));
        assert_eq!(
            run_time_limit(Some(secs(2.0)), Speed::Unlimited, true),
            (Some(secs(2.0)), false)
        );
    }

    #[test]
    fn training_is_paced_to_leave_the_steps_their_share_of_the_run() {
        assert_eq!(
            (STEPS_TIME_FACTOR, STEPS_MIN_MARGIN_SHARE),
            (1.25, 0.03),
            "update the values below"
        );
        // No limit: the whole watch time.
        assert_eq!(pace_seconds(12.0, None), 12.0);
        // 12 s in all, the core stops training at 10.4 s: the steps are estimated at 1.6 s and
        // get 1.25 times that, so the signals are spread over 12 - 2 = 10 s.
        let pace = pace_seconds(12.0, Some((secs(12.0), secs(10.4))));
        assert!((pace - 10.0).abs() < 1e-9, "{pace}");
        // Steps estimated at 0.6 s get at least 3 % of the limit (0.36 s) more: 11.04 s.
        let pace = pace_seconds(12.0, Some((secs(12.0), secs(11.4))));
        assert!((pace - 11.04).abs() < 1e-9, "{pace}");
        // A user's limit of 5 s (steps 2 s) on a 12 s watch: 2.5 s of training.
        let pace = pace_seconds(12.0, Some((secs(5.0), secs(3.0))));
        assert!((pace - 2.5).abs() < 1e-9, "{pace}");
        // Never longer than the watch time (a shorter watch set mid-run), never negative (a
        // limit below the run's minimum: training as fast as it can).
        assert_eq!(pace_seconds(3.0, Some((secs(30.0), secs(29.0)))), 1.75);
        assert_eq!(pace_seconds(12.0, Some((secs(1.0), secs(0.0)))), 0.0);

        // The backstop (24 s) is not the run's end: the watch time is. Steps estimated at
        // 1.6 s (training limit 22.4 s): 12 - 2 = 10 s of training.
        let pace = pace_seconds(12.0, Some((secs(24.0), secs(22.4))));
        assert!((pace - 10.0).abs() < 1e-9, "{pace}");

        // A late run stops training a little after its pace ends.
        assert!(!is_late(10.0, 10.0));
        assert!(!is_late(10.0 + PREVIEW_LAG_SECONDS, 10.0));
        assert!(is_late(10.1, 10.0));
    }

    #[test]
    fn the_schedule_paces_the_growth_slowly_first_and_is_its_own_inverse() {
        let pacer = Pacer {
            budget: 1_000_000,
            growth: 500_000,
            pace: 10.0,
        };
        assert_eq!(pacer.due(0.0), 0);
        assert_eq!(pacer.due(10.0), 1_000_000);
        assert_eq!(pacer.due(20.0), 1_000_000);
        // The growth's signals end at GROWTH_TIME_SHARE of the pace, the first second has
        // (1/6)^1.5 of them.
        assert_eq!(pacer.due(6.0), 500_000);
        assert_eq!(pacer.due(1.0), 34_021);
        // Monotone, and time_of inverts due.
        let mut last = 0;
        for k in 0..=100 {
            let t = 0.1 * f64::from(k);
            let due = pacer.due(t);
            assert!(due >= last);
            last = due;
            assert!((pacer.time_of(due) - t).abs() < 1e-3, "{t}: {due}");
        }
        // A growth as long as the budget (λ set high) takes the whole pace.
        let whole = Pacer {
            growth: 2_000_000,
            ..pacer
        };
        assert_eq!(whole.due(5.0), 353_553);
        // No time to pace: everything at once.
        assert_eq!(Pacer { pace: 0.0, ..pacer }.due(0.0), 1_000_000);
    }

    /// Issue 37, against a simulated clock (not this machine's speed): the default watched run
    /// of the built-in model, its real network stepped to the schedule's signal count at each
    /// simulated frame, holds under 10 % of its nodes 1 s into the run, grows over seconds, and
    /// ends within 20 % of the shown run length when its steps take up to the
    /// STEPS_TIME_FACTOR × their estimate that the pace leaves them.
    #[test]
    fn the_default_run_grows_visibly_and_ends_near_its_length_on_a_simulated_clock() {
        let options = crate::ViewerOptions::default();
        let (_, mesh) = engine::default_model();
        let watch = crate::session::DEFAULT_WATCH_SECONDS;
        let (time_limit, is_watch) = run_time_limit(None, crate::session::speed_for(None), true);
        assert!(is_watch);
        let params = TrainParams {
            target_vertices: crate::session::default_target(mesh.vertex_count()),
            time_limit,
            ..crate::session::train_params(&options).unwrap()
        };
        let mut engine = Engine::new(&mesh, None, &params).unwrap();
        let pacer = Pacer::of(&engine, watch);
        let (limit, training_limit) = engine.limits().expect("a watched run has a limit");
        let steps_estimate = (limit - training_limit).as_secs_f64();
        let frame = 0.025;
        let (mut clock, mut grown_at, mut at_one_second) = (0.0, None, None);
        while !engine.is_finished() {
            clock += frame;
            let due = pacer.due(clock);
            if due > engine.signals() {
                engine.step(due - engine.signals());
            } else if due >= pacer.budget {
                // The pace is over: the trainer decides when it is finished.
                engine.step(1);
            }
            let (nodes, target) = engine.nodes();
            if at_one_second.is_none() && clock >= 1.0 {
                at_one_second = Some((nodes, target));
            }
            if grown_at.is_none() && nodes >= target {
                grown_at = Some(clock);
            }
            assert!(clock < 3.0 * watch, "the simulated run never finished");
        }
        // The issue asks for under 25 %; the even spread of the budget gave about 19 % here.
        let (nodes, target) = at_one_second.unwrap();
        assert!(
            (nodes as f64) < 0.10 * target as f64,
            "{nodes} of {target} nodes after 1 s"
        );
        let grown_at = grown_at.expect("the network reached its nodes");
        assert!(
            grown_at >= 3.0 && grown_at <= pacer.pace,
            "growth over {grown_at:.2} s of a {:.2} s pace",
            pacer.pace
        );
        // The training ends at the pace (one frame after), the steps take their estimate or
        // STEPS_TIME_FACTOR times it.
        assert!(clock <= pacer.pace + 2.0 * frame, "{clock} {}", pacer.pace);
        for factor in [1.0, STEPS_TIME_FACTOR] {
            let end = clock + factor * steps_estimate;
            assert!(
                (end - watch).abs() <= 0.2 * watch,
                "run ends at {end:.2} s of {watch} s (steps {steps_estimate:.2} s × {factor})"
            );
        }
    }

    #[test]
    fn a_paced_preview_runs_on_pace_or_within_its_share_and_ends_before_the_training() {
        assert!(paced_preview_fits(0.0, 5.0, 0.3, 0.5));
        assert!(paced_preview_fits(PREVIEW_LAG_SECONDS, 5.0, 0.3, 0.5));
        // Behind after the last preview, and previews took a fifth of the run: catch up first.
        assert!(!paced_preview_fits(0.4, 5.0, 0.3, 0.2));
        // Behind, but previews took only 5 % of the run so far: a busy machine still shows
        // checkpoints.
        assert!(paced_preview_fits(0.4, 5.0, 0.3, 0.05));
        // The last preview took 0.3 s and 0.2 s of training are left: the final mesh follows.
        assert!(!paced_preview_fits(0.0, 0.2, 0.3, 0.0));
        // The first preview of a run (none timed yet) runs whenever the run is on pace.
        assert!(paced_preview_fits(0.0, 0.01, 0.0, 0.0));
    }
}

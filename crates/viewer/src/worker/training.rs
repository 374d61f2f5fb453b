//! The training thread's message loop: its mutable state ([`Training`]), the commands it
//! answers and the order in which it runs its jobs (in `jobs`) between them.

mod jobs;

use super::{Command, Event, Shared, Speed, run_time_limit};
use crate::engine::{Engine, NetworkSnapshot, TrainParams};
use jobs::{measure_errors, publish, reconstruct, train_batch};
use mesh::TriMesh;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, TryRecvError};
use std::time::{Duration, Instant};

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
    /// Checkpoints skipped by [`CHECKPOINT_TIME_SHARE`](super::CHECKPOINT_TIME_SHARE) since the reset (see [`Live`](super::Live)).
    skipped_checkpoints: u64,
    /// Points of a paced run's error schedule left out since the reset (see [`Live`](super::Live)).
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

pub(super) fn training_loop(commands: &Receiver<Command>, events: &Sender<Event>, shared: &Shared) {
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
                    let model = mesh::Model {
                        mesh: (*session.mesh).clone(),
                        attributes: session.attributes.as_deref().cloned(),
                        ..(*session.place).clone()
                    };
                    match Engine::new(&model, &params) {
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

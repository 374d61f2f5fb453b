//! The jobs the training thread runs between commands: a batch of training signals (paced or
//! at full speed), the live vertex-error measurement, a checkpoint reconstruction, and the
//! publication of the network snapshot to the UI.

use super::{Training, signals_of};
use crate::engine::{self, Engine};
use crate::worker::{
    CHECKPOINT_TIME_SHARE, ERROR_POINT_LAG_SECONDS, ERROR_POINT_TIME_SHARE, Event, Live,
    PACED_ERROR_POINTS, Pacer, Shared, Speed, TRAINING_FRAME_INTERVAL, is_late, pace_seconds,
    paced_preview_fits,
};
use std::sync::mpsc::Sender;
use std::sync::{Arc, PoisonError};
use std::time::{Duration, Instant};

pub(super) fn train_batch(t: &mut Training, shared: &Shared, events: &Sender<Event>) {
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
pub(super) fn measure_errors(t: &mut Training, events: &Sender<Event>) {
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

pub(super) fn reconstruct(t: &mut Training, events: &Sender<Event>) {
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
            mesh: r.mesh,
            train_seconds: t.train_time.as_secs_f64(),
            outcome: r.outcome,
        },
        Err(error) => Event::Failed {
            session,
            message: format!("reconstruction failed: {error}"),
        },
    };
    let _ = events.send(event);
}

pub(super) fn publish(t: &mut Training, shared: &Shared) {
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

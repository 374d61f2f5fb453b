//! The schedule of a training run: how fast it runs ([`Speed`]), the backstop time limit of a
//! watched run ([`run_time_limit`]), the wall time its training is paced over
//! ([`pace_seconds`]), how its growth and error points are spread over that time ([`Pacer`]),
//! and when a paced run may take a checkpoint preview.

use crate::engine::Engine;
use std::time::Duration;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::{self, TrainParams};

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
        let mut engine = Engine::new(&mesh.into(), &params).unwrap();
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

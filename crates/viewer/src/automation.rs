//! Screenshot-and-quit automation (`--quit-after SECS [--screenshot PATH]`) and the one-line
//! `viewer stats:` summary printed when quitting.

use crate::diagnostics::FrameStats;
use crate::io;
use crate::session::Session;
use crate::steps::StepStatus;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// What a pending screenshot delivers: the saved path or the error.
type ScreenshotSlot = Arc<Mutex<Option<crate::error::Result<PathBuf>>>>;

/// Why a scripted run (`--quit-after` with `--screenshot`) failed, for [`crate::run`] to turn
/// into a non-zero exit once the window has closed.
static SCRIPTED_FAILURE: Mutex<Option<String>> = Mutex::new(None);

fn scripted_failure(message: String) {
    *SCRIPTED_FAILURE
        .lock()
        .unwrap_or_else(PoisonError::into_inner) = Some(message);
}

/// The failure of the scripted run that just ended, if any.
pub(crate) fn take_scripted_failure() -> Option<String> {
    SCRIPTED_FAILURE
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .take()
}

/// Screenshot-and-quit state.
#[derive(Default)]
pub struct Automation {
    screenshot_requested: bool,
    screenshot_since: Option<Instant>,
    screenshot_result: ScreenshotSlot,
    close_sent: bool,
}

impl Automation {
    /// Save a PNG of the whole window of `ctx` to `path` once the next frame is rendered.
    pub(crate) fn request_screenshot(&self, ctx: &egui::Context, path: PathBuf) {
        let slot = Arc::clone(&self.screenshot_result);
        let repaint = ctx.clone();
        ctx.request_screenshot(move |image| {
            let result = io::save_png(&image, &path).map(|()| path);
            *slot.lock().unwrap_or_else(PoisonError::into_inner) = Some(result);
            repaint.request_repaint();
        });
        ctx.request_repaint();
    }

    /// Report finished screenshots in `session`'s messages; `elapsed` seconds after the start,
    /// whether the window closes now (after `--quit-after`, with its screenshot first).
    pub(crate) fn update(
        &mut self,
        ctx: &egui::Context,
        session: &mut Session,
        elapsed: f64,
    ) -> bool {
        let finished_shot = self
            .screenshot_result
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take();
        if let Some(result) = finished_shot {
            match result {
                Ok(path) => session.info(format!("saved {}", path.display())),
                Err(e) => {
                    if self.screenshot_requested {
                        scripted_failure(format!("screenshot failed: {e}"));
                    }
                    session.error(format!("screenshot failed: {e}"));
                }
            }
            if self.screenshot_requested {
                self.screenshot_requested = false;
                return true;
            }
        }
        let Some(limit) = session.options().quit_after else {
            return false;
        };
        if self.screenshot_requested
            && self
                .screenshot_since
                .is_some_and(|t| t.elapsed() > Duration::from_secs(10))
        {
            scripted_failure("screenshot timed out after 10 s".into());
            session.error("screenshot timed out after 10 s");
            self.screenshot_requested = false;
            return true;
        }
        if elapsed < limit || self.close_sent || self.screenshot_requested {
            ctx.request_repaint_after(Duration::from_millis(50));
            return false;
        }
        match session.options().screenshot.clone() {
            Some(path) => {
                self.screenshot_requested = true;
                self.screenshot_since = Some(Instant::now());
                self.request_screenshot(ctx, path);
                false
            }
            None => true,
        }
    }

    /// True the first time the window closes (then the summary is printed), false after.
    pub(crate) fn begin_close(&mut self) -> bool {
        !std::mem::replace(&mut self.close_sent, true)
    }
}

/// The one-line `viewer stats:` summary (fps, training rate, sizes, the run's seconds from
/// start to final mesh with its training and steps and each entry of the step strip, backend,
/// viewport rectangles in pixels at `ppp` pixels per point).
pub fn summary(
    session: &Session,
    stats: &FrameStats,
    backend: Option<wgpu::Backend>,
    viewport_rects: [Option<egui::Rect>; 2],
    ppp: f32,
) -> String {
    let live = session.live();
    let rect = |r: Option<egui::Rect>| {
        r.map_or_else(
            || "none".to_string(),
            |r| {
                format!(
                    "{:.0},{:.0},{:.0},{:.0}",
                    r.min.x * ppp,
                    r.min.y * ppp,
                    r.width() * ppp,
                    r.height() * ppp
                )
            },
        )
    };
    let steps = &session.steps;
    let seconds = |s: Option<f64>| s.map_or_else(|| "none".to_string(), |s| format!("{s:.2}"));
    let rows = steps.rows();
    let count = |f: fn(&StepStatus) -> bool| rows.iter().filter(|r| f(&r.status)).count();
    // Each entry of the strip: `build:0.231`, `detail_2:skipped`.
    let group_times = steps
        .groups()
        .iter()
        .map(|g| {
            let status = match g.status() {
                StepStatus::Done { seconds, .. } => format!("{seconds:.3}"),
                StepStatus::Pending => "pending".into(),
                StepStatus::Running => "running".into(),
                StepStatus::Skipped => "skipped".into(),
                StepStatus::NotRun => "not_run".into(),
            };
            format!("{}:{status}", g.label.replace(' ', "_"))
        })
        .collect::<Vec<_>>()
        .join(",");
    format!(
        "viewer stats: model={} frames={} mean_fps={:.1} last_frame_ms={:.1} \
         drawing_cpu_ms_per_frame={:.1} max_nodes={} signals={} mean_signals_per_s={:.0} \
         train_s={:.2} gng_mesh_faces={} qem_faces={} error_points={} checkpoints={} \
         skipped_checkpoints={} skipped_error_points={} skipped_evaluations={} run_s={} pace_s={} steps_estimate_s={} training_wall_s={} \
         pipeline_s={} steps_done={} \
         steps_skipped={} steps={} backend={} gng_viewport={} qem_viewport={}",
        session.model_name,
        stats.frames,
        stats.mean_fps(),
        stats.frame_ms(),
        stats.drawing_cpu_ms_per_frame(),
        stats.max_nodes,
        live.snapshot.signals,
        stats.mean_signals_per_second(live.snapshot.signals, live.train_seconds),
        live.train_seconds,
        session.reconstruction().map_or(0, |m| m.face_count()),
        session.qem_mesh().map_or(0, |m| m.face_count()),
        session.history.errors.len(),
        session.history.reconstructions.len(),
        live.skipped_checkpoints,
        live.skipped_error_points,
        session.skipped_evaluations(),
        seconds(steps.run_seconds),
        seconds(live.pace_seconds),
        seconds(steps.limit.map(|l| l.steps_estimate)),
        seconds(steps.training_seconds),
        seconds(steps.pipeline_seconds),
        count(StepStatus::is_done),
        count(|s| *s == StepStatus::Skipped),
        group_times,
        backend.map_or_else(|| "none".to_string(), |b| format!("{b:?}")),
        rect(viewport_rects[0]),
        rect(viewport_rects[1]),
    )
}

//! Screenshot-and-quit automation (`--quit-after SECS [--screenshot PATH]`) and the one-line
//! `viewer stats:` summary printed when quitting.

use crate::app::ViewerApp;
use crate::io;
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

impl ViewerApp {
    /// Save a PNG of the whole window to `path` once the next frame is rendered.
    pub fn request_screenshot(&mut self, path: PathBuf) {
        let Some(ctx) = self.session_context() else {
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

    fn session_context(&self) -> Option<egui::Context> {
        self.automation_ctx.clone()
    }

    /// Report finished screenshots; quit after `--quit-after` (with its screenshot first).
    pub(crate) fn automation(&mut self, ctx: &egui::Context) {
        self.automation_ctx = Some(ctx.clone());
        let finished_shot = self
            .automation
            .screenshot_result
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take();
        if let Some(result) = finished_shot {
            match result {
                Ok(path) => self.session.info(format!("saved {}", path.display())),
                Err(e) => {
                    if self.automation.screenshot_requested {
                        scripted_failure(format!("screenshot failed: {e}"));
                    }
                    self.session.error(format!("screenshot failed: {e}"));
                }
            }
            if self.automation.screenshot_requested {
                self.automation.screenshot_requested = false;
                self.close(ctx);
            }
        }
        let Some(limit) = self.session.options().quit_after else {
            return;
        };
        if self.automation.screenshot_requested
            && self
                .automation
                .screenshot_since
                .is_some_and(|t| t.elapsed() > Duration::from_secs(10))
        {
            scripted_failure("screenshot timed out after 10 s".into());
            self.session.error("screenshot timed out after 10 s");
            self.automation.screenshot_requested = false;
            self.close(ctx);
        }
        let elapsed = self.started.elapsed().as_secs_f64();
        if elapsed < limit || self.automation.close_sent || self.automation.screenshot_requested {
            ctx.request_repaint_after(Duration::from_millis(50));
            return;
        }
        match self.session.options().screenshot.clone() {
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
        if self.session.options().print_stats {
            println!("{}", self.summary());
        }
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    /// One-line run summary (fps, training rate, sizes, the run's seconds from start to final
    /// mesh with its training and steps and each entry of the step strip, backend, viewport
    /// rectangles in pixels).
    pub fn summary(&self) -> String {
        let live = self.session.live();
        let ppp = self
            .automation_ctx
            .as_ref()
            .map_or(1.0, egui::Context::pixels_per_point);
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
        let steps = &self.session.steps;
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
            self.session.model_name,
            self.stats.frames,
            self.stats.mean_fps(),
            self.stats.frame_ms(),
            self.stats.drawing_cpu_ms_per_frame(),
            self.stats.max_nodes,
            live.snapshot.signals,
            self.stats
                .mean_signals_per_second(live.snapshot.signals, live.train_seconds),
            live.train_seconds,
            self.session.reconstruction().map_or(0, |m| m.face_count()),
            self.session.qem_mesh().map_or(0, |m| m.face_count()),
            self.session.history.errors.len(),
            self.session.history.reconstructions.len(),
            live.skipped_checkpoints,
            live.skipped_error_points,
            self.session.skipped_evaluations(),
            seconds(steps.run_seconds),
            seconds(live.pace_seconds),
            seconds(steps.limit.map(|l| l.steps_estimate)),
            seconds(steps.training_seconds),
            seconds(steps.pipeline_seconds),
            count(StepStatus::is_done),
            count(|s| *s == StepStatus::Skipped),
            group_times,
            self.backend()
                .map_or_else(|| "none".to_string(), |b| format!("{b:?}")),
            rect(self.viewport_rects[0]),
            rect(self.viewport_rects[1]),
        )
    }
}

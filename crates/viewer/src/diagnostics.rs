//! Frame diagnostics: frame times (an `egui::util::History` of recent frames), the measured
//! period after a warm-up for the `viewer stats:` line, and the on-CPU time of the threads that
//! draw (from `/proc/self/task/*/schedstat`), which unlike fps hardly moves when other jobs load
//! the machine.

use std::time::Instant;

/// Seconds after start before frames count for the run summary (start-up and first uploads
/// excluded).
const WARM_UP_SECONDS: f64 = 1.0;

/// Frame timing statistics.
pub struct FrameStats {
    last: Option<Instant>,
    /// Frame intervals (seconds) of the last 120 frames within 2 s.
    recent: egui::util::History<f32>,
    /// Frames since start.
    pub frames: u64,
    /// Frames counted for the run summary (after the warm-up).
    pub measured_frames: u64,
    /// Time covered by `measured_frames`, seconds.
    pub measured_seconds: f64,
    /// Highest node count seen while measuring.
    pub max_nodes: usize,
    /// Signals/s samples while training ran (after the warm-up).
    pub rate_samples: Vec<f64>,
    /// On-CPU seconds of the drawing threads (see [`drawing_cpu_seconds`]) when measuring began.
    cpu_at_measure_start: Option<f64>,
    /// How often each viewport (GNG3D, QEM) was actually redrawn; an unchanged viewport is not.
    pub viewport_redraws: [u64; 2],
}

impl Default for FrameStats {
    fn default() -> Self {
        FrameStats {
            last: None,
            recent: egui::util::History::new(0..120, 2.0),
            frames: 0,
            measured_frames: 0,
            measured_seconds: 0.0,
            max_nodes: 0,
            rate_samples: Vec::new(),
            cpu_at_measure_start: None,
            viewport_redraws: [0; 2],
        }
    }
}

impl FrameStats {
    /// Record a frame drawn `since_start` seconds after the app started.
    pub fn tick(&mut self, since_start: f64) {
        let now = Instant::now();
        if let Some(last) = self.last {
            let dt = now.duration_since(last).as_secs_f64();
            self.recent.add(since_start, dt as f32);
            if since_start > WARM_UP_SECONDS {
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

    /// Record the training state of this frame (for the summary).
    pub fn record_training(&mut self, since_start: f64, nodes: usize, signals_per_second: f64) {
        self.max_nodes = self.max_nodes.max(nodes);
        if signals_per_second > 0.0 && since_start > WARM_UP_SECONDS {
            self.rate_samples.push(signals_per_second);
        }
    }

    /// Mean frame interval over the recent frames, milliseconds (0 when none).
    pub fn frame_ms(&self) -> f64 {
        f64::from(self.recent.average().unwrap_or(0.0)) * 1000.0
    }

    /// Mean on-CPU time of the drawing threads per frame since measuring began (after the
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

    /// Mean training rate over the measured period; when training ended within the warm-up,
    /// the whole run's rate (`signals / train_seconds`) instead of 0.
    pub fn mean_signals_per_second(&self, signals: u64, train_seconds: f64) -> f64 {
        if !self.rate_samples.is_empty() {
            self.rate_samples.iter().sum::<f64>() / self.rate_samples.len() as f64
        } else if train_seconds > 0.0 {
            signals as f64 / train_seconds
        } else {
            0.0
        }
    }
}

/// Names of the viewer's own worker threads: everything else in the process draws the UI (the
/// main thread and the software rasterizer's threads).
pub const WORKER_THREADS: [&str; 5] = [
    "gng-training",
    "qem",
    "evaluation",
    "load-mesh",
    "file-dialog",
];

/// Total on-CPU seconds of the threads that draw (all but [`WORKER_THREADS`]), from
/// `/proc/self/task/*/schedstat`; `None` where that is unavailable (not Linux). Independent of
/// how long the threads waited for a core, so it measures the cost of drawing on a busy machine.
pub fn drawing_cpu_seconds() -> Option<f64> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_falls_back_to_the_whole_run_when_training_ended_in_the_warm_up() {
        let mut stats = FrameStats::default();
        assert_eq!(stats.mean_signals_per_second(0, 0.0), 0.0);
        assert_eq!(stats.mean_signals_per_second(3_000, 0.5), 6_000.0);
        stats.record_training(0.5, 10, 1e6); // in the warm-up: not a sample
        assert!(stats.rate_samples.is_empty());
        stats.record_training(2.0, 20, 2e6);
        stats.record_training(3.0, 30, 4e6);
        assert_eq!(stats.mean_signals_per_second(3_000, 0.5), 3e6);
        assert_eq!(stats.max_nodes, 30);
    }
}

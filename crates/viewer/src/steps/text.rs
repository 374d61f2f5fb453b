//! The step strip's texts: the steps' names, the seconds, counts and statuses as the strip
//! and its details window write them, the training entry and the total.

use super::{StepStatus, StepStrip};
use crate::engine::PipelineStep;

/// A step's name in the strip ("map", "repair").
pub fn short_name(step: PipelineStep) -> &'static str {
    match step {
        PipelineStep::Label => "label",
        PipelineStep::ConnectCells => "cells",
        PipelineStep::MapFaces => "map",
        PipelineStep::SplitBadCells => "split",
        PipelineStep::Attach => "attach",
        PipelineStep::Place => "place",
        PipelineStep::Flip => "flip",
        PipelineStep::Refit => "refit",
        PipelineStep::DetailRound => "detail",
        PipelineStep::CutSeams => "seams",
        PipelineStep::Decimate => "decimate",
        PipelineStep::Relax => "relax",
        PipelineStep::RepairDeviations => "repair",
        _ => step.name(),
    }
}

/// A step's name in the details table ("map faces").
pub fn long_name(step: PipelineStep) -> String {
    step.name().replace('_', " ")
}

/// Seconds for the strip: "0.4 ms", "31 ms", "1.24 s", "11.8 s".
pub fn format_seconds(seconds: f64) -> String {
    if seconds < 0.001 {
        format!("{:.1} ms", seconds * 1e3)
    } else if seconds < 1.0 {
        format!("{:.0} ms", seconds * 1e3)
    } else if seconds < 10.0 {
        format!("{seconds:.2} s")
    } else {
        format!("{seconds:.1} s")
    }
}

/// A count with thousands separators: 12,345.
pub fn group_digits(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// "12,345 faces mapped" for a done step.
pub fn changed_text(step: PipelineStep, changed: usize) -> String {
    format!("{} {}", group_digits(changed), step.changes())
}

/// One row's status as text: its seconds, or what happened to it.
pub fn status_text(status: StepStatus) -> String {
    match status {
        StepStatus::Pending => "pending".into(),
        StepStatus::Running => "running…".into(),
        StepStatus::Done { seconds, .. } => format_seconds(seconds),
        StepStatus::Skipped => "skipped (time limit)".into(),
        StepStatus::NotRun => "not run".into(),
    }
}

/// What the training thread says about the run while it trains (for the strip's first entry).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrainingClock {
    /// Running wall time so far, seconds.
    pub seconds: f64,
    /// A paced run: the running wall time its signals are spread over.
    pub pace_seconds: Option<f64>,
    /// Whether it runs (not paused).
    pub running: bool,
}

/// The training entry's text: "training: 2.31 s of 4.10 s" while it trains, "training: 4.10 s".
pub(super) fn training_text(strip: &StepStrip, clock: TrainingClock) -> (String, StepStatus) {
    match strip.training_seconds {
        Some(seconds) => (
            format!("training: {}", format_seconds(seconds)),
            StepStatus::Done {
                seconds,
                changed: 0,
            },
        ),
        None => {
            let of = clock
                .pace_seconds
                .map_or(String::new(), |p| format!(" of {}", format_seconds(p)));
            let state = if clock.running { "" } else { " (paused)" };
            (
                format!("training: {}{of}{state}", format_seconds(clock.seconds)),
                if clock.running {
                    StepStatus::Running
                } else {
                    StepStatus::Pending
                },
            )
        }
    }
}

/// The total's text: "= 11.8 s of 12.0 s" once done, "limit 12.0 s" before.
pub(super) fn total_text(strip: &StepStrip) -> String {
    let limit = strip.limit.map(|l| {
        let what = if l.is_watch_time {
            "run length"
        } else {
            "time limit"
        };
        (format_seconds(l.seconds), what)
    });
    match (strip.total_seconds(), limit) {
        (Some(total), Some((limit, what))) => {
            format!("= {} ({what} {limit})", format_seconds(total))
        }
        (Some(total), None) => format!("= {}", format_seconds(total)),
        (None, Some((limit, what))) => format!("{what} {limit}"),
        (None, None) => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats() {
        assert_eq!(format_seconds(0.0004), "0.4 ms");
        assert_eq!(format_seconds(0.0312), "31 ms");
        assert_eq!(format_seconds(1.2345), "1.23 s");
        assert_eq!(format_seconds(11.84), "11.8 s");
        assert_eq!(group_digits(0), "0");
        assert_eq!(group_digits(999), "999");
        assert_eq!(group_digits(43_243), "43,243");
        assert_eq!(group_digits(1_234_567), "1,234,567");
        assert_eq!(
            changed_text(PipelineStep::MapFaces, 12_345),
            "12,345 faces mapped"
        );
        assert_eq!(
            long_name(PipelineStep::RepairDeviations),
            "repair deviations"
        );
        let strip = StepStrip::default();
        let clock = TrainingClock {
            seconds: 2.5,
            pace_seconds: Some(8.25),
            running: true,
        };
        assert_eq!(
            training_text(&strip, clock),
            (
                "training: 2.50 s of 8.25 s".to_string(),
                StepStatus::Running
            )
        );
    }
}

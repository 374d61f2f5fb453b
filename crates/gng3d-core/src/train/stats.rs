//! What training reports and takes: the public [`StopReason`], [`Snapshot`], [`Progress`] and
//! [`TrainingStats`] of a trainer, and the [`CancelToken`] that stops it.

use glam::Vec3;
#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};
use std::time::Duration;

/// Shared flag that stops a running [`crate::Trainer`] from another thread (at its next check, within
/// about a thousand signals): the workspace's one cancel flag, [`mesh::cancel::Cancel`], under
/// the name the trainer has always given it ([`crate::finish_cancellable`], QEM's
/// `QemParams::cancel` and the metrics take the same type).
pub type CancelToken = mesh::cancel::Cancel;

/// Why training ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum StopReason {
    /// The signal budget was used and the node count is at the target.
    #[cfg_attr(feature = "serde", serde(alias = "Completed"))]
    Completed,
    /// The time limit was reached.
    #[cfg_attr(feature = "serde", serde(alias = "TimeLimit"))]
    TimeLimit,
    /// Cancelled through a [`CancelToken`] or an observer.
    #[cfg_attr(feature = "serde", serde(alias = "Cancelled"))]
    Cancelled,
    /// Twice the signal budget was used without reaching the target (should not happen).
    #[cfg_attr(feature = "serde", serde(alias = "SignalCap"))]
    SignalCap,
}

impl std::fmt::Display for StopReason {
    /// In words, lowercase, as the CLI and the viewer print it ("completed", "time limit").
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StopReason::Completed => "completed",
            StopReason::TimeLimit => "time limit",
            StopReason::Cancelled => "cancelled",
            StopReason::SignalCap => "signal cap",
        })
    }
}

/// A copy of the network with compact indices, for drawing.
#[derive(Debug, Clone, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Snapshot {
    /// Node positions, model units.
    pub positions: Vec<Vec3>,
    /// GNG edges as index pairs into `positions` (smaller index first).
    pub edges: Vec<[u32; 2]>,
    /// Signals processed so far.
    pub signals: u64,
    /// Target node count.
    pub target: usize,
    /// Whether training has ended.
    pub finished: bool,
}

/// Training progress reported to [`crate::Trainer::train`] observers.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Progress {
    /// Signals processed so far (the paper's iterations).
    pub signals: u64,
    /// Current node count.
    pub nodes: usize,
    /// Current edge count.
    pub edges: usize,
    /// Training time so far (sum of the time spent inside `step`).
    pub elapsed: Duration,
}

/// Counters of a finished or running training.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct TrainingStats {
    /// Signals processed.
    pub signals: u64,
    /// λ in use (lowered by the time-limit schedule when needed).
    pub lambda: u64,
    /// Signal budget (see [`crate::GngParams::max_signals`] and [`crate::GngParams::epochs`]).
    pub max_signals: u64,
    /// Nodes inserted (Fritzke insertion).
    pub insertions: u64,
    /// Nodes removed by the μ inactivity rule.
    pub removed_inactive: u64,
    /// Nodes removed because they lost their last edge.
    pub removed_isolated: u64,
    /// Connected input components trained, each by its own network (or two, one a half, with
    /// [`crate::GngParams::split_training`]).
    pub components: usize,
    /// Training time, seconds.
    pub seconds: f64,
    /// Training time when the network first held all its nodes, seconds (`None` until then).
    pub growth_seconds: Option<f64>,
    /// Why training ended (`None` while running).
    pub stop: Option<StopReason>,
}

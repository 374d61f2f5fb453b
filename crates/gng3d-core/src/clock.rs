//! The run's clock: when the run began (the time limit counts from there, less the pauses a
//! front end hands back) and the wall time at which training stops once the network holds its
//! nodes. The run owns it; the training reads it.

use std::time::{Duration, Instant};

/// When a run began and when its training must stop.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Clock {
    /// When the run began (the top of [`crate::Trainer::new`]), moved on by the pauses left
    /// out ([`crate::Trainer::discount`]).
    pub started: Instant,
    /// Wall time from `started` at which training stops once the network holds its nodes
    /// (the time limit less what the plan needs).
    pub training_limit: Option<Duration>,
}

//! Phase 1, the networks: the GNG3D training of every piece of the input ([`training`]: the
//! rounds, the time-limit schedule of λ, the counters), one piece's network and inner loop
//! ([`part`]), the network itself ([`network`]), its nearest-node grid ([`grid`]), the
//! curvature weights of the signals ([`features`]) and what the training reports ([`stats`]).
//!
//! Steps of one [`crate::Trainer::step`] call: for every piece of the domain
//! ([`crate::domain`]) in turn, present signals in chunks of `CHECK_EVERY` (winner search on
//! the grid, GNG update, insertion every λ, removal of nodes that won nothing in the μ window),
//! then check the budget, the target, the time limit (rescheduling λ from the measured
//! throughput) and the cancel token.

mod features;
mod grid;
mod network;
mod part;
mod stats;
mod training;

pub use stats::{CancelToken, Progress, Snapshot, StopReason, TrainingStats};
pub(crate) use training::Training;

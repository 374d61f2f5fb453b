//! Measured policy numbers that code outside this crate quotes or tests against (the CLI's help
//! text, the viewer's and the facade's tests). Not part of the supported API: the numbers are
//! documented, with their measurements, where they are defined, and they change when a
//! measurement says so. Users set the corresponding options ([`crate::GngOptions`]).
//!
//! Also the domain's thresholds that both the set-up (`domain`) and the warnings' words
//! (`report`) read.

pub use crate::options::{
    DEFAULT_DETAIL_ROUNDS, DEFAULT_OVERSAMPLE, DETAIL_MIN_RATIO, MAX_DETAIL_ROUNDS, MAX_SIGNALS,
    RELAX_MAX_RATIO,
};
pub use crate::params::{DEFAULT_SIGNALS_PER_NODE, PAPER_EPOCHS};

/// A component keeps its own nodes only when its proportional share of the target is at least
/// this many nodes: fewer cannot make a closed triangle fan, and a 1-2 node piece would be a
/// dangling sliver. Smaller components are dropped with a [`crate::GngWarning::DroppedComponents`].
pub(crate) const MIN_COMPONENT_NODES: usize = 3;

/// A vertex farther than this many robust radii (90th-percentile distance from the component's
/// median) is a stray point (scanner outlier, corrupted coordinate) and gives no signal. 1000
/// keeps legitimate long, thin parts (a rod 100× longer than wide is ~2 radii long at its
/// tips) and catches the 1e8-away points of the scans.
pub(crate) const STRAY_RADII: f64 = 1000.0;

/// A piece is trained as two halves ([`crate::GngParams::split_training`]) from this many nodes on,
/// i.e. at least 256 a half: smaller networks train in about 10 ms (the cow at 10 %: 435 nodes,
/// 43,500 signals, 11-15 ms), less than phase 2 takes, and the cells along the cut would be a
/// larger share of all cells.
pub const SPLIT_MIN_NODES: usize = 512;

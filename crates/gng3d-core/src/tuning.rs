//! Measured policy numbers that code outside this crate quotes or tests against (the CLI's help
//! text, the viewer's and the facade's tests). Not part of the supported API: the numbers are
//! documented, with their measurements, where they are defined, and they change when a
//! measurement says so. Users set the corresponding options ([`crate::GngOptions`]).

pub use crate::domain::SPLIT_MIN_NODES;
pub use crate::options::{
    DEFAULT_DETAIL_ROUNDS, DEFAULT_OVERSAMPLE, DETAIL_MIN_RATIO, MAX_DETAIL_ROUNDS, MAX_SIGNALS,
    RELAX_MAX_RATIO,
};
pub use crate::params::{DEFAULT_SIGNALS_PER_NODE, PAPER_EPOCHS};

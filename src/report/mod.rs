//! Experiment reports: plots and tables written by `compare` and `reproduce`.

pub mod paper;
pub mod plot;
pub mod table;

//! The GNG3D step strip: where a run's seconds go. The training comes first, then every step of
//! the finished network's pipeline (`gng3d_core::pipeline`), each pending, running, done (with
//! its seconds and what it changed), skipped (the time limit left it out) or not run (a detail
//! round found nothing to add, so the builds after it had nothing to do), then the total
//! against the run's time limit.
//!
//! [`StepStrip`] is the UI-free state the session fills from the training thread's events;
//! [`strip_ui`] draws it as one compact row under the viewports (build rounds grouped), and
//! [`details_window`] as a table of every step.
//!
//! `state` holds the strip's state, `text` its texts, `draw` the egui drawing.

mod draw;
mod state;
mod text;

pub use draw::*;
pub use state::*;
pub use text::*;

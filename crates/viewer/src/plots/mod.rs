//! Live plots in the style of the GNG3D paper's Figure 1 (E_avg and E_max against iterations on a
//! log scale, QEM's values as horizontal lines), E_sur and Hausdorff after each reconstruction on
//! their own axes, and a checkpoint table like the paper's Table 1 with CSV export. Every plot
//! spans the run's whole signal budget on x from the start, so the curves fill in left to right.
//!
//! `state` holds what the plots show (the error history and its CSV export), `axes` the
//! axes' ticks, labels and number formats, `draw` the plots and their legends, and
//! `table` the checkpoint tables.

mod axes;
mod draw;
mod state;
mod table;

pub use axes::*;
pub use draw::*;
pub use state::*;
pub use table::*;

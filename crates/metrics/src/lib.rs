//! Error metrics for simplified meshes: the GNG3D paper's E_avg/E_max/E_sur and Metro-style
//! symmetric surface distance.

pub mod paper;

pub use paper::{NearestVertexIndex, VertexErrors, vertex_errors};

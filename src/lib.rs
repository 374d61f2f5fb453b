//! gng3d: simplify triangle meshes with GNG3D (a Growing Neural Gas) and with Garland–Heckbert
//! quadric error metrics, and measure both honestly side by side.
//!
//! This facade re-exports the workspace crates so one dependency gives the whole toolkit:
//! [`mesh`] (mesh type, I/O, topology, sampling), [`gng3d_core`] (GNG3D training and
//! reconstruction), [`qem`] (quadric error metric simplification) and [`metrics`] (paper errors
//! and Metro-style surface distance).

pub use gng3d_core;
pub use mesh;
pub use metrics;
pub use qem;

pub mod experiment;
pub mod report;

//! Shared triangle mesh type for gng3d: geometry, I/O, cleaning, topology, sampling and
//! procedural models. Every algorithm crate takes and returns a [`TriMesh`].

pub mod clean;
pub mod error;
pub mod fixtures;
pub mod geometry;
pub mod io;
pub mod procedural;
pub mod quadric;
pub mod sampling;
pub mod topology;
mod trimesh;

pub use trimesh::{Aabb, TriMesh};

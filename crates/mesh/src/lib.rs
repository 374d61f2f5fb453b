//! Shared triangle mesh type for gng3d: geometry, I/O, cleaning, topology, sampling and
//! procedural models. Every algorithm crate takes and returns a [`TriMesh`].

// Lets shared helper code (fixtures.rs, also compiled into this crate's own tests and benches)
// name this crate `mesh` from inside and outside.
extern crate self as mesh;

pub mod clean;
pub mod error;
/// Test and benchmark helper: the shared meshes folder (feature `fixtures`).
#[cfg(any(test, feature = "fixtures"))]
pub mod fixtures;
pub mod geometry;
pub mod io;
pub mod procedural;
pub mod quadric;
pub mod sampling;
pub mod topology;
mod trimesh;

pub use trimesh::{Aabb, TriMesh};

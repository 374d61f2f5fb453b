//! Shared triangle mesh type for gng3d: geometry, I/O, cleaning, topology, sampling and
//! procedural models. Every algorithm crate takes and returns a [`TriMesh`].
//!
//! ```
//! use gng3d_mesh::{Model, TriMesh, clean, io, procedural, topology};
//! let sphere = procedural::icosphere(2); // 162 vertices, 320 faces, closed, genus 0
//! let report = topology::analyze(&sphere);
//! assert_eq!((report.boundary_edges, report.genus), (0, Some(0)));
//! // Welding merges exact duplicates (as OBJ/STL exporters write them), cleaning drops
//! // degenerate faces and unreferenced vertices.
//! let (welded, cleaning) = clean::prepare(&Model::from(sphere));
//! assert_eq!(welded.mesh.vertex_count(), 162);
//! assert_eq!(cleaning.welded_vertices, 0);
//! // Files: OBJ, PLY and STL, chosen by extension; writes go through a temp file + rename.
//! let path = std::env::temp_dir().join("mesh-doc-example.ply");
//! io::save(&welded, &path).unwrap();
//! let back: TriMesh = io::load(&path).unwrap().mesh;
//! assert_eq!(back.face_count(), 320);
//! # std::fs::remove_file(&path).ok();
//! ```

// Lets shared helper code (fixtures.rs, also compiled into this crate's own tests and benches)
// name this crate `mesh` from inside and outside.
extern crate self as mesh;

pub mod attributes;
pub mod cancel;
pub mod clean;
pub mod error;
// Test and benchmark helpers (feature `fixtures`), documented in the module.
#[cfg(any(test, feature = "fixtures"))]
pub mod fixtures;
pub mod geometry;
pub mod io;
mod model;
pub mod procedural;
pub mod quadric;
pub mod sampling;
pub mod topology;
pub mod transfer;
mod trimesh;

pub use attributes::AttributeKind;
pub use model::Model;
pub use trimesh::{Aabb, TriMesh};

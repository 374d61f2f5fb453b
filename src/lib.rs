//! gng3d: simplify triangle meshes with GNG3D (a Growing Neural Gas) and with Garland–Heckbert
//! quadric error metrics, and measure both honestly side by side.
//!
//! This facade re-exports the workspace crates so one dependency gives the whole toolkit:
//! [`job`] (the one run of every front end: load, clean, simplify, carry the attributes, save),
//! [`mesh`] (mesh type, I/O, topology, sampling), [`gng3d_core`] (GNG3D training and
//! reconstruction), [`qem`] (quadric error metric simplification) and [`metrics`] (paper errors
//! and Metro-style surface distance).
//!
//! ```
//! use gng3d::{job, mesh, metrics};
//! // A built-in model; `job::load(path, &request, &[])?.model` reads OBJ, PLY, STL or glTF instead.
//! let model = mesh::Model::from(mesh::procedural::icosphere(4)); // 2,562 vertices
//! let mut params = metrics::MetricsParams::default();
//! params.hausdorff.samples = Some(20_000);
//! for method in [job::Method::Gng, job::Method::Qem] {
//!     // The run `gng3d simplify --method gng|qem --vertices 600` makes (`job::simplify_file` on files).
//!     let request = job::Request::new(job::Target::Vertices(600)).with_method(method);
//!     let outcome = job::run(&model, &request, &mut ()).unwrap();
//!     assert_eq!(outcome.model.mesh.vertex_count(), 600); // both hold the count here
//!     let e = metrics::evaluate(&model.mesh, &outcome.model.mesh, &params).unwrap();
//!     println!("{method}: E_avg {:.2e}, Hausdorff {:.2e}", e.e_avg, e.hausdorff.max);
//! }
//! ```

pub use gng3d_core;
pub use job;
pub use mesh;
pub use metrics;
pub use qem;

pub mod experiment;
pub mod report;

//! gng3d: simplify triangle meshes with GNG3D (a Growing Neural Gas) and with Garland–Heckbert
//! quadric error metrics, and measure both honestly side by side.
//!
//! This facade re-exports the workspace crates so one dependency gives the whole toolkit:
//! [`mesh`] (mesh type, I/O, topology, sampling), [`gng3d_core`] (GNG3D training and
//! reconstruction), [`qem`] (quadric error metric simplification) and [`metrics`] (paper errors
//! and Metro-style surface distance).
//!
//! ```
//! use gng3d::{gng3d_core, mesh, metrics, qem};
//! // A built-in model; `mesh::io::load(path)?.mesh` reads OBJ, PLY or STL instead.
//! let original = mesh::clean::prepare(&mesh::procedural::icosphere(4)).0; // 2,562 vertices
//! let options = gng3d_core::GngOptions::for_target(gng3d_core::GngTarget::Vertices(600));
//! let gng = gng3d_core::simplify(&original.clone().into(), &options).unwrap(); // GNG3D-Q, as the CLI runs it
//! let qem_params = qem::QemParams::with_target(qem::Target::Vertices(600));
//! let (qem_model, _) = qem::simplify(&mesh::Model::from(original.clone()), &qem_params).unwrap();
//! let qem_mesh = qem_model.mesh;
//! let mut params = metrics::MetricsParams::default();
//! params.hausdorff.samples = Some(20_000);
//! let g = metrics::evaluate(&original, &gng.mesh, &params).unwrap();
//! let q = metrics::evaluate(&original, &qem_mesh, &params).unwrap();
//! assert_eq!(gng.mesh.vertex_count(), 600); // GNG3D holds the vertex count exactly
//! assert_eq!(qem_mesh.vertex_count(), 600);
//! println!("E_avg GNG3D-Q {:.2e} vs QEM {:.2e}", g.e_avg, q.e_avg);
//! println!("Hausdorff GNG3D-Q {:.2e} vs QEM {:.2e}", g.hausdorff.max, q.hausdorff.max);
//! ```

pub use gng3d_core;
pub use job;
pub use mesh;
pub use metrics;
pub use qem;

pub mod experiment;
pub mod report;

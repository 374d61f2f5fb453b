//! One simplification job for every gng3d front end — the CLI's `simplify` and `batch`, the
//! facade's `compare` and `reproduce`, the viewer and Python all call it: load a model, clean
//! it, simplify it with QEM or GNG3D, carry its attributes, save it.
//!
//! - [`Request`]: what a run is asked (method, target, seed, threads, time limit, attribute
//!   policy, the GNG3D variant, QEM's options), with the one table of defaults
//!   ([`DEFAULT_METHOD`], [`DEFAULT_SEED`]) and the one check ([`Request::validate`]).
//! - [`run`] (or [`Job`], to cancel it from another thread): a [`mesh::Model`] in, an
//!   [`Outcome`] out (the output model, a [`Summary`], the warnings); [`GngRun`], GNG3D's run
//!   for a front end that steps the training itself (the viewer).
//! - [`load`], [`save`], [`simplify_file`]: the same on files.
//! - [`Partition`]: a mesh larger than memory, streamed through the `partition` crate (QEM on
//!   positions only) when the request says [`Partition::Auto`]; [`simplify_file`] runs it.
//! - [`batch`]: many files into one folder, a status row each (`gng3d batch`, Python's
//!   `gng3d.batch`).
//!
//! ```
//! use job::{Method, Request, Target};
//! let model = mesh::Model::from(mesh::procedural::icosphere(3)); // 642 vertices
//! for method in [Method::Qem, Method::Gng] {
//!     let request = Request::new(Target::Ratio(0.25)).with_method(method);
//!     let outcome = job::run(&model, &request, &mut ()).unwrap();
//!     assert_eq!(outcome.model.mesh.vertex_count(), 161); // the same count for both
//!     assert!(outcome.warnings.is_empty());
//! }
//! ```

pub mod batch;
mod error;
mod file;
mod gng;
mod partitioned;
mod request;
mod run;
mod summary;

pub use error::{ErrorKind, JobError, Spelling};
pub use file::{FileOutcome, Loaded, check_output, load, save, simplify_file};
pub use gng::GngRun;
pub use partitioned::{
    Partition, PartitionOptions, default_work_dir, dropped_attributes, parse_size, partition_target,
};
pub use request::{
    AttributePolicy, DEFAULT_METHOD, DEFAULT_SEED, GngVariant, MAX_THREADS, Method, Opt,
    QemOptions, Request, Target, parse_placement, parse_shape, parse_signals, placement_name,
    shape_name, signals_name,
};
pub use run::{Job, Observer, Outcome, run};
pub use summary::{PartitionSummary, QemSummary, StepSeconds, Summary, Warning};

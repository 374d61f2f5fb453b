//! [`JobError`]: why a job did not give a model, one type for every front end.

use crate::{Method, Opt};
use std::path::PathBuf;

/// Why a run gave no model. The front ends map it onto their own surface (the CLI's message and
/// exit code, Python's exception types) through [`JobError::kind`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum JobError {
    /// An option's value is out of its range or unknown.
    #[error("{}", option_message(option.keyword(), message))]
    Option {
        /// The option.
        option: Opt,
        /// What is wrong, e.g. "must be in 1 to 256, got 0".
        message: String,
    },
    /// Options that the method does not take.
    #[error("{}", not_for_method(options, *method, Spelling::Keywords))]
    NotForMethod {
        /// The options given.
        options: Vec<Opt>,
        /// The method asked for.
        method: Method,
        /// Why, in words.
        detail: &'static str,
    },
    /// No target was given (or none the method takes).
    #[error(
        "give a target: a vertex count, a share of the vertices, a face count (QEM) or a bound on the error (QEM)"
    )]
    NoTarget,
    /// Reading, cleaning or writing a model failed (the message names the file).
    #[error(transparent)]
    Mesh(#[from] mesh::error::MeshError),
    /// GNG3D could not run or gave no mesh.
    #[error(transparent)]
    Gng(Box<gng3d_core::GngError>),
    /// QEM could not run.
    #[error(transparent)]
    Qem(Box<qem::QemError>),
    /// The method returned a mesh without triangles: nothing is written.
    #[error("{method} produced an empty mesh ({vertices} vertices, no triangles)")]
    EmptyOutput {
        /// The method's label ("QEM", "GNG3D").
        method: &'static str,
        /// Vertices it returned.
        vertices: usize,
    },
    /// The output path cannot take a model (an unknown extension, a folder) or the model has
    /// no triangles: nothing is written.
    #[error("{}: {message}", path.display())]
    Output {
        /// The output path.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// QEM options that the partitioned run does not take.
    #[error("{}", not_with_partition(options, Spelling::Keywords))]
    NotWithPartition {
        /// The options given.
        options: Vec<Opt>,
    },
    /// The partitioned run failed (the message names the file: the input, a chunk of the work
    /// folder, the output).
    #[error(transparent)]
    Partition(Box<partition::PartitionError>),
    /// The run was cancelled.
    #[error("cancelled")]
    Cancelled,
    /// Starting the run's threads failed.
    #[error("starting {threads} threads failed: {message}")]
    Threads {
        /// The count asked for.
        threads: usize,
        /// The system's reason.
        message: String,
    },
}

/// What kind of failure a [`JobError`] is, for front ends that map kinds onto their own error
/// types (Python: `ValueError`, `OSError`, `RuntimeError`, `KeyboardInterrupt`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The request or the input is unusable.
    Invalid,
    /// A file could not be read or written.
    Io,
    /// The run ended without a model.
    Failed,
    /// The run was cancelled.
    Cancelled,
}

impl JobError {
    /// An [`JobError::Option`] error.
    pub fn option(option: Opt, message: impl Into<String>) -> JobError {
        JobError::Option {
            option,
            message: message.into(),
        }
    }

    /// The message with the options spelt as `spelling` spells them ("--time-limit" on the
    /// command line, "time_limit" in Python); [`Display`](std::fmt::Display) uses the keywords.
    pub fn message(&self, spelling: Spelling) -> String {
        let name = |o: &Opt| match spelling {
            Spelling::Flags => o.flag().to_string(),
            Spelling::Keywords => o.keyword().to_string(),
        };
        match self {
            JobError::Option { option, message } => option_message(&name(option), message),
            JobError::NotForMethod {
                options, method, ..
            } => not_for_method(options, *method, spelling),
            JobError::NotWithPartition { options } => not_with_partition(options, spelling),
            e => e.to_string(),
        }
    }

    /// The kind of failure.
    pub fn kind(&self) -> ErrorKind {
        use gng3d_core::GngError as G;
        match self {
            JobError::Mesh(
                mesh::error::MeshError::Io { .. } | mesh::error::MeshError::Write { .. },
            ) => ErrorKind::Io,
            JobError::Cancelled => ErrorKind::Cancelled,
            // A busy work folder is a file in use (OSError in Python).
            JobError::Partition(e)
                if matches!(
                    **e,
                    partition::PartitionError::Io { .. } | partition::PartitionError::Locked { .. }
                ) =>
            {
                ErrorKind::Io
            }
            JobError::Partition(e) if matches!(**e, partition::PartitionError::Qem { .. }) => {
                ErrorKind::Failed
            }
            JobError::Gng(e) if matches!(**e, G::Cancelled) => ErrorKind::Cancelled,
            JobError::Qem(e) if matches!(**e, qem::QemError::Cancelled) => ErrorKind::Cancelled,
            JobError::Gng(e)
                if matches!(
                    **e,
                    G::TooFewNodes { .. } | G::EmptyMesh { .. } | G::Decimation(_)
                ) =>
            {
                ErrorKind::Failed
            }
            JobError::EmptyOutput { .. } | JobError::Threads { .. } => ErrorKind::Failed,
            _ => ErrorKind::Invalid,
        }
    }
}

impl From<gng3d_core::GngError> for JobError {
    fn from(e: gng3d_core::GngError) -> JobError {
        match e {
            gng3d_core::GngError::Cancelled => JobError::Cancelled,
            e => JobError::Gng(Box::new(e)),
        }
    }
}

impl From<qem::QemError> for JobError {
    fn from(e: qem::QemError) -> JobError {
        match e {
            qem::QemError::Cancelled => JobError::Cancelled,
            e => JobError::Qem(Box::new(e)),
        }
    }
}

impl From<partition::PartitionError> for JobError {
    /// A mesh file's problem as [`JobError::Mesh`], the rest in the partition's words (which
    /// name the file).
    fn from(e: partition::PartitionError) -> JobError {
        match e {
            partition::PartitionError::Mesh(e) => JobError::Mesh(e),
            e => JobError::Partition(Box::new(e)),
        }
    }
}

/// How a front end spells options in messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spelling {
    /// Command-line flags (`--time-limit`).
    Flags,
    /// Python keywords (`time_limit`).
    Keywords,
}

/// "NAMES apply to METHOD only" of `options` refused for `method`.
fn not_for_method(options: &[Opt], method: Method, spelling: Spelling) -> String {
    let names = spelled(options, spelling);
    let verb = if names.len() == 1 { "applies" } else { "apply" };
    let only = match (spelling, method.is_gng()) {
        (Spelling::Flags, true) => "QEM only (--method qem)",
        (Spelling::Flags, false) => "--method gng only (or --method paper)",
        (Spelling::Keywords, true) => "method 'qem' only",
        (Spelling::Keywords, false) => "method 'gng' and 'paper' only, not 'qem'",
    };
    format!("{} {verb} to {only}", and_list(&names))
}

/// "NAMES do not apply with the partition" of `options` refused for a partitioned run.
fn not_with_partition(options: &[Opt], spelling: Spelling) -> String {
    let names = spelled(options, spelling);
    let with = match spelling {
        Spelling::Flags => "--partition auto",
        Spelling::Keywords => "partition='auto'",
    };
    let verb = if names.len() == 1 { "does" } else { "do" };
    format!(
        "{} {verb} not apply with {with}: the partitioned simplification is QEM to a size target, on positions, with the default options",
        and_list(&names)
    )
}

/// The names of `options` as the front end spells them.
fn spelled(options: &[Opt], spelling: Spelling) -> Vec<String> {
    options
        .iter()
        .map(|o| match spelling {
            Spelling::Flags => o.flag().to_string(),
            Spelling::Keywords => o.keyword().to_string(),
        })
        .collect()
}

/// "NAME must be ..." or "NAME: what".
fn option_message(name: &str, message: &str) -> String {
    if message.starts_with("must") {
        format!("{name} {message}")
    } else {
        format!("{name}: {message}")
    }
}

/// "a, b and c".
fn and_list(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

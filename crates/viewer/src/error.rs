//! The viewer's error type: every fallible operation of the session, the I/O helpers and the
//! window returns [`ViewerError`], whose message names the file or option and the problem.

use std::path::PathBuf;

/// What went wrong in the viewer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ViewerError {
    /// A command-line or UI option is out of range (checked before anything starts).
    #[error("invalid option {option}: {problem}")]
    InvalidOption {
        /// The option as the user spells it (e.g. `--time-limit`).
        option: &'static str,
        /// What is wrong with the value.
        problem: String,
    },
    /// A mesh file could not be read or has nothing to simplify.
    #[error("{}: {message}", path.display())]
    Load {
        /// The file.
        path: PathBuf,
        /// The loader's message.
        message: String,
    },
    /// A file could not be written (mesh export, CSV, screenshot).
    #[error("{}: {message}", path.display())]
    Save {
        /// The file.
        path: PathBuf,
        /// What failed.
        message: String,
    },
    /// Nothing to export yet on that side.
    #[error("{}: nothing to export yet ({what})", path.display())]
    NothingToExport {
        /// The requested file.
        path: PathBuf,
        /// Which result is missing.
        what: &'static str,
    },
    /// GNG3D could not start or reconstruct.
    #[error("GNG3D: {0}")]
    Gng(String),
    /// QEM failed.
    #[error("QEM: {0}")]
    Qem(String),
    /// A simplified mesh could not be measured.
    #[error("metrics: {0}")]
    Metrics(String),
    /// A background job ended without an answer (its thread panicked).
    #[error("background job {0} ended without a result")]
    JobLost(&'static str),
    /// The window could not be opened (no usable graphics adapter, no display).
    #[error("could not open the viewer window: {0}")]
    Window(String),
}

/// Shorthand for results of the viewer.
pub type Result<T, E = ViewerError> = std::result::Result<T, E>;

//! Experiment reports: plots and tables written by `compare` and `reproduce`.

pub mod compare;
pub mod paper;
pub mod plot;
pub mod table;

/// Why a report file could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Writing a file (or creating its folder) failed.
    #[error(transparent)]
    Write(#[from] mesh::error::MeshError),
    /// A folder could not be created.
    #[error("cannot create folder {path}: {source}")]
    Folder {
        /// The folder.
        path: std::path::PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Encoding a table as CSV failed.
    #[error("CSV: {0}")]
    Csv(String),
    /// Drawing or encoding a chart failed.
    #[error("plot {path}: {message}")]
    Plot {
        /// The chart file.
        path: std::path::PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Serialising a report as JSON failed.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
}

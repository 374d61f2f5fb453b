//! [`Summary`]: what a run did, as every front end reports it (the CLI's `--json` and its
//! one-line summary, Python's `report`, the batch's rows).

use serde::Serialize;
use serde_json::Value;

/// A warning in a summary: a machine-readable kind and its sentence.
#[derive(Debug, Clone, Serialize)]
pub struct Warning {
    /// What kind (e.g. `target_not_reached`).
    pub kind: &'static str,
    /// The sentence.
    pub message: String,
}

/// QEM's summary: counts, seconds, the library's report and the warnings.
#[derive(Debug, Clone, Serialize)]
pub struct QemSummary {
    /// `qem`.
    pub method: &'static str,
    /// Output vertices.
    pub vertices: usize,
    /// Output faces.
    pub faces: usize,
    /// Wall time of the simplification, seconds (loading, cleaning and saving excluded).
    pub seconds: f64,
    /// The library's report (collapses, largest error, stop reason, ...).
    pub report: qem::QemReport,
    /// Why the output differs from the request (a target not reached).
    pub warnings: Vec<Warning>,
}

/// What a run did: GNG3D's summary or QEM's, serialised with their fields at the top level.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
#[non_exhaustive]
pub enum Summary {
    /// A GNG3D run.
    Gng(Box<gng3d_core::GngSummary>),
    /// A QEM run.
    Qem(Box<QemSummary>),
}

impl Summary {
    /// The method's name (`qem`, `gng`, `paper`).
    pub fn method(&self) -> &'static str {
        match self {
            Summary::Gng(s) => s.method,
            Summary::Qem(s) => s.method,
        }
    }

    /// Vertices and faces of the mesh the run was given (after welding and cleaning).
    pub fn input_counts(&self) -> (usize, usize) {
        match self {
            Summary::Gng(s) => (s.input_vertices, s.input_faces),
            Summary::Qem(s) => (s.report.input_vertices, s.report.input_faces),
        }
    }

    /// Vertices and faces of the output.
    pub fn counts(&self) -> (usize, usize) {
        match self {
            Summary::Gng(s) => (s.vertices, s.faces),
            Summary::Qem(s) => (s.vertices, s.faces),
        }
    }

    /// Wall time of the run, seconds (loading and saving excluded).
    pub fn seconds(&self) -> f64 {
        match self {
            Summary::Gng(s) => s.seconds,
            Summary::Qem(s) => s.seconds,
        }
    }

    /// The summary as JSON, each warning with its sentence as `message` (`warnings`: the run's
    /// sentences, in the order of the summary's warnings).
    pub fn to_json(&self, warnings: &[String]) -> Value {
        let mut value = serde_json::to_value(self).unwrap_or(Value::Null);
        if let Some(Value::Array(list)) = value.get_mut("warnings") {
            for (w, m) in list.iter_mut().zip(warnings) {
                if let Value::Object(fields) = w {
                    fields
                        .entry("message")
                        .or_insert_with(|| Value::String(m.clone()));
                }
            }
        }
        value
    }
}

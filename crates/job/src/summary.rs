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

/// The partitioned run's summary (`--partition auto`): counts, the cells, seconds per step.
#[derive(Debug, Clone, Serialize)]
#[non_exhaustive]
pub struct PartitionSummary {
    /// `qem`.
    pub method: &'static str,
    /// `auto`.
    pub partition: &'static str,
    /// Vertex records and triangles of the input (not welded).
    pub input_vertices: usize,
    /// Triangles of the input.
    pub input_faces: usize,
    /// Output vertices.
    pub vertices: usize,
    /// Output faces.
    pub faces: usize,
    /// Wall time of the whole run, seconds (the output's writing included).
    pub seconds: f64,
    /// Cells with faces.
    pub cells: usize,
    /// Cells found finished by an earlier run and not redone.
    pub cells_resumed: usize,
    /// Vertices on the cells' borders (locked in the cells).
    pub shared_vertices: usize,
    /// Faces of the stitched cells before the final pass.
    pub stitched_faces: usize,
    /// Seconds of each step: `partition` (0 when an earlier run's was reused), `cells`,
    /// `finish` (stitch, final pass, writing).
    pub step_seconds: StepSeconds,
    /// The work folder.
    pub work_dir: std::path::PathBuf,
    /// Why the output differs from the request (attributes dropped, a target not reached).
    pub warnings: Vec<Warning>,
}

/// Seconds of the partitioned run's steps.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StepSeconds {
    /// The streaming partition.
    pub partition: f64,
    /// The cells.
    pub cells: f64,
    /// Stitch, final pass and writing.
    pub finish: f64,
}

impl PartitionSummary {
    pub(crate) fn new(
        report: &partition::PartitionReport,
        seconds: f64,
        work_dir: std::path::PathBuf,
        warnings: Vec<Warning>,
    ) -> PartitionSummary {
        PartitionSummary {
            method: "qem",
            partition: "auto",
            input_vertices: report.input_vertices,
            input_faces: report.input_faces,
            vertices: report.vertices,
            faces: report.faces,
            seconds,
            cells: report.cells,
            cells_resumed: report.cells_resumed,
            shared_vertices: report.shared_vertices,
            stitched_faces: report.stitched_faces,
            step_seconds: StepSeconds {
                partition: report.seconds[0],
                cells: report.seconds[1],
                finish: report.seconds[2],
            },
            work_dir,
            warnings,
        }
    }
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
    /// A partitioned QEM run.
    Partition(Box<PartitionSummary>),
}

impl Summary {
    /// The method's name (`qem`, `gng`, `paper`).
    pub fn method(&self) -> &'static str {
        match self {
            Summary::Gng(s) => s.method,
            Summary::Qem(s) => s.method,
            Summary::Partition(s) => s.method,
        }
    }

    /// Vertices and faces of the mesh the run was given (after welding and cleaning).
    pub fn input_counts(&self) -> (usize, usize) {
        match self {
            Summary::Gng(s) => (s.input_vertices, s.input_faces),
            Summary::Qem(s) => (s.report.input_vertices, s.report.input_faces),
            Summary::Partition(s) => (s.input_vertices, s.input_faces),
        }
    }

    /// Vertices and faces of the output.
    pub fn counts(&self) -> (usize, usize) {
        match self {
            Summary::Gng(s) => (s.vertices, s.faces),
            Summary::Qem(s) => (s.vertices, s.faces),
            Summary::Partition(s) => (s.vertices, s.faces),
        }
    }

    /// Wall time of the run, seconds (loading and saving excluded).
    pub fn seconds(&self) -> f64 {
        match self {
            Summary::Gng(s) => s.seconds,
            Summary::Qem(s) => s.seconds,
            Summary::Partition(s) => s.seconds,
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

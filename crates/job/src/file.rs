//! The job on files: [`load`] (read, check the outputs against the input's files, apply the
//! attribute policy, weld and clean), [`save`] (checked, read back, atomic) and
//! [`simplify_file`], the whole job in one call — `gng3d simplify`, Python's `simplify_file` and
//! every batch row.

use crate::{AttributePolicy, JobError, Observer, Outcome, Request};
use mesh::Model;
use mesh::error::MeshWarning;
use mesh::io::{Format, KeptAttributes};
use std::path::Path;

/// A model as a run takes it, and what loading it said.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The model, welded and cleaned (unless the request says not to), its attributes
    /// following (none when the request drops them).
    pub model: Model,
    /// The loader's warnings (repairs, references refused, values reinterpreted, ...).
    pub warnings: Vec<MeshWarning>,
    /// Vertex records of the file, as stored.
    pub file_vertices: usize,
    /// Triangles of the file, as stored (polygons triangulated).
    pub file_faces: usize,
}

/// Check that `path` can take a model: a known extension, not a folder, a folder that takes
/// new files. Front ends call it before loading anything, so a typo costs nothing.
pub fn check_output(path: &Path) -> Result<Format, JobError> {
    let format = Format::from_path(path).ok_or_else(|| JobError::Output {
        path: path.to_path_buf(),
        message: "unknown output format (expected .obj, .ply, .stl, .gltf or .glb)".into(),
    })?;
    if path.is_dir() {
        return Err(JobError::Output {
            path: path.to_path_buf(),
            message: "is a folder, not a mesh file".into(),
        });
    }
    mesh::io::check_writable(path)?;
    Ok(format)
}

/// Load `path` for `request`: refuse `outputs` (every file the run will write) that would
/// replace the input or a file it reads (`LoadedMesh::check_outputs`), keep or drop the
/// attributes by [`Request::attributes`], weld and clean by [`Request::weld`]
/// (`mesh::clean::prepare`, the attributes following).
pub fn load(path: &Path, request: &Request, outputs: &[&Path]) -> Result<Loaded, JobError> {
    let mut loaded = mesh::io::load(path)?;
    loaded.check_outputs(outputs)?;
    let (file_vertices, file_faces) = (loaded.mesh.vertex_count(), loaded.mesh.face_count());
    let warnings = std::mem::take(&mut loaded.warnings);
    let model = match request.attributes {
        AttributePolicy::Keep => Model::from(loaded),
        AttributePolicy::Drop => Model::from(loaded).without_attributes(),
    };
    Ok(Loaded {
        model: if request.weld {
            mesh::clean::prepare(&model).0
        } else {
            model
        },
        warnings,
        file_vertices,
        file_faces,
    })
}

/// Write `model` to `path` (format by extension) with the mesh crate's one checked writer
/// (`mesh::io::save`: read back before it replaces anything, atomic,
/// a `.gltf` with its `<stem>.bin`, an OBJ's material files and a glTF's images copied beside
/// it). A model without triangles is an error and nothing is written. What the format cannot
/// keep is in the returned report's `dropped`.
pub fn save(model: &Model, path: &Path) -> Result<KeptAttributes, JobError> {
    check_output(path)?;
    if model.mesh.face_count() == 0 {
        return Err(JobError::Output {
            path: path.to_path_buf(),
            message: format!(
                "the model has no triangles ({} vertices); nothing written",
                model.mesh.vertex_count()
            ),
        });
    }
    Ok(mesh::io::save(model, path)?)
}

/// Whether `a` and `b` name the same file.
fn same_file(a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
}

/// A file simplified into another.
#[derive(Debug, Clone)]
pub struct FileOutcome {
    /// The run's outcome (its model is what was written).
    pub outcome: Outcome,
    /// What the output kept of the input's attributes.
    pub kept: KeptAttributes,
    /// Vertex records and triangles of the input file, as stored.
    pub file_counts: (usize, usize),
}

impl FileOutcome {
    /// The summary as JSON with the `attributes` object (`gng3d simplify --json`).
    pub fn to_json(&self) -> serde_json::Value {
        let mut value = self.outcome.summary.to_json(&self.outcome.warnings);
        if let serde_json::Value::Object(fields) = &mut value {
            fields.insert(
                "attributes".into(),
                serde_json::to_value(&self.kept).unwrap_or(serde_json::Value::Null),
            );
        }
        value
    }
}

/// The whole job: check the request and the output path, [`load`] `input` (its warnings go to
/// `on_loaded` before the run), [`crate::run`], [`save`] to `output`.
pub fn simplify_file(
    input: &Path,
    output: &Path,
    request: &Request,
    on_loaded: impl FnOnce(&[MeshWarning]),
    observer: &mut dyn Observer,
) -> Result<FileOutcome, JobError> {
    request.validate()?;
    check_output(output)?;
    if let crate::Partition::Auto(options) = &request.partition {
        if input.exists() && output.exists() && same_file(input, output) {
            return Err(JobError::Output {
                path: output.to_path_buf(),
                message: "is the input; choose another output".into(),
            });
        }
        return crate::partitioned::simplify_file(input, output, request, options, observer);
    }
    let loaded = load(input, request, &[output])?;
    on_loaded(&loaded.warnings);
    let outcome = crate::run(&loaded.model, request, observer)?;
    let kept = save(&outcome.model, output)?;
    Ok(FileOutcome {
        outcome,
        kept,
        file_counts: (loaded.file_vertices, loaded.file_faces),
    })
}

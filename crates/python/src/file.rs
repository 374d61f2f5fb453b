//! Mesh files with their attributes: what `gng3d.load` leaves out (named in its warning), and
//! the loading and writing around `gng3d.simplify_file`, as `gng3d simplify` does them
//! (crates/cli/src/cli/simplify/attributes.rs): the attributes and materials loaded with the
//! mesh, welded with it, and written where the output format stores them, with a warning for
//! what it does not.

use mesh::TriMesh;
use mesh::attributes::{Attributes, Materials};
use mesh::error::MeshError;
use mesh::io::{Format, LoadedMesh};
use std::path::Path;

/// What `load` (positions and triangles only) leaves out of `loaded`, in words ("texture
/// coordinates and 1 material"), or `None` when the file holds nothing else.
pub fn not_returned(loaded: &LoadedMesh) -> Option<String> {
    let names = loaded
        .attributes
        .as_ref()
        .map(Attributes::names)
        .unwrap_or_default();
    let mut words: Vec<String> = Vec::new();
    for name in names {
        words.push(match name {
            "normals" => "normals".into(),
            "uv0" => "texture coordinates".into(),
            "uv1" => "a second set of texture coordinates".into(),
            "colors" => "colours".into(),
            "materials" => match loaded.materials.as_ref().map_or(0, |m| m.names.len()) {
                0 => "materials".into(),
                1 => "1 material".into(),
                n => format!("{n} materials"),
            },
            other => other.into(),
        });
    }
    match words.as_slice() {
        [] => None,
        [one] => Some(one.clone()),
        [rest @ .., last] => Some(format!("{} and {last}", rest.join(", "))),
    }
}

/// A file's mesh for a run: welded and cleaned as the CLI prepares what it loads
/// (`mesh::clean::prepare_with_attributes` with attributes) unless `weld` is false, with the
/// attributes (when the file has any) following the mesh.
pub fn prepare(loaded: LoadedMesh, weld: bool) -> (TriMesh, Option<Attributes>) {
    let attributes = loaded.attributes.filter(|a| !a.is_empty());
    match (weld, attributes) {
        (false, attributes) => (loaded.mesh, attributes),
        (true, Some(a)) => {
            let (mesh, a, _) = mesh::clean::prepare_with_attributes(&loaded.mesh, &a);
            (mesh, Some(a))
        }
        (true, None) => (mesh::clean::prepare(&loaded.mesh).0, None),
    }
}

/// What writing an output did with the input's attributes: the `"attributes"` object of
/// `gng3d simplify --json`.
#[derive(Debug, Default, serde::Serialize)]
pub struct Kept {
    /// Attributes of the input (`normals`, `uv0`, `uv1`, `colors`, `materials`).
    pub input: Vec<&'static str>,
    /// Attributes written to the output (read back from what was written).
    pub kept: Vec<&'static str>,
    /// What was not written or not copied, one sentence each (also a warning).
    pub dropped: Vec<String>,
}

/// Writes `simplified` with `attributes` and `materials` to `path` (`format`) atomically: the
/// bytes are encoded (`mesh::io::encode_with_attributes`), read back, then written, and the
/// input's material libraries and textures (OBJ) or images (glTF) copied next to it. An
/// attribute that does not read back and that no warning of the encoder names gets a sentence
/// of its own: nothing is dropped silently.
pub fn save(
    simplified: &TriMesh,
    attributes: Option<&Attributes>,
    materials: Option<&Materials>,
    path: &Path,
    format: Format,
) -> Result<Kept, MeshError> {
    let Some(attributes) = attributes else {
        mesh::io::save(simplified, path)?;
        return Ok(Kept::default());
    };
    let (bytes, warnings) =
        mesh::io::encode_with_attributes(simplified, attributes, materials, format, path)?;
    let mut dropped: Vec<String> = warnings.iter().map(ToString::to_string).collect();
    let reread = mesh::io::load_bytes(&bytes, format, path)?;
    if reread.mesh.face_count() == 0 {
        return Err(MeshError::Write {
            path: path.to_path_buf(),
            message: "the output reads back without faces; nothing written".into(),
        });
    }
    let back = reread
        .attributes
        .as_ref()
        .map(Attributes::names)
        .unwrap_or_default();
    let input = attributes.names();
    let (kept, lost): (Vec<&'static str>, Vec<&'static str>) =
        input.iter().copied().partition(|n| back.contains(n));
    for name in lost {
        if !dropped.iter().any(|w| w.contains(name)) {
            dropped.push(format!(
                "{name} not kept: the output does not read back with it"
            ));
        }
    }
    mesh::io::write_atomic(path, &bytes)?;
    if attributes.face_material.is_some()
        && let Some(m) = materials
    {
        let copied = match format {
            Format::Obj => mesh::io::copy_material_files(m, path),
            Format::Gltf | Format::Glb => mesh::io::copy_gltf_images(m, path),
            Format::Ply | Format::Stl => Vec::new(),
        };
        dropped.extend(copied.iter().map(ToString::to_string));
    }
    Ok(Kept {
        input,
        kept,
        dropped,
    })
}

//! Mesh files with their attributes: what `gng3d.load` leaves out (named in its warning), and
//! the loading and writing around `gng3d.simplify_file`, as `gng3d simplify` does them
//! (crates/cli/src/cli/simplify/attributes.rs): the attributes and materials loaded with the
//! mesh, welded with it, and written where the output format stores them, with a warning for
//! what it does not.

use mesh::TriMesh;
use mesh::attributes::{Attributes, Materials};
use mesh::error::MeshError;
use mesh::io::LoadedMesh;
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
/// (`mesh::clean::prepare_with_optional_attributes`) unless `weld` is false, with the
/// attributes (when the file has any) following the mesh.
pub fn prepare(loaded: LoadedMesh, weld: bool) -> (TriMesh, Option<Attributes>) {
    let attributes = loaded.attributes.filter(|a| !a.is_empty());
    if weld {
        let (mesh, a, _) =
            mesh::clean::prepare_with_optional_attributes(&loaded.mesh, attributes.as_ref());
        (mesh, a)
    } else {
        (loaded.mesh, attributes)
    }
}

/// What writing an output did with the input's attributes: the `"attributes"` object of
/// `gng3d simplify --json`.
pub type Kept = mesh::io::KeptAttributes;

/// Writes `simplified` with `attributes` and `materials` to `path` (format by extension) as
/// `gng3d simplify` does, through the mesh crate's one checked writer
/// (`mesh::io::save_with_attributes`, or `mesh::io::save` without attributes, as `gng3d.save`
/// writes): encoded, read back, refused with nothing written when it does not load, holds no
/// face or lacks an attribute the format stores, written atomically (a `.gltf` with its
/// `<stem>.bin`), the input's material files or images copied next to it.
pub fn save(
    simplified: &TriMesh,
    attributes: Option<&Attributes>,
    materials: Option<&Materials>,
    path: &Path,
) -> Result<Kept, MeshError> {
    match attributes {
        Some(a) => mesh::io::save_with_attributes(simplified, a, materials, path),
        None => mesh::io::save(simplified, path).map(|()| Kept::default()),
    }
}

//! Mesh files with their attributes: what `gng3d.load` leaves out (named in its warning), and
//! the loading around `gng3d.simplify_file`, as `gng3d simplify` does it
//! (crates/cli/src/cli/simplify/attributes.rs): the attributes loaded with the mesh and welded
//! with it. The output is written by the mesh crate's one checked writer
//! (`mesh::io::save_with_optional_attributes`), as the CLI writes it.

use mesh::TriMesh;
use mesh::attributes::Attributes;
use mesh::io::LoadedMesh;

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

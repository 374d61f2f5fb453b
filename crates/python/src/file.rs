//! Mesh files with their attributes: what `gng3d.load` leaves out, named in its warning
//! (`gng3d.simplify_file` keeps them, through the job's load and save).

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

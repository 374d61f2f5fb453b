//! Mesh files with their attributes: what `gng3d.load` leaves out, named in its warning
//! (`gng3d.simplify_file` keeps them, through the job's load and save).

use mesh::AttributeKind;
use mesh::attributes::Attributes;
use mesh::io::LoadedMesh;

/// What `load` (positions and triangles only) leaves out of `loaded`, in words ("texture
/// coordinates and 1 material"), or `None` when the file holds nothing else.
pub fn not_returned(loaded: &LoadedMesh) -> Option<String> {
    let kinds = loaded
        .attributes
        .as_ref()
        .map(Attributes::kinds)
        .unwrap_or_default();
    let mut words: Vec<String> = Vec::new();
    for kind in kinds {
        words.push(match kind {
            AttributeKind::Uv0 => "texture coordinates".into(),
            AttributeKind::Uv1 => "a second set of texture coordinates".into(),
            AttributeKind::Colors => "colours".into(),
            AttributeKind::Materials => {
                match loaded.materials.as_ref().map_or(0, |m| m.names.len()) {
                    0 => "materials".into(),
                    1 => "1 material".into(),
                    n => format!("{n} materials"),
                }
            }
            other => other.to_string(),
        });
    }
    match words.as_slice() {
        [] => None,
        [one] => Some(one.clone()),
        [rest @ .., last] => Some(format!("{} and {last}", rest.join(", "))),
    }
}

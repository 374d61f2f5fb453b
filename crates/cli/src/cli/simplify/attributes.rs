//! Normals, texture coordinates, colours and materials through `gng3d simplify`: loaded with
//! the mesh, kept by QEM (`qem::simplify_with_attributes`) and given to GNG3D's output from the
//! original surface (`mesh::transfer::transfer_attributes`), written where the output format
//! stores them; what is not written is a warning and is named in `--json` (`"attributes"`), and
//! an output that does not read back with what it was said to keep is an error, not exit 0.

use mesh::TriMesh;
use mesh::attributes::{Attributes, Materials};
use serde::Serialize;
use std::path::Path;

/// What a run's input has besides positions and triangles.
pub(crate) struct Extras {
    /// The attributes of the input mesh's corners, when the file has any.
    pub(crate) attributes: Option<Attributes>,
    /// The materials the file names.
    pub(crate) materials: Option<Materials>,
    /// Where the positions' origin lies in the file's coordinates (`LoadedMesh::origin`),
    /// added back when the output is written.
    pub(crate) origin: glam::DVec3,
}

/// What a run did with the input's attributes: the `"attributes"` object of `--json`.
pub(crate) type Kept = mesh::io::KeptAttributes;

/// Load `path` (warnings on stderr) and clean it as `load_input` does (weld, degenerate and
/// duplicate faces, unreferenced vertices), the attributes following (`raw`: as stored).
/// `outputs` (every file the run will write) are refused before any work when a write would
/// replace the input or a file it reads (`LoadedMesh::check_outputs`).
pub(crate) fn load(path: &Path, raw: bool, outputs: &[&Path]) -> anyhow::Result<(TriMesh, Extras)> {
    crate::process::working_on(path);
    let loaded = mesh::io::load(path)?;
    loaded.check_outputs(outputs)?;
    for w in &loaded.warnings {
        eprintln!("warning: {}: {w}", path.display());
    }
    let attributes = loaded.attributes.filter(|a| !a.is_empty());
    let materials = loaded.materials;
    let origin = loaded.origin;
    if raw {
        return Ok((
            loaded.mesh,
            Extras {
                attributes,
                materials,
                origin,
            },
        ));
    }
    let (mesh, attributes, _) =
        mesh::clean::prepare_with_optional_attributes(&loaded.mesh, attributes.as_ref());
    Ok((
        mesh,
        Extras {
            attributes,
            materials,
            origin,
        },
    ))
}

/// QEM on `input`, keeping its attributes when it has any; with `lock_border` the vertices on
/// the input's border edges are never contracted.
pub(crate) fn simplify_qem(
    input: &TriMesh,
    extras: &Extras,
    params: &qem::QemParams,
    lock_border: bool,
) -> Result<(TriMesh, Option<Attributes>, qem::QemReport), qem::QemError> {
    if lock_border {
        let locked = qem::border_vertices(input);
        return qem::simplify_locked(input, extras.attributes.as_ref(), params, &locked);
    }
    match &extras.attributes {
        Some(a) => qem::simplify_with_attributes(input, a, params)
            .map(|(mesh, a, report)| (mesh, Some(a), report)),
        None => qem::simplify(input, params).map(|(mesh, report)| (mesh, None, report)),
    }
}

/// The input's attributes for `simplified` (any mesh near the input, e.g. GNG3D's), from the
/// closest points of the input's surface.
pub(crate) fn transfer(
    input: &TriMesh,
    extras: &Extras,
    simplified: &TriMesh,
) -> Option<Attributes> {
    extras
        .attributes
        .as_ref()
        .map(|a| mesh::transfer::transfer_attributes(input, a, simplified))
}

/// Write `simplified` with `attributes` to `path` (`crate::cli::save_output`: checked, read
/// back, atomic; the input's material files copied next to an OBJ output and a glTF input's
/// image files next to a glTF output; a `.gltf` with its `<stem>.bin`). Warnings for what the
/// format cannot keep go to stderr and into the returned [`Kept`].
pub(crate) fn save(
    simplified: &TriMesh,
    attributes: Option<&Attributes>,
    extras: &Extras,
    path: &Path,
    method: &str,
) -> anyhow::Result<Kept> {
    crate::cli::save_output(
        simplified,
        attributes,
        extras.materials.as_ref(),
        extras.origin,
        path,
        method,
    )
}

/// `summary` with the `"attributes"` object added, for `--json`.
#[derive(Serialize)]
pub(crate) struct WithAttributes<'a, T: Serialize> {
    /// The method's summary, its fields at the top level.
    #[serde(flatten)]
    pub(crate) summary: &'a T,
    /// What was kept.
    pub(crate) attributes: &'a Kept,
}

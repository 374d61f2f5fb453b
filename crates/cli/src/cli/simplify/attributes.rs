//! Normals, texture coordinates, colours and materials through `gng3d simplify`: loaded with
//! the mesh, kept by QEM (`qem::simplify_with_attributes`) and given to GNG3D's output from the
//! original surface (`mesh::transfer::transfer_attributes`), written where the output format
//! stores them; what is not written is a warning and is named in `--json` (`"attributes"`), and
//! an output that does not read back with what it was said to keep is an error, not exit 0.

use anyhow::Context;
use mesh::TriMesh;
use mesh::attributes::{Attributes, Materials};
use mesh::io::Format;
use serde::Serialize;
use std::path::Path;

/// What a run's input has besides positions and triangles.
pub(crate) struct Extras {
    /// The attributes of the input mesh's corners, when the file has any.
    pub(crate) attributes: Option<Attributes>,
    /// The materials the file names.
    pub(crate) materials: Option<Materials>,
}

/// What a run did with the input's attributes: the `"attributes"` object of `--json`.
#[derive(Debug, Default, Serialize)]
pub(crate) struct Kept {
    /// Attributes of the input (`normals`, `uv0`, `uv1`, `colors`, `materials`).
    pub(crate) input: Vec<&'static str>,
    /// Attributes written to the output.
    pub(crate) kept: Vec<&'static str>,
    /// Attributes not written, each with why (also a warning on stderr).
    pub(crate) dropped: Vec<String>,
}

/// Load `path` (warnings on stderr) and clean it as `load_input` does (weld, degenerate and
/// duplicate faces, unreferenced vertices), the attributes following (`raw`: as stored).
pub(crate) fn load(path: &Path, raw: bool) -> anyhow::Result<(TriMesh, Extras)> {
    crate::process::working_on(path);
    let loaded = mesh::io::load(path)?;
    for w in &loaded.warnings {
        eprintln!("warning: {}: {w}", path.display());
    }
    let attributes = loaded.attributes.filter(|a| !a.is_empty());
    let materials = loaded.materials;
    if raw {
        return Ok((
            loaded.mesh,
            Extras {
                attributes,
                materials,
            },
        ));
    }
    Ok(match attributes {
        Some(a) => {
            let (mesh, attributes, _) = mesh::clean::prepare_with_attributes(&loaded.mesh, &a);
            let attributes = Some(attributes);
            (
                mesh,
                Extras {
                    attributes,
                    materials,
                },
            )
        }
        None => (
            mesh::clean::prepare(&loaded.mesh).0,
            Extras {
                attributes: None,
                materials,
            },
        ),
    })
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

/// Whether `format` stores attribute `name`.
fn stores(format: Format, name: &str) -> bool {
    match format {
        Format::Stl => false,
        Format::Obj => name != "uv1",
        Format::Ply => matches!(name, "normals" | "uv0" | "colors"),
        Format::Gltf | Format::Glb => true,
    }
}

/// Write `simplified` with `attributes` to `path` as `crate::cli::save_checked` writes a mesh
/// (checked, read back, atomic), copying the input's material files next to an OBJ output and
/// a glTF input's image files next to a glTF output (a `.gltf` holds its buffer as a `data:` URI).
/// Warnings for what the format cannot keep go to stderr and into the returned [`Kept`].
pub(crate) fn save(
    simplified: &TriMesh,
    attributes: Option<&Attributes>,
    extras: &Extras,
    path: &Path,
    method: &str,
) -> anyhow::Result<Kept> {
    let Some(attributes) = attributes else {
        crate::cli::save_checked(simplified, path, method)?;
        return Ok(Kept::default());
    };
    let format = crate::cli::check_output_mesh_path(path)?;
    if simplified.face_count() == 0 {
        anyhow::bail!(
            "{method} produced an empty mesh ({} vertices, no triangles); nothing written to {}",
            simplified.vertex_count(),
            path.display()
        );
    }
    let (bytes, warnings) = mesh::io::encode_with_attributes(
        simplified,
        attributes,
        extras.materials.as_ref(),
        format,
        path,
    )?;
    let names = attributes.names();
    let kept: Vec<&'static str> = names
        .iter()
        .copied()
        .filter(|n| stores(format, n))
        .collect();
    // The output must read back with every attribute it is said to keep.
    let reread = mesh::io::load_bytes(&bytes, format, path).with_context(|| {
        format!(
            "{method} produced a mesh the loader refuses; nothing written to {}",
            path.display()
        )
    })?;
    let back = reread
        .attributes
        .as_ref()
        .map(Attributes::names)
        .unwrap_or_default();
    if reread.mesh.face_count() == 0 || kept.iter().any(|n| !back.contains(n)) {
        anyhow::bail!(
            "{method}'s output does not read back with {}; nothing written to {}",
            kept.join(", "),
            path.display()
        );
    }
    mesh::io::write_atomic(path, &bytes)?;
    let mut all = warnings;
    if attributes.face_material.is_some()
        && let Some(m) = &extras.materials
    {
        match format {
            Format::Obj => all.extend(mesh::io::copy_material_files(m, path)),
            Format::Gltf | Format::Glb => all.extend(mesh::io::copy_gltf_images(m, path)),
            Format::Ply | Format::Stl => {}
        }
    }
    for w in &all {
        eprintln!("warning: {}: {w}", path.display());
    }
    Ok(Kept {
        input: names.clone(),
        kept,
        dropped: all.iter().map(ToString::to_string).collect(),
    })
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

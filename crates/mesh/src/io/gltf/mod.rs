//! glTF 2.0 reader and writer: `.gltf` (JSON with external `.bin` buffers or `data:` URIs) and
//! `.glb` (binary container).
//!
//! Reading: the JSON document is parsed and validated by the `gltf` crate (every index a glTF
//! object uses refers to an object that exists); the GLB container, the buffers and the accessors
//! are read here, every byte range checked, so a broken file is an error naming it and never a
//! panic. Every triangle primitive of every mesh that the default scene's nodes instance (the
//! first scene when none is the default; every mesh once when there is no scene) is placed in
//! world space and joined into one mesh. A glTF vertex is one wedge ([`Attributes`]); the
//! vertices become position vertices through the weld ([`crate::clean::weld_exact_map`]), so
//! a UV or normal seam is two wedges of one vertex and touching sheets stay apart.
//!
//! Writing: one mesh, one node, one primitive per material, all sharing one set of vertex
//! accessors (one glTF vertex per wedge). What is not geometry (materials, textures, images,
//! samplers, the asset record and the extensions they use) comes from the input glTF
//! ([`GltfAssets`]) unchanged.
//!
//! The reader's steps, one file each: the GLB container ([`glb`]), the buffers and accessors
//! ([`buffers`]), the meshes and nodes ([`meshes`]), the materials and images ([`assets`]); the
//! writer is [`write`], the URIs both use are in [`uri`].

mod assets;
mod buffers;
mod glb;
mod meshes;
mod uri;
mod write;

pub use crate::attributes::gltf_assets::GltfAssets;
pub(crate) use assets::copy_images;
pub(in crate::io) use assets::{image_files, read_image_file};
pub(crate) use buffers::SideBuffer;
pub(in crate::io) use uri::{data_uri, percent_decode, percent_encode, relative_uri};
pub(crate) use write::{BufferStorage, write};

use super::RawMesh;
use crate::TriMesh;
use crate::attributes::{Attributes, Materials};
use crate::error::{MeshError, MeshWarning};
use assets::{carry, material_names};
use buffers::Source;
use glam::DVec3;
use serde_json::Value;
use std::path::Path;
#[cfg(test)]
use {
    glam::{Vec2, Vec3, Vec4},
    serde_json::json,
    std::{path::PathBuf, sync::Arc},
    uri::{base64_decode, base64_encode},
};

/// Extensions that compress the geometry, which this reader does not decode.
const COMPRESSION: &[&str] = &[
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
    "KHR_meshopt_compression",
];

/// Extensions that place or repeat the geometry, which this reader does not apply.
const GEOMETRY: &[&str] = &["EXT_mesh_gpu_instancing"];

/// Required extensions this reader implements (quantised attributes) or carries to a glTF
/// output unchanged (material and texture extensions), by name or prefix.
const UNDERSTOOD: &[&str] = &[
    "KHR_mesh_quantization",
    "KHR_materials_",
    "KHR_texture_",
    "EXT_texture_",
];

/// Parse a `.gltf` or `.glb` file (told apart by the GLB magic bytes; when `binary`, content
/// that is neither is reported as a broken GLB header); external buffers are resolved against
/// the folder of `path`, except a buffer whose URI names `side` (file name, bytes): it is read
/// from those bytes (the `.bin` of a `.gltf` being written, checked before either file exists).
pub(crate) fn parse(
    bytes: &[u8],
    path: &Path,
    binary: bool,
    side: Option<SideBuffer>,
    origin: DVec3,
) -> Result<RawMesh, MeshError> {
    let (json_bytes, bin) = glb::json_and_bin(bytes, path, binary)?;
    let value: Value = serde_json::from_slice(json_bytes)
        .map_err(|e| MeshError::parse(path, "JSON", e.to_string()))?;
    let Value::Object(root_json) = value else {
        return Err(MeshError::parse(
            path,
            "JSON",
            "the document is not a JSON object",
        ));
    };
    let mut warnings = Vec::new();
    check_extensions(&root_json, path, &mut warnings)?;
    let doc = document(json_bytes, path)?;
    let dir = super::contain::folder_of(path);
    let mut files = Vec::new();
    let source = Source::load(&doc, path, bin, side, dir, &mut files);

    let instances = meshes::instances(&doc, &root_json, &source, origin)?;
    let (v, corners, mut face_material) =
        meshes::read_geometry(&instances, &root_json, &source, origin)?
            .finish(&source, &mut warnings)?;

    let (assets, carried_warnings) = carry(&root_json, &source, dir)?;
    warnings.extend(carried_warnings);
    let (names, any_material) = material_names(&assets, &mut face_material);

    // Wedges: one per glTF vertex; position vertices by the weld.
    let (welded, wedge_vertex) =
        crate::clean::weld_exact_map(&TriMesh::new(v.positions, corners.clone()));
    let attributes = Attributes {
        wedge_vertex,
        corners,
        normals: v.present[0].then_some(v.normals),
        uv0: v.present[1].then_some(v.uv0),
        uv1: v.present[2].then_some(v.uv1),
        colors: v.present[3].then_some(v.colors),
        face_material: any_material.then_some(face_material),
    };
    Ok(RawMesh {
        positions: welded.positions,
        triangles: welded.triangles,
        // A file of positions only has no attributes, as from the other readers.
        attributes: (!attributes.is_empty()).then_some(attributes),
        materials: Some(Materials {
            names,
            libraries: Vec::new(),
            gltf: Some(assets),
        }),
        warnings,
        files,
        ..RawMesh::default()
    })
}

/// The checks of the extensions that the document (`root_json`) requires and uses: an error for
/// compressed geometry and for required instancing, warnings for what is read without being
/// applied.
fn check_extensions(
    root_json: &serde_json::Map<String, Value>,
    path: &Path,
    warnings: &mut Vec<MeshWarning>,
) -> Result<(), MeshError> {
    let names = |key: &str| -> Vec<String> {
        root_json
            .get(key)
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(|v| v.as_str().map(str::to_string))
                    .collect()
            })
            .unwrap_or_default()
    };
    let (required, used) = (names("extensionsRequired"), names("extensionsUsed"));
    if let Some(ext) = required.iter().find(|e| COMPRESSION.contains(&e.as_str())) {
        return Err(MeshError::parse(
            path,
            "extensionsRequired",
            format!(
                "the geometry is compressed with {ext}, which this reader does not decode \
                 (decompress the file first)"
            ),
        ));
    }
    // Extensions that place or repeat geometry, which this reader does not apply: required, the
    // file's geometry is not what it would read; only used, the plain meshes are the fallback.
    if let Some(ext) = required.iter().find(|e| GEOMETRY.contains(&e.as_str())) {
        return Err(MeshError::parse(
            path,
            "extensionsRequired",
            format!(
                "the file requires {ext}, which places or repeats the geometry and which this                  reader does not apply (the mesh would be read without it)"
            ),
        ));
    }
    for ext in used.iter().filter(|e| GEOMETRY.contains(&e.as_str())) {
        warnings.push(MeshWarning::IgnoredData {
            what: format!("glTF {ext} data (each mesh read once, without its instances)"),
        });
    }
    for ext in required.iter().filter(|e| {
        !COMPRESSION.contains(&e.as_str())
            && !GEOMETRY.contains(&e.as_str())
            && !UNDERSTOOD.iter().any(|u| e.starts_with(u))
    }) {
        warnings.push(MeshWarning::IgnoredData {
            what: format!(
                "the required glTF extension {ext} (not implemented: what it changes is not                  applied)"
            ),
        });
    }
    for ext in used.iter().filter(|e| COMPRESSION.contains(&e.as_str())) {
        warnings.push(MeshWarning::IgnoredData {
            what: format!("glTF {ext} data (the uncompressed fallback was read)"),
        });
    }
    Ok(())
}

/// The document of `json_bytes`, validated by the `gltf` crate.
fn document(json_bytes: &[u8], path: &Path) -> Result<::gltf::Document, MeshError> {
    let mut root: ::gltf::json::Root = ::gltf::json::deserialize::from_slice(json_bytes)
        .map_err(|e| MeshError::parse(path, "JSON", e.to_string()))?;
    // The `gltf` crate rejects every required extension it does not implement itself; those
    // that matter to the geometry were checked above.
    root.extensions_required.clear();
    // gltf-json 1.4's validation reads each primitive's POSITION accessor by index before it
    // checks that index, and panics on one past the end (found by the CLI fuzz: a GLB whose
    // "accessors" key was mangled): checked here first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (k, primitive) in mesh.primitives.iter().enumerate() {
            let position =
                ::gltf::json::validation::Checked::Valid(::gltf::json::mesh::Semantic::Positions);
            if let Some(index) = primitive.attributes.get(&position)
                && index.value() >= root.accessors.len()
            {
                return Err(MeshError::parse(
                    path,
                    "document",
                    format!(
                        "mesh {m}, primitive {k}: POSITION names accessor {}, but the file has \
                         {} accessors",
                        index.value(),
                        root.accessors.len()
                    ),
                ));
            }
        }
    }
    ::gltf::Document::from_json(root)
        .map_err(|e| MeshError::parse(path, "document", invalid_document(&e)))
}

/// The message of a validation failure of the `gltf` crate.
fn invalid_document(e: &::gltf::Error) -> String {
    match e {
        ::gltf::Error::Validation(list) => {
            let items: Vec<String> = list
                .iter()
                .take(5)
                .map(|(path, error)| format!("{}: {error}", path.as_str()))
                .collect();
            format!("invalid glTF: {}", items.join("; "))
        }
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests;

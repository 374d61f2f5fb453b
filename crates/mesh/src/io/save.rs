//! The checked save ([`save`]): encode, read the bytes back, refuse an output that does not load
//! or lacks what the format stores, write atomically, copy the files the materials name.

use super::atomic::write_atomic_all;
use super::encode::{GltfBuffer, encode_parts};
use super::side_files::{copy_gltf_images, copy_material_files};
use super::{Format, load_encoded};
use crate::Model;
use crate::attributes::{AttributeKind, Attributes};
use crate::error::MeshError;
use std::path::Path;

/// What writing a model did with its attributes ([`save`]): the `"attributes"` object of
/// `gng3d simplify --json` and of the Python report.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct KeptAttributes {
    /// Attributes of the input (serialized as `normals`, `uv0`, `uv1`, `colors`, `materials`).
    pub input: Vec<AttributeKind>,
    /// Attributes written to the output (it reads back with each of them).
    pub kept: Vec<AttributeKind>,
    /// What was not written or not copied, one sentence each (the caller shows them as warnings).
    pub dropped: Vec<String>,
}

impl Format {
    /// Whether this format stores attributes of `kind`.
    pub fn stores(self, kind: AttributeKind) -> bool {
        use AttributeKind::*;
        match self {
            Format::Stl => false,
            Format::Obj => kind != Uv1,
            Format::Ply => matches!(kind, Normals | Uv0 | Colors),
            Format::Gltf | Format::Glb => true,
        }
    }
}

/// Write `model` to `path` (format by extension: OBJ, binary little-endian PLY, binary STL,
/// glTF, GLB), the one checked writer of the library and every front end:
///
/// 1. encode ([`encode_with_attributes`](super::encode_with_attributes); a `.gltf` with its
///    buffer in `<stem>.bin`), the positions plus the model's origin in f64;
/// 2. read the bytes back with [`load_bytes`](super::load_bytes) (a `.gltf` with its `.bin` from
///    memory) and refuse with a [`MeshError::Write`] naming `path` and the problem, writing
///    nothing, when the mesh has no triangle or the bytes do not load, hold no face, or lack an
///    attribute the format stores ([`Format::stores`]);
/// 3. write atomically ([`write_atomic`](super::write_atomic); a `.gltf`'s `.bin` first);
/// 4. copy the material libraries and textures of the materials next to an OBJ
///    ([`copy_material_files`]) and the images of a glTF input next to a glTF
///    ([`copy_gltf_images`]), when the faces have materials.
///
/// The returned [`KeptAttributes`] names the input's attributes, those written, and, as
/// sentences, what the format cannot keep and what could not be copied (never silent); it is
/// empty for a model without attributes.
pub fn save(model: &Model, path: &Path) -> Result<KeptAttributes, MeshError> {
    let (mesh, attributes, materials) = (
        &model.mesh,
        model.attributes.as_ref(),
        model.materials.as_ref(),
    );
    let format = Format::from_path(path).ok_or_else(|| MeshError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let refuse = |message: String| MeshError::Write {
        path: path.to_path_buf(),
        message,
    };
    if mesh.face_count() == 0 {
        return Err(refuse(format!(
            "the mesh has {} vertices and no triangles; nothing written",
            mesh.vertex_count()
        )));
    }
    let encoded = encode_parts(
        mesh,
        attributes,
        materials,
        model.origin,
        format,
        path,
        GltfBuffer::BinFile,
    )?;
    let input = attributes.map(Attributes::kinds).unwrap_or_default();
    let kept: Vec<AttributeKind> = input
        .iter()
        .copied()
        .filter(|&k| format.stores(k))
        .collect();
    let side = encoded
        .bin
        .as_ref()
        .map(|(name, bytes)| (name.as_str(), bytes.as_slice()));
    let reread = load_encoded(&encoded.main, side, format, path).map_err(|e| {
        refuse(format!(
            "the output does not load back ({e}); nothing written"
        ))
    })?;
    let back = reread
        .attributes
        .as_ref()
        .map(Attributes::kinds)
        .unwrap_or_default();
    if reread.mesh.face_count() == 0 || kept.iter().any(|n| !back.contains(n)) {
        return Err(refuse(format!(
            "the output does not read back with {}; nothing written",
            if kept.is_empty() {
                "its faces".to_string()
            } else {
                AttributeKind::list(&kept)
            }
        )));
    }
    // A `.gltf` and its `.bin` together: both written in full before either is renamed, the
    // `.bin` first (a failed write leaves both files as they were).
    let bin = encoded
        .bin
        .as_ref()
        .map(|(name, bytes)| (path.with_file_name(name), bytes.as_slice()));
    let files: Vec<(&Path, &[u8])> = bin
        .iter()
        .map(|(p, b)| (p.as_path(), *b))
        .chain([(path, encoded.main.as_slice())])
        .collect();
    write_atomic_all(&files)?;
    let mut dropped: Vec<String> = encoded.warnings.iter().map(ToString::to_string).collect();
    if let Some(m) = materials
        && attributes.is_some_and(|a| a.face_material.is_some())
    {
        let copied = match format {
            Format::Obj => copy_material_files(m, path),
            Format::Gltf | Format::Glb => copy_gltf_images(m, path),
            Format::Ply | Format::Stl => Vec::new(),
        };
        dropped.extend(copied.iter().map(ToString::to_string));
    }
    Ok(KeptAttributes {
        input,
        kept,
        dropped,
    })
}

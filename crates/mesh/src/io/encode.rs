//! Encoding a mesh as the bytes of a file ([`encode`], [`encode_with_attributes`]; the one
//! encoder behind them and the checked save is [`encode_parts`]), with what the format cannot
//! keep as warnings.

use super::{Format, apart, gltf, matconv, obj, ply, stl};
use crate::TriMesh;
use crate::attributes::{AttributeKind, Attributes, Materials};
use crate::error::{MeshError, MeshWarning};
use glam::DVec3;
use std::path::Path;

/// A [`MeshError::IndexOutOfRange`] for the first corner of `mesh` beyond its positions.
fn check_indices(mesh: &TriMesh, path: &Path) -> Result<(), MeshError> {
    let vertex_count = mesh.positions.len();
    for (face, t) in mesh.triangles.iter().enumerate() {
        if let Some(&index) = t.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(MeshError::IndexOutOfRange {
                path: path.to_path_buf(),
                face,
                index: index as i64,
                vertex_count,
            });
        }
    }
    Ok(())
}

/// The bytes of `mesh` (positions and triangles only) in `format`, as [`save`](super::save) writes
/// them, except that a `.gltf` holds its buffer as a `data:` URI here (one self-contained file;
/// [`save`](super::save) writes the buffer to `<stem>.bin` instead). `path` only names the file in
/// errors. Fails on out-of-range indices.
pub fn encode(mesh: &TriMesh, format: Format, path: &Path) -> Result<Vec<u8>, MeshError> {
    Ok(encode_parts(
        mesh,
        None,
        None,
        DVec3::ZERO,
        format,
        path,
        GltfBuffer::DataUri,
    )?
    .main)
}

/// The materials a glTF output of `attributes` writes: a glTF input's as they are, or OBJ
/// material libraries converted to glTF materials (`embed`: textures into the buffer, for a
/// `.glb`), with whether texture coordinates flip and what was not converted.
fn gltf_materials(
    attributes: &Attributes,
    materials: Option<&Materials>,
    embed: bool,
) -> (Option<Materials>, bool, Vec<MeshWarning>) {
    match materials
        .filter(|_| attributes.face_material.is_some())
        .and_then(|m| matconv::obj_to_gltf(m, embed))
    {
        Some(c) => (Some(c.materials), c.flip_v, c.warnings),
        None => (None, false, Vec::new()),
    }
}

/// The write error for `attributes` that do not fit `mesh` (checked once before writing `path`
/// in any format).
fn check_attributes(mesh: &TriMesh, attributes: &Attributes, path: &Path) -> Result<(), MeshError> {
    attributes
        .validate(mesh)
        .map_err(|message| MeshError::Write {
            path: path.to_path_buf(),
            message: format!("the attributes do not fit the mesh: {message}"),
        })
}

/// The bytes [`save`](super::save) writes for `mesh` with
/// `attributes` in `format`, and what the format cannot keep (as warnings): OBJ keeps normals,
/// texture coordinates (`uv0`), colours (per vertex) and materials; PLY keeps normals, `uv0` and
/// colours, one vertex record per wedge (seams as split vertices, which the weld joins again on
/// loading); STL keeps positions only; glTF keeps everything, one glTF vertex per wedge and one
/// primitive per material, with the materials, textures and images of a glTF input
/// ([`Materials::gltf`]), or the OBJ material libraries of `materials` converted to glTF materials
/// (base colour, opacity, roughness, metallic, emissive and the `map_Kd` texture: embedded in a
/// `.glb`, named by a relative URI in a `.gltf`, see
/// [`copy_gltf_images`](super::copy_gltf_images)), or materials named as in `materials`. An OBJ
/// output of a glTF input names `<path stem>.mtl`, made from the glTF materials by
/// [`copy_material_files`](super::copy_material_files). What does not cross is a warning. A `.gltf`
/// from here holds its buffer as a `data:` URI (one self-contained file);
/// [`save`](super::save) writes it to `<stem>.bin` instead.
/// Attributes that do not fit `mesh` are a [`MeshError::Write`] naming the problem.
pub fn encode_with_attributes(
    mesh: &TriMesh,
    attributes: &Attributes,
    materials: Option<&Materials>,
    format: Format,
    path: &Path,
) -> Result<(Vec<u8>, Vec<MeshWarning>), MeshError> {
    let encoded = encode_parts(
        mesh,
        Some(attributes),
        materials,
        DVec3::ZERO,
        format,
        path,
        GltfBuffer::DataUri,
    )?;
    Ok((encoded.main, encoded.warnings))
}

/// Where the buffer of a `.gltf` goes ([`encode_parts`]; a `.glb` always holds it in its BIN
/// chunk).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum GltfBuffer {
    /// A `data:` URI inside the JSON: one self-contained file ([`encode`],
    /// [`encode_with_attributes`]).
    DataUri,
    /// `<stem>.bin` next to the `.gltf` (what [`save`](super::save) and
    /// [`save`](super::save) write).
    BinFile,
}

/// The encoded output of one write, before it is checked and written.
pub(super) struct Encoded {
    /// The file's bytes.
    pub(super) main: Vec<u8>,
    /// The `.bin` file of a `.gltf` with [`GltfBuffer::BinFile`]: its name next to the `.gltf`
    /// and its bytes.
    pub(super) bin: Option<(String, Vec<u8>)>,
    /// What the format cannot keep, or what did not convert.
    pub(super) warnings: Vec<MeshWarning>,
}

/// The one encoder: `mesh` in `format`, with `attributes` (and their `materials`) when given,
/// positions and triangles only when not.
pub(super) fn encode_parts(
    mesh: &TriMesh,
    attributes: Option<&Attributes>,
    materials: Option<&Materials>,
    origin: DVec3,
    format: Format,
    path: &Path,
    gltf_buffer: GltfBuffer,
) -> Result<Encoded, MeshError> {
    if let Some(a) = attributes {
        check_attributes(mesh, a, path)?;
    }
    check_indices(mesh, path)?;
    let mut warnings = Vec::new();
    let plain = |main| Encoded {
        main,
        bin: None,
        warnings: Vec::new(),
    };
    let Some(attributes) = attributes else {
        return Ok(match format {
            Format::Obj => plain(obj::write(mesh, origin)),
            Format::Ply => plain(ply::write(mesh, origin)),
            Format::Stl => Encoded {
                main: encode_stl(mesh, origin, path)?,
                bin: None,
                warnings: stl_precision(origin),
            },
            Format::Gltf | Format::Glb => encode_gltf(
                mesh,
                &Attributes::per_vertex(mesh),
                None,
                origin,
                format,
                path,
                gltf_buffer,
            ),
        });
    };
    // What the format cannot store is said once, before the format's own warnings.
    let lost: Vec<AttributeKind> = attributes
        .kinds()
        .into_iter()
        .filter(|&k| !format.stores(k))
        .collect();
    if !lost.is_empty() {
        warnings.push(MeshWarning::AttributesDropped {
            attributes: AttributeKind::list(&lost),
            reason: match format {
                Format::Stl => "STL stores positions only",
                Format::Obj => "OBJ has one set of texture coordinates",
                // PLY (glTF stores every kind).
                _ => "PLY stores one set of texture coordinates and no materials",
            }
            .to_string(),
        });
    }
    let main = match format {
        Format::Gltf | Format::Glb => {
            return Ok(encode_gltf(
                mesh,
                attributes,
                materials,
                origin,
                format,
                path,
                gltf_buffer,
            ));
        }
        Format::Stl => {
            warnings.extend(stl_precision(origin));
            encode_stl(mesh, origin, path)?
        }
        Format::Obj => {
            let plan = materials
                .filter(|_| attributes.face_material.is_some())
                .and_then(|m| matconv::gltf_to_mtl(m, path));
            if let Some(p) = &plan {
                warnings.extend(p.warnings.iter().cloned());
            }
            let libraries = materials
                .filter(|_| plan.is_none())
                .map(|m| super::side_files::library_names(m, path))
                .unwrap_or_default();
            obj::write_with_attributes(
                mesh,
                attributes,
                materials,
                &libraries,
                plan.as_ref().map(|p| (p.library.as_str(), p.flip_v)),
                origin,
                &mut warnings,
            )
        }
        Format::Ply => ply::write_with_attributes(mesh, attributes, origin),
    };
    Ok(Encoded {
        main,
        bin: None,
        warnings,
    })
}

/// Binary STL of `mesh`.
fn encode_stl(mesh: &TriMesh, origin: DVec3, path: &Path) -> Result<Vec<u8>, MeshError> {
    stl::write(mesh, origin).map_err(|e| MeshError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// The warning of an STL written far from its coordinates' origin: STL stores f32 only.
fn stl_precision(origin: DVec3) -> Vec<MeshWarning> {
    if origin == DVec3::ZERO {
        return Vec::new();
    }
    vec![MeshWarning::ValuesReinterpreted {
        what: format!(
            "STL stores 32-bit coordinates: positions around ({}, {}, {}) are rounded to about \
             {:.1e} units (OBJ, PLY and glTF keep them)",
            origin.x,
            origin.y,
            origin.z,
            origin.abs().max_element() * f64::from(f32::EPSILON) / 2.0
        ),
    }]
}

/// `mesh` with `attributes` (validated against it) as a `.glb`, or as a `.gltf` with its buffer
/// stored as `gltf_buffer` says; OBJ materials are converted (textures embedded in a `.glb`).
fn encode_gltf(
    mesh: &TriMesh,
    attributes: &Attributes,
    materials: Option<&Materials>,
    origin: DVec3,
    format: Format,
    path: &Path,
    gltf_buffer: GltfBuffer,
) -> Encoded {
    let (converted, flip_v, warnings) =
        gltf_materials(attributes, materials, format == Format::Glb);
    let materials = converted.as_ref().or(materials);
    let bin_name = apart::bin_name(path);
    let storage = match (format, gltf_buffer) {
        (Format::Glb, _) => gltf::BufferStorage::Glb,
        (_, GltfBuffer::DataUri) => gltf::BufferStorage::DataUri,
        (_, GltfBuffer::BinFile) => gltf::BufferStorage::File(&bin_name),
    };
    let written = gltf::write(mesh, attributes, materials, storage, flip_v, origin);
    Encoded {
        main: written.main,
        bin: written.bin.map(|bytes| (bin_name, bytes)),
        warnings,
    }
}

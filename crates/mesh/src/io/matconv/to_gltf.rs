//! OBJ material libraries to glTF materials, for a glTF output of an OBJ input
//! ([`obj_to_gltf`]).

use super::{MtlMaterial, image_mime, parse_mtl, roughness_of_ns};
use crate::attributes::Materials;
use crate::error::MeshWarning;
use crate::io::contain;
use crate::io::gltf::{GltfAssets, percent_encode};
use serde_json::{Map, Value, json};
use std::collections::{BTreeSet, HashMap};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// A path inside a folder (relative, not leaving it).
fn inside(relative: &Path) -> bool {
    !relative.is_absolute()
        && !relative
            .components()
            .any(|c| matches!(c, Component::ParentDir | Component::Prefix(_)))
}

/// glTF materials made from OBJ material libraries.
pub(crate) struct ToGltf {
    /// The materials with [`Materials::gltf`] set to the converted assets.
    pub materials: Materials,
    /// Whether a texture was converted (texture coordinates are then flipped).
    pub flip_v: bool,
    /// What was not converted, and files that could not be read.
    pub warnings: Vec<MeshWarning>,
}

/// Converts the OBJ material libraries of `materials` (none: `None`; also for a glTF input's
/// materials) into glTF materials, one per name of `materials.names` (a name no library
/// defines keeps its name only). Textures become images: embedded bytes when `embed` (a `.glb`)
/// or when the texture lies outside the library's folder, else a relative URI with the file to
/// copy next to the output. Unreadable libraries and textures, non-PNG/JPEG textures, undefined
/// materials and statements not converted are warnings.
pub(crate) fn obj_to_gltf(materials: &Materials, embed: bool) -> Option<ToGltf> {
    if materials.gltf.is_some() || materials.libraries.is_empty() {
        return None;
    }
    let mut warnings = Vec::new();
    let mut defined: HashMap<String, (MtlMaterial, PathBuf)> = HashMap::new();
    let mut dropped = BTreeSet::new();
    let mut unreadable = false;
    for library in &materials.libraries {
        match contain::read_limited(library, contain::LIBRARY_LIMIT) {
            Ok(bytes) => {
                let (list, not) = parse_mtl(&bytes);
                dropped.extend(not);
                let dir = library.parent().unwrap_or(Path::new("")).to_path_buf();
                for m in list {
                    defined
                        .entry(m.name.clone())
                        .or_insert_with(|| (m, dir.clone()));
                }
            }
            Err(e) => {
                unreadable = true;
                warnings.push(MeshWarning::MaterialFileNotCopied {
                    path: library.clone(),
                    reason: format!(
                        "cannot read it ({e}); its materials are written with their names only"
                    ),
                });
            }
        }
    }
    let mut images: Vec<Value> = Vec::new();
    let mut textures: Vec<Value> = Vec::new();
    let mut texture_of: HashMap<PathBuf, Option<usize>> = HashMap::new();
    let mut embedded: Vec<(usize, Arc<[u8]>)> = Vec::new();
    let mut image_files: Vec<(usize, PathBuf)> = Vec::new();
    let mut undefined = Vec::new();
    let mut gltf_materials = Vec::new();
    for name in &materials.names {
        let mut material = json!({ "name": name });
        let Some((m, dir)) = defined.get(name) else {
            if name != "default" {
                undefined.push(name.clone());
            }
            gltf_materials.push(material);
            continue;
        };
        let mut pbr = Map::new();
        let alpha = m.opacity.unwrap_or(1.0).clamp(0.0, 1.0);
        if m.kd.is_some() || alpha < 1.0 {
            let kd = m.kd.unwrap_or([1.0; 3]).map(|x| x.clamp(0.0, 1.0));
            pbr.insert(
                "baseColorFactor".into(),
                json!([kd[0], kd[1], kd[2], alpha]),
            );
        }
        if alpha < 1.0 {
            material["alphaMode"] = json!("BLEND");
        }
        if let Some(file) = &m.map_kd {
            let relative = PathBuf::from(file.replace('\\', "/"));
            let texture = *texture_of.entry(dir.join(&relative)).or_insert_with(|| {
                // The containment rule: a regular file inside the library's folder.
                let (source, bytes) =
                    match contain::read_contained(dir, dir, file, contain::IMAGE_LIMIT) {
                        Ok(read) => read,
                        Err(e) => {
                            warnings.push(MeshWarning::ReferenceRefused {
                                reference: format!(
                                    "texture {} of material {name}",
                                    dir.join(file).display()
                                ),
                                reason: format!("{e}; the material is written without it"),
                            });
                            return None;
                        }
                    };
                let Some(mime) = image_mime(&bytes) else {
                    warnings.push(MeshWarning::AttributesDropped {
                        attributes: format!("texture {} of material {name}", source.display()),
                        reason: "glTF takes PNG and JPEG images only".into(),
                    });
                    return None;
                };
                let index = images.len();
                if embed || !inside(&relative) {
                    images.push(json!({ "mimeType": mime }));
                    embedded.push((index, Arc::from(bytes)));
                } else {
                    let uri = relative.to_string_lossy().replace('\\', "/");
                    images.push(json!({ "uri": percent_encode(&uri) }));
                    image_files.push((index, source.clone()));
                }
                textures.push(json!({ "source": index, "sampler": 0 }));
                Some(textures.len() - 1)
            });
            if let Some(t) = texture {
                pbr.insert("baseColorTexture".into(), json!({ "index": t }));
            }
        }
        pbr.insert(
            "metallicFactor".into(),
            json!(m.pm.unwrap_or(0.0).clamp(0.0, 1.0)),
        );
        let roughness =
            m.pr.map(|r| r.clamp(0.0, 1.0))
                .or(m.ns.map(roughness_of_ns))
                .unwrap_or(1.0);
        pbr.insert("roughnessFactor".into(), json!(roughness));
        material["pbrMetallicRoughness"] = Value::Object(pbr);
        if let Some(ke) = m.ke
            && ke.iter().any(|&x| x > 0.0)
        {
            material["emissiveFactor"] = json!(ke.map(|x| x.clamp(0.0, 1.0)));
        }
        gltf_materials.push(material);
    }
    // With a library unreadable, its warning says so for the materials it would define.
    if !undefined.is_empty() && !unreadable {
        warnings.push(MeshWarning::AttributesDropped {
            attributes: format!("the look of material(s) {}", undefined.join(", ")),
            reason: "no material library defines them; the glTF materials have their names only"
                .into(),
        });
    }
    if !dropped.is_empty() {
        warnings.push(MeshWarning::AttributesDropped {
            attributes: format!(
                "MTL statements {}",
                dropped.into_iter().collect::<Vec<_>>().join(", ")
            ),
            reason: "a glTF material takes Kd, d/Tr, Ns or Pr, Pm, Ke and map_Kd (without \
                     options) only"
                .into(),
        });
    }
    let mut json = Map::new();
    json.insert(
        "asset".into(),
        json!({ "version": "2.0", "generator": "gng3d" }),
    );
    json.insert("materials".into(), Value::Array(gltf_materials));
    let flip_v = !textures.is_empty();
    if flip_v {
        json.insert("textures".into(), Value::Array(textures));
        json.insert("images".into(), Value::Array(images));
        // OBJ textures repeat; linear filtering with mipmaps.
        json.insert(
            "samplers".into(),
            json!([{ "magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497 }]),
        );
    }
    let assets = GltfAssets {
        json,
        embedded_images: embedded,
        source_dir: PathBuf::new(),
        image_files,
    };
    Some(ToGltf {
        materials: Materials {
            names: materials.names.clone(),
            libraries: Vec::new(),
            gltf: Some(assets),
        },
        flip_v,
        warnings,
    })
}

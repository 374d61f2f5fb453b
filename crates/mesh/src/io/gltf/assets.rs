//! What a glTF file holds besides geometry: the materials, textures, images and samplers carried
//! to a glTF output ([`GltfAssets`], [`carry`]), the material names of the faces
//! ([`material_names`]), and the image files they name, read and copied next to an output.

use super::buffers::Source;
use super::uri::{data_uri, percent_decode, relative_uri};
use crate::attributes::gltf_assets::GltfAssets;
use crate::error::{MeshError, MeshWarning};
use serde_json::{Map, Value};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The non-geometry members to carry to an output, with warnings for what is not carried.
pub(super) fn carry(
    root: &Map<String, Value>,
    source: &Source,
    dir: &Path,
) -> Result<(GltfAssets, Vec<MeshWarning>), MeshError> {
    let mut json = Map::new();
    for key in ["asset", "materials", "textures", "images", "samplers"] {
        if let Some(v) = root.get(key) {
            json.insert(key.to_string(), v.clone());
        }
    }
    let mut embedded_images = Vec::new();
    if let Some(Value::Array(images)) = json.get_mut("images") {
        for (i, image) in images.iter_mut().enumerate() {
            if let Some(obj) = image.as_object_mut()
                && let Some(view) = obj.remove("bufferView")
            {
                let view = view
                    .as_u64()
                    .and_then(|v| source.doc.views().nth(v as usize))
                    .ok_or_else(|| source.error(format!("image {i}"), "bad bufferView"))?;
                embedded_images.push((i, Arc::from(source.view_bytes(&view)?)));
            }
        }
    }
    // Extensions named by the kept objects.
    let mut named = BTreeSet::new();
    fn collect(v: &Value, named: &mut BTreeSet<String>) {
        match v {
            Value::Object(map) => {
                for (k, child) in map {
                    if k == "extensions"
                        && let Some(ext) = child.as_object()
                    {
                        named.extend(ext.keys().cloned());
                    }
                    collect(child, named);
                }
            }
            Value::Array(a) => a.iter().for_each(|c| collect(c, named)),
            _ => {}
        }
    }
    for v in json.values() {
        collect(v, &mut named);
    }
    for key in ["extensionsUsed", "extensionsRequired"] {
        if let Some(Value::Array(list)) = root.get(key) {
            let kept: Vec<Value> = list
                .iter()
                .filter(|e| e.as_str().is_some_and(|e| named.contains(e)))
                .cloned()
                .collect();
            if !kept.is_empty() {
                json.insert(key.to_string(), Value::Array(kept));
            }
        }
    }
    let mut warnings = Vec::new();
    for key in ["animations", "skins", "cameras"] {
        if let Some(n) = root.get(key).and_then(Value::as_array).map(Vec::len)
            && n > 0
        {
            warnings.push(MeshWarning::IgnoredData {
                what: format!("{n} glTF {key}"),
            });
        }
    }
    if let Some(ext) = root.get("extensions").and_then(Value::as_object)
        && !ext.is_empty()
    {
        warnings.push(MeshWarning::IgnoredData {
            what: format!(
                "glTF document extensions {}",
                ext.keys().cloned().collect::<Vec<_>>().join(", ")
            ),
        });
    }
    Ok((
        GltfAssets {
            json,
            embedded_images,
            source_dir: dir.to_path_buf(),
            image_files: Vec::new(),
        },
        warnings,
    ))
}

/// The material names of `face_material` (glTF material indices, `u32::MAX` for a primitive
/// without one): the glTF materials' names (`material_<i>` for one without), and `default` after
/// them for the faces without a material, which `face_material` then names; with whether any
/// face has a material.
pub(super) fn material_names(
    assets: &GltfAssets,
    face_material: &mut [u32],
) -> (Vec<String>, bool) {
    let material_count = assets.material_count() as u32;
    let mut names: Vec<String> = (0..material_count as usize)
        .map(|i| {
            assets.array("materials")[i]["name"]
                .as_str()
                .map_or_else(|| format!("material_{i}"), str::to_string)
        })
        .collect();
    let any_material = face_material.iter().any(|&m| m != u32::MAX);
    if face_material.contains(&u32::MAX) && any_material {
        names.push("default".to_string());
    }
    for m in face_material {
        if *m == u32::MAX {
            *m = material_count;
        }
    }
    (names, any_material)
}

/// the containment rule: a file converted from an OBJ library (already resolved), or a regular
/// file inside the input's folder of at most [`crate::io::contain::IMAGE_LIMIT`] bytes.
pub(in crate::io) fn read_image_file(
    assets: &GltfAssets,
    j: usize,
    uri: &str,
) -> Result<(PathBuf, Vec<u8>), crate::io::contain::Refused> {
    use crate::io::contain::{IMAGE_LIMIT, read_contained, read_limited};
    match assets.image_files.iter().find(|(i, _)| *i == j) {
        Some((_, file)) => read_limited(file, IMAGE_LIMIT).map(|b| (file.clone(), b)),
        None => read_contained(
            &assets.source_dir,
            &assets.source_dir,
            &percent_decode(uri),
            IMAGE_LIMIT,
        ),
    }
}

/// The files of the images of `assets` named by relative URIs that exist inside the input's
/// folder, canonical (what an output must not replace).
pub(in crate::io) fn image_files(assets: &GltfAssets) -> Vec<PathBuf> {
    assets
        .array("images")
        .iter()
        .filter_map(|image| image["uri"].as_str())
        .filter(|uri| data_uri(uri).is_none())
        .filter_map(|uri| {
            crate::io::contain::resolve(
                &assets.source_dir,
                &assets.source_dir,
                &percent_decode(uri),
            )
            .ok()
        })
        .collect()
}

/// Copies the images of `assets` named by relative URIs (inside the input's folder) next to
/// `output`, keeping their relative paths ([`crate::io::contain`]'s rule on both sides); files
/// already there are left alone.
pub(crate) fn copy_images(assets: &GltfAssets, output: &Path) -> Vec<MeshWarning> {
    use crate::io::contain::{Beside, beside, folder_of, side_file, write_beside};
    let out_dir = folder_of(output);
    let mut warnings = Vec::new();
    for (i, image) in assets.array("images").iter().enumerate() {
        let Some(uri) = image["uri"].as_str() else {
            continue;
        };
        let Some(relative) = relative_uri(uri) else {
            if data_uri(uri).is_none() {
                warnings.push(MeshWarning::ReferenceRefused {
                    reference: format!("glTF image {i} ({uri})"),
                    reason: "it leaves the model's folder or names a URL; the output names it \
                             as it is, without a copy"
                        .into(),
                });
            }
            continue;
        };
        // A file of that name already beside the output is used only when it holds the same
        // bytes: the output's JSON names the image by the input's URI, so a different file
        // there is reported, never silently taken for the input's (nor replaced).
        let result = read_image_file(assets, i, uri).and_then(|(_, bytes)| {
            let target = side_file(out_dir, &relative)?;
            match beside(&target, &bytes)? {
                Beside::Same => Ok(()),
                Beside::Other => {
                    warnings.push(MeshWarning::ReferenceRefused {
                        reference: format!("glTF image {i} ({uri})"),
                        reason: format!(
                            "a different file named {} is already beside {}: the output names \
                             that file, not the input's image (write to another folder)",
                            relative.display(),
                            output.display()
                        ),
                    });
                    Ok(())
                }
                Beside::Absent => write_beside(out_dir, &relative, &bytes),
            }
        });
        if let Err(reason) = result {
            warnings.push(MeshWarning::ReferenceRefused {
                reference: format!("glTF image {i} ({uri})"),
                reason: format!("{reason}; the output names it without a copy"),
            });
        }
    }
    warnings
}

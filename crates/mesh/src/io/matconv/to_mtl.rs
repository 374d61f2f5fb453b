//! glTF materials to a material library, for an OBJ output of a glTF input ([`gltf_to_mtl`]),
//! and the library and its images written next to the output ([`write_mtl`]).

use super::{image_mime, ns_of_roughness};
use crate::attributes::Materials;
use crate::error::MeshWarning;
use crate::io::contain;
use crate::io::gltf::{GltfAssets, data_uri, percent_decode, relative_uri};
use serde_json::Value;
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where the bytes of an image file written next to an OBJ output come from.
pub(crate) enum ImageSource {
    /// A file of the glTF input, copied.
    Copy(PathBuf),
    /// Bytes of an embedded image (buffer view or `data:` URI), written out.
    Bytes(Arc<[u8]>),
}

/// A material library made from glTF materials, for an OBJ output.
pub(crate) struct ToMtl {
    /// The library's file name (`<output stem>.mtl`), next to the output.
    pub library: String,
    /// Its text.
    pub text: String,
    /// Image files to write next to the output: (name relative to the output's folder, source).
    pub files: Vec<(PathBuf, ImageSource)>,
    /// Whether a texture is referenced (texture coordinates are then flipped).
    pub flip_v: bool,
    /// What was not converted.
    pub warnings: Vec<MeshWarning>,
}

/// Converts the glTF materials of `materials` (a glTF input; otherwise `None`) into a material
/// library for the OBJ `output`: `newmtl` per glTF material with the name the OBJ's `usemtl`
/// gives it, the base colour texture as `map_Kd` (an image named by a relative URI keeps its
/// name and is copied; an embedded one is written as `<output stem>_image<i>.png|jpg`).
pub(crate) fn gltf_to_mtl(materials: &Materials, output: &Path) -> Option<ToMtl> {
    let assets = materials.gltf.as_ref()?;
    let count = assets.material_count();
    if count == 0 {
        return None;
    }
    let stem = output
        .file_stem()
        .map_or_else(|| "materials".into(), |s| s.to_string_lossy().into_owned());
    let mut text = String::from("# written by gng3d from glTF materials\n");
    let mut files: Vec<(PathBuf, ImageSource)> = Vec::new();
    let mut image_names: HashMap<usize, Option<String>> = HashMap::new();
    let mut dropped = BTreeSet::new();
    let mut warnings = Vec::new();
    let num = |v: &Value, default: f64| v.as_f64().unwrap_or(default) as f32;
    for i in 0..count {
        let m = &assets.array("materials")[i];
        let name = materials
            .names
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("material_{i}"));
        text.push_str(&format!("\nnewmtl {}\n", contain::one_line_name(&name)));
        let pbr = &m["pbrMetallicRoughness"];
        let factor: Vec<f32> = pbr["baseColorFactor"]
            .as_array()
            .map(|a| a.iter().map(|x| num(x, 1.0)).collect())
            .filter(|a: &Vec<f32>| a.len() == 4)
            .unwrap_or_else(|| vec![1.0; 4]);
        text.push_str(&format!("Kd {} {} {}\n", factor[0], factor[1], factor[2]));
        let mode = m["alphaMode"].as_str().unwrap_or("OPAQUE");
        if mode != "OPAQUE" && factor[3] < 1.0 {
            text.push_str(&format!("d {}\n", factor[3]));
        }
        if mode == "MASK" {
            dropped.insert("alphaMode MASK (alphaCutoff)".to_string());
        }
        let roughness = num(&pbr["roughnessFactor"], 1.0);
        let metallic = num(&pbr["metallicFactor"], 1.0);
        text.push_str(&format!(
            "Ns {}\nPr {roughness}\nPm {metallic}\n",
            ns_of_roughness(roughness)
        ));
        if let Some(e) = m["emissiveFactor"].as_array()
            && e.len() == 3
            && e.iter().any(|x| num(x, 0.0) > 0.0)
        {
            let e: Vec<f32> = e.iter().map(|x| num(x, 0.0)).collect();
            text.push_str(&format!("Ke {} {} {}\n", e[0], e[1], e[2]));
        }
        for key in [
            "metallicRoughnessTexture",
            "normalTexture",
            "occlusionTexture",
            "emissiveTexture",
        ] {
            if !pbr[key].is_null() || !m[key].is_null() {
                dropped.insert(key.to_string());
            }
        }
        if m["doubleSided"].as_bool() == Some(true) {
            dropped.insert("doubleSided".to_string());
        }
        for e in [&m["extensions"], &pbr["extensions"]] {
            if let Some(e) = e.as_object() {
                dropped.extend(e.keys().cloned());
            }
        }
        let info = &pbr["baseColorTexture"];
        let Some(t) = info["index"].as_u64() else {
            continue;
        };
        if let Some(e) = info["extensions"].as_object() {
            dropped.extend(e.keys().map(|k| format!("{k} (of baseColorTexture)")));
        }
        if info["texCoord"].as_u64().is_some_and(|c| c != 0) {
            dropped.insert("baseColorTexture on TEXCOORD_1".to_string());
            continue;
        }
        let texture = &assets
            .array("textures")
            .get(t as usize)
            .cloned()
            .unwrap_or_default();
        if let Some(e) = texture["extensions"].as_object() {
            dropped.extend(e.keys().map(|k| format!("{k} (of a texture)")));
        }
        if let Some(s) = texture["sampler"].as_u64() {
            let sampler = assets
                .array("samplers")
                .get(s as usize)
                .cloned()
                .unwrap_or_default();
            let wrap = |k: &str| sampler[k].as_u64().is_none_or(|w| w == 10497);
            if !sampler["magFilter"].is_null() && sampler["magFilter"].as_u64() != Some(9729)
                || !wrap("wrapS")
                || !wrap("wrapT")
            {
                dropped.insert("texture sampler filters and wrapping".to_string());
            }
        }
        let Some(j) = texture["source"].as_u64().map(|j| j as usize) else {
            continue;
        };
        let file = image_names
            .entry(j)
            .or_insert_with(|| image_file(assets, j, &stem, &mut files, &mut warnings));
        if let Some(file) = file {
            text.push_str(&format!("map_Kd {}\n", contain::one_line_name(file)));
        }
    }
    if !dropped.is_empty() {
        warnings.push(MeshWarning::AttributesDropped {
            attributes: format!(
                "glTF material properties {}",
                dropped.into_iter().collect::<Vec<_>>().join(", ")
            ),
            reason: "an OBJ material library takes the base colour and texture, roughness, \
                     metallic and emissive colour only"
                .into(),
        });
    }
    let flip_v = image_names.values().any(Option::is_some);
    Some(ToMtl {
        library: format!("{stem}.mtl"),
        text,
        files,
        flip_v,
        warnings,
    })
}

/// The name `map_Kd` gives image `j` of `assets`, with the file to write for it in `files`;
/// `None` (and a warning) for an image that cannot be referenced.
fn image_file(
    assets: &GltfAssets,
    j: usize,
    stem: &str,
    files: &mut Vec<(PathBuf, ImageSource)>,
    warnings: &mut Vec<MeshWarning>,
) -> Option<String> {
    let image = assets.array("images").get(j)?;
    let embedded = |bytes: Arc<[u8]>, files: &mut Vec<(PathBuf, ImageSource)>| {
        // The extension comes from a fixed list, never from the file's `mimeType`.
        let ext = match image_mime(&bytes) {
            Some("image/jpeg") => "jpg",
            Some(_) => "png",
            None => contain::image_extension(image["mimeType"].as_str().unwrap_or("")),
        };
        let name = format!("{stem}_image{j}.{ext}");
        files.push((PathBuf::from(&name), ImageSource::Bytes(bytes)));
        Some(name)
    };
    if let Some((_, bytes)) = assets.embedded_images.iter().find(|(i, _)| *i == j) {
        return embedded(bytes.clone(), files);
    }
    let uri = image["uri"].as_str()?;
    match data_uri(uri) {
        Some(Ok(bytes)) => return embedded(Arc::from(bytes), files),
        Some(Err(e)) => {
            warnings.push(MeshWarning::AttributesDropped {
                attributes: format!("glTF image {j}"),
                reason: e,
            });
            return None;
        }
        None => {}
    }
    if let Some(relative) = relative_uri(uri) {
        let from = match assets.image_files.iter().find(|(i, _)| *i == j) {
            Some((_, f)) => Ok(f.clone()),
            None => contain::resolve(&assets.source_dir, &assets.source_dir, &percent_decode(uri)),
        };
        let name = relative.to_string_lossy().replace('\\', "/");
        match from {
            Ok(from) => files.push((relative, ImageSource::Copy(from))),
            Err(e) => warnings.push(MeshWarning::ReferenceRefused {
                reference: format!("glTF image {j} ({uri})"),
                reason: format!("{e}; the material library names it without a copy"),
            }),
        }
        return Some(name);
    }
    // An absolute path or one leaving the input's folder: referenced where it is.
    if !uri.contains(':') || Path::new(&percent_decode(uri)).is_absolute() {
        let path = assets.source_dir.join(percent_decode(uri));
        return Some(path.to_string_lossy().into_owned());
    }
    warnings.push(MeshWarning::AttributesDropped {
        attributes: format!("glTF image {j} ({uri})"),
        reason: "an OBJ material library names local files only".into(),
    });
    None
}

/// Writes the image files of `plan` next to `output` (embedded ones under the names the plan
/// gave them; copied ones as [`contain::copy_beside`] does: under a new name, which the library
/// then names, when a different file of theirs is there) and then the library (replacing an
/// earlier run's); returns what could not be written and what was renamed.
pub(crate) fn write_mtl(plan: &ToMtl, output: &Path) -> Vec<MeshWarning> {
    use contain::write_beside;
    let out_dir = contain::folder_of(output);
    let stem = crate::io::side_files::output_stem(output);
    let mut warnings = Vec::new();
    let mut refused = |name: &Path, e: contain::Refused| {
        warnings.push(MeshWarning::ReferenceRefused {
            reference: format!("{} beside {}", name.display(), output.display()),
            reason: e.to_string(),
        });
    };
    let mut text = plan.text.clone();
    let mut renamed = Vec::new();
    for (name, source) in &plan.files {
        let result = match source {
            ImageSource::Copy(from) => contain::read_limited(from, contain::IMAGE_LIMIT)
                .and_then(|bytes| contain::copy_beside(out_dir, name, &bytes, &stem)),
            ImageSource::Bytes(bytes) => write_beside(out_dir, name, bytes).map(|()| name.clone()),
        };
        match result {
            Ok(written) if &written != name => {
                let (from, to) = (name.to_string_lossy(), written.to_string_lossy());
                text = crate::io::side_files::rename_texture(&text, &from, &to);
                renamed.push(MeshWarning::SideFileRenamed {
                    wanted: from.into_owned(),
                    written: to.into_owned(),
                });
            }
            Ok(_) => {}
            Err(e) => refused(name, e),
        }
    }
    let library = Path::new(&plan.library);
    if let Err(e) = write_beside(out_dir, library, text.as_bytes()) {
        refused(library, e);
    }
    warnings.extend(renamed);
    warnings
}

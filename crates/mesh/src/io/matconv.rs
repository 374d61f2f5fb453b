//! Materials across OBJ and glTF: an OBJ input's material libraries (MTL) become glTF
//! metallic-roughness materials in a glTF output ([`obj_to_gltf`]), and a glTF input's materials
//! become a material library next to an OBJ output ([`gltf_to_mtl`]), each with its base colour
//! texture, so that the output shows the same colours and texture. What one side has and the
//! other cannot express is named in one warning per output, never dropped silently.
//!
//! | MTL                        | glTF                                                      |
//! |----------------------------|-----------------------------------------------------------|
//! | `Kd r g b`                 | `baseColorFactor` rgb                                     |
//! | `d a` (or `Tr t`: a = 1−t) | `baseColorFactor` alpha; `alphaMode` `BLEND` when a < 1   |
//! | `map_Kd file`              | `baseColorTexture` (PNG or JPEG image)                    |
//! | `Pr r`, else `Ns n`        | `roughnessFactor` r, or √(2 / (n + 2)); 1 without either  |
//! | `Pm m`                     | `metallicFactor` m; 0 without it                          |
//! | `Ke r g b`                 | `emissiveFactor`                                          |
//!
//! The way back writes `Kd`, `d` (when `alphaMode` is not `OPAQUE` and alpha < 1), `Ns` from
//! the roughness (2 / r² − 2, at most 1000), `Pr`, `Pm`, `Ke` (when not black) and `map_Kd`.
//! Texture coordinates are flipped (`v → 1 − v`) when a texture crosses, as the two formats put
//! the image's origin at opposite edges.

use super::contain;
use super::gltf::{GltfAssets, data_uri, percent_decode, percent_encode, relative_uri};
use crate::attributes::Materials;
use crate::error::MeshWarning;
use serde_json::{Map, Value, json};
use std::collections::{BTreeSet, HashMap};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// The statements of one `newmtl` that are converted to glTF.
#[derive(Debug, Default, Clone, PartialEq)]
pub(crate) struct MtlMaterial {
    /// The `newmtl` name.
    pub name: String,
    /// `Kd` (diffuse colour).
    pub kd: Option<[f32; 3]>,
    /// Opacity: `d`, or `1 − Tr` when there is no `d`.
    pub opacity: Option<f32>,
    /// `Tr` seen (used when there is no `d`).
    tr: Option<f32>,
    /// `Ns` (specular exponent).
    pub ns: Option<f32>,
    /// `Pr` (roughness, PBR extension of MTL).
    pub pr: Option<f32>,
    /// `Pm` (metallic, PBR extension of MTL).
    pub pm: Option<f32>,
    /// `Ke` (emissive colour).
    pub ke: Option<[f32; 3]>,
    /// `map_Kd` file name (options removed), as written.
    pub map_kd: Option<String>,
}

/// The `map_*` options and how many values each takes (`-o`, `-s`, `-t` take one to three).
const MAP_OPTIONS: &[(&str, usize)] = &[
    ("-blendu", 1),
    ("-blendv", 1),
    ("-bm", 1),
    ("-boost", 1),
    ("-cc", 1),
    ("-clamp", 1),
    ("-imfchan", 1),
    ("-mm", 2),
    ("-o", 3),
    ("-s", 3),
    ("-t", 3),
    ("-texres", 1),
    ("-type", 1),
];

/// Parses material library text: the materials with their converted statements, and the
/// statements not converted (their keywords as written, `map_Kd` options as `map_Kd -s`;
/// values that do not parse as `Kd (unreadable)` and so on).
pub(crate) fn parse_mtl(text: &[u8]) -> (Vec<MtlMaterial>, BTreeSet<String>) {
    let text = String::from_utf8_lossy(text);
    let mut materials: Vec<MtlMaterial> = Vec::new();
    let mut dropped = BTreeSet::new();
    for line in text.lines() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (keyword, rest) = line
            .split_once(|c: char| c.is_ascii_whitespace())
            .map_or((line, ""), |(k, r)| (k, r.trim()));
        let lower = keyword.to_ascii_lowercase();
        if lower == "newmtl" {
            materials.push(MtlMaterial {
                name: rest.to_string(),
                ..MtlMaterial::default()
            });
            continue;
        }
        let Some(m) = materials.last_mut() else {
            dropped.insert(format!("{keyword} (before any newmtl)"));
            continue;
        };
        let floats = |n: usize| -> Option<Vec<f32>> {
            let v: Option<Vec<f32>> = rest
                .split_ascii_whitespace()
                .map(|t| t.parse().ok())
                .collect();
            v.filter(|v| v.len() == n || (n == 3 && v.len() == 1))
                .map(|v| {
                    if v.len() == 1 && n == 3 {
                        vec![v[0]; 3]
                    } else {
                        v
                    }
                })
        };
        let mut unreadable = || {
            dropped.insert(format!("{keyword} (unreadable values)"));
        };
        match lower.as_str() {
            "kd" | "ke" => match floats(3) {
                Some(v) if lower == "kd" => m.kd = Some([v[0], v[1], v[2]]),
                Some(v) => m.ke = Some([v[0], v[1], v[2]]),
                None => unreadable(),
            },
            "d" | "tr" | "ns" | "pr" | "pm" => match floats(1) {
                Some(v) => {
                    let x = v[0];
                    match lower.as_str() {
                        "d" => m.opacity = Some(x),
                        "tr" => m.tr = Some(x),
                        "ns" => m.ns = Some(x),
                        "pr" => m.pr = Some(x),
                        _ => m.pm = Some(x),
                    }
                }
                None => unreadable(),
            },
            "map_kd" => {
                let words: Vec<&str> = rest.split_ascii_whitespace().collect();
                let mut i = 0;
                while i < words.len() && words[i].starts_with('-') {
                    let option = words[i];
                    dropped.insert(format!("{keyword} option {option}"));
                    i += 1;
                    let takes = MAP_OPTIONS
                        .iter()
                        .find(|(o, _)| o.eq_ignore_ascii_case(option))
                        .map_or(0, |&(_, n)| n);
                    let numeric = matches!(option, "-o" | "-s" | "-t");
                    for _ in 0..takes {
                        if i >= words.len() - 1 || (numeric && words[i].parse::<f32>().is_err()) {
                            break;
                        }
                        i += 1;
                    }
                }
                let file = words[i.min(words.len())..].join(" ");
                if file.is_empty() {
                    dropped.insert(format!("{keyword} (no file)"));
                } else {
                    m.map_kd = Some(file);
                }
            }
            _ => {
                dropped.insert(keyword.to_string());
            }
        }
    }
    for m in &mut materials {
        if m.opacity.is_none() {
            m.opacity = m.tr.map(|t| 1.0 - t);
        }
    }
    (materials, dropped)
}

/// Roughness for an MTL specular exponent (the Blinn-Phong to microfacet rule of thumb
/// √(2 / (Ns + 2)), in [0, 1]).
fn roughness_of_ns(ns: f32) -> f32 {
    (2.0 / (ns.max(0.0) + 2.0)).sqrt().clamp(0.0, 1.0)
}

/// The specular exponent for a roughness (the inverse of [`roughness_of_ns`], at most 1000).
fn ns_of_roughness(r: f32) -> f32 {
    let r = r.clamp(0.0, 1.0);
    if r < 0.0447 {
        1000.0
    } else {
        (2.0 / (r * r) - 2.0).clamp(0.0, 1000.0)
    }
}

/// The MIME type of image bytes, told by their first bytes (glTF takes PNG and JPEG).
pub(crate) fn image_mime(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some("image/jpeg")
    } else {
        None
    }
}

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

/// Writes the library of `plan` next to `output` (replacing an earlier one) and its image files
/// (copied ones left alone when a file of that name is there; embedded ones written); returns
/// what could not be written.
pub(crate) fn write_mtl(plan: &ToMtl, output: &Path) -> Vec<MeshWarning> {
    use contain::{Existing, write_beside};
    let out_dir = contain::folder_of(output);
    let mut warnings = Vec::new();
    let mut refused = |name: &Path, e: contain::Refused| {
        warnings.push(MeshWarning::ReferenceRefused {
            reference: format!("{} beside {}", name.display(), output.display()),
            reason: e.to_string(),
        });
    };
    let library = Path::new(&plan.library);
    if let Err(e) = write_beside(out_dir, library, plan.text.as_bytes(), Existing::Replace) {
        refused(library, e);
    }
    for (name, source) in &plan.files {
        let result = match source {
            ImageSource::Copy(from) => contain::read_limited(from, contain::IMAGE_LIMIT)
                .and_then(|bytes| write_beside(out_dir, name, &bytes, Existing::Keep)),
            ImageSource::Bytes(bytes) => write_beside(out_dir, name, bytes, Existing::Replace),
        };
        if let Err(e) = result {
            refused(name, e);
        }
    }
    warnings
}

/// The base-colour texture of a mesh's materials ([`super::base_color_texture`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BaseColorTexture {
    /// The material it belongs to.
    pub material: String,
    /// Where the image comes from, for messages: the file, or `image J of the glTF` for an
    /// embedded one.
    pub source: String,
    /// The image file's bytes, or why they could not be read.
    pub bytes: Result<Arc<[u8]>, String>,
    /// Whether texture coordinate v = 0 is the image's top row (glTF) rather than its bottom
    /// row (OBJ): the texture coordinates are kept as the file stores them.
    pub v_down: bool,
}

/// The base-colour texture of the first material that has one (OBJ `map_Kd`, glTF
/// `pbrMetallicRoughness.baseColorTexture`), in the order of [`Materials::names`]; `None`
/// when no material names one. The image is read but not decoded.
pub fn base_color_texture(materials: &Materials) -> Option<BaseColorTexture> {
    if let Some(assets) = &materials.gltf {
        return gltf_base_color(materials, assets);
    }
    let mut defined: HashMap<String, (MtlMaterial, PathBuf)> = HashMap::new();
    for library in &materials.libraries {
        // An unreadable library was a warning when the mesh was loaded.
        let Ok(bytes) = contain::read_limited(library, contain::LIBRARY_LIMIT) else {
            continue;
        };
        let dir = library.parent().unwrap_or(Path::new("")).to_path_buf();
        for m in parse_mtl(&bytes).0 {
            defined
                .entry(m.name.clone())
                .or_insert_with(|| (m, dir.clone()));
        }
    }
    materials.names.iter().find_map(|name| {
        let (m, dir) = defined.get(name)?;
        let reference = m.map_kd.as_ref()?;
        Some(BaseColorTexture {
            material: name.clone(),
            source: dir.join(reference.replace('\\', "/")).display().to_string(),
            bytes: contain::read_contained(dir, dir, reference, contain::IMAGE_LIMIT)
                .map(|(_, bytes)| Arc::from(bytes))
                .map_err(|e| e.to_string()),
            v_down: false,
        })
    })
}

/// [`base_color_texture`] of a glTF input's materials.
fn gltf_base_color(materials: &Materials, assets: &GltfAssets) -> Option<BaseColorTexture> {
    (0..assets.material_count()).find_map(|i| {
        let m = &assets.array("materials")[i];
        let texture = m["pbrMetallicRoughness"]["baseColorTexture"]["index"].as_u64()?;
        let j = assets.array("textures").get(texture as usize)?["source"].as_u64()? as usize;
        let image = assets.array("images").get(j)?;
        let material = materials
            .names
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("material_{i}"));
        let embedded = format!("image {j} of the glTF");
        if let Some((_, bytes)) = assets.embedded_images.iter().find(|(k, _)| *k == j) {
            return Some(BaseColorTexture {
                material,
                source: embedded,
                bytes: Ok(bytes.clone()),
                v_down: true,
            });
        }
        let uri = image["uri"].as_str()?;
        if let Some(bytes) = data_uri(uri) {
            return Some(BaseColorTexture {
                material,
                source: embedded,
                bytes: bytes.map(Arc::from),
                v_down: true,
            });
        }
        Some(BaseColorTexture {
            material,
            source: assets
                .source_dir
                .join(percent_decode(uri))
                .display()
                .to_string(),
            bytes: super::gltf::read_image_file(assets, j, uri)
                .map(|(_, bytes)| Arc::from(bytes))
                .map_err(|e| e.to_string()),
            v_down: true,
        })
    })
}

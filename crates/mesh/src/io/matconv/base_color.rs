//! The base-colour texture of a mesh's materials, OBJ or glTF ([`base_color_texture`]), for
//! display.

use super::{MtlMaterial, parse_mtl};
use crate::attributes::Materials;
use crate::io::contain;
use crate::io::gltf::{GltfAssets, data_uri, percent_decode};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

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
            bytes: crate::io::gltf::read_image_file(assets, j, uri)
                .map(|(_, bytes)| Arc::from(bytes))
                .map_err(|e| e.to_string()),
            v_down: true,
        })
    })
}

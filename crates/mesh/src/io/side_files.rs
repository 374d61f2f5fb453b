//! The files a model's materials name, copied next to an output: material libraries and their
//! textures for an OBJ ([`copy_material_files`]), images for a glTF ([`copy_gltf_images`]).

use super::{Format, contain, gltf, matconv, obj};
use crate::attributes::Materials;
use crate::error::MeshWarning;
use std::path::Path;

/// Copies each material library of `materials` and the texture files it names (`map_*`, `bump`,
/// `disp`, `decal`, `refl`, `norm` lines; paths relative to the library) next to `output`, keeping
/// their relative paths; files already there are left alone. For a glTF input's materials, writes
/// the material library made from them (`<output stem>.mtl`, which the OBJ of
/// [`encode_with_attributes`](super::encode_with_attributes) names) and its texture images next to
/// `output` instead. [`save`](super::save) calls it for an OBJ
/// output; it is public for a caller writing the bytes of
/// [`encode_with_attributes`](super::encode_with_attributes) itself.
pub fn copy_material_files(materials: &Materials, output: &Path) -> Vec<MeshWarning> {
    use contain::{Existing, IMAGE_LIMIT, LIBRARY_LIMIT, read_contained, read_limited};
    if let Some(plan) = matconv::gltf_to_mtl(materials, output) {
        return matconv::write_mtl(&plan, output);
    }
    let mut warnings = Vec::new();
    let out_dir = contain::folder_of(output);
    // The containment rule on both sides: libraries (inside the model's folder since loading)
    // and the textures they name (inside the library's folder) are read as regular files of a
    // bounded size, and written only inside the output's folder.
    let mut copy = |what: String, name: &Path, read: Result<Vec<u8>, contain::Refused>| {
        if let Err(e) =
            read.and_then(|bytes| contain::write_beside(out_dir, name, &bytes, Existing::Keep))
        {
            warnings.push(MeshWarning::ReferenceRefused {
                reference: what,
                reason: format!("{e}; not copied next to {}", output.display()),
            });
        }
    };
    for library in &materials.libraries {
        let Some(name) = library.file_name() else {
            continue;
        };
        let text = read_limited(library, LIBRARY_LIMIT);
        let textures = text
            .as_ref()
            .map(|t| obj::mtl_textures(t))
            .unwrap_or_default();
        copy(
            format!("material library {}", library.display()),
            Path::new(name),
            text,
        );
        let lib_dir = contain::folder_of(library);
        for texture in textures {
            let relative = Path::new(&texture);
            // Absolute paths and paths leaving the folder are referenced as they are.
            if relative.is_absolute()
                || relative
                    .components()
                    .any(|c| matches!(c, std::path::Component::ParentDir))
            {
                continue;
            }
            let read = read_contained(lib_dir, lib_dir, &texture, IMAGE_LIMIT).map(|(_, b)| b);
            copy(format!("texture {texture}"), relative, read);
        }
    }
    warnings
}

/// Copies the images of a glTF input ([`Materials::gltf`]) that it names by relative URIs next to
/// `output`, keeping their relative paths; files already there are left alone (what
/// [`save`](super::save) does for a `.gltf` or `.glb`, for a caller
/// writing the bytes of [`encode_with_attributes`](super::encode_with_attributes) itself).
///
/// For OBJ materials written to a `.gltf`, copies the textures of their material libraries that
/// the converted materials name by relative URIs (a `.glb` embeds them: nothing to copy).
pub fn copy_gltf_images(materials: &Materials, output: &Path) -> Vec<MeshWarning> {
    if let Some(assets) = &materials.gltf {
        return gltf::copy_images(assets, output);
    }
    if Format::from_path(output) == Some(Format::Glb) {
        return Vec::new();
    }
    // What could not be read was reported when the glTF was encoded.
    matconv::obj_to_gltf(materials, false)
        .and_then(|c| c.materials.gltf)
        .map(|assets| gltf::copy_images(&assets, output))
        .unwrap_or_default()
}

//! The files a model's materials name, copied next to an output: material libraries and their
//! textures for an OBJ ([`copy_material_files`]), images for a glTF ([`copy_gltf_images`]).

use super::{Format, contain, gltf, matconv, obj};
use crate::attributes::Materials;
use crate::error::MeshWarning;
use std::path::Path;

/// The file names an OBJ `output` gives the material libraries of `materials` (an OBJ input's):
/// `<output stem>.mtl`, then `<stem>-2.mtl`, ...: names the tool chooses and writes for this
/// output, so an output never points at a library that was already in its folder. A name that
/// is one of the input's own libraries is passed over (an output never replaces what its input
/// references).
pub(crate) fn library_names(materials: &Materials, output: &Path) -> Vec<String> {
    let stem = output_stem(output);
    let out_dir = contain::folder_of(output);
    let inputs: Vec<_> = materials
        .libraries
        .iter()
        .filter_map(|l| l.canonicalize().ok())
        .collect();
    let is_input = |name: &str| {
        out_dir
            .join(name)
            .canonicalize()
            .is_ok_and(|p| inputs.contains(&p))
    };
    let mut names: Vec<String> = Vec::new();
    let mut k = 1;
    while names.len() < materials.libraries.len() {
        let name = match k {
            1 => format!("{stem}.mtl"),
            _ => format!("{stem}-{k}.mtl"),
        };
        k += 1;
        if !is_input(&name) {
            names.push(name);
        }
    }
    names
}

/// `output`'s file stem, the prefix of the side files the tool names for it.
pub(crate) fn output_stem(output: &Path) -> String {
    output
        .file_stem()
        .map_or_else(|| "materials".into(), |s| s.to_string_lossy().into_owned())
}

/// `text` of a material library with the texture `from` named `to` (the last word of texture
/// lines: `map_*`, `bump`, `disp`, `decal`, `refl`, `norm`).
pub(crate) fn rename_texture(text: &str, from: &str, to: &str) -> String {
    let mut out = String::with_capacity(text.len() + to.len());
    for line in text.split_inclusive('\n') {
        // The last word as `obj::mtl_textures` reads it (trailing blanks aside).
        let body = line.trim_end();
        let keyword = body.split_ascii_whitespace().next().unwrap_or("");
        let texture = obj::names_texture(keyword);
        match body.rsplit_once(char::is_whitespace) {
            Some((head, last)) if texture && last == from => {
                out.push_str(head);
                out.push(' ');
                out.push_str(to);
                out.push_str(&line[body.len()..]);
            }
            _ => out.push_str(line),
        }
    }
    out
}

/// Writes the material libraries of `materials` next to `output` under the names
/// `<output stem>.mtl`, `<stem>-2.mtl`, ... (replacing an earlier run's), and copies the texture files they
/// name (`map_*`, `bump`, `disp`, `decal`, `refl`, `norm` lines; paths relative to the library)
/// keeping their relative paths: a file of that name already there is used only when it holds
/// the same bytes, otherwise the texture is written under a new name, the library names that,
/// and a warning says so. For a glTF input's materials, writes the
/// material library made from them (`<output stem>.mtl`, which the OBJ of
/// [`encode_with_attributes`](super::encode_with_attributes) names) and its texture images next
/// to `output` instead. [`save`](super::save) calls it for an OBJ output; it is public for a
/// caller writing the bytes of [`encode_with_attributes`](super::encode_with_attributes) itself.
pub fn copy_material_files(materials: &Materials, output: &Path) -> Vec<MeshWarning> {
    use contain::{IMAGE_LIMIT, LIBRARY_LIMIT, read_contained, read_limited};
    if let Some(plan) = matconv::gltf_to_mtl(materials, output) {
        return matconv::write_mtl(&plan, output);
    }
    let mut warnings = Vec::new();
    let out_dir = contain::folder_of(output);
    let stem = output_stem(output);
    // The containment rule on both sides: libraries (inside the model's folder since loading)
    // and the textures they name (inside the library's folder) are read as regular files of a
    // bounded size, and written only inside the output's folder.
    let mut refused = |what: String, e: contain::Refused| {
        warnings.push(MeshWarning::ReferenceRefused {
            reference: what,
            reason: format!("{e}; not copied next to {}", output.display()),
        });
    };
    let mut renamed = Vec::new();
    for (library, name) in materials
        .libraries
        .iter()
        .zip(library_names(materials, output))
    {
        let what = format!("material library {}", library.display());
        let text = match read_limited(library, LIBRARY_LIMIT) {
            Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
            Err(e) => {
                refused(what, e);
                continue;
            }
        };
        let mut written = text.clone();
        let lib_dir = contain::folder_of(library);
        for texture in obj::mtl_textures(text.as_bytes()) {
            let relative = Path::new(&texture);
            // Absolute paths and paths leaving the folder are referenced as they are.
            if relative.is_absolute()
                || relative
                    .components()
                    .any(|c| matches!(c, std::path::Component::ParentDir))
            {
                continue;
            }
            let copied = read_contained(lib_dir, lib_dir, &texture, IMAGE_LIMIT)
                .and_then(|(_, bytes)| contain::copy_beside(out_dir, relative, &bytes, &stem));
            match copied {
                Ok(as_written) if as_written != relative => {
                    let to = as_written.to_string_lossy().replace('\\', "/");
                    written = rename_texture(&written, &texture, &to);
                    renamed.push(MeshWarning::SideFileRenamed {
                        wanted: texture.clone(),
                        written: to,
                    });
                }
                Ok(_) => {}
                Err(e) => refused(format!("texture {texture}"), e),
            }
        }
        if let Err(e) = contain::write_beside(out_dir, Path::new(&name), written.as_bytes()) {
            refused(what, e);
        }
    }
    warnings.extend(renamed);
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

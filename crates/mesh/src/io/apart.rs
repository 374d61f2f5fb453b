//! Outputs never replace inputs: before any work, a front end hands every path it will write to
//! [`LoadedMesh::check_outputs`], which compares every file those writes create or replace
//! ([`written_files`]: the mesh, a `.gltf`'s `.bin`, the material library and images made for
//! an OBJ) with every file the input was read from or names (the model, its buffers, its
//! material libraries and their textures, its images), by canonical path and, on Unix, by
//! device and inode (hard links). `gng3d simplify` (each `--lods` level too), `gng3d batch`
//! through it, and Python's `simplify_file` call it.

use super::{Format, LoadedMesh, contain, gltf, matconv, obj};
use crate::attributes::Materials;
use crate::error::MeshError;
use std::path::{Path, PathBuf};

/// The name of the buffer file written next to the `.gltf` `path` (`<stem>.bin`).
pub(crate) fn bin_name(path: &Path) -> String {
    path.file_stem().map_or_else(
        || "buffer.bin".to_string(),
        |s| format!("{}.bin", s.to_string_lossy()),
    )
}

/// Every file that saving a mesh with `materials` to `path` creates or replaces: `path`, a
/// `.gltf`'s `<stem>.bin`, and for an OBJ of glTF materials the material library and the
/// embedded images written for it. (Material libraries and textures copied next to an output are
/// left alone where a file of that name exists, so they never replace anything.)
pub fn written_files(path: &Path, materials: Option<&Materials>) -> Vec<PathBuf> {
    let mut out = vec![path.to_path_buf()];
    match Format::from_path(path) {
        Some(Format::Gltf) => out.push(path.with_file_name(bin_name(path))),
        Some(Format::Obj) => {
            if let Some(plan) = materials.and_then(|m| matconv::gltf_to_mtl(m, path)) {
                let dir = contain::folder_of(path);
                out.push(dir.join(&plan.library));
                out.extend(
                    plan.files
                        .iter()
                        .filter(|(_, source)| matches!(source, matconv::ImageSource::Bytes(_)))
                        .map(|(name, _)| dir.join(name)),
                );
            }
        }
        _ => {}
    }
    out
}

impl LoadedMesh {
    /// Every file this mesh was read from or names that exists: [`LoadedMesh::files`], its
    /// material libraries and the textures they name, and the images of a glTF named by URI.
    pub fn input_files(&self) -> Vec<PathBuf> {
        let mut out = self.files.clone();
        if let Some(m) = &self.materials {
            for library in &m.libraries {
                out.push(library.clone());
                let dir = contain::folder_of(library);
                if let Ok(text) = contain::read_limited(library, contain::LIBRARY_LIMIT) {
                    out.extend(
                        obj::mtl_textures(&text)
                            .iter()
                            .filter_map(|t| contain::resolve(dir, dir, t).ok()),
                    );
                }
            }
            if let Some(assets) = &m.gltf {
                out.extend(gltf::image_files(assets));
            }
        }
        out.retain(|p| p.exists());
        out
    }

    /// Refuses, before any work, `outputs` whose writes ([`written_files`]) would create or
    /// replace a file of [`LoadedMesh::input_files`]: a [`MeshError::Write`] naming the output
    /// and the input file, and nothing is written. Two outputs that would write the same file
    /// are refused too.
    pub fn check_outputs(&self, outputs: &[&Path]) -> Result<(), MeshError> {
        let inputs: Vec<(PathBuf, Identity)> = self
            .input_files()
            .into_iter()
            .filter_map(|p| identity(&p).map(|id| (p, id)))
            .collect();
        let mut written: Vec<(PathBuf, &Path, Identity)> = Vec::new();
        for &output in outputs {
            let materials = self.materials.as_ref();
            for file in written_files(output, materials) {
                let Some(id) = identity(&file) else { continue };
                let refuse = |message: String| MeshError::Write {
                    path: output.to_path_buf(),
                    message,
                };
                if let Some((input, _)) = inputs.iter().find(|(_, i)| i.same(&id)) {
                    let role = if self.files.first() == Some(input) {
                        "the input itself"
                    } else {
                        "a file the input reads"
                    };
                    return Err(refuse(format!(
                        "writing it would replace {} ({role}); nothing written, choose another \
                         output name or folder",
                        input.display()
                    )));
                }
                if let Some((other_file, other, _)) = written.iter().find(|(_, _, w)| w.same(&id)) {
                    return Err(refuse(format!(
                        "it would write {} that {} also writes; nothing written",
                        other_file.display(),
                        other.display()
                    )));
                }
                written.push((file, output, id));
            }
        }
        Ok(())
    }
}

/// What names one file: its canonical path (of the folder, for a file not there yet) and, for
/// an existing file on Unix, its device and inode.
struct Identity {
    path: PathBuf,
    inode: Option<(u64, u64)>,
}

impl Identity {
    fn same(&self, other: &Identity) -> bool {
        self.path == other.path || (self.inode.is_some() && self.inode == other.inode)
    }
}

fn identity(path: &Path) -> Option<Identity> {
    let canonical = match path.canonicalize() {
        Ok(p) => p,
        Err(_) => contain::folder_of(path)
            .canonicalize()
            .ok()?
            .join(path.file_name()?),
    };
    #[cfg(unix)]
    let inode = {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata(&canonical)
            .ok()
            .map(|m| (m.dev(), m.ino()))
    };
    #[cfg(not(unix))]
    let inode = None;
    Some(Identity {
        path: canonical,
        inode,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::icosphere;

    #[test]
    fn outputs_that_would_replace_an_input_or_each_other_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("scene.gltf");
        super::super::save(&icosphere(1).into(), &input).unwrap();
        let loaded = super::super::load(&input).unwrap();
        assert_eq!(loaded.input_files().len(), 2, "{:?}", loaded.input_files());
        let err = |outs: &[&Path]| loaded.check_outputs(outs).unwrap_err().to_string();
        // The input itself, by another spelling.
        let again = dir.path().join(".").join("scene.gltf");
        assert!(err(&[&again]).contains("(the input itself)"));
        // Another .gltf whose .bin is the input's buffer.
        let e = err(&[&dir.path().join(".").join("scene.GLTF")]);
        assert!(e.contains("scene.bin (a file the input reads)"), "{e}");
        // Two outputs writing one file (m.gltf and m.GLTF both write m.bin).
        let e = err(&[&dir.path().join("m.gltf"), &dir.path().join("m.GLTF")]);
        assert!(e.contains("m.bin that") && e.contains("also writes"), "{e}");
        // Elsewhere is fine.
        loaded
            .check_outputs(&[&dir.path().join("out.gltf"), &dir.path().join("out.ply")])
            .unwrap();
        #[cfg(unix)]
        {
            let link = dir.path().join("hard.gltf");
            std::fs::hard_link(&input, &link).unwrap();
            assert!(err(&[&link]).contains("the input itself"));
        }
    }
}

//! The glTF description held by [`Materials`](super::Materials): what a glTF file holds besides
//! geometry ([`GltfAssets`]), carried unchanged from a glTF input to a glTF output. Read and
//! written by `crate::io`, which also names it `crate::io::GltfAssets`.

use serde_json::{Map, Value};
use std::path::PathBuf;
use std::sync::Arc;

/// The parts of a glTF file that are not geometry, carried from a glTF input to a glTF output
/// unchanged, so that the output looks the same in a viewer: the `asset` record, `materials`,
/// `textures`, `images` and `samplers` as they were in the file, and the names in
/// `extensionsUsed` / `extensionsRequired` that these objects use. Images stored in buffer views
/// are kept as bytes and embedded again in the output; images named by a relative URI are copied
/// next to the output ([`crate::io::save`]).
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct GltfAssets {
    /// The carried JSON members (`asset`, `materials`, `textures`, `images`, `samplers`,
    /// `extensionsUsed`, `extensionsRequired`); images that were in buffer views have no
    /// `bufferView` here.
    pub(crate) json: Map<String, Value>,
    /// The bytes of the images that were in buffer views, by image index.
    pub(crate) embedded_images: Vec<(usize, Arc<[u8]>)>,
    /// The folder of the input file, against which relative image URIs are resolved.
    pub(crate) source_dir: PathBuf,
    /// Files to copy for images named by a relative URI, by image index, where they do not lie
    /// at that URI in `source_dir` (materials converted from OBJ material libraries).
    pub(crate) image_files: Vec<(usize, PathBuf)>,
}

impl GltfAssets {
    /// Number of glTF materials (indices `0..material_count()` of
    /// [`Attributes::face_material`](crate::attributes::Attributes::face_material) are these
    /// materials; a higher index is a primitive that had none).
    pub fn material_count(&self) -> usize {
        self.array("materials").len()
    }

    /// Number of images (embedded or named by a URI).
    pub fn image_count(&self) -> usize {
        self.array("images").len()
    }

    /// The carried JSON members, as they will be written: `asset`, `materials`, `textures`,
    /// `images`, `samplers`, `extensionsUsed`, `extensionsRequired` (those present). An image
    /// that was stored in a buffer view has no `bufferView` member here; the writer adds one.
    pub fn json(&self) -> &Map<String, Value> {
        &self.json
    }

    /// The array member `key` of the carried JSON (empty when absent).
    pub(crate) fn array(&self, key: &str) -> &[Value] {
        self.json
            .get(key)
            .and_then(Value::as_array)
            .map_or(&[], Vec::as_slice)
    }
}

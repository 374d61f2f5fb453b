//! glTF 2.0 reader and writer: `.gltf` (JSON with external `.bin` buffers or `data:` URIs) and
//! `.glb` (binary container).
//!
//! Reading: the JSON document is parsed and validated by the `gltf` crate (every index a glTF
//! object uses refers to an object that exists); the GLB container, the buffers and the accessors
//! are read here, every byte range checked, so a broken file is an error naming it and never a
//! panic. Every triangle primitive of every mesh that the default scene's nodes instance (the
//! first scene when none is the default; every mesh once when there is no scene) is placed in
//! world space and joined into one mesh. A glTF vertex is one wedge ([`Attributes`]); the
//! vertices become position vertices through the weld ([`crate::clean::weld_exact_map`]), so
//! a UV or normal seam is two wedges of one vertex and touching sheets stay apart.
//!
//! Writing: one mesh, one node, one primitive per material, all sharing one set of vertex
//! accessors (one glTF vertex per wedge). What is not geometry (materials, textures, images,
//! samplers, the asset record and the extensions they use) comes from the input glTF
//! ([`GltfAssets`]) unchanged.

use super::RawMesh;
use crate::TriMesh;
use crate::attributes::{Attributes, Materials};
use crate::error::{MeshError, MeshWarning};
use ::gltf::accessor::DataType;
use glam::{DMat4, DVec3, Mat3, Mat4, Vec2, Vec3, Vec4};
use serde_json::{Map, Value, json};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The first four bytes of a GLB file.
const GLB_MAGIC: &[u8; 4] = b"glTF";
/// GLB chunk type of the JSON chunk ("JSON").
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// GLB chunk type of the binary chunk ("BIN\0").
const CHUNK_BIN: u32 = 0x004E_4942;

/// Extensions that compress the geometry, which this reader does not decode.
const COMPRESSION: &[&str] = &[
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
    "KHR_meshopt_compression",
];

/// Extensions that place or repeat the geometry, which this reader does not apply.
const GEOMETRY: &[&str] = &["EXT_mesh_gpu_instancing"];

/// Required extensions this reader implements (quantised attributes) or carries to a glTF
/// output unchanged (material and texture extensions), by name or prefix.
const UNDERSTOOD: &[&str] = &[
    "KHR_mesh_quantization",
    "KHR_materials_",
    "KHR_texture_",
    "EXT_texture_",
];

/// The attributes read from a primitive; all others are reported as ignored.
const READ_ATTRIBUTES: [&str; 5] = ["POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0"];

/// The parts of a glTF file that are not geometry, carried from a glTF input to a glTF output
/// unchanged, so that the output looks the same in a viewer: the `asset` record, `materials`,
/// `textures`, `images` and `samplers` as they were in the file, and the names in
/// `extensionsUsed` / `extensionsRequired` that these objects use. Images stored in buffer views
/// are kept as bytes and embedded again in the output; images named by a relative URI are copied
/// next to the output ([`super::save_with_attributes`]).
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct GltfAssets {
    /// The carried JSON members (`asset`, `materials`, `textures`, `images`, `samplers`,
    /// `extensionsUsed`, `extensionsRequired`); images that were in buffer views have no
    /// `bufferView` here.
    pub(super) json: Map<String, Value>,
    /// The bytes of the images that were in buffer views, by image index.
    pub(super) embedded_images: Vec<(usize, Arc<[u8]>)>,
    /// The folder of the input file, against which relative image URIs are resolved.
    pub(super) source_dir: PathBuf,
    /// Files to copy for images named by a relative URI, by image index, where they do not lie
    /// at that URI in `source_dir` (materials converted from OBJ material libraries).
    pub(super) image_files: Vec<(usize, PathBuf)>,
}

impl GltfAssets {
    /// Number of glTF materials (indices `0..material_count()` of
    /// [`Attributes::face_material`] are these materials; a higher index is a primitive that had
    /// none).
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
    pub(super) fn array(&self, key: &str) -> &[Value] {
        self.json
            .get(key)
            .and_then(Value::as_array)
            .map_or(&[], Vec::as_slice)
    }
}

/// Split a GLB container into its JSON chunk and its optional BIN chunk.
fn split_glb<'a>(bytes: &'a [u8], path: &Path) -> Result<(&'a [u8], Option<&'a [u8]>), MeshError> {
    let u32_at =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    if bytes.len() < 12 {
        return Err(MeshError::parse(
            path,
            "GLB header",
            format!(
                "the file has {} bytes, fewer than the 12-byte header",
                bytes.len()
            ),
        ));
    }
    let version = u32_at(4);
    if version != 2 {
        return Err(MeshError::parse(
            path,
            "GLB header",
            format!("GLB version {version}; only glTF 2.0 (version 2) is read"),
        ));
    }
    let length = u32_at(8) as usize;
    if length > bytes.len() || length < 12 {
        return Err(MeshError::parse(
            path,
            "GLB header",
            format!(
                "the header gives a length of {length} bytes, but the file has {} (truncated?)",
                bytes.len()
            ),
        ));
    }
    let mut at = 12;
    let mut json: Option<&[u8]> = None;
    let mut bin: Option<&[u8]> = None;
    while at < length {
        if at + 8 > length {
            return Err(MeshError::parse(
                path,
                format!("byte {at}"),
                "a chunk header runs past the end of the file (truncated?)",
            ));
        }
        let chunk_length = u32_at(at) as usize;
        let kind = u32_at(at + 4);
        let start = at + 8;
        let end = start.checked_add(chunk_length).filter(|&e| e <= length);
        let Some(end) = end else {
            return Err(MeshError::parse(
                path,
                format!("byte {at}"),
                format!(
                    "a chunk of {chunk_length} bytes runs past the end of the file at {length} bytes \
                     (truncated?)"
                ),
            ));
        };
        match kind {
            CHUNK_JSON if json.is_none() && at == 12 => json = Some(&bytes[start..end]),
            CHUNK_BIN if bin.is_none() && json.is_some() => bin = Some(&bytes[start..end]),
            _ => {}
        }
        at = end;
    }
    let json = json.ok_or_else(|| {
        MeshError::parse(path, "byte 12", "the first GLB chunk is not the JSON chunk")
    })?;
    Ok((json, bin))
}

/// Decode standard base64 (with or without padding); `None` on a character outside the alphabet.
fn base64_decode(text: &str) -> Option<Vec<u8>> {
    let text = text.trim_end_matches('=');
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in text.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return None,
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// Encode bytes as standard base64 with padding.
fn base64_encode(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Decode `%XX` escapes of a URI (invalid escapes are kept as written).
pub(super) fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && i + 2 < bytes.len()
            && let Some(v) = std::str::from_utf8(&bytes[i + 1..i + 3])
                .ok()
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        {
            out.push(v);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Escape the characters of a file name that may not stand in a URI as they are.
pub(super) fn percent_encode(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for b in name.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// The payload of a `data:` URI (base64 only).
pub(super) fn data_uri(uri: &str) -> Option<Result<Vec<u8>, String>> {
    let rest = uri.strip_prefix("data:")?;
    Some(match rest.split_once(',') {
        Some((meta, payload)) if meta.ends_with(";base64") => {
            base64_decode(payload).ok_or_else(|| "the data: URI is not valid base64".to_string())
        }
        _ => Err("only base64 data: URIs are read".to_string()),
    })
}

/// A relative URI as a path inside `dir`, or `None` for an absolute path or one leaving `dir`
/// (which are not copied).
pub(super) fn relative_uri(uri: &str) -> Option<PathBuf> {
    if uri.contains(':') {
        return None;
    }
    let relative = PathBuf::from(percent_decode(uri));
    let inside = !relative.is_absolute()
        && !relative
            .components()
            .any(|c| matches!(c, std::path::Component::ParentDir));
    inside.then_some(relative)
}

/// The decoded document with its buffers, for reading accessors.
struct Source<'a> {
    /// The validated document.
    doc: &'a ::gltf::Document,
    /// Each buffer's bytes, or why they could not be read.
    buffers: Vec<Result<Vec<u8>, String>>,
    /// The file, for the messages.
    path: &'a Path,
}

impl Source<'_> {
    fn error(&self, location: impl Into<String>, message: impl Into<String>) -> MeshError {
        MeshError::parse(self.path, location, message)
    }

    /// The bytes of buffer view `view`, range-checked against its buffer.
    fn view_bytes(&self, view: &::gltf::buffer::View) -> Result<&[u8], MeshError> {
        let b = view.buffer().index();
        let data = self.buffers[b]
            .as_ref()
            .map_err(|e| self.error(format!("buffer {b}"), e.clone()))?;
        let (start, length) = (view.offset(), view.length());
        start
            .checked_add(length)
            .and_then(|end| data.get(start..end))
            .ok_or_else(|| {
                self.error(
                    format!("buffer view {}", view.index()),
                    format!(
                        "bytes {start}..{} lie outside buffer {b}, which has {} bytes",
                        start.saturating_add(length),
                        data.len()
                    ),
                )
            })
    }

    /// The bytes of buffer view `view` and its stride, checked to hold `count` elements of
    /// `element` bytes from `offset` (strided by the view's `byteStride`, or packed).
    fn range<'v>(
        &'v self,
        what: &str,
        view: &::gltf::buffer::View,
        offset: usize,
        count: usize,
        element: usize,
    ) -> Result<(&'v [u8], usize), MeshError> {
        let data = self.view_bytes(view)?;
        let stride = view.stride().unwrap_or(element);
        if stride < element {
            return Err(self.error(
                what,
                format!(
                    "byteStride {stride} of buffer view {} is smaller than an element ({element} \
                     bytes)",
                    view.index()
                ),
            ));
        }
        if count == 0 {
            return Ok((data, stride));
        }
        let end = (count - 1)
            .checked_mul(stride)
            .and_then(|n| n.checked_add(offset))
            .and_then(|n| n.checked_add(element));
        match end {
            Some(end) if end <= data.len() => Ok((data, stride)),
            _ => Err(self.error(
                what,
                format!(
                    "{count} elements of {element} bytes from byte {offset} (stride {stride}) do \
                     not fit in buffer view {}, which has {} bytes",
                    view.index(),
                    data.len()
                ),
            )),
        }
    }

    /// Calls `f` with the bytes of each of `count` elements of `element` bytes at `offset` in
    /// `view` ([`Source::range`]).
    fn elements(
        &self,
        what: &str,
        view: &::gltf::buffer::View,
        offset: usize,
        count: usize,
        element: usize,
        mut f: impl FnMut(usize, &[u8]),
    ) -> Result<(), MeshError> {
        let (data, stride) = self.range(what, view, offset, count, element)?;
        for i in 0..count {
            let at = offset + i * stride;
            f(i, &data[at..at + element]);
        }
        Ok(())
    }

    /// Checks, before anything is allocated for them, that the `count` elements of `element`
    /// bytes of `accessor` exist: in its buffer view, or (without one: zeros, or sparse values
    /// only) no more than the file's buffers could describe, so that a count in the JSON alone
    /// cannot ask for any amount of memory.
    fn check_count(
        &self,
        accessor: &::gltf::Accessor,
        what: &str,
        element: usize,
    ) -> Result<(), MeshError> {
        let count = accessor.count();
        match accessor.view() {
            Some(view) => self
                .range(what, &view, accessor.offset(), count, element)
                .map(|_| ()),
            None => {
                let bytes: usize = self.buffers.iter().flatten().map(Vec::len).sum();
                if count > bytes.max(1 << 24) {
                    Err(self.error(
                        what,
                        format!(
                            "{count} elements without a buffer view, more than the file's buffers \
                             ({bytes} bytes) could hold"
                        ),
                    ))
                } else {
                    Ok(())
                }
            }
        }
    }

    /// The values of `accessor` as `f32`s, `dims` per element (normalized integers mapped to
    /// [0, 1] or [-1, 1] as the glTF specification says; other integers as they are), with
    /// sparse substitution.
    fn floats(
        &self,
        accessor: &::gltf::Accessor,
        what: &str,
        dims: &[usize],
    ) -> Result<(Vec<f32>, usize), MeshError> {
        let what = format!("accessor {} ({what})", accessor.index());
        let n = accessor.dimensions().multiplicity();
        if !dims.contains(&n) {
            return Err(self.error(
                &what,
                format!(
                    "{:?} elements; expected {}",
                    accessor.dimensions(),
                    dims.iter()
                        .map(|d| format!("{d} components"))
                        .collect::<Vec<_>>()
                        .join(" or ")
                ),
            ));
        }
        let ty = accessor.data_type();
        let normalized = accessor.normalized();
        let size = ty.size();
        let count = accessor.count();
        self.check_count(accessor, &what, n * size)?;
        let mut out = vec![0f32; count * n];
        let decode = |bytes: &[u8], out: &mut [f32]| {
            for (k, o) in out.iter_mut().enumerate() {
                *o = component(&bytes[k * size..(k + 1) * size], ty, normalized);
            }
        };
        if let Some(view) = accessor.view() {
            self.elements(&what, &view, accessor.offset(), count, n * size, |i, e| {
                decode(e, &mut out[i * n..(i + 1) * n])
            })?;
        }
        if let Some(sparse) = accessor.sparse() {
            let indices = self.sparse_indices(&sparse, &what, count)?;
            let values = sparse.values();
            self.elements(
                &what,
                &values.view(),
                values.offset(),
                indices.len(),
                n * size,
                |i, e| {
                    let at = indices[i] as usize;
                    decode(e, &mut out[at * n..(at + 1) * n])
                },
            )?;
        }
        Ok((out, n))
    }

    /// The indices of a sparse accessor, checked against `count`.
    fn sparse_indices(
        &self,
        sparse: &::gltf::accessor::sparse::Sparse,
        what: &str,
        count: usize,
    ) -> Result<Vec<u32>, MeshError> {
        use ::gltf::accessor::sparse::IndexType;
        let indices = sparse.indices();
        let ty = match indices.index_type() {
            IndexType::U8 => DataType::U8,
            IndexType::U16 => DataType::U16,
            IndexType::U32 => DataType::U32,
        };
        let mut out = Vec::new();
        self.elements(
            what,
            &indices.view(),
            indices.offset(),
            sparse.count(),
            ty.size(),
            |_, e| out.push(unsigned(e, ty)),
        )?;
        if let Some(&bad) = out.iter().find(|&&i| i as usize >= count) {
            return Err(self.error(
                what,
                format!("sparse index {bad} is beyond its {count} elements"),
            ));
        }
        Ok(out)
    }

    /// The values of an index accessor (unsigned byte, short or int scalars).
    fn indices(&self, accessor: &::gltf::Accessor, what: &str) -> Result<Vec<u32>, MeshError> {
        let what = format!("accessor {} ({what})", accessor.index());
        let ty = accessor.data_type();
        if accessor.dimensions() != ::gltf::accessor::Dimensions::Scalar
            || !matches!(ty, DataType::U8 | DataType::U16 | DataType::U32)
        {
            return Err(self.error(
                &what,
                format!(
                    "indices must be unsigned byte, short or int scalars, not {:?} {:?}",
                    ty,
                    accessor.dimensions()
                ),
            ));
        }
        self.check_count(accessor, &what, ty.size())?;
        let mut out = vec![0u32; accessor.count()];
        if let Some(view) = accessor.view() {
            self.elements(
                &what,
                &view,
                accessor.offset(),
                out.len(),
                ty.size(),
                |i, e| out[i] = unsigned(e, ty),
            )?;
        }
        if let Some(sparse) = accessor.sparse() {
            let at = self.sparse_indices(&sparse, &what, out.len())?;
            let values = sparse.values();
            self.elements(
                &what,
                &values.view(),
                values.offset(),
                at.len(),
                ty.size(),
                |i, e| out[at[i] as usize] = unsigned(e, ty),
            )?;
        }
        Ok(out)
    }
}

/// An unsigned integer component (little-endian).
fn unsigned(bytes: &[u8], ty: DataType) -> u32 {
    match ty {
        DataType::U8 => u32::from(bytes[0]),
        DataType::U16 => u32::from(u16::from_le_bytes([bytes[0], bytes[1]])),
        _ => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
    }
}

/// One component as `f32` (little-endian), normalized integers scaled as the glTF
/// specification says.
fn component(bytes: &[u8], ty: DataType, normalized: bool) -> f32 {
    match ty {
        DataType::F32 => f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
        DataType::I8 => {
            let v = f32::from(bytes[0] as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        DataType::U8 => {
            let v = f32::from(bytes[0]);
            if normalized { v / 255.0 } else { v }
        }
        DataType::I16 => {
            let v = f32::from(i16::from_le_bytes([bytes[0], bytes[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = f32::from(u16::from_le_bytes([bytes[0], bytes[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        DataType::U32 => {
            let v = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f32;
            if normalized { v / u32::MAX as f32 } else { v }
        }
    }
}

/// The glTF vertices read so far (one wedge each), in world space.
#[derive(Default)]
struct Vertices {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uv0: Vec<Vec2>,
    uv1: Vec<Vec2>,
    colors: Vec<Vec4>,
    /// Vertices of vertex sets without NORMAL / TEXCOORD_0 / TEXCOORD_1 / COLOR_0.
    missing: [usize; 4],
    /// Whether any vertex set has NORMAL / TEXCOORD_0 / TEXCOORD_1 / COLOR_0.
    present: [bool; 4],
}

/// Parse a `.gltf` or `.glb` file (told apart by the GLB magic bytes; when `binary`, content
/// that is neither is reported as a broken GLB header); external buffers are resolved against
/// the folder of `path`, except a buffer whose URI names `side` (file name, bytes): it is read
/// from those bytes (the `.bin` of a `.gltf` being written, checked before either file exists).
pub(crate) fn parse(
    bytes: &[u8],
    path: &Path,
    binary: bool,
    side: Option<SideBuffer>,
    origin: DVec3,
) -> Result<RawMesh, MeshError> {
    let (json_bytes, bin) = if bytes.starts_with(GLB_MAGIC) {
        split_glb(bytes, path)?
    } else if binary && bytes.trim_ascii_start().first() != Some(&b'{') {
        return Err(MeshError::parse(
            path,
            "GLB header",
            format!(
                "not a GLB file: it does not start with \"glTF\" ({} bytes; truncated?)",
                bytes.len()
            ),
        ));
    } else {
        (bytes, None)
    };
    let value: Value = serde_json::from_slice(json_bytes)
        .map_err(|e| MeshError::parse(path, "JSON", e.to_string()))?;
    let Value::Object(root_json) = value else {
        return Err(MeshError::parse(
            path,
            "JSON",
            "the document is not a JSON object",
        ));
    };
    let mut warnings = Vec::new();
    let names = |key: &str| -> Vec<String> {
        root_json
            .get(key)
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(|v| v.as_str().map(str::to_string))
                    .collect()
            })
            .unwrap_or_default()
    };
    let (required, used) = (names("extensionsRequired"), names("extensionsUsed"));
    if let Some(ext) = required.iter().find(|e| COMPRESSION.contains(&e.as_str())) {
        return Err(MeshError::parse(
            path,
            "extensionsRequired",
            format!(
                "the geometry is compressed with {ext}, which this reader does not decode \
                 (decompress the file first)"
            ),
        ));
    }
    // Extensions that place or repeat geometry, which this reader does not apply: required, the
    // file's geometry is not what it would read; only used, the plain meshes are the fallback.
    if let Some(ext) = required.iter().find(|e| GEOMETRY.contains(&e.as_str())) {
        return Err(MeshError::parse(
            path,
            "extensionsRequired",
            format!(
                "the file requires {ext}, which places or repeats the geometry and which this                  reader does not apply (the mesh would be read without it)"
            ),
        ));
    }
    for ext in used.iter().filter(|e| GEOMETRY.contains(&e.as_str())) {
        warnings.push(MeshWarning::IgnoredData {
            what: format!("glTF {ext} data (each mesh read once, without its instances)"),
        });
    }
    for ext in required.iter().filter(|e| {
        !COMPRESSION.contains(&e.as_str())
            && !GEOMETRY.contains(&e.as_str())
            && !UNDERSTOOD.iter().any(|u| e.starts_with(u))
    }) {
        warnings.push(MeshWarning::IgnoredData {
            what: format!(
                "the required glTF extension {ext} (not implemented: what it changes is not                  applied)"
            ),
        });
    }
    for ext in used.iter().filter(|e| COMPRESSION.contains(&e.as_str())) {
        warnings.push(MeshWarning::IgnoredData {
            what: format!("glTF {ext} data (the uncompressed fallback was read)"),
        });
    }
    let mut root: ::gltf::json::Root = ::gltf::json::deserialize::from_slice(json_bytes)
        .map_err(|e| MeshError::parse(path, "JSON", e.to_string()))?;
    // The `gltf` crate rejects every required extension it does not implement itself; those
    // that matter to the geometry were checked above.
    root.extensions_required.clear();
    // gltf-json 1.4's validation reads each primitive's POSITION accessor by index before it
    // checks that index, and panics on one past the end (found by the CLI fuzz: a GLB whose
    // "accessors" key was mangled): checked here first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (k, primitive) in mesh.primitives.iter().enumerate() {
            let position =
                ::gltf::json::validation::Checked::Valid(::gltf::json::mesh::Semantic::Positions);
            if let Some(index) = primitive.attributes.get(&position)
                && index.value() >= root.accessors.len()
            {
                return Err(MeshError::parse(
                    path,
                    "document",
                    format!(
                        "mesh {m}, primitive {k}: POSITION names accessor {}, but the file has \
                         {} accessors",
                        index.value(),
                        root.accessors.len()
                    ),
                ));
            }
        }
    }
    let doc = ::gltf::Document::from_json(root)
        .map_err(|e| MeshError::parse(path, "document", invalid_document(&e)))?;
    let dir = super::contain::folder_of(path);
    let mut files = Vec::new();
    let buffers = doc
        .buffers()
        .map(|b| load_buffer(&b, bin, side, dir, &mut files))
        .collect();
    let source = Source {
        doc: &doc,
        buffers,
        path,
    };

    // The mesh instances: (mesh, world transform).
    // With a far `origin`, the world transforms again in f64 from the JSON (the `gltf` crate
    // reads them as f32, which rounds a georeferenced translation to decimetres).
    let mut instances: Vec<(::gltf::Mesh, Mat4, DMat4)> = Vec::new();
    match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => {
            // glTF nodes form trees (one parent each): a node reached twice is a cycle or a
            // shared child, either of which could make the walk endless or exponential.
            let mut seen = vec![false; doc.nodes().len()];
            let mut stack: Vec<(::gltf::Node, Mat4, DMat4)> = scene
                .nodes()
                .map(|n| (n, Mat4::IDENTITY, DMat4::IDENTITY))
                .collect();
            stack.reverse();
            while let Some((node, parent, parent64)) = stack.pop() {
                if std::mem::replace(&mut seen[node.index()], true) {
                    return Err(source.error(
                        format!("node {}", node.index()),
                        "the node is reached twice from the scene (the node hierarchy has a \
                         cycle or a node with two parents; glTF nodes form trees)",
                    ));
                }
                let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
                let world64 = if origin == DVec3::ZERO {
                    DMat4::IDENTITY
                } else {
                    parent64 * local_transform_f64(&root_json["nodes"][node.index()])
                };
                if let Some(mesh) = node.mesh() {
                    instances.push((mesh, world, world64));
                }
                let children: Vec<_> = node.children().collect();
                for child in children.into_iter().rev() {
                    stack.push((child, world, world64));
                }
            }
        }
        None => instances.extend(doc.meshes().map(|m| (m, Mat4::IDENTITY, DMat4::IDENTITY))),
    }

    let mut v = Vertices::default();
    let mut corners: Vec<[u32; 3]> = Vec::new();
    let mut face_material: Vec<u32> = Vec::new();
    // The vertex sets read: (instance, accessors of READ_ATTRIBUTES) -> (first wedge, count);
    // primitives sharing their accessors share their vertices.
    type SetKey = (usize, [Option<usize>; 5]);
    let mut sets: HashMap<SetKey, (u32, usize)> = HashMap::new();
    let mut ignored_attributes = BTreeSet::new();
    let mut ignored_extensions = BTreeSet::new();
    let mut not_triangles = 0usize;
    let mut point_line_sets: HashMap<(usize, usize), usize> = HashMap::new();
    let mut no_position = 0usize;
    let mut morphed = 0usize;
    for (instance, (mesh, world, world64)) in instances.iter().enumerate() {
        let normal_matrix = Mat3::from_mat4(*world).inverse().transpose();
        let flip = world.determinant() < 0.0;
        let identity = *world == Mat4::IDENTITY;
        for prim in mesh.primitives() {
            let at = format!("mesh {} primitive {}", mesh.index(), prim.index());
            let prim_json = &root_json["meshes"][mesh.index()]["primitives"][prim.index()];
            use ::gltf::mesh::Mode;
            let mode = prim.mode();
            if !matches!(
                mode,
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
            ) {
                not_triangles += 1;
                // Their vertices, once per vertex set, for the error of a file of only these.
                if let Some(i) = prim_json["attributes"]["POSITION"].as_u64()
                    && let Some(a) = doc.accessors().nth(i as usize)
                {
                    point_line_sets.insert((instance, a.index()), a.count());
                }
                continue;
            }
            let mut accessor_of = [None; 5];
            if let Some(attributes) = prim_json["attributes"].as_object() {
                for (name, index) in attributes {
                    match READ_ATTRIBUTES.iter().position(|a| a == name) {
                        Some(k) => accessor_of[k] = index.as_u64().map(|i| i as usize),
                        None => {
                            ignored_attributes.insert(name.clone());
                        }
                    }
                }
            }
            if prim_json
                .get("targets")
                .is_some_and(|t| t.as_array().is_some_and(|a| !a.is_empty()))
            {
                morphed += 1;
            }
            if let Some(ext) = prim_json["extensions"].as_object() {
                ignored_extensions.extend(ext.keys().cloned());
            }
            let Some(position_index) = accessor_of[0] else {
                no_position += 1;
                continue;
            };
            let accessor = |i: usize| {
                doc.accessors()
                    .nth(i)
                    .ok_or_else(|| source.error(&at, format!("accessor {i} does not exist")))
            };
            let key = (instance, accessor_of);
            let (base, count) = match sets.get(&key) {
                Some(&set) => set,
                None => {
                    let base = v.positions.len() as u32;
                    let (p, _) = source.floats(&accessor(position_index)?, "POSITION", &[3])?;
                    let count = p.len() / 3;
                    if v.positions.len() + count > u32::MAX as usize {
                        return Err(source.error(at, "more than 2^32 vertices"));
                    }
                    v.positions.extend(
                        p.chunks_exact(3)
                            .map(|c| Vec3::new(c[0], c[1], c[2]))
                            // Untransformed instances keep their bits (also -0.0).
                            .map(|p| {
                                if origin != DVec3::ZERO {
                                    (world64.transform_point3(p.as_dvec3()) - origin).as_vec3()
                                } else if identity {
                                    p
                                } else {
                                    world.transform_point3(p)
                                }
                            }),
                    );
                    for (k, name) in READ_ATTRIBUTES.iter().enumerate().skip(1) {
                        let Some(index) = accessor_of[k] else {
                            v.missing[k - 1] += count;
                            match k {
                                1 => v.normals.resize(v.positions.len(), Vec3::ZERO),
                                2 => v.uv0.resize(v.positions.len(), Vec2::ZERO),
                                3 => v.uv1.resize(v.positions.len(), Vec2::ZERO),
                                _ => v.colors.resize(v.positions.len(), Vec4::ONE),
                            }
                            continue;
                        };
                        let dims: &[usize] = match k {
                            1 => &[3],
                            2 | 3 => &[2],
                            _ => &[3, 4],
                        };
                        let (a, n) = source.floats(&accessor(index)?, name, dims)?;
                        if a.len() / n != count {
                            return Err(source.error(
                                at,
                                format!(
                                    "{name} has {} elements, but POSITION has {count}",
                                    a.len() / n
                                ),
                            ));
                        }
                        v.present[k - 1] = true;
                        match k {
                            1 => v.normals.extend(a.chunks_exact(3).map(|c| {
                                let n = Vec3::new(c[0], c[1], c[2]);
                                // Normals of untransformed instances keep their bits.
                                if normal_matrix == Mat3::IDENTITY {
                                    n
                                } else {
                                    (normal_matrix * n).normalize_or_zero()
                                }
                            })),
                            2 => v
                                .uv0
                                .extend(a.chunks_exact(2).map(|c| Vec2::new(c[0], c[1]))),
                            3 => v
                                .uv1
                                .extend(a.chunks_exact(2).map(|c| Vec2::new(c[0], c[1]))),
                            _ => v.colors.extend(a.chunks_exact(n).map(|c| {
                                Vec4::new(c[0], c[1], c[2], if n == 4 { c[3] } else { 1.0 })
                            })),
                        }
                    }
                    sets.insert(key, (base, count));
                    (base, count)
                }
            };
            let indices = match prim.indices() {
                Some(a) => {
                    let indices = source.indices(&a, "indices")?;
                    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= count) {
                        return Err(source.error(
                            at,
                            format!(
                                "index {bad} (accessor {}) refers to vertex {bad}, but the \
                                 primitive has {count} vertices",
                                a.index()
                            ),
                        ));
                    }
                    indices
                }
                None => (0..count as u32).collect(),
            };
            let material = prim.material().index().map_or(u32::MAX, |m| m as u32);
            let before = corners.len();
            match mode {
                Mode::Triangles => {
                    corners.extend(indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]));
                }
                Mode::TriangleStrip => {
                    corners.extend(indices.windows(3).enumerate().map(|(i, t)| {
                        if i % 2 == 0 {
                            [t[0], t[1], t[2]]
                        } else {
                            [t[0], t[2], t[1]]
                        }
                    }));
                }
                _ => {
                    if let Some((&first, rest)) = indices.split_first() {
                        corners.extend(rest.windows(2).map(|t| [t[0], t[1], first]));
                    }
                }
            }
            for c in &mut corners[before..] {
                *c = c.map(|i| i + base);
                if flip {
                    c.swap(1, 2);
                }
            }
            face_material.resize(corners.len(), material);
        }
    }
    let point_line_vertices: usize = point_line_sets.values().sum();
    if corners.is_empty() && not_triangles > 0 && point_line_vertices > 0 {
        return Err(MeshError::NoTriangles {
            path: source.path.to_path_buf(),
            vertex_count: v.positions.len() + point_line_vertices,
            primitives: not_triangles,
        });
    }
    if not_triangles > 0 {
        warnings.push(MeshWarning::IgnoredData {
            what: format!("{not_triangles} glTF primitive(s) of points or lines"),
        });
    }
    if no_position > 0 {
        warnings.push(MeshWarning::IgnoredData {
            what: format!("{no_position} glTF primitive(s) without POSITION"),
        });
    }
    if !ignored_attributes.is_empty() {
        warnings.push(MeshWarning::IgnoredData {
            what: format!(
                "glTF vertex attributes {}",
                ignored_attributes
                    .into_iter()
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    if morphed > 0 {
        warnings.push(MeshWarning::IgnoredData {
            what: format!("glTF morph targets of {morphed} primitive(s)"),
        });
    }
    ignored_extensions.retain(|e| !COMPRESSION.contains(&e.as_str()));
    if !ignored_extensions.is_empty() {
        warnings.push(MeshWarning::IgnoredData {
            what: format!(
                "glTF primitive extensions {}",
                ignored_extensions
                    .into_iter()
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    for (k, name) in ["normals", "uv0", "uv1"].iter().enumerate() {
        if v.present[k] && v.missing[k] > 0 {
            warnings.push(MeshWarning::MissingCornerAttribute {
                attribute: name.to_string(),
                count: v.missing[k],
            });
        }
    }

    let (assets, carried_warnings) = carry(&root_json, &source, dir)?;
    warnings.extend(carried_warnings);
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
    for m in &mut face_material {
        if *m == u32::MAX {
            *m = material_count;
        }
    }

    // Wedges: one per glTF vertex; position vertices by the weld.
    let (welded, wedge_vertex) =
        crate::clean::weld_exact_map(&TriMesh::new(v.positions, corners.clone()));
    let attributes = Attributes {
        wedge_vertex,
        corners,
        normals: v.present[0].then_some(v.normals),
        uv0: v.present[1].then_some(v.uv0),
        uv1: v.present[2].then_some(v.uv1),
        colors: v.present[3].then_some(v.colors),
        face_material: any_material.then_some(face_material),
    };
    Ok(RawMesh {
        positions: welded.positions,
        triangles: welded.triangles,
        // A file of positions only has no attributes, as from the other readers.
        attributes: (!attributes.is_empty()).then_some(attributes),
        materials: Some(Materials {
            names,
            libraries: Vec::new(),
            gltf: Some(assets),
        }),
        warnings,
        files,
        ..RawMesh::default()
    })
}

/// A node's local transform in f64 from its JSON: `matrix` (column-major), or translation,
/// rotation and scale (identity where absent or malformed; the `gltf` crate validated them).
fn local_transform_f64(node: &Value) -> DMat4 {
    let numbers = |key: &str, n: usize| -> Option<Vec<f64>> {
        let v: Vec<f64> = node[key]
            .as_array()?
            .iter()
            .filter_map(Value::as_f64)
            .collect();
        (v.len() == n).then_some(v)
    };
    if let Some(m) = numbers("matrix", 16) {
        let mut cols = [0.0; 16];
        cols.copy_from_slice(&m);
        return DMat4::from_cols_array(&cols);
    }
    let t = numbers("translation", 3).map_or(DVec3::ZERO, |v| DVec3::new(v[0], v[1], v[2]));
    let r = numbers("rotation", 4).map_or(glam::DQuat::IDENTITY, |v| {
        glam::DQuat::from_xyzw(v[0], v[1], v[2], v[3]).normalize()
    });
    let s = numbers("scale", 3).map_or(DVec3::ONE, |v| DVec3::new(v[0], v[1], v[2]));
    DMat4::from_scale_rotation_translation(s, r, t)
}

/// The message of a validation failure of the `gltf` crate.
fn invalid_document(e: &::gltf::Error) -> String {
    match e {
        ::gltf::Error::Validation(list) => {
            let items: Vec<String> = list
                .iter()
                .take(5)
                .map(|(path, error)| format!("{}: {error}", path.as_str()))
                .collect();
            format!("invalid glTF: {}", items.join("; "))
        }
        other => other.to_string(),
    }
}

/// A buffer file handed over in memory: its name next to the `.gltf` (as the URI names it,
/// percent-decoded) and its bytes.
pub(crate) type SideBuffer<'a> = (&'a str, &'a [u8]);

/// The bytes of `buffer`: the GLB BIN chunk, a `data:` URI, the `side` buffer when the URI names
/// it, or a file next to the glTF; checked against the declared `byteLength`.
fn load_buffer(
    buffer: &::gltf::Buffer,
    bin: Option<&[u8]>,
    side: Option<SideBuffer>,
    dir: &Path,
    files: &mut Vec<PathBuf>,
) -> Result<Vec<u8>, String> {
    let data = match buffer.source() {
        ::gltf::buffer::Source::Bin => match bin {
            Some(b) if buffer.index() == 0 => b.to_vec(),
            _ => {
                return Err(format!(
                    "buffer {} has no uri and the file has no GLB BIN chunk for it",
                    buffer.index()
                ));
            }
        },
        ::gltf::buffer::Source::Uri(uri) => match data_uri(uri) {
            Some(r) => r?,
            None => {
                let name = percent_decode(uri);
                if let Some((_, bytes)) = side.filter(|(n, _)| *n == name) {
                    bytes.to_vec()
                } else {
                    // The containment rule: a regular file inside the glTF's folder, at most
                    // the bytes the buffer declares.
                    super::contain::resolve(dir, dir, &name)
                        .and_then(|file| {
                            let bytes = super::contain::read_prefix(&file, buffer.length() as u64);
                            files.push(file);
                            bytes
                        })
                        .map_err(|e| format!("buffer {} ({uri}) not read: {e}", buffer.index()))?
                }
            }
        },
    };
    if data.len() < buffer.length() {
        return Err(format!(
            "buffer {} declares {} bytes but has {} (truncated?)",
            buffer.index(),
            buffer.length(),
            data.len()
        ));
    }
    Ok(data)
}

/// The non-geometry members to carry to an output, with warnings for what is not carried.
fn carry(
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

/// The binary buffer being laid out, with its buffer views and accessors.
#[derive(Default)]
struct Layout {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Layout {
    /// Appends `bytes` as a buffer view (4-byte aligned); returns its index.
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view =
            json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    /// Appends a float vertex attribute of `N` components; returns its accessor index.
    fn floats<const N: usize>(&mut self, values: &[[f32; N]], with_bounds: bool) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let view = self.view(&bytes, Some(34962));
        let kind = ["SCALAR", "VEC2", "VEC3", "VEC4"][N - 1];
        let mut accessor = json!({
            "bufferView": view, "componentType": 5126, "count": values.len(), "type": kind,
        });
        if with_bounds && !values.is_empty() {
            let mut min = [f32::INFINITY; N];
            let mut max = [f32::NEG_INFINITY; N];
            for v in values {
                for k in 0..N {
                    min[k] = min[k].min(v[k]);
                    max[k] = max[k].max(v[k]);
                }
            }
            accessor["min"] = json!(min.iter().map(|&x| f64::from(x)).collect::<Vec<_>>());
            accessor["max"] = json!(max.iter().map(|&x| f64::from(x)).collect::<Vec<_>>());
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Appends triangle indices (unsigned short when every index fits, else unsigned int);
    /// returns the accessor index.
    fn indices(&mut self, indices: &[u32], vertex_count: usize) -> usize {
        let (bytes, component): (Vec<u8>, u32) = if vertex_count <= 65535 {
            (
                indices
                    .iter()
                    .flat_map(|&i| (i as u16).to_le_bytes())
                    .collect(),
                5123,
            )
        } else {
            (
                indices.iter().flat_map(|&i| i.to_le_bytes()).collect(),
                5125,
            )
        };
        let view = self.view(&bytes, Some(34963));
        self.accessors.push(json!({
            "bufferView": view, "componentType": component, "count": indices.len(), "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }
}

/// How the buffer of a written `.gltf` is stored.
pub(crate) enum BufferStorage<'a> {
    /// In the GLB BIN chunk (a `.glb`).
    Glb,
    /// As a `data:` URI inside the JSON (a self-contained `.gltf`).
    DataUri,
    /// In a separate file of this name next to the `.gltf`.
    File(&'a str),
}

/// The bytes of a written glTF (JSON or GLB) and of its separate buffer file, if any.
pub(crate) struct Written {
    /// The `.gltf` JSON or the `.glb` container.
    pub main: Vec<u8>,
    /// The buffer, for [`BufferStorage::File`].
    pub bin: Option<Vec<u8>>,
}

/// Lays out `mesh` with `attributes` (already validated against it) as glTF: one glTF vertex
/// per wedge, one primitive per material; the non-geometry members from `materials`' glTF
/// assets, or plain materials named as in `materials`. Normals that are not of unit length
/// (the validator's rule) are normalized, zero ones replaced by their triangle's normal. With
/// `flip_v` (a texture converted from an OBJ material library), `TEXCOORD_0` is written as
/// `(u, 1 − v)`: OBJ's `v` runs up from the image's bottom edge, glTF's down from its top edge.
pub(crate) fn write(
    mesh: &TriMesh,
    attributes: &Attributes,
    materials: Option<&Materials>,
    storage: BufferStorage,
    flip_v: bool,
    origin: DVec3,
) -> Written {
    let wedges = attributes.wedge_count();
    let mut layout = Layout::default();
    let positions: Vec<[f32; 3]> = attributes
        .wedge_vertex
        .iter()
        .map(|&v| mesh.positions[v as usize].to_array())
        .collect();
    let mut vertex_attributes = Map::new();
    vertex_attributes.insert("POSITION".into(), json!(layout.floats(&positions, true)));
    if let Some(normals) = &attributes.normals {
        // Unit within the validator's tolerance: written as they are (bit for bit).
        let unit = |v: Vec3| (v.length_squared() - 1.0).abs() < 1e-5;
        let mut n: Vec<Vec3> = normals.clone();
        let face_normals = mesh.face_normals();
        for (f, c) in attributes.corners.iter().enumerate() {
            for &w in c {
                let v = n[w as usize];
                if !unit(v) {
                    n[w as usize] = v
                        .try_normalize()
                        .or_else(|| face_normals[f].try_normalize())
                        .unwrap_or(Vec3::Z);
                }
            }
        }
        // Wedges no corner uses.
        for v in &mut n {
            if !unit(*v) {
                *v = v.try_normalize().unwrap_or(Vec3::Z);
            }
        }
        let n: Vec<[f32; 3]> = n.iter().map(|x| x.to_array()).collect();
        vertex_attributes.insert("NORMAL".into(), json!(layout.floats(&n, false)));
    }
    if let Some(uv) = &attributes.uv0 {
        let uv: Vec<[f32; 2]> = uv
            .iter()
            .map(|x| {
                if flip_v {
                    [x.x, 1.0 - x.y]
                } else {
                    x.to_array()
                }
            })
            .collect();
        vertex_attributes.insert("TEXCOORD_0".into(), json!(layout.floats(&uv, false)));
    }
    if let Some(uv) = &attributes.uv1 {
        let uv: Vec<[f32; 2]> = uv.iter().map(|x| x.to_array()).collect();
        vertex_attributes.insert("TEXCOORD_1".into(), json!(layout.floats(&uv, false)));
    }
    if let Some(colors) = &attributes.colors {
        let c: Vec<[f32; 4]> = colors.iter().map(|x| x.to_array()).collect();
        vertex_attributes.insert("COLOR_0".into(), json!(layout.floats(&c, false)));
    }

    let assets = materials.and_then(|m| m.gltf.as_ref());
    let mut root = Map::new();
    let mut material_count = 0;
    if let Some(assets) = assets {
        root.extend(assets.json.clone());
        material_count = assets.material_count();
        if let Some(Value::Array(images)) = root.get_mut("images") {
            for (i, bytes) in &assets.embedded_images {
                let view = layout.view(bytes, None);
                if let Some(image) = images.get_mut(*i) {
                    image["bufferView"] = json!(view);
                }
            }
        }
    } else if let Some(m) = materials
        && attributes.face_material.is_some()
        && !m.names.is_empty()
    {
        material_count = m.names.len();
        root.insert(
            "materials".into(),
            Value::Array(m.names.iter().map(|n| json!({ "name": n })).collect()),
        );
    }
    root.entry("asset")
        .or_insert_with(|| json!({ "version": "2.0", "generator": "gng3d" }));

    // One primitive per material, in material order.
    let mut groups: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (f, c) in attributes.corners.iter().enumerate() {
        let m = attributes.face_material.as_ref().map_or(u32::MAX, |m| m[f]);
        groups.entry(m).or_default().extend_from_slice(c);
    }
    let mut primitives = Vec::new();
    for (m, indices) in &groups {
        let accessor = layout.indices(indices, wedges);
        let mut p = json!({ "attributes": vertex_attributes, "indices": accessor, "mode": 4 });
        if (*m as usize) < material_count {
            p["material"] = json!(m);
        }
        primitives.push(p);
    }
    while !layout.bin.len().is_multiple_of(4) {
        layout.bin.push(0);
    }
    root.insert("scene".into(), json!(0));
    root.insert("scenes".into(), json!([{ "nodes": [0] }]));
    // A model far from its coordinates' origin: the origin as the node's translation (f64 in
    // the JSON), the positions relative to it (f32 keeps them to the model's own precision).
    root.insert(
        "nodes".into(),
        if origin == DVec3::ZERO {
            json!([{ "mesh": 0 }])
        } else {
            json!([{ "mesh": 0, "translation": origin.to_array() }])
        },
    );
    root.insert("meshes".into(), json!([{ "primitives": primitives }]));
    root.insert("accessors".into(), Value::Array(layout.accessors));
    root.insert("bufferViews".into(), Value::Array(layout.views));
    let mut buffer = json!({ "byteLength": layout.bin.len() });
    let mut bin = None;
    match storage {
        BufferStorage::Glb => {}
        BufferStorage::DataUri => {
            buffer["uri"] = json!(format!(
                "data:application/octet-stream;base64,{}",
                base64_encode(&layout.bin)
            ));
        }
        BufferStorage::File(name) => {
            buffer["uri"] = json!(percent_encode(name));
        }
    }
    root.insert("buffers".into(), json!([buffer]));
    let text = serde_json::to_vec(&Value::Object(root)).expect("JSON values serialize");
    let main = match storage {
        BufferStorage::Glb => glb(text, &layout.bin),
        BufferStorage::File(_) => {
            bin = Some(layout.bin);
            text
        }
        BufferStorage::DataUri => text,
    };
    Written { main, bin }
}

/// A GLB container of `json` (padded with spaces) and `bin` (padded with zeros).
fn glb(mut json: Vec<u8>, bin: &[u8]) -> Vec<u8> {
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(GLB_MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
    out.extend_from_slice(bin);
    out
}

/// The bytes of image `j` of `assets` that its (relative, not `data:`) `uri` names, read by
/// the containment rule: a file converted from an OBJ library (already resolved), or a regular
/// file inside the input's folder of at most [`super::contain::IMAGE_LIMIT`] bytes.
pub(super) fn read_image_file(
    assets: &GltfAssets,
    j: usize,
    uri: &str,
) -> Result<(PathBuf, Vec<u8>), super::contain::Refused> {
    use super::contain::{IMAGE_LIMIT, read_contained, read_limited};
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
pub(super) fn image_files(assets: &GltfAssets) -> Vec<PathBuf> {
    assets
        .array("images")
        .iter()
        .filter_map(|image| image["uri"].as_str())
        .filter(|uri| data_uri(uri).is_none())
        .filter_map(|uri| {
            super::contain::resolve(&assets.source_dir, &assets.source_dir, &percent_decode(uri))
                .ok()
        })
        .collect()
}

/// Copies the images of `assets` named by relative URIs (inside the input's folder) next to
/// `output`, keeping their relative paths ([`super::contain`]'s rule on both sides); files
/// already there are left alone.
pub(crate) fn copy_images(assets: &GltfAssets, output: &Path) -> Vec<MeshWarning> {
    use super::contain::{Existing, folder_of, write_beside};
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
        let result = read_image_file(assets, i, uri)
            .and_then(|(_, bytes)| write_beside(out_dir, &relative, &bytes, Existing::Keep));
        if let Err(reason) = result {
            warnings.push(MeshWarning::ReferenceRefused {
                reference: format!("glTF image {i} ({uri})"),
                reason: format!("{reason}; the output names it without a copy"),
            });
        }
    }
    warnings
}

#[cfg(test)]
mod tests;

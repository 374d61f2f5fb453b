//! The GLB container: split into its JSON and BIN chunks when reading ([`json_and_bin`]), put
//! together when writing ([`glb`]).

use crate::error::MeshError;
use std::path::Path;

/// The first four bytes of a GLB file.
const GLB_MAGIC: &[u8; 4] = b"glTF";
/// GLB chunk type of the JSON chunk ("JSON").
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// GLB chunk type of the binary chunk ("BIN\0").
const CHUNK_BIN: u32 = 0x004E_4942;

/// The JSON bytes of a `.gltf` or `.glb` file and the GLB BIN chunk, if any (told apart by the
/// GLB magic bytes; when `binary`, content that is neither is reported as a broken GLB header).
pub(super) fn json_and_bin<'a>(
    bytes: &'a [u8],
    path: &Path,
    binary: bool,
) -> Result<(&'a [u8], Option<&'a [u8]>), MeshError> {
    Ok(if bytes.starts_with(GLB_MAGIC) {
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
    })
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

/// A GLB container of `json` (padded with spaces) and `bin` (padded with zeros).
pub(super) fn glb(mut json: Vec<u8>, bin: &[u8]) -> Vec<u8> {
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

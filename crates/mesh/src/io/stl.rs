//! STL reader (ASCII or binary, via stl_io) and binary writer. STL stores unindexed triangles;
//! stl_io merges bit-identical corner positions into shared vertices.
//!
//! Which of the two encodings a file uses is decided here, not by stl_io's probe (which wants
//! `"solid "` with a space and reads a bare `solid` first line as binary): a file is binary when
//! its size is exactly `84 + 50 × count` for the count in its header, ASCII when it starts with
//! `solid` and says `facet` or `endsolid` somewhere, and binary otherwise. Binary files whose
//! size does not match their count get an error (too short) or a warning (extra records).

use super::RawMesh;
use crate::TriMesh;
use crate::error::{MeshError, MeshWarning};
use glam::Vec3;
use std::path::Path;

/// Bytes of the binary header: 80 free bytes and a little-endian u32 triangle count.
const HEADER: usize = 84;
/// Bytes of one binary triangle record: normal, three corners (12 f32) and a u16 attribute.
const RECORD: usize = 50;

/// True when `bytes` is an ASCII STL: starts with `solid`, mentions a facet or `endsolid`, and
/// is not at the same time a size-consistent binary file (binary headers may start with
/// "solid" too).
fn is_ascii(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    if !bytes[start..].starts_with(b"solid") {
        return false;
    }
    if bytes.len() >= HEADER {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if count
            .checked_mul(RECORD)
            .and_then(|n| n.checked_add(HEADER))
            == Some(bytes.len())
        {
            return false;
        }
    }
    let has = |needle: &[u8]| bytes.windows(needle.len()).any(|w| w == needle);
    has(b"facet") || has(b"endsolid")
}

/// The ASCII text with its first line made acceptable to stl_io (`solid <name>`) and every
/// facet normal written as `0 0 0`: the normals are not used (faces come from their corners),
/// and exporters write `facet normal -nan -nan -nan` for zero-area facets, which refused the
/// whole file (the same normals in binary STL load).
fn normalised_ascii(bytes: &[u8]) -> Vec<u8> {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let rest = &bytes[start..];
    let line_end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
    let first = &rest[..line_end];
    let name = first[5..].trim_ascii();
    let mut out = Vec::with_capacity(bytes.len() + 8);
    out.extend_from_slice(b"solid ");
    out.extend_from_slice(if name.is_empty() { b"unnamed" } else { name });
    for line in rest[line_end..].split_inclusive(|&b| b == b'\n') {
        let body = line.trim_ascii_start();
        let indent = &line[..line.len() - body.len()];
        if body.len() >= 12 && body[..12].eq_ignore_ascii_case(b"facet normal") {
            out.extend_from_slice(indent);
            out.extend_from_slice(b"facet normal 0 0 0");
            out.extend_from_slice(if line.ends_with(b"\r\n") {
                b"\r\n"
            } else if line.ends_with(b"\n") {
                b"\n"
            } else {
                b""
            });
        } else {
            out.extend_from_slice(line);
        }
    }
    out
}

/// Checks the binary layout: enough bytes for the header count; warns about extra bytes.
fn check_binary(bytes: &[u8], path: &Path, raw: &mut RawMesh) -> Result<(), MeshError> {
    if bytes.is_empty() {
        return Err(MeshError::Empty {
            path: path.to_path_buf(),
        });
    }
    if bytes.len() < HEADER {
        return Err(MeshError::parse(
            path,
            "header",
            format!(
                "not an ASCII STL (no `solid ... facet`) and too short for a binary STL: {} bytes, \
                 but a binary STL has an 84-byte header (80 bytes + triangle count)",
                bytes.len()
            ),
        ));
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    let records = ((bytes.len() - HEADER) / RECORD) as u64;
    let expected = HEADER as u64 + RECORD as u64 * count;
    if count > records {
        return Err(MeshError::parse(
            path,
            "header",
            format!(
                "binary STL header says {count} triangles ({expected} bytes), but the file has {} \
                 bytes ({records} complete 50-byte records)",
                bytes.len()
            ),
        ));
    }
    if expected != bytes.len() as u64 {
        raw.warnings.push(MeshWarning::StlSizeMismatch {
            header_triangles: count,
            file_bytes: bytes.len() as u64,
        });
    }
    Ok(())
}

/// Parse an STL file.
pub(crate) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh, MeshError> {
    let mut raw = RawMesh::default();
    let indexed = if is_ascii(bytes) {
        let text = normalised_ascii(bytes);
        stl_io::read_stl(&mut std::io::Cursor::new(text))
            .map_err(|e| MeshError::parse(path, "ascii stl data", e.to_string()))?
    } else {
        check_binary(bytes, path, &mut raw)?;
        // stl_io reads exactly the header's count of records.
        let mut cursor = std::io::Cursor::new(bytes);
        stl_io::read_stl(&mut cursor)
            .map_err(|e| MeshError::parse(path, "binary stl data", e.to_string()))?
    };
    raw.positions = indexed
        .vertices
        .iter()
        .map(|v| Vec3::from_array(v.0))
        .collect();
    raw.triangles = indexed
        .faces
        .iter()
        .map(|f| f.vertices.map(|i| i as u32))
        .collect();
    Ok(raw)
}

/// Binary STL bytes for `mesh` (facet normals from the geometry).
/// A non-zero `origin` is added to the positions in f64 and rounded to STL's f32.
pub(crate) fn write(mesh: &TriMesh, origin: glam::DVec3) -> std::io::Result<Vec<u8>> {
    let normals = mesh.face_normals();
    let moved = |p: Vec3| {
        if origin == glam::DVec3::ZERO {
            p
        } else {
            (p.as_dvec3() + origin).as_vec3()
        }
    };
    let triangles: Vec<stl_io::Triangle> = (0..mesh.triangles.len())
        .map(|f| {
            let [a, b, c] = mesh.triangle(f).map(moved);
            stl_io::Triangle {
                normal: stl_io::Normal::new(normals[f].to_array()),
                vertices: [
                    stl_io::Vertex::new(a.to_array()),
                    stl_io::Vertex::new(b.to_array()),
                    stl_io::Vertex::new(c.to_array()),
                ],
            }
        })
        .collect();
    let mut out = Vec::with_capacity(84 + 50 * triangles.len());
    stl_io::write_stl(&mut out, triangles.iter())?;
    Ok(out)
}

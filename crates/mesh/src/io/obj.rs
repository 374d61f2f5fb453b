//! Wavefront OBJ reader and writer: `v` and `f` records only (texture coordinates, normals,
//! groups and materials are ignored); all vertex records are kept, in file order.
//!
//! [`parse`] is hand-written rather than built on tobj: tobj renumbers vertices by first use,
//! which drops unreferenced vertex records and reorders the rest, and its errors carry no line
//! number. [`parse_with_tobj`] is the tobj-based alternative (`io::load_obj_with_tobj`), also
//! used as an independent oracle for [`parse`] in the tests.

use super::RawMesh;
use crate::TriMesh;
use crate::error::MeshError;
use glam::Vec3;
use std::fmt::Write as _;
use std::path::Path;

/// The UTF-8 byte order mark some Windows tools put at the start of text files.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Parse OBJ text.
///
/// Only `v` and `f` lines are decoded, so comments, names and other records may hold any bytes
/// (non-UTF-8 text in a comment is common in files from older tools); a leading UTF-8 byte
/// order mark is skipped. Face indices in errors are reported as written, with the line.
pub(crate) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh, MeshError> {
    let bytes = bytes.strip_prefix(BOM).unwrap_or(bytes);
    let mut raw = RawMesh::default();
    let mut poly: Vec<u32> = Vec::with_capacity(8);
    // Lines end in LF (a CR before it is whitespace to the records), or in a lone CR in files
    // from classic Mac OS tools, which read as one line without a face before.
    let end = if bytes.contains(&b'\n') { b'\n' } else { b'\r' };
    for (line_no, line) in bytes.split(|&b| b == end).enumerate() {
        let line = line.trim_ascii_start();
        let kind = match line {
            [b'v', b' ' | b'\t', ..] => b'v',
            [b'f', b' ' | b'\t', ..] => b'f',
            _ => continue,
        };
        let location = || format!("line {}", line_no + 1);
        let rest = std::str::from_utf8(&line[2..]).map_err(|_| {
            MeshError::parse(
                path,
                location(),
                "vertex or face record is not valid UTF-8 text",
            )
        })?;
        if kind == b'v' {
            let mut it = rest.split_ascii_whitespace();
            let mut p = [0f32; 3];
            for c in &mut p {
                let token = it.next().ok_or_else(|| {
                    MeshError::parse(path, location(), "vertex needs 3 coordinates")
                })?;
                *c = token.parse().map_err(|_| {
                    MeshError::parse(path, location(), format!("bad coordinate {token:?}"))
                })?;
            }
            raw.positions.push(Vec3::from_array(p));
            continue;
        }
        poly.clear();
        let n = raw.positions.len();
        for corner in rest.split_ascii_whitespace() {
            let token = corner.split('/').next().unwrap_or("");
            let index: i64 = token.parse().map_err(|_| {
                MeshError::parse(path, location(), format!("bad vertex index {corner:?}"))
            })?;
            // OBJ indices are 1-based; negative ones count back from the last vertex so far.
            let zero_based = if index < 0 {
                n as i64 + index
            } else {
                index - 1
            };
            if index == 0 || zero_based < 0 || zero_based >= n as i64 {
                return Err(MeshError::ObjIndex {
                    path: path.to_path_buf(),
                    line: line_no + 1,
                    index,
                    vertex_count: n,
                });
            }
            poly.push(zero_based as u32);
        }
        raw.push_polygon(&poly);
    }
    Ok(raw)
}

/// Parse OBJ text with tobj (`triangulate`, points and lines ignored, materials not loaded).
/// All objects and groups are merged; each keeps tobj's numbering, by first use within the
/// group, so unreferenced `v` records are dropped and a vertex used by two groups appears twice.
pub(crate) fn parse_with_tobj(bytes: &[u8], path: &Path) -> Result<RawMesh, MeshError> {
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = bytes.strip_prefix(BOM).unwrap_or(bytes);
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| MeshError::parse(path, "tobj", e.to_string()))?;
    let mut raw = RawMesh::default();
    for model in &models {
        let base = raw.positions.len() as u32;
        raw.positions.extend(
            model
                .mesh
                .positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        raw.triangles.extend(
            model
                .mesh
                .indices
                .chunks_exact(3)
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }
    Ok(raw)
}

/// OBJ text for `mesh` (`v` lines with shortest round-trip floats, 1-based `f` lines).
pub(crate) fn write(mesh: &TriMesh) -> Vec<u8> {
    let mut out = String::with_capacity(mesh.positions.len() * 30 + mesh.triangles.len() * 24);
    out.push_str("# written by gng3d\n");
    for p in &mesh.positions {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    for t in &mesh.triangles {
        let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    out.into_bytes()
}

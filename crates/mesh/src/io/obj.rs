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

/// Parse OBJ text.
pub(crate) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh, MeshError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1;
        MeshError::parse(path, format!("line {line}"), "not valid UTF-8 text")
    })?;
    let mut raw = RawMesh::default();
    let mut poly: Vec<u32> = Vec::with_capacity(8);
    let mut face = 0usize;
    for (line_no, line) in text.lines().enumerate() {
        let line = line.trim_start();
        let Some(rest) = line
            .strip_prefix("v ")
            .or_else(|| line.strip_prefix("v\t"))
            .map(|r| (b'v', r))
            .or_else(|| {
                line.strip_prefix("f ")
                    .or_else(|| line.strip_prefix("f\t"))
                    .map(|r| (b'f', r))
            })
        else {
            continue;
        };
        let location = || format!("line {}", line_no + 1);
        match rest {
            (b'v', coords) => {
                let mut it = coords.split_ascii_whitespace();
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
            }
            (_, corners) => {
                poly.clear();
                let n = raw.positions.len();
                for corner in corners.split_ascii_whitespace() {
                    let token = corner.split('/').next().unwrap_or("");
                    let index: i64 = token.parse().map_err(|_| {
                        MeshError::parse(path, location(), format!("bad vertex index {corner:?}"))
                    })?;
                    // OBJ indices are 1-based; negative ones count back from the last vertex.
                    let zero_based = if index < 0 {
                        n as i64 + index
                    } else {
                        index - 1
                    };
                    if index == 0 || zero_based < 0 || zero_based >= n as i64 {
                        return Err(MeshError::IndexOutOfRange {
                            path: path.to_path_buf(),
                            face,
                            index: zero_based,
                            vertex_count: n,
                        });
                    }
                    poly.push(zero_based as u32);
                }
                raw.push_polygon(&poly);
                face += 1;
            }
        }
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
    let mut reader = bytes;
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

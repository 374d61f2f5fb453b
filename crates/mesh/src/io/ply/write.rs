//! The PLY writer: binary little-endian, `float x y z` (or `double` for a model written back at
//! its far origin), optional normals, texture coordinates and 8-bit colours per wedge, and
//! `list uchar int vertex_indices`.

use crate::TriMesh;
use crate::attributes::Attributes;
use glam::{DVec3, Vec3};

/// Binary little-endian PLY for `mesh` (`float x y z`, `list uchar int vertex_indices`).
pub(crate) fn write(mesh: &TriMesh, origin: DVec3) -> Vec<u8> {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by gng3d\n\
         element vertex {}\n{}element face {}\nproperty list uchar int vertex_indices\n\
         end_header\n",
        mesh.positions.len(),
        position_properties(origin),
        mesh.triangles.len()
    );
    let mut out =
        Vec::with_capacity(header.len() + mesh.positions.len() * 12 + mesh.triangles.len() * 13);
    out.extend_from_slice(header.as_bytes());
    for &p in &mesh.positions {
        position(&mut out, p, origin);
    }
    for t in &mesh.triangles {
        out.push(3);
        for &i in t {
            out.extend_from_slice(&(i as i32).to_le_bytes());
        }
    }
    out
}

/// The position properties: `float x y z`, or `double` when the positions are written moved by
/// a non-zero `origin` (a model far from its coordinates' origin keeps its coordinates).
fn position_properties(origin: DVec3) -> &'static str {
    if origin == DVec3::ZERO {
        "property float x\nproperty float y\nproperty float z\n"
    } else {
        "property double x\nproperty double y\nproperty double z\n"
    }
}

/// Appends the position `p` as [`position_properties`] declares it.
fn position(out: &mut Vec<u8>, p: Vec3, origin: DVec3) {
    if origin == DVec3::ZERO {
        for c in p.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    } else {
        for c in (p.as_dvec3() + origin).to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
}

/// Binary little-endian PLY for `mesh` with `attributes` (checked to fit): one vertex record per
/// wedge (`float x y z`, then `float nx ny nz`, `float s t`, `uchar red green blue alpha` as
/// present) and the corners as faces, so a seam is two vertex records at one position; with
/// one wedge per vertex (no seams), the vertices and triangles of `mesh` as they are.
pub(crate) fn write_with_attributes(
    mesh: &TriMesh,
    attributes: &Attributes,
    origin: DVec3,
) -> Vec<u8> {
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by gng3d\n\
         element vertex {}\n{}",
        attributes.wedge_count(),
        position_properties(origin)
    );
    if attributes.normals.is_some() {
        header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    if attributes.uv0.is_some() {
        header.push_str("property float s\nproperty float t\n");
    }
    if attributes.colors.is_some() {
        header.push_str(
            "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n",
        );
    }
    header.push_str(&format!(
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        attributes.corners.len()
    ));
    let mut out = Vec::with_capacity(
        header.len() + attributes.wedge_count() * 36 + attributes.corners.len() * 13,
    );
    out.extend_from_slice(header.as_bytes());
    let floats = |out: &mut Vec<u8>, values: &[f32]| {
        for c in values {
            out.extend_from_slice(&c.to_le_bytes());
        }
    };
    // Without seams (one wedge per vertex) the records follow the vertices, so the file keeps
    // the mesh's vertex numbering.
    let mut wedge_of = vec![u32::MAX; mesh.positions.len()];
    let one_per_vertex = attributes.wedge_count() == mesh.positions.len()
        && attributes.wedge_vertex.iter().enumerate().all(|(w, &v)| {
            let slot = &mut wedge_of[v as usize];
            let first = *slot == u32::MAX;
            *slot = w as u32;
            first
        });
    let order: Vec<(usize, u32)> = if one_per_vertex {
        wedge_of
            .iter()
            .enumerate()
            .map(|(v, &w)| (w as usize, v as u32))
            .collect()
    } else {
        attributes
            .wedge_vertex
            .iter()
            .copied()
            .enumerate()
            .collect()
    };
    for (w, v) in order {
        position(&mut out, mesh.positions[v as usize], origin);
        if let Some(n) = &attributes.normals {
            floats(&mut out, &n[w].to_array());
        }
        if let Some(uv) = &attributes.uv0 {
            floats(&mut out, &uv[w].to_array());
        }
        if let Some(colors) = &attributes.colors {
            for c in colors[w].to_array() {
                out.push((c.clamp(0.0, 1.0) * 255.0).round() as u8);
            }
        }
    }
    let faces = if one_per_vertex {
        &mesh.triangles
    } else {
        &attributes.corners
    };
    for c in faces {
        out.push(3);
        for &w in c {
            out.extend_from_slice(&(w as i32).to_le_bytes());
        }
    }
    out
}

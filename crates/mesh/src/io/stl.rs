//! STL reader (ASCII or binary, via stl_io) and binary writer. STL stores unindexed triangles;
//! stl_io merges bit-identical corner positions into shared vertices.

use super::RawMesh;
use crate::TriMesh;
use crate::error::MeshError;
use glam::Vec3;
use std::path::Path;

/// Parse an STL file.
pub(crate) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh, MeshError> {
    let mut cursor = std::io::Cursor::new(bytes);
    let indexed = stl_io::read_stl(&mut cursor)
        .map_err(|e| MeshError::parse(path, "stl data", e.to_string()))?;
    let mut raw = RawMesh {
        positions: indexed
            .vertices
            .iter()
            .map(|v| Vec3::from_array(v.0))
            .collect(),
        ..RawMesh::default()
    };
    raw.triangles = indexed
        .faces
        .iter()
        .map(|f| f.vertices.map(|i| i as u32))
        .collect();
    Ok(raw)
}

/// Binary STL bytes for `mesh` (facet normals from the geometry).
pub(crate) fn write(mesh: &TriMesh) -> std::io::Result<Vec<u8>> {
    let normals = mesh.face_normals();
    let triangles: Vec<stl_io::Triangle> = (0..mesh.triangles.len())
        .map(|f| {
            let [a, b, c] = mesh.triangle(f);
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

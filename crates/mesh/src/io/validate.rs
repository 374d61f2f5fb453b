//! The checks and repairs every loaded mesh goes through ([`validate`]): empty meshes,
//! non-finite coordinates and meshes without faces are errors; degenerate and duplicate faces,
//! non-finite attribute values and colours on a 0-255 scale are repaired with warnings.

use super::{LoadedMesh, RawMesh};
use crate::TriMesh;
use crate::attributes::Attributes;
use crate::clean::drop_faces_with_mask;
use crate::error::{MeshError, MeshWarning};
use std::path::Path;

/// Check for empty meshes, non-finite coordinates and point clouds; drop degenerate and
/// duplicate faces with warnings.
pub(super) fn validate(raw: RawMesh, path: &Path) -> Result<LoadedMesh, MeshError> {
    if raw.positions.is_empty() {
        return Err(MeshError::Empty {
            path: path.to_path_buf(),
        });
    }
    if let Some(vertex) = raw.positions.iter().position(|p| !p.is_finite()) {
        return Err(MeshError::NonFinite {
            path: path.to_path_buf(),
            vertex,
        });
    }
    let mut warnings = raw.warnings;
    if raw.polygons > 0 {
        warnings.push(MeshWarning::PolygonsTriangulated {
            count: raw.polygons,
        });
    }
    if raw.short_faces > 0 {
        warnings.push(MeshWarning::ShortFaces {
            count: raw.short_faces,
        });
    }
    let vertex_count = raw.positions.len();
    let mut mesh = TriMesh::new(raw.positions, raw.triangles);
    let (dropped, kept) = drop_faces_with_mask(&mut mesh);
    let mut attributes = raw.attributes;
    if let (Some(a), Some(kept)) = (attributes.as_mut(), kept) {
        *a = a.select_faces(&kept);
    }
    if attributes.is_none()
        && (raw.normals.is_some() || raw.vertex_uvs.is_some() || raw.vertex_colors.is_some())
    {
        let mut a = Attributes::per_vertex(&mesh);
        a.normals = raw.normals.clone();
        a.uv0 = raw.vertex_uvs;
        a.colors = raw.vertex_colors;
        attributes = Some(a);
    }
    if dropped.degenerate > 0 {
        warnings.push(MeshWarning::DegenerateFaces {
            count: dropped.degenerate,
        });
    }
    if dropped.duplicate > 0 {
        warnings.push(MeshWarning::DuplicateFaces {
            count: dropped.duplicate,
        });
    }
    if let Some(a) = attributes.as_mut() {
        drop_non_finite(a, &mut warnings);
        colour_range(a, &mut warnings);
    }
    if mesh.triangles.is_empty() {
        return Err(MeshError::NoFaces {
            path: path.to_path_buf(),
            vertex_count,
        });
    }
    Ok(LoadedMesh {
        mesh,
        warnings,
        vertex_normals: raw.normals,
        attributes,
        materials: raw.materials,
        files: raw.files,
        origin: raw.origin,
    })
}

/// Drops each attribute array of `a` that holds a NaN or infinite value, with a warning naming
/// it and the first wedge (values the algorithms and writers cannot use; positions are checked
/// as an error instead).
fn drop_non_finite(a: &mut Attributes, warnings: &mut Vec<MeshWarning>) {
    fn check<T>(
        name: &str,
        values: &mut Option<Vec<T>>,
        finite: impl Fn(&T) -> bool,
        warnings: &mut Vec<MeshWarning>,
    ) {
        if let Some(w) = values
            .as_ref()
            .and_then(|v| v.iter().position(|x| !finite(x)))
        {
            *values = None;
            warnings.push(MeshWarning::AttributesDropped {
                attributes: name.to_string(),
                reason: format!("value {w} is not a finite number"),
            });
        }
    }
    check("normals", &mut a.normals, |v| v.is_finite(), warnings);
    check("uv0", &mut a.uv0, |v| v.is_finite(), warnings);
    check("uv1", &mut a.uv1, |v| v.is_finite(), warnings);
    check("colors", &mut a.colors, |v| v.is_finite(), warnings);
}

/// Colours above 1 that all fit 0–255 (OBJ `v x y z r g b` and float PLY colours written by
/// tools that use 8-bit values) are scaled by 1/255, with a warning; beyond 255 they are kept
/// with a warning (a writer would clamp them).
fn colour_range(a: &mut Attributes, warnings: &mut Vec<MeshWarning>) {
    let Some(colors) = a.colors.as_mut() else {
        return;
    };
    let max = colors
        .iter()
        .map(|c| c.truncate().max_element())
        .fold(f32::MIN, f32::max);
    if max <= 1.0 {
        return;
    }
    if max <= 255.0 {
        for c in colors.iter_mut() {
            let alpha = c.w;
            *c /= 255.0;
            c.w = if alpha <= 1.0 { alpha } else { alpha / 255.0 };
        }
        warnings.push(MeshWarning::ValuesReinterpreted {
            what: format!("colours with values up to {max} were read as 0-255 and scaled to 0-1"),
        });
    } else {
        warnings.push(MeshWarning::ValuesReinterpreted {
            what: format!("colours with values up to {max} are beyond 0-1; kept as read"),
        });
    }
}

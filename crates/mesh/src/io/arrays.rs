//! Meshes handed over in memory rather than read from a file: positions and signed triangle
//! indices checked as a file is ([`from_arrays`]), and f64 points made f32 positions around the
//! origin that loading would choose ([`recentre`]).

use super::validate::validate;
use super::{LoadedMesh, RawMesh, far_origin_of};
use crate::error::MeshError;
use glam::{DVec3, Vec3};
use std::path::Path;

/// A mesh handed over in memory (positions and triangles with signed indices, as arrays from
/// another language give them), checked and repaired as [`load`](super::load) checks a file: an
/// index below 0 or beyond the vertices is a [`MeshError::IndexOutOfRange`], then the empty,
/// non-finite and no-face checks and the dropped degenerate and duplicate faces of
/// [`load`](super::load). `name` stands for the file in the messages (e.g. `"faces"`), so a front
/// end taking arrays reports the loader's sentences.
///
/// ```
/// use gng3d_mesh::io::from_arrays;
/// use glam::Vec3;
/// use std::path::Path;
/// let square = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
/// let loaded = from_arrays(square.clone(), [[0, 1, 2], [1, 3, 2], [0, 1, 2]], Path::new("faces"));
/// assert_eq!(loaded.unwrap().mesh.face_count(), 2); // the repeated face is dropped, as in `load`
/// let err = from_arrays(square, [[0, 1, 4]], Path::new("faces")).unwrap_err();
/// assert_eq!(err.to_string(), "faces: face 0 refers to vertex 4, but there are only 4 vertices");
/// ```
pub fn from_arrays(
    positions: Vec<Vec3>,
    triangles: impl IntoIterator<Item = [i64; 3]>,
    name: &Path,
) -> Result<LoadedMesh, MeshError> {
    let vertex_count = positions.len();
    let triangles = triangles.into_iter();
    let mut checked = Vec::with_capacity(triangles.size_hint().0);
    for (face, t) in triangles.enumerate() {
        let mut corners = [0u32; 3];
        for (corner, &index) in corners.iter_mut().zip(&t) {
            *corner = match u32::try_from(index) {
                Ok(i) if (i as usize) < vertex_count => i,
                _ => {
                    return Err(MeshError::IndexOutOfRange {
                        path: name.to_path_buf(),
                        face,
                        index,
                        vertex_count,
                    });
                }
            };
        }
        checked.push(corners);
    }
    validate(
        RawMesh {
            positions,
            triangles: checked,
            ..RawMesh::default()
        },
        name,
    )
}

/// `points` (f64, e.g. arrays handed over from another language) as f32 positions relative to
/// `origin`, or when `None` to the origin [`load`](super::load) would choose
/// ([`LoadedMesh::origin`]: zero unless rounding to f32 would move a point by more than 1e-6 of
/// their extent); returns the positions and the origin used. With a zero origin each position is
/// the point rounded to f32.
///
/// ```
/// use glam::DVec3;
/// let far = [DVec3::new(450_000.0, 5_400_000.0, 0.0), DVec3::new(450_020.0, 5_400_020.0, 3.0)];
/// let (positions, origin) = gng3d_mesh::io::recentre(&far, None);
/// assert_eq!(origin, DVec3::new(450_010.0, 5_400_010.0, 1.5));
/// assert_eq!(positions[1].as_dvec3() + origin, far[1]);
/// ```
pub fn recentre(points: &[DVec3], origin: Option<DVec3>) -> (Vec<Vec3>, DVec3) {
    let origin = origin
        .or_else(|| far_origin_of(points.iter().copied()))
        .unwrap_or(DVec3::ZERO);
    let positions = if origin == DVec3::ZERO {
        points.iter().map(|p| p.as_vec3()).collect()
    } else {
        points.iter().map(|p| (*p - origin).as_vec3()).collect()
    };
    (positions, origin)
}

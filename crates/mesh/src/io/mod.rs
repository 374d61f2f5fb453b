//! Loading and saving meshes (OBJ, PLY, STL, glTF 2.0 as `.gltf` or `.glb`), chosen by file
//! extension (case-insensitive).
//!
//! [`load`] returns the mesh as stored in the file: every vertex record is kept (also
//! unreferenced ones) in file order, polygons are fan-triangulated, and only faces with a
//! repeated vertex index or a vertex set equal to an earlier face are dropped (reported as
//! [`MeshWarning`]s). Malformed input gives a [`MeshError`] naming the file and the line or
//! element.
//!
//! [`save`] is the one mesh writer: it encodes a [`Model`](crate::Model), reads the bytes back with the loader and refuses (writing nothing) an output that
//! does not load, holds no face or lacks an attribute the format stores, then writes each file
//! to a temporary sibling and renames it, so a failed write never leaves a partial or
//! unloadable output; [`write_atomic`] does the same for any bytes. A `.gltf` is written with
//! its buffer in `<stem>.bin` next to it; [`encode`] and [`encode_with_attributes`] give the
//! bytes of one file (a `.gltf` then holds its buffer as a `data:` URI).

mod apart;
mod arrays;
mod atomic;
mod contain;
mod encode;
mod gltf;
mod matconv;
mod obj;
pub mod ply;
mod save;
mod side_files;
pub mod stl;
mod validate;

pub use apart::written_files;
pub use arrays::{from_arrays, recentre};
#[cfg(test)]
use atomic::{InFlight, unfinished_writes, write_atomic_all};
pub use atomic::{check_writable, remove_unfinished_writes, write_atomic};
pub use contain::{ReferenceScope, reference_scope, set_reference_scope};
pub use encode::{encode, encode_with_attributes};
pub use gltf::GltfAssets;
pub use matconv::{BaseColorTexture, base_color_texture};
pub use save::{KeptAttributes, save};
pub use side_files::{copy_gltf_images, copy_material_files};
use validate::validate;

use crate::TriMesh;
use crate::attributes::{Attributes, Materials};
use crate::error::{MeshError, MeshWarning};
use glam::{DVec3, Vec2, Vec3, Vec4};
use std::path::{Path, PathBuf};
/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ (ASCII).
    Obj,
    /// Stanford PLY (ASCII or binary; written as binary little-endian).
    Ply,
    /// STL (ASCII or binary; written as binary).
    Stl,
    /// glTF 2.0 JSON (`.gltf`; buffers in `.bin` files or `data:` URIs; written with a `.bin`
    /// next to it).
    Gltf,
    /// glTF 2.0 binary container (`.glb`).
    Glb,
}

impl Format {
    /// The format named by `path`'s extension (case-insensitive), if known.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Format::Obj),
            "ply" => Some(Format::Ply),
            "stl" => Some(Format::Stl),
            "gltf" => Some(Format::Gltf),
            "glb" => Some(Format::Glb),
            _ => None,
        }
    }
}

/// A mesh as loaded from a file, with the non-fatal problems found and optional per-vertex
/// normals stored in the file (PLY `nx ny nz`).
#[derive(Debug, Clone)]
pub struct LoadedMesh {
    /// Positions (all vertex records, in file order) and triangles.
    pub mesh: TriMesh,
    /// Problems that were repaired by dropping faces.
    pub warnings: Vec<MeshWarning>,
    /// Per-vertex normals from the file, when it has them (same length as positions).
    pub vertex_normals: Option<Vec<Vec3>>,
    /// Normals, texture coordinates, colours and materials of the corners, when the file has
    /// any (OBJ `vt`/`vn`/vertex colours/`usemtl`, PLY `nx ny nz`, `s t`, `red green blue`,
    /// glTF `NORMAL`, `TEXCOORD_0`/`_1`, `COLOR_0` and primitive materials).
    pub attributes: Option<Attributes>,
    /// The materials the file names (OBJ `usemtl` names and `mtllib` files; glTF material
    /// names, with the file's materials, textures and images in [`Materials::gltf`]).
    pub materials: Option<Materials>,
    /// The files it was read from: the model file (from [`load`]) and the buffer files a
    /// `.gltf` names, canonical. With the files its materials name, what an output must never
    /// replace ([`LoadedMesh::check_outputs`]).
    pub files: Vec<PathBuf>,
    /// Where the positions' origin lies in the file's coordinates: zero for most models; for a
    /// model far from its coordinates' origin (georeferenced scans: x = 450,000,
    /// y = 5,400,000: rounding to f32 would move a vertex by more than 1e-6 of its extent), the
    /// centre of its bounding box, subtracted in `f64` before the positions became `f32`, so that they keep `f32`'s precision relative
    /// to the model's own size. The writers add it back in `f64` (`save_*` take it): OBJ
    /// and PLY (as `double`) keep the coordinates, glTF puts it in the node's translation, STL
    /// (`f32` only) warns.
    pub origin: DVec3,
}

/// What a format parser hands back before validation.
#[derive(Debug, Default)]
pub(crate) struct RawMesh {
    /// Vertex positions in file order.
    pub positions: Vec<Vec3>,
    /// Triangles (polygons already fan-triangulated; indices already range-checked).
    pub triangles: Vec<[u32; 3]>,
    /// Per-vertex normals, when the file stores them.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates (PLY `s t`).
    pub vertex_uvs: Option<Vec<Vec2>>,
    /// Per-vertex colours (PLY `red green blue [alpha]`).
    pub vertex_colors: Option<Vec<Vec4>>,
    /// Per-corner attributes (OBJ), one corner triple per entry of `triangles`.
    pub attributes: Option<Attributes>,
    /// Material names and libraries.
    pub materials: Option<Materials>,
    /// Number of polygons with more than three corners that were split.
    pub polygons: usize,
    /// Number of face records with fewer than three corners that were ignored.
    pub short_faces: usize,
    /// Format-specific warnings found while parsing.
    pub warnings: Vec<MeshWarning>,
    /// Files read besides the model file (a `.gltf`'s buffer files), canonical.
    pub files: Vec<PathBuf>,
    /// The model-space point that `positions` are relative to (see [`LoadedMesh::origin`]).
    pub origin: DVec3,
}

impl RawMesh {
    /// Fan-triangulate `poly` (already zero-based, range-checked indices) into `self.triangles`.
    pub(crate) fn push_polygon(&mut self, poly: &[u32]) {
        match poly.len() {
            0..=2 => self.short_faces += 1,
            3 => self.triangles.push([poly[0], poly[1], poly[2]]),
            n => {
                self.polygons += 1;
                for i in 1..n - 1 {
                    self.triangles.push([poly[0], poly[i], poly[i + 1]]);
                }
            }
        }
    }
}

/// Load a mesh from `path`; the format is chosen by the extension (obj, ply, stl, gltf, glb; any
/// case).
pub fn load(path: &Path) -> Result<LoadedMesh, MeshError> {
    let format = Format::from_path(path).ok_or_else(|| MeshError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let mut loaded = load_bytes(&read_model(path)?, format, path)?;
    if let Ok(file) = path.canonicalize() {
        loaded.files.insert(0, file);
    }
    Ok(loaded)
}

/// Load an OBJ file with the tobj-based reader instead of the built-in one: an independent
/// implementation that drops unreferenced vertices and renumbers the rest by first use (per
/// object/group, all merged into one mesh); its errors carry no line number. Degenerate and
/// duplicate faces are dropped with warnings as in [`load`]. Prefer [`load`] for counts as
/// stored in the file.
pub fn load_obj_with_tobj(path: &Path) -> Result<LoadedMesh, MeshError> {
    validate(obj::parse_with_tobj(&read_model(path)?, path)?, path)
}

/// The bytes of the model file `path`: a regular file (a FIFO or a device such as `/dev/zero`
/// is refused before it is opened, see [`contain`]), read whole.
fn read_model(path: &Path) -> Result<Vec<u8>, MeshError> {
    contain::read_limited(path, u64::MAX).map_err(|e| MeshError::Io {
        path: path.to_path_buf(),
        source: match e {
            contain::Refused::Io(source) => source,
            other => std::io::Error::other(other.to_string()),
        },
    })
}

/// Parse `bytes` in `format`; `path` is used in error messages, and for glTF its folder is where
/// external buffers (`.bin` files) are read from (a `.gltf` and a `.glb` are told apart by their
/// content, so either format reads both).
pub fn load_bytes(bytes: &[u8], format: Format, path: &Path) -> Result<LoadedMesh, MeshError> {
    load_encoded(bytes, None, format, path)
}

/// [`load_bytes`], with the buffer file that a `.gltf` names as `side` read from memory (the
/// check of [`save`] before anything is written).
fn load_encoded(
    bytes: &[u8],
    side: Option<gltf::SideBuffer>,
    format: Format,
    path: &Path,
) -> Result<LoadedMesh, MeshError> {
    let parse = |origin: DVec3| -> Result<RawMesh, MeshError> {
        let mut raw = match format {
            Format::Obj => obj::parse(bytes, path, origin)?,
            Format::Ply => ply::parse(bytes, path, origin)?,
            Format::Stl => {
                // STL stores f32: subtracting in f64 and rounding once is exact enough.
                let mut raw = stl::parse(bytes, path)?;
                if origin != DVec3::ZERO {
                    for p in &mut raw.positions {
                        *p = (p.as_dvec3() - origin).as_vec3();
                    }
                }
                raw
            }
            Format::Gltf | Format::Glb => {
                gltf::parse(bytes, path, format == Format::Glb, side, origin)?
            }
        };
        raw.origin = origin;
        Ok(raw)
    };
    let raw = parse(DVec3::ZERO)?;
    // A model far from its coordinates' origin is read again, its positions recentred in f64.
    let raw = match far_origin(&raw.positions) {
        Some(origin) => parse(origin)?,
        None => raw,
    };
    validate(raw, path)
}

/// The origin to recentre `positions` on, when rounding their coordinates to f32 moves a
/// vertex by more than 1e-6 of the model's extent (half the spacing of f32 values at the largest
/// coordinate, against the bounding-box diagonal): the box's centre. Models near their
/// coordinates' origin keep their positions bit for bit (a 0.1-unit scan at z = 1.6, 16 extents
/// away, rounds by 6e-7 of its extent and stays as read).
fn far_origin(positions: &[Vec3]) -> Option<DVec3> {
    far_origin_of(positions.iter().map(|p| p.as_dvec3()))
}

/// [`far_origin`] of points in f64.
fn far_origin_of(points: impl Iterator<Item = DVec3>) -> Option<DVec3> {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in points {
        if p.is_finite() {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    let extent = (hi - lo).length();
    let far = lo.abs().max(hi.abs()).max_element();
    if !(extent > 0.0 && far > 0.0 && far.is_finite()) {
        return None;
    }
    // The spacing of f32 values at `far`: 2^(exponent - 23).
    let half_spacing = (far.log2().floor() - 24.0).exp2();
    (half_spacing > 1e-6 * extent).then_some((lo + hi) * 0.5)
}

#[cfg(test)]
mod attribute_tests;
#[cfg(test)]
mod matconv_tests;
#[cfg(test)]
mod oracle_tests;
#[cfg(test)]
mod tests;

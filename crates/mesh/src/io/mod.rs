//! Loading and saving meshes (OBJ, PLY, STL, glTF 2.0 as `.gltf` or `.glb`), chosen by file
//! extension (case-insensitive).
//!
//! [`load`] returns the mesh as stored in the file: every vertex record is kept (also
//! unreferenced ones) in file order, polygons are fan-triangulated, and only faces with a
//! repeated vertex index or a vertex set equal to an earlier face are dropped (reported as
//! [`MeshWarning`]s). Malformed input gives a [`MeshError`] naming the file and the line or
//! element.
//!
//! [`save_with_attributes`] is the one mesh writer ([`save`] is it without attributes,
//! [`save_with_optional_attributes`] either, for an input that may have none): it
//! encodes, reads the bytes back with the loader and refuses (writing nothing) an output that
//! does not load, holds no face or lacks an attribute the format stores, then writes each file
//! to a temporary sibling and renames it, so a failed write never leaves a partial or
//! unloadable output; [`write_atomic`] does the same for any bytes. A `.gltf` is written with
//! its buffer in `<stem>.bin` next to it; [`encode`] and [`encode_with_attributes`] give the
//! bytes of one file (a `.gltf` then holds its buffer as a `data:` URI).

mod apart;
mod atomic;
mod contain;
mod gltf;
mod matconv;
mod obj;
mod ply;
mod stl;

pub use apart::written_files;
use atomic::write_atomic_all;
#[cfg(test)]
use atomic::{InFlight, unfinished_writes};
pub use atomic::{check_writable, remove_unfinished_writes, write_atomic};
pub use contain::{ReferenceScope, reference_scope, set_reference_scope};
pub use gltf::GltfAssets;
pub use matconv::{BaseColorTexture, base_color_texture};

use crate::TriMesh;
use crate::attributes::{Attributes, Materials};
use crate::clean::drop_faces_with_mask;
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
/// check of [`save_with_attributes`] before anything is written).
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

/// A mesh handed over in memory (positions and triangles with signed indices, as arrays from
/// another language give them), checked and repaired as [`load`] checks a file: an index below
/// 0 or beyond the vertices is a [`MeshError::IndexOutOfRange`], then the empty, non-finite and
/// no-face checks and the dropped degenerate and duplicate faces of [`load`]. `name` stands for
/// the file in the messages (e.g. `"faces"`), so a front end taking arrays reports the loader's
/// sentences.
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
/// `origin`, or when `None` to the origin [`load`] would choose ([`LoadedMesh::origin`]: zero
/// unless rounding to f32 would move a point by more than 1e-6 of their extent); returns the
/// positions and the origin used. With a zero origin each position is the point rounded to f32.
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

/// Check for empty meshes, non-finite coordinates and point clouds; drop degenerate and
/// duplicate faces with warnings.
fn validate(raw: RawMesh, path: &Path) -> Result<LoadedMesh, MeshError> {
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

/// A [`MeshError::IndexOutOfRange`] for the first corner of `mesh` beyond its positions.
fn check_indices(mesh: &TriMesh, path: &Path) -> Result<(), MeshError> {
    let vertex_count = mesh.positions.len();
    for (face, t) in mesh.triangles.iter().enumerate() {
        if let Some(&index) = t.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(MeshError::IndexOutOfRange {
                path: path.to_path_buf(),
                face,
                index: index as i64,
                vertex_count,
            });
        }
    }
    Ok(())
}

/// The bytes of `mesh` (positions and triangles only) in `format`, as [`save`] writes them,
/// except that a `.gltf` holds its buffer as a `data:` URI here (one self-contained file; [`save`]
/// writes the buffer to `<stem>.bin` instead). `path` only names the file in errors. Fails on
/// out-of-range indices.
pub fn encode(mesh: &TriMesh, format: Format, path: &Path) -> Result<Vec<u8>, MeshError> {
    Ok(encode_parts(
        mesh,
        None,
        None,
        DVec3::ZERO,
        format,
        path,
        GltfBuffer::DataUri,
    )?
    .main)
}

/// The materials a glTF output of `attributes` writes: a glTF input's as they are, or OBJ
/// material libraries converted to glTF materials (`embed`: textures into the buffer, for a
/// `.glb`), with whether texture coordinates flip and what was not converted.
fn gltf_materials(
    attributes: &Attributes,
    materials: Option<&Materials>,
    embed: bool,
) -> (Option<Materials>, bool, Vec<MeshWarning>) {
    match materials
        .filter(|_| attributes.face_material.is_some())
        .and_then(|m| matconv::obj_to_gltf(m, embed))
    {
        Some(c) => (Some(c.materials), c.flip_v, c.warnings),
        None => (None, false, Vec::new()),
    }
}

/// The write error for `attributes` that do not fit `mesh` (checked once before writing `path`
/// in any format).
fn check_attributes(mesh: &TriMesh, attributes: &Attributes, path: &Path) -> Result<(), MeshError> {
    attributes
        .validate(mesh)
        .map_err(|message| MeshError::Write {
            path: path.to_path_buf(),
            message: format!("the attributes do not fit the mesh: {message}"),
        })
}

/// The bytes [`save_with_attributes`] writes for `mesh` with `attributes` in `format`, and what
/// the format cannot keep (as warnings): OBJ keeps normals, texture coordinates (`uv0`), colours
/// (per vertex) and materials; PLY keeps normals, `uv0` and colours, one vertex record per wedge
/// (seams as split vertices, which the weld joins again on loading); STL keeps positions only;
/// glTF keeps everything, one glTF vertex per wedge and one primitive per material, with the
/// materials, textures and images of a glTF input ([`Materials::gltf`]), or the OBJ material
/// libraries of `materials` converted to glTF materials (base colour, opacity, roughness,
/// metallic, emissive and the `map_Kd` texture: embedded in a `.glb`, named by a relative URI in
/// a `.gltf`, see [`copy_gltf_images`]), or materials named as in `materials`. An OBJ output of
/// a glTF input names `<path stem>.mtl`, made from the glTF materials by
/// [`copy_material_files`]. What does not cross is a warning. A `.gltf` from here holds its
/// buffer as a `data:` URI (one self-contained file); [`save_with_attributes`] writes it to
/// `<stem>.bin` instead. Attributes that do not fit `mesh` are a [`MeshError::Write`] naming the
/// problem.
pub fn encode_with_attributes(
    mesh: &TriMesh,
    attributes: &Attributes,
    materials: Option<&Materials>,
    format: Format,
    path: &Path,
) -> Result<(Vec<u8>, Vec<MeshWarning>), MeshError> {
    let encoded = encode_parts(
        mesh,
        Some(attributes),
        materials,
        DVec3::ZERO,
        format,
        path,
        GltfBuffer::DataUri,
    )?;
    Ok((encoded.main, encoded.warnings))
}

/// Where the buffer of a `.gltf` goes ([`encode_parts`]; a `.glb` always holds it in its BIN
/// chunk).
#[derive(Clone, Copy, PartialEq, Eq)]
enum GltfBuffer {
    /// A `data:` URI inside the JSON: one self-contained file ([`encode`],
    /// [`encode_with_attributes`]).
    DataUri,
    /// `<stem>.bin` next to the `.gltf` (what [`save`] and [`save_with_attributes`] write).
    BinFile,
}

/// The encoded output of one write, before it is checked and written.
struct Encoded {
    /// The file's bytes.
    main: Vec<u8>,
    /// The `.bin` file of a `.gltf` with [`GltfBuffer::BinFile`]: its name next to the `.gltf`
    /// and its bytes.
    bin: Option<(String, Vec<u8>)>,
    /// What the format cannot keep, or what did not convert.
    warnings: Vec<MeshWarning>,
}

/// The one encoder: `mesh` in `format`, with `attributes` (and their `materials`) when given,
/// positions and triangles only when not.
fn encode_parts(
    mesh: &TriMesh,
    attributes: Option<&Attributes>,
    materials: Option<&Materials>,
    origin: DVec3,
    format: Format,
    path: &Path,
    gltf_buffer: GltfBuffer,
) -> Result<Encoded, MeshError> {
    if let Some(a) = attributes {
        check_attributes(mesh, a, path)?;
    }
    check_indices(mesh, path)?;
    let mut warnings = Vec::new();
    let plain = |main| Encoded {
        main,
        bin: None,
        warnings: Vec::new(),
    };
    let Some(attributes) = attributes else {
        return Ok(match format {
            Format::Obj => plain(obj::write(mesh, origin)),
            Format::Ply => plain(ply::write(mesh, origin)),
            Format::Stl => Encoded {
                main: encode_stl(mesh, origin, path)?,
                bin: None,
                warnings: stl_precision(origin),
            },
            Format::Gltf | Format::Glb => encode_gltf(
                mesh,
                &Attributes::per_vertex(mesh),
                None,
                origin,
                format,
                path,
                gltf_buffer,
            ),
        });
    };
    let mut dropped = |names: Vec<&str>, reason: &str| {
        if !names.is_empty() {
            warnings.push(MeshWarning::AttributesDropped {
                attributes: names.join(", "),
                reason: reason.to_string(),
            });
        }
    };
    let main = match format {
        Format::Gltf | Format::Glb => {
            return Ok(encode_gltf(
                mesh,
                attributes,
                materials,
                origin,
                format,
                path,
                gltf_buffer,
            ));
        }
        Format::Stl => {
            dropped(attributes.names(), "STL stores positions only");
            warnings.extend(stl_precision(origin));
            encode_stl(mesh, origin, path)?
        }
        Format::Obj => {
            let mut not = Vec::new();
            if attributes.uv1.is_some() {
                not.push("uv1");
            }
            dropped(not, "OBJ has one set of texture coordinates");
            let plan = materials
                .filter(|_| attributes.face_material.is_some())
                .and_then(|m| matconv::gltf_to_mtl(m, path));
            if let Some(p) = &plan {
                warnings.extend(p.warnings.iter().cloned());
            }
            obj::write_with_attributes(
                mesh,
                attributes,
                materials,
                plan.as_ref().map(|p| (p.library.as_str(), p.flip_v)),
                origin,
                &mut warnings,
            )
        }
        Format::Ply => {
            let mut not = Vec::new();
            if attributes.uv1.is_some() {
                not.push("uv1");
            }
            if attributes.face_material.is_some() {
                not.push("materials");
            }
            dropped(
                not,
                "PLY stores one set of texture coordinates and no materials",
            );
            ply::write_with_attributes(mesh, attributes, origin)
        }
    };
    Ok(Encoded {
        main,
        bin: None,
        warnings,
    })
}

/// Binary STL of `mesh`.
fn encode_stl(mesh: &TriMesh, origin: DVec3, path: &Path) -> Result<Vec<u8>, MeshError> {
    stl::write(mesh, origin).map_err(|e| MeshError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// The warning of an STL written far from its coordinates' origin: STL stores f32 only.
fn stl_precision(origin: DVec3) -> Vec<MeshWarning> {
    if origin == DVec3::ZERO {
        return Vec::new();
    }
    vec![MeshWarning::ValuesReinterpreted {
        what: format!(
            "STL stores 32-bit coordinates: positions around ({}, {}, {}) are rounded to about \
             {:.1e} units (OBJ, PLY and glTF keep them)",
            origin.x,
            origin.y,
            origin.z,
            origin.abs().max_element() * f64::from(f32::EPSILON) / 2.0
        ),
    }]
}

/// `mesh` with `attributes` (validated against it) as a `.glb`, or as a `.gltf` with its buffer
/// stored as `gltf_buffer` says; OBJ materials are converted (textures embedded in a `.glb`).
fn encode_gltf(
    mesh: &TriMesh,
    attributes: &Attributes,
    materials: Option<&Materials>,
    origin: DVec3,
    format: Format,
    path: &Path,
    gltf_buffer: GltfBuffer,
) -> Encoded {
    let (converted, flip_v, warnings) =
        gltf_materials(attributes, materials, format == Format::Glb);
    let materials = converted.as_ref().or(materials);
    let bin_name = apart::bin_name(path);
    let storage = match (format, gltf_buffer) {
        (Format::Glb, _) => gltf::BufferStorage::Glb,
        (_, GltfBuffer::DataUri) => gltf::BufferStorage::DataUri,
        (_, GltfBuffer::BinFile) => gltf::BufferStorage::File(&bin_name),
    };
    let written = gltf::write(mesh, attributes, materials, storage, flip_v, origin);
    Encoded {
        main: written.main,
        bin: written.bin.map(|bytes| (bin_name, bytes)),
        warnings,
    }
}

/// Copies each material library of `materials` and the texture files it names (`map_*`,
/// `bump`, `disp`, `decal`, `refl`, `norm` lines; paths relative to the library) next to
/// `output`, keeping their relative paths; files already there are left alone. For a glTF
/// input's materials, writes the material library made from them (`<output stem>.mtl`, which
/// the OBJ of [`encode_with_attributes`] names) and its texture images next to `output` instead.
/// [`save_with_attributes`] calls it for an OBJ output; it is public for a caller writing the
/// bytes of [`encode_with_attributes`] itself.
pub fn copy_material_files(materials: &Materials, output: &Path) -> Vec<MeshWarning> {
    use contain::{Existing, IMAGE_LIMIT, LIBRARY_LIMIT, read_contained, read_limited};
    if let Some(plan) = matconv::gltf_to_mtl(materials, output) {
        return matconv::write_mtl(&plan, output);
    }
    let mut warnings = Vec::new();
    let out_dir = contain::folder_of(output);
    // The containment rule on both sides: libraries (inside the model's folder since loading)
    // and the textures they name (inside the library's folder) are read as regular files of a
    // bounded size, and written only inside the output's folder.
    let mut copy = |what: String, name: &Path, read: Result<Vec<u8>, contain::Refused>| {
        if let Err(e) =
            read.and_then(|bytes| contain::write_beside(out_dir, name, &bytes, Existing::Keep))
        {
            warnings.push(MeshWarning::ReferenceRefused {
                reference: what,
                reason: format!("{e}; not copied next to {}", output.display()),
            });
        }
    };
    for library in &materials.libraries {
        let Some(name) = library.file_name() else {
            continue;
        };
        let text = read_limited(library, LIBRARY_LIMIT);
        let textures = text
            .as_ref()
            .map(|t| obj::mtl_textures(t))
            .unwrap_or_default();
        copy(
            format!("material library {}", library.display()),
            Path::new(name),
            text,
        );
        let lib_dir = contain::folder_of(library);
        for texture in textures {
            let relative = Path::new(&texture);
            // Absolute paths and paths leaving the folder are referenced as they are.
            if relative.is_absolute()
                || relative
                    .components()
                    .any(|c| matches!(c, std::path::Component::ParentDir))
            {
                continue;
            }
            let read = read_contained(lib_dir, lib_dir, &texture, IMAGE_LIMIT).map(|(_, b)| b);
            copy(format!("texture {texture}"), relative, read);
        }
    }
    warnings
}

/// Copies the images of a glTF input ([`Materials::gltf`]) that it names by relative URIs next
/// to `output`, keeping their relative paths; files already there are left alone (what
/// [`save_with_attributes`] does for a `.gltf` or `.glb`, for a caller writing the bytes of
/// [`encode_with_attributes`] itself).
///
/// For OBJ materials written to a `.gltf`, copies the textures of their material libraries that
/// the converted materials name by relative URIs (a `.glb` embeds them: nothing to copy).
pub fn copy_gltf_images(materials: &Materials, output: &Path) -> Vec<MeshWarning> {
    if let Some(assets) = &materials.gltf {
        return gltf::copy_images(assets, output);
    }
    if Format::from_path(output) == Some(Format::Glb) {
        return Vec::new();
    }
    // What could not be read was reported when the glTF was encoded.
    matconv::obj_to_gltf(materials, false)
        .and_then(|c| c.materials.gltf)
        .map(|assets| gltf::copy_images(&assets, output))
        .unwrap_or_default()
}

/// Write `mesh` (positions and triangles only) to `path`: OBJ, binary little-endian PLY, binary
/// STL, glTF (`.gltf` with its buffer in `<stem>.bin` next to it) or GLB, by extension. The
/// same checked write as [`save_with_attributes`] without attributes: a mesh without
/// triangles, or bytes that do not load back, are a [`MeshError::Write`] and nothing is
/// written; each file goes to a temporary sibling that is then renamed over its name.
pub fn save(mesh: &TriMesh, path: &Path) -> Result<(), MeshError> {
    save_with_optional_attributes(mesh, None, None, DVec3::ZERO, path).map(|_| ())
}

/// What writing a mesh with its attributes did with them ([`save_with_attributes`]): the
/// `"attributes"` object of `gng3d simplify --json` and of the Python report.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct KeptAttributes {
    /// Attributes of the input (`normals`, `uv0`, `uv1`, `colors`, `materials`).
    pub input: Vec<&'static str>,
    /// Attributes written to the output (it reads back with each of them).
    pub kept: Vec<&'static str>,
    /// What was not written or not copied, one sentence each (the caller shows them as warnings).
    pub dropped: Vec<String>,
}

impl Format {
    /// Whether this format stores attribute `name` (as [`Attributes::names`] gives it).
    pub fn stores(self, name: &str) -> bool {
        match self {
            Format::Stl => false,
            Format::Obj => name != "uv1",
            Format::Ply => matches!(name, "normals" | "uv0" | "colors"),
            Format::Gltf | Format::Glb => true,
        }
    }
}

/// Write `mesh` with `attributes` to `path` (format by extension), the one checked writer that
/// the library, `gng3d simplify` and Python's `simplify_file` use (the last two through
/// [`save_with_optional_attributes`]):
///
/// 1. encode ([`encode_with_attributes`]; a `.gltf` with its buffer in `<stem>.bin`);
/// 2. read the bytes back with [`load_bytes`] (a `.gltf` with its `.bin` from memory) and
///    refuse with a [`MeshError::Write`] naming `path` and the problem, writing nothing, when
///    the mesh has no triangle or the bytes do not load, hold no face, or lack an attribute the
///    format stores ([`Format::stores`]);
/// 3. write atomically ([`write_atomic`]; a `.gltf`'s `.bin` first);
/// 4. copy the material libraries and textures of `materials` next to an OBJ
///    ([`copy_material_files`]) and the images of a glTF input next to a glTF
///    ([`copy_gltf_images`]), when the faces have materials.
///
/// The returned [`KeptAttributes`] names the input's attributes, those written, and, as
/// sentences, what the format cannot keep and what could not be copied (never silent). [`save`]
/// is the same write without attributes.
pub fn save_with_attributes(
    mesh: &TriMesh,
    attributes: &Attributes,
    materials: Option<&Materials>,
    path: &Path,
) -> Result<KeptAttributes, MeshError> {
    save_with_optional_attributes(mesh, Some(attributes), materials, DVec3::ZERO, path)
}

/// [`save_with_attributes`] when `attributes` are given, [`save`] when not (then the returned
/// [`KeptAttributes`] is empty): the one branch of the front ends whose input may have no
/// attributes (`gng3d simplify`, Python's `simplify_file`), as
/// [`crate::clean::prepare_with_optional_attributes`] is for the cleaning. `origin` is the
/// input's [`LoadedMesh::origin`], added back to the positions in f64 (zero: written as they
/// are).
pub fn save_with_optional_attributes(
    mesh: &TriMesh,
    attributes: Option<&Attributes>,
    materials: Option<&Materials>,
    origin: DVec3,
    path: &Path,
) -> Result<KeptAttributes, MeshError> {
    let format = Format::from_path(path).ok_or_else(|| MeshError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let refuse = |message: String| MeshError::Write {
        path: path.to_path_buf(),
        message,
    };
    if mesh.face_count() == 0 {
        return Err(refuse(format!(
            "the mesh has {} vertices and no triangles; nothing written",
            mesh.vertex_count()
        )));
    }
    let encoded = encode_parts(
        mesh,
        attributes,
        materials,
        origin,
        format,
        path,
        GltfBuffer::BinFile,
    )?;
    let input = attributes.map(Attributes::names).unwrap_or_default();
    let kept: Vec<&'static str> = input.iter().copied().filter(|n| format.stores(n)).collect();
    let side = encoded
        .bin
        .as_ref()
        .map(|(name, bytes)| (name.as_str(), bytes.as_slice()));
    let reread = load_encoded(&encoded.main, side, format, path).map_err(|e| {
        refuse(format!(
            "the output does not load back ({e}); nothing written"
        ))
    })?;
    let back = reread
        .attributes
        .as_ref()
        .map(Attributes::names)
        .unwrap_or_default();
    if reread.mesh.face_count() == 0 || kept.iter().any(|n| !back.contains(n)) {
        return Err(refuse(format!(
            "the output does not read back with {}; nothing written",
            if kept.is_empty() {
                "its faces".to_string()
            } else {
                kept.join(", ")
            }
        )));
    }
    // A `.gltf` and its `.bin` together: both written in full before either is renamed, the
    // `.bin` first (a failed write leaves both files as they were).
    let bin = encoded
        .bin
        .as_ref()
        .map(|(name, bytes)| (path.with_file_name(name), bytes.as_slice()));
    let files: Vec<(&Path, &[u8])> = bin
        .iter()
        .map(|(p, b)| (p.as_path(), *b))
        .chain([(path, encoded.main.as_slice())])
        .collect();
    write_atomic_all(&files)?;
    let mut dropped: Vec<String> = encoded.warnings.iter().map(ToString::to_string).collect();
    if let Some(m) = materials
        && attributes.is_some_and(|a| a.face_material.is_some())
    {
        let copied = match format {
            Format::Obj => copy_material_files(m, path),
            Format::Gltf | Format::Glb => copy_gltf_images(m, path),
            Format::Ply | Format::Stl => Vec::new(),
        };
        dropped.extend(copied.iter().map(ToString::to_string));
    }
    Ok(KeptAttributes {
        input,
        kept,
        dropped,
    })
}

#[cfg(test)]
mod attribute_tests;
#[cfg(test)]
mod matconv_tests;
#[cfg(test)]
mod oracle_tests;
#[cfg(test)]
mod tests;

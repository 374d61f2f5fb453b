//! Wavefront OBJ reader and writer: positions (`v`, with optional `r g b` colours), faces,
//! texture coordinates (`vt`), normals (`vn`) and materials (`mtllib`, `usemtl`); groups and
//! objects are merged into one mesh; all vertex records are kept, in file order.
//!
//! [`parse`] is hand-written rather than built on tobj: tobj renumbers vertices by first use,
//! which drops unreferenced vertex records and reorders the rest, and its errors carry no line
//! number. [`parse_with_tobj`] is the tobj-based alternative (`io::load_obj_with_tobj`), also
//! used as an independent oracle for [`parse`] in the tests.

use super::RawMesh;
use crate::TriMesh;
use crate::attributes::{Attributes, Materials};
use crate::error::{MeshError, MeshWarning};
use glam::{DVec3, Vec2, Vec3, Vec4};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

/// The UTF-8 byte order mark some Windows tools put at the start of text files.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Texture coordinates, normals, colours and materials gathered while parsing, turned into
/// wedges at the end.
#[derive(Default)]
struct Corners {
    /// `vt` records.
    uvs: Vec<Vec2>,
    /// `vn` records.
    normals: Vec<Vec3>,
    /// Colour of each `v` record (white for those without), once a record has one.
    colors: Vec<Vec4>,
    /// `v` records with a colour.
    colored: usize,
    /// Wedge of each distinct `(v, vt, vn)` corner (`u32::MAX`: none).
    wedges: HashMap<[u32; 3], u32>,
    /// The `(v, vt, vn)` of each wedge.
    keys: Vec<[u32; 3]>,
    /// Wedges of each triangle, once corners are tracked (from the first `vt`, `vn` or
    /// `usemtl`; earlier triangles are filled in then).
    corners: Vec<[u32; 3]>,
    /// Material of each triangle (`u32::MAX`: none), tracked with `corners`.
    face_material: Vec<u32>,
    /// The current `usemtl`.
    material: Option<u32>,
    /// Material names in order of first use.
    names: Vec<String>,
    /// `mtllib` files, resolved against the OBJ's folder.
    libraries: Vec<std::path::PathBuf>,
    /// Smoothing groups seen (other than off / 0).
    smoothing: std::collections::BTreeSet<String>,
    /// Records this reader does not keep, with their counts.
    ignored: std::collections::BTreeMap<&'static str, usize>,
    /// `v` records with a fourth value (a weight) or a count of extra values that is not a colour.
    odd_vertices: usize,
}

impl Corners {
    /// Whether corners are tracked (the file has attributes or materials so far).
    fn tracking(&self) -> bool {
        !self.uvs.is_empty() || !self.normals.is_empty() || self.material.is_some()
    }

    fn wedge(&mut self, key: [u32; 3]) -> u32 {
        let next = self.keys.len() as u32;
        let w = *self.wedges.entry(key).or_insert(next);
        if w == next {
            self.keys.push(key);
        }
        w
    }

    /// Give the triangles parsed before tracking began their (position-only) wedges.
    fn catch_up(&mut self, triangles: &[[u32; 3]]) {
        for t in &triangles[self.corners.len()..] {
            let c = t.map(|v| self.wedge([v, u32::MAX, u32::MAX]));
            self.corners.push(c);
            self.face_material.push(u32::MAX);
        }
    }
}

/// Parse OBJ text.
///
/// `v` (with optional `r g b` colour), `vt`, `vn`, `f`, `usemtl` and `mtllib` lines are
/// decoded; other records are skipped (`vp`, `l`, `p` and several smoothing groups with a
/// warning), so comments, names and other records may hold any bytes (non-UTF-8 text in a
/// comment is common in files from older tools); a leading UTF-8 byte order mark is skipped.
/// Face indices in errors are reported as written, with the line. A file without `vt`, `vn`,
/// colours or materials is read by the same loop at the same speed as a positions-only reader.
pub(crate) fn parse(bytes: &[u8], path: &Path, origin: DVec3) -> Result<RawMesh, MeshError> {
    let bytes = bytes.strip_prefix(BOM).unwrap_or(bytes);
    let mut raw = RawMesh::default();
    let mut poly: Vec<u32> = Vec::with_capacity(8);
    let mut poly_w: Vec<u32> = Vec::with_capacity(8);
    let mut c = Corners::default();
    // Lines end in LF (a CR before it is whitespace to the records), or in a lone CR in files
    // from classic Mac OS tools, which read as one line without a face before.
    let end = if bytes.contains(&b'\n') { b'\n' } else { b'\r' };
    for (line_no, line) in bytes.split(|&b| b == end).enumerate() {
        let line = line.trim_ascii_start();
        let (kind, skip) = match line {
            [b'v', b' ' | b'\t', ..] => (b'v', 2),
            [b'f', b' ' | b'\t', ..] => (b'f', 2),
            [b'v', b't', b' ' | b'\t', ..] => (b't', 3),
            [b'v', b'n', b' ' | b'\t', ..] => (b'n', 3),
            [b'u', b's', b'e', b'm', b't', b'l', b' ' | b'\t', ..] => (b'u', 7),
            [b'm', b't', b'l', b'l', b'i', b'b', b' ' | b'\t', ..] => (b'm', 7),
            [b's', b' ' | b'\t', ..] => (b's', 2),
            [b'v', b'p', b' ' | b'\t', ..] => {
                *c.ignored
                    .entry("OBJ vp (parameter space vertex) records")
                    .or_default() += 1;
                continue;
            }
            [b'l', b' ' | b'\t', ..] => {
                *c.ignored.entry("OBJ l (line) records").or_default() += 1;
                continue;
            }
            [b'p', b' ' | b'\t', ..] => {
                *c.ignored.entry("OBJ p (point) records").or_default() += 1;
                continue;
            }
            _ => continue,
        };
        let location = || format!("line {}", line_no + 1);
        if matches!(kind, b'u' | b'm' | b's') {
            let rest = String::from_utf8_lossy(&line[skip..]).trim().to_string();
            match kind {
                b'u' => {
                    let id = match c.names.iter().position(|n| *n == rest) {
                        Some(i) => i as u32,
                        None => {
                            c.names.push(rest);
                            c.names.len() as u32 - 1
                        }
                    };
                    c.catch_up(&raw.triangles);
                    c.material = Some(id);
                }
                b'm' if !rest.is_empty() => {
                    // The containment rule: a library inside the OBJ's folder, or a warning and
                    // nothing read (a missing one is still named, as before).
                    let dir = super::contain::folder_of(path);
                    let found = super::contain::resolve(dir, dir, &rest).and_then(|p| {
                        if p.is_file() {
                            Ok(p)
                        } else {
                            Err(super::contain::Refused::NotRegular)
                        }
                    });
                    match found {
                        Ok(_) => c.libraries.push(dir.join(&rest)),
                        Err(super::contain::Refused::Io(e))
                            if e.kind() == std::io::ErrorKind::NotFound =>
                        {
                            c.libraries.push(dir.join(&rest));
                        }
                        Err(e) => raw.warnings.push(MeshWarning::ReferenceRefused {
                            reference: format!("mtllib {rest}"),
                            reason: e.to_string(),
                        }),
                    }
                }
                b's' if rest != "off" && rest != "0" => {
                    c.smoothing.insert(rest);
                }
                _ => {}
            }
            continue;
        }
        let rest = std::str::from_utf8(&line[skip..]).map_err(|_| {
            MeshError::parse(
                path,
                location(),
                "vertex or face record is not valid UTF-8 text",
            )
        })?;
        match kind {
            b'v' => {
                let mut it = rest.split_ascii_whitespace();
                let mut p = [0f32; 3];
                for (x, o) in p.iter_mut().zip(origin.to_array()) {
                    let token = it.next().ok_or_else(|| {
                        MeshError::parse(path, location(), "vertex needs 3 coordinates")
                    })?;
                    let bad =
                        |_| MeshError::parse(path, location(), format!("bad coordinate {token:?}"));
                    // Far from the origin: parsed in f64 and recentred before rounding to f32.
                    *x = if origin == DVec3::ZERO {
                        token.parse().map_err(bad)?
                    } else {
                        (token.parse::<f64>().map_err(bad)? - o) as f32
                    };
                }
                raw.positions.push(Vec3::from_array(p));
                if let Some(first) = it.next() {
                    vertex_extra(&mut c, first, it, raw.positions.len(), path, line_no)?;
                } else if !c.colors.is_empty() {
                    c.colors.push(Vec4::ONE);
                }
                continue;
            }
            b't' | b'n' => {
                let mut it = rest.split_ascii_whitespace();
                let count = if kind == b't' { 2 } else { 3 };
                let mut x = [0f32; 3];
                for (i, slot) in x.iter_mut().take(count).enumerate() {
                    // `vt u` (1D texture) reads v = 0.
                    match it.next() {
                        Some(token) => {
                            *slot = token.parse().map_err(|_| {
                                MeshError::parse(path, location(), format!("bad value {token:?}"))
                            })?;
                        }
                        None if kind == b't' && i == 1 => {}
                        None => {
                            return Err(MeshError::parse(
                                path,
                                location(),
                                "vertex normal needs 3 values",
                            ));
                        }
                    }
                }
                if kind == b't' {
                    c.catch_up(&raw.triangles);
                    c.uvs.push(Vec2::new(x[0], x[1]));
                } else {
                    c.catch_up(&raw.triangles);
                    c.normals.push(Vec3::from_array(x));
                }
                continue;
            }
            _ => {}
        }
        poly.clear();
        poly_w.clear();
        let n = raw.positions.len();
        let tracking = c.tracking();
        for corner in rest.split_ascii_whitespace() {
            let mut parts = corner.split('/');
            let token = parts.next().unwrap_or("");
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
            if tracking {
                let vt = attribute_index(parts.next(), c.uvs.len(), "texture coordinate", corner)
                    .map_err(|m| MeshError::parse(path, location(), m))?;
                let vn = attribute_index(parts.next(), c.normals.len(), "normal", corner)
                    .map_err(|m| MeshError::parse(path, location(), m))?;
                let w = c.wedge([zero_based as u32, vt, vn]);
                poly_w.push(w);
            }
        }
        raw.push_polygon(&poly);
        if tracking {
            let material = c.material.unwrap_or(u32::MAX);
            for i in 1..poly_w.len().saturating_sub(1) {
                c.corners.push([poly_w[0], poly_w[i], poly_w[i + 1]]);
                c.face_material.push(material);
            }
            debug_assert_eq!(c.corners.len(), raw.triangles.len());
        }
    }
    finish(c, &mut raw);
    Ok(raw)
}

/// The values after `x y z` on a `v` line: `r g b` is a colour; anything else is ignored with
/// a warning. `count` is the number of `v` records so far (this one included).
fn vertex_extra<'a>(
    c: &mut Corners,
    first: &'a str,
    it: impl Iterator<Item = &'a str>,
    count: usize,
    path: &Path,
    line_no: usize,
) -> Result<(), MeshError> {
    let values: Vec<&str> = std::iter::once(first).chain(it).collect();
    if values.len() == 3 {
        let mut rgb = [0f32; 3];
        for (slot, token) in rgb.iter_mut().zip(&values) {
            *slot = token.parse().map_err(|_| {
                MeshError::parse(
                    path,
                    format!("line {}", line_no + 1),
                    format!("bad colour value {token:?}"),
                )
            })?;
        }
        if c.colors.len() < count - 1 {
            c.colors.resize(count - 1, Vec4::ONE);
        }
        c.colors.push(Vec4::new(rgb[0], rgb[1], rgb[2], 1.0));
        c.colored += 1;
    } else {
        c.odd_vertices += 1;
        if !c.colors.is_empty() {
            c.colors.push(Vec4::ONE);
        }
    }
    Ok(())
}

/// The zero-based index of a `vt` or `vn` reference (`u32::MAX` when absent or empty), checked
/// against the `defined` records so far.
fn attribute_index(
    token: Option<&str>,
    defined: usize,
    what: &str,
    corner: &str,
) -> Result<u32, String> {
    let Some(token) = token.filter(|t| !t.is_empty()) else {
        return Ok(u32::MAX);
    };
    let index: i64 = token
        .parse()
        .map_err(|_| format!("bad {what} index in {corner:?}"))?;
    let zero_based = if index < 0 {
        defined as i64 + index
    } else {
        index - 1
    };
    if index == 0 || zero_based < 0 || zero_based >= defined as i64 {
        return Err(format!(
            "face refers to {what} {index}, but {defined} are defined before it"
        ));
    }
    Ok(zero_based as u32)
}

/// Turn what [`parse`] gathered into the raw mesh's attributes, materials and warnings.
fn finish(mut c: Corners, raw: &mut RawMesh) {
    for (what, count) in &c.ignored {
        raw.warnings.push(MeshWarning::IgnoredData {
            what: format!("{count} {what}"),
        });
    }
    if c.odd_vertices > 0 {
        raw.warnings.push(MeshWarning::IgnoredData {
            what: format!(
                "extra values on {} OBJ v record(s) (only x y z or x y z r g b are read)",
                c.odd_vertices
            ),
        });
    }
    if c.smoothing.len() > 1 && c.normals.is_empty() {
        raw.warnings.push(MeshWarning::IgnoredData {
            what: format!(
                "{} OBJ smoothing groups (s); normals are not derived from them",
                c.smoothing.len()
            ),
        });
    }
    if !c.colors.is_empty() && c.colors.len() < raw.positions.len() {
        c.colors.resize(raw.positions.len(), Vec4::ONE);
    }
    if c.colored > 0 && c.colored < raw.positions.len() {
        raw.warnings.push(MeshWarning::MissingCornerAttribute {
            attribute: "colors".into(),
            count: raw.positions.len() - c.colored,
        });
    }
    let materials = (!c.names.is_empty() || !c.libraries.is_empty()).then(|| Materials {
        names: c.names.clone(),
        libraries: c.libraries.clone(),
        gltf: None,
    });
    if c.corners.is_empty() {
        // No vt, vn or usemtl: per-vertex colours at most.
        if c.colored > 0 {
            raw.vertex_colors = Some(c.colors);
        }
        raw.materials = materials;
        return;
    }
    c.catch_up(&raw.triangles);
    let mut attributes = Attributes {
        wedge_vertex: c.keys.iter().map(|k| k[0]).collect(),
        corners: c.corners,
        ..Attributes::default()
    };
    let lacking_corners = |slot: usize| {
        attributes
            .corners
            .iter()
            .flatten()
            .filter(|&&w| c.keys[w as usize][slot] == u32::MAX)
            .count()
    };
    let (uv_lacking, normal_lacking) = (lacking_corners(1), lacking_corners(2));
    // `vt` / `vn` records that no corner references are not attributes of the mesh: ignored
    // with one warning, not zeros on every corner.
    let all = attributes.corners.len() * 3;
    for (records, lacking, what) in [
        (c.uvs.len(), uv_lacking, "vt (texture coordinate)"),
        (c.normals.len(), normal_lacking, "vn (normal)"),
    ] {
        if records > 0 && lacking == all {
            raw.warnings.push(MeshWarning::IgnoredData {
                what: format!("the file's {records} OBJ {what} record(s), which no face uses"),
            });
        }
    }
    if uv_lacking == all {
        c.uvs.clear();
    }
    if normal_lacking == all {
        c.normals.clear();
    }
    let mut missing = |attribute: &str, count: usize| {
        if count > 0 {
            raw.warnings.push(MeshWarning::MissingCornerAttribute {
                attribute: attribute.into(),
                count,
            });
        }
    };
    if !c.uvs.is_empty() {
        let lacking = uv_lacking;
        missing("uv0", lacking);
        attributes.uv0 = Some(
            c.keys
                .iter()
                .map(|k| c.uvs.get(k[1] as usize).copied().unwrap_or(Vec2::ZERO))
                .collect(),
        );
    }
    if !c.normals.is_empty() {
        let lacking = normal_lacking;
        missing("normals", lacking);
        attributes.normals = Some(
            c.keys
                .iter()
                .map(|k| c.normals.get(k[2] as usize).copied().unwrap_or(Vec3::ZERO))
                .collect(),
        );
    }
    if c.colored > 0 {
        attributes.colors = Some(c.keys.iter().map(|k| c.colors[k[0] as usize]).collect());
    }
    let mut materials = materials;
    if let Some(m) = materials.as_mut()
        && !m.names.is_empty()
    {
        // Faces before the first `usemtl` get a material named "default".
        if c.face_material.contains(&u32::MAX) {
            let id = m.names.len() as u32;
            m.names.push("default".into());
            for f in &mut c.face_material {
                if *f == u32::MAX {
                    *f = id;
                }
            }
        }
        attributes.face_material = Some(c.face_material);
    }
    raw.attributes = (!attributes.is_empty()).then_some(attributes);
    raw.materials = materials;
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
pub(crate) fn write(mesh: &TriMesh, origin: DVec3) -> Vec<u8> {
    let mut out = String::with_capacity(mesh.positions.len() * 30 + mesh.triangles.len() * 24);
    out.push_str("# written by gng3d\n");
    for &p in &mesh.positions {
        out.push('v');
        position(&mut out, p, origin);
        out.push('\n');
    }
    for t in &mesh.triangles {
        let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    out.into_bytes()
}

/// ` x y z` of `p` (shortest round-trip floats), moved by `origin` in f64 when it is not zero.
fn position(out: &mut String, p: Vec3, origin: DVec3) {
    if origin == DVec3::ZERO {
        let _ = write!(out, " {} {} {}", p.x, p.y, p.z);
    } else {
        let q = p.as_dvec3() + origin;
        let _ = write!(out, " {} {} {}", q.x, q.y, q.z);
    }
}

/// OBJ text for `mesh` with `attributes` (checked to fit): `mtllib` lines, `v` (with `r g b`
/// when there are colours: the first wedge's of each vertex, a warning when its wedges differ),
/// one `vt` and one `vn` per wedge, `usemtl` where the material changes, `f v/vt/vn` corners.
///
/// `libraries`: the names of the material libraries written beside the output
/// ([`side_files::library_names`](super::side_files::library_names)).
/// `converted`: the file name of a material library made from glTF materials, and whether
/// texture coordinates are written as `(u, 1 − v)` (a glTF texture crossed over: glTF's `v`
/// runs down from the image's top edge, OBJ's up from its bottom edge).
pub(crate) fn write_with_attributes(
    mesh: &TriMesh,
    attributes: &Attributes,
    materials: Option<&Materials>,
    libraries: &[String],
    converted: Option<(&str, bool)>,
    origin: DVec3,
    warnings: &mut Vec<MeshWarning>,
) -> Vec<u8> {
    let wedges = attributes.wedge_count();
    let mut out =
        String::with_capacity(mesh.positions.len() * 30 + wedges * 50 + mesh.triangles.len() * 40);
    out.push_str("# written by gng3d\n");
    if attributes.face_material.is_some() && materials.is_some() {
        for name in libraries {
            let _ = writeln!(out, "mtllib {name}");
        }
        if let Some((library, _)) = converted {
            let _ = writeln!(out, "mtllib {library}");
        }
    }
    let flip_v = converted.is_some_and(|(_, flip)| flip);
    // Colours per position vertex: the first wedge's.
    let vertex_color = attributes.colors.as_ref().map(|colors| {
        let mut per_vertex: Vec<Option<Vec4>> = vec![None; mesh.positions.len()];
        let mut differ = 0usize;
        for (w, &v) in attributes.wedge_vertex.iter().enumerate() {
            match per_vertex[v as usize] {
                None => per_vertex[v as usize] = Some(colors[w]),
                Some(c) if c != colors[w] => differ += 1,
                Some(_) => {}
            }
        }
        if differ > 0 {
            warnings.push(MeshWarning::AttributesDropped {
                attributes: format!("colors of {differ} wedge(s)"),
                reason: "OBJ stores one colour per vertex; the first of each vertex is kept".into(),
            });
        }
        per_vertex
    });
    for (i, &p) in mesh.positions.iter().enumerate() {
        out.push('v');
        position(&mut out, p, origin);
        match vertex_color.as_ref().and_then(|c| c[i]) {
            Some(c) => {
                let _ = writeln!(out, " {} {} {}", c.x, c.y, c.z);
            }
            None if vertex_color.is_some() => out.push_str(" 1 1 1\n"),
            None => out.push('\n'),
        }
    }
    if let Some(uv) = &attributes.uv0 {
        for t in uv {
            let v = if flip_v { 1.0 - t.y } else { t.y };
            let _ = writeln!(out, "vt {} {v}", t.x);
        }
    }
    if let Some(normals) = &attributes.normals {
        for n in normals {
            let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
        }
    }
    let (uv, nor) = (attributes.uv0.is_some(), attributes.normals.is_some());
    let mut current = u32::MAX;
    for (f, t) in mesh.triangles.iter().enumerate() {
        if let Some(m) = &attributes.face_material
            && m[f] != current
        {
            current = m[f];
            let name = materials
                .and_then(|ms| ms.names.get(current as usize))
                .cloned()
                .unwrap_or_else(|| format!("material_{current}"));
            let _ = writeln!(out, "usemtl {}", super::contain::one_line_name(&name));
        }
        let c = attributes.corners[f];
        out.push('f');
        for k in 0..3 {
            let (v, w) = (t[k] + 1, c[k] + 1);
            let _ = match (uv, nor) {
                (true, true) => write!(out, " {v}/{w}/{w}"),
                (true, false) => write!(out, " {v}/{w}"),
                (false, true) => write!(out, " {v}//{w}"),
                (false, false) => write!(out, " {v}"),
            };
        }
        out.push('\n');
    }
    out.into_bytes()
}

/// Whether an MTL line starting with `keyword` names a texture file as its last word (`map_*`,
/// `bump`, `disp`, `decal`, `refl`, `norm`).
pub(crate) fn names_texture(keyword: &str) -> bool {
    let lower = keyword.to_ascii_lowercase();
    lower.starts_with("map_")
        || matches!(lower.as_str(), "bump" | "disp" | "decal" | "refl" | "norm")
}

/// The texture files a material library names (the last word of its `map_*`, `bump`, `disp`,
/// `decal`, `refl` and `norm` lines), in order.
pub(crate) fn mtl_textures(text: &[u8]) -> Vec<String> {
    let text = String::from_utf8_lossy(text);
    let mut out: Vec<String> = Vec::new();
    for line in text.lines() {
        let mut words = line.split_ascii_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        if names_texture(keyword)
            && let Some(file) = words.last()
            && !out.iter().any(|o| o == file)
        {
            out.push(file.to_string());
        }
    }
    out
}

//! Stanford PLY reader (ASCII, binary little- and big-endian) and binary little-endian writer.
//!
//! A hand-written reader over the raw bytes: it reads `x y z` (any scalar type), optional
//! `nx ny nz`, texture coordinates (`s t`, `u v`, `texture_u texture_v`) and colours (`red green
//! blue [alpha]`, integers scaled to [0, 1]), skips any other vertex property and any other
//! element with a warning naming them, and
//! takes the face list property `vertex_indices` / `vertex_index` with any integer count and
//! index types; polygons are fan-triangulated. Header counts are never trusted for allocation.
//!
//! Public: the header parser ([`parse_header`], [`read_header`] and its types), the one PLY
//! header parser of the project (the partition's streaming reader uses it).

use super::RawMesh;
use crate::error::{MeshError, MeshWarning};
use glam::{DVec3, Vec2, Vec3, Vec4};
use std::path::Path;

mod header;
mod layout;
mod write;
use header::type_name;
pub use header::{
    Element, Encoding, Header, MAX_HEADER_BYTES, Property, Scalar, parse_header, read_header,
};
use layout::*;
pub(crate) use write::{write, write_with_attributes};

/// Parse a PLY file.
pub(crate) fn parse(bytes: &[u8], path: &Path, origin: DVec3) -> Result<RawMesh, MeshError> {
    let header = parse_header(bytes, path)?;
    let body = &bytes[header.body..];
    // The readers subtract `raw.origin` from the positions in f64 before rounding to f32.
    let mut raw = RawMesh {
        origin,
        warnings: ignored_data(&header),
        ..RawMesh::default()
    };
    match header.encoding {
        Encoding::Ascii => parse_ascii(&header, body, path, &mut raw)?,
        Encoding::BinaryLe => parse_binary::<false>(&header, body, path, &mut raw)?,
        Encoding::BinaryBe => parse_binary::<true>(&header, body, path, &mut raw)?,
    }
    rescale_wide_integer_colours(&header, &mut raw);
    Ok(raw)
}

/// Colours stored as 16- or 32-bit integers whose values all fit 0–255 are 8-bit colours in a
/// wide type (as several writers store them): scaled by 1/255 instead of the type's range (which
/// made them black), with a warning.
fn rescale_wide_integer_colours(header: &Header, raw: &mut RawMesh) {
    let Some(element) = header.elements.iter().find(|e| e.name == "vertex") else {
        return;
    };
    let ty = element.properties.iter().find_map(|p| match p {
        Property::Scalar(n, ty) if n == "red" => Some(*ty),
        _ => None,
    });
    let Some(ty @ (Scalar::U16 | Scalar::I16 | Scalar::U32 | Scalar::I32)) = ty else {
        return;
    };
    let Some(colors) = raw.vertex_colors.as_mut() else {
        return;
    };
    let scale = color_scale(ty) as f32;
    let max_raw = colors
        .iter()
        .map(|c| c.truncate().max_element() / scale)
        .fold(0.0f32, f32::max);
    if max_raw <= 255.5 {
        let factor = (1.0 / 255.0) / scale;
        for c in colors.iter_mut() {
            let alpha = c.w;
            *c *= factor;
            if alpha == 1.0 {
                c.w = 1.0;
            }
        }
        raw.warnings.push(MeshWarning::ValuesReinterpreted {
            what: format!(
                "{} colours all at most 255 were read as 0-255 (not as the type's 0-{})",
                type_name(ty),
                if matches!(ty, Scalar::U16 | Scalar::I16) {
                    "65535"
                } else {
                    "4294967295"
                }
            ),
        });
    }
}

/// Which role an element plays.
enum Role {
    Vertex(VertexLayout),
    Face(usize),
    Other,
}

fn role(element: &Element, seen_vertex: bool, path: &Path) -> Result<Role, MeshError> {
    Ok(match element.name.as_str() {
        "vertex" if !seen_vertex => Role::Vertex(vertex_layout(element, path)?),
        "face" => match face_list_index(element) {
            Some(i) => Role::Face(i),
            None => {
                return Err(MeshError::parse(
                    path,
                    "header",
                    "face element lacks a vertex_indices list",
                ));
            }
        },
        _ => Role::Other,
    })
}

fn check_index(raw: &RawMesh, value: i64, face: usize, path: &Path) -> Result<u32, MeshError> {
    let n = raw.positions.len();
    if value < 0 || value >= n as i64 {
        return Err(MeshError::IndexOutOfRange {
            path: path.to_path_buf(),
            face,
            index: value,
            vertex_count: n,
        });
    }
    Ok(value as u32)
}

fn parse_ascii(
    header: &Header,
    body: &[u8],
    path: &Path,
    raw: &mut RawMesh,
) -> Result<(), MeshError> {
    let text = std::str::from_utf8(body)
        .map_err(|_| MeshError::parse(path, "body", "ASCII PLY body is not text"))?;
    let mut tokens = text.split_ascii_whitespace();
    let mut seen_vertex = false;
    let mut values: Vec<f64> = Vec::new();
    let mut poly: Vec<u32> = Vec::new();
    for element in &header.elements {
        let role = role(element, seen_vertex, path)?;
        if let Role::Vertex(_) = role {
            seen_vertex = true;
        }
        if element.properties.is_empty() {
            continue;
        }
        for record in 0..element.count {
            let loc = || format!("{} {record}", element.name);
            let mut next = |what: &str| -> Result<f64, MeshError> {
                let t = tokens.next().ok_or_else(|| {
                    MeshError::parse(path, loc(), format!("file ends while reading {what}"))
                })?;
                t.parse::<f64>().map_err(|_| {
                    MeshError::parse(path, loc(), format!("bad number {t:?} in {what}"))
                })
            };
            values.clear();
            poly.clear();
            for (pi, property) in element.properties.iter().enumerate() {
                match property {
                    Property::Scalar(name, _) => values.push(next(name)?),
                    Property::List(name, _, _) => {
                        let count = next(name)?;
                        if count < 0.0 || count.fract() != 0.0 {
                            return Err(MeshError::parse(path, loc(), "bad list length"));
                        }
                        values.push(f64::NAN);
                        for _ in 0..count as usize {
                            let v = next(name)?;
                            if let Role::Face(fi) = role
                                && fi == pi
                            {
                                if v.fract() != 0.0 {
                                    return Err(MeshError::parse(
                                        path,
                                        loc(),
                                        format!("vertex index {v} is not an integer"),
                                    ));
                                }
                                poly.push(check_index(raw, v as i64, record, path)?);
                            }
                        }
                    }
                }
            }
            match &role {
                Role::Vertex(layout) => {
                    let [x, y, z] = layout.position;
                    let o = raw.origin;
                    raw.positions.push(Vec3::new(
                        (values[x] - o.x) as f32,
                        (values[y] - o.y) as f32,
                        (values[z] - o.z) as f32,
                    ));
                    if let Some([a, b, c]) = layout.normal {
                        raw.normals.get_or_insert_with(Vec::new).push(Vec3::new(
                            values[a] as f32,
                            values[b] as f32,
                            values[c] as f32,
                        ));
                    }
                    if let Some([s, t]) = layout.uv {
                        raw.vertex_uvs
                            .get_or_insert_with(Vec::new)
                            .push(Vec2::new(values[s] as f32, values[t] as f32));
                    }
                    if let Some(([r, g, b], alpha, scale)) = layout.color {
                        let a = alpha.map_or(1.0, |a| values[a] * scale);
                        raw.vertex_colors
                            .get_or_insert_with(Vec::new)
                            .push(Vec4::new(
                                (values[r] * scale) as f32,
                                (values[g] * scale) as f32,
                                (values[b] * scale) as f32,
                                a as f32,
                            ));
                    }
                }
                Role::Face(_) => raw.push_polygon(&poly),
                Role::Other => {}
            }
        }
    }
    Ok(())
}

/// Reads a `$t` of `$n` bytes at `$at` in the byte order `$be` (true: big endian) and casts
/// it to `$out`; the caller checked bounds.
macro_rules! read_as {
    ($b:expr, $at:expr, $be:expr, $t:ty, $n:expr, $out:ty) => {{
        let a: [u8; $n] = $b[$at..$at + $n].try_into().unwrap();
        (if $be {
            <$t>::from_be_bytes(a)
        } else {
            <$t>::from_le_bytes(a)
        }) as $out
    }};
}

/// Read scalar `ty` at `at` as f64 (caller checked bounds).
#[inline(always)]
fn read_scalar<const BE: bool>(b: &[u8], at: usize, ty: Scalar) -> f64 {
    match ty {
        Scalar::I8 => b[at] as i8 as f64,
        Scalar::U8 => b[at] as f64,
        Scalar::I16 => read_as!(b, at, BE, i16, 2, f64),
        Scalar::U16 => read_as!(b, at, BE, u16, 2, f64),
        Scalar::I32 => read_as!(b, at, BE, i32, 4, f64),
        Scalar::U32 => read_as!(b, at, BE, u32, 4, f64),
        Scalar::F32 => read_as!(b, at, BE, f32, 4, f64),
        Scalar::F64 => read_as!(b, at, BE, f64, 8, f64),
    }
}

/// Read integer `ty` at `at` as i64 (caller checked bounds).
#[inline(always)]
fn read_int<const BE: bool>(b: &[u8], at: usize, ty: Scalar) -> i64 {
    match ty {
        Scalar::I8 => b[at] as i8 as i64,
        Scalar::U8 => b[at] as i64,
        Scalar::I16 => read_as!(b, at, BE, i16, 2, i64),
        Scalar::U16 => read_as!(b, at, BE, u16, 2, i64),
        Scalar::I32 => read_as!(b, at, BE, i32, 4, i64),
        Scalar::U32 => read_as!(b, at, BE, u32, 4, i64),
        // Float list entries used as indices: the caller has checked they are whole numbers.
        Scalar::F32 | Scalar::F64 => read_scalar::<BE>(b, at, ty) as i64,
    }
}

fn parse_binary<const BE: bool>(
    header: &Header,
    body: &[u8],
    path: &Path,
    raw: &mut RawMesh,
) -> Result<(), MeshError> {
    let mut at = 0usize;
    let mut seen_vertex = false;
    let mut poly: Vec<u32> = Vec::new();
    let eof = |element: &Element, record: usize| {
        MeshError::parse(
            path,
            format!("{} {record}", element.name),
            "file ends inside the element data",
        )
    };
    for element in &header.elements {
        let role = role(element, seen_vertex, path)?;
        let fixed: Option<Vec<(usize, Scalar)>> = {
            let mut offset = 0;
            let mut out = Vec::new();
            let mut all_scalar = true;
            for p in &element.properties {
                match p {
                    Property::Scalar(_, ty) => {
                        out.push((offset, *ty));
                        offset += ty.size();
                    }
                    Property::List(..) => all_scalar = false,
                }
            }
            all_scalar.then_some(out)
        };
        match (&role, fixed) {
            (Role::Vertex(layout), Some(offsets)) => {
                seen_vertex = true;
                // Fixed-size records: the fast path.
                let stride: usize = offsets.last().map(|(o, t)| o + t.size()).unwrap_or(0);
                let need = stride
                    .checked_mul(element.count)
                    .filter(|&n| n <= body.len() - at)
                    .ok_or_else(|| eof(element, (body.len() - at) / stride.max(1)))?;
                let data = &body[at..at + need];
                let px = layout.position.map(|i| offsets[i]);
                let nx = layout.normal.map(|n| n.map(|i| offsets[i]));
                raw.positions.reserve(element.count);
                let mut normals = nx.map(|_| Vec::with_capacity(element.count));
                let origin = raw.origin;
                for r in 0..element.count {
                    let base = r * stride;
                    let get = |(o, t): (usize, Scalar)| read_scalar::<BE>(data, base + o, t) as f32;
                    // Recentred in f64 (subtracting zero changes no value).
                    let coord = |(o, t): (usize, Scalar), c: f64| {
                        (read_scalar::<BE>(data, base + o, t) - c) as f32
                    };
                    raw.positions.push(Vec3::new(
                        coord(px[0], origin.x),
                        coord(px[1], origin.y),
                        coord(px[2], origin.z),
                    ));
                    if let (Some(n), Some(ns)) = (nx, normals.as_mut()) {
                        ns.push(Vec3::new(get(n[0]), get(n[1]), get(n[2])));
                    }
                }
                raw.normals = normals;
                // Texture coordinates and colours, when present, in their own loops (the
                // positions' loop stays as it was for the files without them).
                if let Some(uv) = layout.uv {
                    let [s, t] = uv.map(|i| offsets[i]);
                    raw.vertex_uvs = Some(
                        (0..element.count)
                            .map(|r| {
                                let base = r * stride;
                                let get = |(o, ty): (usize, Scalar)| {
                                    read_scalar::<BE>(data, base + o, ty) as f32
                                };
                                Vec2::new(get(s), get(t))
                            })
                            .collect(),
                    );
                }
                if let Some((rgb, alpha, scale)) = layout.color {
                    let rgb = rgb.map(|i| offsets[i]);
                    let alpha = alpha.map(|i| offsets[i]);
                    raw.vertex_colors = Some(
                        (0..element.count)
                            .map(|r| {
                                let base = r * stride;
                                let get = |(o, ty): (usize, Scalar)| {
                                    (read_scalar::<BE>(data, base + o, ty) * scale) as f32
                                };
                                Vec4::new(
                                    get(rgb[0]),
                                    get(rgb[1]),
                                    get(rgb[2]),
                                    alpha.map_or(1.0, get),
                                )
                            })
                            .collect(),
                    );
                }
                at += need;
            }
            (Role::Other, Some(offsets)) => {
                let stride: usize = offsets.last().map(|(o, t)| o + t.size()).unwrap_or(0);
                let need = stride
                    .checked_mul(element.count)
                    .filter(|&n| n <= body.len() - at)
                    .ok_or_else(|| eof(element, 0))?;
                at += need;
            }
            _ => {
                if let Role::Vertex(_) = role {
                    return Err(MeshError::parse(
                        path,
                        "header",
                        "list properties in the vertex element are not supported",
                    ));
                }
                let face_list = match role {
                    Role::Face(i) => Some(i),
                    _ => None,
                };
                for record in 0..element.count {
                    poly.clear();
                    for (pi, p) in element.properties.iter().enumerate() {
                        match p {
                            Property::Scalar(_, ty) => {
                                if body.len() - at < ty.size() {
                                    return Err(eof(element, record));
                                }
                                at += ty.size();
                            }
                            Property::List(_, count_ty, item_ty) => {
                                if body.len() - at < count_ty.size() {
                                    return Err(eof(element, record));
                                }
                                let count = read_int::<BE>(body, at, *count_ty);
                                at += count_ty.size();
                                if count < 0 {
                                    return Err(MeshError::parse(
                                        path,
                                        format!("{} {record}", element.name),
                                        format!("negative list length {count}"),
                                    ));
                                }
                                let len = (count as usize)
                                    .checked_mul(item_ty.size())
                                    .filter(|&n| n <= body.len() - at)
                                    .ok_or_else(|| eof(element, record))?;
                                if face_list == Some(pi) {
                                    for k in 0..count as usize {
                                        let at = at + k * item_ty.size();
                                        // Float indices must be whole numbers, as in the
                                        // ASCII reader (NaN read as vertex 0, 2.7 as 2).
                                        if !item_ty.is_integer() {
                                            let v = read_scalar::<BE>(body, at, *item_ty);
                                            if !v.is_finite() || v.fract() != 0.0 {
                                                return Err(MeshError::parse(
                                                    path,
                                                    format!("{} {record}", element.name),
                                                    format!("vertex index {v} is not an integer"),
                                                ));
                                            }
                                        }
                                        let v = read_int::<BE>(body, at, *item_ty);
                                        poly.push(check_index(raw, v, record, path)?);
                                    }
                                }
                                at += len;
                            }
                        }
                    }
                    if face_list.is_some() {
                        raw.push_polygon(&poly);
                    }
                }
            }
        }
    }
    Ok(())
}

//! Stanford PLY reader (ASCII, binary little- and big-endian) and binary little-endian writer.
//!
//! A hand-written reader over the raw bytes: it reads `x y z` (any scalar type), optional
//! `nx ny nz`, texture coordinates (`s t`, `u v`, `texture_u texture_v`) and colours (`red green
//! blue [alpha]`, integers scaled to [0, 1]), skips any other vertex property and any other
//! element with a warning naming them, and
//! takes the face list property `vertex_indices` / `vertex_index` with any integer count and
//! index types; polygons are fan-triangulated. Header counts are never trusted for allocation.

use super::RawMesh;
use crate::error::{MeshError, MeshWarning};
use glam::{DVec3, Vec2, Vec3, Vec4};
use std::path::Path;

mod write;
pub(crate) use write::{write, write_with_attributes};

/// A PLY scalar type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// One property of an element.
#[derive(Debug, Clone)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

/// One element declaration.
#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    BinaryLe,
    BinaryBe,
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    /// Byte offset of the body.
    body: usize,
}

fn parse_header(bytes: &[u8], path: &Path) -> Result<Header, MeshError> {
    let mut pos = 0usize;
    let mut line_no = 0usize;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        line_no += 1;
        let loc = format!("header line {line_no}");
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map(|i| pos + i)
            .ok_or_else(|| MeshError::parse(path, &loc, "header ends without end_header"))?;
        let line = std::str::from_utf8(&bytes[pos..end])
            .map_err(|_| MeshError::parse(path, &loc, "header is not text"))?
            .trim();
        pos = end + 1;
        let mut words = line.split_ascii_whitespace();
        let keyword = words.next().unwrap_or("");
        if line_no == 1 {
            if line != "ply" {
                return Err(MeshError::parse(path, &loc, "missing 'ply' magic"));
            }
            continue;
        }
        let bad = |msg: &str| MeshError::parse(path, &loc, format!("{msg}: {line:?}"));
        match keyword {
            "format" => {
                encoding = Some(match words.next() {
                    Some("ascii") => Encoding::Ascii,
                    Some("binary_little_endian") => Encoding::BinaryLe,
                    Some("binary_big_endian") => Encoding::BinaryBe,
                    _ => return Err(bad("unknown format")),
                });
            }
            "comment" | "obj_info" | "" => {}
            "element" => {
                let name = words.next().ok_or_else(|| bad("element without name"))?;
                let count = words
                    .next()
                    .and_then(|c| c.parse::<usize>().ok())
                    .ok_or_else(|| bad("element without a valid count"))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            "property" => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| bad("property before any element"))?;
                let ty = words.next().ok_or_else(|| bad("property without type"))?;
                let property = if ty == "list" {
                    let count = words.next().and_then(Scalar::parse);
                    let item = words.next().and_then(Scalar::parse);
                    let name = words.next();
                    match (count, item, name) {
                        (Some(c), Some(i), Some(n)) if c.is_integer() => {
                            Property::List(n.to_string(), c, i)
                        }
                        _ => return Err(bad("bad list property")),
                    }
                } else {
                    let ty = Scalar::parse(ty).ok_or_else(|| bad("unknown property type"))?;
                    let name = words.next().ok_or_else(|| bad("property without name"))?;
                    Property::Scalar(name.to_string(), ty)
                };
                element.properties.push(property);
            }
            "end_header" => break,
            _ => return Err(bad("unknown header keyword")),
        }
    }
    let encoding = encoding.ok_or_else(|| MeshError::parse(path, "header", "no format line"))?;
    Ok(Header {
        encoding,
        elements,
        body: pos,
    })
}

/// Where the vertex fields we want sit among the vertex element's properties.
struct VertexLayout {
    position: [usize; 3],
    normal: Option<[usize; 3]>,
    /// `s t`, `u v`, `texture_u texture_v` or `texture_s texture_t`.
    uv: Option<[usize; 2]>,
    /// `red green blue [alpha]` (alpha 1 when absent) and the factor to [0, 1].
    color: Option<([usize; 3], Option<usize>, f64)>,
}

/// The colour factor to [0, 1] for a channel of type `ty`.
fn color_scale(ty: Scalar) -> f64 {
    match ty {
        Scalar::U8 | Scalar::I8 => 1.0 / 255.0,
        Scalar::U16 | Scalar::I16 => 1.0 / 65535.0,
        Scalar::U32 | Scalar::I32 => 1.0 / 4294967295.0,
        Scalar::F32 | Scalar::F64 => 1.0,
    }
}

/// The vertex properties this reader reads.
const VERTEX_PROPERTIES: [&str; 16] = [
    "x",
    "y",
    "z",
    "nx",
    "ny",
    "nz",
    "s",
    "t",
    "u",
    "v",
    "texture_u",
    "texture_v",
    "red",
    "green",
    "blue",
    "alpha",
];

/// Warnings for what the header declares and this reader skips: vertex properties it does not
/// read, face properties other than the index list, other elements.
fn ignored_data(header: &Header) -> Vec<MeshWarning> {
    let mut out = Vec::new();
    let mut seen_vertex = false;
    for element in &header.elements {
        let names = |skip: &dyn Fn(&str) -> bool| -> Vec<String> {
            element
                .properties
                .iter()
                .map(|p| match p {
                    Property::Scalar(n, _) | Property::List(n, _, _) => n.clone(),
                })
                .filter(|n| !skip(n))
                .collect()
        };
        let (what, list) = match element.name.as_str() {
            "vertex" if !seen_vertex => {
                seen_vertex = true;
                (
                    "vertex",
                    names(&|n| {
                        VERTEX_PROPERTIES.contains(&n) || n == "texture_s" || n == "texture_t"
                    }),
                )
            }
            "face" => (
                "face",
                names(&|n| n == "vertex_indices" || n == "vertex_index"),
            ),
            _ => {
                if element.count > 0 {
                    out.push(MeshWarning::IgnoredData {
                        what: format!("PLY element {} ({} records)", element.name, element.count),
                    });
                }
                continue;
            }
        };
        if !list.is_empty() && element.count > 0 {
            out.push(MeshWarning::IgnoredData {
                what: format!("PLY {what} properties {}", list.join(", ")),
            });
        }
        if what == "vertex" && element.count > 0 {
            out.extend(partial_vertex_properties(element));
        }
    }
    out
}

/// Vertex properties of a known name that are not read: a group without all its members
/// (`red green` without `blue`, `nx ny` without `nz`) or a list instead of a scalar.
fn partial_vertex_properties(element: &Element) -> Vec<MeshWarning> {
    let scalar = |name: &str| {
        element
            .properties
            .iter()
            .any(|p| matches!(p, Property::Scalar(n, _) if n == name))
    };
    let mut out = Vec::new();
    for group in [
        &["nx", "ny", "nz"][..],
        &["red", "green", "blue"],
        &["s", "t"],
        &["u", "v"],
        &["texture_u", "texture_v"],
        &["texture_s", "texture_t"],
    ] {
        let (have, lack): (Vec<&str>, Vec<&str>) = group.iter().partition(|n| scalar(n));
        if !have.is_empty() && !lack.is_empty() {
            out.push(MeshWarning::IgnoredData {
                what: format!(
                    "PLY vertex properties {} (without {})",
                    have.join(", "),
                    lack.join(", ")
                ),
            });
        }
    }
    for p in &element.properties {
        if let Property::List(n, _, _) = p
            && (VERTEX_PROPERTIES.contains(&n.as_str()) || n == "texture_s" || n == "texture_t")
        {
            out.push(MeshWarning::IgnoredData {
                what: format!("PLY vertex property {n} (a list, where a number is read)"),
            });
        }
    }
    out
}

fn vertex_layout(element: &Element, path: &Path) -> Result<VertexLayout, MeshError> {
    let find = |name: &str| {
        element
            .properties
            .iter()
            .position(|p| matches!(p, Property::Scalar(n, _) if n == name))
    };
    let position = match (find("x"), find("y"), find("z")) {
        (Some(x), Some(y), Some(z)) => [x, y, z],
        _ => {
            return Err(MeshError::parse(
                path,
                "header",
                "vertex element lacks scalar x, y, z properties",
            ));
        }
    };
    let normal = match (find("nx"), find("ny"), find("nz")) {
        (Some(x), Some(y), Some(z)) => Some([x, y, z]),
        _ => None,
    };
    let uv = [
        ("s", "t"),
        ("u", "v"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ]
    .iter()
    .find_map(|(a, b)| Some([find(a)?, find(b)?]));
    let color = match (find("red"), find("green"), find("blue")) {
        (Some(r), Some(g), Some(b)) => {
            let scale = match &element.properties[r] {
                Property::Scalar(_, ty) => color_scale(*ty),
                Property::List(..) => 1.0,
            };
            Some(([r, g, b], find("alpha"), scale))
        }
        _ => None,
    };
    Ok(VertexLayout {
        position,
        normal,
        uv,
        color,
    })
}

fn face_list_index(element: &Element) -> Option<usize> {
    element.properties.iter().position(
        |p| matches!(p, Property::List(n, _, _) if n == "vertex_indices" || n == "vertex_index"),
    )
}

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

/// The PLY name of `ty`.
fn type_name(ty: Scalar) -> &'static str {
    match ty {
        Scalar::U8 => "uchar",
        Scalar::I8 => "char",
        Scalar::U16 => "ushort",
        Scalar::I16 => "short",
        Scalar::U32 => "uint",
        Scalar::I32 => "int",
        Scalar::F32 => "float",
        Scalar::F64 => "double",
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

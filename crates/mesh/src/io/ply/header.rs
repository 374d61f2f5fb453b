//! The PLY header: scalar types, elements and their properties, the encoding, and where the
//! body starts.

use crate::error::MeshError;
use std::path::Path;

/// A PLY scalar type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Scalar {
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
    pub(super) fn parse(name: &str) -> Option<Scalar> {
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

    pub(super) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub(super) fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// One property of an element.
#[derive(Debug, Clone)]
pub(super) enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

/// One element declaration.
#[derive(Debug, Clone)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) count: usize,
    pub(super) properties: Vec<Property>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Encoding {
    Ascii,
    BinaryLe,
    BinaryBe,
}

pub(super) struct Header {
    pub(super) encoding: Encoding,
    pub(super) elements: Vec<Element>,
    /// Byte offset of the body.
    pub(super) body: usize,
}

pub(super) fn parse_header(bytes: &[u8], path: &Path) -> Result<Header, MeshError> {
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

/// The PLY name of `ty`.
pub(super) fn type_name(ty: Scalar) -> &'static str {
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

//! The PLY header: scalar types, elements and their properties, the encoding, and where the
//! body starts. The one header parser: the in-memory loader and the partition's streaming
//! reader (`gng3d-partition`) both read headers with [`parse_header`] / [`read_header`].

use crate::error::MeshError;
use std::io::{BufRead, Read};
use std::path::Path;

/// A header longer than this (1 MiB) is not taken by [`read_header`]: a file without an
/// `end_header` line in its first MiB is not a PLY file worth streaming.
pub const MAX_HEADER_BYTES: usize = 1 << 20;

/// A PLY scalar type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)] // the PLY types by their sizes
pub enum Scalar {
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
    /// The type of a PLY type name (`uchar`, `uint8`, `float`, ...).
    pub fn parse(name: &str) -> Option<Scalar> {
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

    /// Bytes of one binary value.
    pub fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// Whether the type is an integer one.
    pub fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// One property of an element.
#[derive(Debug, Clone)]
pub enum Property {
    /// A scalar: its name and type.
    Scalar(String, Scalar),
    /// A list: its name, the type of its length and the type of its items.
    List(String, Scalar, Scalar),
}

impl Property {
    /// The property's name.
    pub fn name(&self) -> &str {
        match self {
            Property::Scalar(n, _) | Property::List(n, _, _) => n,
        }
    }
}

/// One element declaration.
#[derive(Debug, Clone)]
pub struct Element {
    /// `vertex`, `face`, ...
    pub name: String,
    /// Records the header announces (a claim: check it against the file before sizing
    /// anything from it).
    pub count: usize,
    /// Its properties in record order.
    pub properties: Vec<Property>,
}

/// How the body is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// `format ascii`.
    Ascii,
    /// `format binary_little_endian`.
    BinaryLe,
    /// `format binary_big_endian`.
    BinaryBe,
}

/// A parsed PLY header.
#[derive(Debug, Clone)]
pub struct Header {
    /// The body's encoding.
    pub encoding: Encoding,
    /// The elements in file order.
    pub elements: Vec<Element>,
    /// Byte offset of the body.
    pub body: usize,
}

/// The header of a PLY file whose first bytes (at least up to its `end_header` line) are
/// `bytes`; `path` names the file in errors ([`MeshError::Parse`] at "header line N").
pub fn parse_header(bytes: &[u8], path: &Path) -> Result<Header, MeshError> {
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

/// The header of the PLY file read by `reader` from its start: its lines up to `end_header`
/// (at most [`MAX_HEADER_BYTES`]) read and given to [`parse_header`], the reader left at the
/// body. `path` names the file in errors.
pub fn read_header(reader: &mut impl BufRead, path: &Path) -> Result<Header, MeshError> {
    let mut bytes = Vec::new();
    loop {
        let before = bytes.len();
        let n = reader
            .by_ref()
            .take((MAX_HEADER_BYTES - before) as u64)
            .read_until(b'\n', &mut bytes)
            .map_err(|source| MeshError::Io {
                path: path.to_path_buf(),
                source,
            })?;
        let line = bytes[before..].trim_ascii();
        // Stop at the end of the header, the end of the file or the limit; the parser names
        // what is wrong with what was read.
        if n == 0 || line == b"end_header" || bytes.len() >= MAX_HEADER_BYTES {
            break;
        }
        // A first line other than the magic: no need to read further (a binary file may
        // have no newline for megabytes).
        if before == 0 && line != b"ply" {
            break;
        }
    }
    parse_header(&bytes, path)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn read_header_stops_at_end_header_and_at_its_limit() {
        let path = Path::new("x.ply");
        let head = b"ply\r\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n\
                     element face 1\nproperty list uchar int vertex_indices\nend_header\n";
        let mut bytes = head.to_vec();
        bytes.extend_from_slice(&[0xff; 64]);
        let mut reader = std::io::Cursor::new(&bytes);
        let header = read_header(&mut reader, path).unwrap();
        assert_eq!(header.body, head.len());
        assert_eq!(reader.position() as usize, head.len());
        assert_eq!(header.encoding, Encoding::BinaryLe);
        let counts: Vec<_> = header
            .elements
            .iter()
            .map(|e| (e.name.as_str(), e.count))
            .collect();
        assert_eq!(counts, [("vertex", 2), ("face", 1)]);
        assert_eq!(header.elements[1].properties[0].name(), "vertex_indices");
        // Comments past the limit: refused after 1 MiB, naming the file.
        let mut long = b"ply\nformat ascii 1.0\n".to_vec();
        while long.len() <= MAX_HEADER_BYTES {
            long.extend_from_slice(b"comment filler filler filler filler\n");
        }
        long.extend_from_slice(b"end_header\n");
        let e = read_header(&mut std::io::Cursor::new(&long), path).unwrap_err();
        assert!(
            e.to_string().contains("x.ply") && e.to_string().contains("end_header"),
            "{e}"
        );
        // Not PLY: one line read.
        let e = read_header(&mut std::io::Cursor::new(b"solid x\nfacet\n"), path).unwrap_err();
        assert!(e.to_string().contains("magic"), "{e}");
    }
}

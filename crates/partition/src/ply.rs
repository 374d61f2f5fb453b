//! A streaming PLY reader: the header, then the vertex positions and face index lists handed to
//! callbacks record by record, never held. ASCII, binary little- and big-endian; any scalar
//! types; elements other than `vertex` and `face` are skipped (seeked over when fixed-size).
//!
//! mesh::io has the project's PLY loader, but it parses a file held in memory and its header
//! types are private to it; this reader reads from a file handle, so the header's scalar types
//! and element declarations are parsed twice (the next step: one public header parser in
//! mesh::io serving both).
//!
//! Nothing in the header is trusted beyond what the file holds: the element counts are checked
//! against the file's length (a record takes at least its binary size, or two bytes per scalar
//! in ASCII) before any per-vertex array is sized from them, a short body is
//! [`PartitionError::Truncated`], an index past the vertices is
//! [`PartitionError::IndexOutOfRange`].

use crate::PartitionError;
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// Header lines beyond this many bytes: not a PLY file.
const MAX_HEADER_BYTES: u64 = 1 << 20;
/// Read buffer of a pass.
const BUFFER: usize = 1 << 20;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    BinaryLe,
    BinaryBe,
}

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
}

#[derive(Debug, Clone, Copy)]
enum Property {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<(String, Property)>,
}

impl Element {
    /// Bytes of one binary record when it has no list.
    fn fixed_size(&self) -> Option<usize> {
        self.properties
            .iter()
            .map(|(_, p)| match p {
                Property::Scalar(s) => Some(s.size()),
                Property::List { .. } => None,
            })
            .sum()
    }

    /// The fewest bytes a record can take.
    fn min_size(&self, encoding: Encoding) -> u64 {
        self.properties
            .iter()
            .map(|(_, p)| match (encoding, p) {
                (Encoding::Ascii, _) => 2,
                (_, Property::Scalar(s)) => s.size() as u64,
                (_, Property::List { count, .. }) => count.size() as u64,
            })
            .sum()
    }
}

/// What a pass hands each face's index list to.
pub(crate) type FaceVisitor<'a> = &'a mut dyn FnMut(&[u32]) -> Result<(), PartitionError>;

/// An opened PLY file: its header, and where the positions and the index lists are.
#[derive(Debug)]
pub(crate) struct PlyStream {
    path: PathBuf,
    encoding: Encoding,
    elements: Vec<Element>,
    body: u64,
    vertex: usize,
    face: usize,
    xyz: [usize; 3],
    indices: usize,
}

impl PlyStream {
    /// Read and check the header of `path`.
    pub(crate) fn open(path: &Path) -> Result<PlyStream, PartitionError> {
        let malformed = |problem: String| PartitionError::Malformed {
            path: path.to_path_buf(),
            problem,
        };
        let file = File::open(path).map_err(|source| PartitionError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let len = file.metadata().map(|m| m.len()).unwrap_or(0);
        let mut reader = BufReader::new(file).take(MAX_HEADER_BYTES);
        let mut line = String::new();
        let mut body = 0u64;
        let mut encoding = None;
        let mut elements: Vec<Element> = Vec::new();
        let mut first = true;
        loop {
            line.clear();
            let n = reader
                .read_line(&mut line)
                .map_err(|_| malformed("the header is not text (or not a PLY file)".to_string()))?;
            if n == 0 {
                return Err(malformed("no end_header line".to_string()));
            }
            body += n as u64;
            let words: Vec<&str> = line.split_ascii_whitespace().collect();
            if first {
                if words != ["ply"] {
                    return Err(malformed("does not start with 'ply'".to_string()));
                }
                first = false;
                continue;
            }
            match words.as_slice() {
                ["format", f, _] => {
                    encoding = Some(match *f {
                        "ascii" => Encoding::Ascii,
                        "binary_little_endian" => Encoding::BinaryLe,
                        "binary_big_endian" => Encoding::BinaryBe,
                        other => return Err(malformed(format!("unknown format '{other}'"))),
                    })
                }
                ["element", name, count] => elements.push(Element {
                    name: name.to_string(),
                    count: count
                        .parse()
                        .map_err(|_| malformed(format!("element {name}: bad count '{count}'")))?,
                    properties: Vec::new(),
                }),
                ["property", "list", count, item, name] => {
                    let (Some(count), Some(item)) = (Scalar::parse(count), Scalar::parse(item))
                    else {
                        return Err(malformed(format!("property {name}: unknown type")));
                    };
                    let element = elements
                        .last_mut()
                        .ok_or_else(|| malformed(format!("property {name} before any element")))?;
                    element
                        .properties
                        .push((name.to_string(), Property::List { count, item }));
                }
                ["property", ty, name] => {
                    let ty = Scalar::parse(ty).ok_or_else(|| {
                        malformed(format!("property {name}: unknown type '{ty}'"))
                    })?;
                    let element = elements
                        .last_mut()
                        .ok_or_else(|| malformed(format!("property {name} before any element")))?;
                    element
                        .properties
                        .push((name.to_string(), Property::Scalar(ty)));
                }
                ["end_header"] => break,
                ["comment", ..] | ["obj_info", ..] | [] => {}
                _ => {
                    return Err(malformed(format!(
                        "unexpected header line '{}'",
                        line.trim()
                    )));
                }
            }
        }
        let encoding = encoding.ok_or_else(|| malformed("no format line".to_string()))?;
        let find = |name: &str| elements.iter().position(|e| e.name == name);
        let vertex = find("vertex").ok_or_else(|| malformed("no vertex element".to_string()))?;
        let face = find("face").ok_or_else(|| malformed("no face element".to_string()))?;
        if face < vertex {
            return Err(malformed(
                "the faces come before the vertices (not supported by the streaming reader)"
                    .to_string(),
            ));
        }
        let scalar = |name: &str| {
            elements[vertex]
                .properties
                .iter()
                .position(|(n, p)| n == name && matches!(p, Property::Scalar(_)))
                .ok_or_else(|| malformed(format!("the vertices have no scalar '{name}'")))
        };
        let xyz = [scalar("x")?, scalar("y")?, scalar("z")?];
        let indices = elements[face]
            .properties
            .iter()
            .position(|(n, p)| {
                (n == "vertex_indices" || n == "vertex_index")
                    && matches!(p, Property::List { item, .. } if !matches!(item, Scalar::F32 | Scalar::F64))
            })
            .ok_or_else(|| malformed("the faces have no integer list 'vertex_indices'".to_string()))?;
        // Counts are claims: the body must be able to hold them.
        let mut need = 0u64;
        for e in &elements {
            need = need.saturating_add(e.count.saturating_mul(e.min_size(encoding)));
        }
        if need > len.saturating_sub(body) {
            return Err(PartitionError::Truncated {
                path: path.to_path_buf(),
                problem: format!(
                    "the header's counts need at least {need} bytes, the body has {}",
                    len.saturating_sub(body)
                ),
            });
        }
        if elements[vertex].count > u64::from(u32::MAX) {
            return Err(malformed("more than 2³² vertices".to_string()));
        }
        Ok(PlyStream {
            path: path.to_path_buf(),
            encoding,
            elements,
            body,
            vertex,
            face,
            xyz,
            indices,
        })
    }

    /// What the header holds besides the positions and the faces' index lists ("vertex
    /// property nx", "element edge"): what a positions-only run ignores.
    pub(crate) fn ignored(&self) -> Vec<String> {
        let mut ignored = Vec::new();
        for (k, element) in self.elements.iter().enumerate() {
            if k != self.vertex && k != self.face {
                ignored.push(format!("element {}", element.name));
                continue;
            }
            for (p, (name, _)) in element.properties.iter().enumerate() {
                let used = if k == self.vertex {
                    self.xyz.contains(&p)
                } else {
                    p == self.indices
                };
                if !used {
                    ignored.push(format!("{} property {name}", element.name));
                }
            }
        }
        ignored
    }

    /// Vertex records the header announces (checked against the file's length).
    pub(crate) fn vertex_count(&self) -> usize {
        self.elements[self.vertex].count as usize
    }

    /// Face records the header announces (checked against the file's length).
    pub(crate) fn face_count(&self) -> usize {
        self.elements[self.face].count as usize
    }

    /// One pass over the body: every vertex position to `vertex` (index, position); with
    /// `face`, every face's index list (range-checked) to it. Without `face` the pass stops after
    /// the vertices.
    pub(crate) fn read(
        &self,
        vertex: &mut dyn FnMut(u32, [f64; 3]) -> Result<(), PartitionError>,
        mut face: Option<FaceVisitor<'_>>,
    ) -> Result<(), PartitionError> {
        let io = |source| PartitionError::Io {
            path: self.path.clone(),
            source,
        };
        let mut file = File::open(&self.path).map_err(io)?;
        file.seek(SeekFrom::Start(self.body)).map_err(io)?;
        let mut src = Source {
            reader: BufReader::with_capacity(BUFFER, file),
            encoding: self.encoding,
            line: String::new(),
            at: 0,
        };
        let vertices = self.vertex_count() as u64;
        let mut values = Vec::new();
        let mut list = Vec::new();
        for (k, element) in self.elements.iter().enumerate() {
            if k > self.face || (k > self.vertex && face.is_none()) {
                break;
            }
            let wanted = k == self.vertex || k == self.face;
            if !wanted
                && self.encoding != Encoding::Ascii
                && let Some(size) = element.fixed_size()
            {
                let skip = (size as u64).saturating_mul(element.count);
                src.reader.seek_relative(skip as i64).map_err(io)?;
                continue;
            }
            for record in 0..element.count {
                let truncated = |e: std::io::Error| self.record_error(e, element, record);
                values.clear();
                for (p, (_, property)) in element.properties.iter().enumerate() {
                    match *property {
                        Property::Scalar(ty) => values.push(src.scalar(ty).map_err(truncated)?),
                        Property::List { count, item } => {
                            let n = src.scalar(count).map_err(truncated)?;
                            if !(0.0..=1e6).contains(&n) || n.fract() != 0.0 {
                                return Err(self.malformed(element, record, "bad list length"));
                            }
                            let keep = k == self.face && p == self.indices;
                            if keep {
                                list.clear();
                            }
                            for _ in 0..n as usize {
                                let v = src.scalar(item).map_err(truncated)?;
                                if keep {
                                    if !(0.0..vertices as f64).contains(&v) || v.fract() != 0.0 {
                                        return Err(PartitionError::IndexOutOfRange {
                                            path: self.path.clone(),
                                            face: record,
                                            index: v,
                                            vertices,
                                        });
                                    }
                                    list.push(v as u32);
                                }
                            }
                        }
                    }
                }
                if k == self.vertex {
                    let p = self.xyz.map(|i| values[i]);
                    if p.iter().any(|c| !c.is_finite()) {
                        return Err(self.malformed(element, record, "non-finite coordinate"));
                    }
                    vertex(record as u32, p)?;
                } else if k == self.face
                    && let Some(face) = face.as_mut()
                {
                    face(&list)?;
                }
            }
        }
        Ok(())
    }

    fn malformed(&self, element: &Element, record: u64, what: &str) -> PartitionError {
        PartitionError::Malformed {
            path: self.path.clone(),
            problem: format!("{} {record}: {what}", element.name),
        }
    }

    fn record_error(&self, e: std::io::Error, element: &Element, record: u64) -> PartitionError {
        match e.kind() {
            std::io::ErrorKind::UnexpectedEof => PartitionError::Truncated {
                path: self.path.clone(),
                problem: format!(
                    "the file ends in {} {record} of {}",
                    element.name, element.count
                ),
            },
            std::io::ErrorKind::InvalidData => self.malformed(element, record, &e.to_string()),
            _ => PartitionError::Io {
                path: self.path.clone(),
                source: e,
            },
        }
    }
}

/// The body's bytes or tokens.
struct Source {
    reader: BufReader<File>,
    encoding: Encoding,
    /// ASCII: the current line and how far it is consumed.
    line: String,
    at: usize,
}

impl Source {
    fn scalar(&mut self, ty: Scalar) -> std::io::Result<f64> {
        let mut b = [0u8; 8];
        let n = ty.size();
        let bytes = &mut b[..n];
        match self.encoding {
            Encoding::Ascii => return self.token(),
            Encoding::BinaryLe => self.reader.read_exact(bytes)?,
            Encoding::BinaryBe => {
                self.reader.read_exact(bytes)?;
                bytes.reverse();
            }
        }
        Ok(match ty {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    /// The next whitespace-separated ASCII number (records may span lines).
    fn token(&mut self) -> std::io::Result<f64> {
        loop {
            let rest = &self.line[self.at..];
            let start = rest.len() - rest.trim_start().len();
            let rest = &rest[start..];
            if !rest.is_empty() {
                let end = rest
                    .find(|c: char| c.is_ascii_whitespace())
                    .unwrap_or(rest.len());
                let token = &rest[..end];
                self.at += start + end;
                return token.parse::<f64>().map_err(|_| {
                    std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        format!("'{token}' is not a number"),
                    )
                });
            }
            self.line.clear();
            self.at = 0;
            if self.reader.read_line(&mut self.line)? == 0 {
                return Err(std::io::ErrorKind::UnexpectedEof.into());
            }
        }
    }
}

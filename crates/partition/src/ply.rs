//! A streaming PLY reader: the header, then the vertex positions and face index lists handed to
//! callbacks record by record, never held. ASCII, binary little- and big-endian; any scalar
//! types; elements other than `vertex` and `face` are skipped (seeked over when fixed-size).
//!
//! The header is read by mesh::io's PLY header parser ([`mesh::io::ply::read_header`], the
//! project's one), with its limit (1 MiB); the body is read here from a file handle, since the
//! loader's body readers take a file held in memory.
//!
//! Nothing in the header is trusted beyond what the file holds: the element counts are checked
//! against the file's length (a record takes at least its binary size, or two bytes per scalar
//! in ASCII) before any per-vertex array is sized from them, a short body is
//! [`PartitionError::Truncated`], an index past the vertices is
//! [`PartitionError::IndexOutOfRange`].

use crate::PartitionError;
use mesh::io::ply::{Element, Encoding, Property, Scalar};
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// Read buffer of a pass.
const BUFFER: usize = 1 << 20;

/// Bytes of one binary record of `element` when it has no list.
fn fixed_size(element: &Element) -> Option<usize> {
    element
        .properties
        .iter()
        .map(|p| match p {
            Property::Scalar(_, s) => Some(s.size()),
            Property::List(..) => None,
        })
        .sum()
}

/// The fewest bytes a record of `element` can take.
fn min_size(element: &Element, encoding: Encoding) -> u64 {
    element
        .properties
        .iter()
        .map(|p| match (encoding, p) {
            (Encoding::Ascii, _) => 2,
            (_, Property::Scalar(_, s)) => s.size() as u64,
            (_, Property::List(_, count, _)) => count.size() as u64,
        })
        .sum()
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
        let header =
            mesh::io::ply::read_header(&mut BufReader::new(file), path).map_err(|e| match e {
                mesh::error::MeshError::Parse {
                    location, message, ..
                } => malformed(format!("{location}: {message}")),
                mesh::error::MeshError::Io { source, .. } => PartitionError::Io {
                    path: path.to_path_buf(),
                    source,
                },
                other => PartitionError::Mesh(other),
            })?;
        let (encoding, elements, body) = (header.encoding, header.elements, header.body as u64);
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
                .position(|p| matches!(p, Property::Scalar(n, _) if n == name))
                .ok_or_else(|| malformed(format!("the vertices have no scalar '{name}'")))
        };
        let xyz = [scalar("x")?, scalar("y")?, scalar("z")?];
        let indices = elements[face]
            .properties
            .iter()
            .position(|p| {
                matches!(p, Property::List(n, _, item)
                    if (n == "vertex_indices" || n == "vertex_index") && item.is_integer())
            })
            .ok_or_else(|| {
                malformed("the faces have no integer list 'vertex_indices'".to_string())
            })?;
        // Counts are claims: the body must be able to hold them.
        let mut need = 0u64;
        for e in &elements {
            need = need.saturating_add((e.count as u64).saturating_mul(min_size(e, encoding)));
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
        if elements[vertex].count as u64 > u64::from(u32::MAX) {
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
            for (p, name) in element.properties.iter().map(Property::name).enumerate() {
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
        self.elements[self.vertex].count
    }

    /// Face records the header announces (checked against the file's length).
    pub(crate) fn face_count(&self) -> usize {
        self.elements[self.face].count
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
                && let Some(size) = fixed_size(element)
            {
                let skip = (size as u64).saturating_mul(element.count as u64);
                src.reader.seek_relative(skip as i64).map_err(io)?;
                continue;
            }
            for record in 0..element.count as u64 {
                let truncated = |e: std::io::Error| self.record_error(e, element, record);
                values.clear();
                for (p, property) in element.properties.iter().enumerate() {
                    match *property {
                        Property::Scalar(_, ty) => values.push(src.scalar(ty).map_err(truncated)?),
                        Property::List(_, count, item) => {
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

//! A streaming OBJ reader: `v` positions and `f` index lists (the position index of each corner,
//! 1-based or negative, i.e. relative to the vertices read so far), handed to callbacks line by
//! line; every other line is ignored. Opening the file counts its `v` and `f` lines (one pass),
//! so that an index can be range-checked and per-vertex arrays sized from what the file holds.
//!
//! A face may name a vertex defined after it (positive index): the face is still read, the
//! partition only places it by cells not yet known (cell 0), which costs balance, not
//! correctness (shared vertices are found from the faces, not from the cells).

use crate::PartitionError;
use crate::ply::FaceVisitor;
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

/// Read buffer of a pass.
const BUFFER: usize = 1 << 20;

/// An opened OBJ file and its counts.
/// The kinds of OBJ lines that carry attributes a positions-only run does not read.
const IGNORED: [&str; 4] = ["vt", "vn", "usemtl", "mtllib"];

#[derive(Debug)]
pub(crate) struct ObjStream {
    path: PathBuf,
    vertices: u64,
    faces: u64,
    /// Lines of the kinds a positions-only run ignores (`vt`, `vn`, `usemtl`, `mtllib`), with
    /// their counts.
    ignored: Vec<(&'static str, u64)>,
}

impl ObjStream {
    /// Count the vertices and faces of `path`.
    pub(crate) fn open(path: &Path) -> Result<ObjStream, PartitionError> {
        let mut stream = ObjStream {
            path: path.to_path_buf(),
            vertices: 0,
            faces: 0,
            ignored: Vec::new(),
        };
        let (mut v, mut f) = (0u64, 0u64);
        let mut ignored = IGNORED.map(|k| (k, 0u64));
        stream.lines(&mut |_, line| {
            match line.split_ascii_whitespace().next() {
                Some("v") => v += 1,
                Some("f") => f += 1,
                Some(kind) => {
                    if let Some(slot) = ignored.iter_mut().find(|(k, _)| *k == kind) {
                        slot.1 += 1;
                    }
                }
                None => {}
            }
            Ok(())
        })?;
        stream.ignored = ignored.into_iter().filter(|(_, n)| *n > 0).collect();
        if v > u64::from(u32::MAX) {
            return Err(PartitionError::Malformed {
                path: path.to_path_buf(),
                problem: "more than 2³² vertices".to_string(),
            });
        }
        (stream.vertices, stream.faces) = (v, f);
        Ok(stream)
    }

    /// The ignored kinds of lines found ("1200 vt lines").
    pub(crate) fn ignored(&self) -> Vec<String> {
        self.ignored
            .iter()
            .map(|(k, n)| format!("{n} {k} lines"))
            .collect()
    }

    /// `v` lines.
    pub(crate) fn vertex_count(&self) -> usize {
        self.vertices as usize
    }

    /// `f` lines.
    pub(crate) fn face_count(&self) -> usize {
        self.faces as usize
    }

    /// One pass: every position to `vertex`; with `face`, every face's (zero-based,
    /// range-checked) position indices to it.
    pub(crate) fn read(
        &self,
        vertex: &mut dyn FnMut(u32, [f64; 3]) -> Result<(), PartitionError>,
        mut face: Option<FaceVisitor<'_>>,
    ) -> Result<(), PartitionError> {
        let mut seen = 0u64;
        let mut faces = 0u64;
        let mut list = Vec::new();
        self.lines(&mut |number, line| {
            let mut words = line.split_ascii_whitespace();
            match words.next() {
                Some("v") => {
                    let mut p = [0.0; 3];
                    for c in &mut p {
                        *c = words
                            .next()
                            .and_then(|w| w.parse::<f64>().ok())
                            .filter(|c| c.is_finite())
                            .ok_or_else(|| self.malformed(number, "a vertex needs 3 numbers"))?;
                    }
                    vertex(seen as u32, p)?;
                    seen += 1;
                }
                Some("f") if face.is_some() => {
                    list.clear();
                    for w in words {
                        let i: i64 = w
                            .split('/')
                            .next()
                            .and_then(|i| i.parse().ok())
                            .ok_or_else(|| {
                                self.malformed(number, "a face index is not a number")
                            })?;
                        let index = if i < 0 { seen as i64 + i } else { i - 1 };
                        if index < 0 || index as u64 >= self.vertices {
                            return Err(PartitionError::IndexOutOfRange {
                                path: self.path.clone(),
                                face: faces,
                                index: i as f64,
                                vertices: self.vertices,
                            });
                        }
                        list.push(index as u32);
                    }
                    faces += 1;
                    if let Some(face) = face.as_mut() {
                        face(&list)?;
                    }
                }
                _ => {}
            }
            Ok(())
        })
    }

    fn malformed(&self, line: u64, what: &str) -> PartitionError {
        PartitionError::Malformed {
            path: self.path.clone(),
            problem: format!("line {line}: {what}"),
        }
    }

    /// Every line of the file (numbered from 1) to `visit`.
    fn lines(
        &self,
        visit: &mut dyn FnMut(u64, &str) -> Result<(), PartitionError>,
    ) -> Result<(), PartitionError> {
        let io = |source| PartitionError::Io {
            path: self.path.clone(),
            source,
        };
        let mut reader = BufReader::with_capacity(BUFFER, File::open(&self.path).map_err(io)?);
        let mut bytes = Vec::new();
        let mut number = 0u64;
        loop {
            bytes.clear();
            if reader.read_until(b'\n', &mut bytes).map_err(io)? == 0 {
                return Ok(());
            }
            number += 1;
            let line = std::str::from_utf8(&bytes)
                .map_err(|_| self.malformed(number, "not UTF-8 text"))?;
            visit(number, line)?;
        }
    }
}

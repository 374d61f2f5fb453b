//! STL reader (ASCII or binary, via stl_io's triangle readers) and binary writer. STL stores
//! unindexed triangles; corners with bit-identical positions are welded into one vertex
//! ([`weld_key`], [`Welder`]: stl_io's rule, first occurrence first).
//!
//! Public for the partition's streaming reader (`gng3d-partition`), so that both read STL by one
//! set of rules: [`StlFile`] streams a file's triangles from a file handle with the loader's
//! choice of encoding, size check and ASCII normalisation, and [`weld_key`] is the weld.
//!
//! Which of the two encodings a file uses is decided here, not by stl_io's probe (which wants
//! `"solid "` with a space and reads a bare `solid` first line as binary): a file is binary when
//! its size is exactly `84 + 50 × count` for the count in its header, ASCII when it starts with
//! `solid` and says `facet` or `endsolid` somewhere, and binary otherwise. Binary files whose
//! size does not match their count get an error (too short) or a warning (extra records).

use super::RawMesh;
use crate::TriMesh;
use crate::error::{MeshError, MeshWarning};
use glam::Vec3;
use std::collections::HashMap;
use std::io::{BufRead, Read, Seek, SeekFrom};
use std::path::Path;

/// Bytes of the binary header: 80 free bytes and a little-endian u32 triangle count.
const HEADER: usize = 84;
/// Bytes of one binary triangle record: normal, three corners (12 f32) and a u16 attribute.
const RECORD: usize = 50;

/// True when `bytes` is an ASCII STL: starts with `solid`, mentions a facet or `endsolid`, and
/// is not at the same time a size-consistent binary file (binary headers may start with
/// "solid" too).
fn is_ascii(bytes: &[u8]) -> bool {
    is_ascii_by(bytes, bytes.len() as u64, || {
        let has = |needle: &[u8]| bytes.windows(needle.len()).any(|w| w == needle);
        has(b"facet") || has(b"endsolid")
    })
}

/// [`is_ascii`] of a file whose first bytes are `head` (at least its first 84 bytes past any
/// leading whitespace), whose length is `len`, and which `mentions` a facet or `endsolid`
/// (asked last, only when the rest leaves the question open).
fn is_ascii_by(head: &[u8], len: u64, mentions: impl FnOnce() -> bool) -> bool {
    let start = head
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(head.len());
    if !head[start..].starts_with(b"solid") {
        return false;
    }
    if head.len() >= HEADER {
        let count = u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64;
        if count
            .checked_mul(RECORD as u64)
            .and_then(|n| n.checked_add(HEADER as u64))
            == Some(len)
        {
            return false;
        }
    }
    mentions()
}

/// ASCII STL text with its first line made acceptable to stl_io (`solid <name>`) and every
/// facet normal written as `0 0 0`: the normals are not used (faces come from their corners),
/// and exporters write `facet normal -nan -nan -nan` for zero-area facets, which refused the
/// whole file (the same normals in binary STL load). Line by line, so a file is streamed.
struct NormalisedAscii<R> {
    inner: R,
    /// Whether the first line (after leading whitespace) is done.
    started: bool,
    line: Vec<u8>,
    /// The normalised bytes not handed out yet: `out[at..]`.
    out: Vec<u8>,
    at: usize,
}

impl<R: BufRead> NormalisedAscii<R> {
    fn new(inner: R) -> NormalisedAscii<R> {
        NormalisedAscii {
            inner,
            started: false,
            line: Vec::new(),
            out: Vec::new(),
            at: 0,
        }
    }

    /// The next line's normalised bytes into `out`; false at the end.
    fn fill(&mut self) -> std::io::Result<bool> {
        self.out.clear();
        self.at = 0;
        loop {
            self.line.clear();
            if self.inner.read_until(b'\n', &mut self.line)? == 0 {
                return Ok(false);
            }
            if self.started {
                let line = &self.line[..];
                let body = line.trim_ascii_start();
                if body.len() >= 12 && body[..12].eq_ignore_ascii_case(b"facet normal") {
                    self.out.extend_from_slice(&line[..line.len() - body.len()]);
                    self.out.extend_from_slice(b"facet normal 0 0 0");
                    self.out.extend_from_slice(if line.ends_with(b"\r\n") {
                        b"\r\n"
                    } else if line.ends_with(b"\n") {
                        b"\n"
                    } else {
                        b""
                    });
                } else {
                    self.out.extend_from_slice(line);
                }
                return Ok(true);
            }
            // Leading whitespace (blank lines included) is skipped; the first line is `solid
            // <name>` (the caller checked it starts with `solid`).
            let Some(start) = self.line.iter().position(|b| !b.is_ascii_whitespace()) else {
                continue;
            };
            self.started = true;
            let first = &self.line[start..];
            let newline = first.ends_with(b"\n");
            let name = first.get(5..).unwrap_or_default().trim_ascii();
            self.out.extend_from_slice(b"solid ");
            self.out
                .extend_from_slice(if name.is_empty() { b"unnamed" } else { name });
            if newline {
                self.out.push(b'\n');
            }
            return Ok(true);
        }
    }
}

/// Back to the start only (stl_io rewinds after probing the first line).
impl<R: BufRead + Seek> Seek for NormalisedAscii<R> {
    fn seek(&mut self, to: SeekFrom) -> std::io::Result<u64> {
        if to != SeekFrom::Start(0) {
            return Err(std::io::ErrorKind::Unsupported.into());
        }
        self.inner.seek(to)?;
        (self.started, self.at) = (false, 0);
        self.out.clear();
        Ok(0)
    }
}

impl<R: BufRead> Read for NormalisedAscii<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        while self.at == self.out.len() {
            if !self.fill()? {
                return Ok(0);
            }
        }
        let n = buf.len().min(self.out.len() - self.at);
        buf[..n].copy_from_slice(&self.out[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// Checks the binary layout: enough bytes for the header count; warns about extra bytes.
fn check_binary(bytes: &[u8], path: &Path, raw: &mut RawMesh) -> Result<(), MeshError> {
    let count = bytes
        .get(80..84)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]));
    if let Some(w) = check_binary_by(count, bytes.len() as u64, path)? {
        raw.warnings.push(w);
    }
    Ok(())
}

/// [`check_binary`] of a file of `len` bytes whose header holds `count` (`None`: shorter than a
/// header): the error, or the warning about extra bytes.
fn check_binary_by(
    count: Option<u32>,
    len: u64,
    path: &Path,
) -> Result<Option<MeshWarning>, MeshError> {
    if len == 0 {
        return Err(MeshError::Empty {
            path: path.to_path_buf(),
        });
    }
    let Some(count) = count.filter(|_| len >= HEADER as u64) else {
        return Err(MeshError::parse(
            path,
            "header",
            format!(
                "not an ASCII STL (no `solid ... facet`) and too short for a binary STL: {len} bytes, \
                 but a binary STL has an 84-byte header (80 bytes + triangle count)"
            ),
        ));
    };
    let count = u64::from(count);
    let records = (len - HEADER as u64) / RECORD as u64;
    let expected = HEADER as u64 + RECORD as u64 * count;
    if count > records {
        return Err(MeshError::parse(
            path,
            "header",
            format!(
                "binary STL header says {count} triangles ({expected} bytes), but the file has \
                 {len} bytes ({records} complete 50-byte records)"
            ),
        ));
    }
    Ok((expected != len).then_some(MeshWarning::StlSizeMismatch {
        header_triangles: count,
        file_bytes: len,
    }))
}

/// The weld key of a corner position: its coordinates' bits. Corners with one key are one
/// vertex (stl_io's rule: exact equality, `-0.0` and `0.0` apart).
pub fn weld_key(p: [f32; 3]) -> [u32; 3] {
    p.map(f32::to_bits)
}

/// Corner positions welded by [`weld_key`] into vertices numbered in order of first occurrence.
#[derive(Debug, Default)]
pub struct Welder {
    index: HashMap<[u32; 3], u32>,
    positions: Vec<Vec3>,
}

impl Welder {
    /// The vertex of corner position `p` (a new one when `p` was not seen).
    pub fn vertex(&mut self, p: [f32; 3]) -> u32 {
        let next = self.positions.len() as u32;
        let v = *self.index.entry(weld_key(p)).or_insert(next);
        if v == next {
            self.positions.push(Vec3::from_array(p));
        }
        v
    }

    /// The vertices' positions, by vertex.
    pub fn into_positions(self) -> Vec<Vec3> {
        self.positions
    }
}

/// An STL file opened for streaming ([`StlFile::triangles`]): its encoding chosen and a binary
/// file's count checked against its length, as the loader does, without reading it whole.
#[derive(Debug)]
pub struct StlFile {
    path: std::path::PathBuf,
    ascii: bool,
    count: Option<u64>,
    warning: Option<MeshWarning>,
}

/// Bytes of the start of a file read to choose its encoding (leading whitespace, the header).
const HEAD: usize = 4096;

impl StlFile {
    /// Open `path`: ASCII when it starts with `solid`, is not a size-consistent binary file and
    /// mentions a facet or `endsolid` (then the file is scanned for them); binary otherwise,
    /// with its header's count checked against its length.
    pub fn open(path: &Path) -> Result<StlFile, MeshError> {
        let io = |source| MeshError::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut file = std::fs::File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        let mut head = Vec::with_capacity(HEAD);
        (&mut file)
            .take(HEAD as u64)
            .read_to_end(&mut head)
            .map_err(io)?;
        let ascii = is_ascii_by(&head, len, || mentions(path, &[b"facet", b"endsolid"]));
        let (count, warning) = if ascii {
            (None, None)
        } else {
            let count = head
                .get(80..84)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]));
            (count.map(u64::from), check_binary_by(count, len, path)?)
        };
        Ok(StlFile {
            path: path.to_path_buf(),
            ascii,
            count,
            warning,
        })
    }

    /// Whether the file is ASCII.
    pub fn is_ascii(&self) -> bool {
        self.ascii
    }

    /// A binary file's triangle count (checked against its length); `None` for ASCII.
    pub fn binary_count(&self) -> Option<u64> {
        self.count
    }

    /// The warning of a binary file longer than its count says (the rest is not read).
    pub fn warning(&self) -> Option<&MeshWarning> {
        self.warning.as_ref()
    }

    /// One pass over the file: each triangle's three corner positions to `visit`, in file
    /// order. Returns the number of triangles. A record that does not parse is a
    /// [`MeshError::Parse`] naming the file.
    pub fn triangles<E: From<MeshError>>(
        &self,
        visit: &mut dyn FnMut([[f32; 3]; 3]) -> Result<(), E>,
    ) -> Result<u64, E> {
        let file = std::fs::File::open(&self.path).map_err(|source| MeshError::Io {
            path: self.path.clone(),
            source,
        })?;
        let mut reader = std::io::BufReader::with_capacity(1 << 20, file);
        each_triangle(&mut reader, self.ascii, &self.path, visit)
    }
}

/// Whether the file at `path` holds one of `needles`, read in blocks (a failed read: no).
fn mentions(path: &Path, needles: &[&[u8]]) -> bool {
    let Ok(mut file) = std::fs::File::open(path) else {
        return false;
    };
    let keep = needles.iter().map(|n| n.len()).max().unwrap_or(0);
    let mut block = vec![0u8; 1 << 20];
    let mut carried = 0;
    loop {
        let n = match file.read(&mut block[carried..]) {
            Ok(0) | Err(_) => return false,
            Ok(n) => n,
        };
        let filled = &block[..carried + n];
        if needles
            .iter()
            .any(|needle| filled.windows(needle.len()).any(|w| w == *needle))
        {
            return true;
        }
        // The tail of this block starts the next one: a needle across the cut is found.
        let len = filled.len();
        carried = keep.min(len);
        block.copy_within(len - carried..len, 0);
    }
}

/// Every triangle of the STL text (`ascii`) or binary data read by `reader` from its start to
/// `visit`; stl_io parses the records. Returns the number of triangles.
fn each_triangle<E: From<MeshError>, R: BufRead + Seek>(
    reader: &mut R,
    ascii: bool,
    path: &Path,
    visit: &mut dyn FnMut([[f32; 3]; 3]) -> Result<(), E>,
) -> Result<u64, E> {
    let what = if ascii {
        "ascii stl data"
    } else {
        "binary stl data"
    };
    let parse_error = |e: std::io::Error| MeshError::parse(path, what, e.to_string());
    let mut normalised;
    // stl_io's reader of either encoding (a binary one reads exactly the header's count).
    let triangles = if ascii {
        normalised = NormalisedAscii::new(reader);
        stl_io::create_stl_reader(&mut normalised)
    } else {
        stl_io::create_stl_reader(reader)
    }
    .map_err(parse_error)?;
    let mut count = 0u64;
    for t in triangles {
        let t = t.map_err(parse_error)?;
        visit(t.vertices.map(|v| v.0))?;
        count += 1;
    }
    Ok(count)
}

/// Parse an STL file.
pub(crate) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh, MeshError> {
    let mut raw = RawMesh::default();
    let ascii = is_ascii(bytes);
    if !ascii {
        check_binary(bytes, path, &mut raw)?;
    }
    let mut welder = Welder::default();
    let mut triangles = Vec::new();
    each_triangle::<MeshError, _>(&mut std::io::Cursor::new(bytes), ascii, path, &mut |t| {
        triangles.push(t.map(|p| welder.vertex(p)));
        Ok(())
    })?;
    raw.positions = welder.into_positions();
    raw.triangles = triangles;
    Ok(raw)
}

/// Binary STL bytes for `mesh` (facet normals from the geometry).
/// A non-zero `origin` is added to the positions in f64 and rounded to STL's f32.
pub(crate) fn write(mesh: &TriMesh, origin: glam::DVec3) -> std::io::Result<Vec<u8>> {
    let normals = mesh.face_normals();
    let moved = |p: Vec3| {
        if origin == glam::DVec3::ZERO {
            p
        } else {
            (p.as_dvec3() + origin).as_vec3()
        }
    };
    let triangles: Vec<stl_io::Triangle> = (0..mesh.triangles.len())
        .map(|f| {
            let [a, b, c] = mesh.triangle(f).map(moved);
            stl_io::Triangle {
                normal: stl_io::Normal::new(normals[f].to_array()),
                vertices: [
                    stl_io::Vertex::new(a.to_array()),
                    stl_io::Vertex::new(b.to_array()),
                    stl_io::Vertex::new(c.to_array()),
                ],
            }
        })
        .collect();
    let mut out = Vec::with_capacity(84 + 50 * triangles.len());
    stl_io::write_stl(&mut out, triangles.iter())?;
    Ok(out)
}

//! STL input of the partition (binary and ASCII), streamed: STL stores each triangle's corner
//! positions, no shared vertices, so the corners are welded here by the single-process
//! loader's rule (`mesh::io::stl::weld_key`: bit-equal positions are one vertex), which
//! reads the file with the loader's choice of encoding, size check and ASCII rules
//! (`mesh::io::stl::StlFile`).
//!
//! A weld needs every occurrence of a position in one place; a position's grid cell is a
//! function of the position, so the weld is done per cell, never over the whole mesh:
//! - Pass 1 (input): bounding box and a sample (the first corner of every n/262,144-th
//!   triangle) size the grid, as for PLY/OBJ.
//! - Pass 2 (input): each triangle (one whose corners weld into fewer than three vertices is
//!   dropped, as the loader's validation drops it) goes to the smallest cell of its corners,
//!   written as its three positions to that cell's `cell-NNNNN.corners`; each corner outside
//!   its face's cell is written with that cell to `border.corners`.
//! - Border: the border's positions in memory (the only per-vertex table: border vertices
//!   only), with the cells whose faces use them; one read of every `.corners` file adds the
//!   position's own cell when its faces use it. A position used by faces of two cells is
//!   shared: ids 0..S in the order of their keys, written to `shared.verts`.
//! - Each cell in turn (one cell in memory): its corners welded (`mesh::io::stl::Welder`),
//!   shared positions given their id, the others ids after every earlier cell's, written as
//!   the `.faces` and `.verts` chunks the cells read for PLY/OBJ; its `.corners` removed.

use crate::PartitionError;
use crate::chunk::{VERTEX_RECORD, chunk_paths};
use crate::grid::{BYTES_PER_FACE, Grid, SAMPLE};
use mesh::io::stl::{StlFile, Welder, weld_key};
use rustc_hash::FxHashMap;
use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

/// Write buffer per cell file.
const CELL_BUFFER: usize = 1 << 16;
/// A triangle in a `.corners` file: three positions (`f32` bits).
const TRIANGLE: usize = 36;
/// A record of `border.corners`: a position's bits and the cell (`u16`) of a face using it.
const BORDER: usize = 14;

/// An opened STL file and its triangle count.
#[derive(Debug)]
pub(crate) struct StlStream {
    path: PathBuf,
    file: StlFile,
    faces: u64,
}

/// A mesh::io error as this crate's (it names the file).
fn mesh_error(e: mesh::error::MeshError) -> PartitionError {
    PartitionError::Mesh(e)
}

impl StlStream {
    /// Open `path` and count its triangles (binary: its header's count, checked against its
    /// length; ASCII: one pass).
    pub(crate) fn open(path: &Path) -> Result<StlStream, PartitionError> {
        let file = StlFile::open(path).map_err(mesh_error)?;
        let faces = match file.binary_count() {
            Some(n) => n,
            None => file.triangles::<PartitionError>(&mut |_| Ok(()))?,
        };
        Ok(StlStream {
            path: path.to_path_buf(),
            file,
            faces,
        })
    }

    /// Triangle records.
    pub(crate) fn face_count(&self) -> usize {
        self.faces as usize
    }

    /// One pass: each triangle's corners to `visit` (non-finite coordinates refused).
    fn read(
        &self,
        visit: &mut dyn FnMut([[f32; 3]; 3]) -> Result<(), PartitionError>,
    ) -> Result<(), PartitionError> {
        let mut record = 0u64;
        self.file.triangles::<PartitionError>(&mut |t| {
            if t.iter().flatten().any(|c| !c.is_finite()) {
                return Err(PartitionError::Malformed {
                    path: self.path.clone(),
                    problem: format!("triangle {record}: non-finite coordinate"),
                });
            }
            record += 1;
            visit(t)
        })?;
        Ok(())
    }
}

/// The cell of position `p`.
fn cell(grid: &Grid, p: [f32; 3]) -> u16 {
    grid.cell(p.map(f64::from))
}

/// What the STL partition wrote: vertices (welded), shared vertices, triangles per cell.
pub(crate) struct Written {
    pub(crate) vertices: u64,
    pub(crate) shared: u64,
    pub(crate) cell_faces: Vec<u64>,
}

/// The partition of an STL input into `work` (already cleared) for `budget`: the chunk files
/// of the PLY/OBJ path (see the module).
pub(crate) fn partition(
    stl: &StlStream,
    work: &Path,
    budget: u64,
) -> Result<Written, PartitionError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| PartitionError::Io { path, source }
    };
    let empty = || PartitionError::Empty {
        path: stl.path.clone(),
    };
    // Pass 1: bounding box and a sample.
    let stride = stl.face_count().div_ceil(SAMPLE).max(1);
    let (mut min, mut max) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let mut sample = Vec::new();
    let mut record = 0usize;
    stl.read(&mut |t| {
        for p in t {
            for i in 0..3 {
                min[i] = min[i].min(f64::from(p[i]));
                max[i] = max[i].max(f64::from(p[i]));
            }
        }
        if record.is_multiple_of(stride) {
            sample.push(t[0].map(f64::from));
        }
        record += 1;
        Ok(())
    })?;
    if sample.is_empty() {
        return Err(empty());
    }
    let faces_per_sample = record as f64 / sample.len() as f64;
    let grid = Grid::sized(
        min,
        max,
        &sample,
        faces_per_sample,
        (budget / BYTES_PER_FACE) as f64,
    );
    drop(sample);
    let cells = grid.len();
    // Pass 2: each triangle's corners to its cell, the corners outside it to the border.
    let corners_path = |k: usize| work.join(format!("cell-{k:05}.corners"));
    let border_path = work.join("border.corners");
    let mut corner_files = Vec::with_capacity(cells);
    for k in 0..cells {
        let path = corners_path(k);
        let file = File::create(&path).map_err(io(&path))?;
        corner_files.push(BufWriter::with_capacity(CELL_BUFFER, file));
    }
    let mut border_file = BufWriter::with_capacity(
        CELL_BUFFER,
        File::create(&border_path).map_err(io(&border_path))?,
    );
    let mut cell_faces = vec![0u64; cells];
    stl.read(&mut |t| {
        let keys = t.map(weld_key);
        if keys[0] == keys[1] || keys[1] == keys[2] || keys[0] == keys[2] {
            return Ok(());
        }
        let homes = t.map(|p| cell(&grid, p));
        let k = homes.iter().copied().min().unwrap_or(0);
        let mut bytes = [0u8; TRIANGLE];
        for (j, key) in keys.iter().enumerate() {
            for (i, bits) in key.iter().enumerate() {
                bytes[12 * j + 4 * i..12 * j + 4 * i + 4].copy_from_slice(&bits.to_le_bytes());
            }
            if homes[j] != k {
                let mut record = [0u8; BORDER];
                record[..12].copy_from_slice(&bytes[12 * j..12 * j + 12]);
                record[12..].copy_from_slice(&k.to_le_bytes());
                border_file
                    .write_all(&record)
                    .map_err(|e| io(&border_path)(e))?;
            }
        }
        corner_files[k as usize]
            .write_all(&bytes)
            .map_err(|e| io(&corners_path(k as usize))(e))?;
        cell_faces[k as usize] += 1;
        Ok(())
    })?;
    for (k, mut f) in corner_files.into_iter().enumerate() {
        f.flush().map_err(io(&corners_path(k)))?;
    }
    border_file.flush().map_err(io(&border_path))?;
    drop(border_file);
    if cell_faces.iter().all(|&c| c == 0) {
        return Err(empty());
    }
    // The border: each position used from outside its own cell, with the first such cell and
    // whether a second cell (another outside one, or its own) uses it.
    let mut border: FxHashMap<[u32; 3], (u16, bool)> = FxHashMap::default();
    records(&border_path, BORDER, &mut |r| {
        let key = [0, 4, 8].map(|i| word(r, i));
        let k = u16::from_le_bytes([r[12], r[13]]);
        let entry = border.entry(key).or_insert((k, false));
        entry.1 |= entry.0 != k;
        Ok(())
    })?;
    std::fs::remove_file(&border_path).map_err(io(&border_path))?;
    // Its own cell uses it too: shared.
    for k in (0..cells).filter(|&k| cell_faces[k] > 0) {
        records(&corners_path(k), TRIANGLE, &mut |r| {
            for j in 0..3 {
                let key = [0, 4, 8].map(|i| word(r, 12 * j + i));
                if let Some(entry) = border.get_mut(&key)
                    && cell(&grid, key.map(f32::from_bits)) as usize == k
                {
                    entry.1 = true;
                }
            }
            Ok(())
        })?;
    }
    let mut shared_keys: Vec<[u32; 3]> = border
        .into_iter()
        .filter_map(|(key, (_, shared))| shared.then_some(key))
        .collect();
    // One order whatever the hash map's: by key.
    shared_keys.sort_unstable();
    let shared_path = work.join("shared.verts");
    let mut shared_file = BufWriter::with_capacity(
        CELL_BUFFER,
        File::create(&shared_path).map_err(io(&shared_path))?,
    );
    let mut shared: FxHashMap<[u32; 3], u32> = FxHashMap::default();
    for (id, key) in shared_keys.iter().enumerate() {
        let id = id as u32;
        shared.insert(*key, id);
        shared_file
            .write_all(&vertex_record(id, *key))
            .map_err(io(&shared_path))?;
    }
    shared_file.flush().map_err(io(&shared_path))?;
    drop(shared_file);
    // Each cell: welded, written as the PLY/OBJ path's chunks.
    let mut next = shared_keys.len() as u64;
    for k in 0..cells {
        let chunk = chunk_paths(work, k);
        let mut faces = BufWriter::with_capacity(
            CELL_BUFFER,
            File::create(&chunk.faces).map_err(io(&chunk.faces))?,
        );
        let mut welder = Welder::default();
        records(&corners_path(k), TRIANGLE, &mut |r| {
            let mut ids = [0u8; 12];
            for j in 0..3 {
                let key = [0, 4, 8].map(|i| word(r, 12 * j + i));
                let id = match shared.get(&key) {
                    Some(&id) => u64::from(id),
                    None => next + u64::from(welder.vertex(key.map(f32::from_bits))),
                };
                let id = u32::try_from(id)
                    .ok()
                    .filter(|&id| id < crate::cell::OWN)
                    .ok_or_else(|| PartitionError::Malformed {
                        path: stl.path.clone(),
                        problem: "more than 2³² vertices".to_string(),
                    })?;
                ids[4 * j..4 * j + 4].copy_from_slice(&id.to_le_bytes());
            }
            faces.write_all(&ids).map_err(io(&chunk.faces))
        })?;
        faces.flush().map_err(io(&chunk.faces))?;
        let mut verts = BufWriter::with_capacity(
            CELL_BUFFER,
            File::create(&chunk.vertices).map_err(io(&chunk.vertices))?,
        );
        let positions = welder.into_positions();
        for (i, p) in positions.iter().enumerate() {
            let key = weld_key(p.to_array());
            verts
                .write_all(&vertex_record((next + i as u64) as u32, key))
                .map_err(io(&chunk.vertices))?;
        }
        verts.flush().map_err(io(&chunk.vertices))?;
        next += positions.len() as u64;
        std::fs::remove_file(corners_path(k)).map_err(io(&corners_path(k)))?;
    }
    Ok(Written {
        vertices: next,
        shared: shared_keys.len() as u64,
        cell_faces,
    })
}

/// A `.verts` record: the id, then the position's bits.
fn vertex_record(id: u32, key: [u32; 3]) -> [u8; VERTEX_RECORD] {
    let mut bytes = [0u8; VERTEX_RECORD];
    bytes[..4].copy_from_slice(&id.to_le_bytes());
    for i in 0..3 {
        bytes[4 + 4 * i..8 + 4 * i].copy_from_slice(&key[i].to_le_bytes());
    }
    bytes
}

/// Each `size`-byte record of the file at `path` to `visit`, streamed.
fn records(
    path: &Path,
    size: usize,
    visit: &mut dyn FnMut(&[u8]) -> Result<(), PartitionError>,
) -> Result<(), PartitionError> {
    let io = |source| PartitionError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut reader = BufReader::with_capacity(1 << 20, File::open(path).map_err(io)?);
    let mut record = vec![0u8; size];
    loop {
        match reader.read_exact(&mut record) {
            Ok(()) => visit(&record)?,
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(()),
            Err(e) => return Err(io(e)),
        }
    }
}

/// The little-endian `u32` at `i`.
fn word(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

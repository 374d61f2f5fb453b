//! Step 1, the streaming partition, and the chunk files of the work folder.
//!
//! Files (all little-endian): `cell-NNNNN.faces` (triangles as three `u32` global vertex ids),
//! `cell-NNNNN.verts` and `shared.verts` (records of a `u32` global id and three `f32`), the
//! cells' outputs `cell-NNNNN.out` ([`crate::cell`]), and `manifest` (text, written last and
//! atomically: the partition is complete when it exists and names the same input).

use crate::grid::{BYTES_PER_FACE, Grid, SAMPLE};
use crate::obj::ObjStream;
use crate::ply::{FaceVisitor, PlyStream};
use crate::stl::StlStream;
use crate::{PartitionError, Target};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A vertex record in a `.verts` chunk: global id, then x, y, z.
pub(crate) const VERTEX_RECORD: usize = 16;
/// Write buffer per cell file.
const CELL_BUFFER: usize = 1 << 16;
/// `refcell` of a vertex no face uses yet / used by faces of two cells.
const UNUSED: u16 = u16::MAX;
const SHARED: u16 = u16::MAX - 1;

/// What the partition wrote: the input it was made from, its counts and the faces per cell.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Manifest {
    /// Length and modification time (ns since the epoch) of the input: a work folder made from
    /// another file is not reused.
    pub input: (u64, u128),
    /// The memory budget the grid was sized for.
    pub budget: u64,
    /// Vertex records of the input.
    pub vertices: u64,
    /// Triangles of the input (after fan triangulation, without faces repeating a vertex).
    pub faces: u64,
    /// Vertices used by faces of more than one cell.
    pub shared: u64,
    /// Triangles of each cell.
    pub cell_faces: Vec<u64>,
}

/// The files of one cell: its input chunks and its output.
#[derive(Debug, Clone, PartialEq)]
pub struct CellChunk {
    /// Triangles over global vertex ids.
    pub faces: PathBuf,
    /// Positions of the vertices used by this cell only.
    pub vertices: PathBuf,
    /// Positions of every vertex used by more than one cell (all cells read it, keeping their
    /// own).
    pub shared: PathBuf,
    /// Where the simplified cell goes.
    pub output: PathBuf,
}

impl Manifest {
    /// The cells that hold faces (the others have nothing to simplify).
    pub fn cells(&self) -> Vec<usize> {
        (0..self.cell_faces.len())
            .filter(|&k| self.cell_faces[k] > 0)
            .collect()
    }

    /// The files of cell `k` in `work`.
    pub fn chunk(&self, work: &Path, k: usize) -> CellChunk {
        chunk_paths(work, k)
    }

    /// The manifest of a complete partition in `work` (for a driver that runs the cells
    /// elsewhere: [`Manifest::chunk`] names each cell's files).
    pub fn load(work: &Path) -> Result<Manifest, PartitionError> {
        let path = work.join("manifest");
        let text = std::fs::read_to_string(&path).map_err(|source| PartitionError::Io {
            path: path.clone(),
            source,
        })?;
        Manifest::from_text(&text).ok_or_else(|| PartitionError::BadChunk {
            path,
            problem: "not a gng3d-partition 1 manifest".to_string(),
        })
    }

    /// The fraction of the input's faces that `target` keeps.
    pub fn face_ratio(&self, target: Target) -> f64 {
        let r = match target {
            Target::Ratio(r) => r,
            Target::Faces(f) => f as f64 / self.faces.max(1) as f64,
            // A closed mesh has about two faces a vertex, as many by ratio.
            Target::Vertices(v) => v as f64 / self.vertices.max(1) as f64,
        };
        r.clamp(0.0, 1.0)
    }

    fn to_text(&self) -> String {
        let cells: Vec<String> = self.cell_faces.iter().map(u64::to_string).collect();
        format!(
            "gng3d-partition 1\ninput {} {}\nbudget {}\nvertices {}\nfaces {}\nshared {}\ncells {}\n",
            self.input.0,
            self.input.1,
            self.budget,
            self.vertices,
            self.faces,
            self.shared,
            cells.join(" ")
        )
    }

    fn from_text(text: &str) -> Option<Manifest> {
        let mut lines = text.lines();
        (lines.next()? == "gng3d-partition 1").then_some(())?;
        let mut field = |name: &str| -> Option<Vec<u128>> {
            let rest = lines.next()?.strip_prefix(name)?;
            rest.split_ascii_whitespace()
                .map(|w| w.parse().ok())
                .collect()
        };
        let input = field("input ")?;
        let one = |v: Option<Vec<u128>>| v.and_then(|v| v.first().map(|&x| x as u64));
        Some(Manifest {
            input: (*input.first()? as u64, *input.get(1)?),
            budget: one(field("budget "))?,
            vertices: one(field("vertices "))?,
            faces: one(field("faces "))?,
            shared: one(field("shared "))?,
            cell_faces: field("cells")?.into_iter().map(|c| c as u64).collect(),
        })
    }
}

/// A streamed input file.
enum Input {
    Ply(PlyStream),
    Obj(ObjStream),
    /// Not indexed: partitioned by [`crate::stl`] (which welds), never read by [`Input::read`].
    Stl(StlStream),
}

impl Input {
    /// The reader of `path`'s format (by extension).
    fn open(path: &Path) -> Result<Input, PartitionError> {
        match mesh::io::Format::from_path(path) {
            Some(mesh::io::Format::Ply) => Ok(Input::Ply(PlyStream::open(path)?)),
            Some(mesh::io::Format::Obj) => Ok(Input::Obj(ObjStream::open(path)?)),
            Some(mesh::io::Format::Stl) => Ok(Input::Stl(StlStream::open(path)?)),
            _ => Err(PartitionError::UnsupportedFormat {
                path: path.to_path_buf(),
            }),
        }
    }

    /// Vertex records (`None` for STL, which has none: its corners are welded).
    fn vertex_count(&self) -> Option<usize> {
        match self {
            Input::Ply(s) => Some(s.vertex_count()),
            Input::Obj(s) => Some(s.vertex_count()),
            Input::Stl(_) => None,
        }
    }

    fn face_count(&self) -> usize {
        match self {
            Input::Ply(s) => s.face_count(),
            Input::Obj(s) => s.face_count(),
            Input::Stl(s) => s.face_count(),
        }
    }

    fn ignored(&self) -> Vec<String> {
        match self {
            Input::Ply(s) => s.ignored(),
            Input::Obj(s) => s.ignored(),
            Input::Stl(_) => Vec::new(),
        }
    }

    fn read(
        &self,
        vertex: &mut dyn FnMut(u32, [f64; 3]) -> Result<(), PartitionError>,
        face: Option<FaceVisitor<'_>>,
    ) -> Result<(), PartitionError> {
        match self {
            Input::Ply(s) => s.read(vertex, face),
            Input::Obj(s) => s.read(vertex, face),
            Input::Stl(_) => unreachable!("STL is partitioned by crate::stl"),
        }
    }
}

/// What [`inspect`] found in an input.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub struct InputInfo {
    /// Vertex records; `None` for STL, which has none (its corners are welded into vertices
    /// during the partition: [`Manifest::vertices`] has their count).
    pub vertices: Option<u64>,
    /// Face records (PLY), `f` lines (OBJ) or triangles (STL), before triangulation.
    pub faces: u64,
    /// What the file holds besides positions and faces, which the partitioned simplification
    /// ignores ("vertex property nx", "1200 vt lines"); empty when nothing.
    pub ignored: Vec<String>,
}

/// The counts of `input` (PLY: its header; OBJ: one pass over its lines) and what it holds
/// that the positions-only partition ignores, for a front end to resolve a target and say what
/// is dropped before the run.
pub fn inspect(input: &Path) -> Result<InputInfo, PartitionError> {
    let stream = Input::open(input)?;
    Ok(InputInfo {
        vertices: stream.vertex_count().map(|n| n as u64),
        faces: stream.face_count() as u64,
        ignored: stream.ignored(),
    })
}

/// A hidden temporary name next to `path`, for a write that ends with a rename.
pub(crate) fn temporary_sibling(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let name = format!(".{}.{}.tmp", name.unwrap_or_default(), std::process::id());
    path.with_file_name(name)
}

/// Length and modification time of `path`.
fn identity(path: &Path) -> Result<(u64, u128), PartitionError> {
    let meta = std::fs::metadata(path).map_err(|source| PartitionError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let modified = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_nanos());
    Ok((meta.len(), modified))
}

/// The manifest of `work` if it was made from `input` with `budget` (a resumed run: its cells'
/// outputs are kept); otherwise the folder's chunk files are removed and [`partition`] runs.
/// Step 1 of [`crate::simplify`], public for a driver that runs the cells elsewhere.
pub fn reuse_or_partition(
    input: &Path,
    work: &Path,
    budget: u64,
) -> Result<Manifest, PartitionError> {
    if let Ok(m) = Manifest::load(work)
        && m.input == identity(input)?
        && m.budget == budget
    {
        return Ok(m);
    }
    partition(input, work, budget)
}

/// Step 1: cut `input` (PLY, OBJ or STL, by extension) into the cells of a grid sized for `budget` bytes a cell, writing
/// the chunk files and the manifest into `work` (created; earlier chunk files removed).
pub fn partition(input: &Path, work: &Path, budget: u64) -> Result<Manifest, PartitionError> {
    let identity = identity(input)?;
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| PartitionError::Io { path, source }
    };
    std::fs::create_dir_all(work).map_err(io(work))?;
    clear(work)?;
    let ply = Input::open(input)?;
    let n = match &ply {
        Input::Stl(stl) => {
            let written = crate::stl::partition(stl, work, budget)?;
            let manifest = Manifest {
                input: identity,
                budget,
                vertices: written.vertices,
                faces: written.cell_faces.iter().sum(),
                shared: written.shared,
                cell_faces: written.cell_faces,
            };
            mesh::io::write_atomic(&work.join("manifest"), manifest.to_text().as_bytes())?;
            return Ok(manifest);
        }
        _ => ply.vertex_count().unwrap_or(0),
    };
    // Pass 1: bounding box and a sample of the positions.
    let stride = n.div_ceil(SAMPLE).max(1);
    let (mut min, mut max) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let mut sample = Vec::with_capacity(n.min(SAMPLE));
    ply.read(
        &mut |v, p| {
            for i in 0..3 {
                min[i] = min[i].min(p[i]);
                max[i] = max[i].max(p[i]);
            }
            if (v as usize).is_multiple_of(stride) {
                sample.push(p);
            }
            Ok(())
        },
        None,
    )?;
    if n == 0 || ply.face_count() == 0 {
        return Err(PartitionError::Empty {
            path: input.to_path_buf(),
        });
    }
    let faces_per_sample = ply.face_count() as f64 / sample.len() as f64;
    let max_faces = (budget / BYTES_PER_FACE) as f64;
    let grid = Grid::sized(min, max, &sample, faces_per_sample, max_faces);
    drop(sample);
    // Pass 2: each vertex's cell; each triangle to the smallest cell of its vertices.
    let cells = grid.len();
    let mut face_files = Vec::with_capacity(cells);
    let chunk_of = |k: usize| chunk_paths(work, k);
    for k in 0..cells {
        let path = chunk_of(k).faces;
        let file = File::create(&path).map_err(io(&path))?;
        face_files.push(BufWriter::with_capacity(CELL_BUFFER, file));
    }
    // Cells, not a `&mut`: the vertex and face callbacks of one pass both reach it.
    let vcell = vec![std::cell::Cell::new(0u16); n];
    let mut refcell = vec![UNUSED; n];
    let mut cell_faces = vec![0u64; cells];
    // Error makers are called only on an error: a path built per face was 20 % of the pass.
    let write_error = |k: usize| io(&chunk_of(k).faces);
    ply.read(
        &mut |v, p| {
            vcell[v as usize].set(grid.cell(p));
            Ok(())
        },
        Some(&mut |poly: &[u32]| {
            for i in 1..poly.len().saturating_sub(1) {
                let t = [poly[0], poly[i], poly[i + 1]];
                if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                    continue;
                }
                let k = t
                    .iter()
                    .map(|&v| vcell[v as usize].get())
                    .min()
                    .unwrap_or(0);
                let mut bytes = [0u8; 12];
                for (j, &v) in t.iter().enumerate() {
                    bytes[4 * j..4 * j + 4].copy_from_slice(&v.to_le_bytes());
                    let r = &mut refcell[v as usize];
                    if *r == UNUSED {
                        *r = k;
                    } else if *r != k {
                        *r = SHARED;
                    }
                }
                face_files[k as usize]
                    .write_all(&bytes)
                    .map_err(|e| write_error(k as usize)(e))?;
                cell_faces[k as usize] += 1;
            }
            Ok(())
        }),
    )?;
    for (k, mut f) in face_files.into_iter().enumerate() {
        f.flush().map_err(write_error(k))?;
    }
    drop(vcell);
    if cell_faces.iter().all(|&c| c == 0) {
        return Err(PartitionError::Empty {
            path: input.to_path_buf(),
        });
    }
    // Pass 3: each used vertex's position to its one cell, or to the shared file.
    let mut vertex_files = Vec::with_capacity(cells + 1);
    for k in 0..=cells {
        let path = if k == cells {
            work.join("shared.verts")
        } else {
            chunk_of(k).vertices
        };
        let file = File::create(&path).map_err(io(&path))?;
        vertex_files.push((path, BufWriter::with_capacity(CELL_BUFFER, file)));
    }
    let mut shared = 0u64;
    ply.read(
        &mut |v, p| {
            let slot = match refcell[v as usize] {
                UNUSED => return Ok(()),
                SHARED => {
                    shared += 1;
                    cells
                }
                k => k as usize,
            };
            let mut bytes = [0u8; VERTEX_RECORD];
            bytes[..4].copy_from_slice(&v.to_le_bytes());
            for i in 0..3 {
                bytes[4 + 4 * i..8 + 4 * i].copy_from_slice(&(p[i] as f32).to_le_bytes());
            }
            let (path, file) = &mut vertex_files[slot];
            file.write_all(&bytes).map_err(|e| io(path)(e))
        },
        None,
    )?;
    for (path, mut f) in vertex_files {
        f.flush().map_err(io(&path))?;
    }
    let manifest = Manifest {
        input: identity,
        budget,
        vertices: n as u64,
        faces: cell_faces.iter().sum(),
        shared,
        cell_faces,
    };
    mesh::io::write_atomic(&work.join("manifest"), manifest.to_text().as_bytes())?;
    Ok(manifest)
}

/// The files of cell `k` in `work` ([`Manifest::chunk`]).
pub(crate) fn chunk_paths(work: &Path, k: usize) -> CellChunk {
    CellChunk {
        faces: work.join(format!("cell-{k:05}.faces")),
        vertices: work.join(format!("cell-{k:05}.verts")),
        shared: work.join("shared.verts"),
        output: work.join(format!("cell-{k:05}.out")),
    }
}

/// Remove the files a partition writes (the manifest first, so a half-cleared folder is never
/// taken for a complete one); other files in `work` are left alone.
fn clear(work: &Path) -> Result<(), PartitionError> {
    let io = |source| PartitionError::Io {
        path: work.to_path_buf(),
        source,
    };
    let manifest = work.join("manifest");
    if manifest.exists() {
        std::fs::remove_file(&manifest).map_err(io)?;
    }
    for entry in std::fs::read_dir(work).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let ours = (name.starts_with("cell-")
            && [".faces", ".verts", ".out", ".corners"]
                .iter()
                .any(|e| name.ends_with(e)))
            || name == "shared.verts"
            || name == "border.corners";
        if ours {
            std::fs::remove_file(&path).map_err(io)?;
        }
    }
    Ok(())
}

/// The whole of a chunk file.
pub(crate) fn read_all(path: &Path) -> Result<Vec<u8>, PartitionError> {
    std::fs::read(path).map_err(|source| PartitionError::Io {
        path: path.to_path_buf(),
        source,
    })
}

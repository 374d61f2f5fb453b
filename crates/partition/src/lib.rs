//! Simplification of one mesh larger than memory (issue 50): a streaming spatial partition into
//! cells, each cell simplified on its own with its border locked, the cells stitched back by
//! global vertex id, and one QEM pass over the stitched mesh down to the exact target.
//!
//! Steps of [`simplify`] (each a public function, so that another driver, a process pool or a
//! Dask worker, can run them apart):
//! 1. **Partition** ([`partition`]): three streaming passes over the input (PLY or OBJ; STL,
//!    which has no shared vertices, is welded per cell: see `stl.rs`). Pass 1 takes the
//!    bounding box and a sample of the positions and sizes a grid so that every cell's faces fit
//!    the memory budget; pass 2 gives each vertex its grid cell and each face the smallest cell
//!    of its vertices, writing the face (global vertex ids) to that cell's chunk and marking the
//!    vertices referenced from two cells as shared; pass 3 writes each vertex's position to the
//!    chunk of the one cell that uses it, or to the shared file. The work folder then holds
//!    chunk files and a [`Manifest`], written last, which marks the partition complete.
//! 2. **Cells** ([`simplify_cell`]): one cell in memory per thread; its shared vertices locked
//!    (so both sides of a border keep them exactly), simplified with `qem::simplify` to twice
//!    its share of the target (plus its locked band), and written atomically to its output
//!    chunk. A cell whose output exists is not redone: a killed run resumes.
//! 3. **Stitch** ([`stitch`]): the cells' outputs joined; a shared vertex, same global id and
//!    same position on every side, becomes one vertex, so a closed input stays closed.
//! 4. **Final pass** ([`finish`]): `qem::simplify` over the stitched mesh (about twice the
//!    target) with nothing locked, down to the exact target, so no grid of border vertices
//!    survives.
//!
//! One run at a time per work folder: [`simplify`] holds a [`WorkLock`] on it (a driver running
//! the steps apart takes one itself); the lock of a killed run is released by the system.
//!
//! For front ends: [`inspect`] reads an input's counts and names what a positions-only run
//! ignores (to resolve a target and warn before the run); [`reuse_or_partition`] is step 1 with
//! the resume check, for a driver that runs the cells elsewhere (`gng3d.distributed`).
//!
//! Memory of the partition: the budget's cell buffers plus 4 bytes per input vertex (its cell
//! and the cell that uses it, `u16` each); the mesh itself is never held.
//!
//! ```
//! use partition::{PartitionParams, simplify};
//! let dir = tempfile::tempdir().unwrap();
//! let input = dir.path().join("sphere.ply");
//! partition::generate::write_displaced_sphere(&input, 20_000, 7).unwrap();
//! let params = PartitionParams {
//!     memory_budget: 1 << 20, // 1 MiB a cell: a few cells
//!     ..PartitionParams::new(qem::Target::Faces(2_000), dir.path().join("work"))
//! };
//! let output = dir.path().join("coarse.ply");
//! let report = simplify(&input, &output, &params).unwrap();
//! assert!(report.cells > 1);
//! let coarse = mesh::io::load(&output).unwrap().mesh;
//! assert!((1_999..=2_000).contains(&coarse.face_count()));
//! ```

mod cell;
mod chunk;
pub mod generate;
mod grid;
mod lock;
mod obj;
mod ply;
mod stitch;
mod stl;

pub use cell::{CellReport, resume_or_simplify_cell, simplify_cell};
pub use chunk::{CellChunk, InputInfo, Manifest, inspect, partition, reuse_or_partition};
pub use lock::WorkLock;
pub use stitch::{finish, stitch};

use qem::Target;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Called after each cell with (cells done, cells in all); from the worker threads.
pub type Progress = Arc<dyn Fn(usize, usize) + Send + Sync>;

/// Parameters of [`simplify`].
#[derive(Clone)]
pub struct PartitionParams {
    /// Size of the output: faces, vertices or a ratio of the input's faces (exact, as
    /// `qem::simplify` reaches it).
    pub target: Target,
    /// Bytes one cell may take while it is simplified: the grid is sized so that a cell holds
    /// at most `budget / 200` faces (QEM needs about 160 bytes a face).
    pub memory_budget: u64,
    /// Threads, i.e. cells simplified at once (0: rayon's default).
    pub threads: usize,
    /// The folder of the chunk files (created; reused by a later run on the same input).
    pub work_dir: PathBuf,
    /// Told the number of cells done after each cell.
    pub progress: Option<Progress>,
}

impl std::fmt::Debug for PartitionParams {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PartitionParams")
            .field("target", &self.target)
            .field("memory_budget", &self.memory_budget)
            .field("threads", &self.threads)
            .field("work_dir", &self.work_dir)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

/// Default memory budget of a cell: 1 GiB (about 5M faces a cell).
const DEFAULT_BUDGET: u64 = 1 << 30;

impl PartitionParams {
    /// `target` with the default budget (1 GiB a cell), rayon's threads and `work_dir`.
    pub fn new(target: Target, work_dir: PathBuf) -> PartitionParams {
        PartitionParams {
            target,
            memory_budget: DEFAULT_BUDGET,
            threads: 0,
            work_dir,
            progress: None,
        }
    }
}

/// What [`simplify`] did.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct PartitionReport {
    /// Vertices and faces (triangles) of the input.
    pub input_vertices: usize,
    /// Triangles of the input (polygons fan-triangulated, faces repeating a vertex dropped).
    pub input_faces: usize,
    /// Cells with faces.
    pub cells: usize,
    /// Cells whose output was found from an earlier run and not redone.
    pub cells_resumed: usize,
    /// Vertices used by more than one cell (locked in the cells).
    pub shared_vertices: usize,
    /// Faces of the stitched mesh before the final pass.
    pub stitched_faces: usize,
    /// Vertices and faces of the output.
    pub vertices: usize,
    /// Faces of the output.
    pub faces: usize,
    /// Seconds of the partition (0 when an earlier run's was reused), the cells, stitch and
    /// final pass (with the writing of the output).
    pub seconds: [f64; 3],
}

/// Errors of this crate; every one names the file it is about.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PartitionError {
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The input is not a file these readers take (PLY header, OBJ line), or a record is
    /// unreadable.
    #[error("{}: {problem}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong, and where.
        problem: String,
    },
    /// The file holds less than its header announces.
    #[error("{}: truncated: {problem}", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// What is missing.
        problem: String,
    },
    /// A face names a vertex that does not exist.
    #[error("{}: face {face} names vertex {index}, but there are {vertices} vertices", path.display())]
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// Face record.
        face: u64,
        /// The index it names.
        index: f64,
        /// Vertex records.
        vertices: u64,
    },
    /// The input has no face.
    #[error("{}: no face", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// A chunk file of the work folder is not what this crate wrote (or from another version).
    #[error("{}: not a chunk file of this run ({problem})", path.display())]
    BadChunk {
        /// The file.
        path: PathBuf,
        /// What does not fit.
        problem: String,
    },
    /// The input's format is not read by the streaming partition (PLY, OBJ and STL).
    #[error("{}: only PLY, OBJ and STL are read by the streaming partition", path.display())]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
    },
    /// QEM refused a cell or the final pass.
    #[error("{}: {source}", path.display())]
    Qem {
        /// The cell's output chunk, or the output mesh for the final pass.
        path: PathBuf,
        /// QEM's error.
        source: qem::QemError,
    },
    /// Writing the output mesh failed.
    #[error(transparent)]
    Mesh(#[from] mesh::error::MeshError),
    /// Another run holds the work folder ([`WorkLock`]).
    #[error(
        "{}: the work folder is in use by another run ({holder}); wait for it to end, or give another work folder",
        path.display()
    )]
    Locked {
        /// The work folder.
        path: PathBuf,
        /// Who holds it ("process 1234"), as its lock file says.
        holder: String,
    },
    /// A parameter is out of range.
    #[error("invalid parameter: {0}")]
    InvalidParameter(&'static str),
}

/// Simplify the mesh in `input` (PLY, OBJ or STL) to `params.target` without ever holding it, writing the
/// result to `output` (any format `mesh::io::save` writes). See the crate's steps.
pub fn simplify(
    input: &Path,
    output: &Path,
    params: &PartitionParams,
) -> Result<PartitionReport, PartitionError> {
    if params.memory_budget < 1 << 16 {
        return Err(PartitionError::InvalidParameter(
            "memory_budget below 64 KiB",
        ));
    }
    if let Target::Ratio(r) = params.target
        && !(r > 0.0 && r <= 1.0)
    {
        return Err(PartitionError::InvalidParameter("ratio outside (0, 1]"));
    }
    mesh::io::check_writable(output)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(params.threads)
        .build()
        .map_err(|_| PartitionError::InvalidParameter("threads: no thread pool"))?;
    // Held to the end: a second run on this folder is refused, not interleaved with this one.
    let _lock = WorkLock::acquire(&params.work_dir)?;
    let start = Instant::now();
    let manifest = chunk::reuse_or_partition(input, &params.work_dir, params.memory_budget)?;
    let partition_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let ratio = manifest.face_ratio(params.target);
    let cells = manifest.cells();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let resumed: Vec<bool> = pool.install(|| {
        cells
            .par_iter()
            .map(|&k| {
                let chunk = manifest.chunk(&params.work_dir, k);
                let skip = resume_or_simplify_cell(&chunk, ratio)?.is_none();
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                if let Some(progress) = &params.progress {
                    progress(n, cells.len());
                }
                Ok(skip)
            })
            .collect::<Result<_, PartitionError>>()
    })?;
    let cells_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let stitched = stitch(&params.work_dir, &manifest, ratio)?;
    let stitched_faces = stitched.face_count();
    let coarse = pool.install(|| finish(stitched, params.target, &manifest, output))?;
    let (vertices, faces) = (coarse.vertex_count(), coarse.face_count());
    mesh::io::save(&mesh::Model::from(coarse), output)?;
    Ok(PartitionReport {
        input_vertices: manifest.vertices as usize,
        input_faces: manifest.faces as usize,
        cells: cells.len(),
        cells_resumed: resumed.iter().filter(|&&r| r).count(),
        shared_vertices: manifest.shared as usize,
        stitched_faces,
        vertices,
        faces,
        seconds: [
            partition_seconds,
            cells_seconds,
            start.elapsed().as_secs_f64(),
        ],
    })
}

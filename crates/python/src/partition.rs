//! The partitioned simplification's steps (`partition`, issue 50) for `gng3d.distributed`,
//! which runs the cells on Dask workers: [`partition_plan`] (the request checked by the job,
//! the target resolved as `gng3d simplify --partition auto` resolves it, the input cut into
//! cells or an earlier cut reused), [`partition_cell`] (one cell, from the work folder's
//! files only, skipped when an earlier run finished it) and [`partition_finish`] (stitch,
//! final pass, write). The same calls in the same order as `partition::simplify`, so the
//! output is the CLI's, byte for byte. The GIL is released in each. [`partition_lock`] holds
//! the work folder for the driver's run, as `partition::simplify` holds it for the CLI's.

use crate::keywords;
use job::{JobError, Partition, PartitionOptions};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::time::Instant;

/// A partition error as the Python exception of its kind (`OSError` for a file, `ValueError`
/// for a malformed input or chunk).
fn error(e: partition::PartitionError) -> PyErr {
    keywords::job_error(JobError::from(e))
}

/// Check the request of ``options`` (``vertices_target``, ``faces_target``, ``ratio``,
/// ``attributes``, ``threads``, ... as for :func:`gng3d.simplify_file`) for a partitioned run,
/// check ``output``, then cut ``input`` (PLY, OBJ or STL) into the cells of ``memory_budget`` bytes
/// in ``work_dir`` (reused when it holds a cut of the same input and budget). Returns a dict:
/// ``cells`` (the cells with faces), ``ratio`` (each cell's share of its faces), ``target``
/// (for :func:`partition_finish`), ``input_vertices``, ``input_faces``, ``shared_vertices``,
/// ``warnings`` (the attributes dropped) and ``seconds``.
#[pyfunction]
#[pyo3(signature = (input, output, work_dir, memory_budget, **options))]
pub fn partition_plan<'py>(
    py: Python<'py>,
    input: PathBuf,
    output: PathBuf,
    work_dir: PathBuf,
    memory_budget: u64,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let mut request = keywords::request(py, "distributed.simplify", options, &keywords::KEYWORDS)?;
    request.partition = Partition::Auto(PartitionOptions {
        memory_budget,
        work_dir: Some(work_dir.clone()),
        keep_work: true,
    });
    request.validate().map_err(keywords::job_error)?;
    job::check_output(&output).map_err(keywords::job_error)?;
    let start = Instant::now();
    let (info, target, manifest) = py
        .detach(|| -> Result<_, JobError> {
            let info = partition::inspect(&input)?;
            let target = job::partition_target(request.target, info.vertices)?;
            let manifest = partition::reuse_or_partition(&input, &work_dir, memory_budget)?;
            Ok((info, target, manifest))
        })
        .map_err(keywords::job_error)?;
    let cells = manifest.cells();
    let warnings: Vec<String> = job::dropped_attributes(&request, &info.ignored)
        .into_iter()
        .collect();
    let plan = serde_json::json!({
        "cells": cells,
        "ratio": manifest.face_ratio(target),
        "target": serde_json::to_string(&target).map_err(|e| PyValueError::new_err(e.to_string()))?,
        "input_vertices": manifest.vertices,
        "input_faces": manifest.faces,
        "shared_vertices": manifest.shared,
        "warnings": warnings,
        "seconds": start.elapsed().as_secs_f64(),
    });
    crate::to_python(py, &plan)
}

/// Simplify cell ``cell`` of the partition in ``work_dir`` to ``ratio`` of its faces (the
/// plan's), unless its output is there from an earlier run. Reads the work folder's files
/// only, so a worker with the folder runs it. Returns a dict: ``cell``, ``resumed``,
/// ``input_faces``, ``locked``, ``faces``, ``seconds``.
#[pyfunction]
pub fn partition_cell<'py>(
    py: Python<'py>,
    work_dir: PathBuf,
    cell: usize,
    ratio: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let start = Instant::now();
    // One thread a cell: a Dask worker runs as many cells at once as it has threads
    // (`threads_per_worker`), and a cell whose QEM set-up spread over rayon's global pool (a
    // thread per core) made two workers on two cores run four threads. The output is the same
    // on any thread count (a run with locked vertices is QEM's sequential engine).
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("no thread: {e}")))?;
    let report = py
        .detach(|| -> Result<_, partition::PartitionError> {
            let chunk = partition::Manifest::load(&work_dir)?.chunk(&work_dir, cell);
            pool.install(|| partition::resume_or_simplify_cell(&chunk, ratio))
        })
        .map_err(error)?;
    let value = serde_json::json!({
        "cell": cell,
        "resumed": report.is_none(),
        "input_faces": report.map(|r| r.input_faces),
        "locked": report.map(|r| r.locked),
        "faces": report.map(|r| r.faces),
        "seconds": start.elapsed().as_secs_f64(),
    });
    crate::to_python(py, &value)
}

/// Stitch the cells of ``work_dir`` (every one finished), simplify the stitched mesh to the
/// plan's ``target`` and write it to ``output`` (format by extension, atomically). Returns a
/// dict: ``vertices``, ``faces``, ``stitched_faces``, ``seconds``.
#[pyfunction]
pub fn partition_finish<'py>(
    py: Python<'py>,
    work_dir: PathBuf,
    output: PathBuf,
    target: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let target: qem::Target = serde_json::from_str(target)
        .map_err(|e| PyValueError::new_err(format!("target: not a plan's target ({e})")))?;
    let start = Instant::now();
    let (stitched_faces, vertices, faces) = py
        .detach(|| -> Result<_, JobError> {
            let manifest = partition::Manifest::load(&work_dir)?;
            let stitched = partition::stitch(&work_dir, &manifest, manifest.face_ratio(target))?;
            let stitched_faces = stitched.face_count();
            let coarse = partition::finish(stitched, target, &manifest, &output)?;
            let counts = (stitched_faces, coarse.vertex_count(), coarse.face_count());
            mesh::io::save(&mesh::Model::from(coarse), &output)?;
            Ok(counts)
        })
        .map_err(keywords::job_error)?;
    let value = serde_json::json!({
        "vertices": vertices,
        "faces": faces,
        "stitched_faces": stitched_faces,
        "seconds": start.elapsed().as_secs_f64(),
    });
    crate::to_python(py, &value)
}

/// The lock of a work folder for one run (``partition::WorkLock``: an operating-system lock,
/// dropped when its process ends, killed or not), from :func:`partition_lock` until
/// :meth:`release` (or until it is collected).
#[pyclass(module = "gng3d")]
pub struct PartitionLock {
    lock: Option<partition::WorkLock>,
}

#[pymethods]
impl PartitionLock {
    /// Release the lock (again: nothing).
    fn release(&mut self) {
        self.lock = None;
    }
}

/// Lock ``work_dir`` (created if missing) for this run: another run on it is refused with
/// ``OSError`` naming the folder and the process holding it.
#[pyfunction]
pub fn partition_lock(py: Python<'_>, work_dir: PathBuf) -> PyResult<PartitionLock> {
    let lock = py
        .detach(|| partition::WorkLock::acquire(&work_dir))
        .map_err(error)?;
    Ok(PartitionLock { lock: Some(lock) })
}

/// The size ``text`` (``"2GB"``, ``"512MiB"``, a number of bytes) in bytes, as the CLI's
/// ``--memory-budget`` reads it.
#[pyfunction]
pub fn parse_size(text: &str) -> PyResult<u64> {
    job::parse_size(text).map_err(keywords::job_error)
}

/// The default work folder of a partitioned run writing ``output``, as the CLI names it.
#[pyfunction]
pub fn partition_work_dir(output: PathBuf) -> PathBuf {
    job::default_work_dir(&output)
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PartitionLock>()?;
    m.add_function(wrap_pyfunction!(partition_lock, m)?)?;
    m.add_function(wrap_pyfunction!(partition_plan, m)?)?;
    m.add_function(wrap_pyfunction!(partition_cell, m)?)?;
    m.add_function(wrap_pyfunction!(partition_finish, m)?)?;
    m.add_function(wrap_pyfunction!(parse_size, m)?)?;
    m.add_function(wrap_pyfunction!(partition_work_dir, m)?)?;
    Ok(())
}

//! The batch engine (`job::batch`, the one `gng3d batch` runs) for `gng3d.batch`: the plan of
//! the files, one file run in this process as its row, and the stats table. `gng3d.batch`
//! only orchestrates (a process pool or a Dask client, the command line); the rows are
//! `job::batch::Row` as dicts, their keys `BATCH_FIELDS`.

use crate::keywords;
use job::batch::{self, Inputs, Item, Plan, PlanError, Row, Shard, Status, Table};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A plan's error as the Python exception of its kind.
fn plan_error(e: PlanError) -> PyErr {
    match e {
        PlanError::Invalid(m) => PyValueError::new_err(m),
        PlanError::Io(m) => PyOSError::new_err(m),
        PlanError::Mesh(m) => crate::convert::mesh_error(m),
    }
}

/// `row` as a dict with its keys in the order of `BATCH_FIELDS`.
fn row_dict<'py>(py: Python<'py>, row: &Row) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(row).map_err(|e| PyValueError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A row dict back as a `Row`.
fn row_from(py: Python<'_>, row: &Bound<'_, PyAny>) -> PyResult<Row> {
    let text: String = py
        .import("json")?
        .call_method1("dumps", (row,))?
        .extract()?;
    serde_json::from_str(&text).map_err(|e| PyValueError::new_err(format!("not a batch row: {e}")))
}

/// The mesh files of a folder (sorted), a manifest (one path a line, relative to it) or one
/// mesh file, as ``gng3d batch`` lists them.
#[pyfunction]
pub fn batch_list_inputs(source: PathBuf) -> PyResult<Vec<PathBuf>> {
    batch::list_inputs(&source).map_err(plan_error)
}

/// The order to start ``files`` in: largest first by bytes on disk, unreadable files last.
#[pyfunction]
pub fn batch_largest_first(files: Vec<PathBuf>) -> Vec<usize> {
    let paths: Vec<&std::path::Path> = files.iter().map(PathBuf::as_path).collect();
    batch::largest_first(&paths)
}

/// The plan of a batch: ``source`` (a folder, manifest or mesh) or ``files`` into ``out_dir``
/// (created), ``suffix`` (e.g. ``".ply"``) the outputs' format, shard ``rank`` of
/// ``world_size``; checked as ``gng3d batch`` checks it (no two files to one output, no
/// result over an input). Returns ``(items, stats_name)``: this shard's ``(input, output)``
/// pairs in the list's order and the stats table's default name.
#[pyfunction]
#[pyo3(signature = (source, files, out_dir, suffix, rank, world_size))]
pub fn batch_plan(
    source: Option<PathBuf>,
    files: Option<Vec<PathBuf>>,
    out_dir: PathBuf,
    suffix: Option<String>,
    rank: usize,
    world_size: usize,
) -> PyResult<(Vec<(PathBuf, PathBuf)>, String)> {
    let shard = Shard::new(rank, world_size).ok_or_else(|| {
        PyValueError::new_err(format!(
            "rank must be in [0, world_size), got rank {rank}, world size {world_size}"
        ))
    })?;
    let format = suffix.as_deref().map(|s| s.trim_start_matches('.'));
    if let Some(f) = format
        && !batch::known_format(f)
    {
        return Err(PyValueError::new_err(format!(
            "suffix must be .obj, .ply, .stl, .gltf or .glb, got {:?}",
            suffix.unwrap_or_default()
        )));
    }
    let files = files.unwrap_or_default();
    let inputs = match &source {
        Some(source) => Inputs::Source(source),
        None => Inputs::Files(&files),
    };
    let plan = Plan::new(inputs, &out_dir, format, shard).map_err(plan_error)?;
    let items = plan
        .items()
        .iter()
        .map(|i| (i.input.clone(), i.output.clone()))
        .collect();
    Ok((items, shard.stats_name()))
}

/// Check the simplification keywords of a batch (as :func:`gng3d.simplify` takes them)
/// before any file is read: a bad option is one ValueError, not an error row per file.
#[pyfunction]
#[pyo3(signature = (**options))]
pub fn batch_check(py: Python<'_>, options: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
    let request = keywords::request(py, "simplify_files", options, &keywords::KEYWORDS)?;
    request.validate().map_err(keywords::job_error)
}

/// Simplify ``input`` into ``output`` in this process (the GIL released) with the keywords of
/// :func:`gng3d.simplify_file`: its row as a dict (never raises for the file's own failure:
/// the row's ``error`` is ``"ExceptionType: message"``). ``skip_existing``: an existing output
/// gives a skipped row (:meth:`BatchTable.add` completes it); ``measure``: the symmetric
/// Hausdorff max and mean of the two files (``samples`` per direction).
#[pyfunction]
#[pyo3(signature = (input, output, skip_existing, measure, samples, **options))]
pub fn batch_run<'py>(
    py: Python<'py>,
    input: PathBuf,
    output: PathBuf,
    skip_existing: bool,
    measure: bool,
    samples: Option<usize>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let request = keywords::request(py, "simplify_file", options, &keywords::KEYWORDS)?;
    let params = metrics::HausdorffParams {
        samples,
        ..Default::default()
    };
    params
        .validate()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let settings = batch::Settings {
        skip_existing,
        measure: measure.then_some(params),
    };
    let item = Item { input, output };
    let describe = |item: &Item, _: &job::Request, e: job::JobError| {
        Python::attach(|py| {
            let e = crate::naming(py, keywords::job_error(e), &item.input);
            let kind = e
                .get_type(py)
                .name()
                .map_or_else(|_| "Exception".to_string(), |n| n.to_string());
            format!("{kind}: {}", e.value(py))
        })
    };
    let row = py.detach(|| batch::run_one(&item, &request, &settings, &describe));
    row_dict(py, &row)
}

/// The error row of ``input`` (into ``output``) with ``method``: for a file whose worker died
/// (memory, a signal) or whose task was lost.
#[pyfunction]
pub fn batch_failed_row<'py>(
    py: Python<'py>,
    input: PathBuf,
    output: PathBuf,
    method: &str,
    error: &str,
) -> PyResult<Bound<'py, PyAny>> {
    row_dict(py, &Row::failed(&Item { input, output }, method, error))
}

/// One line: how many rows (their ``status`` strings) were ok, skipped and failed, and the
/// wall time when given.
#[pyfunction]
#[pyo3(signature = (statuses, seconds=None))]
pub fn batch_summary(statuses: Vec<String>, seconds: Option<f64>) -> String {
    let statuses: Vec<Status> = statuses
        .iter()
        .map(|s| match s.as_str() {
            "ok" => Status::Ok,
            "skipped" => Status::Skipped,
            _ => Status::Error,
        })
        .collect();
    batch::summary(&statuses, seconds)
}

/// A batch's stats table (``gng3d batch``'s): rows appended as files complete, locked against
/// other batches writing it; ``path`` None keeps none.
#[pyclass(module = "gng3d")]
pub struct BatchTable {
    table: Table,
}

#[pymethods]
impl BatchTable {
    #[new]
    #[pyo3(signature = (path=None))]
    fn new(path: Option<PathBuf>) -> PyResult<BatchTable> {
        let table = Table::open(path.as_deref()).map_err(plan_error)?;
        Ok(BatchTable { table })
    }

    /// Record ``row`` and return it as the batch reports it: a skipped file an earlier run
    /// recorded comes back with that run's row; one without gets its counts from its files.
    fn add<'py>(
        &mut self,
        py: Python<'py>,
        row: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let row = row_from(py, row)?;
        let row = py.detach(|| self.table.add(row)).map_err(plan_error)?;
        row_dict(py, &row)
    }
}

/// Adds the batch functions, `BatchTable` and `BATCH_FIELDS` to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(batch_list_inputs, m)?)?;
    m.add_function(wrap_pyfunction!(batch_largest_first, m)?)?;
    m.add_function(wrap_pyfunction!(batch_plan, m)?)?;
    m.add_function(wrap_pyfunction!(batch_check, m)?)?;
    m.add_function(wrap_pyfunction!(batch_run, m)?)?;
    m.add_function(wrap_pyfunction!(batch_failed_row, m)?)?;
    m.add_function(wrap_pyfunction!(batch_summary, m)?)?;
    m.add_class::<BatchTable>()?;
    m.add("BATCH_FIELDS", batch::FIELDS.to_vec())?;
    Ok(())
}

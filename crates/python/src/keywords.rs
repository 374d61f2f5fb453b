//! The keywords of `gng3d.simplify`, `gng3d.simplify_file` and `gng3d.Trainer`, parsed once into
//! the job's request (`job::Request`, which checks them in its one place, as it checks the
//! CLI's flags): one table of names ([`KEYWORDS`], which the stubs are tested against), one
//! parser, one mapping of the job's errors onto Python's exceptions.

use crate::run::{seed_keyword, threads_keyword};
use job::{JobError, Method, Request, Spelling, Target};
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Every keyword a run takes, in the order the stubs list them (`gng3d._gng3d.KEYWORDS`).
pub const KEYWORDS: [&str; 23] = [
    "vertices_target",
    "faces_target",
    "ratio",
    "method",
    "time_limit",
    "seed",
    "weld",
    "attributes",
    "placement",
    "flips",
    "refit",
    "relax",
    "deviation_repair",
    "epochs",
    "signals",
    "oversample",
    "detail_rounds",
    "shape",
    "creases",
    "threshold",
    "lock_border",
    "max_error",
    "threads",
];

/// The keywords that apply to QEM only (refused by [`gng3d.Trainer`], which runs GNG3D).
pub const QEM_ONLY: [&str; 4] = ["faces_target", "threshold", "lock_border", "max_error"];

/// The value of keyword `name` as a `T`, or a TypeError naming it.
fn get<'py, T: pyo3::conversion::FromPyObjectOwned<'py>>(
    options: &Bound<'py, PyDict>,
    name: &str,
) -> PyResult<Option<T>> {
    match options.get_item(name)? {
        Some(v) if !v.is_none() => v.extract::<T>().map(Some).map_err(|_| {
            let kind = v
                .get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default();
            PyTypeError::new_err(format!("{name}: unexpected type {kind}"))
        }),
        _ => Ok(None),
    }
}

/// A keyword naming one of a fixed set (`method="qem"`), parsed by the job.
fn named<T>(
    options: &Bound<'_, PyDict>,
    name: &str,
    parse: impl Fn(&str) -> Result<T, JobError>,
) -> PyResult<Option<T>> {
    get::<String>(options, name)?
        .map(|s| parse(&s).map_err(job_error))
        .transpose()
}

/// The request of a call's keywords (`options`, what `**options` collected): a TypeError for
/// a keyword `function` does not take (`allowed`), the job's checks for the rest.
pub fn request(
    py: Python<'_>,
    function: &str,
    options: Option<&Bound<'_, PyDict>>,
    allowed: &[&str],
) -> PyResult<Request> {
    let empty = PyDict::new(py);
    let options = options.unwrap_or(&empty);
    for key in options.keys() {
        let key: String = key.extract()?;
        if !allowed.contains(&key.as_str()) {
            return Err(PyTypeError::new_err(format!(
                "{function}() got an unexpected keyword argument '{key}'"
            )));
        }
    }
    let target = match (
        get::<usize>(options, "vertices_target")?,
        get::<usize>(options, "faces_target")?,
        get::<f64>(options, "ratio")?,
    ) {
        (Some(n), None, None) => Target::Vertices(n),
        (None, Some(n), None) => Target::Faces(n),
        (None, None, Some(r)) => Target::Ratio(r),
        (None, None, None) if get::<f64>(options, "max_error")?.is_some() => Target::MaxErrorOnly,
        (None, None, None) => {
            return Err(PyValueError::new_err(
                "give a target: vertices_target=N, faces_target=N (QEM) or ratio=R",
            ));
        }
        _ => {
            return Err(PyValueError::new_err(
                "give one target: vertices_target, faces_target or ratio, not several",
            ));
        }
    };
    let mut request = Request::new(target);
    if let Some(m) = named(options, "method", str::parse::<Method>)? {
        request.method = m;
    }
    request.seed = seed_keyword(options.get_item("seed")?.as_ref())?;
    request.threads = threads_keyword(options.get_item("threads")?.as_ref())?;
    request.time_limit = get(options, "time_limit")?;
    if let Some(w) = get::<bool>(options, "weld")? {
        request.weld = w;
    }
    if let Some(a) = named(options, "attributes", str::parse)? {
        request.attributes = a;
    }
    request.gng = job::GngVariant {
        placement: named(options, "placement", job::parse_placement)?,
        flips: get(options, "flips")?,
        refit: get(options, "refit")?,
        relax: get(options, "relax")?,
        deviation_repair: get(options, "deviation_repair")?,
        epochs: get(options, "epochs")?,
        signals: named(options, "signals", job::parse_signals)?,
        oversample: get(options, "oversample")?,
        detail_rounds: get(options, "detail_rounds")?,
        shape: named(options, "shape", job::parse_shape)?,
        creases: get(options, "creases")?,
    };
    request.qem = job::QemOptions {
        threshold: get(options, "threshold")?.unwrap_or(0.0),
        lock_border: get(options, "lock_border")?.unwrap_or(false),
        max_error: get(options, "max_error")?,
        attribute_weights: None,
    };
    request.validate().map_err(job_error)?;
    Ok(request)
}

/// A job error as a Python exception: what the input or the options make impossible is a
/// ValueError (options named by their keywords), a file that cannot be read or written an
/// OSError (FileNotFoundError for a missing one), a run that ended without a mesh a
/// RuntimeError, a cancelled one KeyboardInterrupt.
pub fn job_error(e: JobError) -> PyErr {
    match e {
        JobError::Mesh(m) => crate::convert::mesh_error(m),
        JobError::Gng(g) => crate::run::gng_error(*g),
        e => {
            let message = e.message(Spelling::Keywords);
            match e.kind() {
                job::ErrorKind::Io => PyOSError::new_err(message),
                job::ErrorKind::Failed => PyRuntimeError::new_err(message),
                job::ErrorKind::Cancelled => PyKeyboardInterrupt::new_err(message),
                _ => PyValueError::new_err(message),
            }
        }
    }
}

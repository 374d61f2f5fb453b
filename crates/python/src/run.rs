//! What the calls of the module share around the job (`job::Job`): the range checks of their
//! whole-number keywords, the thread pool of `threads=`, the mapping of GNG3D's errors onto
//! Python's exceptions, the summary of a `Trainer`'s mesh, and the wait that lets Ctrl-C stop
//! the work ([`interruptible`]).

use gng3d_core::{GngError, GngOptions, Trainer};
use mesh::cancel::Cancel;
use pyo3::exceptions::{
    PyKeyboardInterrupt, PyOverflowError, PyRuntimeError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration, Instant};

/// Most threads a call may ask for (`threads=`): the job's bound (`job::MAX_THREADS`).
pub const MAX_THREADS: usize = job::MAX_THREADS;

/// A whole-number keyword `name` of a call in `min..=max`: a ValueError naming it and the bound
/// otherwise (a negative or huge int too, not pyo3's OverflowError without the name), a
/// TypeError naming it for what is not an int (anything with `__index__`, numpy's ints too).
pub fn whole_number(name: &str, value: &Bound<'_, PyAny>, min: u64, max: u64) -> PyResult<u64> {
    let n = match value.extract::<i128>() {
        Ok(n) => n,
        Err(e) if e.is_instance_of::<PyOverflowError>(value.py()) => {
            // Beyond i128: out of any range here.
            return Err(out_of_range(name, &value, value.lt(0)?, min, max));
        }
        Err(_) => {
            return Err(PyTypeError::new_err(format!(
                "{name} must be an int, got {}",
                value.get_type().name()?
            )));
        }
    };
    in_range(name, n, min, max)
}

/// `n`, the value of keyword `name`, when in `min..=max`; a ValueError naming it and the bound
/// it is beyond otherwise, in the library's words for its own parameters
/// (`GngError::Parameter`: "parameter threads = 0 is out of range: must be at least 1").
pub fn in_range(name: &str, n: i128, min: u64, max: u64) -> PyResult<u64> {
    if n < i128::from(min) || n > i128::from(max) {
        return Err(out_of_range(name, &n, n < i128::from(min), min, max));
    }
    // In range of a u64 by the check above.
    Ok(n as u64)
}

/// The ValueError of [`in_range`] for `value`, `below` the range or above it.
fn out_of_range(
    name: &str,
    value: &dyn std::fmt::Display,
    below: bool,
    min: u64,
    max: u64,
) -> PyErr {
    let bound = if below {
        format!("must be at least {min}")
    } else {
        format!("must be at most {max}")
    };
    PyValueError::new_err(format!(
        "parameter {name} = {value} is out of range: {bound}"
    ))
}

/// The `threads=` keyword of every call that takes one (`simplify`, `simplify_file`,
/// `Trainer`; `gng3d.batch` passes it to `simplify`): `None`, or a count in 1 to
/// [`MAX_THREADS`] (a ValueError naming `threads` and the bound otherwise).
pub fn threads_keyword(value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    match value {
        None => Ok(None),
        Some(v) if v.is_none() => Ok(None),
        Some(v) => Ok(Some(
            whole_number("threads", v, 1, MAX_THREADS as u64)? as usize
        )),
    }
}

/// GNG3D's seed when a call gives none: the job's (`job::DEFAULT_SEED`), the default of every
/// front end, so `gng3d.simplify(v, f, ...)` and `gng3d simplify IN OUT ...` give the same mesh
/// without a seed. Exposed as `gng3d.DEFAULT_SEED`.
pub fn default_seed() -> u64 {
    job::DEFAULT_SEED
}

/// The `seed=` keyword of the GNG3D calls: `None` for [`default_seed`], else an int in
/// 0 to 2**64 - 1 (a ValueError naming `seed` otherwise).
pub fn seed_keyword(value: Option<&Bound<'_, PyAny>>) -> PyResult<u64> {
    match value {
        Some(v) if !v.is_none() => whole_number("seed", v, 0, u64::MAX),
        _ => Ok(default_seed()),
    }
}

/// The pool the QEM steps of a run use: `threads` threads (checked by [`threads_keyword`]),
/// or `None` for rayon's global pool (the machine's cores).
pub fn pool(threads: Option<usize>) -> PyResult<Option<rayon::ThreadPool>> {
    let Some(n) = threads else {
        return Ok(None);
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map(Some)
        .map_err(|e| PyRuntimeError::new_err(format!("starting {n} threads failed: {e}")))
}

/// `f` in `pool` when there is one.
pub fn in_pool<T: Send>(pool: Option<&rayon::ThreadPool>, f: impl FnOnce() -> T + Send) -> T {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

/// A library error as a Python exception: what the input or the options make impossible is a
/// ValueError, a run that ended without a mesh a RuntimeError; the message is the library's.
pub fn gng_error(e: GngError) -> PyErr {
    // The library's sentence shows the reason as a Rust `Option` ("stopped (None)"): in words.
    if let GngError::TooFewNodes { nodes, stop } = e {
        return PyRuntimeError::new_err(match stop {
            None => format!(
                "the network has {nodes} nodes, too few for a mesh (3 at least): train it first \
                 (Trainer.step or Trainer.train)"
            ),
            Some(reason) => format!(
                "training stopped ({reason}) with {nodes} nodes, too few for a mesh; give it \
                 more time or signals"
            ),
        });
    }
    match e {
        GngError::TooFewNodes { .. } | GngError::EmptyMesh { .. } | GngError::Decimation(_) => {
            PyRuntimeError::new_err(e.to_string())
        }
        // Only after a Ctrl-C ([`interruptible`] returns the handler's exception first).
        GngError::Cancelled => PyKeyboardInterrupt::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// The outcome of `result`, a mesh of `trainer`'s network (finished, or a preview), as the job
/// assembles a GNG3D run's (`job::Outcome::of_gng`).
pub fn summarize(
    trainer: &Trainer,
    options: &GngOptions,
    method: job::Method,
    started: Instant,
    result: gng3d_core::GngResult,
) -> job::Outcome {
    job::Outcome::of_gng(
        &mesh::Model::default(),
        method,
        trainer,
        options,
        result,
        started.elapsed().as_secs_f64(),
    )
}

/// How often [`interruptible`] runs Python's signal handlers while the work runs.
pub const POLL_INTERRUPT: Duration = Duration::from_millis(50);

/// Runs `work` on another thread, the GIL released, while the calling thread runs Python's
/// signal handlers (`py.check_signals()`) every [`POLL_INTERRUPT`]: the one place where every
/// long call of the module (`simplify` with each method, `simplify_file`, `Trainer.mesh`,
/// `metrics`) waits for its work. When a handler raises (Ctrl-C: KeyboardInterrupt), `cancel`
/// is set, so the work stops at its next check (the libraries' cancel hooks:
/// `Trainer::cancel_token`, `gng3d_core::finish_cancellable`, `qem::QemParams::cancel`,
/// `metrics::evaluate_cancellable`, `metrics::Surface::with_cancel`); its result is dropped and
/// the handler's exception returned. The handlers also run once after the work ends, as
/// Python would run them at its next instruction. `work` must not touch Python objects (it
/// runs without the GIL). A panic in `work` is raised again here.
pub fn interruptible<T: Send>(
    py: Python<'_>,
    cancel: &Cancel,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let mut raised: Option<PyErr> = None;
    let joined = py.detach(|| {
        std::thread::scope(|scope| {
            let (done, ended) = std::sync::mpsc::channel::<()>();
            // `done` is dropped when `work` returns (or unwinds): the wait below ends.
            let worker = scope.spawn(move || {
                let _done = done;
                work()
            });
            while let Err(RecvTimeoutError::Timeout) = ended.recv_timeout(POLL_INTERRUPT) {
                if raised.is_none()
                    && let Err(e) = Python::attach(|py| py.check_signals())
                {
                    raised = Some(e);
                    cancel.cancel();
                }
            }
            worker.join()
        })
    });
    let out = match joined {
        Ok(out) => out,
        Err(panic) => std::panic::resume_unwind(panic),
    };
    if let Some(e) = raised {
        return Err(e);
    }
    py.check_signals()?;
    Ok(out)
}

//! The runs behind `gng3d.simplify` and `gng3d.Trainer`: the options a Python call gives, mapped
//! onto the library's own (`gng3d_core::GngOptions`, `qem::QemParams`), which validate them; the
//! same steps as `gng3d simplify` after loading; and the report its `--json` prints.

use gng3d_core::{GngError, GngOptions, GngTarget, Placement, SignalSource, Trainer};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use mesh::cancel::Cancel;
use pyo3::exceptions::{
    PyKeyboardInterrupt, PyOverflowError, PyRuntimeError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use serde::Serialize;
use serde_json::Value;
use std::ops::ControlFlow;
use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration, Instant};

/// The method a call asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// GNG3D-Q (the library's and the CLI's default GNG3D).
    Gng,
    /// The published GNG3D (`GngOptions::paper`).
    Paper,
    /// Garland–Heckbert QEM.
    Qem,
}

impl Method {
    /// The method named `name`, or a ValueError listing the names.
    pub fn parse(name: &str) -> PyResult<Method> {
        match name {
            "gng" => Ok(Method::Gng),
            "paper" => Ok(Method::Paper),
            "qem" => Ok(Method::Qem),
            _ => Err(PyValueError::new_err(format!(
                "method must be 'gng', 'paper' or 'qem', got {name:?}"
            ))),
        }
    }

    /// The name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Gng => "gng",
            Method::Paper => "paper",
            Method::Qem => "qem",
        }
    }
}

/// The size a call asks for (exactly one of the three keywords).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Size {
    /// `vertices_target=N`.
    Vertices(usize),
    /// `faces_target=N` (QEM only).
    Faces(usize),
    /// `ratio=R`: a share of the input's vertices, for every method.
    Ratio(f64),
}

impl Size {
    /// The one target given, or a ValueError.
    pub fn from_keywords(
        vertices: Option<usize>,
        faces: Option<usize>,
        ratio: Option<f64>,
    ) -> PyResult<Size> {
        match (vertices, faces, ratio) {
            (Some(n), None, None) => Ok(Size::Vertices(n)),
            (None, Some(n), None) => Ok(Size::Faces(n)),
            (None, None, Some(r)) => Ok(Size::Ratio(r)),
            (None, None, None) => Err(PyValueError::new_err(
                "give a target: vertices_target=N, faces_target=N (QEM) or ratio=R",
            )),
            _ => Err(PyValueError::new_err(
                "give one target: vertices_target, faces_target or ratio, not several",
            )),
        }
    }
}

/// The GNG3D keywords of a call (the CLI's `--placement`, `--no-flips`, … flags); `None`: not
/// given, the library's default.
#[derive(Debug, Clone, Default)]
pub struct GngKeywords {
    /// `time_limit` (seconds).
    pub time_limit: Option<f64>,
    /// `placement`: "node", "project" or "quadric".
    pub placement: Option<String>,
    /// `flips`.
    pub flips: Option<bool>,
    /// `refit`.
    pub refit: Option<bool>,
    /// `relax`.
    pub relax: Option<bool>,
    /// `deviation_repair`.
    pub deviation_repair: Option<bool>,
    /// `epochs`.
    pub epochs: Option<f64>,
    /// `signals`: "vertices", "surface" or "curvature".
    pub signals: Option<String>,
    /// `oversample`.
    pub oversample: Option<f64>,
    /// `detail_rounds`.
    pub detail_rounds: Option<usize>,
    /// `threads`: most threads of the run (GNG3D and QEM alike, not refused for QEM).
    pub threads: Option<usize>,
}

impl GngKeywords {
    /// The names of the keywords that were given (they apply to GNG3D only).
    fn given(&self) -> Vec<&'static str> {
        let mut names = Vec::new();
        let mut note = |given: bool, name| {
            if given {
                names.push(name);
            }
        };
        note(self.time_limit.is_some(), "time_limit");
        note(self.placement.is_some(), "placement");
        note(self.flips.is_some(), "flips");
        note(self.refit.is_some(), "refit");
        note(self.relax.is_some(), "relax");
        note(self.deviation_repair.is_some(), "deviation_repair");
        note(self.epochs.is_some(), "epochs");
        note(self.signals.is_some(), "signals");
        note(self.oversample.is_some(), "oversample");
        note(self.detail_rounds.is_some(), "detail_rounds");
        names
    }

    /// `GngOptions` for `size` and `seed`, as `gng3d simplify --method gng` builds them from
    /// its flags (`paper`: `GngOptions::paper`), validated by the library
    /// (`GngOptions::validate`) before the mesh is looked at.
    pub fn options(&self, method: Method, size: Size, seed: u64) -> PyResult<GngOptions> {
        let target = match size {
            Size::Vertices(n) => GngTarget::Vertices(n),
            Size::Ratio(r) => GngTarget::VertexRatio(r),
            Size::Faces(_) => {
                return Err(PyValueError::new_err(format!(
                    "faces_target applies to method 'qem' only; use vertices_target or ratio with method '{}'",
                    method.name()
                )));
            }
        };
        let mut options = match method {
            Method::Paper => GngOptions::paper(target),
            _ => GngOptions::for_target(target),
        };
        options.seed = seed;
        options.time_limit_seconds = self.time_limit;
        if let Some(p) = &self.placement {
            options.reconstruction.placement = match p.as_str() {
                "node" => Placement::Node,
                "project" => Placement::Project,
                "quadric" => Placement::Quadric,
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "placement must be 'node', 'project' or 'quadric', got {p:?}"
                    )));
                }
            };
        }
        if let Some(s) = &self.signals {
            options.signal_source = match s.as_str() {
                "vertices" => SignalSource::Vertices,
                "surface" => SignalSource::Surface,
                "curvature" => SignalSource::Curvature,
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "signals must be 'vertices', 'surface' or 'curvature', got {s:?}"
                    )));
                }
            };
        }
        if let Some(f) = self.flips {
            options.reconstruction.flip_edges = f;
        }
        if let Some(r) = self.refit {
            options.reconstruction.refit = r;
        }
        if let Some(r) = self.relax {
            options.reconstruction.relax = r;
        }
        if let Some(r) = self.deviation_repair {
            options.reconstruction.repair_deviations = r;
        }
        if self.epochs.is_some() {
            options.epochs = self.epochs;
            options.max_signals = None;
        }
        if self.oversample.is_some() {
            options.oversample = self.oversample;
        }
        if self.detail_rounds.is_some() {
            options.detail_rounds = self.detail_rounds;
        }
        options.threads = self.threads;
        options.validate().map_err(gng_error)?;
        Ok(options)
    }

    /// A ValueError when GNG3D keywords were given to QEM (as the CLI refuses its GNG3D flags
    /// with `--method qem`).
    pub fn refuse_for_qem(&self) -> PyResult<()> {
        let given = self.given();
        if given.is_empty() {
            return Ok(());
        }
        Err(PyValueError::new_err(format!(
            "{} apply to method 'gng' and 'paper' only, not 'qem'",
            given.join(", ")
        )))
    }
}

/// Most threads a call may ask for (`threads=`). A fixed bound, not one of the machine's core
/// count, so that a call valid on one machine is valid on every one (the mesh does not depend on
/// the count). Far above any useful count: GNG3D's training splits into at most a few parts and
/// QEM into a few; threads beyond the cores only wait. The bound keeps a typo such as
/// `threads=10000` (a pool of 10,000 threads, 40 s and more for a 0.01 s job) from running.
pub const MAX_THREADS: usize = 256;

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

/// GNG3D's seed when a call gives none: the library's default (`GngOptions::default().seed`),
/// which the CLI's `--seed` default is too, so `gng3d.simplify(v, f, ...)` and
/// `gng3d simplify IN OUT ...` give the same mesh without a seed. Exposed as
/// `gng3d.DEFAULT_SEED`.
pub fn default_seed() -> u64 {
    GngOptions::default().seed
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

/// A finished run: the mesh, the `--json` report and the warnings' sentences.
pub struct Outcome {
    /// The simplified mesh.
    pub mesh: TriMesh,
    /// The input's attributes on the simplified mesh, when the run was given some.
    pub attributes: Option<Attributes>,
    /// The CLI's `--json` fields.
    pub report: Value,
    /// One sentence per warning (what the CLI prints on stderr).
    pub warnings: Vec<String>,
}

/// `report`'s `warnings` with each one's sentence added as `message`.
fn with_messages(report: &mut Value, messages: &[String]) {
    if let Some(Value::Array(list)) = report.get_mut("warnings") {
        for (w, m) in list.iter_mut().zip(messages) {
            if let Value::Object(fields) = w {
                fields.insert("message".into(), Value::String(m.clone()));
            }
        }
    }
}

/// The steps after training on `trainer` and the summary, as the CLI does them; `started` is
/// when the run began (the report's `seconds`). `cancel` stops them (`GngError::Cancelled`).
pub fn finish_gng(
    trainer: &Trainer,
    options: &GngOptions,
    method: Method,
    started: Instant,
    pool: Option<&rayon::ThreadPool>,
    cancel: &Cancel,
) -> Result<Outcome, GngError> {
    let result = in_pool(pool, || {
        gng3d_core::finish_cancellable(trainer, cancel, |_| {})
    })?;
    Ok(summarize(trainer, options, method, started, result))
}

/// The outcome of `result`, a mesh of `trainer`'s network (finished, or a preview).
pub fn summarize(
    trainer: &Trainer,
    options: &GngOptions,
    method: Method,
    started: Instant,
    result: gng3d_core::GngResult,
) -> Outcome {
    let summary = gng3d_core::GngSummary::new(
        method.name(),
        trainer,
        options.oversample_factor(),
        &result,
        started.elapsed().as_secs_f64(),
    );
    let warnings: Vec<String> = result
        .report
        .warnings
        .iter()
        .map(|w| w.to_string())
        .collect();
    let mut report = serde_json::to_value(&summary).unwrap_or(Value::Null);
    with_messages(&mut report, &warnings);
    Outcome {
        mesh: result.mesh,
        attributes: None,
        report,
        warnings,
    }
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

/// A GNG3D run on a prepared input, as `gng3d simplify --method gng` runs it (the same training
/// rounds between progress reports, so the same mesh for the same options and seed).
/// With `attributes`, the output's triangles follow their seams (`Trainer::with_attributes`)
/// and its attributes come from the input's surface (`mesh::transfer::transfer_attributes`),
/// as `gng3d_core::simplify_with_attributes` and the CLI give them.
/// Ctrl-C stops training (through the trainer's cancel token, checked every thousand signals
/// or so) and the steps after it (`gng3d_core::finish_cancellable`) within a fraction of a
/// second, through [`interruptible`]: the handler's KeyboardInterrupt is returned then.
pub fn run_gng(
    py: Python<'_>,
    input: &TriMesh,
    attributes: Option<&Attributes>,
    options: &GngOptions,
    method: Method,
    pool: Option<&rayon::ThreadPool>,
) -> PyResult<Outcome> {
    let params = py.detach(|| options.resolve(input)).map_err(gng_error)?;
    let started = Instant::now();
    let mut trainer = py
        .detach(|| match attributes {
            Some(a) => Trainer::with_attributes(input, a, params),
            None => Trainer::new(input, params),
        })
        .map_err(gng_error)?;
    let budget = trainer.stats().max_signals;
    let every = (budget / 20).clamp(1_000, 2_000_000);
    let training = &mut trainer;
    // The CLI's rounds (the same mesh as `gng3d simplify`).
    interruptible(py, &training.cancel_token(), || {
        training.train(every, |_| ControlFlow::Continue(()));
    })?;
    let cancel = Cancel::default();
    let mut outcome = interruptible(py, &cancel, || {
        finish_gng(&trainer, options, method, started, pool, &cancel)
    })?
    .map_err(gng_error)?;
    outcome.attributes = attributes.map(|a| {
        py.detach(|| {
            in_pool(pool, || {
                mesh::transfer::transfer_attributes(input, a, &outcome.mesh)
            })
        })
    });
    Ok(outcome)
}

/// `gng3d simplify --method qem --json`'s summary (crates/cli/src/cli/simplify/qem.rs), plus the
/// warning the CLI prints when the target was not reached.
#[derive(Debug, Serialize)]
struct QemSummary {
    method: &'static str,
    vertices: usize,
    faces: usize,
    seconds: f64,
    report: qem::QemReport,
    warnings: Vec<QemWarning>,
}

/// A QEM run that stopped short of its target.
#[derive(Debug, Serialize)]
struct QemWarning {
    kind: &'static str,
    message: String,
}

/// The QEM target of `size` on `input`: `ratio` is a share of the input's (referenced)
/// vertices here as for GNG3D, through the library's one mapping (`GngTarget::vertex_count`,
/// which `gng3d simplify --method qem --ratio` uses too).
pub fn qem_target(size: Size, input: &TriMesh) -> PyResult<qem::Target> {
    Ok(match size {
        Size::Vertices(n) => qem::Target::Vertices(n),
        Size::Faces(n) => qem::Target::Faces(n),
        Size::Ratio(r) => qem::Target::Vertices(
            GngTarget::VertexRatio(r)
                .vertex_count(input)
                .map_err(gng_error)?,
        ),
    })
}

/// A QEM run with the library's parameters for `target` and `threshold`, as
/// `gng3d simplify --method qem` runs it: with `attributes`, kept through the contractions
/// (`qem::simplify_with_attributes`, whose seams also shape the geometry). `cancel` stops it
/// (KeyboardInterrupt; run it in [`interruptible`]).
pub fn run_qem(
    input: &TriMesh,
    attributes: Option<&Attributes>,
    target: qem::Target,
    threshold: f64,
    pool: Option<&rayon::ThreadPool>,
    cancel: &Cancel,
) -> PyResult<Outcome> {
    let params = qem::QemParams {
        target,
        pair_threshold: threshold,
        cancel: Some(cancel.clone()),
        ..qem::QemParams::default()
    };
    let (simplified, kept, report) = in_pool(pool, || match attributes {
        Some(a) => qem::simplify_with_attributes(input, a, &params)
            .map(|(mesh, kept, report)| (mesh, Some(kept), report)),
        None => qem::simplify(input, &params).map(|(mesh, report)| (mesh, None, report)),
    })
    .map_err(|e| match e {
        qem::QemError::Cancelled => PyKeyboardInterrupt::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    })?;
    if simplified.face_count() == 0 {
        return Err(PyRuntimeError::new_err(format!(
            "QEM produced an empty mesh ({} vertices, no triangles)",
            simplified.vertex_count()
        )));
    }
    let warnings: Vec<String> = report.shortfall(target).into_iter().collect();
    let summary = QemSummary {
        method: "qem",
        vertices: report.vertices,
        faces: report.faces,
        seconds: report.seconds,
        warnings: warnings
            .iter()
            .map(|m| QemWarning {
                kind: "target_not_reached",
                message: m.clone(),
            })
            .collect(),
        report,
    };
    Ok(Outcome {
        mesh: simplified,
        attributes: kept,
        report: serde_json::to_value(&summary).unwrap_or(Value::Null),
        warnings,
    })
}

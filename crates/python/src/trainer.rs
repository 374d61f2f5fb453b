//! `gng3d.Trainer`: GNG3D step by step, for notebooks that draw the network and the paper's
//! error curves while it learns.

use crate::convert;
use crate::keywords;
use crate::run;
use crate::{SimplifyResult, prepared};
use gng3d_core::GngOptions;
use job::Method;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::sync::{Mutex, MutexGuard};
use std::time::Instant;

/// The trainer and what its summary needs.
struct State {
    trainer: gng3d_core::Trainer,
    options: GngOptions,
    method: Method,
    started: Instant,
    /// `threads=`: the pool of the QEM steps after training.
    pool: Option<rayon::ThreadPool>,
}

/// GNG3D step by step: train in chunks, look at the network, rebuild the mesh at any time.
///
/// Takes the arguments of :func:`gng3d.simplify` for ``method="gng"`` or ``"paper"``. The
/// clock of ``time_limit`` starts when the trainer is made.
///
/// Example (a live plot of the paper's error curves):
///     >>> t = gng3d.Trainer(v, f, vertices_target=2000, method="paper")   # doctest: +SKIP
///     >>> while not t.finished:                                            # doctest: +SKIP
///     ...     p = t.step(20_000)
///     ...     e = t.errors()
///     ...     print(p["signals"], p["nodes"], e["e_avg"], e["e_max"])
///     >>> result = t.mesh()                                                # doctest: +SKIP
///
/// Every method releases the GIL while it works; one call at a time runs on a trainer: a
/// second thread's call waits for the first (so one thread may train while another reads
/// :attr:`progress`, :meth:`snapshot` or :meth:`errors` for a plot; a :meth:`step` lets
/// readers in between its chunks of a few tens of milliseconds).
///
/// Ctrl-C stops :meth:`step`, :meth:`train` and :meth:`mesh` within a fraction of a second
/// with KeyboardInterrupt; the network keeps what it learnt, training can go on and
/// :meth:`mesh` can be called again.
#[pyclass(module = "gng3d", frozen)]
pub struct Trainer {
    state: Mutex<State>,
    /// Stops training from any thread, also while a call holds the state.
    cancel: gng3d_core::CancelToken,
    /// Where float64 input far from its coordinates' origin was recentred from (zero for most).
    origin: glam::DVec3,
}

/// Signals of the first chunk of a [`Trainer::step`] call; later chunks are sized from the
/// measured rate to last about [`CHUNK_SECONDS`].
const FIRST_CHUNK: u64 = 16_384;
/// Smallest and largest chunk of a step call.
const CHUNK_RANGE: (u64, u64) = (1_024, 1 << 26);
/// Aimed-at duration of one chunk: the longest wait for Ctrl-C or for another thread's read.
const CHUNK_SECONDS: f64 = 0.05;

impl Trainer {
    /// Runs `f` on the state without the GIL, waiting for another thread's call to end. The
    /// GIL is released before the lock is taken and `f` runs without it, so a thread that
    /// holds the lock never waits for the GIL (no deadlock with one that holds the GIL and
    /// waits for the lock): `f` must not touch Python objects (it is `Send` and gets no
    /// `Python` token; what it returns is turned into Python objects after the lock is
    /// released).
    fn with<T: Send>(&self, py: Python<'_>, f: impl FnOnce(&mut State) -> T + Send) -> T {
        py.detach(|| f(&mut self.lock()))
    }

    /// The state, once another thread's call has ended; only without the GIL (see
    /// [`Trainer::with`]).
    fn lock(&self) -> MutexGuard<'_, State> {
        match self.state.lock() {
            Ok(s) => s,
            Err(poisoned) => poisoned.into_inner(),
        }
    }

    /// Up to `n` more signals (fewer when training ends) in chunks of about
    /// [`CHUNK_SECONDS`], the lock released and Python's signal handlers run between chunks:
    /// Ctrl-C raises KeyboardInterrupt (the handler's exception) within a chunk, and other
    /// threads' calls get in. The network after S signals is the same whatever the chunks
    /// (`gng3d_core::Trainer::step`).
    fn step_in_chunks(&self, py: Python<'_>, n: u64) -> PyResult<()> {
        let mut left = n;
        let mut chunk = FIRST_CHUNK;
        while left > 0 {
            let this = chunk.min(left);
            let started = Instant::now();
            let (done, finished) = self.with(py, |s| {
                let done = s.trainer.step(this);
                (done, s.trainer.is_finished())
            });
            left -= done.min(left);
            if finished || done == 0 {
                break;
            }
            py.check_signals()?;
            let seconds = started.elapsed().as_secs_f64();
            if done == this && seconds > 0.0 {
                let rate = done as f64 / seconds;
                let next = (rate * CHUNK_SECONDS) as u64;
                // At most doubling: a chunk's rate says little about a network that grows.
                chunk = next
                    .min(chunk.saturating_mul(2))
                    .clamp(CHUNK_RANGE.0, CHUNK_RANGE.1);
            }
        }
        Ok(())
    }
}

/// What the progress dict shows, read under the lock (no Python objects there).
struct ProgressView {
    progress: gng3d_core::Progress,
    stats: gng3d_core::TrainingStats,
    target: usize,
    finished: bool,
}

impl ProgressView {
    fn of(t: &gng3d_core::Trainer) -> ProgressView {
        ProgressView {
            progress: t.progress(),
            stats: t.stats(),
            target: t.node_target(),
            finished: t.is_finished(),
        }
    }

    /// The progress dict.
    fn dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (p, stats) = (&self.progress, &self.stats);
        let d = PyDict::new(py);
        d.set_item("signals", p.signals)?;
        d.set_item("nodes", p.nodes)?;
        d.set_item("edges", p.edges)?;
        d.set_item("seconds", p.elapsed.as_secs_f64())?;
        d.set_item("budget", stats.max_signals)?;
        d.set_item("target", self.target)?;
        d.set_item("finished", self.finished)?;
        d.set_item("stop", stats.stop.map(|s| format!("{s:?}")))?;
        Ok(d)
    }
}

#[pymethods]
impl Trainer {
    #[new]
    #[pyo3(signature = (vertices, faces, **options))]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Trainer> {
        // The run's keywords less QEM's, parsed and checked by the one parser; GNG3D unless
        // `method` says otherwise.
        let allowed: Vec<&str> = keywords::KEYWORDS
            .into_iter()
            .filter(|k| !keywords::QEM_ONLY.contains(k) && *k != "attributes")
            .collect();
        let with_gng = PyDict::new(py);
        with_gng.set_item("method", "gng")?;
        if let Some(o) = options {
            with_gng.update(o.as_mapping())?;
        }
        let request = keywords::request(py, "Trainer", Some(&with_gng), &allowed)?;
        let method = request.method;
        if !method.is_gng() {
            return Err(PyValueError::new_err(
                "Trainer runs GNG3D: method must be 'gng' or 'paper' (use gng3d.simplify for 'qem')",
            ));
        }
        let options = request.gng_options().map_err(keywords::job_error)?;
        let weld = request.weld;
        let pool = run::pool(request.threads)?;
        let (input, origin) = prepared(py, vertices, faces, weld)?;
        let started = Instant::now();
        let trainer = py
            .detach(|| {
                let params = options.resolve(&input)?;
                gng3d_core::Trainer::new(&input.into(), params)
            })
            .map_err(run::gng_error)?;
        Ok(Trainer {
            origin,
            cancel: trainer.cancel_token(),
            state: Mutex::new(State {
                trainer,
                options,
                method,
                started,
                pool,
            }),
        })
    }

    /// Train ``signals`` more signals, an int >= 0 (fewer when the budget or the time limit
    /// ends training first); returns :attr:`progress`. Ctrl-C stops it within a fraction of
    /// a second with KeyboardInterrupt (the network keeps the signals trained so far).
    #[pyo3(signature = (signals=10_000))]
    fn step<'py>(&self, py: Python<'py>, signals: i128) -> PyResult<Bound<'py, PyDict>> {
        let n = run::in_range("signals", signals, 0, u64::MAX)?;
        self.step_in_chunks(py, n)?;
        self.progress(py)
    }

    /// Train to the end. With ``callback``, call it with :attr:`progress` every ``every``
    /// signals (an int >= 1; default: 5 % of the budget); a callback that returns ``False``
    /// stops training there (the network keeps what it learnt; :meth:`mesh` rebuilds from
    /// it). Ctrl-C stops it too, within a fraction of a second, raising KeyboardInterrupt.
    #[pyo3(signature = (callback=None, every=None))]
    fn train<'py>(
        &self,
        py: Python<'py>,
        callback: Option<Bound<'py, PyAny>>,
        every: Option<i128>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let every = match every {
            Some(e) => run::in_range("every", e, 1, u64::MAX)?,
            None => {
                let budget = self.with(py, |s| s.trainer.stats().max_signals);
                (budget / 20).clamp(1_000, 2_000_000)
            }
        };
        loop {
            self.step_in_chunks(py, every)?;
            let view = self.with(py, |s| ProgressView::of(&s.trainer));
            let finished = view.finished;
            if let Some(cb) = &callback {
                let answer = cb.call1((view.dict(py)?,))?;
                if let Ok(false) = answer.extract::<bool>() {
                    break;
                }
            }
            if finished {
                break;
            }
        }
        self.progress(py)
    }

    /// dict: ``signals``, ``nodes``, ``edges``, ``seconds`` (training time), ``budget``
    /// (signals the run may use), ``target`` (nodes the network aims for), ``finished``,
    /// ``stop`` (why training ended, or None).
    #[getter]
    fn progress<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.with(py, |s| ProgressView::of(&s.trainer)).dict(py)
    }

    /// Whether training has ended (budget, time limit or a stop).
    #[getter]
    fn finished(&self, py: Python<'_>) -> bool {
        self.with(py, |s| s.trainer.is_finished())
    }

    /// The network now: ``(positions, edges)``, float64 (k, 3) and int64 (e, 2).
    fn snapshot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let snap = self.with(py, |s| s.trainer.snapshot());
        PyTuple::new(
            py,
            [
                convert::positions_array(py, &snap.positions, self.origin).into_any(),
                convert::index_array(py, &snap.edges).into_any(),
            ],
        )
    }

    /// The paper's errors of the network now against the original vertices (squared
    /// distances): dict with ``e_avg`` and ``e_max``.
    fn errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let errors = self
            .with(py, |s| {
                let snap = s.trainer.snapshot();
                metrics::vertex_errors(&s.trainer.original().positions, &snap.positions)
            })
            .ok_or_else(|| PyRuntimeError::new_err("the network has no nodes yet"))?;
        let d = PyDict::new(py);
        d.set_item("e_avg", errors.e_avg)?;
        d.set_item("e_max", errors.e_max)?;
        Ok(d)
    }

    /// Stop training (from another thread, or before :meth:`mesh` to take the network as it
    /// is).
    fn stop(&self) {
        self.cancel.cancel();
    }

    /// The mesh of the network: once training has ended, what :func:`gng3d.simplify` gives
    /// (same report, same warnings); before, a preview (the run's steps without the detail
    /// rounds, no warnings). Ctrl-C stops it within a fraction of a second with
    /// KeyboardInterrupt (the trainer is unchanged).
    fn mesh(&self, py: Python<'_>) -> PyResult<SimplifyResult> {
        let cancel = gng3d_core::Cancel::default();
        // The lock is taken on the worker thread, without the GIL (as `with` takes it).
        let outcome = run::interruptible(py, &cancel, || {
            let s = self.lock();
            let trainer = &s.trainer;
            let result = run::in_pool(s.pool.as_ref(), || {
                if trainer.is_finished() {
                    gng3d_core::finish_cancellable(trainer, &cancel, |_| {})
                } else {
                    trainer.preview()
                }
            })?;
            Ok(run::summarize(
                &s.trainer, &s.options, s.method, s.started, result,
            ))
        })?
        .map_err(run::gng_error)?;
        SimplifyResult::new(py, &outcome, self.origin)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        self.with(py, |s| {
            let p = s.trainer.progress();
            format!(
                "Trainer(method={:?}, nodes={}/{}, signals={}/{}, finished={})",
                s.method.name(),
                p.nodes,
                s.trainer.node_target(),
                p.signals,
                s.trainer.stats().max_signals,
                s.trainer.is_finished()
            )
        })
    }
}

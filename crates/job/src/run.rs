//! [`Job`]: one run on a model, the same for every front end — GNG3D (train, the steps after
//! training, the attributes from the original's surface) or QEM (contractions that carry the
//! attributes) — giving an [`Outcome`].

use crate::summary::{QemSummary, Summary, Warning};
use crate::{GngRun, JobError, Method, Request, Target};
use gng3d_core::{GngOptions, PlannedStep, Progress, StepRecord, Trainer};
use mesh::Model;
use mesh::cancel::Cancel;

/// What a front end sees of a run while it goes (progress bars, a viewer's status line). Every
/// method has a default that does nothing; `()` observes nothing.
pub trait Observer: Send {
    /// GNG3D's training moved on (every [`gng3d_core::training_round`] signals): `budget` is the most
    /// signals it presents.
    fn training(&mut self, _progress: &Progress, _budget: u64) {}
    /// GNG3D's training ended; these steps come next.
    fn planned(&mut self, _steps: &[PlannedStep]) {}
    /// One of those steps finished.
    fn step(&mut self, _record: &StepRecord) {}
    /// QEM started contracting.
    fn contracting(&mut self) {}
    /// The partitioned run finished `done` of its `total` cells.
    fn cells(&mut self, _done: usize, _total: usize) {}
}

impl Observer for () {}

/// A finished run.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The simplified model: its mesh, its attributes (carried when the request keeps them),
    /// the input's materials and origin.
    pub model: Model,
    /// What the run did (the `--json` summary).
    pub summary: Summary,
    /// Why the output differs from the request, one sentence each (also in the summary).
    pub warnings: Vec<String>,
    /// Why GNG3D's training ended (`None` for QEM).
    pub training_stop: Option<gng3d_core::StopReason>,
}

impl Outcome {
    /// The outcome of a GNG3D run: `result`, the mesh [`gng3d_core::finish`] made of
    /// `trainer`'s network (resolved from `options`), in `base`'s place (its materials and
    /// origin), with `method`'s summary and `seconds` as the front end measured them. The one
    /// assembly of the job and of front ends that drive a trainer themselves (Python's
    /// `Trainer.mesh`).
    pub fn of_gng(
        base: &Model,
        method: Method,
        trainer: &Trainer,
        options: &GngOptions,
        result: gng3d_core::GngResult,
        seconds: f64,
    ) -> Outcome {
        let summary = gng3d_core::GngSummary::new(
            method.name(),
            trainer,
            options.oversample_factor(),
            &result,
            seconds,
        );
        let warnings = result
            .report
            .warnings
            .iter()
            .map(|w| w.to_string())
            .collect();
        Outcome {
            model: base.with_mesh(result.mesh, result.attributes),
            summary: Summary::Gng(Box::new(summary)),
            warnings,
            training_stop: trainer.stats().stop,
        }
    }

    /// One line for people: the method, the counts before and after, the work and the time,
    /// the output's topology — the same line for every method and front end.
    pub fn line(&self) -> String {
        let topology = mesh::topology::analyze(&self.model.mesh);
        let (iv, ifaces) = self.summary.input_counts();
        let (v, f) = self.summary.counts();
        let work = match &self.summary {
            Summary::Gng(s) => format!(
                "{} signals ({})",
                s.iterations,
                self.training_stop
                    .unwrap_or(gng3d_core::StopReason::Completed)
            ),
            Summary::Qem(s) => format!("{} collapses", s.report.collapses),
            Summary::Partition(s) => format!(
                "{} cells ({} resumed), {} stitched faces",
                s.cells, s.cells_resumed, s.stitched_faces
            ),
        };
        format!(
            "{}: {iv} -> {v} vertices, {ifaces} -> {f} faces, {work} in {:.3} s; closed: {}, manifold: {}, genus: {}",
            self.summary.method(),
            self.summary.seconds(),
            topology.closed,
            topology.manifold,
            topology.genus.map_or("undefined".into(), |g| g.to_string()),
        )
    }
}

/// What a run does, once prepared.
enum Prepared {
    /// GNG3D: the run made for the input.
    Gng(Box<GngRun>),
    /// QEM: its parameters and target.
    Qem {
        params: Box<qem::QemParams>,
        target: qem::Target,
    },
}

/// A run prepared on one model: the request validated, GNG3D's options resolved against the
/// mesh and its trainer built ([`GngRun`]), or QEM's target set. [`Job::cancel`] gives the flag
/// that stops it from another thread; [`Job::run`] runs it.
pub struct Job<'a> {
    input: &'a Model,
    request: &'a Request,
    prepared: Prepared,
    cancel: Cancel,
    pool: Option<rayon::ThreadPool>,
}

impl<'a> Job<'a> {
    /// Prepare `request` on `input` (a model as [`crate::load`] gives it; its attributes are
    /// carried when there are some).
    pub fn new(input: &'a Model, request: &'a Request) -> Result<Job<'a>, JobError> {
        request.validate()?;
        let pool = match request.threads {
            Some(n) => Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| JobError::Threads {
                        threads: n,
                        message: e.to_string(),
                    })?,
            ),
            None => None,
        };
        if request.method == Method::Qem {
            let target = request.qem_target(&input.mesh)?;
            let cancel = Cancel::default();
            let params = qem::QemParams {
                cancel: Some(cancel.clone()),
                ..request.qem_params(target)
            };
            return Ok(Job {
                input,
                request,
                prepared: Prepared::Qem {
                    params: Box::new(params),
                    target,
                },
                cancel,
                pool,
            });
        }
        let run = GngRun::new(input, request)?;
        let cancel = run.trainer().cancel_token();
        Ok(Job {
            input,
            request,
            prepared: Prepared::Gng(Box::new(run)),
            cancel,
            pool,
        })
    }

    /// The flag that stops the run at its next check ([`JobError::Cancelled`], never a partial
    /// model).
    pub fn cancel(&self) -> Cancel {
        self.cancel.clone()
    }

    /// Run it.
    pub fn run(self, observer: &mut dyn Observer) -> Result<Outcome, JobError> {
        let pool = self.pool.as_ref();
        match self.prepared {
            Prepared::Gng(mut run) => {
                run.train(observer);
                if self.cancel.is_cancelled() {
                    return Err(JobError::Cancelled);
                }
                observer.planned(run.trainer().plan().steps());
                in_pool(pool, || {
                    run.finish(Some(&self.cancel), |r| observer.step(r))
                })
            }
            Prepared::Qem { params, target } => {
                observer.contracting();
                let (model, report) = in_pool(pool, || qem::simplify(self.input, &params))?;
                if model.mesh.face_count() == 0 {
                    return Err(JobError::EmptyOutput {
                        method: "QEM",
                        vertices: model.mesh.vertex_count(),
                    });
                }
                // With a bound on the error alone there is no size to fall short of.
                let warnings: Vec<String> = report
                    .shortfall(target)
                    .filter(|_| self.request.target != Target::MaxErrorOnly)
                    .into_iter()
                    .collect();
                let summary = QemSummary {
                    method: "qem",
                    vertices: report.vertices,
                    faces: report.faces,
                    seconds: report.seconds,
                    warnings: warnings
                        .iter()
                        .map(|m| Warning {
                            kind: "target_not_reached",
                            message: m.clone(),
                        })
                        .collect(),
                    report,
                };
                Ok(Outcome {
                    model,
                    summary: Summary::Qem(Box::new(summary)),
                    warnings,
                    training_stop: None,
                })
            }
        }
    }
}

/// Run `request` on `input`: [`Job::new`] then [`Job::run`].
pub fn run(
    input: &Model,
    request: &Request,
    observer: &mut dyn Observer,
) -> Result<Outcome, JobError> {
    Job::new(input, request)?.run(observer)
}

/// `f` in `pool` when there is one.
fn in_pool<T: Send>(pool: Option<&rayon::ThreadPool>, f: impl FnOnce() -> T + Send) -> T {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

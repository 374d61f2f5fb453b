//! The run around the training: the original and what is known of it (its pieces, the
//! tables built beside the training, its seam charts), the plan after training, the clock and
//! the warnings of the set-up. It starts the run ([`Run::start`]) and, once training hands its
//! network over ([`Trained`]), runs the plan and assembles the result ([`Run::finish`]).
//!
//! The folder also holds the tables' helper thread ([`tables`]).

mod tables;

use crate::GngResult;
use crate::clock::Clock;
use crate::domain::{Domain, Pieces};
use crate::error::GngError;
use crate::params::{GngParams, ReconstructionParams};
use crate::pipeline::{Plan, Step, StepRecord};
use crate::report::{GngReport, GngWarning};
use crate::train::{CancelToken, Snapshot, TrainingStats};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::sync::Arc;
use std::time::{Duration, Instant};
use tables::BackgroundTables;

/// The run of a [`crate::Trainer`] apart from its networks.
#[derive(Debug, Clone)]
pub(crate) struct Run {
    original: Arc<TriMesh>,
    /// Distinct points and components of `original`, shared with phase 2.
    pieces: Pieces,
    /// Phase 2's tables of `original`, built on a helper thread while training runs.
    tables: Arc<BackgroundTables>,
    /// Each original triangle's side of the seams when the input's attributes have seams
    /// ([`crate::Trainer::new`] with attributes, `seams::split_inner_chains`).
    charts: Option<Arc<Vec<u32>>>,
    /// The input's creases, when it has some (`charts` then follow them too).
    creases: Option<Arc<crate::finish::creases::Creases>>,
    /// Whether the input's attributes have seams (`charts` follow them).
    attribute_seams: bool,
    /// The input's attributes, whose values the output takes at its corners
    /// ([`crate::GngResult::attributes`]).
    attributes: Option<Arc<Attributes>>,
    /// The steps after training ([`Plan::of`] the parameters, less what the time limit left
    /// out).
    plan: Plan,
    /// The plan these parameters have without a time limit.
    full_plan: Plan,
    /// Runs of each optional step the time limit left out of the plan.
    cut_runs: Vec<(Step, usize)>,
    /// What the time limit left out of the run before it started.
    plan_warnings: Vec<GngWarning>,
    /// Warnings of the domain set-up (dropped components, stray vertices, capacity).
    domain_warnings: Vec<GngWarning>,
    /// When the run began and when training stops.
    clock: Clock,
    /// Threads the steps after training may use ([`crate::parallel::threads`] of
    /// [`GngParams::threads`]).
    threads: usize,
}

/// What the training hands over to the run's end: its network and counters, and the warnings
/// of the whole run so far ([`crate::Trainer::warnings`]).
pub(crate) struct Trained<'a> {
    /// The parameters in use.
    pub params: &'a GngParams,
    /// The network.
    pub snap: &'a Snapshot,
    /// The training's counters.
    pub stats: TrainingStats,
    /// The run's warnings so far.
    pub warnings: Vec<GngWarning>,
}

impl Run {
    /// Validate `params` against `mesh`, share the time limit between the training and the
    /// steps after it, start the tables' helper thread and build the domain the training
    /// trains on. Returns the run, the parameters to train with and the domain (its warnings
    /// taken into the run).
    pub(crate) fn start(
        mesh: &TriMesh,
        attributes: Option<&Attributes>,
        params: GngParams,
    ) -> Result<(Run, GngParams, Domain), GngError> {
        let started = Instant::now();
        params.validate()?;
        for (f, t) in mesh.triangles.iter().enumerate() {
            if t.iter().any(|&v| v as usize >= mesh.positions.len()) {
                return Err(GngError::BadIndex { face: f });
            }
        }
        if let Some(v) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(GngError::NonFinite { vertex: v });
        }
        let creases = params
            .reconstruction
            .creases
            .then(|| crate::finish::creases::detect(mesh))
            .flatten()
            .map(Arc::new);
        let attribute_seams = attributes.is_some_and(|a| !a.seam_edges(mesh).is_empty());
        let charts = seam_charts(mesh, attributes, creases.as_deref()).map(Arc::new);
        // The time limit is shared between the training and the steps after it, once.
        let time_plan =
            crate::pipeline::plan_for_time(params, mesh.positions.len(), charts.is_some());
        let params = time_plan.params;
        // Phase 2's tables start now, on the core that the set-up below leaves idle, rather
        // than during training, whose two halves keep both cores busy.
        let threads = crate::parallel::threads(params.threads);
        let original = Arc::new(mesh.clone());
        let tables = Arc::new(BackgroundTables::start(&original, threads > 1));
        let pieces = Pieces::of(mesh);
        let mut domain = Domain::build(mesh, &pieces, &params)?;
        let run = Run {
            original,
            pieces,
            tables,
            charts,
            creases,
            attribute_seams,
            attributes: attributes.map(|a| Arc::new(a.clone())),
            plan: time_plan.plan,
            full_plan: time_plan.full,
            cut_runs: time_plan.cut_runs,
            plan_warnings: time_plan.warnings,
            domain_warnings: std::mem::take(&mut domain.warnings),
            clock: Clock {
                started,
                training_limit: time_plan.training_limit,
            },
            threads,
        };
        Ok((run, params, domain))
    }

    /// The steps [`crate::finish`] runs after training.
    pub(crate) fn plan(&self) -> &Plan {
        &self.plan
    }

    /// The steps without a time limit.
    pub(crate) fn full_plan(&self) -> &Plan {
        &self.full_plan
    }

    /// The run's clock.
    pub(crate) fn clock(&self) -> &Clock {
        &self.clock
    }

    /// Leave `idle` out of the run's clock.
    pub(crate) fn discount(&mut self, idle: Duration) {
        self.clock.started += idle;
    }

    /// The mesh being simplified.
    pub(crate) fn original(&self) -> &TriMesh {
        &self.original
    }

    /// Threads the steps after training may use.
    pub(crate) fn threads(&self) -> usize {
        self.threads
    }

    /// What the set-up left out or dropped: the time limit's cuts, then the domain's.
    pub(crate) fn warnings(&self) -> Vec<GngWarning> {
        let mut w = self.plan_warnings.clone();
        w.extend(self.domain_warnings.iter().cloned());
        w
    }

    /// A preview of `trained`: the run's plan without its detail rounds, with the checks of
    /// [`Run::finish`]; no warnings.
    pub(crate) fn preview(&self, trained: Trained<'_>) -> Result<GngResult, GngError> {
        let mut reconstruction = trained.params.reconstruction.clone();
        reconstruction.detail_rounds = 0;
        let plan = Plan::with_seams(
            &reconstruction,
            trained.params.decimates(),
            self.charts.is_some(),
        );
        let mut result = self.finish_with(trained, &plan, &reconstruction, None, None, |_| {})?;
        result.report.warnings.clear();
        Ok(result)
    }

    pub(crate) fn pipeline_input<'a>(
        &'a self,
        params: &'a GngParams,
        snap: &'a Snapshot,
        reconstruction: &'a ReconstructionParams,
    ) -> crate::pipeline::Input<'a> {
        crate::pipeline::Input {
            original: &self.original,
            pieces: &self.pieces,
            tables: self.tables.get(),
            nodes: &snap.positions,
            edges: &snap.edges,
            params: reconstruction,
            decimate_to: (params.decimates() || self.charts.is_some())
                .then_some(params.target_vertices),
            charts: self.charts.as_deref().map(Vec::as_slice),
            creases: self.creases.as_deref(),
            attribute_seams: self.attribute_seams,
            threads: self.threads,
        }
    }

    /// [`crate::finish_cancellable`]: `plan` on what training handed over, with the checks and
    /// warnings of a run, stopped with [`GngError::Cancelled`] when `cancel` is set; the
    /// output's attributes from the original's surface when the input has some.
    pub(crate) fn finish(
        &self,
        trained: Trained<'_>,
        plan: &Plan,
        cancel: Option<&CancelToken>,
        on_step: impl FnMut(&StepRecord),
    ) -> Result<GngResult, GngError> {
        let deadline = trained.params.time_limit.map(|limit| {
            self.clock.started + Duration::from_secs_f64(crate::pipeline::aim_seconds(limit))
        });
        let reconstruction = &trained.params.reconstruction;
        let mut result =
            self.finish_with(trained, plan, reconstruction, deadline, cancel, on_step)?;
        result.attributes = self
            .attributes
            .as_deref()
            .map(|a| mesh::transfer::transfer_attributes(&self.original, a, &result.mesh));
        Ok(result)
    }

    /// `plan` with `reconstruction` on what training handed over, then the checks and the
    /// warnings: the run's result.
    fn finish_with(
        &self,
        trained: Trained<'_>,
        plan: &Plan,
        reconstruction: &ReconstructionParams,
        deadline: Option<Instant>,
        cancel: Option<&CancelToken>,
        on_step: impl FnMut(&StepRecord),
    ) -> Result<GngResult, GngError> {
        let Trained {
            params,
            snap,
            stats,
            warnings,
        } = trained;
        if snap.positions.len() < 3 {
            return Err(GngError::TooFewNodes {
                nodes: snap.positions.len(),
                stop: stats.stop,
            });
        }
        let input = self.pipeline_input(params, snap, reconstruction);
        let out =
            crate::pipeline::run(&input, plan, deadline, cancel, on_step).map_err(|e| match e {
                qem::QemError::Cancelled => GngError::Cancelled,
                e => GngError::Decimation(e),
            })?;
        if out.report.vertices == 0 || out.mesh.face_count() == 0 {
            return Err(GngError::EmptyMesh {
                nodes: snap.positions.len(),
            });
        }
        let mut warnings = warnings;
        // Runs of each optional step left out for time: before the run (the plan's cuts) and
        // during it (the driver), out of the runs it has without a time limit.
        for &step in crate::pipeline::CUT_ORDER.iter().filter_map(|c| match c {
            crate::pipeline::Cut::Step(step) => Some(step),
            _ => None,
        }) {
            let before = self
                .cut_runs
                .iter()
                .find(|(s, _)| *s == step)
                .map_or(0, |c| c.1);
            let during = out.skipped.iter().filter(|&&s| s == step).count();
            let planned = self.full_plan.count(step);
            if before + during > 0 && planned > 0 {
                warnings.push(GngWarning::StepSkippedForTime {
                    step,
                    skipped: (before + during).min(planned),
                    planned,
                });
            }
        }
        if let Some(ratio) = out.seams_not_followed {
            warnings.push(GngWarning::SeamsNotFollowed { ratio });
        }
        if out.report.unreferenced_nodes > 0 {
            warnings.push(GngWarning::UnattachedNodes {
                nodes: out.report.unreferenced_nodes,
            });
        }
        let target = params.target_vertices;
        let vertices = out.mesh.vertex_count();
        if params.decimates() || self.charts.is_some() {
            if vertices > target {
                warnings.push(GngWarning::DecimationStopped { vertices, target });
            }
            if vertices == target {
                warnings.retain(|w| {
                    !matches!(
                        w,
                        GngWarning::TargetAboveCapacity { .. }
                            | GngWarning::TimeLimitBeforeTarget { .. }
                            | GngWarning::UnattachedNodes { .. }
                    )
                });
            }
        }
        let topology = &out.report.topology;
        if topology.boundary_edges > 0 && self.input_is_closed() {
            warnings.push(GngWarning::OpenedHoles {
                boundary_edges: topology.boundary_edges,
                boundary_loops: topology.boundary_loops,
            });
        }
        if let Some(changed) = self.topology_changed(topology) {
            warnings.push(changed);
        }
        let report = GngReport {
            training: stats,
            target_vertices: target,
            network_vertices: out.report.vertices,
            vertices,
            faces: out.mesh.face_count(),
            reconstruction: out.report,
            steps: out.steps,
            seconds: self.clock.started.elapsed().as_secs_f64(),
            warnings,
        };
        Ok(GngResult {
            mesh: out.mesh,
            attributes: None,
            nodes: snap.positions.clone(),
            report,
        })
    }

    /// [`GngWarning::TopologyChanged`] when `output` has more components, non-manifold edges
    /// or non-manifold vertices than the input (the input is analysed only when the output has
    /// more than one component or a non-manifold element).
    fn topology_changed(&self, output: &mesh::topology::TopologyReport) -> Option<GngWarning> {
        if output.components <= 1
            && output.non_manifold_edges == 0
            && output.non_manifold_vertices == 0
        {
            return None;
        }
        let input = mesh::topology::analyze(&self.original);
        let worse = output.components > input.components
            || output.non_manifold_edges > input.non_manifold_edges
            || output.non_manifold_vertices > input.non_manifold_vertices;
        worse.then_some(GngWarning::TopologyChanged {
            components: [input.components, output.components],
            non_manifold_edges: [input.non_manifold_edges, output.non_manifold_edges],
            non_manifold_vertices: [input.non_manifold_vertices, output.non_manifold_vertices],
        })
    }

    /// Whether the input has no border edge (then an output with one has a hole the run made).
    fn input_is_closed(&self) -> bool {
        match self.tables.get() {
            Some(t) => (0..t.edges.len()).all(|e| !t.edges.is_boundary(e)),
            None => mesh::topology::analyze(&self.original).boundary_edges == 0,
        }
    }
}

/// Each original triangle's side of the seams the cut follows ([`Step::CutSeams`]): the
/// attribute charts when they have seams (`seams::split_inner_chains`) and the smooth patches between
/// the creases, paired; `None` with neither.
fn seam_charts(
    mesh: &TriMesh,
    attributes: Option<&Attributes>,
    creases: Option<&crate::finish::creases::Creases>,
) -> Option<Vec<u32>> {
    let attribute = attributes
        .map(|a| (a.charts(mesh), a.seam_edges(mesh)))
        .filter(|(_, seams)| !seams.is_empty());
    let (charts, seams) = match (attribute, creases) {
        (None, None) => return None,
        (Some(attribute), None) => attribute,
        (attribute, Some(creases)) => {
            let (charts, mut seams) =
                attribute.unwrap_or_else(|| (vec![0; mesh.triangles.len()], Vec::new()));
            seams.extend_from_slice(creases.edges());
            seams.sort_unstable();
            seams.dedup();
            let mut ids: rustc_hash::FxHashMap<(u32, u32), u32> = Default::default();
            let paired = charts
                .iter()
                .zip(&creases.patches)
                .map(|(&chart, &patch)| {
                    let next = ids.len() as u32;
                    *ids.entry((chart, patch)).or_insert(next)
                })
                .collect();
            (paired, seams)
        }
    };
    Some(crate::finish::seams::split_inner_chains(
        mesh, charts, &seams,
    ))
}

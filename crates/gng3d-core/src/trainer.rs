//! Phase 1: the GNG3D training loop, step-wise ([`Trainer::step`]) or to completion with a
//! progress observer ([`Trainer::train`]), plus snapshots and cancellation for viewers.
//!
//! Steps of one [`Trainer::step`] call: for every piece of the domain ([`crate::domain`]) in
//! turn, present signals in chunks of `CHECK_EVERY` (winner search on the grid, GNG update,
//! insertion every λ, removal of nodes that won nothing in the μ window), then check the
//! budget, the target, the time limit (rescheduling λ from the measured throughput) and the
//! cancel token.
//!
//! (Over ~700 lines on purpose: the per-piece loop (`Part`) and the `Trainer` that schedules it
//! share the loop settings and counters of the hot path; the tests are the last 20 lines.)

use crate::GngResult;
use crate::ReconstructionParams;
use crate::domain::{Domain, Frame, Piece, Pieces};
use crate::error::GngError;
use crate::grid::{Grid, NONE, Nearest2};
use crate::network::Network;
use crate::params::{DEFAULT_SIGNALS_PER_NODE, GngParams, SearchStrategy, SignalSource};
use crate::pipeline::{Plan, StepRecord};
use crate::reconstruct::{OriginalTables, Reconstruction};
use crate::report::{GngReport, GngWarning};
use glam::Vec3;
use mesh::TriMesh;
use mesh::attributes::Attributes;
use mesh::sampling::AreaSampler;
use rand::Rng;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};
use std::ops::ControlFlow;
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Grid resolution: rebuild once the node count has grown by this factor since the last build.
const GRID_REBUILD_GROWTH: usize = 2;
/// Grid resolution: cell side as a multiple of the mean node spacing on the surface,
/// sqrt(area / nodes). Nodes live on a 2-D surface, so the side must follow N^(-1/2) rather
/// than the volume's N^(-1/3) (fewer nodes examined per query at every size).
const GRID_CELL_SPACING: f64 = 1.3;
/// Grid resolution: at least this many cells per node (flat or tiny boxes).
const GRID_MIN_CELLS_PER_NODE: f64 = 1.0;
/// Grid resolution: at most this many cells per node (bounds memory for thin, tall boxes).
const GRID_MAX_CELLS_PER_NODE: f64 = 64.0;
/// Renumber nodes in grid order every this many times |A| signals.
const RENUMBER_EVERY_EPOCHS: u64 = 16;
/// Signals drawn ahead of presenting them (see `Part::run_signals`): ~10 % more signals/s at
/// 10k nodes on armadillo (1.0 → 1.1 M/s, same results).
const SIGNAL_BATCH: usize = 64;
/// Signals between checks of the clock and the cancellation flag; also the canonical chunk
/// of a part past its budget, whose end is where it checks whether it is done (so that a part's
/// result does not depend on how `step` calls divide the signals).
const CHECK_EVERY: u64 = 1024;
/// Signals per part in one round of [`Trainer::step`]: the parts of a round run side by side
/// (one thread each, up to [`crate::parallel::threads`]), and between rounds the time-limit
/// schedule looks at the throughput. ~3 ms of igea's training a part, against ~50 µs to start
/// and join a thread.
const ROUND_SIGNALS_PER_PART: u64 = 8 * CHECK_EVERY;
/// Largest automatic λ.
const MAX_AUTO_LAMBDA: u64 = 200;
/// With a time limit, growth is scheduled to end by this share of it, so the rest refines a
/// network that already has its N nodes (a 2× margin for the throughput falling as it grows).
pub const GROWTH_SHARE_OF_TIME_LIMIT: f64 = 0.5;
/// Signals before the throughput is trusted for the time-limit schedule.
const RATE_WARMUP_SIGNALS: u64 = 4096;

/// Shared flag that stops a running [`Trainer`] from another thread (at its next check, within
/// about a thousand signals): the workspace's one cancel flag, [`mesh::cancel::Cancel`], under
/// the name the trainer has always given it ([`crate::finish_cancellable`], QEM's
/// `QemParams::cancel` and the metrics take the same type).
pub type CancelToken = mesh::cancel::Cancel;

/// Why training ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum StopReason {
    /// The signal budget was used and the node count is at the target.
    #[cfg_attr(feature = "serde", serde(alias = "Completed"))]
    Completed,
    /// The time limit was reached.
    #[cfg_attr(feature = "serde", serde(alias = "TimeLimit"))]
    TimeLimit,
    /// Cancelled through a [`CancelToken`] or an observer.
    #[cfg_attr(feature = "serde", serde(alias = "Cancelled"))]
    Cancelled,
    /// Twice the signal budget was used without reaching the target (should not happen).
    #[cfg_attr(feature = "serde", serde(alias = "SignalCap"))]
    SignalCap,
}

impl std::fmt::Display for StopReason {
    /// In words, lowercase, as the CLI and the viewer print it ("completed", "time limit").
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StopReason::Completed => "completed",
            StopReason::TimeLimit => "time limit",
            StopReason::Cancelled => "cancelled",
            StopReason::SignalCap => "signal cap",
        })
    }
}

/// A copy of the network with compact indices, for drawing.
#[derive(Debug, Clone, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Snapshot {
    /// Node positions, model units.
    pub positions: Vec<Vec3>,
    /// GNG edges as index pairs into `positions` (smaller index first).
    pub edges: Vec<[u32; 2]>,
    /// Signals processed so far.
    pub signals: u64,
    /// Target node count.
    pub target: usize,
    /// Whether training has ended.
    pub finished: bool,
}

/// Training progress reported to [`Trainer::train`] observers.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Progress {
    /// Signals processed so far (the paper's iterations).
    pub signals: u64,
    /// Current node count.
    pub nodes: usize,
    /// Current edge count.
    pub edges: usize,
    /// Training time so far (sum of the time spent inside `step`).
    pub elapsed: Duration,
}

/// Counters of a finished or running training.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct TrainingStats {
    /// Signals processed.
    pub signals: u64,
    /// λ in use (lowered by the time-limit schedule when needed).
    pub lambda: u64,
    /// Signal budget (see [`GngParams::max_signals`] and [`GngParams::epochs`]).
    pub max_signals: u64,
    /// Nodes inserted (Fritzke insertion).
    pub insertions: u64,
    /// Nodes removed by the μ inactivity rule.
    pub removed_inactive: u64,
    /// Nodes removed because they lost their last edge.
    pub removed_isolated: u64,
    /// Connected input components trained, each by its own network (or two, one a half, with
    /// [`GngParams::split_training`]).
    pub components: usize,
    /// Training time, seconds.
    pub seconds: f64,
    /// Training time when the network first held all its nodes, seconds (`None` until then).
    pub growth_seconds: Option<f64>,
    /// Why training ended (`None` while running).
    pub stop: Option<StopReason>,
}

/// Signal generator over one piece of the original mesh (local coordinates).
#[derive(Debug, Clone)]
enum Signals {
    /// Distinct referenced vertex positions.
    Points(Vec<Vec3>),
    /// Area-weighted uniform points on the surface (mesh's alias-table sampler).
    Surface(AreaSampler),
}

impl Signals {
    /// Fill `out` with signals, in the order of the random stream. Vertex signals draw all the
    /// indices first and then gather the points: the gathers are independent loads from a
    /// table larger than the cache (igea: 134k points, 1.6 MB), and in a tight loop of their
    /// own they overlap, where interleaved with the generator each one stalled (perf: 15 % of
    /// training on the load of `p[index]`). Same stream, same signals.
    #[inline(always)]
    fn draw_batch(&self, rng: &mut Pcg64Mcg, out: &mut [Vec3], index: &mut [u32]) {
        match self {
            Signals::Points(p) => {
                for i in index.iter_mut() {
                    *i = rng.random_range(0..p.len()) as u32;
                }
                for (slot, &i) in out.iter_mut().zip(index.iter()) {
                    *slot = p[i as usize];
                }
            }
            Signals::Surface(s) => {
                for slot in out {
                    *slot = s.sample(rng).position;
                }
            }
        }
    }
}

/// Cells for a grid of volume `volume` over `nodes` nodes spread on a surface of area `area`.
fn grid_cells(area: f64, volume: f64, nodes: usize) -> usize {
    let n = nodes.max(1) as f64;
    let side = GRID_CELL_SPACING * (area / n).sqrt();
    let cells = volume / (side * side * side);
    let (lo, hi) = (n * GRID_MIN_CELLS_PER_NODE, n * GRID_MAX_CELLS_PER_NODE);
    let cells = if cells.is_finite() {
        cells.clamp(lo, hi)
    } else {
        hi
    };
    cells as usize
}

/// Settings shared by every part's inner loop.
#[derive(Debug, Clone, Copy)]
struct LoopSettings {
    eps_b: f32,
    eps_n: f32,
    max_age: u32,
    inv_decay: f64,
    alpha: f64,
    removal_window: f64,
    lambda: u64,
}

/// One network trained on one connected piece of the input, in that piece's local frame.
#[derive(Debug, Clone)]
struct Part {
    frame: Frame,
    signals_src: Signals,
    /// Box of the piece's non-stray points (local), for the grid.
    bbox: mesh::Aabb,
    /// Surface area of the piece (local units squared), for the grid resolution.
    area: f64,
    /// Node count at the last grid rebuild.
    grid_built_for: usize,
    net: Network,
    target: usize,
    budget: u64,
    signals: u64,
    next_insert: u64,
    next_renumber: u64,
    window_start: u64,
    insertions: u64,
    removed_inactive: u64,
    /// Budget used and target held.
    done: bool,
    /// Twice the budget used without reaching the target.
    capped: bool,
    /// This part's own random stream (signals and the two seed nodes), so that parts can
    /// train on separate threads with the same result as on one.
    rng: Pcg64Mcg,
    /// Connected component of the input the part trains (the two halves of a split piece
    /// share one).
    component: usize,
}

impl Part {
    fn new(
        piece: Piece,
        source: SignalSource,
        search: SearchStrategy,
        budget: u64,
        lambda: u64,
        mut rng: Pcg64Mcg,
    ) -> Result<Part, GngError> {
        let bbox = mesh::Aabb::from_points(&piece.points);
        let grid = match search {
            SearchStrategy::Grid => Some(Grid::new(bbox.min, bbox.max, 1)),
            SearchStrategy::LinearScan => None,
        };
        let mut net = Network::new(grid, piece.target + 16);
        let pts = &piece.points;
        // A piece asked to keep every vertex (vertex signals, target = point count) is its own
        // best approximation: nodes sit on the points and it needs no training.
        let saturated = source == SignalSource::Vertices && piece.target >= pts.len();
        if saturated {
            for &p in pts {
                net.add_node(p, 0.0, 0);
            }
        } else {
            let a = rng.random_range(0..pts.len());
            let mut b = rng.random_range(0..pts.len() - 1);
            if b >= a {
                b += 1;
            }
            net.add_node(pts[a], 0.0, 0);
            net.add_node(pts[b], 0.0, 0);
        }
        let signals_src = match source {
            // The points move into the sampler (no copy of the input's distinct points).
            SignalSource::Vertices => Signals::Points(piece.points),
            SignalSource::Surface => {
                Signals::Surface(AreaSampler::new(&piece.surface).map_err(|_| GngError::ZeroArea)?)
            }
            // GNG3D-Q: curvature-weighted areas (crate::features), bounded to 1-4x the area.
            SignalSource::Curvature => {
                let weights = crate::features::curvature_face_weights(&piece.surface, piece.target);
                Signals::Surface(
                    AreaSampler::weighted(&piece.surface, |f, _| weights[f])
                        .map_err(|_| GngError::ZeroArea)?,
                )
            }
        };
        Ok(Part {
            frame: piece.frame,
            signals_src,
            bbox,
            area: piece.area,
            grid_built_for: 2,
            net,
            target: piece.target,
            budget,
            signals: 0,
            next_insert: lambda,
            next_renumber: 0,
            window_start: 0,
            insertions: 0,
            removed_inactive: 0,
            done: saturated,
            capped: false,
            rng,
            component: piece.component,
        })
    }

    /// Update `done`/`capped` from the counters.
    fn update_state(&mut self) {
        if self.signals >= self.budget {
            if self.net.live >= self.target {
                self.done = true;
            } else if self.signals >= 2 * self.budget {
                self.done = true;
                self.capped = true;
            }
        }
    }

    /// Signals to the end of the current canonical chunk: up to the budget, then to the next
    /// multiple of [`CHECK_EVERY`].
    fn to_boundary(&self) -> u64 {
        if self.signals < self.budget {
            (self.budget - self.signals).min(CHECK_EVERY - self.signals % CHECK_EVERY)
        } else {
            CHECK_EVERY - self.signals % CHECK_EVERY
        }
    }

    /// Process up to `quota` signals in chunks that end on the canonical boundaries
    /// ([`Part::to_boundary`]), where `done` is updated; stop early when done, cancelled or
    /// past `deadline`. Returns the signals processed.
    fn advance(
        &mut self,
        quota: u64,
        search: SearchStrategy,
        s: LoopSettings,
        deadline: Option<Instant>,
        cancel: &CancelToken,
    ) -> u64 {
        // The linear scan costs O(|A|) per signal: check the clock correspondingly more often.
        let check_every = match search {
            SearchStrategy::Grid => CHECK_EVERY,
            SearchStrategy::LinearScan => (CHECK_EVERY * 64 / self.net.live.max(1) as u64).max(1),
        };
        let mut processed = 0;
        while processed < quota && !self.done {
            if cancel.is_cancelled() || deadline.is_some_and(|d| Instant::now() >= d) {
                break;
            }
            let boundary = self.to_boundary();
            let chunk = boundary.min(check_every).min(quota - processed);
            match search {
                SearchStrategy::Grid => self.run_signals::<true>(chunk, s),
                SearchStrategy::LinearScan => self.run_signals::<false>(chunk, s),
            }
            processed += chunk;
            if chunk == boundary {
                self.update_state();
            }
        }
        processed
    }

    /// (Re)build the grid for the current node count.
    fn rebuild_grid(&mut self) {
        let live = self.net.live;
        let cells = match &self.net.grid {
            Some(g) => grid_cells(self.area, g.volume(), live),
            None => return,
        };
        self.grid_built_for = live;
        let nodes: Vec<(u32, Vec3)> = self
            .net
            .live_slots()
            .map(|s| (s, self.net.pos[s as usize]))
            .collect();
        if let Some(g) = &mut self.net.grid {
            g.rebuild(cells, nodes.into_iter());
            debug_assert_eq!(g.len(), live);
        }
        self.net.renumber_by_cell();
    }

    /// The inner loop: `count` signals with nearest search through the grid (`GRID`) or a scan.
    ///
    /// Signals are drawn `SIGNAL_BATCH` at a time before any of them is presented: they do not
    /// depend on the network, and a draw is a few random reads into arrays larger than the
    /// cache (alias table, face corners, or vertex positions), so drawing them in a tight loop
    /// lets the reads overlap instead of each one stalling the update that follows it. The
    /// random stream is consumed in the same order, so results are unchanged.
    fn run_signals<const GRID: bool>(&mut self, count: u64, s: LoopSettings) {
        let mut batch = [Vec3::ZERO; SIGNAL_BATCH];
        let mut index = [0u32; SIGNAL_BATCH];
        let mut left = count;
        while left > 0 {
            let size = left.min(SIGNAL_BATCH as u64) as usize;
            left -= size as u64;
            self.signals_src
                .draw_batch(&mut self.rng, &mut batch[..size], &mut index[..size]);
            for &x in &batch[..size] {
                self.present::<GRID>(x, s);
            }
        }
    }

    /// One signal: winner search, GNG update, insertion every λ, removal window.
    #[inline(always)]
    fn present<const GRID: bool>(&mut self, x: Vec3, s: LoopSettings) {
        let nn = if GRID {
            match &self.net.grid {
                Some(g) => g.nearest2(x, &self.net.pos),
                None => Nearest2::EMPTY,
            }
        } else {
            self.linear_nearest2(x)
        };
        let s1 = nn.first;
        if s1 != NONE {
            let net = &mut self.net;
            let i1 = s1 as usize;
            net.wins[i1] = net.wins[i1].wrapping_add(1);
            net.last_win[i1] = self.signals;
            net.err[i1] += nn.first_d2 as f64 * net.inv_scale;
            net.note_error(i1);
            net.pull(s1, x, s.eps_b);
            let d = net.degree[i1] as usize;
            for k in 0..d {
                let nb = net.adj[i1].nb[k];
                net.pull(nb, x, s.eps_n);
            }
            if nn.second != NONE {
                net.connect(s1, nn.second);
            }
            net.drop_old_edges(s1, s.max_age);
            net.decay(s.inv_decay);
        }
        self.signals += 1;
        if GRID && self.signals >= self.next_renumber {
            self.net.renumber_by_cell();
            self.next_renumber = self.signals + RENUMBER_EVERY_EPOCHS * self.net.live as u64;
        }
        if self.signals >= self.next_insert {
            self.next_insert = self.signals + s.lambda;
            if self.net.live < self.target {
                self.insert(x, s.alpha);
            }
        }
        if s.removal_window > 0.0 && self.signals < self.budget {
            let window = (s.removal_window * self.net.live as f64) as u64;
            if self.signals - self.window_start >= window.max(1) {
                self.remove_inactive();
            }
        }
    }

    /// Naive two-nearest search over all live nodes.
    fn linear_nearest2(&self, x: Vec3) -> Nearest2 {
        let mut best = Nearest2::EMPTY;
        for (i, (p, &a)) in self.net.pos.iter().zip(&self.net.alive).enumerate() {
            if a {
                best.offer(i as u32, (*p - x).length_squared());
            }
        }
        best
    }

    /// Fritzke insertion between the max-error node q and its max-error neighbour f.
    fn insert(&mut self, x: Vec3, alpha: f64) {
        let net = &mut self.net;
        let Some(q) = net.max_error_node() else {
            net.add_node(x, 0.0, self.signals);
            return;
        };
        let dq = net.degree[q as usize] as usize;
        if dq == 0 {
            // Only possible when the network collapsed to unconnected nodes: seed at the signal.
            net.add_node(x, 0.0, self.signals);
            return;
        }
        let f = net.adj[q as usize].nb[..dq]
            .iter()
            .copied()
            .max_by(|&a, &b| net.err[a as usize].total_cmp(&net.err[b as usize]))
            .unwrap_or(NONE);
        net.err[q as usize] *= alpha;
        net.err[f as usize] *= alpha;
        let mid = (net.pos[q as usize] + net.pos[f as usize]) * 0.5;
        let r = net.add_node(mid, net.err[q as usize], self.signals);
        net.disconnect(q, f);
        net.connect(q, r);
        net.connect(r, f);
        self.insertions += 1;
        if net.grid.is_some() && net.live > GRID_REBUILD_GROWTH * self.grid_built_for {
            self.rebuild_grid();
        }
    }

    /// GNG3D rule: remove nodes that won nothing since the window started; start a new window.
    fn remove_inactive(&mut self) {
        let start = self.window_start;
        for s in 0..self.net.pos.len() {
            if self.net.live <= 2 {
                break;
            }
            if self.net.alive[s] && self.net.last_win[s] < start {
                self.removed_inactive += 1;
                self.net.remove_node(s as u32);
            }
        }
        self.window_start = self.signals;
    }
}

/// Step-wise GNG3D trainer over one mesh. See the crate docs for an example.
///
/// Every connected component of the input with enough mass for 3 nodes (a triangle) is
/// trained by its own network in its own local frame
/// (see the `domain` module), so pieces never share nodes and far-away or huge coordinates do
/// not spoil the grid or f32 precision. With [`GngParams::split_training`] a large component
/// trains as two halves. The parts advance in rounds, side by side on threads, each with its
/// own random stream: the result does not depend on the thread count or on how `step` calls
/// divide the signals.
#[derive(Debug, Clone)]
pub struct Trainer {
    original: Arc<TriMesh>,
    /// Distinct points and components of `original`, shared with phase 2.
    input: Pieces,
    /// Phase 2's tables of `original`, built on a helper thread while training runs.
    tables: Arc<BackgroundTables>,
    /// Each original triangle's side of the seams when the input's attributes have seams
    /// ([`Trainer::with_attributes`], `seams::seam_sides`).
    charts: Option<Arc<Vec<u32>>>,
    params: GngParams,
    /// The steps after training ([`Plan::of`] the parameters, less what the time limit left
    /// out).
    plan: Plan,
    /// Wall time from `started` at which training stops once the network holds its nodes
    /// (the time limit less what the plan needs).
    training_limit: Option<Duration>,
    /// What the time limit left out of the run before it started.
    plan_warnings: Vec<GngWarning>,
    /// The plan these parameters have without a time limit.
    full_plan: Plan,
    /// Runs of each optional step the time limit left out of the plan.
    cut_runs: Vec<(crate::pipeline::Step, usize)>,
    /// When the run began (the top of [`Trainer::new`]): the time limit counts from here.
    started: Instant,
    parts: Vec<Part>,
    /// Warnings of the domain set-up (dropped components, stray vertices, capacity).
    domain_warnings: Vec<GngWarning>,
    /// Nodes all parts together aim for.
    held_target: usize,
    /// λ in use; the time-limit schedule only ever lowers it.
    lambda: u64,
    budget: u64,
    inv_decay: f64,
    signals: u64,
    elapsed: Duration,
    growth_elapsed: Option<Duration>,
    /// Highest signals/s seen over one chunk (for the time-limit schedule).
    peak_rate: f64,
    stop: Option<StopReason>,
    cancel: CancelToken,
    /// Threads a round and the steps after training may use ([`crate::parallel::threads`] of
    /// [`GngParams::threads`]).
    threads: usize,
}

impl Trainer {
    /// Validate `params` against `mesh` and set up training (two nodes at random vertices of
    /// every trained component).
    pub fn new(mesh: &TriMesh, params: GngParams) -> Result<Trainer, GngError> {
        Trainer::set_up(mesh, None, params)
    }

    /// [`Trainer::new`] for a mesh with attributes (normals, texture coordinates, colours,
    /// materials; they must fit `mesh`: [`mesh::attributes::Attributes::validate`]). When they
    /// have seams ([`mesh::attributes::Attributes::seam_edges`]) the output's triangles follow
    /// them: the plan cuts the network's mesh along the seams and decimates it along them
    /// ([`crate::Step::CutSeams`]), in every run, oversampled or not, so that the values a
    /// front end then takes from the original (`mesh::transfer::transfer_attributes`) are never
    /// interpolated across a seam. Without seams this is [`Trainer::new`]: the same output. The
    /// output has no attributes; the vertex count stays exact.
    pub fn with_attributes(
        mesh: &TriMesh,
        attributes: &Attributes,
        params: GngParams,
    ) -> Result<Trainer, GngError> {
        attributes.validate(mesh).map_err(GngError::Attributes)?;
        Trainer::set_up(mesh, Some(attributes), params)
    }

    fn set_up(
        mesh: &TriMesh,
        attributes: Option<&Attributes>,
        params: GngParams,
    ) -> Result<Trainer, GngError> {
        let started = Instant::now();
        params.validate()?;
        let charts = attributes
            .filter(|a| !a.seam_edges(mesh).is_empty())
            .map(|a| Arc::new(crate::seams::seam_sides(mesh, a)));
        // The time limit is shared between the training and the steps after it, once.
        let time_plan =
            crate::pipeline::plan_for_time(params, mesh.positions.len(), charts.is_some());
        let params = time_plan.params;
        for (f, t) in mesh.triangles.iter().enumerate() {
            if t.iter().any(|&v| v as usize >= mesh.positions.len()) {
                return Err(GngError::BadIndex { face: f });
            }
        }
        if let Some(v) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(GngError::NonFinite { vertex: v });
        }
        // Phase 2's tables start now, on the core that the set-up below leaves idle, rather
        // than during training, whose two halves keep both cores busy.
        let threads = crate::parallel::threads(params.threads);
        let original = Arc::new(mesh.clone());
        let tables = Arc::new(BackgroundTables::start(&original, threads > 1));
        let input = Pieces::of(mesh);
        let domain = Domain::build(mesh, &input, &params)?;
        let n = params.network_target();
        let budget = signal_budget(&params, domain.distinct);
        let lambda = params
            .lambda
            .map(u64::from)
            .unwrap_or_else(|| (budget / (2 * n as u64)).clamp(1, MAX_AUTO_LAMBDA));
        let held_target: usize = domain.pieces.iter().map(|p| p.target).sum();
        let mut parts = Vec::with_capacity(domain.pieces.len());
        for (k, piece) in domain.pieces.into_iter().enumerate() {
            // Each part's share of the budget follows its share of the nodes.
            let share = (budget as f64 * piece.target as f64 / held_target.max(1) as f64) as u64;
            // Part k's stream: the seed for the first part (a one-part run draws what it drew
            // before parts had streams of their own), then seeds spread by a Weyl step.
            let seed = params
                .seed
                .wrapping_add((k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
            parts.push(Part::new(
                piece,
                params.signal_source,
                params.search,
                share.max(1),
                lambda,
                Pcg64Mcg::seed_from_u64(seed),
            )?);
        }
        Ok(Trainer {
            tables,
            charts,
            original,
            input,
            plan: time_plan.plan,
            training_limit: time_plan.training_limit,
            plan_warnings: time_plan.warnings,
            full_plan: time_plan.full,
            cut_runs: time_plan.cut_runs,
            started,
            inv_decay: 1.0 / params.error_decay,
            params,
            parts,
            domain_warnings: domain.warnings,
            held_target,
            lambda,
            budget,
            signals: 0,
            elapsed: Duration::ZERO,
            growth_elapsed: None,
            peak_rate: 0.0,
            stop: None,
            cancel: CancelToken::default(),
            threads,
        })
    }

    /// The parameters in use.
    pub fn params(&self) -> &GngParams {
        &self.params
    }

    /// The steps [`crate::finish`] runs after training.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// The steps these parameters have without a time limit: [`Trainer::plan`] is this list
    /// less what the limit left out before the run started.
    pub fn full_plan(&self) -> &Plan {
        &self.full_plan
    }

    /// With a time limit, the wall time from the start of the run ([`Trainer::new`]) at which
    /// training stops once the network holds its nodes: the limit less what the plan's steps
    /// need. A front end that paces training (a viewer) paces it to this.
    pub fn training_limit(&self) -> Option<Duration> {
        self.training_limit
    }

    /// Wall time since the start of the run ([`Trainer::new`]), less what [`Trainer::discount`]
    /// left out.
    pub fn run_elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// Leave `idle` out of the run's clock: a front end that paused the run (a viewer) hands
    /// the pause back, so that the time limit counts only the time the run was going.
    pub fn discount(&mut self, idle: Duration) {
        self.started += idle;
    }

    /// The mesh being simplified.
    pub fn original(&self) -> &TriMesh {
        &self.original
    }

    /// A token that cancels this trainer from any thread.
    pub fn cancel_token(&self) -> CancelToken {
        self.cancel.clone()
    }

    /// Whether training has ended (budget used with the target reached, time limit, cancel).
    pub fn is_finished(&self) -> bool {
        self.stop.is_some()
    }

    /// Signals processed so far.
    pub fn signals(&self) -> u64 {
        self.signals
    }

    /// Current node count (all components).
    pub fn node_count(&self) -> usize {
        self.parts.iter().map(|p| p.net.live).sum()
    }

    /// Node count the trained components aim for: the target, unless
    /// [`Trainer::warnings`] reports that it cannot be held.
    pub fn node_target(&self) -> usize {
        self.held_target
    }

    /// Current edge count.
    pub fn edge_count(&self) -> usize {
        self.parts.iter().map(|p| p.net.edges).sum()
    }

    /// Training time so far.
    pub fn elapsed(&self) -> Duration {
        self.elapsed
    }

    /// What was dropped from the input or keeps the network from the target so far.
    pub fn warnings(&self) -> Vec<GngWarning> {
        let mut w = self.plan_warnings.clone();
        w.extend(self.domain_warnings.iter().cloned());
        if self.stop == Some(StopReason::TimeLimit) && self.node_count() < self.held_target {
            w.push(GngWarning::TimeLimitBeforeTarget {
                nodes: self.node_count(),
                target: self.held_target,
                limit_seconds: self.params.time_limit.map_or(0.0, |t| t.as_secs_f64()),
            });
        }
        w
    }

    /// Counters so far.
    pub fn stats(&self) -> TrainingStats {
        let sum = |f: fn(&Part) -> u64| self.parts.iter().map(f).sum::<u64>();
        TrainingStats {
            signals: self.signals,
            lambda: self.lambda,
            max_signals: self.budget,
            insertions: sum(|p| p.insertions),
            removed_inactive: sum(|p| p.removed_inactive),
            removed_isolated: sum(|p| p.net.removed_isolated),
            components: self
                .parts
                .iter()
                .map(|p| p.component)
                .collect::<std::collections::BTreeSet<_>>()
                .len(),
            seconds: self.elapsed.as_secs_f64(),
            growth_seconds: self.growth_elapsed.map(|d| d.as_secs_f64()),
            stop: self.stop,
        }
    }

    /// Switch the nearest-node search (e.g. to compare against the linear-scan baseline).
    pub fn set_search_strategy(&mut self, search: SearchStrategy) {
        self.params.search = search;
        for part in &mut self.parts {
            match search {
                SearchStrategy::LinearScan => part.net.grid = None,
                SearchStrategy::Grid => {
                    if part.net.grid.is_none() {
                        part.net.grid = Some(Grid::new(part.bbox.min, part.bbox.max, 1));
                        part.rebuild_grid();
                    }
                }
            }
        }
    }

    /// Time-limit schedule: lower λ so that the missing nodes are inserted by
    /// [`GROWTH_SHARE_OF_TIME_LIMIT`] of the limit at the peak throughput measured over one
    /// chunk. The peak, not the running mean: insertions get dearer as the network grows
    /// (max-error scan, grid rebuilds), and a falling mean rate made the schedule spiral down
    /// to λ = 1 with growth still unfinished (measured on igea, N = 20,000, 0.5 s).
    fn schedule_growth(&mut self, now: Duration) {
        let Some(limit) = self.training_limit else {
            return;
        };
        if self.growth_elapsed.is_some() || self.signals < RATE_WARMUP_SIGNALS || now.is_zero() {
            return;
        }
        let missing: usize = self
            .parts
            .iter()
            .map(|p| p.target.saturating_sub(p.net.live))
            .sum();
        if missing == 0 {
            return;
        }
        let rate = self.peak_rate.max(self.signals as f64 / now.as_secs_f64());
        let wall = self.started.elapsed().as_secs_f64();
        let left = (limit.as_secs_f64() * GROWTH_SHARE_OF_TIME_LIMIT - wall).max(0.0);
        let affordable = (rate * left / missing as f64).floor().max(1.0) as u64;
        if affordable < self.lambda {
            self.lambda = affordable;
            for p in &mut self.parts {
                p.next_insert = p.next_insert.min(p.signals + affordable);
            }
        }
    }

    /// Why training ends when every part is done: its budget, or the cap of twice the budget
    /// for a part that could not reach its nodes.
    fn budget_stop(&self) -> StopReason {
        if self.parts.iter().any(|p| p.capped) {
            StopReason::SignalCap
        } else {
            StopReason::Completed
        }
    }

    /// One insertion per signal from now on (growth past the training's share of the time
    /// limit).
    fn force_growth(&mut self) {
        if self.lambda > 1 {
            self.lambda = 1;
            for p in &mut self.parts {
                p.next_insert = p.next_insert.min(p.signals + 1);
            }
        }
    }

    /// Process up to `n` signals (fewer when training ends); returns how many were processed.
    ///
    /// In rounds: the unfinished parts' signal counts after a round are shares of their total
    /// in proportion to the budgets (`round_quotas`), and the parts of a round run side by
    /// side, one thread each (up to the machine's parallelism). A part's result depends only on
    /// its own stream and signal count, and the counts only on the total, so the network after
    /// S signals is the same whatever the rounds, the threads or the `step` calls before.
    pub fn step(&mut self, n: u64) -> u64 {
        if self.stop.is_some() {
            return 0;
        }
        let start = Instant::now();
        let mut done = 0;
        while done < n {
            if self.cancel.is_cancelled() {
                self.stop = Some(StopReason::Cancelled);
                break;
            }
            // The time limit counts wall time from the start of the run (set-up included).
            let now = self.started.elapsed();
            let past_limit = self.training_limit.is_some_and(|limit| now >= limit);
            if past_limit {
                if self.node_count() >= self.held_target {
                    self.stop = Some(StopReason::TimeLimit);
                    break;
                }
                // Growth is never cut short (the vertex count stays exact): past the limit the
                // missing nodes come in as fast as they can, one per signal.
                self.force_growth();
            }
            let (budgets, counts): (Vec<u64>, Vec<u64>) = self
                .parts
                .iter()
                .filter(|p| !p.done)
                .map(|p| (p.budget, p.signals))
                .unzip();
            if budgets.is_empty() {
                self.stop = Some(self.budget_stop());
                break;
            }
            self.schedule_growth(self.elapsed + start.elapsed());
            let settings = LoopSettings {
                eps_b: self.params.eps_winner,
                eps_n: self.params.eps_neighbour,
                max_age: self.params.max_edge_age,
                inv_decay: self.inv_decay,
                alpha: self.params.alpha,
                removal_window: self.params.removal_window,
                lambda: self.lambda,
            };
            // One round: the unfinished parts side by side, each with its share.
            let round = (n - done).min(ROUND_SIGNALS_PER_PART * budgets.len() as u64);
            let quotas = round_quotas(round, &budgets, &counts);
            let deadline = self
                .training_limit
                .filter(|_| !past_limit)
                .map(|limit| self.started + limit);
            let (search, cancel) = (self.params.search, &self.cancel);
            let mut work: Vec<(&mut Part, u64)> = self
                .parts
                .iter_mut()
                .filter(|p| !p.done)
                .zip(quotas)
                .collect();
            let round_start = Instant::now();
            let processed = crate::parallel::sum_over_groups(&mut work, self.threads, |work| {
                let (part, quota) = work;
                part.advance(*quota, search, settings, deadline, cancel)
            });
            if self.training_limit.is_some() && processed >= CHECK_EVERY / 2 {
                let dt = round_start.elapsed().as_secs_f64();
                if dt > 0.0 {
                    self.peak_rate = self.peak_rate.max(processed as f64 / dt);
                }
            }
            done += processed;
            self.signals += processed;
            if self.growth_elapsed.is_none() && self.node_count() >= self.held_target {
                self.growth_elapsed = Some(self.elapsed + start.elapsed());
            }
            // Finished as soon as the last part is, not at the next call.
            if self.parts.iter().all(|p| p.done) {
                self.stop = Some(self.budget_stop());
                break;
            }
        }
        self.elapsed += start.elapsed();
        done
    }

    /// Run to completion, calling `observer` every `every` signals (and once at the end); the
    /// observer may stop training by returning `ControlFlow::Break(())`.
    pub fn train(&mut self, every: u64, mut observer: impl FnMut(&Progress) -> ControlFlow<()>) {
        let every = every.max(1);
        while !self.is_finished() {
            self.step(every);
            let progress = self.progress();
            if observer(&progress).is_break() {
                if self.stop.is_none() {
                    self.stop = Some(StopReason::Cancelled);
                }
                break;
            }
        }
    }

    /// Current progress. Vertex errors of the nodes: `metrics::vertex_errors` on
    /// [`Trainer::snapshot`] positions.
    pub fn progress(&self) -> Progress {
        Progress {
            signals: self.signals,
            nodes: self.node_count(),
            edges: self.edge_count(),
            elapsed: self.elapsed,
        }
    }

    /// Copy of the network (all components, world coordinates) with compact indices.
    pub fn snapshot(&self) -> Snapshot {
        let mut positions = Vec::with_capacity(self.node_count());
        let mut edges = Vec::with_capacity(self.edge_count());
        for part in &self.parts {
            let mut map = vec![NONE; part.net.pos.len()];
            for s in part.net.live_slots() {
                map[s as usize] = positions.len() as u32;
                positions.push(part.frame.to_world(part.net.pos[s as usize]));
            }
            edges.extend(
                part.net
                    .edge_pairs()
                    .map(|(a, b)| [map[a as usize], map[b as usize]]),
            );
        }
        Snapshot {
            positions,
            edges,
            signals: self.signals,
            target: self.params.network_target(),
            finished: self.is_finished(),
        }
    }

    /// The reconstruction alone (no decimation) of the current network with `params`, every
    /// option as given (a tool for experiments: option (f) and (g) add vertices here).
    pub fn reconstruct(&self, params: &ReconstructionParams) -> Reconstruction {
        let snap = self.snapshot();
        crate::pipeline::reconstruct_only(&self.pipeline_input(&snap, params))
    }

    /// A preview of the current network, e.g. while it trains: the run's plan without its
    /// detail rounds (each costs about one more reconstruction), with [`crate::finish`]'s checks;
    /// no warnings (a network still growing is short of the target by design).
    pub fn preview(&self) -> Result<GngResult, GngError> {
        let mut reconstruction = self.params.reconstruction.clone();
        reconstruction.detail_rounds = 0;
        let plan = Plan::with_seams(
            &reconstruction,
            self.params.decimates(),
            self.charts.is_some(),
        );
        let snap = self.snapshot();
        let mut result = self.run_plan_with(&snap, &plan, &reconstruction, None, None, |_| {})?;
        result.report.warnings.clear();
        Ok(result)
    }

    fn pipeline_input<'a>(
        &'a self,
        snap: &'a Snapshot,
        params: &'a ReconstructionParams,
    ) -> crate::pipeline::Input<'a> {
        crate::pipeline::Input {
            original: &self.original,
            pieces: &self.input,
            tables: self.tables.get(),
            nodes: &snap.positions,
            edges: &snap.edges,
            params,
            decimate_to: (self.params.decimates() || self.charts.is_some())
                .then_some(self.params.target_vertices),
            charts: self.charts.as_deref().map(Vec::as_slice),
            threads: self.threads,
        }
    }

    /// [`crate::finish_cancellable`]: `plan` on `snap`, with the checks and warnings of a run,
    /// stopped with [`GngError::Cancelled`] when `cancel` is set.
    pub(crate) fn run_plan(
        &self,
        snap: &Snapshot,
        plan: &Plan,
        cancel: Option<&CancelToken>,
        on_step: impl FnMut(&StepRecord),
    ) -> Result<GngResult, GngError> {
        let deadline = self.params.time_limit.map(|limit| {
            self.started + Duration::from_secs_f64(crate::pipeline::aim_seconds(limit))
        });
        self.run_plan_with(
            snap,
            plan,
            &self.params.reconstruction,
            deadline,
            cancel,
            on_step,
        )
    }

    fn run_plan_with(
        &self,
        snap: &Snapshot,
        plan: &Plan,
        reconstruction: &ReconstructionParams,
        deadline: Option<Instant>,
        cancel: Option<&CancelToken>,
        on_step: impl FnMut(&StepRecord),
    ) -> Result<GngResult, GngError> {
        let stats = self.stats();
        if snap.positions.len() < 3 {
            return Err(GngError::TooFewNodes {
                nodes: snap.positions.len(),
                stop: stats.stop,
            });
        }
        let input = self.pipeline_input(snap, reconstruction);
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
        let mut warnings = self.warnings();
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
        let target = self.params.target_vertices;
        let vertices = out.mesh.vertex_count();
        if self.params.decimates() || self.charts.is_some() {
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
        let report = GngReport {
            training: stats,
            target_vertices: target,
            network_vertices: out.report.vertices,
            vertices,
            faces: out.mesh.face_count(),
            reconstruction: out.report,
            steps: out.steps,
            seconds: self.started.elapsed().as_secs_f64(),
            warnings,
        };
        Ok(GngResult {
            mesh: out.mesh,
            nodes: snap.positions.clone(),
            report,
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

/// `round` more signals for the open parts with these budgets and signal counts, so that each
/// part's count after the round is its share of the open parts' total *after* the round, in
/// proportion to the budgets (largest part first for the remainder). The counts are then a
/// function of that total alone, not of how earlier calls divided it: two calls of 3,331 and
/// 6,669 signals leave every part where one call of 10,000 does (a viewer's checkpoint shows
/// the same network). Parts already past their share (possible with three or more parts,
/// where rounding is not monotone) get none, and the others' shares shrink to keep the sum.
fn round_quotas(round: u64, budgets: &[u64], counts: &[u64]) -> Vec<u64> {
    let total = round + counts.iter().sum::<u64>();
    let weight: u128 = budgets.iter().map(|&b| u128::from(b.max(1))).sum();
    let mut share: Vec<u64> = budgets
        .iter()
        .map(|&b| (u128::from(total) * u128::from(b.max(1)) / weight.max(1)) as u64)
        .collect();
    let given: u64 = share.iter().sum();
    if let Some(k) = (0..budgets.len()).max_by_key(|&k| (budgets[k], std::cmp::Reverse(k))) {
        share[k] += total - given;
    }
    let mut quotas: Vec<u64> = share
        .iter()
        .zip(counts)
        .map(|(&s, &c)| s.saturating_sub(c))
        .collect();
    let mut excess = quotas.iter().sum::<u64>() - round;
    while excess > 0 {
        let k = (0..quotas.len()).max_by_key(|&k| quotas[k]).unwrap_or(0);
        let cut = excess.min(quotas[k]);
        quotas[k] -= cut;
        excess -= cut;
    }
    quotas
}

/// Phase 2's tables of the original ([`OriginalTables`]: edge table, vertex adjacency), built
/// on a helper thread started with the trainer, so that they are ready when training ends
/// (igea: ~45 ms of work that phase 2 no longer waits for, and both cores label). Shared by
/// clones of the trainer; every reconstruction (the viewer's checkpoints too) reuses them.
struct BackgroundTables {
    handle: Mutex<Option<JoinHandle<OriginalTables>>>,
    tables: OnceLock<Option<OriginalTables>>,
}

impl BackgroundTables {
    /// Start building the tables of `original` on a helper thread when `spawn` (nothing when
    /// not, or when no thread can be started: phase 2 then builds them itself).
    fn start(original: &Arc<TriMesh>, spawn: bool) -> BackgroundTables {
        let mesh = Arc::clone(original);
        let handle = spawn
            .then(|| {
                std::thread::Builder::new()
                    .name("gng3d-tables".into())
                    .spawn(move || OriginalTables::of(&mesh))
                    .ok()
            })
            .flatten();
        BackgroundTables {
            handle: Mutex::new(handle),
            tables: OnceLock::new(),
        }
    }

    /// The tables, waiting for the helper thread if needed; `None` when it could not run.
    fn get(&self) -> Option<&OriginalTables> {
        self.tables
            .get_or_init(|| {
                let handle = self.handle.lock().ok()?.take()?;
                handle.join().ok()
            })
            .as_ref()
    }
}

impl std::fmt::Debug for BackgroundTables {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BackgroundTables")
            .field("ready", &self.tables.get().is_some())
            .finish()
    }
}

/// Total signal budget: `max_signals`, else `epochs` × distinct vertices, else
/// [`DEFAULT_SIGNALS_PER_NODE`] × the output's vertex count (the decimation's target in
/// oversampled runs, whose extra nodes share that budget).
pub(crate) fn signal_budget(params: &GngParams, distinct: usize) -> u64 {
    let n = params.target_vertices as f64;
    let v = distinct as f64;
    let b = match (params.max_signals, params.epochs) {
        (Some(m), _) => m as f64,
        (None, Some(e)) => e * v,
        (None, None) => DEFAULT_SIGNALS_PER_NODE * n,
    };
    (b.round() as u64).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_cells_follow_the_surface_spacing_and_clamp() {
        // Surface of area 1 in a box of volume 0.1: side = spacing / sqrt(n).
        let n = 10_000;
        let side = GRID_CELL_SPACING / (n as f64).sqrt();
        let want = 0.1 / (side * side * side);
        let got = grid_cells(1.0, 0.1, n) as f64;
        assert!((got - want).abs() <= 1.0, "{got} vs {want}");
        // Four times the nodes: half the side, eight times the cells.
        let ratio = grid_cells(1.0, 0.1, 4 * n) as f64 / got;
        assert!((ratio - 8.0).abs() < 1e-3, "{ratio}");
        // Degenerate inputs stay within [1, 64] cells per node.
        assert_eq!(grid_cells(0.0, 1.0, 100), 6_400);
        assert_eq!(grid_cells(1.0, 0.0, 100), 100);
        assert_eq!(grid_cells(1e12, 1.0, 100), 100);
    }

    /// A trainer of `mesh` for `target` nodes with `split_training`, on `threads` threads.
    fn trainer(mesh: &TriMesh, target: usize, split: bool, threads: usize) -> Trainer {
        let mut params = GngParams::for_target(target);
        params.split_training = split;
        let mut t = Trainer::new(mesh, params).expect("trainer");
        t.threads = threads;
        t
    }

    #[test]
    fn halves_train_the_same_on_one_thread_and_two_in_any_step_sizes() {
        let sphere = mesh::procedural::icosphere(5);
        let mut one = trainer(&sphere, 800, true, 1);
        assert_eq!(one.parts.len(), 2, "a 800-node sphere trains as two halves");
        assert_eq!(one.stats().components, 1);
        assert_eq!(one.parts.iter().map(|p| p.target).sum::<usize>(), 800);
        while !one.is_finished() {
            one.step(u64::MAX);
        }
        let mut two = trainer(&sphere, 800, true, 2);
        let mut calls = 0;
        while !two.is_finished() {
            // Odd step sizes: rounds end anywhere inside the parts' chunks.
            two.step(777 + 1000 * (calls % 3));
            calls += 1;
        }
        assert!(calls > 10);
        let (a, b) = (one.snapshot(), two.snapshot());
        assert_eq!(a.positions.len(), 800);
        assert_eq!(a.positions, b.positions);
        assert_eq!(a.edges, b.edges);
        assert_eq!(one.signals(), two.signals());
        // Each half holds the nodes allotted to it.
        let per_part: Vec<usize> = one.parts.iter().map(|p| p.net.live).collect();
        assert_eq!(
            per_part,
            one.parts.iter().map(|p| p.target).collect::<Vec<_>>()
        );
    }

    #[test]
    fn halves_pass_through_the_same_states_whatever_the_step_sizes() {
        // What a viewer's checkpoint shows after S signals must not depend on how the calls
        // before it divided those S signals between them.
        let sphere = mesh::procedural::icosphere(5);
        let mut even = trainer(&sphere, 800, true, 2);
        let mut odd = trainer(&sphere, 800, true, 2);
        let mut checked = 0;
        while !even.is_finished() {
            even.step(10_000);
            odd.step(3_331);
            odd.step(6_669);
            assert_eq!(even.signals(), odd.signals());
            let (a, b) = (even.snapshot(), odd.snapshot());
            assert_eq!(a.positions, b.positions, "after {} signals", even.signals());
            checked += 1;
        }
        assert!(checked > 5);
    }

    #[test]
    fn round_quotas_follow_the_total_and_sum_to_the_round() {
        // Two parts: each count is a function of the total only.
        let b = [300, 100];
        let once = round_quotas(1000, &b, &[0, 0]);
        assert_eq!(once, vec![750, 250]);
        let first = round_quotas(333, &b, &[0, 0]);
        let second = round_quotas(667, &b, &[first[0], first[1]]);
        assert_eq!([first[0] + second[0], first[1] + second[1]], [750, 250]);
        // Any parts and counts: the quotas sum to the round.
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        for _ in 0..500 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let n = 1 + (x % 5) as usize;
            let budgets: Vec<u64> = (0..n).map(|i| 1 + (x >> (8 * i)) % 1000).collect();
            let counts: Vec<u64> = (0..n).map(|i| (x >> (7 * i + 3)) % 5000).collect();
            let round = x % 7000;
            let q = round_quotas(round, &budgets, &counts);
            assert_eq!(
                q.iter().sum::<u64>(),
                round,
                "{budgets:?} {counts:?} {round}"
            );
        }
    }

    #[test]
    fn a_network_below_the_split_size_trains_as_one_part() {
        let sphere = mesh::procedural::icosphere(4);
        let split = trainer(&sphere, crate::domain::SPLIT_MIN_NODES - 1, true, 2);
        assert_eq!(split.parts.len(), 1);
        // And without the option a large one is one part as well.
        assert_eq!(trainer(&sphere, 1000, false, 2).parts.len(), 1);
    }
}

//! Phase 1: the GNG3D training loop, step-wise ([`Trainer::step`]) or to completion with a
//! progress observer ([`Trainer::train`]), plus snapshots and cancellation for viewers.

use crate::ReconstructionParams;
use crate::error::GngError;
use crate::grid::{Grid, NONE, Nearest2};
use crate::network::Network;
use crate::params::{GngParams, SearchStrategy, SignalSource};
use crate::reconstruct::{Reconstruction, reconstruct};
use glam::Vec3;
use mesh::TriMesh;
use rand::Rng;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
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
/// Signals between checks of the clock and the cancellation flag.
const CHECK_EVERY: u64 = 1024;
/// Largest automatic λ.
const MAX_AUTO_LAMBDA: u64 = 200;

/// Shared flag that stops a running [`Trainer`] from another thread.
#[derive(Debug, Clone, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    /// Ask the trainer to stop at its next check (within about a thousand signals).
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether cancellation was requested.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Why training ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum StopReason {
    /// The signal budget was used and the node count is at the target.
    Completed,
    /// The time limit was reached.
    TimeLimit,
    /// Cancelled through a [`CancelToken`] or an observer.
    Cancelled,
    /// Twice the signal budget was used without reaching the target (should not happen).
    SignalCap,
}

/// A copy of the network with compact indices, for drawing.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Progress {
    /// Signals processed so far (the paper's iterations).
    pub signals: u64,
    /// Current node count.
    pub nodes: usize,
    /// Current edge count.
    pub edges: usize,
    /// Training time so far (sum of the time spent inside `step`).
    pub elapsed: Duration,
    /// e_avg/e_max of the nodes against the original vertices, when
    /// [`GngParams::track_errors`] is set.
    pub errors: Option<metrics::VertexErrors>,
}

/// Counters of a finished or running training.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrainingStats {
    /// Signals processed.
    pub signals: u64,
    /// λ actually used.
    pub lambda: u64,
    /// Signal budget (30 epochs unless set).
    pub max_signals: u64,
    /// Nodes inserted (Fritzke insertion).
    pub insertions: u64,
    /// Nodes removed by the μ inactivity rule.
    pub removed_inactive: u64,
    /// Nodes removed because they lost their last edge.
    pub removed_isolated: u64,
    /// Training time, seconds.
    pub seconds: f64,
    /// Why training ended (`None` while running).
    pub stop: Option<StopReason>,
}

/// Signal generator over the original mesh.
#[derive(Debug, Clone)]
enum Signals {
    /// Distinct referenced vertex positions.
    Points(Vec<Vec3>),
    /// Triangles (corner positions) with a Walker/Vose alias table over their areas, for O(1)
    /// area-weighted sampling.
    Surface {
        corners: Vec<[Vec3; 3]>,
        /// Probability of keeping slot i (else take `alias[i]`).
        keep: Vec<f64>,
        alias: Vec<u32>,
    },
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

/// Vose's alias table for sampling index i with probability `weights[i] / sum`.
fn alias_table(weights: &[f64]) -> (Vec<f64>, Vec<u32>) {
    let n = weights.len();
    let total: f64 = weights.iter().sum();
    let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
    let mut alias: Vec<u32> = (0..n as u32).collect();
    let (mut small, mut large): (Vec<u32>, Vec<u32>) =
        (0..n as u32).partition(|&i| scaled[i as usize] < 1.0);
    while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
        alias[s as usize] = l;
        scaled[l as usize] -= 1.0 - scaled[s as usize];
        if scaled[l as usize] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    // Leftovers are 1 up to rounding.
    for i in small.into_iter().chain(large) {
        scaled[i as usize] = 1.0;
    }
    (scaled, alias)
}

impl Signals {
    #[inline(always)]
    fn draw(&self, rng: &mut Pcg64Mcg) -> Vec3 {
        match self {
            Signals::Points(p) => p[rng.random_range(0..p.len())],
            Signals::Surface {
                corners,
                keep,
                alias,
            } => {
                let i = rng.random_range(0..corners.len());
                let f = if rng.random::<f64>() < keep[i] {
                    i
                } else {
                    alias[i] as usize
                };
                let [a, b, c] = corners[f];
                let (u, v): (f32, f32) = (rng.random(), rng.random());
                let su = u.sqrt();
                a * (1.0 - su) + b * (su * (1.0 - v)) + c * (su * v)
            }
        }
    }
}

/// Step-wise GNG3D trainer over one mesh. See the crate docs for an example.
#[derive(Debug, Clone)]
pub struct Trainer {
    original: TriMesh,
    /// Distinct referenced vertex positions (for errors and the target check).
    vertices: Vec<Vec3>,
    signals_src: Signals,
    /// Surface area of the mesh (model units squared), for the grid resolution.
    area: f64,
    /// Node count at the last grid rebuild.
    grid_built_for: usize,
    params: GngParams,
    net: Network,
    rng: Pcg64Mcg,
    lambda: u64,
    budget: u64,
    inv_decay: f64,
    signals: u64,
    next_insert: u64,
    next_renumber: u64,
    window_start: u64,
    insertions: u64,
    removed_inactive: u64,
    elapsed: Duration,
    stop: Option<StopReason>,
    cancel: CancelToken,
}

/// Distinct positions of referenced vertices, in first-reference order, plus the box around them.
fn distinct_referenced(mesh: &TriMesh) -> Vec<Vec3> {
    let mut used = vec![false; mesh.positions.len()];
    let mut out = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for t in &mesh.triangles {
        for &v in t {
            let v = v as usize;
            if !used[v] {
                used[v] = true;
                let p = mesh.positions[v];
                if seen.insert(p.to_array().map(f32::to_bits)) {
                    out.push(p);
                }
            }
        }
    }
    out
}

impl Trainer {
    /// Validate `params` against `mesh` and set up training (two nodes at random vertices).
    pub fn new(mesh: &TriMesh, params: GngParams) -> Result<Trainer, GngError> {
        for (f, t) in mesh.triangles.iter().enumerate() {
            if t.iter().any(|&v| v as usize >= mesh.positions.len()) {
                return Err(GngError::BadIndex { face: f });
            }
        }
        if let Some(v) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(GngError::NonFinite { vertex: v });
        }
        let vertices = distinct_referenced(mesh);
        if vertices.len() < 3 {
            return Err(GngError::TooFewVertices {
                vertices: vertices.len(),
            });
        }
        let n = params.target_vertices;
        let vertex_bound = params.signal_source == SignalSource::Vertices;
        if n < 3 || (vertex_bound && n > vertices.len()) {
            return Err(GngError::Target {
                target: n,
                available: vertices.len(),
            });
        }
        check_param("eps_winner", params.eps_winner as f64, 0.0, 1.0)?;
        check_param("eps_neighbour", params.eps_neighbour as f64, 0.0, 1.0)?;
        check_param("alpha", params.alpha, 0.0, 1.0)?;
        check_param("error_decay", params.error_decay, f64::MIN_POSITIVE, 1.0)?;
        if !(params.removal_window >= 0.0 && params.removal_window.is_finite()) {
            return Err(GngError::Parameter {
                name: "removal_window",
                value: params.removal_window,
            });
        }
        if params.lambda == Some(0) {
            return Err(GngError::Parameter {
                name: "lambda",
                value: 0.0,
            });
        }
        let signals_src = match params.signal_source {
            SignalSource::Vertices => Signals::Points(vertices.clone()),
            SignalSource::Surface | SignalSource::Curvature => {
                let mut corners = Vec::with_capacity(mesh.triangles.len());
                let mut areas = Vec::with_capacity(mesh.triangles.len());
                // GNG3D-Q: curvature-weighted areas (crate::features).
                let weights = (params.signal_source == SignalSource::Curvature)
                    .then(|| crate::features::curvature_face_weights(mesh, n));
                for f in 0..mesh.triangles.len() {
                    let a = mesh.triangle_area(f);
                    if a > 0.0 && a.is_finite() {
                        areas.push(weights.as_ref().map_or(a, |w| w[f]));
                        corners.push(mesh.triangle(f));
                    }
                }
                if corners.is_empty() {
                    return Err(GngError::ZeroArea);
                }
                let (keep, alias) = alias_table(&areas);
                Signals::Surface {
                    corners,
                    keep,
                    alias,
                }
            }
        };
        let budget = params
            .max_signals
            .unwrap_or(30 * vertices.len() as u64)
            .max(1);
        let lambda = params
            .lambda
            .map(u64::from)
            .unwrap_or_else(|| (budget / (2 * n as u64)).clamp(1, MAX_AUTO_LAMBDA));
        let bbox = mesh::Aabb::from_points(&vertices);
        let grid = match params.search {
            SearchStrategy::Grid => Some(Grid::new(bbox.min, bbox.max, 1)),
            SearchStrategy::LinearScan => None,
        };
        let mut rng = Pcg64Mcg::seed_from_u64(params.seed);
        let mut net = Network::new(grid, n + 16);
        let a = rng.random_range(0..vertices.len());
        let mut b = rng.random_range(0..vertices.len() - 1);
        if b >= a {
            b += 1;
        }
        net.add_node(vertices[a], 0.0, 0);
        net.add_node(vertices[b], 0.0, 0);
        Ok(Trainer {
            original: mesh.clone(),
            vertices,
            signals_src,
            area: mesh.area(),
            grid_built_for: 2,
            inv_decay: 1.0 / params.error_decay,
            params,
            net,
            rng,
            lambda,
            budget,
            signals: 0,
            next_insert: lambda,
            next_renumber: 0,
            window_start: 0,
            insertions: 0,
            removed_inactive: 0,
            elapsed: Duration::ZERO,
            stop: None,
            cancel: CancelToken::default(),
        })
    }

    /// The parameters in use.
    pub fn params(&self) -> &GngParams {
        &self.params
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

    /// Current node count.
    pub fn node_count(&self) -> usize {
        self.net.live
    }

    /// Current edge count.
    pub fn edge_count(&self) -> usize {
        self.net.edges
    }

    /// Training time so far.
    pub fn elapsed(&self) -> Duration {
        self.elapsed
    }

    /// Counters so far.
    pub fn stats(&self) -> TrainingStats {
        TrainingStats {
            signals: self.signals,
            lambda: self.lambda,
            max_signals: self.budget,
            insertions: self.insertions,
            removed_inactive: self.removed_inactive,
            removed_isolated: self.net.removed_isolated,
            seconds: self.elapsed.as_secs_f64(),
            stop: self.stop,
        }
    }

    /// Switch the nearest-node search (e.g. to compare against the linear-scan baseline).
    pub fn set_search_strategy(&mut self, search: SearchStrategy) {
        self.params.search = search;
        match search {
            SearchStrategy::LinearScan => self.net.grid = None,
            SearchStrategy::Grid => {
                if self.net.grid.is_none() {
                    let bbox = mesh::Aabb::from_points(&self.vertices);
                    let mut g = Grid::new(bbox.min, bbox.max, 1);
                    let cells = grid_cells(self.area, g.volume(), self.net.live);
                    self.grid_built_for = self.net.live;
                    let nodes: Vec<(u32, Vec3)> = self
                        .net
                        .live_slots()
                        .map(|s| (s, self.net.pos[s as usize]))
                        .collect();
                    g.rebuild(cells, nodes.into_iter());
                    self.net.grid = Some(g);
                }
            }
        }
    }

    /// Process up to `n` signals (fewer when training ends); returns how many were processed.
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
            if let Some(limit) = self.params.time_limit
                && self.elapsed + start.elapsed() >= limit
            {
                self.stop = Some(StopReason::TimeLimit);
                break;
            }
            if self.signals >= self.budget {
                if self.net.live >= self.params.target_vertices {
                    self.stop = Some(StopReason::Completed);
                    break;
                }
                if self.signals >= 2 * self.budget {
                    self.stop = Some(StopReason::SignalCap);
                    break;
                }
            }
            // The linear scan costs O(|A|) per signal: check the clock correspondingly more often.
            let check_every = match self.params.search {
                SearchStrategy::Grid => CHECK_EVERY,
                SearchStrategy::LinearScan => {
                    (CHECK_EVERY * 64 / self.net.live.max(1) as u64).max(1)
                }
            };
            let mut chunk = (n - done).min(check_every);
            if self.signals < self.budget {
                chunk = chunk.min(self.budget - self.signals);
            }
            match self.params.search {
                SearchStrategy::Grid => self.run_signals::<true>(chunk),
                SearchStrategy::LinearScan => self.run_signals::<false>(chunk),
            }
            done += chunk;
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

    /// Current progress (errors only when [`GngParams::track_errors`] is set).
    pub fn progress(&self) -> Progress {
        Progress {
            signals: self.signals,
            nodes: self.net.live,
            edges: self.net.edges,
            elapsed: self.elapsed,
            errors: if self.params.track_errors {
                self.current_errors()
            } else {
                None
            },
        }
    }

    /// e_avg/e_max (squared model units) of the current nodes against the distinct original
    /// vertices.
    pub fn current_errors(&self) -> Option<metrics::VertexErrors> {
        let nodes: Vec<Vec3> = self
            .net
            .live_slots()
            .map(|s| self.net.pos[s as usize])
            .collect();
        metrics::vertex_errors(&self.vertices, &nodes)
    }

    /// Copy of the network with compact indices.
    pub fn snapshot(&self) -> Snapshot {
        let mut map = vec![NONE; self.net.pos.len()];
        let mut positions = Vec::with_capacity(self.net.live);
        for s in self.net.live_slots() {
            map[s as usize] = positions.len() as u32;
            positions.push(self.net.pos[s as usize]);
        }
        let edges = self
            .net
            .edge_pairs()
            .map(|(a, b)| [map[a as usize], map[b as usize]])
            .collect();
        Snapshot {
            positions,
            edges,
            signals: self.signals,
            target: self.params.target_vertices,
            finished: self.is_finished(),
        }
    }

    /// Phase 2 on the current network.
    pub fn reconstruct(&self, params: &ReconstructionParams) -> Reconstruction {
        let snap = self.snapshot();
        reconstruct(&self.original, &snap.positions, &snap.edges, params)
    }

    /// The inner loop: `count` signals with nearest search through the grid (`GRID`) or a scan.
    fn run_signals<const GRID: bool>(&mut self, count: u64) {
        let eps_b = self.params.eps_winner;
        let eps_n = self.params.eps_neighbour;
        let max_age = self.params.max_edge_age;
        for _ in 0..count {
            let x = self.signals_src.draw(&mut self.rng);
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
                net.pull(s1, x, eps_b);
                let d = net.degree[i1] as usize;
                for k in 0..d {
                    let nb = net.adj[i1].nb[k];
                    net.pull(nb, x, eps_n);
                }
                if nn.second != NONE {
                    net.connect(s1, nn.second);
                }
                net.drop_old_edges(s1, max_age);
                net.decay(self.inv_decay);
            }
            self.signals += 1;
            if GRID && self.signals >= self.next_renumber {
                self.net.renumber_by_cell();
                self.next_renumber = self.signals + RENUMBER_EVERY_EPOCHS * self.net.live as u64;
            }
            if self.signals >= self.next_insert {
                self.next_insert = self.signals + self.lambda;
                if self.net.live < self.params.target_vertices {
                    self.insert(x);
                }
            }
            if self.params.removal_window > 0.0 && self.signals < self.budget {
                let window = (self.params.removal_window * self.net.live as f64) as u64;
                if self.signals - self.window_start >= window.max(1) {
                    self.remove_inactive();
                }
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
    fn insert(&mut self, x: Vec3) {
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
        let alpha = self.params.alpha;
        net.err[q as usize] *= alpha;
        net.err[f as usize] *= alpha;
        let mid = (net.pos[q as usize] + net.pos[f as usize]) * 0.5;
        let r = net.add_node(mid, net.err[q as usize], self.signals);
        net.disconnect(q, f);
        net.connect(q, r);
        net.connect(r, f);
        self.insertions += 1;
        if let Some(g) = &mut net.grid
            && net.live > GRID_REBUILD_GROWTH * self.grid_built_for
        {
            let cells = grid_cells(self.area, g.volume(), net.live);
            self.grid_built_for = net.live;
            let nodes: Vec<(u32, Vec3)> = net
                .alive
                .iter()
                .enumerate()
                .filter(|(_, a)| **a)
                .map(|(i, _)| (i as u32, net.pos[i]))
                .collect();
            g.rebuild(cells, nodes.into_iter());
            debug_assert_eq!(g.len(), net.live);
            net.renumber_by_cell();
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

fn check_param(name: &'static str, value: f64, lo: f64, hi: f64) -> Result<(), GngError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(GngError::Parameter { name, value })
    }
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

    #[test]
    fn alias_table_reproduces_the_weights() {
        let w = [1.0, 3.0, 0.5, 0.0, 5.5];
        let (keep, alias) = alias_table(&w);
        // Exact probability of each index: sum over slots of (keep or 1 - keep) / n.
        let n = w.len() as f64;
        let mut p = [0.0f64; 5];
        for i in 0..w.len() {
            p[i] += keep[i] / n;
            p[alias[i] as usize] += (1.0 - keep[i]) / n;
        }
        let total: f64 = w.iter().sum();
        for i in 0..w.len() {
            assert!(
                (p[i] - w[i] / total).abs() < 1e-12,
                "{i}: {} vs {}",
                p[i],
                w[i] / total
            );
        }
    }
}

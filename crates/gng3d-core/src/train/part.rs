//! One network trained on one connected piece of the input ([`Part`]), in that piece's local
//! frame: its signals, its grid and the inner loop of the training (winner search, GNG update,
//! insertion every λ, removal of nodes that won nothing in the μ window).
//!
//! (The hot path of the training: a part's loop settings and counters stay together here.)

use super::grid::{Grid, NONE, Nearest2};
use super::network::Network;
use super::stats::CancelToken;
use crate::domain::{Frame, Piece};
use crate::error::GngError;
use crate::params::{SearchStrategy, SignalSource};
use glam::Vec3;
use mesh::sampling::AreaSampler;
use rand::Rng;
use rand_pcg::Pcg64Mcg;
use std::time::Instant;

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
pub(super) const CHECK_EVERY: u64 = 1024;
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
pub(super) struct LoopSettings {
    pub(super) eps_b: f32,
    pub(super) eps_n: f32,
    pub(super) max_age: u32,
    pub(super) inv_decay: f64,
    pub(super) alpha: f64,
    pub(super) removal_window: f64,
    pub(super) lambda: u64,
}

/// One network trained on one connected piece of the input, in that piece's local frame.
#[derive(Debug, Clone)]
pub(super) struct Part {
    pub(super) frame: Frame,
    signals_src: Signals,
    /// Box of the piece's non-stray points (local), for the grid.
    pub(super) bbox: mesh::Aabb,
    /// Surface area of the piece (local units squared), for the grid resolution.
    pub(super) area: f64,
    /// Node count at the last grid rebuild.
    pub(super) grid_built_for: usize,
    pub(super) net: Network,
    pub(super) target: usize,
    pub(super) budget: u64,
    pub(super) signals: u64,
    pub(super) next_insert: u64,
    pub(super) next_renumber: u64,
    pub(super) window_start: u64,
    pub(super) insertions: u64,
    pub(super) removed_inactive: u64,
    /// Budget used and target held.
    pub(super) done: bool,
    /// Twice the budget used without reaching the target.
    pub(super) capped: bool,
    /// This part's own random stream (signals and the two seed nodes), so that parts can
    /// train on separate threads with the same result as on one.
    pub(super) rng: Pcg64Mcg,
    /// Connected component of the input the part trains (the two halves of a split piece
    /// share one).
    pub(super) component: usize,
}

impl Part {
    pub(super) fn new(
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
                let weights = super::features::curvature_face_weights(&piece.surface, piece.target);
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
    pub(super) fn update_state(&mut self) {
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
    pub(super) fn to_boundary(&self) -> u64 {
        if self.signals < self.budget {
            (self.budget - self.signals).min(CHECK_EVERY - self.signals % CHECK_EVERY)
        } else {
            CHECK_EVERY - self.signals % CHECK_EVERY
        }
    }

    /// Process up to `quota` signals in chunks that end on the canonical boundaries
    /// ([`Part::to_boundary`]), where `done` is updated; stop early when done, cancelled or
    /// past `deadline`. Returns the signals processed.
    pub(super) fn advance(
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
    pub(super) fn rebuild_grid(&mut self) {
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
    pub(super) fn run_signals<const GRID: bool>(&mut self, count: u64, s: LoopSettings) {
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
    pub(super) fn present<const GRID: bool>(&mut self, x: Vec3, s: LoopSettings) {
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
    pub(super) fn linear_nearest2(&self, x: Vec3) -> Nearest2 {
        let mut best = Nearest2::EMPTY;
        for (i, (p, &a)) in self.net.pos.iter().zip(&self.net.alive).enumerate() {
            if a {
                best.offer(i as u32, (*p - x).length_squared());
            }
        }
        best
    }

    /// Fritzke insertion between the max-error node q and its max-error neighbour f.
    pub(super) fn insert(&mut self, x: Vec3, alpha: f64) {
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
    pub(super) fn remove_inactive(&mut self) {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    pub(super) fn grid_cells_follow_the_surface_spacing_and_clamp() {
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
}

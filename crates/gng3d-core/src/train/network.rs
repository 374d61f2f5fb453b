//! The Growing Neural Gas graph: struct-of-arrays node store with a free list, small inline
//! adjacency arrays, edge ages derived from win counters and lazily decayed errors.
//!
//! Edge ages: an edge only ages when one of its endpoints wins, so its age equals
//! `wins[a] + wins[b] - stamp`, where `stamp` is that sum when the edge was created or last
//! refreshed. Ageing every edge of the winner is then just `wins[s1] += 1`.
//!
//! Errors: every error decays by the factor d after each signal. Instead of touching every
//! node, the store keeps `E / d^t` and a running `1 / d^t`, renormalised before it overflows.

use super::grid::{Grid, NONE};
use glam::Vec3;

/// Maximum number of neighbours kept inline per node; adding an edge to a full node evicts its
/// oldest edge.
pub(crate) const MAX_DEGREE: usize = 16;

/// Slots per block of the max-error index (`Network::block_max`).
const ERROR_BLOCK: usize = 64;

/// Renormalise scaled errors once the inverse decay scale passes this value.
const RENORMALISE_AT: f64 = 1e200;

/// Inline adjacency of one node: neighbour slots and the age stamps of the edges to them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Adjacency {
    /// Neighbour slots; only the first `degree` entries are valid.
    pub nb: [u32; MAX_DEGREE],
    /// Age stamp of the edge to `nb[i]` (see module docs).
    pub stamp: [u32; MAX_DEGREE],
}

impl Adjacency {
    const EMPTY: Adjacency = Adjacency {
        nb: [NONE; MAX_DEGREE],
        stamp: [0; MAX_DEGREE],
    };
}

/// Node store of the network.
#[derive(Debug, Clone)]
pub(crate) struct Network {
    /// Position of each slot.
    pub pos: Vec<Vec3>,
    /// Scaled local error `E / d^t` (f64); negative infinity for free slots.
    pub err: Vec<f64>,
    /// Per block of [`ERROR_BLOCK`] slots, an upper bound of its errors, exact for the block
    /// that [`Network::max_error_node`] returns: errors only grow at the winner (which raises
    /// its block's bound), shrink at insertions and removals (which leave the bound stale-high
    /// until a query corrects it) and are rescaled all together (which rebuilds the bounds).
    /// The query then scans |A|/64 bounds and a few blocks instead of all |A| errors: with a
    /// time limit λ gets small and the full scan was ~30 % of training (igea, 20,000 nodes).
    block_max: Vec<f64>,
    /// Number of signals each slot has won (wrapping), used for edge ages.
    pub wins: Vec<u32>,
    /// Signal index at which each slot last won (or was created).
    pub last_win: Vec<u64>,
    /// Number of neighbours of each slot.
    pub degree: Vec<u8>,
    /// Inline adjacency of each slot.
    pub adj: Vec<Adjacency>,
    /// Whether each slot holds a live node.
    pub alive: Vec<bool>,
    /// Free slots, reused last-in first-out.
    free: Vec<u32>,
    /// Number of live nodes.
    pub live: usize,
    /// Number of edges.
    pub edges: usize,
    /// `1 / d^t`: multiply a true error by this to get the stored value.
    pub inv_scale: f64,
    /// Spatial index of live nodes (`None` for the linear-scan strategy).
    pub grid: Option<Grid>,
    /// Nodes removed because they lost their last edge.
    pub removed_isolated: u64,
    /// Scratch stack for cascading removals (kept to avoid allocation).
    stack: Vec<u32>,
}

impl Network {
    /// An empty network, optionally indexed by `grid`.
    pub fn new(grid: Option<Grid>, capacity: usize) -> Network {
        Network {
            pos: Vec::with_capacity(capacity),
            err: Vec::with_capacity(capacity),
            block_max: Vec::new(),
            wins: Vec::with_capacity(capacity),
            last_win: Vec::with_capacity(capacity),
            degree: Vec::with_capacity(capacity),
            adj: Vec::with_capacity(capacity),
            alive: Vec::with_capacity(capacity),
            free: Vec::new(),
            live: 0,
            edges: 0,
            inv_scale: 1.0,
            grid,
            removed_isolated: 0,
            stack: Vec::new(),
        }
    }

    /// Add a node at `p` with true error `error`, created at signal `now`; returns its slot.
    pub fn add_node(&mut self, p: Vec3, scaled_error: f64, now: u64) -> u32 {
        let slot = if let Some(s) = self.free.pop() {
            let i = s as usize;
            self.pos[i] = p;
            self.err[i] = scaled_error;
            self.note_error(i);
            self.wins[i] = 0;
            self.last_win[i] = now;
            self.degree[i] = 0;
            self.alive[i] = true;
            s
        } else {
            self.pos.push(p);
            self.err.push(scaled_error);
            self.note_error(self.err.len() - 1);
            self.wins.push(0);
            self.last_win.push(now);
            self.degree.push(0);
            self.adj.push(Adjacency::EMPTY);
            self.alive.push(true);
            (self.pos.len() - 1) as u32
        };
        self.live += 1;
        if let Some(g) = &mut self.grid {
            g.insert(slot, p);
        }
        slot
    }

    /// Age of the edge stored at entry `i` of node `a`.
    #[inline(always)]
    pub fn age(&self, a: u32, i: usize) -> u32 {
        let adj = &self.adj[a as usize];
        let b = adj.nb[i];
        self.wins[a as usize]
            .wrapping_add(self.wins[b as usize])
            .wrapping_sub(adj.stamp[i])
    }

    /// Entry index of neighbour `b` in `a`'s list.
    #[inline(always)]
    pub fn find(&self, a: u32, b: u32) -> Option<usize> {
        let d = self.degree[a as usize] as usize;
        self.adj[a as usize].nb[..d].iter().position(|&x| x == b)
    }

    /// Stamp that gives the edge a-b age zero now.
    #[inline(always)]
    fn fresh_stamp(&self, a: u32, b: u32) -> u32 {
        self.wins[a as usize].wrapping_add(self.wins[b as usize])
    }

    /// Create edge a-b with age 0, or reset its age when it exists.
    #[inline]
    pub fn connect(&mut self, a: u32, b: u32) {
        let stamp = self.fresh_stamp(a, b);
        if let Some(i) = self.find(a, b) {
            self.adj[a as usize].stamp[i] = stamp;
            if let Some(j) = self.find(b, a) {
                self.adj[b as usize].stamp[j] = stamp;
            }
            return;
        }
        for n in [a, b] {
            if self.degree[n as usize] as usize == MAX_DEGREE {
                self.evict_oldest(n, a, b);
            }
        }
        self.push_entry(a, b, stamp);
        self.push_entry(b, a, stamp);
        self.edges += 1;
    }

    #[inline(always)]
    fn push_entry(&mut self, a: u32, b: u32, stamp: u32) {
        let d = self.degree[a as usize] as usize;
        let adj = &mut self.adj[a as usize];
        adj.nb[d] = b;
        adj.stamp[d] = stamp;
        self.degree[a as usize] += 1;
    }

    /// Drop the oldest edge of the full node `n`; a neighbour left isolated is removed unless it
    /// is one of `keep_a`, `keep_b`.
    fn evict_oldest(&mut self, n: u32, keep_a: u32, keep_b: u32) {
        let d = self.degree[n as usize] as usize;
        let oldest = (0..d).max_by_key(|&i| self.age(n, i)).unwrap_or(0);
        let other = self.adj[n as usize].nb[oldest];
        self.remove_entry(n, oldest);
        if let Some(j) = self.find(other, n) {
            self.remove_entry(other, j);
        }
        self.edges -= 1;
        if self.degree[other as usize] == 0 && other != keep_a && other != keep_b {
            self.removed_isolated += 1;
            self.remove_node(other);
        }
    }

    /// Swap-remove entry `i` of `a`'s adjacency.
    #[inline(always)]
    fn remove_entry(&mut self, a: u32, i: usize) {
        let last = self.degree[a as usize] as usize - 1;
        let adj = &mut self.adj[a as usize];
        adj.nb[i] = adj.nb[last];
        adj.stamp[i] = adj.stamp[last];
        self.degree[a as usize] -= 1;
    }

    /// Remove the edges of `a` older than `max_age`; neighbours left isolated are removed.
    #[inline]
    pub fn drop_old_edges(&mut self, a: u32, max_age: u32) {
        let mut i = 0;
        while i < self.degree[a as usize] as usize {
            if self.age(a, i) > max_age {
                let b = self.adj[a as usize].nb[i];
                self.remove_entry(a, i);
                if let Some(j) = self.find(b, a) {
                    self.remove_entry(b, j);
                }
                self.edges -= 1;
                if self.degree[b as usize] == 0 {
                    self.removed_isolated += 1;
                    self.remove_node(b);
                }
            } else {
                i += 1;
            }
        }
    }

    /// Remove edge a-b when present.
    pub fn disconnect(&mut self, a: u32, b: u32) {
        if let Some(i) = self.find(a, b) {
            self.remove_entry(a, i);
            if let Some(j) = self.find(b, a) {
                self.remove_entry(b, j);
            }
            self.edges -= 1;
        }
    }

    /// Remove node `n` and its edges; neighbours left isolated are removed too (cascading).
    pub fn remove_node(&mut self, n: u32) {
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        stack.push(n);
        let mut first = true;
        while let Some(v) = stack.pop() {
            if !self.alive[v as usize] {
                continue;
            }
            if !first {
                self.removed_isolated += 1;
            }
            first = false;
            let d = self.degree[v as usize] as usize;
            for i in 0..d {
                let b = self.adj[v as usize].nb[i];
                if let Some(j) = self.find(b, v) {
                    self.remove_entry(b, j);
                }
                self.edges -= 1;
                if self.degree[b as usize] == 0 {
                    stack.push(b);
                }
            }
            self.degree[v as usize] = 0;
            self.alive[v as usize] = false;
            self.err[v as usize] = f64::NEG_INFINITY;
            self.live -= 1;
            self.free.push(v);
            if let Some(g) = &mut self.grid {
                g.remove(v);
            }
        }
        self.stack = stack;
    }

    /// Move `n` by `rate` toward `x`, keeping the grid current.
    #[inline(always)]
    pub fn pull(&mut self, n: u32, x: Vec3, rate: f32) {
        let p = &mut self.pos[n as usize];
        *p += (x - *p) * rate;
        let p = *p;
        if let Some(g) = &mut self.grid {
            g.moved(n, p);
        }
    }

    /// Advance the lazy decay by one signal (`inv_decay` = 1/d).
    #[inline(always)]
    pub fn decay(&mut self, inv_decay: f64) {
        self.inv_scale *= inv_decay;
        if self.inv_scale > RENORMALISE_AT {
            let s = 1.0 / self.inv_scale;
            for (e, &a) in self.err.iter_mut().zip(&self.alive) {
                if a {
                    *e *= s;
                }
            }
            self.inv_scale = 1.0;
            self.rebuild_block_max();
        }
    }

    /// Record that the error of slot `i` may have grown (keeps [`Network::block_max`] an upper
    /// bound).
    #[inline(always)]
    pub fn note_error(&mut self, i: usize) {
        let b = i / ERROR_BLOCK;
        if b >= self.block_max.len() {
            self.block_max.resize(b + 1, f64::NEG_INFINITY);
        }
        if self.err[i] > self.block_max[b] {
            self.block_max[b] = self.err[i];
        }
    }

    /// Exact bounds from the errors (after a rescale or a renumbering).
    fn rebuild_block_max(&mut self) {
        self.block_max.clear();
        self.block_max.extend(self.err.chunks(ERROR_BLOCK).map(|c| {
            c.iter()
                .fold(f64::NEG_INFINITY, |m, &e| if e > m { e } else { m })
        }));
    }

    /// Live slot with the largest error (free slots hold negative infinity); on ties the
    /// lowest slot, as a full scan would give.
    pub fn max_error_node(&mut self) -> Option<u32> {
        loop {
            // The lowest block with the largest bound.
            let mut best = f64::NEG_INFINITY;
            let mut block = usize::MAX;
            for (b, &m) in self.block_max.iter().enumerate() {
                if m > best {
                    best = m;
                    block = b;
                }
            }
            if block == usize::MAX {
                return None;
            }
            let start = block * ERROR_BLOCK;
            let end = (start + ERROR_BLOCK).min(self.err.len());
            let errors = &self.err[start..end];
            let exact = errors
                .iter()
                .fold(f64::NEG_INFINITY, |m, &e| if e > m { e } else { m });
            if exact == best {
                // Lower blocks have bounds below `best`, so the first slot with it is global.
                return errors
                    .iter()
                    .position(|&e| e == best)
                    .map(|i| (start + i) as u32);
            }
            // A stale bound: correct it and look again.
            self.block_max[block] = exact;
        }
    }

    /// Renumber live nodes in grid-cell order so nodes near each other in space are near each
    /// other in memory (fewer cache misses in the search); frees all dead slots. No-op without
    /// a grid.
    pub fn renumber_by_cell(&mut self) {
        let Some(grid) = &self.grid else {
            return;
        };
        let mut order: Vec<(u32, u32)> = self.live_slots().map(|s| (grid.cell_of(s), s)).collect();
        order.sort_unstable();
        let mut new_of = vec![NONE; self.pos.len()];
        for (i, &(_, s)) in order.iter().enumerate() {
            new_of[s as usize] = i as u32;
        }
        let n = order.len();
        let mut pos = Vec::with_capacity(self.pos.capacity());
        let mut err = Vec::with_capacity(self.err.capacity());
        let mut wins = Vec::with_capacity(self.wins.capacity());
        let mut last_win = Vec::with_capacity(self.last_win.capacity());
        let mut degree = Vec::with_capacity(self.degree.capacity());
        let mut adj = Vec::with_capacity(self.adj.capacity());
        for &(_, s) in &order {
            let s = s as usize;
            pos.push(self.pos[s]);
            err.push(self.err[s]);
            wins.push(self.wins[s]);
            last_win.push(self.last_win[s]);
            degree.push(self.degree[s]);
            let mut a = self.adj[s];
            for nb in &mut a.nb[..self.degree[s] as usize] {
                *nb = new_of[*nb as usize];
            }
            adj.push(a);
        }
        self.pos = pos;
        self.err = err;
        self.wins = wins;
        self.last_win = last_win;
        self.degree = degree;
        self.adj = adj;
        self.alive = vec![true; n];
        self.free.clear();
        self.rebuild_block_max();
        if let Some(g) = &mut self.grid {
            g.clear(n);
            for i in 0..n {
                g.insert(i as u32, self.pos[i]);
            }
        }
    }

    /// Live slots.
    pub fn live_slots(&self) -> impl Iterator<Item = u32> + '_ {
        self.alive
            .iter()
            .enumerate()
            .filter(|(_, a)| **a)
            .map(|(i, _)| i as u32)
    }

    /// Edges as (a, b) slot pairs with a < b.
    pub fn edge_pairs(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.live_slots().flat_map(move |a| {
            let d = self.degree[a as usize] as usize;
            self.adj[a as usize].nb[..d]
                .iter()
                .filter(move |&&b| a < b)
                .map(move |&b| (a, b))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block bounds give the same slot as a plain scan (largest error, lowest slot on
    /// ties) through growth, error increases, α shrinks, removals, slot reuse, rescales and
    /// renumbering.
    #[test]
    fn max_error_node_matches_a_full_scan() {
        let scan = |net: &Network| {
            let m = net.err.iter().fold(f64::NEG_INFINITY, |m, &e| m.max(e));
            (m > f64::NEG_INFINITY)
                .then(|| net.err.iter().position(|&e| e == m).unwrap_or(0) as u32)
        };
        let grid = Grid::new(Vec3::ZERO, Vec3::ONE, 64);
        let mut net = Network::new(Some(grid), 16);
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as usize
        };
        for step in 0..5_000 {
            match next() % 7 {
                0 | 1 => {
                    let p = Vec3::new(0.3, 0.5, 0.7) * ((step % 97) as f32 / 97.0);
                    // Integer errors make exact ties common.
                    net.add_node(p, (next() % 50) as f64, step);
                }
                2 | 3 if net.live > 0 => {
                    let s = net.live_slots().nth(next() % net.live).unwrap_or(0) as usize;
                    net.err[s] += (next() % 20) as f64;
                    net.note_error(s);
                }
                4 if net.live > 0 => {
                    let s = net.live_slots().nth(next() % net.live).unwrap_or(0) as usize;
                    net.err[s] *= 0.5;
                }
                5 if net.live > 2 => {
                    let s = net.live_slots().nth(next() % net.live).unwrap_or(0);
                    net.remove_node(s);
                }
                6 if step % 50 == 0 => net.renumber_by_cell(),
                6 if step % 31 == 0 => {
                    net.inv_scale = RENORMALISE_AT * 2.0;
                    net.decay(1.0);
                }
                _ => {}
            }
            let want = scan(&net);
            assert_eq!(net.max_error_node(), want, "step {step}");
        }
        assert!(
            net.live > 100,
            "the test grew a real network ({} nodes)",
            net.live
        );
    }
}

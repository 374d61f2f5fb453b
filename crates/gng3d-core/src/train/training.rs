//! The training loop over all parts ([`Training`]): rounds of signals shared out by budget
//! ([`round_quotas`]), the time-limit schedule of λ (against the run's [`Clock`]), the
//! counters, and the copy of the network ([`Snapshot`]).

use super::grid::{Grid, NONE};
use super::part::{CHECK_EVERY, LoopSettings, Part};
use super::stats::{CancelToken, Progress, Snapshot, StopReason, TrainingStats};
use crate::clock::Clock;
use crate::domain::Piece;
use crate::error::GngError;
use crate::params::{DEFAULT_SIGNALS_PER_NODE, GngParams, SearchStrategy};
use crate::report::GngWarning;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::time::{Duration, Instant};

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

/// The networks of a run and their counters: every trained piece's [`Part`], advanced in
/// rounds side by side on threads, each with its own random stream, so that the result does
/// not depend on the thread count or on how `step` calls divide the signals.
#[derive(Debug, Clone)]
pub(crate) struct Training {
    pub(crate) params: GngParams,
    parts: Vec<Part>,
    /// Nodes all parts together aim for.
    pub(crate) held_target: usize,
    /// λ in use; the time-limit schedule only ever lowers it.
    lambda: u64,
    budget: u64,
    inv_decay: f64,
    pub(crate) signals: u64,
    pub(crate) elapsed: Duration,
    growth_elapsed: Option<Duration>,
    /// Highest signals/s seen over one chunk (for the time-limit schedule).
    peak_rate: f64,
    pub(crate) stop: Option<StopReason>,
    pub(crate) cancel: CancelToken,
    /// Threads a round may use ([`crate::parallel::threads`] of [`GngParams::threads`]).
    pub(crate) threads: usize,
}

impl Training {
    /// Two nodes at random vertices of every piece of `domain`, the budget and λ of `params`;
    /// rounds on up to `threads` threads.
    pub(crate) fn new(
        params: GngParams,
        pieces: Vec<Piece>,
        distinct: usize,
        threads: usize,
    ) -> Result<Training, GngError> {
        let n = params.network_target();
        let budget = signal_budget(&params, distinct);
        let lambda = params
            .lambda
            .map(u64::from)
            .unwrap_or_else(|| (budget / (2 * n as u64)).clamp(1, MAX_AUTO_LAMBDA));
        let held_target: usize = pieces.iter().map(|p| p.target).sum();
        let mut parts = Vec::with_capacity(pieces.len());
        for (k, piece) in pieces.into_iter().enumerate() {
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
        Ok(Training {
            inv_decay: 1.0 / params.error_decay,
            params,
            parts,
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

    /// Whether training has ended (budget used with the target reached, time limit, cancel).
    pub(crate) fn is_finished(&self) -> bool {
        self.stop.is_some()
    }

    /// Current node count (all components).
    pub(crate) fn node_count(&self) -> usize {
        self.parts.iter().map(|p| p.net.live).sum()
    }

    /// Current edge count.
    pub(crate) fn edge_count(&self) -> usize {
        self.parts.iter().map(|p| p.net.edges).sum()
    }

    /// What keeps the network from the target so far: the time limit, when it stopped the
    /// growth short of the nodes the parts aim for.
    pub(crate) fn warnings(&self) -> Vec<GngWarning> {
        let mut w = Vec::new();
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
    pub(crate) fn stats(&self) -> TrainingStats {
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
    pub(crate) fn set_search_strategy(&mut self, search: SearchStrategy) {
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
    fn schedule_growth(&mut self, now: Duration, clock: &Clock) {
        let Some(limit) = clock.training_limit else {
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
        let wall = clock.started.elapsed().as_secs_f64();
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
    pub(crate) fn step(&mut self, n: u64, clock: &Clock) -> u64 {
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
            let now = clock.started.elapsed();
            let past_limit = clock.training_limit.is_some_and(|limit| now >= limit);
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
            self.schedule_growth(self.elapsed + start.elapsed(), clock);
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
            let deadline = clock
                .training_limit
                .filter(|_| !past_limit)
                .map(|limit| clock.started + limit);
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
            if clock.training_limit.is_some() && processed >= CHECK_EVERY / 2 {
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

    /// Current progress. Vertex errors of the nodes: `metrics::vertex_errors` on
    /// [`Trainer::snapshot`] positions.
    pub(crate) fn progress(&self) -> Progress {
        Progress {
            signals: self.signals,
            nodes: self.node_count(),
            edges: self.edge_count(),
            elapsed: self.elapsed,
        }
    }

    /// Copy of the network (all components, world coordinates) with compact indices.
    pub(crate) fn snapshot(&self) -> Snapshot {
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
    use crate::domain::{Domain, Pieces};
    use mesh::TriMesh;

    /// The training of `mesh` for `target` nodes with `split_training`, on `threads` threads.
    fn trainer(mesh: &TriMesh, target: usize, split: bool, threads: usize) -> Training {
        let mut params = GngParams::for_target(target);
        params.split_training = split;
        let domain = Domain::build(mesh, &Pieces::of(mesh), &params).expect("domain");
        Training::new(params, domain.pieces, domain.distinct, threads).expect("trainer")
    }

    /// The clock of a run without a time limit.
    fn clock() -> Clock {
        Clock {
            started: Instant::now(),
            training_limit: None,
        }
    }

    #[test]
    fn halves_train_the_same_on_one_thread_and_two_in_any_step_sizes() {
        let sphere = mesh::procedural::icosphere(5);
        let clock = clock();
        let mut one = trainer(&sphere, 800, true, 1);
        assert_eq!(one.parts.len(), 2, "a 800-node sphere trains as two halves");
        assert_eq!(one.stats().components, 1);
        assert_eq!(one.parts.iter().map(|p| p.target).sum::<usize>(), 800);
        while !one.is_finished() {
            one.step(u64::MAX, &clock);
        }
        let mut two = trainer(&sphere, 800, true, 2);
        let mut calls = 0;
        while !two.is_finished() {
            // Odd step sizes: rounds end anywhere inside the parts' chunks.
            two.step(777 + 1000 * (calls % 3), &clock);
            calls += 1;
        }
        assert!(calls > 10);
        let (a, b) = (one.snapshot(), two.snapshot());
        assert_eq!(a.positions.len(), 800);
        assert_eq!(a.positions, b.positions);
        assert_eq!(a.edges, b.edges);
        assert_eq!(one.signals, two.signals);
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
        let clock = clock();
        let mut even = trainer(&sphere, 800, true, 2);
        let mut odd = trainer(&sphere, 800, true, 2);
        let mut checked = 0;
        while !even.is_finished() {
            even.step(10_000, &clock);
            odd.step(3_331, &clock);
            odd.step(6_669, &clock);
            assert_eq!(even.signals, odd.signals);
            let (a, b) = (even.snapshot(), odd.snapshot());
            assert_eq!(a.positions, b.positions, "after {} signals", even.signals);
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
        let split = trainer(&sphere, crate::tuning::SPLIT_MIN_NODES - 1, true, 2);
        assert_eq!(split.parts.len(), 1);
        // And without the option a large one is one part as well.
        assert_eq!(trainer(&sphere, 1000, false, 2).parts.len(), 1);
    }
}

//! The passes over one prepared mesh (passes 2–6 of the parent module's list): the vertex set-up,
//! the virtual pairs, the initial costing and sort, the contraction loop over the sorted
//! candidate list ([`Schedule`]: one pass's walk in cost order, the rebuild after a stall, the
//! next pass's list) and the output. [`super::partition`] runs them on each part of a
//! partitioned run.

use super::candidates::{Cand, GENERATIONS, is_live, key_cost, merge_live, sort_key};
use super::checks::check_cancel;
use super::engine::Engine;
use super::outcome::Run;
use super::prefetch::{self, prefetch_ptr};
use super::resources::release_freed_memory;
use super::seams::Seams;
use super::{attribute_error, prepare, setup, wedges};
use crate::radix::{sort_by_u32_key, sort_by_u32_key_in_parts};
use crate::{QemError, QemParams, StopReason, Target, pairs};
use mesh::TriMesh;
use mesh::cancel::Cancel;

/// Parts of the candidate list's whole-list sorts ([`sort_by_u32_key_in_parts`]): the sort's
/// scratch is the list's length over this.
const WHOLE_SORT_PARTS: usize = 2;
/// Lists shorter than this (6 MiB of candidates, ~350k faces) are sorted whole: the merge of the
/// parts cost +8 M instructions (2.5 %) on armadillo at 10 % in callgrind (a first version of the
/// merge), and the sort is not where the peak of a small mesh is.
const SORT_IN_PARTS_MIN: usize = 1 << 19;
/// The candidate list gives back its spare capacity after a merge (when it is more than an
/// eighth of the list) only when its capacity is at least this large (~700k candidates, ~470k
/// faces): for smaller meshes the passes are not at a peak that matters.
const RELEASE_MIN_BYTES: usize = 8 << 20;
/// Capacity given back by the candidate list between two trims of the freed memory, after the
/// first (igea-1m at 10 %, two threads: trimming after every merge cost ~2 % CPU for no lower
/// peak; one thread: 170.6 MiB either way, 175.9 without the first trim).
const TRIM_MIN_BYTES: usize = 8 << 20;

/// A pair whose kept end has a face list longer than this is *heavy*: its check
/// ([`Engine::allowed`]) walks the whole list, and a hub's candidates come back after every
/// contraction around it. Ordinary meshes have lists of 6-20 entries; a fan-triangulated cap
/// has one vertex with as many faces as the cap has segments.
const HEAVY_LIST: u32 = 256;
/// Checks of heavy pairs per kept end and pass, after which that vertex's further heavy pairs
/// are dropped for the pass, as a rejected pair is (they come back when a contraction touches an
/// end, or in a rebuild). Without a bound a flat fan of N triangles spent O(N) per rejected hub
/// pair on about N rejections (issue 33: 131,072 triangles 84 s at 10 %, 200,000 past 300 s);
/// with it a pass spends at most `HEAVY_TRIES ×` the list on a hub. The pass after a rebuild has
/// no bound, so that [`StopReason::NoValidPairs`] still means that every pair failed its check.
const HEAVY_TRIES: u32 = 4;
/// A pass looks at [`QemParams::cancel`] after every this many contractions (about a
/// millisecond of igea's passes), besides once before each pass.
const CANCEL_EVERY: usize = 4096;

/// Passes 2–6 over a prepared mesh; vertices flagged in `locked` are never contracted. Also
/// returns, for each output vertex, its index in `prepared`. The only error is
/// [`QemError::Cancelled`].
pub(super) fn simplify_prepared(
    prepared: prepare::Prepared,
    params: &QemParams,
    locked: Option<&[bool]>,
) -> Result<(Run, Vec<u32>), QemError> {
    simplify_prepared_with(prepared, params, locked, None, |e, frame| e.output(frame))
}

/// What an attribute run adds to the passes (prepared numbering): the seams, whose `edges` get
/// constraint planes and whose vertices are contracted only along them ([`Seams`]), the
/// attribute error added to the cost (`None`: all weights 0), and the values carried through the
/// contractions ([`wedges`]).
pub(super) struct AttributeRun {
    pub(super) seams: Seams,
    pub(super) edges: Vec<[u32; 2]>,
    pub(super) attr: Option<attribute_error::AttributeError>,
    pub(super) values: wedges::WedgeValues,
}

/// [`simplify_prepared`] with an attribute run's additions, the result made by `output` from the
/// engine after the passes (which holds the attribute run's values and seams, when there is one).
/// The only error is [`QemError::Cancelled`] ([`QemParams::cancel`], looked at between the
/// steps, before each pass and every [`CANCEL_EVERY`] contractions of a pass).
pub(super) fn simplify_prepared_with<T>(
    prepared: prepare::Prepared,
    params: &QemParams,
    locked: Option<&[bool]>,
    attribute_run: Option<AttributeRun>,
    output: impl FnOnce(&Engine, &prepare::Frame) -> (TriMesh, T),
) -> Result<(Run, T), QemError> {
    let prepare::Prepared {
        pos,
        faces,
        refs,
        face_start,
        frame,
    } = prepared;
    let input_faces = faces.len();
    // An attribute run's seams drop the pairs they forbid as the set-up lists them (a pass over
    // the whole list afterwards was about 1 ms on a 268k-face atlas).
    let seams = attribute_run.as_ref().map(|run| &run.seams);
    check_cancel(params)?;
    let setup::VertexSetup { mut vx, list } =
        setup::vertex_setup(&pos, &faces, &refs, &face_start, params, locked, seams);
    if let Some(run) = &attribute_run {
        let edges = &run.edges;
        setup::seam_planes(&mut vx, &pos, &faces, &refs, &face_start, edges, params);
    }
    let area = params
        .max_relative_error
        .map(|_| vertex_areas(&pos, &faces));
    drop((pos, face_start));
    check_cancel(params)?;
    let mut e = Engine::new(vx, faces, refs, params);
    e.area = area;
    let mut schedule = Schedule::new(list);
    let virtual_pairs = add_virtual_pairs(&mut e, &mut schedule.list, params, frame.scale);
    if let Some(run) = attribute_run {
        let seams = run.seams;
        if virtual_pairs > 0 {
            schedule
                .list
                .retain(|c| seams.pair_ok(c.a as usize, c.b as usize));
        }
        e.seams = Some(seams);
        e.attr = run.attr;
        e.values = Some(run.values);
    }
    e.cost_all(&mut schedule.list);
    check_cancel(params)?;
    schedule.sort();

    let goal = Goal::new(params.target, input_faces);
    let scale4 = frame.scale.powi(4);
    let max_error = params.max_error.map_or(f64::INFINITY, |m| m * scale4);
    // Compared with cost / area in the normalised frame (unit diagonal): squared distances.
    let max_relative2 = params.max_relative_error.map_or(f64::INFINITY, |m| m * m);
    let mut totals = PassOutcome::default();
    let mut pass = 0u32;
    // Pass numbers where the candidates' generations (`candidates::is_live`) restarted from 0.
    let mut generation_base = 0u32;
    let mut rebuilt_without_progress = false;
    let stop_reason = loop {
        if goal.reached(&e) {
            break StopReason::TargetReached;
        }
        if schedule.list.is_empty() {
            break StopReason::NoValidPairs;
        }
        check_cancel(params)?;
        pass += 1;
        if pass - generation_base >= GENERATIONS {
            // The candidates' generation field is full: number afresh from 0 and re-cost every
            // current pair (never reached on the shared meshes: 8-14 passes at 10 % and 1 %).
            generation_base = pass;
            e.contracted.fill(0);
            e.generation = 0;
            schedule.rebuild(&mut e, pass);
            pass += 1;
        }
        e.generation = pass - generation_base;
        let cap = schedule.cost_cap(&e, goal.contractions_needed(&e));
        let rule = PassRule {
            pass,
            cap,
            max_error,
            max_relative2,
            goal: &goal,
            heavy_tries: if rebuilt_without_progress {
                u32::MAX
            } else {
                HEAVY_TRIES
            },
            cancel: params.cancel.as_ref(),
        };
        let outcome = schedule.one_pass(&mut e, &rule);
        if outcome.cancelled {
            return Err(QemError::Cancelled);
        }
        totals.done += outcome.done;
        totals.rejected += outcome.rejected;
        totals.worst = totals.worst.max(outcome.worst);
        totals.worst_relative2 = totals.worst_relative2.max(outcome.worst_relative2);
        if let Some(reason) = outcome.stop {
            break reason;
        }
        if goal.reached(&e) {
            break StopReason::TargetReached;
        }
        if outcome.done == 0 {
            if rebuilt_without_progress {
                // Every pair left failed a check; some only the error bound.
                break if outcome.over_bound > 0 {
                    StopReason::MaxError
                } else {
                    StopReason::NoValidPairs
                };
            }
            // Everything left was rejected: re-offer every current pair once.
            rebuilt_without_progress = true;
            pass += 1;
            e.generation = pass - generation_base;
            schedule.rebuild(&mut e, pass);
            continue;
        }
        rebuilt_without_progress = false;
        schedule.next_list(&mut e, pass, outcome.consumed);
    };
    drop(schedule);
    let fixed_seam_vertices = fixed_seam_vertices(&e);
    let stop_reason = seam_floor(stop_reason, fixed_seam_vertices, e.live_vertices);
    let (mesh, made) = output(&e, &frame);
    let run = Run {
        mesh,
        collapses: totals.done,
        rejected: totals.rejected,
        max_error: totals.worst / scale4,
        passes: pass as usize,
        stop_reason,
        virtual_pairs,
        max_relative_error: params
            .max_relative_error
            .map(|_| totals.worst_relative2.sqrt()),
        fixed_seam_vertices,
    };
    Ok((run, made))
}

/// The live vertices an attribute run never contracts: its fixed seam vertices (seam ends and
/// crossings, [`Seams::is_fixed`]); 0 without seams.
fn fixed_seam_vertices(e: &Engine) -> usize {
    e.seams.as_ref().map_or(0, |seams| {
        (0..e.vx.len())
            .filter(|&v| e.vx[v].len > 0 && seams.is_fixed(v))
            .count()
    })
}

/// [`StopReason::Seams`] for a run that found no valid contraction when at least half of its
/// `live` vertices are `fixed` seam vertices: the attributes' seams, not the mesh, are the
/// floor. Measured on synthetic atlases of gargoyle-10k (10,000 faces; 190, 250, 600 and 1,500
/// charts) asked for 10 and 2 % of the faces: every run that stopped short stopped with 344 of
/// 345, 446 of 447, 1,002 of 1,007 and 2,172 of 2,178 live vertices fixed, and
/// meshoptimizer's `simplifyWithAttributes` stopped at the same face counts (2,016 against our
/// 2,012 on 600 charts, 4,348-4,350 against 4,352-4,354 on 1,500). The error did not jump
/// before that floor: the cheapest pair at the start of every pass cost at most the largest
/// cost performed so far (docs/notes/attributes.md, "The seams' floor"), so no rule stops
/// earlier. Runs stopped by topology (a closed surface at a handful of vertices) have few
/// fixed vertices left and keep [`StopReason::NoValidPairs`].
fn seam_floor(reason: StopReason, fixed: usize, live: usize) -> StopReason {
    if reason == StopReason::NoValidPairs && fixed > 0 && 2 * fixed >= live {
        StopReason::Seams
    } else {
        reason
    }
}

/// Per vertex, the summed area of its faces (normalised frame): the weight of its plane quadric
/// (`mesh::quadric::area_weighted_plane`), which `max_relative_error` divides the cost by.
fn vertex_areas(pos: &[glam::DVec3], faces: &[[u32; 3]]) -> Vec<f64> {
    let mut area = vec![0.0; pos.len()];
    for t in faces {
        let [p0, p1, p2] = t.map(|v| pos[v as usize]);
        let a = 0.5 * (p1 - p0).cross(p2 - p0).length();
        for &v in t {
            area[v as usize] += a;
        }
    }
    area
}

/// The virtual-pairs pass: non-edge pairs closer than `pair_threshold` (normalised by `scale`)
/// are appended to `list` (not yet costed) and registered with the engine; returns their number.
fn add_virtual_pairs(
    e: &mut Engine,
    list: &mut Vec<Cand>,
    params: &QemParams,
    scale: f64,
) -> usize {
    if params.pair_threshold <= 0.0 {
        return 0;
    }
    let used: Vec<bool> = e.vx.iter().map(|v| v.len > 0).collect();
    let positions: Vec<_> = e.vx.iter().map(|d| d.p).collect();
    let close = pairs::close_pairs(
        &positions,
        &used,
        params.pair_threshold * scale,
        params.max_pairs_per_vertex,
    );
    let mut sorted_edges: Vec<[u32; 2]> = list.iter().map(|c| [c.a, c.b]).collect();
    sorted_edges.sort_unstable();
    let non_edge: Vec<[u32; 2]> = close
        .into_iter()
        .filter(|p| sorted_edges.binary_search(p).is_err())
        .collect();
    list.extend(non_edge.iter().map(|&[a, b]| Cand::pair(a, b)));
    e.virt = Some(pairs::VirtualPairs::new(e.vx.len(), &non_edge));
    non_edge.len()
}

/// When to stop: at most `faces` faces and at most `vertices` vertices (`usize::MAX`: no bound).
struct Goal {
    faces: usize,
    vertices: usize,
}

impl Goal {
    fn new(target: Target, input_faces: usize) -> Goal {
        let (faces, vertices) = match target {
            Target::Vertices(v) => (usize::MAX, v),
            Target::Faces(f) => (f, usize::MAX),
            Target::Ratio(r) => (((input_faces as f64) * r).round() as usize, usize::MAX),
        };
        Goal { faces, vertices }
    }

    #[inline]
    fn reached(&self, e: &Engine) -> bool {
        e.live_faces <= self.faces && e.live_vertices <= self.vertices
    }

    /// Contractions still needed (an interior edge collapse removes two faces).
    fn contractions_needed(&self, e: &Engine) -> usize {
        if self.faces != usize::MAX {
            (e.live_faces - self.faces).div_ceil(2)
        } else {
            e.live_vertices - self.vertices
        }
    }
}

/// What a pass may do: its number (the `touched` stamp of the vertices it merges), the cost cap
/// past which it stops (after at least one contraction), the run's error bound, its goal and the
/// checks of heavy pairs it may spend per vertex ([`HEAVY_TRIES`]), and the run's cancel flag.
struct PassRule<'a> {
    pass: u32,
    cap: f32,
    max_error: f64,
    /// Square of `max_relative_error` (infinite without it).
    max_relative2: f64,
    goal: &'a Goal,
    heavy_tries: u32,
    cancel: Option<&'a Cancel>,
}

/// What a pass did (and, summed, the whole run).
#[derive(Debug, Default)]
struct PassOutcome {
    /// Contractions performed.
    done: usize,
    /// Contractions rejected by the topology / normal checks.
    rejected: usize,
    /// Largest cost of a performed contraction (normalised frame).
    worst: f64,
    /// Largest cost / area of a performed contraction (with `max_relative_error`).
    worst_relative2: f64,
    /// Pairs skipped for exceeding `max_relative_error`.
    over_bound: usize,
    /// Entries of the list visited (contracted, rejected or stale); the rest is carried.
    consumed: usize,
    /// Set when the run must stop (the next contraction exceeds `max_error`).
    stop: Option<StopReason>,
    /// The pass stopped because the run was cancelled ([`QemParams::cancel`]).
    cancelled: bool,
    /// Checks of heavy pairs ([`HEAVY_LIST`]) in this pass, per kept end.
    heavy: std::collections::HashMap<u32, u32>,
}

/// The sorted candidate list and the buffers the passes reuse (kept for the whole run: no
/// allocation per pass once they have grown).
struct Schedule {
    /// Candidates in increasing cost (stale entries are skipped when visited).
    list: Vec<Cand>,
    /// Scratch of the radix sorts (released after each sort of the whole list, which needs it
    /// as large as the list, or sorts long lists in parts with a scratch of half their length;
    /// the fresh lists need far less).
    sort_tmp: Vec<Cand>,
    /// Pairs of the vertices merged in the last pass.
    fresh: Vec<Cand>,
    /// Vertices that survived a contraction in the current pass.
    survivors: Vec<u32>,
    /// Scratch of the survivors' sort.
    survivors_tmp: Vec<u32>,
    /// Bytes of list capacity given back since the last trim ([`TRIM_MIN_BYTES`] at the start,
    /// so that the first release trims).
    released: usize,
}

impl Schedule {
    fn new(list: Vec<Cand>) -> Schedule {
        Schedule {
            list,
            sort_tmp: Vec::new(),
            fresh: Vec::new(),
            survivors: Vec::new(),
            survivors_tmp: Vec::new(),
            released: TRIM_MIN_BYTES,
        }
    }

    /// Sort the whole list by cost.
    fn sort(&mut self) {
        // In parts: the scratch is half the list instead of all of it (the initial sort was one
        // of the one-thread peaks on igea-1m; the order is the same stable order).
        if self.list.len() >= SORT_IN_PARTS_MIN {
            sort_by_u32_key_in_parts(&mut self.list, WHOLE_SORT_PARTS, |c| sort_key(c.key));
        } else {
            sort_by_u32_key(&mut self.list, &mut self.sort_tmp, |c| sort_key(c.key));
            self.sort_tmp = Vec::new();
        }
    }

    /// Cost cap of a pass that needs `goal` contractions: 1.5 × the cost of the (goal/2)-th live
    /// entry (stale entries skipped), so a pass takes roughly half of what is still needed in
    /// close to greedy order before the costs around the merged vertices are refreshed.
    fn cost_cap(&self, e: &Engine, goal: usize) -> f32 {
        let list = &self.list;
        let mut cap_key = list[list.len() - 1].key;
        let mut live = 0usize;
        for c in list {
            if is_live(c, &e.contracted) {
                live += 1;
                if live > goal / 2 {
                    cap_key = c.key;
                    break;
                }
            }
        }
        1.5 * key_cost(cap_key)
    }

    /// One pass: walk the list in cost order and contract every live pair up to `cap` (at least
    /// one) that passes the checks, until the goal is reached or a cost exceeds `max_error`.
    /// Meshes whose engine data stays in cache skip the prefetch pipeline
    /// ([`prefetch::worth_it`]); both walks visit the same entries in the same order.
    fn one_pass(&mut self, e: &mut Engine, rule: &PassRule) -> PassOutcome {
        let mut out = PassOutcome {
            consumed: self.list.len(),
            ..PassOutcome::default()
        };
        self.survivors.clear();
        if e.prefetching {
            self.walk_prefetched(e, rule, &mut out);
        } else {
            for i in 0..self.list.len() {
                let c = self.list[i];
                if is_live(&c, &e.contracted)
                    && visit(e, c, i, rule, &mut self.survivors, &mut out).is_break()
                {
                    break;
                }
            }
        }
        out
    }

    /// [`Schedule::one_pass`]'s walk with the staged prefetch pipeline: the stages run over the
    /// upcoming *live* entries (most entries of a pass go stale before they are reached):
    /// `queue[qh..qt]` (modulo its length) holds the list indices of the next live entries found
    /// by the look-ahead `la`.
    fn walk_prefetched(&mut self, e: &mut Engine, rule: &PassRule, out: &mut PassOutcome) {
        let Schedule {
            list, survivors, ..
        } = self;
        const QUEUE: usize = prefetch::RECORDS;
        let mut queue = [0u32; QUEUE];
        let (mut qh, mut qt, mut la) = (0usize, 0usize, 0usize);
        loop {
            while qt - qh < QUEUE && la < list.len() {
                if let Some(ahead) = list.get(la + prefetch::CONTRACTED) {
                    prefetch_ptr(e.contracted.as_ptr().wrapping_add(ahead.a as usize));
                    prefetch_ptr(e.contracted.as_ptr().wrapping_add(ahead.b as usize));
                }
                let c = &list[la];
                if is_live(c, &e.contracted) {
                    e.prefetch(c.a as usize, c.b as usize);
                    queue[qt % QUEUE] = la as u32;
                    qt += 1;
                }
                la += 1;
            }
            if qh == qt {
                break;
            }
            let i = queue[qh % QUEUE] as usize;
            qh += 1;
            let upcoming = |k: usize| {
                (qh + k < qt)
                    .then(|| &list[queue[(qh + k) % QUEUE] as usize])
                    .filter(|c| is_live(c, &e.contracted))
            };
            if let Some(ahead) = upcoming(prefetch::LISTS - 1) {
                e.prefetch_lists(ahead.a as usize, ahead.b as usize);
            }
            if let Some(ahead) = upcoming(prefetch::FACES - 1) {
                e.prefetch_faces(ahead.a as usize, ahead.b as usize);
            }
            if let Some(ahead) = upcoming(prefetch::RING - 1) {
                e.prefetch_ring(ahead.a as usize, ahead.b as usize);
            }
            let c = list[i];
            // An entry can go stale between its look-ahead and its turn.
            if is_live(&c, &e.contracted) && visit(e, c, i, rule, survivors, out).is_break() {
                break;
            }
        }
    }

    /// After a pass without progress: a fresh list of every current pair (each produced once,
    /// by its smaller end), costed and sorted, for pass `pass`.
    fn rebuild(&mut self, e: &mut Engine, pass: u32) {
        self.list.clear();
        for v in 0..e.vx.len() {
            e.vx[v].touched = pass; // so that each pair is produced once, by its smaller index
        }
        for v in 0..e.vx.len() {
            if e.vx[v].alive && e.vx[v].len > 0 && !e.vx[v].locked {
                e.pairs_of(v, pass, &mut self.list);
            }
        }
        self.sort();
    }

    /// The next list after pass `pass`: the unvisited rest `list[consumed..]` (stale entries
    /// dropped) merged with the fresh pairs of the merged vertices.
    fn next_list(&mut self, e: &mut Engine, pass: u32, consumed: usize) {
        self.fresh.clear();
        // In index (Morton) order, so that neighbouring survivors share cached vertex data
        // (halves the last-level misses of the re-pairing on igea 10 %).
        sort_by_u32_key(&mut self.survivors, &mut self.survivors_tmp, |&v| v);
        e.fresh_pairs(&self.survivors, pass, &mut self.fresh);
        sort_by_u32_key(&mut self.fresh, &mut self.sort_tmp, |c| sort_key(c.key));
        merge_live(&mut self.list, consumed, &self.fresh, &e.contracted);
        // The list shortens from pass to pass; its emptied capacity goes back to the system
        // (it was touched, so it would stay resident to the end and be part of the peak).
        let len = self.list.len();
        let spare = self.list.capacity() - len;
        if spare > len / 8
            && self.list.capacity() * std::mem::size_of::<Cand>() >= RELEASE_MIN_BYTES
        {
            self.list.shrink_to(len);
            // What was freed stays resident until trimmed (glibc); the first release also
            // returns what the set-up freed, later ones wait until enough has piled up (each trim
            // walks every arena, and on two threads the other part's too).
            self.released = self
                .released
                .saturating_add(spare * std::mem::size_of::<Cand>());
            if self.released >= TRIM_MIN_BYTES {
                release_freed_memory();
                self.released = 0;
            }
        }
    }
}

/// The pass's step for the live entry `c` at list index `i`: stop at the cost cap (after at least
/// one contraction) or at `max_error`; otherwise evaluate, check and contract, keeping the vertex
/// with the longer face list. Breaks when the pass ends here.
#[inline(always)]
fn visit(
    e: &mut Engine,
    c: Cand,
    i: usize,
    rule: &PassRule,
    survivors: &mut Vec<u32>,
    out: &mut PassOutcome,
) -> std::ops::ControlFlow<()> {
    use std::ops::ControlFlow::{Break, Continue};
    let PassRule {
        pass,
        cap,
        max_error,
        max_relative2,
        goal,
        heavy_tries,
        cancel,
    } = *rule;
    let (a, b) = (c.a as usize, c.b as usize);
    if out.done > 0 && key_cost(c.key) > cap {
        out.consumed = i;
        return Break(());
    }
    let (cost, p) = e.evaluate(a, b);
    if cost > max_error {
        out.stop = Some(StopReason::MaxError);
        return Break(());
    }
    let mut relative2 = 0.0;
    if let Some(area) = &e.area {
        relative2 = cost / (area[a] + area[b]).max(f64::MIN_POSITIVE);
        if relative2 > max_relative2 {
            // Skipped like a rejected pair: it comes back when a contraction changes an end.
            out.over_bound += 1;
            return Continue(());
        }
    }
    // Keep the seam vertex of a pair with one end off the seams (it stays), else the vertex
    // with the longer face list (less relinking).
    let anchor = e.seams.as_ref().and_then(|s| s.anchor(a, b));
    let (a, b) = if anchor == Some(b) || (anchor.is_none() && e.vx[b].len > e.vx[a].len) {
        (b, a)
    } else {
        (a, b)
    };
    if e.vx[a].len > HEAVY_LIST {
        let tries = out.heavy.entry(a as u32).or_default();
        if *tries >= heavy_tries {
            return Continue(());
        }
        *tries += 1;
    }
    if !e.allowed(a, b, p) {
        // Dropped; the pair comes back when a neighbouring contraction touches an endpoint, or
        // in a full rebuild.
        out.rejected += 1;
        return Continue(());
    }
    e.collapse(a, b, p);
    e.vx[a].touched = pass;
    e.vx[b].touched = pass;
    survivors.push(a as u32);
    out.done += 1;
    out.worst = out.worst.max(cost);
    out.worst_relative2 = out.worst_relative2.max(relative2);
    if out.done.is_multiple_of(CANCEL_EVERY) && cancel.is_some_and(Cancel::is_cancelled) {
        out.cancelled = true;
        return Break(());
    }
    if goal.reached(e) {
        out.consumed = i + 1;
        return Break(());
    }
    Continue(())
}

#[cfg(test)]
mod tests {
    use super::super::prefetch::FORCE;

    /// `mesh` prepared and simplified to `faces` with the prefetch stages forced on or off.
    fn simplified(mesh: &mesh::TriMesh, faces: usize, prefetch: bool) -> mesh::TriMesh {
        FORCE.with(|f| f.set(Some(prefetch)));
        let params = crate::QemParams::with_target(crate::Target::Faces(faces));
        let prepared = super::prepare::prepare(mesh).expect("prepare");
        let out = super::simplify_prepared(prepared, &params, None).expect("simplify");
        FORCE.with(|f| f.set(None));
        out.0.mesh
    }

    #[test]
    fn the_walk_without_prefetch_contracts_the_same_pairs() {
        // One mesh below and one above MIN_VERTICES, each simplified both ways, to 10 % and 1 %.
        for mesh in [
            mesh::procedural::icosphere(4),
            mesh::procedural::icosphere(5),
        ] {
            for faces in [mesh.face_count() / 10, mesh.face_count() / 100] {
                let with = simplified(&mesh, faces, true);
                let without = simplified(&mesh, faces, false);
                assert!(with.face_count() <= faces && with.face_count() > 0);
                assert_eq!(with.triangles, without.triangles);
                assert_eq!(with.positions, without.positions);
            }
        }
    }
}

//! The contraction engine: flat arrays, per-vertex face lists in one growing buffer (CSR-like,
//! rewritten on collapse and compacted now and then), and a sorted candidate list processed in
//! passes instead of a heap.
//!
//! Each pass walks the pairs in increasing cost and contracts every pair whose endpoints were not
//! touched earlier in the pass, up to a cost cap (1.5 × the cost at the middle of the pass's goal),
//! so the order stays close to the greedy order of Garland & Heckbert. Pairs of untouched vertices
//! keep their exact cost and order for the next pass; pairs of the merged vertices are evaluated
//! afresh, sorted, and merged in. This keeps memory access sequential (no heap sift misses).

use crate::radix::sort_by_u32_key;
use crate::{QemError, QemParams, QemReport, Quadric, StopReason, Target, pairs};
use glam::{DVec3, Vec3};
use mesh::TriMesh;
use rayon::prelude::*;
use std::time::Instant;

/// Marks a dead face (in its first slot) and an empty linked list.
const DEAD: u32 = u32::MAX;
/// How many list entries ahead the pass loop prefetches version stamps.
const PREFETCH_STAMPS: usize = 32;
/// How many live candidates (or survivors, in the pair generation) ahead the vertex records of
/// the endpoints are prefetched.
const PREFETCH_DISTANCE: usize = 16;
/// How many live candidates (survivors) ahead the face lists are prefetched.
const PREFETCH_LISTS: usize = 8;
/// How many live candidates (survivors) ahead the faces are prefetched.
const PREFETCH_FACES: usize = 4;
/// How many live candidates (survivors) ahead the records around the endpoints are prefetched.
const PREFETCH_RING: usize = 2;

/// Work lists shorter than this are processed on the calling thread only.
const PARALLEL_MIN: usize = 32_768;
/// Whether `len` work items (at least `min`) are worth splitting over the rayon pool; with one
/// thread (`RAYON_NUM_THREADS=1`) everything runs on the calling thread.
fn parallel(len: usize, min: usize) -> bool {
    len >= min && rayon::current_num_threads() > 1
}

/// Items per parallel task.
const PARALLEL_CHUNK: usize = 8_192;

/// Hint the CPU to load the cache line at `p` (a hint only: any address is fine).
#[inline(always)]
fn prefetch_ptr<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: prefetching is only a hint; it never faults, whatever the address.
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// A candidate pair with its cost (as `f32` bits, which order like the non-negative cost).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord)]
struct Cand {
    key: u32,
    a: u32,
    b: u32,
    /// Sum of the two vertices' version stamps at evaluation time (stale once either changes).
    stamp: u32,
}

/// The part of a cost key that orders candidates: the low 10 mantissa bits are dropped (costs
/// within a relative 2⁻¹³ count as equal and keep their order), so the radix sort needs two
/// 11-bit digits instead of three.
#[inline]
fn sort_key(key: u32) -> u32 {
    key >> 10
}

#[inline]
fn cost_key(cost: f64) -> u32 {
    let c = cost as f32;
    if c.is_nan() {
        f32::MAX.to_bits()
    } else {
        c.max(0.0).to_bits()
    }
}

/// Linked lists of non-edge pairs per (representative) vertex, plus union-find to resolve merges.
struct VirtualPairs {
    parent: Vec<u32>,
    head: Vec<u32>,
    tail: Vec<u32>,
    next: Vec<u32>,
    /// Node `2p + s` belongs to pair `p` on side `s`; `other` is the vertex on the other side.
    other: Vec<u32>,
}

impl VirtualPairs {
    fn new(vertices: usize, pairs: &[[u32; 2]]) -> Self {
        let mut vp = VirtualPairs {
            parent: (0..vertices as u32).collect(),
            head: vec![DEAD; vertices],
            tail: vec![DEAD; vertices],
            next: vec![DEAD; pairs.len() * 2],
            other: Vec::with_capacity(pairs.len() * 2),
        };
        for (p, &[u, v]) in pairs.iter().enumerate() {
            vp.other.push(v);
            vp.other.push(u);
            vp.append(u as usize, (2 * p) as u32);
            vp.append(v as usize, (2 * p + 1) as u32);
        }
        vp
    }

    fn append(&mut self, v: usize, node: u32) {
        if self.head[v] == DEAD {
            self.head[v] = node;
        } else {
            self.next[self.tail[v] as usize] = node;
        }
        self.tail[v] = node;
    }

    fn find(&mut self, mut v: u32) -> u32 {
        while self.parent[v as usize] != v {
            let g = self.parent[self.parent[v as usize] as usize];
            self.parent[v as usize] = g;
            v = g;
        }
        v
    }

    /// Vertex `b` merged into `a`: union, and concatenate `b`'s list onto `a`'s.
    fn merge(&mut self, a: usize, b: usize) {
        self.parent[b] = a as u32;
        if self.head[b] == DEAD {
            return;
        }
        if self.head[a] == DEAD {
            self.head[a] = self.head[b];
        } else {
            self.next[self.tail[a] as usize] = self.head[b];
        }
        self.tail[a] = self.tail[b];
        self.head[b] = DEAD;
        self.tail[b] = DEAD;
    }
}

/// Everything per vertex, in two cache lines: the first holds what the checks read for the
/// neighbours of a pair (position, scratch mark, valence), the second the rest of the quadric and
/// the face-list bookkeeping; a record never straddles more lines than it needs.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(64))]
struct Vertex {
    /// Position in the normalised frame.
    p: DVec3,
    /// Scratch mark (compared with `Engine::tick`).
    mark: u32,
    /// Live faces around the vertex.
    valence: u32,
    /// Quadric (face planes plus boundary planes) in the normalised frame.
    q: Quadric,
    /// Start of the face list in `refs`.
    start: u32,
    /// Length of the face list (may include dead faces).
    len: u32,
    /// Pass in which the vertex was last touched by a contraction.
    touched: u32,
    /// Not merged into another vertex.
    alive: bool,
    /// On a boundary edge (or a non-manifold edge).
    boundary: bool,
}

// Two whole cache lines per vertex.
const _: () = assert!(std::mem::size_of::<Vertex>() == 128);

/// Mutable simplification state.
struct Engine {
    /// Geometry and bookkeeping per vertex.
    vx: Vec<Vertex>,
    /// Version per vertex, bumped by every contraction of the vertex (a separate compact array:
    /// the candidate walks test it for every entry, in cost order, i.e. at random).
    stamps: Vec<u32>,
    faces: Vec<[u32; 3]>,
    /// Face lists, appended to on every collapse (capacity reserved up to `refs_limit`).
    refs: Vec<u32>,
    /// Length of `refs` above which it is compacted.
    refs_limit: usize,
    /// The other buffer of the compaction.
    refs_spare: Vec<u32>,
    /// Current scratch-mark value.
    tick: u32,
    scratch: Vec<u32>,
    virt: Option<VirtualPairs>,
    live_faces: usize,
    live_vertices: usize,
    preserve_topology: bool,
    min_normal_cos: f64,
}

#[inline]
fn contains(t: &[u32; 3], v: u32) -> bool {
    t[0] == v || t[1] == v || t[2] == v
}

/// The corner that follows `u` in face `t` (around a closed fan of `u`, every neighbour once).
#[inline]
fn corner_after(t: &[u32; 3], u: u32) -> u32 {
    if t[0] == u {
        t[1]
    } else if t[1] == u {
        t[2]
    } else {
        t[0]
    }
}

impl Engine {
    /// Hint the CPU to load both cache lines of vertex record `i` (a no-op out of range).
    #[inline]
    fn prefetch_record(&self, i: usize) {
        if i < self.vx.len() {
            let d = self.vx.as_ptr().wrapping_add(i).cast::<u8>();
            prefetch_ptr(d);
            prefetch_ptr(d.wrapping_add(64));
        }
    }

    /// Hint the CPU to load the face list of `i` (its record should be cached).
    #[inline]
    fn prefetch_list(&self, i: usize) {
        if let Some(info) = self.vx.get(i) {
            let s = info.start as usize;
            prefetch_ptr(self.refs.as_ptr().wrapping_add(s));
            prefetch_ptr(self.refs.as_ptr().wrapping_add(s + info.len as usize));
        }
    }

    /// Hint the CPU to load the faces of `i` (its list should be cached).
    #[inline]
    fn prefetch_faces_of(&self, i: usize) {
        if i < self.vx.len() {
            for &f in &self.refs[self.list(i)] {
                prefetch_ptr(self.faces.as_ptr().wrapping_add(f as usize));
            }
        }
    }

    /// Hint the CPU to load the records of the vertices around `i` (its faces should be cached):
    /// the first line only (position, mark and valence: what the topology and flip checks read),
    /// or the whole record when `whole` (the pair generation also reads the quadric).
    #[inline]
    fn prefetch_ring_of(&self, i: usize, whole: bool) {
        if i < self.vx.len() {
            for &f in &self.refs[self.list(i)] {
                let w = corner_after(&self.faces[f as usize], i as u32) as usize;
                if whole {
                    self.prefetch_record(w);
                } else {
                    prefetch_ptr(self.vx.as_ptr().wrapping_add(w));
                }
            }
        }
    }

    /// First prefetch stage of a candidate walk (cost order, i.e. at random): the records of
    /// `a` and `b`.
    #[inline]
    fn prefetch(&self, a: usize, b: usize) {
        self.prefetch_record(a);
        self.prefetch_record(b);
    }

    /// Second prefetch stage: the face lists of `a` and `b`.
    #[inline]
    fn prefetch_lists(&self, a: usize, b: usize) {
        self.prefetch_list(a);
        self.prefetch_list(b);
    }

    /// Third prefetch stage: the faces of `a` and `b`.
    #[inline]
    fn prefetch_faces(&self, a: usize, b: usize) {
        self.prefetch_faces_of(a);
        self.prefetch_faces_of(b);
    }

    /// Fourth prefetch stage: the positions of the vertices around `a` and `b`.
    #[inline]
    fn prefetch_ring(&self, a: usize, b: usize) {
        self.prefetch_ring_of(a, false);
        self.prefetch_ring_of(b, false);
    }

    #[inline]
    fn list(&self, v: usize) -> std::ops::Range<usize> {
        let s = self.vx[v].start as usize;
        s..s + self.vx[v].len as usize
    }

    #[inline]
    fn next_tick(&mut self) -> u32 {
        self.tick = self.tick.wrapping_add(1);
        if self.tick == 0 {
            for x in &mut self.vx {
                x.mark = 0;
            }
            self.tick = 1;
        }
        self.tick
    }

    /// Placement and cost for the pair: the quadric minimiser (where `E = c + bᵀv`), else the best
    /// point of the segment, else the best of the ends and the midpoint.
    #[inline]
    fn place(q: &Quadric, pa: DVec3, pb: DVec3) -> (f64, DVec3) {
        let d = pb - pa;
        let len2 = d.length_squared();
        let mid = 0.5 * (pa + pb);
        if let Some(x) = q.minimizer() {
            // Guard against nearly singular systems that throw the point far away.
            if (x - mid).length_squared() <= 9.0 * len2 {
                return (q.c + q.b_vec().dot(x), x);
            }
        }
        let dad = d.dot(q.mul_a(d));
        if dad > 1e-12 * q.trace() * len2 {
            let t = (-d.dot(q.mul_a(pa) + q.b_vec()) / dad).clamp(0.0, 1.0);
            let x = pa + d * t;
            return (q.eval(x), x);
        }
        let (ea, eb, em) = (q.eval(pa), q.eval(pb), q.eval(mid));
        if em <= ea && em <= eb {
            (em, mid)
        } else if ea <= eb {
            (ea, pa)
        } else {
            (eb, pb)
        }
    }

    #[inline]
    fn evaluate(&self, a: usize, b: usize) -> (f64, DVec3) {
        let (da, db) = (&self.vx[a], &self.vx[b]);
        let q = da.q + db.q;
        let (cost, p) = Self::place(&q, da.p, db.p);
        (cost.max(0.0), p)
    }

    #[inline]
    fn candidate(&self, a: usize, b: usize) -> Cand {
        let (cost, _) = self.evaluate(a, b);
        Cand {
            key: cost_key(cost),
            a: a as u32,
            b: b as u32,
            stamp: self.stamps[a].wrapping_add(self.stamps[b]),
        }
    }

    /// Evaluate every pair of `list` (the `a` and `b` fields are set; sorted by `a`, so only the
    /// records of the `b` ends are prefetched), in parallel for large lists.
    fn cost_all(&self, list: &mut [Cand]) {
        let cost = |chunk: &mut [Cand]| {
            for i in 0..chunk.len() {
                if let Some(ahead) = chunk.get(i + PREFETCH_DISTANCE) {
                    self.prefetch_record(ahead.b as usize);
                }
                let c = &mut chunk[i];
                *c = self.candidate(c.a as usize, c.b as usize);
            }
        };
        if parallel(list.len(), PARALLEL_MIN) {
            list.par_chunks_mut(PARALLEL_CHUNK).for_each(cost);
        } else {
            cost(list);
        }
    }

    /// Append the pairs of the merged vertices `survivors` (sorted) to `fresh`, prefetching a few
    /// survivors ahead (sequential: on two shared cores a parallel split measured no faster).
    fn fresh_pairs(&mut self, survivors: &[u32], pass: u32, fresh: &mut Vec<Cand>) {
        for (i, &a) in survivors.iter().enumerate() {
            self.prefetch_survivors(survivors, i);
            self.pairs_of(a as usize, pass, fresh);
        }
    }

    /// Prefetch, in stages, the records, face lists, faces and neighbour records for the pair
    /// generation of the survivors a few places after `i`.
    #[inline]
    fn prefetch_survivors(&self, survivors: &[u32], i: usize) {
        if let Some(&ahead) = survivors.get(i + PREFETCH_DISTANCE) {
            self.prefetch_record(ahead as usize);
        }
        if let Some(&ahead) = survivors.get(i + PREFETCH_LISTS) {
            self.prefetch_list(ahead as usize);
        }
        if let Some(&ahead) = survivors.get(i + PREFETCH_FACES) {
            self.prefetch_faces_of(ahead as usize);
        }
        if let Some(&ahead) = survivors.get(i + PREFETCH_RING) {
            self.prefetch_ring_of(ahead as usize, true);
        }
    }

    /// Append the pairs of the merged vertex `a` (mesh edges and non-edge pairs) to `out`; a pair
    /// with another vertex touched in pass `pass` is produced by the smaller index only.
    fn pairs_of(&mut self, a: usize, pass: u32, out: &mut Vec<Cand>) {
        let t = self.next_tick();
        self.vx[a].mark = t;
        let keep = |e: &Self, v: usize| e.vx[v].touched != pass || a < v;
        for i in self.list(a) {
            let tri = self.faces[self.refs[i] as usize];
            if tri[0] == DEAD {
                continue;
            }
            for v in tri {
                let v = v as usize;
                if self.vx[v].mark != t {
                    self.vx[v].mark = t;
                    if keep(self, v) {
                        out.push(self.candidate(a, v));
                    }
                }
            }
        }
        if let Some(mut vp) = self.virt.take() {
            let mut node = vp.head[a];
            while node != DEAD {
                let o = vp.find(vp.other[node as usize]) as usize;
                node = vp.next[node as usize];
                if self.vx[o].alive && self.vx[o].mark != t {
                    self.vx[o].mark = t;
                    if keep(self, o) {
                        out.push(self.candidate(a, o));
                    }
                }
            }
            self.virt = Some(vp);
        }
    }

    /// Whether moving vertex `u` (now at `pu`) of face `tri` to `p` turns the face normal too far.
    #[inline(always)]
    fn flips(&self, tri: [u32; 3], u: u32, pu: DVec3, p: DVec3) -> bool {
        let (i1, i2) = if tri[0] == u {
            (tri[1], tri[2])
        } else if tri[1] == u {
            (tri[2], tri[0])
        } else {
            (tri[0], tri[1])
        };
        let p1 = self.vx[i1 as usize].p;
        let p2 = self.vx[i2 as usize].p;
        let old = (p1 - pu).cross(p2 - pu);
        let ol = old.length_squared();
        if ol == 0.0 {
            return false;
        }
        let new = (p1 - p).cross(p2 - p);
        let nl = new.length_squared();
        old.dot(new) <= self.min_normal_cos * (ol * nl).sqrt()
    }

    /// Check the topology/normal conditions for contracting `b` into `a` at `p`: one walk over the
    /// faces of `a` (shared faces, neighbour marks, normal flips of the faces that move) and one
    /// over the faces of `b` (common neighbours, flips, tetrahedron test).
    fn allowed(&mut self, a: usize, b: usize, p: DVec3) -> bool {
        if !self.preserve_topology {
            return true;
        }
        let (au, bu) = (a as u32, b as u32);
        let mut shared = 0usize;
        let mut opp = [DEAD; 2];
        let mut alive_a = 0usize;
        let ta = self.next_tick();
        let pa = self.vx[a].p;
        for i in self.list(a) {
            let t = self.faces[self.refs[i] as usize];
            if t[0] == DEAD {
                continue;
            }
            alive_a += 1;
            for v in t {
                self.vx[v as usize].mark = ta;
            }
            if contains(&t, bu) {
                if shared < 2 {
                    opp[shared] = t[0] ^ t[1] ^ t[2] ^ au ^ bu;
                }
                shared += 1;
            } else if self.flips(t, au, pa, p) {
                return false;
            }
        }
        if shared > 2 || (shared == 2 && self.vx[a].boundary && self.vx[b].boundary) {
            return false;
        }
        // Link condition: common neighbours must be exactly the opposite vertices.
        let tb = self.next_tick();
        let mut common = 0usize;
        let mut alive_b = 0usize;
        let (c, d) = (opp[0], opp[1]);
        let mut b_has_cd = false;
        let pb = self.vx[b].p;
        for i in self.list(b) {
            let t = self.faces[self.refs[i] as usize];
            if t[0] == DEAD {
                continue;
            }
            alive_b += 1;
            for v in t {
                if v != au && v != bu && self.vx[v as usize].mark == ta {
                    self.vx[v as usize].mark = tb;
                    common += 1;
                }
            }
            if !contains(&t, au) {
                if self.flips(t, bu, pb, p) {
                    return false;
                }
                b_has_cd |= shared == 2 && contains(&t, c) && contains(&t, d);
            }
        }
        if common != shared || alive_a + alive_b <= 2 * shared {
            return false;
        }
        // No opposite vertex may be left without faces.
        for &o in &opp[..shared] {
            if self.vx[o as usize].valence < 2 {
                return false;
            }
        }
        // Tetrahedron: faces (a, c, d) and (b, c, d) would become the same face.
        if b_has_cd
            && self.list(a).any(|i| {
                let t = self.faces[self.refs[i] as usize];
                t[0] != DEAD && contains(&t, c) && contains(&t, d)
            })
        {
            return false;
        }
        true
    }

    /// Contract `b` into `a`, moving `a` to `p`.
    fn collapse(&mut self, a: usize, b: usize, p: DVec3) {
        let (au, bu) = (a as u32, b as u32);
        self.vx[a].p = p;
        let qb = self.vx[b].q;
        self.vx[a].q += qb;
        self.vx[a].boundary |= self.vx[b].boundary;
        self.vx[b].alive = false;
        self.stamps[a] = self.stamps[a].wrapping_add(1);
        self.stamps[b] = self.stamps[b].wrapping_add(1);
        self.live_vertices -= 1;
        self.scratch.clear();
        for i in self.list(b) {
            let f = self.refs[i] as usize;
            let t = &mut self.faces[f];
            if t[0] == DEAD {
                continue;
            }
            if contains(t, au) {
                let third = t[0] ^ t[1] ^ t[2] ^ au ^ bu;
                t[0] = DEAD;
                self.vx[third as usize].valence -= 1;
                self.live_faces -= 1;
            } else {
                for v in t.iter_mut() {
                    if *v == bu {
                        *v = au;
                    }
                }
                self.scratch.push(f as u32);
            }
        }
        let start = self.refs.len();
        for i in self.list(a) {
            let f = self.refs[i];
            if self.faces[f as usize][0] != DEAD {
                self.refs.push(f);
            }
        }
        self.refs.extend_from_slice(&self.scratch);
        self.vx[a].start = start as u32;
        self.vx[a].len = (self.refs.len() - start) as u32;
        self.vx[b].len = 0;
        self.vx[a].valence = self.vx[a].len;
        self.vx[b].valence = 0;
        if let Some(vp) = self.virt.as_mut() {
            vp.merge(a, b);
        }
        if self.refs.len() > self.refs_limit {
            self.compact_refs();
        }
    }

    /// Rewrite the face lists without dead faces and free space.
    fn compact_refs(&mut self) {
        // Into the spare buffer (kept between compactions: no fresh pages to fault in).
        let mut fresh = std::mem::take(&mut self.refs_spare);
        fresh.clear();
        fresh.reserve(self.refs_limit);
        for v in 0..self.vx.len() {
            let range = self.list(v);
            let start = fresh.len();
            if self.vx[v].alive {
                for i in range {
                    let f = self.refs[i];
                    if self.faces[f as usize][0] != DEAD {
                        fresh.push(f);
                    }
                }
            }
            self.vx[v].start = start as u32;
            self.vx[v].len = (fresh.len() - start) as u32;
        }
        self.refs_spare = std::mem::replace(&mut self.refs, fresh);
        self.refs_limit = (self.refs.len() * 3).max(1024);
    }
}

/// Run the whole simplification.
pub fn run(input: &TriMesh, params: &QemParams) -> Result<(TriMesh, QemReport), QemError> {
    let started = Instant::now();
    validate(params)?;
    let n = input.positions.len();
    if n >= u32::MAX as usize || input.triangles.len() >= u32::MAX as usize / 2 {
        return Err(QemError::InvalidParameter(
            "mesh too large for 32-bit indices".into(),
        ));
    }
    // Validate and drop faces that repeat a vertex index.
    let mut faces: Vec<[u32; 3]> = Vec::with_capacity(input.triangles.len());
    for (fi, t) in input.triangles.iter().enumerate() {
        for &v in t {
            if v as usize >= n {
                return Err(QemError::InvalidIndex {
                    face: fi,
                    index: v,
                    vertices: n,
                });
            }
        }
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            faces.push(*t);
        }
    }
    if faces.is_empty() {
        return Err(QemError::EmptyMesh);
    }
    let mut old_face_len = vec![0u32; n];
    for t in &faces {
        for &v in t {
            old_face_len[v as usize] += 1;
        }
    }
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for (i, p) in input.positions.iter().enumerate() {
        if old_face_len[i] > 0 {
            if !p.is_finite() {
                return Err(QemError::NonFiniteVertex(i));
            }
            lo = lo.min(p.as_dvec3());
            hi = hi.max(p.as_dvec3());
        }
    }
    // Work in a normalised frame (centred, unit bounding-box diagonal) for conditioning.
    let center = 0.5 * (lo + hi);
    let diag = (hi - lo).length();
    let scale = if diag > 0.0 { 1.0 / diag } else { 1.0 };
    // Renumber the referenced vertices along a Morton curve and sort the faces by their smallest
    // new index: neighbouring elements then sit close in memory (inputs are often scan-ordered).
    let mut order: Vec<u64> = (0..n)
        .filter(|&i| old_face_len[i] > 0)
        .map(|i| (morton((input.positions[i].as_dvec3() - center) * scale) << 32) | i as u64)
        .collect();
    let mut scratch64: Vec<u64> = Vec::new();
    // The 22 high bits of the Morton code (7 per axis) are locality enough: two radix passes.
    sort_by_u32_key(&mut order, &mut scratch64, |&o| (o >> 40) as u32);
    let mut new_index = vec![DEAD; n];
    for (k, &o) in order.iter().enumerate() {
        new_index[o as u32 as usize] = k as u32;
    }
    let pos: Vec<DVec3> = order
        .iter()
        .map(|&o| (input.positions[o as u32 as usize].as_dvec3() - center) * scale)
        .collect();
    // Faces per renumbered vertex (the same faces, so the old counts permuted).
    let face_len: Vec<u32> = order
        .iter()
        .map(|&o| old_face_len[o as u32 as usize])
        .collect();
    drop(order);
    drop(scratch64);
    drop(old_face_len);
    let n = pos.len();
    // Faces, renumbered, in order of their smallest vertex (a stable counting sort).
    let renumbered = |t: &[u32; 3]| t.map(|v| new_index[v as usize]);
    let smallest = |t: &[u32; 3]| t[0].min(t[1]).min(t[2]) as usize;
    let mut slot = vec![0u32; n + 1];
    for t in &faces {
        slot[smallest(&renumbered(t)) + 1] += 1;
    }
    for v in 0..n {
        slot[v + 1] += slot[v];
    }
    let mut sorted = vec![[0u32; 3]; faces.len()];
    for t in &faces {
        let r = renumbered(t);
        let s = &mut slot[smallest(&r)];
        sorted[*s as usize] = r;
        *s += 1;
    }
    drop(slot);
    drop(new_index);
    let faces = sorted;

    // Vertex -> face lists (CSR).
    let mut face_start = vec![0u32; n];
    let mut acc = 0u32;
    for v in 0..n {
        face_start[v] = acc;
        acc += face_len[v];
    }
    let mut refs = vec![0u32; acc as usize];
    let mut fill = face_start.clone();
    for (f, t) in faces.iter().enumerate() {
        for &v in t {
            refs[fill[v as usize] as usize] = f as u32;
            fill[v as usize] += 1;
        }
    }
    drop(fill);

    // Per vertex, in parallel: area-weighted face quadrics, boundary planes, boundary flag, and
    // the edges to higher-numbered neighbours.
    let input_faces = faces.len();
    let refs_limit = (refs.len() * 3).max(1024);
    let VertexSetup { vx, mut list } = vertex_setup(&pos, &faces, &refs, &face_start, params);
    drop(pos);

    let referenced_vertices = n;
    // Room for the appended lists up front: growing by doubling would copy and fault in pages.
    refs.reserve(refs_limit + 64 - refs.len());
    let mut e = Engine {
        vx,
        stamps: vec![0; n],
        faces,
        refs,
        refs_limit,
        refs_spare: Vec::new(),
        tick: 0,
        scratch: Vec::new(),
        virt: None,
        live_faces: input_faces,
        live_vertices: referenced_vertices,
        preserve_topology: params.preserve_topology,
        min_normal_cos: params.min_normal_cos,
    };

    // Non-edge pairs within the threshold.
    let mut virtual_pairs = 0;
    if params.pair_threshold > 0.0 {
        let used: Vec<bool> = e.vx.iter().map(|v| v.len > 0).collect();
        let positions: Vec<DVec3> = e.vx.iter().map(|d| d.p).collect();
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
        virtual_pairs = non_edge.len();
        list.extend(non_edge.iter().map(|&[a, b]| Cand {
            a,
            b,
            ..Cand::default()
        }));
        e.virt = Some(VirtualPairs::new(n, &non_edge));
    }

    e.cost_all(&mut list);
    let mut sort_tmp: Vec<Cand> = Vec::new();
    sort_by_u32_key(&mut list, &mut sort_tmp, |c| sort_key(c.key));

    let (target_faces, target_vertices) = match params.target {
        Target::Vertices(v) => (usize::MAX, v),
        Target::Faces(f) => (f, usize::MAX),
        Target::Ratio(r) => (((input_faces as f64) * r).round() as usize, usize::MAX),
    };
    let scale4 = scale.powi(4);
    let max_error = params.max_error.map_or(f64::INFINITY, |m| m * scale4);

    let mut collapses = 0usize;
    let mut rejected = 0usize;
    let mut worst = 0.0f64;
    let mut pass = 0u32;
    let mut fresh: Vec<Cand> = Vec::new();
    let mut survivors: Vec<u32> = Vec::new();
    let mut survivors_tmp: Vec<u32> = Vec::new();
    let mut rebuilt_without_progress = false;
    let reached = |e: &Engine| e.live_faces <= target_faces && e.live_vertices <= target_vertices;
    let stop_reason = loop {
        if reached(&e) {
            break StopReason::TargetReached;
        }
        if list.is_empty() {
            break StopReason::NoValidPairs;
        }
        pass += 1;
        // Contractions still needed (an interior edge collapse removes two faces).
        let goal = if target_faces != usize::MAX {
            (e.live_faces - target_faces).div_ceil(2)
        } else {
            e.live_vertices - target_vertices
        };
        // Cost cap: 1.5 × the cost of the (goal/2)-th live entry (stale entries skipped).
        let mut cap_key = list[list.len() - 1].key;
        let mut live = 0usize;
        for c in &list {
            if is_live(c, &e.stamps) {
                live += 1;
                if live > goal / 2 {
                    cap_key = c.key;
                    break;
                }
            }
        }
        let cap = 1.5 * f32::from_bits(cap_key);
        let mut done = 0usize;
        let mut stop = None;
        survivors.clear();
        // Every visited entry is consumed (contracted, rejected or stale); the rest is carried.
        let mut consumed = list.len();
        // The prefetch stages run over the upcoming *live* entries (most entries of a pass go
        // stale before they are reached): `queue[qh..qt]` (modulo its length) holds the list
        // indices of the next live entries found by the look-ahead `la`.
        let mut queue = [0u32; PREFETCH_DISTANCE];
        let (mut qh, mut qt, mut la) = (0usize, 0usize, 0usize);
        loop {
            while qt - qh < PREFETCH_DISTANCE && la < list.len() {
                if let Some(ahead) = list.get(la + PREFETCH_STAMPS) {
                    prefetch_ptr(e.stamps.as_ptr().wrapping_add(ahead.a as usize));
                    prefetch_ptr(e.stamps.as_ptr().wrapping_add(ahead.b as usize));
                }
                let c = &list[la];
                if is_live(c, &e.stamps) {
                    e.prefetch(c.a as usize, c.b as usize);
                    queue[qt % PREFETCH_DISTANCE] = la as u32;
                    qt += 1;
                }
                la += 1;
            }
            if qh == qt {
                break;
            }
            let i = queue[qh % PREFETCH_DISTANCE] as usize;
            qh += 1;
            let upcoming = |k: usize| {
                (qh + k < qt)
                    .then(|| &list[queue[(qh + k) % PREFETCH_DISTANCE] as usize])
                    .filter(|c| is_live(c, &e.stamps))
            };
            if let Some(ahead) = upcoming(PREFETCH_LISTS - 1) {
                e.prefetch_lists(ahead.a as usize, ahead.b as usize);
            }
            if let Some(ahead) = upcoming(PREFETCH_FACES - 1) {
                e.prefetch_faces(ahead.a as usize, ahead.b as usize);
            }
            if let Some(ahead) = upcoming(PREFETCH_RING - 1) {
                e.prefetch_ring(ahead.a as usize, ahead.b as usize);
            }
            let c = &list[i];
            if !is_live(c, &e.stamps) {
                continue;
            }
            let (a, b) = (c.a as usize, c.b as usize);
            if done > 0 && f32::from_bits(c.key) > cap {
                consumed = i;
                break;
            }
            let (cost, p) = e.evaluate(a, b);
            if cost > max_error {
                stop = Some(StopReason::MaxError);
                break;
            }
            // Keep the vertex with the longer face list (less relinking).
            let (a, b) = if e.vx[b].len > e.vx[a].len {
                (b, a)
            } else {
                (a, b)
            };
            if !e.allowed(a, b, p) {
                // Dropped; the pair comes back when a neighbouring contraction touches an
                // endpoint, or in a full rebuild.
                rejected += 1;
                continue;
            }
            e.collapse(a, b, p);
            e.vx[a].touched = pass;
            e.vx[b].touched = pass;
            survivors.push(a as u32);
            done += 1;
            worst = worst.max(cost);
            if reached(&e) {
                consumed = i + 1;
                break;
            }
        }
        collapses += done;
        if let Some(reason) = stop {
            break reason;
        }
        if reached(&e) {
            break StopReason::TargetReached;
        }
        if done == 0 {
            if rebuilt_without_progress {
                break StopReason::NoValidPairs;
            }
            // Everything left was rejected: re-offer every current pair once.
            rebuilt_without_progress = true;
            pass += 1;
            list.clear();
            for v in 0..e.vx.len() {
                e.vx[v].touched = pass; // so that each pair is produced once, by its smaller index
            }
            for v in 0..e.vx.len() {
                if e.vx[v].alive && e.vx[v].len > 0 {
                    e.pairs_of(v, pass, &mut list);
                }
            }
            sort_by_u32_key(&mut list, &mut sort_tmp, |c| sort_key(c.key));
            continue;
        }
        rebuilt_without_progress = false;
        // Next list: the unvisited rest (stale entries are skipped when visited), merged with the
        // fresh pairs of the merged vertices.
        fresh.clear();
        // In index (Morton) order, so that neighbouring survivors share cached vertex data.
        sort_by_u32_key(&mut survivors, &mut survivors_tmp, |&v| v);
        e.fresh_pairs(&survivors, pass, &mut fresh);
        sort_by_u32_key(&mut fresh, &mut sort_tmp, |c| sort_key(c.key));
        merge_live(&list, consumed, &fresh, &e.stamps, &mut sort_tmp);
        std::mem::swap(&mut list, &mut sort_tmp);
    };

    let out = e.output(center, diag, scale);
    let report = QemReport {
        input_vertices: referenced_vertices,
        input_faces,
        collapses,
        vertices: out.positions.len(),
        faces: out.triangles.len(),
        max_error: worst / scale4,
        seconds: started.elapsed().as_secs_f64(),
        target_reached: stop_reason == StopReason::TargetReached,
        stop_reason,
        rejected,
        virtual_pairs,
        passes: pass as usize,
    };
    Ok((out, report))
}

impl Engine {
    /// Compact into a `TriMesh`: live faces without duplicates, referenced vertices only (in
    /// original index order), positions mapped back to model units.
    fn output(&self, center: DVec3, diag: f64, scale: f64) -> TriMesh {
        let _ = diag;
        let mut tris: Vec<[u32; 3]> = self
            .faces
            .iter()
            .copied()
            .filter(|t| t[0] != DEAD)
            .collect();
        // Drop duplicate faces (same vertex set), keeping the first.
        let mut keys: Vec<([u32; 3], u32)> = tris
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let mut k = *t;
                k.sort_unstable();
                (k, i as u32)
            })
            .collect();
        keys.sort_unstable();
        let mut keep = vec![true; tris.len()];
        for w in keys.windows(2) {
            if w[0].0 == w[1].0 {
                keep[w[1].1 as usize] = false;
            }
        }
        let mut i = 0;
        tris.retain(|_| {
            i += 1;
            keep[i - 1]
        });
        let mut remap = vec![DEAD; self.vx.len()];
        for t in &tris {
            for &v in t {
                remap[v as usize] = 0;
            }
        }
        let mut positions = Vec::new();
        for (v, r) in remap.iter_mut().enumerate() {
            if *r == 0 {
                *r = positions.len() as u32;
                let p = self.vx[v].p / scale + center;
                positions.push(Vec3::new(p.x as f32, p.y as f32, p.z as f32));
            }
        }
        for t in &mut tris {
            for v in t.iter_mut() {
                *v = remap[*v as usize];
            }
        }
        TriMesh::new(positions, tris)
    }
}

/// What [`vertex_setup`] produces.
struct VertexSetup {
    /// Per vertex: position, quadric (face planes plus boundary planes), face list (`len` faces
    /// from `face_start`), valence and boundary flag.
    vx: Vec<Vertex>,
    /// The mesh edges `(u, v)`, `u < v`, in order of `u` (costs not yet evaluated).
    list: Vec<Cand>,
}

/// Up to this many faces around a vertex, [`vertex_setup`] finds ring neighbours by linear search.
const RING_SEARCH_MAX: usize = 32;
/// Vertices per parallel task of [`vertex_setup`].
const VERTEX_CHUNK: usize = 2_048;

/// Per-vertex setup over the vertex → face lists `refs` (vertex `u`'s faces start at
/// `face_start[u]`), one independent task per chunk of vertices: each vertex sums the area-weighted
/// plane quadrics of its faces (every face's plane is computed by each of its corners, identically)
/// and, from its ring of distinct neighbours with the number of faces on each edge, gets its
/// boundary flag, the perpendicular boundary planes of its boundary edges (computed from the
/// lower-numbered end, so both ends add the same plane) and its edges to higher-numbered vertices.
fn vertex_setup(
    pos: &[DVec3],
    faces: &[[u32; 3]],
    refs: &[u32],
    face_start: &[u32],
    params: &QemParams,
) -> VertexSetup {
    let n = pos.len();
    // Face planes scaled so that the plane quadric is their outer product: `g = n·√(area)`,
    // `gd = d·√(area)` (zero for degenerate faces).
    let plane = |t: &[u32; 3]| -> [f64; 4] {
        let [p0, p1, p2] = t.map(|w| pos[w as usize]);
        let cross = (p1 - p0).cross(p2 - p0);
        let len = cross.length();
        if len > 0.0 && len.is_finite() {
            let g = cross * (0.5 / len).sqrt();
            [g.x, g.y, g.z, -g.dot(p0)]
        } else {
            [0.0; 4]
        }
    };
    let planes: Vec<[f64; 4]> = if parallel(faces.len(), PARALLEL_MIN) {
        faces
            .par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .map(plane)
            .collect()
    } else {
        faces.iter().map(plane).collect()
    };
    let mut vx: Vec<Vertex> = Vec::with_capacity(n);
    let chunk = |first: usize, out: &mut [std::mem::MaybeUninit<Vertex>]| {
        let mut edges = Vec::with_capacity(out.len() * 3 + 16);
        // (neighbour, faces on the edge, last such face)
        let mut ring: Vec<(u32, u32, u32)> = Vec::with_capacity(64);
        for (k, slot) in out.iter_mut().enumerate() {
            let u = first + k;
            let uu = u as u32;
            let end = face_start.get(u + 1).map_or(refs.len(), |&e| e as usize);
            let list = &refs[face_start[u] as usize..end];
            let mut q = Quadric::default();
            ring.clear();
            for &f in list {
                let tri = faces[f as usize];
                let [gx, gy, gz, gd] = planes[f as usize];
                q += Quadric::from_plane(DVec3::new(gx, gy, gz), gd, 1.0);
                // The two other corners (every face in the list has `u` exactly once).
                let others = if tri[0] == uu {
                    [tri[1], tri[2]]
                } else if tri[1] == uu {
                    [tri[2], tri[0]]
                } else {
                    [tri[0], tri[1]]
                };
                if list.len() <= RING_SEARCH_MAX {
                    for v in others {
                        match ring.iter_mut().find(|r| r.0 == v) {
                            Some(r) => {
                                r.1 += 1;
                                r.2 = f;
                            }
                            None => ring.push((v, 1, f)),
                        }
                    }
                } else {
                    ring.extend(others.map(|v| (v, 1, f)));
                }
            }
            if list.len() > RING_SEARCH_MAX {
                // High valence: group by sorting instead of searching (stable: keeps the last face).
                ring.sort_by_key(|r| r.0);
                let mut w = 0;
                for r in 0..ring.len() {
                    if w > 0 && ring[w - 1].0 == ring[r].0 {
                        ring[w - 1].1 += 1;
                        ring[w - 1].2 = ring[r].2;
                    } else {
                        ring[w] = ring[r];
                        w += 1;
                    }
                }
                ring.truncate(w);
            }
            let mut on_boundary = false;
            for &(v, count, f) in &ring {
                on_boundary |= count != 2;
                if count == 1 && params.preserve_boundary {
                    let (lo, hi) = (uu.min(v) as usize, uu.max(v) as usize);
                    let [p0, p1, p2] = faces[f as usize].map(|w| pos[w as usize]);
                    let face_normal = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                    let edge = pos[hi] - pos[lo];
                    let m = edge.cross(face_normal).normalize_or_zero();
                    if m != DVec3::ZERO {
                        let w = params.boundary_weight * edge.length_squared();
                        q += Quadric::from_plane(m, -m.dot(pos[lo]), w);
                    }
                }
                if v > uu {
                    edges.push(Cand {
                        a: uu,
                        b: v,
                        ..Cand::default()
                    });
                }
            }
            slot.write(Vertex {
                p: pos[u],
                mark: 0,
                valence: list.len() as u32,
                q,
                start: face_start[u],
                len: list.len() as u32,
                touched: 0,
                alive: true,
                boundary: on_boundary,
            });
        }
        edges
    };
    let out = &mut vx.spare_capacity_mut()[..n];
    let lists: Vec<Vec<Cand>> = if parallel(n, PARALLEL_MIN / 4) {
        out.par_chunks_mut(VERTEX_CHUNK)
            .enumerate()
            .map(|(c, o)| chunk(c * VERTEX_CHUNK, o))
            .collect()
    } else {
        vec![chunk(0, out)]
    };
    // SAFETY: every chunk wrote each of its slots exactly once, and the chunks cover `0..n`.
    unsafe { vx.set_len(n) };
    let list = if lists.len() == 1 {
        lists.into_iter().next().unwrap_or_default()
    } else {
        let mut list = Vec::with_capacity(lists.iter().map(Vec::len).sum());
        for l in &lists {
            list.extend_from_slice(l);
        }
        list
    };
    VertexSetup { vx, list }
}

/// 30-bit Morton code of a point of the normalised frame (coordinates within ±1).
fn morton(p: DVec3) -> u64 {
    fn spread(x: f64) -> u64 {
        let mut v = (((x + 1.0) * 512.0).clamp(0.0, 1023.0)) as u64;
        v = (v | (v << 16)) & 0x0300_00ff;
        v = (v | (v << 8)) & 0x0300_f00f;
        v = (v | (v << 4)) & 0x030c_30c3;
        (v | (v << 2)) & 0x0924_9249
    }
    spread(p.x) | (spread(p.y) << 1) | (spread(p.z) << 2)
}

/// Whether the candidate still describes the current pair: neither end contracted (or merged
/// away, which also bumps its stamp) since it was evaluated. Stamps only grow, so the sum cannot
/// come back to an old value short of 2³² contractions.
#[inline]
fn is_live(c: &Cand, stamps: &[u32]) -> bool {
    stamps[c.a as usize].wrapping_add(stamps[c.b as usize]) == c.stamp
}

/// Write into `out` the merge of the sorted unvisited rest `list[consumed..]` of the candidate
/// list (dropping stale entries, so that later passes neither copy nor walk them) with the sorted
/// fresh list `fresh` (all live); on equal sort keys carried entries come first. One sequential
/// read and write; the caller swaps `out` and `list` (both buffers are kept for the whole run).
fn merge_live(list: &[Cand], consumed: usize, fresh: &[Cand], stamps: &[u32], out: &mut Vec<Cand>) {
    out.clear();
    out.reserve(list.len() - consumed + fresh.len());
    let mut j = 0;
    for c in &list[consumed..] {
        if !is_live(c, stamps) {
            continue;
        }
        let k = sort_key(c.key);
        while j < fresh.len() && sort_key(fresh[j].key) < k {
            out.push(fresh[j]);
            j += 1;
        }
        out.push(*c);
    }
    out.extend_from_slice(&fresh[j..]);
}

fn validate(p: &QemParams) -> Result<(), QemError> {
    let bad = |s: String| Err(QemError::InvalidParameter(s));
    if let Target::Ratio(r) = p.target
        && !(r > 0.0 && r <= 1.0)
    {
        return bad(format!("target ratio {r} is not in (0, 1]"));
    }
    if !(p.pair_threshold >= 0.0 && p.pair_threshold.is_finite()) {
        return bad(format!(
            "pair threshold {} must be finite and >= 0",
            p.pair_threshold
        ));
    }
    if !(p.boundary_weight >= 0.0 && p.boundary_weight.is_finite()) {
        return bad(format!(
            "boundary weight {} must be finite and >= 0",
            p.boundary_weight
        ));
    }
    if let Some(m) = p.max_error
        && m.is_nan()
    {
        return bad("max error is NaN".into());
    }
    if !(-1.0..=1.0).contains(&p.min_normal_cos) {
        return bad(format!(
            "min_normal_cos {} is not in [-1, 1]",
            p.min_normal_cos
        ));
    }
    Ok(())
}

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
use std::time::Instant;

/// Marks a dead face (in its first slot) and an empty linked list.
const DEAD: u32 = u32::MAX;
/// How many candidates ahead the pass loop prefetches vertex data.
const PREFETCH_DISTANCE: usize = 8;

/// A candidate pair with its cost (as `f32` bits, which order like the non-negative cost).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
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

/// Geometry of a vertex in the normalised frame.
#[derive(Debug, Clone, Copy, Default)]
struct VertexData {
    q: Quadric,
    p: DVec3,
}

/// Per-vertex bookkeeping.
#[derive(Debug, Clone, Copy, Default)]
struct VertexInfo {
    /// Start of the face list in `refs`.
    start: u32,
    /// Length of the face list (may include dead faces).
    len: u32,
    /// Live faces around the vertex.
    valence: u32,
    /// Pass in which the vertex was last touched by a contraction.
    touched: u32,
    /// Scratch mark (compared with `Engine::tick`).
    mark: u32,
    /// Not merged into another vertex.
    alive: bool,
    /// On a boundary edge (or a non-manifold edge).
    boundary: bool,
}

/// Mutable simplification state.
struct Engine {
    /// Quadric and position per vertex (read together by every evaluation).
    vd: Vec<VertexData>,
    /// Topology bookkeeping per vertex, packed so one cache line serves a vertex.
    v: Vec<VertexInfo>,
    /// Version per vertex, bumped by every contraction of the vertex (a separate compact array:
    /// the candidate walks test it for every entry, in cost order, i.e. at random).
    stamps: Vec<u32>,
    faces: Vec<[u32; 3]>,
    refs: Vec<u32>,
    refs_limit: usize,
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

impl Engine {
    /// Hint the CPU to load the bookkeeping and geometry of `a` and `b` (candidate list walks visit
    /// vertices in cost order, i.e. at random).
    #[inline]
    fn prefetch(&self, a: usize, b: usize) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            for i in [a, b] {
                if i < self.v.len() {
                    // SAFETY: prefetching is only a hint and the pointers are in bounds.
                    unsafe {
                        _mm_prefetch::<_MM_HINT_T0>(self.v.as_ptr().add(i).cast());
                        let d = self.vd.as_ptr().add(i).cast::<i8>();
                        _mm_prefetch::<_MM_HINT_T0>(d);
                        _mm_prefetch::<_MM_HINT_T0>(d.add(64));
                    }
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (a, b);
    }

    #[inline]
    fn list(&self, v: usize) -> std::ops::Range<usize> {
        let s = self.v[v].start as usize;
        s..s + self.v[v].len as usize
    }

    #[inline]
    fn next_tick(&mut self) -> u32 {
        self.tick = self.tick.wrapping_add(1);
        if self.tick == 0 {
            for v in &mut self.v {
                v.mark = 0;
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
        let (da, db) = (&self.vd[a], &self.vd[b]);
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

    /// Append the pairs of the merged vertex `a` (mesh edges and non-edge pairs) to `out`; a pair
    /// with another vertex touched in pass `pass` is produced by the smaller index only.
    fn pairs_of(&mut self, a: usize, pass: u32, out: &mut Vec<Cand>) {
        let t = self.next_tick();
        self.v[a].mark = t;
        let keep = |e: &Self, v: usize| e.v[v].touched != pass || a < v;
        for i in self.list(a) {
            let tri = self.faces[self.refs[i] as usize];
            if tri[0] == DEAD {
                continue;
            }
            for v in tri {
                let v = v as usize;
                if self.v[v].mark != t {
                    self.v[v].mark = t;
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
                if self.v[o].alive && self.v[o].mark != t {
                    self.v[o].mark = t;
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
        let p1 = self.vd[i1 as usize].p;
        let p2 = self.vd[i2 as usize].p;
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
        let pa = self.vd[a].p;
        for i in self.list(a) {
            let t = self.faces[self.refs[i] as usize];
            if t[0] == DEAD {
                continue;
            }
            alive_a += 1;
            for v in t {
                self.v[v as usize].mark = ta;
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
        if shared > 2 || (shared == 2 && self.v[a].boundary && self.v[b].boundary) {
            return false;
        }
        // Link condition: common neighbours must be exactly the opposite vertices.
        let tb = self.next_tick();
        let mut common = 0usize;
        let mut alive_b = 0usize;
        let (c, d) = (opp[0], opp[1]);
        let mut b_has_cd = false;
        let pb = self.vd[b].p;
        for i in self.list(b) {
            let t = self.faces[self.refs[i] as usize];
            if t[0] == DEAD {
                continue;
            }
            alive_b += 1;
            for v in t {
                if v != au && v != bu && self.v[v as usize].mark == ta {
                    self.v[v as usize].mark = tb;
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
            if self.v[o as usize].valence < 2 {
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
        self.vd[a].p = p;
        let qb = self.vd[b].q;
        self.vd[a].q += qb;
        self.v[a].boundary |= self.v[b].boundary;
        self.v[b].alive = false;
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
                self.v[third as usize].valence -= 1;
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
        self.v[a].start = start as u32;
        self.v[a].len = (self.refs.len() - start) as u32;
        self.v[b].len = 0;
        self.v[a].valence = self.v[a].len;
        self.v[b].valence = 0;
        if let Some(vp) = self.virt.as_mut() {
            vp.merge(a, b);
        }
        if self.refs.len() > self.refs_limit {
            self.compact_refs();
        }
    }

    /// Rewrite the face lists without dead faces and free space.
    fn compact_refs(&mut self) {
        let mut fresh = Vec::with_capacity(self.refs_limit);
        for v in 0..self.v.len() {
            let range = self.list(v);
            let start = fresh.len();
            if self.v[v].alive {
                for i in range {
                    let f = self.refs[i];
                    if self.faces[f as usize][0] != DEAD {
                        fresh.push(f);
                    }
                }
            }
            self.v[v].start = start as u32;
            self.v[v].len = (fresh.len() - start) as u32;
        }
        self.refs = fresh;
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
    let mut face_len = vec![0u32; n];
    for t in &faces {
        for &v in t {
            face_len[v as usize] += 1;
        }
    }
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for (i, p) in input.positions.iter().enumerate() {
        if face_len[i] > 0 {
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
        .filter(|&i| face_len[i] > 0)
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
    drop(order);
    let n = pos.len();
    let mut keyed: Vec<u64> = faces
        .iter()
        .enumerate()
        .map(|(f, t)| {
            let m = t.iter().map(|&v| new_index[v as usize]).min().unwrap_or(0);
            (u64::from(m) << 32) | f as u64
        })
        .collect();
    sort_by_u32_key(&mut keyed, &mut scratch64, |&k| (k >> 32) as u32);
    drop(scratch64);
    let faces: Vec<[u32; 3]> = keyed
        .iter()
        .map(|&k| faces[k as u32 as usize].map(|v| new_index[v as usize]))
        .collect();
    drop(keyed);
    drop(new_index);
    let mut face_len = vec![0u32; n];
    for t in &faces {
        for &v in t {
            face_len[v as usize] += 1;
        }
    }

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

    // Area-weighted face quadrics.
    let mut vd: Vec<VertexData> = pos
        .iter()
        .map(|&p| VertexData {
            q: Quadric::default(),
            p,
        })
        .collect();
    drop(pos);
    for t in &faces {
        let [p0, p1, p2] = t.map(|v| vd[v as usize].p);
        let cross = (p1 - p0).cross(p2 - p0);
        let len = cross.length();
        if len > 0.0 && len.is_finite() {
            let nrm = cross / len;
            let q = Quadric::from_plane(nrm, -nrm.dot(p0), 0.5 * len);
            for &v in t {
                vd[v as usize].q += q;
            }
        }
    }

    let referenced_vertices = n;
    let input_faces = faces.len();
    let refs_limit = (refs.len() * 3).max(1024);
    let v: Vec<VertexInfo> = (0..n)
        .map(|i| VertexInfo {
            start: face_start[i],
            len: face_len[i],
            valence: face_len[i],
            alive: true,
            ..Default::default()
        })
        .collect();
    let mut e = Engine {
        vd,
        v,
        stamps: vec![0; n],
        faces,
        refs,
        refs_limit,
        tick: 0,
        scratch: Vec::new(),
        virt: None,
        live_faces: input_faces,
        live_vertices: referenced_vertices,
        preserve_topology: params.preserve_topology,
        min_normal_cos: params.min_normal_cos,
    };

    // Edges, boundary detection and boundary constraint planes: for each vertex, its distinct
    // neighbours with the number of faces on the edge and one of those faces.
    let mut ring_slot = vec![0u32; n];
    let mut ring: Vec<(u32, u32, u32)> = Vec::new();
    let mut edges: Vec<[u32; 2]> = Vec::with_capacity(input_faces * 3 / 2 + 16);
    for u in 0..n {
        if e.v[u].len == 0 {
            continue;
        }
        let t = e.next_tick();
        ring.clear();
        let uu = u as u32;
        for i in e.list(u) {
            let f = e.refs[i];
            let tri = e.faces[f as usize];
            // The two other corners (every face in the list has `u` exactly once).
            let others = if tri[0] == uu {
                [tri[1], tri[2]]
            } else if tri[1] == uu {
                [tri[2], tri[0]]
            } else {
                [tri[0], tri[1]]
            };
            for v in others {
                let vi = v as usize;
                if e.v[vi].mark != t {
                    e.v[vi].mark = t;
                    ring_slot[vi] = ring.len() as u32;
                    ring.push((v, 1, f));
                } else {
                    let r = &mut ring[ring_slot[vi] as usize];
                    r.1 += 1;
                    r.2 = f;
                }
            }
        }
        for &(v, count, f) in &ring {
            let vi = v as usize;
            if count != 2 {
                e.v[u].boundary = true;
            }
            if vi > u {
                edges.push([u as u32, v]);
                if count == 1 && params.preserve_boundary {
                    let [p0, p1, p2] = e.faces[f as usize].map(|w| e.vd[w as usize].p);
                    let face_normal = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                    let edge = e.vd[vi].p - e.vd[u].p;
                    let m = edge.cross(face_normal).normalize_or_zero();
                    if m != DVec3::ZERO {
                        let w = params.boundary_weight * edge.length_squared();
                        let q = Quadric::from_plane(m, -m.dot(e.vd[u].p), w);
                        e.vd[u].q += q;
                        e.vd[vi].q += q;
                    }
                }
            }
        }
    }
    drop(ring_slot);

    // Non-edge pairs within the threshold.
    let mut virtual_pairs = 0;
    if params.pair_threshold > 0.0 {
        let used: Vec<bool> = e.v.iter().map(|v| v.len > 0).collect();
        let positions: Vec<DVec3> = e.vd.iter().map(|d| d.p).collect();
        let close = pairs::close_pairs(
            &positions,
            &used,
            params.pair_threshold * scale,
            params.max_pairs_per_vertex,
        );
        let mut sorted_edges = edges.clone();
        sorted_edges.sort_unstable();
        let non_edge: Vec<[u32; 2]> = close
            .into_iter()
            .filter(|p| sorted_edges.binary_search(p).is_err())
            .collect();
        virtual_pairs = non_edge.len();
        edges.extend_from_slice(&non_edge);
        e.virt = Some(VirtualPairs::new(n, &non_edge));
    }

    let mut list: Vec<Cand> = edges
        .iter()
        .map(|&[u, v]| e.candidate(u as usize, v as usize))
        .collect();
    drop(edges);
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
    let mut next: Vec<Cand> = Vec::with_capacity(list.len());
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
        for (i, c) in list.iter().enumerate() {
            if let Some(ahead) = list.get(i + PREFETCH_DISTANCE)
                && is_live(ahead, &e.stamps)
            {
                e.prefetch(ahead.a as usize, ahead.b as usize);
            }
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
            let (a, b) = if e.v[b].len > e.v[a].len {
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
            e.v[a].touched = pass;
            e.v[b].touched = pass;
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
            for v in 0..e.v.len() {
                e.v[v].touched = pass; // so that each pair is produced once, by its smaller index
            }
            for v in 0..e.v.len() {
                if e.v[v].alive && e.v[v].len > 0 {
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
        for &a in &survivors {
            e.pairs_of(a as usize, pass, &mut fresh);
        }
        sort_by_u32_key(&mut fresh, &mut sort_tmp, |c| sort_key(c.key));
        next.clear();
        merge_live(&list[consumed..], &fresh, &e.stamps, &mut next);
        std::mem::swap(&mut list, &mut next);
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
        let mut remap = vec![DEAD; self.v.len()];
        for t in &tris {
            for &v in t {
                remap[v as usize] = 0;
            }
        }
        let mut positions = Vec::new();
        for (v, r) in remap.iter_mut().enumerate() {
            if *r == 0 {
                *r = positions.len() as u32;
                let p = self.vd[v].p / scale + center;
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

/// Merge the sorted carried list `x` (dropping its stale entries, so that later passes neither
/// copy nor walk them) with the sorted fresh list `y` (all live) into `out`.
fn merge_live(x: &[Cand], y: &[Cand], stamps: &[u32], out: &mut Vec<Cand>) {
    out.reserve(x.len() + y.len());
    let mut j = 0;
    for c in x {
        if !is_live(c, stamps) {
            continue;
        }
        let k = sort_key(c.key);
        while j < y.len() && sort_key(y[j].key) < k {
            out.push(y[j]);
            j += 1;
        }
        out.push(*c);
    }
    out.extend_from_slice(&y[j..]);
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

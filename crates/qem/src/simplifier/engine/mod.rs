//! The contraction engine: per-vertex records in one cache-line-aligned array, per-vertex face
//! lists in one growing buffer (CSR-like, rewritten on collapse and compacted now and then), the
//! pair costing and placement, the topology / normal checks and the collapse itself. What to
//! contract, and when, is decided by the pass loop ([`super::passes`]).

mod stages;

use super::attribute_error::AttributeError;
use super::candidates::{Cand, key_of};
use super::prefetch;
use super::prepare::Frame;
use super::resources::{PARALLEL_CHUNK, PARALLEL_MIN, parallel};
use super::seams::Seams;
use super::triangle::{DEAD, contains, segment_parameter};
use super::vertex::Vertex;
use super::wedges::{WedgeValues, fan_sides};
use crate::pairs::VirtualPairs;
use crate::{QemParams, Quadric};
use glam::DVec3;
use mesh::TriMesh;
use rayon::prelude::*;

/// Mutable simplification state.
pub(super) struct Engine {
    /// Geometry and bookkeeping per vertex.
    pub(super) vx: Vec<Vertex>,
    /// Generation in which each vertex was last contracted, 0 if never (a separate compact
    /// array: the candidate walks test it for every entry, in cost order, i.e. at random).
    pub(super) contracted: Vec<u16>,
    /// The generation pairs are costed in now (see `candidates::is_live`).
    pub(super) generation: u32,
    /// Faces (vertex triples; [`DEAD`] in the first slot once removed).
    pub(super) faces: Vec<[u32; 3]>,
    /// Face lists, appended to on every collapse (capacity reserved up to `refs_limit`).
    pub(super) refs: Vec<u32>,
    /// Length of `refs` above which it is compacted (verbatim: the lists keep their dead faces).
    refs_limit: usize,
    /// What `refs` would hold had it only ever been compacted by dropping dead faces, at three
    /// times its length (the rule until 2026-12-05), and that length: such a compaction shortens
    /// the lists, and the list lengths decide which end of a pair is kept, so it still happens
    /// exactly when it used to, and the output does not depend on the verbatim compactions.
    lists_total: usize,
    /// See `lists_total`.
    lists_limit: usize,
    /// The other buffer of the compaction.
    refs_spare: Vec<u32>,
    /// Current scratch-mark value.
    tick: u32,
    /// Faces of the collapsed vertex that move to the survivor (reused by every collapse).
    scratch: Vec<u32>,
    /// Non-edge pairs, when `pair_threshold > 0`.
    pub(super) virt: Option<VirtualPairs>,
    /// Faces not yet removed.
    pub(super) live_faces: usize,
    /// Vertices not yet merged away.
    pub(super) live_vertices: usize,
    preserve_topology: bool,
    min_normal_cos: f64,
    /// `QemParams::edge_length_weight` (0: none).
    edge_length_weight: f64,
    /// Whether the walks in cost order prefetch ([`prefetch::worth_it`]).
    pub(super) prefetching: bool,
    /// Attribute seams, when the run keeps attributes (`None`: positions only).
    pub(super) seams: Option<Seams>,
    /// Attribute error quadrics, when the run keeps attributes with a non-zero weight (`None`:
    /// the cost is the geometric one). Outside `Vertex`: positions-only runs keep their
    /// 128-byte record.
    pub(super) attr: Option<AttributeError>,
    /// The attribute values carried through the contractions, when the run keeps attributes.
    pub(super) values: Option<WedgeValues>,
    /// Summed face area of each vertex's quadric (normalised frame), with
    /// `QemParams::max_relative_error` only.
    pub(super) area: Option<Vec<f64>>,
}

/// The length `refs` may grow to from `len` before it is compacted verbatim: the room for the
/// appended lists is reserved up front (growing by doubling would copy and fault in pages), and
/// only the part the appends reach is touched. Twice the length for large meshes since
/// 2026-12-05 (three times before, and compactions dropped dead faces): on igea-1m at 10 % the
/// lists are now compacted once, after the third pass, instead of growing into their room to
/// the end (docs/notes/qem.md).
fn refs_limit(len: usize) -> usize {
    if len >= TWICE_MIN_REFS {
        len * 2
    } else {
        lists_limit(len)
    }
}

/// Face lists shorter than this (entries; 3 a face) keep three times their length of room: their
/// room is not at a peak that matters, and a compaction costs a sweep over the vertex records.
const TWICE_MIN_REFS: usize = 1_200_000;

/// The length of `lists_total` past which the lists are compacted dropping their dead faces (the
/// only compaction until 2026-12-05: the same moments, so the same output).
fn lists_limit(len: usize) -> usize {
    (len * 3).max(1024)
}

impl Engine {
    /// The engine over the set-up vertex records `vx`, the (renumbered, sorted) `faces` and the
    /// vertex → face lists `refs` that the records point into.
    pub(super) fn new(
        vx: Vec<Vertex>,
        faces: Vec<[u32; 3]>,
        mut refs: Vec<u32>,
        params: &QemParams,
    ) -> Engine {
        let refs_limit = refs_limit(refs.len());
        // Room for the appended lists up front: growing by doubling would copy and fault in pages.
        refs.reserve(refs_limit + 64 - refs.len());
        let n = vx.len();
        Engine {
            vx,
            contracted: vec![0; n],
            generation: 0,
            live_faces: faces.len(),
            faces,
            lists_total: refs.len(),
            lists_limit: lists_limit(refs.len()),
            refs,
            refs_limit,
            refs_spare: Vec::new(),
            tick: 0,
            scratch: Vec::new(),
            virt: None,
            live_vertices: n,
            preserve_topology: params.preserve_topology,
            min_normal_cos: params.min_normal_cos,
            edge_length_weight: params.edge_length_weight,
            prefetching: prefetch::worth_it(n),
            seams: None,
            attr: None,
            values: None,
            area: None,
        }
    }

    #[inline]
    pub(super) fn list(&self, v: usize) -> std::ops::Range<usize> {
        self.vx[v].list()
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
        Self::place_on_segment(q, pa, pb)
    }

    /// The quadric's best point in the plane through the seam edge `a`–`b` that holds the
    /// edge and its faces' mean normal (so the point may move along the seam and off the
    /// surface, not across the seam); the segment's best point when that plane's system is
    /// degenerate or its point falls far from the edge.
    fn place_in_seam_plane(&self, q: &Quadric, a: usize, b: usize) -> (f64, DVec3) {
        let (pa, pb) = (self.vx[a].p, self.vx[b].p);
        let d = pb - pa;
        let len2 = d.length_squared();
        let mut normal = DVec3::ZERO;
        for i in self.list(a) {
            let t = self.faces[self.refs[i] as usize];
            if t[0] != DEAD && contains(&t, b as u32) {
                let [p0, p1, p2] = t.map(|w| self.vx[w as usize].p);
                normal += (p1 - p0).cross(p2 - p0).normalize_or_zero();
            }
        }
        let e1 = d.normalize_or_zero();
        let e2 = (normal - e1 * e1.dot(normal)).normalize_or_zero();
        if e1 == DVec3::ZERO || e2 == DVec3::ZERO {
            return Self::place_on_segment(q, pa, pb);
        }
        // x = pa + u e1 + v e2: minimise E(x) = xᵀAx + 2bᵀx + c over (u, v).
        let g = q.mul_a(pa) + q.b_vec();
        let (ae1, ae2) = (q.mul_a(e1), q.mul_a(e2));
        let (h11, h12, h22) = (e1.dot(ae1), e1.dot(ae2), e2.dot(ae2));
        let (g1, g2) = (e1.dot(g), e2.dot(g));
        let det = h11 * h22 - h12 * h12;
        if det > 1e-12 * (h11 * h22).abs().max(f64::MIN_POSITIVE) {
            let u = (-g1 * h22 + g2 * h12) / det;
            let v = (g1 * h12 - g2 * h11) / det;
            let x = pa + e1 * u + e2 * v;
            if (x - 0.5 * (pa + pb)).length_squared() <= 9.0 * len2 {
                return (q.eval(x), x);
            }
        }
        Self::place_on_segment(q, pa, pb)
    }

    /// The best point of the segment `pa`–`pb`, else the best of the ends and the midpoint.
    #[inline]
    fn place_on_segment(q: &Quadric, pa: DVec3, pb: DVec3) -> (f64, DVec3) {
        let d = pb - pa;
        let len2 = d.length_squared();
        let mid = 0.5 * (pa + pb);
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
    pub(super) fn evaluate(&self, a: usize, b: usize) -> (f64, DVec3) {
        let (da, db) = (&self.vx[a], &self.vx[b]);
        let q = da.q + db.q;
        let anchor = self.seams.as_ref().and_then(|s| s.anchor(a, b));
        let (cost, p) = match anchor {
            Some(v) => (q.eval(self.vx[v].p), self.vx[v].p),
            // Two movable seam vertices along their seam: in the plane that holds their seam
            // edge and its faces' normal, so the seam stays where it was on the surface. The
            // seam planes held it there at weight 15; at weight 1
            // ([`crate::QemParams::seam_weight`]) the free minimiser let it slide: spot at 25 %,
            // each output wedge's UV against the original's at the closest point (test
            // `spot_keeps_its_texture_coordinates_where_they_were`), 95th percentile 5.3 % of the
            // texture, 1.04 % in the plane (0.96 % at weight 15, free). On the segment instead:
            // 0.46 %, but 1.3-1.6 × spot's Hausdorff distance; on an end (meshoptimizer's
            // collapse) 1.2-1.6 × on spot and the fandisk atlas (docs/notes/attributes.md,
            // "Seam plane weight, again").
            None if self.seams.as_ref().is_some_and(|s| s.seam[a]) => {
                self.place_in_seam_plane(&q, a, b)
            }
            None => Self::place(&q, da.p, db.p),
        };
        let mut cost = cost.max(0.0);
        if self.edge_length_weight > 0.0 {
            let len2 = da.p.distance_squared(db.p);
            cost += self.edge_length_weight * len2 * len2;
        }
        if let (Some(attr), Some(seams)) = (&self.attr, &self.seams) {
            cost += attr.error(a, b, p, seams);
        }
        (cost, p)
    }

    #[inline]
    fn candidate(&self, a: usize, b: usize) -> Cand {
        let (cost, _) = self.evaluate(a, b);
        Cand {
            key: key_of(cost, self.generation),
            a: a as u32,
            b: b as u32,
        }
    }

    /// Evaluate every pair of `list` (the `a` and `b` fields are set; sorted by `a`, so only the
    /// records of the `b` ends are prefetched), in parallel for large lists.
    pub(super) fn cost_all(&self, list: &mut [Cand]) {
        let cost = |chunk: &mut [Cand]| {
            for i in 0..chunk.len() {
                if self.prefetching
                    && let Some(ahead) = chunk.get(i + prefetch::RECORDS)
                {
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
    pub(super) fn fresh_pairs(&mut self, survivors: &[u32], pass: u32, fresh: &mut Vec<Cand>) {
        for (i, &a) in survivors.iter().enumerate() {
            if self.prefetching {
                self.prefetch_survivors(survivors, i);
            }
            self.pairs_of(a as usize, pass, fresh);
        }
    }

    /// Append the pairs of the merged vertex `a` (mesh edges and non-edge pairs) to `out`; a pair
    /// with another vertex touched in pass `pass` is produced by the smaller index only.
    pub(super) fn pairs_of(&mut self, a: usize, pass: u32, out: &mut Vec<Cand>) {
        let t = self.next_tick();
        self.vx[a].mark = t;
        let keep = |e: &Self, v: usize| {
            (e.vx[v].touched != pass || a < v)
                && !e.vx[v].locked
                && e.seams.as_ref().is_none_or(|s| s.pair_ok(a, v))
        };
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
            while !VirtualPairs::is_end(node) {
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
    pub(super) fn allowed(&mut self, a: usize, b: usize, p: DVec3) -> bool {
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
    pub(super) fn collapse(&mut self, a: usize, b: usize, p: DVec3) {
        let (au, bu) = (a as u32, b as u32);
        let t = match self.values {
            Some(_) => segment_parameter(self.vx[a].p, self.vx[b].p, p),
            None => 0.0,
        };
        // The side of seam vertex `a` that `b`, off the seams, joins: found before the faces
        // move (only the attribute error needs it).
        let side = match (&self.attr, &self.seams) {
            (Some(_), Some(seams)) if seams.anchor(a, b) == Some(a) => self.side_of(a, b, seams),
            _ => 0,
        };
        // Into a fixed seam vertex: the faces that move onto `a` take its input wedge on their
        // side of b's seam, from the face of the edge a-b on that side.
        let fixed_wedges = match &self.seams {
            Some(seams) if self.values.is_some() && seams.is_fixed(a) => {
                self.fixed_wedges(a, b, seams)
            }
            _ => None,
        };
        self.vx[a].p = p;
        let qb = self.vx[b].q;
        self.vx[a].q += qb;
        self.vx[a].boundary |= self.vx[b].boundary;
        self.vx[b].alive = false;
        self.contracted[a] = self.generation as u16;
        self.contracted[b] = self.generation as u16;
        self.live_vertices -= 1;
        self.scratch.clear();
        for (j, i) in self.list(b).enumerate() {
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
                if let (Some(w), Some(values)) = (&fixed_wedges, self.values.as_mut()) {
                    values.set_corner_wedge(f, au, t, w[usize::from(w.len() > 2 && w[2 + j] != 0)]);
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
        if let Some(area) = self.area.as_mut() {
            area[a] += area[b];
        }
        if let Some(seams) = self.seams.as_mut() {
            // Before the seams merge: the sides are matched by the seam neighbours of `a`, `b`.
            if let Some(attr) = self.attr.as_mut() {
                attr.merge(a, b, seams, side);
            }
            if let Some(values) = self.values.as_mut() {
                values.merge(a, b, t, seams);
            }
            seams.merge(a, b);
        }
        self.lists_total += self.refs.len() - start;
        if self.lists_total > self.lists_limit {
            self.compact_refs(true);
        } else if self.refs.len() > self.refs_limit {
            self.compact_refs(false);
        }
    }

    /// The side of seam vertex `a` ([`fan_sides`]) that its neighbour `b`, off the seams, lies on.
    /// For `b` contracted into the fixed seam vertex `a`: a's input wedges `[w0, w1]` for b's
    /// faces on side 0 and 1 (from the faces of the edge a-b), then, when `b` is on a seam, the
    /// side of each entry of b's face list (0 or 1, as `u32`); `None` without a face of a-b.
    fn fixed_wedges(&self, a: usize, b: usize, seams: &Seams) -> Option<Vec<u32>> {
        let values = self.values.as_ref()?;
        let au = a as u32;
        let wedge_of = |f: usize| values.corner_wedge(f, au, &self.faces[f]);
        let live = |i: usize| self.faces[self.refs[i] as usize][0] != DEAD;
        if !seams.seam[b] {
            // Off the seams: b's faces are all on one side.
            let f = self
                .list(b)
                .map(|i| self.refs[i] as usize)
                .find(|&f| self.faces[f][0] != DEAD && contains(&self.faces[f], au))?;
            return Some(vec![wedge_of(f); 2]);
        }
        let fan: Vec<u32> = self
            .list(b)
            .filter(|&i| live(i))
            .map(|i| self.refs[i])
            .collect();
        let (mut reached, mut stack) = (Vec::new(), Vec::new());
        let [n0, n1] = seams.along[b];
        let faces = |f: u32| self.faces[f as usize];
        fan_sides(&fan, faces, [b as u32, n0, n1], &mut reached, &mut stack);
        let mut w = [None; 2];
        for (&f, &r) in fan.iter().zip(&reached) {
            if contains(&self.faces[f as usize], au) {
                w[usize::from(!r)] = Some(wedge_of(f as usize));
            }
        }
        let (w0, w1) = (w[0].or(w[1])?, w[1].or(w[0])?);
        let mut out = vec![w0, w1];
        let mut k = 0;
        for i in self.list(b) {
            let side = if live(i) {
                k += 1;
                u32::from(!reached[k - 1])
            } else {
                0
            };
            out.push(side);
        }
        Some(out)
    }

    fn side_of(&self, a: usize, b: usize, seams: &Seams) -> usize {
        let fan: Vec<u32> = self
            .list(a)
            .map(|i| self.refs[i])
            .filter(|&f| self.faces[f as usize][0] != DEAD)
            .collect();
        let (mut reached, mut stack) = (Vec::new(), Vec::new());
        let [n0, n1] = seams.along[a];
        let faces = |f: u32| self.faces[f as usize];
        fan_sides(&fan, faces, [a as u32, n0, n1], &mut reached, &mut stack);
        let with_b = fan
            .iter()
            .position(|&f| contains(&self.faces[f as usize], b as u32));
        match with_b {
            Some(i) if !reached[i] && reached.iter().any(|&r| r) => 1,
            _ => 0,
        }
    }

    /// Rewrite the face lists without the space of abandoned lists; with `drop_dead`, also
    /// without dead faces (which shortens the lists).
    fn compact_refs(&mut self, drop_dead: bool) {
        // Into the spare buffer (kept between compactions: no fresh pages to fault in).
        let mut fresh = std::mem::take(&mut self.refs_spare);
        fresh.clear();
        // Room for the growth after it (`refs_limit` of at most the present length).
        fresh.reserve(refs_limit(self.refs.len()) + 64);
        for v in 0..self.vx.len() {
            let range = self.list(v);
            let start = fresh.len();
            if self.vx[v].alive {
                if drop_dead {
                    for i in range {
                        let f = self.refs[i];
                        if self.faces[f as usize][0] != DEAD {
                            fresh.push(f);
                        }
                    }
                } else {
                    fresh.extend_from_slice(&self.refs[range]);
                }
            }
            self.vx[v].start = start as u32;
            self.vx[v].len = (fresh.len() - start) as u32;
        }
        self.refs_spare = std::mem::replace(&mut self.refs, fresh);
        self.refs_limit = refs_limit(self.refs.len());
        if drop_dead {
            self.lists_total = self.refs.len();
            self.lists_limit = lists_limit(self.refs.len());
        }
    }

    /// The result as a `TriMesh` in model units: the live faces, duplicates removed (two faces
    /// can end up on the same three vertices), and the referenced vertices only, in index order
    /// (both steps are `mesh::clean`'s); also returns the engine index of each output vertex.
    pub(super) fn output(&self, frame: &Frame) -> (TriMesh, Vec<u32>) {
        let faces = self
            .faces
            .iter()
            .copied()
            .filter(|t| t[0] != DEAD)
            .collect();
        // Positions are filled in below, for the referenced vertices only.
        let mut out = TriMesh::new(Vec::new(), faces);
        mesh::clean::drop_degenerate_and_duplicate_faces_in_place(&mut out);
        let kept = mesh::clean::compact_vertex_indices(&mut out.triangles, self.vx.len());
        out.positions = kept
            .iter()
            .map(|&v| frame.to_model(self.vx[v as usize].p))
            .collect();
        (out, kept)
    }
}

//! The attribute values of an attribute run, carried through the contractions (as
//! meshoptimizer keeps its wedges) instead of looked up on the original surface afterwards.
//!
//! Each engine vertex holds one set of values per side of the seam through it: side 0 is the
//! fan on the left of the seam walked from `along[0]` through the vertex to `along[1]` (the
//! faces reached from the one holding the directed edge vertex → `along[1]` without crossing
//! the seam), side 1 the rest; a vertex off the seams uses side 0 only. When `b` is contracted
//! into `a` at `p`, each side of `a` becomes the interpolation of its values and those of the
//! matching side of `b` ([`Seams::matching`]) at the parameter of `p`'s projection onto the
//! segment `a`–`b`: the values the original surface had between the two, to first order.
//!
//! A vertex never merged keeps every corner's own input wedge, exactly: that covers the seam
//! ends, crossings and poles (locked, with more than two sets of values) and the vertices the
//! target left alone. The output's corners take their vertex's set on the corner's side; the
//! side of a merged seam vertex's faces is found by the same fan walk as the input's
//! ([`fan_sides`]).
//!
//! Measured against the closest-point transfer it replaces (docs/notes/attributes.md, "Values
//! from the contractions"): see the note for the texture error and time figures.

use super::attributes::View;
use super::engine::{DEAD, Engine, Seams, corner_after};
use super::prepare::Frame;
use glam::{DVec3, Vec2, Vec3, Vec4};
use mesh::TriMesh;
use mesh::attributes::Attributes;

/// Which attributes a run carries, and where each sits in a side's components.
#[derive(Debug, Clone, Copy)]
struct Layout {
    normals: Option<usize>,
    uv0: Option<usize>,
    uv1: Option<usize>,
    colors: Option<usize>,
    /// Components per side.
    stride: usize,
}

impl Layout {
    fn of(attributes: &Attributes) -> Layout {
        let mut stride = 0;
        let mut slot = |present: bool, dims: usize| {
            present.then(|| {
                stride += dims;
                stride - dims
            })
        };
        let normals = slot(attributes.normals.is_some(), 3);
        let uv0 = slot(attributes.uv0.is_some(), 2);
        let uv1 = slot(attributes.uv1.is_some(), 2);
        let colors = slot(attributes.colors.is_some(), 4);
        Layout {
            normals,
            uv0,
            uv1,
            colors,
            stride,
        }
    }

    /// The first fitted component: every one after the normals.
    fn fit_from(&self) -> usize {
        self.normals.map_or(0, |n| n + 3)
    }

    /// Numbers per side of the fit sums (1 when nothing is fitted).
    fn fit_len(&self) -> usize {
        1 + 4 * (self.stride - self.fit_from())
    }
}

/// Every input wedge's values in one flat table, [`Layout`] order (`stride` numbers per
/// wedge): read per face corner by the values' set-up and the output, and per weighted channel
/// by the attribute error, without a look at which attributes are present each time (gathering
/// per corner was a fifth of the set-up's instructions on spot).
pub(super) struct InputValues {
    layout: Layout,
    flat: Vec<f32>,
}

impl InputValues {
    pub(super) fn of(attributes: &Attributes) -> InputValues {
        let layout = Layout::of(attributes);
        let s = layout.stride;
        let mut flat = vec![0.0f32; attributes.wedge_count() * s];
        fn put<const D: usize, T: AsRef<[f32; D]>>(
            flat: &mut [f32],
            s: usize,
            at: usize,
            column: &[T],
        ) {
            for (w, x) in flat.chunks_exact_mut(s).zip(column) {
                w[at..at + D].copy_from_slice(x.as_ref());
            }
        }
        let a = attributes;
        if let (Some(at), Some(c)) = (layout.normals, &a.normals) {
            put(&mut flat, s, at, c);
        }
        if let (Some(at), Some(c)) = (layout.uv0, &a.uv0) {
            put(&mut flat, s, at, c);
        }
        if let (Some(at), Some(c)) = (layout.uv1, &a.uv1) {
            put(&mut flat, s, at, c);
        }
        if let (Some(at), Some(c)) = (layout.colors, &a.colors) {
            put(&mut flat, s, at, c);
        }
        InputValues { layout, flat }
    }

    /// Input wedge `w`'s values.
    #[inline]
    pub(super) fn wedge(&self, w: usize) -> &[f32] {
        let s = self.layout.stride;
        &self.flat[w * s..(w + 1) * s]
    }

    /// The attribute error's channels with a non-zero weight: (weight, first component,
    /// components), texture coordinates first, then normals and colours.
    pub(super) fn weighted(&self, uv: f64, normal: f64, color: f64) -> Vec<(f64, usize, usize)> {
        let l = &self.layout;
        [
            (uv, l.uv0, 2),
            (uv, l.uv1, 2),
            (normal, l.normals, 3),
            (color, l.colors, 4),
        ]
        .into_iter()
        .filter_map(|(w, at, dims)| at.filter(|_| w > 0.0).map(|at| (w, at, dims)))
        .collect()
    }
}

/// Per engine vertex, two sides of values (see the module docs), in rows ([`WedgeValues::row`]):
/// row `v` is vertex `v`'s side 0; the seam vertices' side 1 rows follow, then one row of zeros
/// that stands for the side 1 of every other vertex (never written: only a seam vertex has a
/// side 1). Before, every vertex had both rows: on a 1.07M-face atlas the values took 98 MB,
/// most of it zeros faulted in and dragged through the caches.
pub(super) struct WedgeValues {
    /// Per row, `stride` values interpolated along the contractions.
    lerp: Vec<f32>,
    /// Per row, `1 + 4 fitted` sums: the area `W`, then per fitted channel `G` (3) and `D`
    /// ([`FIT_FROM`](Layout::fit_from) onwards: every channel but the normals).
    fit: Vec<f64>,
    /// Per vertex, the row of its side 1: its own for a seam vertex, else the zero row.
    side1: Vec<u32>,
    /// The row of zeros (the last).
    zero_row: u32,
    /// The input wedges' values.
    input: InputValues,
    /// Merged at least once as the survivor of a contraction (its values are interpolated).
    merged: Vec<bool>,
    /// Each engine face's input wedge per corner, for the vertices never merged: the face's own
    /// input wedges, but where a face moved onto a fixed seam vertex, that vertex's wedge on
    /// the face's side.
    corners: Vec<[u32; 3]>,
}

impl WedgeValues {
    /// The values of the prepared faces of `view` (positions `pos`, normalised frame) on their
    /// vertices: `side[3 f + k]` is the side of corner `k` of prepared face `f`, and only the
    /// vertices flagged in `seam` have a side 1.
    pub(super) fn new(
        view: View,
        input: InputValues,
        pos: &[DVec3],
        side: &[u8],
        seam: &[bool],
    ) -> WedgeValues {
        let vertices = pos.len();
        let layout = input.layout;
        let (s, from, len) = (layout.stride, layout.fit_from(), layout.fit_len());
        let mut rows = vertices;
        let mut side1: Vec<u32> = seam
            .iter()
            .map(|&on| {
                let row = if on { rows } else { u32::MAX as usize };
                rows += usize::from(on);
                row as u32
            })
            .collect();
        // The zero row last.
        let zero = rows as u32;
        rows += 1;
        for r in &mut side1 {
            if *r == u32::MAX {
                *r = zero;
            }
        }
        let row = |v: u32, k: u8| {
            if k == 0 {
                v as usize
            } else {
                side1[v as usize] as usize
            }
        };
        let mut lerp = vec![0.0; rows * s];
        let mut fit = vec![0.0f64; if len > 1 { rows * len } else { 0 }];
        // Each row's interpolated values are those of its last corner in face order. A side's
        // corners nearly always hold the same values, but not always (on the 69k-face bunny
        // atlas the first corner's and the last corner's gave two rows different values), so
        // the last one stays the rule; the corner is noted here and its values copied once per
        // row below (copying at every corner was a third of the set-up's instructions on spot).
        let mut last = vec![u32::MAX; rows];
        let mut face_fit = vec![0.0f64; len];
        for (f, t) in view.faces.iter().enumerate() {
            let corner = [0, 1, 2].map(|k| input.wedge(view.wedge(f, k) as usize));
            let p = t.map(|v| pos[v as usize]);
            // A degenerate face adds its values with a negligible weight and no gradient, so
            // that a side with degenerate faces only still has a value.
            let (area, t1, t2) = gradient_basis(p).unwrap_or((1e-300, DVec3::ZERO, DVec3::ZERO));
            // The face's fit sums, the same for its three corners: computed once, not per
            // corner.
            if len > 1 {
                face_fit[0] = area;
                let fitted = corner.map(|c| &c[from..s]);
                let channels = fitted[0].iter().zip(fitted[1]).zip(fitted[2]);
                for (i, ((&x0, &x1), &x2)) in channels.enumerate() {
                    let (s0, s1, s2) = (f64::from(x0), f64::from(x1), f64::from(x2));
                    let g = (s1 - s0) * t1 + (s2 - s0) * t2;
                    let o = 1 + 4 * i;
                    face_fit[o] = area * g.x;
                    face_fit[o + 1] = area * g.y;
                    face_fit[o + 2] = area * g.z;
                    face_fit[o + 3] = area * (s0 - g.dot(p[0]));
                }
            }
            for k in 0..3 {
                let slot = row(t[k], side[f * 3 + k]);
                last[slot] = (f * 3 + k) as u32;
                if len > 1 {
                    let x = &mut fit[slot * len..(slot + 1) * len];
                    for (sum, add) in x.iter_mut().zip(&face_fit) {
                        *sum += add;
                    }
                }
            }
        }
        for (row, &corner) in last.iter().enumerate() {
            if corner != u32::MAX {
                let w = view.wedge(corner as usize / 3, corner as usize % 3);
                lerp[row * s..(row + 1) * s].copy_from_slice(input.wedge(w as usize));
            }
        }
        WedgeValues {
            lerp,
            fit,
            side1,
            zero_row: zero,
            input,
            merged: vec![false; vertices],
            // The view's own gather (a copy was 3.2 MB more on a 268k-face atlas).
            corners: view.corners,
        }
    }

    /// Hint the CPU to load vertex `v`'s side 0 row (`lerp` and `fit`), which a contraction of
    /// `v` reads and writes ([`WedgeValues::merge`]): in the pass walk these were half of
    /// `Engine::collapse`'s time on a 69k-face atlas (cache misses on the values of the
    /// contracted vertex), as the vertex records were before their prefetch.
    #[inline]
    pub(super) fn prefetch(&self, v: usize) {
        let lines = |start: *const u8, bytes: usize| {
            for offset in (0..bytes).step_by(64) {
                super::prefetch::prefetch_ptr(start.wrapping_add(offset));
            }
            super::prefetch::prefetch_ptr(start.wrapping_add(bytes - 1));
        };
        let (s, len) = (self.input.layout.stride, self.input.layout.fit_len());
        if (v + 1) * s <= self.lerp.len() {
            lines(self.lerp[v * s..].as_ptr().cast(), s * 4);
        }
        if len > 1 && (v + 1) * len <= self.fit.len() {
            lines(self.fit[v * len..].as_ptr().cast(), len * 8);
        }
    }

    /// The number of rows (the zero row is the last).
    fn rows(&self) -> usize {
        self.zero_row as usize + 1
    }

    /// The row of vertex `v`'s side `side` (0 or 1).
    #[inline]
    pub(super) fn row(&self, v: usize, side: usize) -> usize {
        if side == 0 { v } else { self.side1[v] as usize }
    }

    /// The input wedge of engine face `f` (corners `t`) at its vertex `v`.
    pub(super) fn corner_wedge(&self, f: usize, v: u32, t: &[u32; 3]) -> u32 {
        let k = t.iter().position(|&x| x == v).unwrap_or(0);
        self.corners[f][k]
    }

    /// Engine face `f` (corners `t`) takes input wedge `w` at its vertex `v`.
    pub(super) fn set_corner_wedge(&mut self, f: usize, v: u32, t: &[u32; 3], w: u32) {
        let k = t.iter().position(|&x| x == v).unwrap_or(0);
        self.corners[f][k] = w;
    }

    /// `b` is contracted into `a` at `t` along `a`–`b` (0: at `a`), matched by `seams` (called
    /// before the seams are merged).
    pub(super) fn merge(&mut self, a: usize, b: usize, t: f32, seams: &Seams) {
        if seams.anchor(a, b) == Some(a) {
            // `a` stays where it is: its values too (the fit of its own faces at its own
            // position is its value exactly, and b's faces would only blur it). A fixed one
            // keeps its corners' input wedges, the moved faces' set by the engine.
            if !seams.is_fixed(a) {
                self.merged[a] = true;
            }
            return;
        }
        self.merged[a] = true;
        let (s, len) = (self.input.layout.stride, self.input.layout.fit_len());
        let sides = if seams.seam[a] { 2 } else { 1 };
        for (sa, sb) in seams.matching(a, b).into_iter().enumerate().take(sides) {
            let (ra, rb) = (self.row(a, sa), self.row(b, sb));
            // Only a seam vertex has a side 1, and only a seam vertex merges two sides.
            debug_assert!(
                sa == 0 || ra != self.zero_row as usize,
                "side 1 of a non-seam vertex"
            );
            let (to, from) = rows_mut(&mut self.lerp, ra, rb, s);
            for (x, &y) in to.iter_mut().zip(from.iter()) {
                *x += t * (y - *x);
            }
            if len > 1 {
                let (to, from) = rows_mut(&mut self.fit, ra, rb, len);
                for (x, &y) in to.iter_mut().zip(from.iter()) {
                    *x += y;
                }
            }
        }
    }

    /// The values of row `slot` ([`WedgeValues::row`]) at `p` into `out`: the normals
    /// interpolated, the rest fitted.
    fn values_at(&self, slot: usize, p: DVec3, out: &mut [f32]) {
        let (s, from, len) = (
            self.input.layout.stride,
            self.input.layout.fit_from(),
            self.input.layout.fit_len(),
        );
        out.copy_from_slice(&self.lerp[slot * s..(slot + 1) * s]);
        if len > 1 {
            let x = &self.fit[slot * len..(slot + 1) * len];
            for (value, sums) in out[from..].iter_mut().zip(x[1..].chunks_exact(4)) {
                let fitted = sums[0] * p.x + sums[1] * p.y + sums[2] * p.z + sums[3];
                *value = (fitted / x[0]) as f32;
            }
        }
    }
}

/// Rows `to` (mutable) and `from` (`to != from`) of `width` values each of `rows`: two slices, so
/// that a merge's loops run without a bounds check per value (index by index they were a third of
/// a contraction's added instructions on a 268k-face atlas).
fn rows_mut<T>(rows: &mut [T], to: usize, from: usize, width: usize) -> (&mut [T], &[T]) {
    debug_assert_ne!(to, from, "a row merged into itself");
    if to < from {
        let (low, high) = rows.split_at_mut(from * width);
        (&mut low[to * width..(to + 1) * width], &high[..width])
    } else {
        let (low, high) = rows.split_at_mut(to * width);
        (&mut high[..width], &low[from * width..(from + 1) * width])
    }
}

/// For a triangle at `pos`, its area and the two vectors `t1`, `t2` in its plane such that the
/// linear function with values `s0`, `s1`, `s2` at its corners has the gradient
/// `(s1 − s0) t1 + (s2 − s0) t2` (`g·e1 = s1 − s0`, `g·e2 = s2 − s0`, `g` in the plane);
/// `None` for a degenerate triangle. The one gradient of the attribute error's sums and of the
/// carried values' fit.
pub(super) fn gradient_basis(pos: [DVec3; 3]) -> Option<(f64, DVec3, DVec3)> {
    let (e1, e2) = (pos[1] - pos[0], pos[2] - pos[0]);
    let n = e1.cross(e2);
    let n2 = n.length_squared();
    // With g in the plane: g = ((s1 − s0) (e2 × n) + (s2 − s0) (n × e1)) / |n|².
    (n2 > 0.0 && n2.is_finite()).then(|| (0.5 * n2.sqrt(), e2.cross(n) / n2, n.cross(e1) / n2))
}

/// Where `p` projects onto the segment `pa`–`pb`, as a parameter in [0, 1] (½ for a point
/// segment): the interpolation parameter of a contraction.
#[inline]
pub(super) fn segment_parameter(pa: DVec3, pb: DVec3, p: DVec3) -> f32 {
    let d = pb - pa;
    let len2 = d.length_squared();
    if len2 > 0.0 {
        ((p - pa).dot(d) / len2).clamp(0.0, 1.0) as f32
    } else {
        0.5
    }
}

/// The sides of the faces `fan` around seam vertex `v` with seam neighbours `n0`, `n1`
/// (`faces(f)` gives face `f`'s corners): `reached[i]` is true for side 0, the faces reached from
/// the one holding the directed edge `v → n1` (else one holding `n1`) through edges off the seam.
/// With no such face every entry stays false. `stack` is scratch.
pub(super) fn fan_sides(
    fan: &[u32],
    faces: impl Fn(u32) -> [u32; 3],
    [v, n0, n1]: [u32; 3],
    reached: &mut Vec<bool>,
    stack: &mut Vec<usize>,
) {
    reached.clear();
    reached.resize(fan.len(), false);
    let first = fan
        .iter()
        .position(|&f| corner_after(&faces(f), v) == n1)
        .or_else(|| fan.iter().position(|&f| faces(f).contains(&n1)));
    let Some(first) = first else {
        return;
    };
    reached[first] = true;
    stack.clear();
    stack.push(first);
    while let Some(i) = stack.pop() {
        for x in faces(fan[i]) {
            if x == v || x == n0 || x == n1 {
                continue;
            }
            for (j, &g) in fan.iter().enumerate() {
                if !reached[j] && faces(g).contains(&x) {
                    reached[j] = true;
                    stack.push(j);
                }
            }
        }
    }
}

/// [`fan_sides`], then `mark(face, corner)` for each corner of `v` (`vn[0]`) on side 1; none
/// when no face starts side 0 (the fan is one side). The one rule of the input's corners and
/// the output's.
pub(super) fn mark_side1(
    fan: &[u32],
    faces: impl Fn(u32) -> [u32; 3],
    vn: [u32; 3],
    reached: &mut Vec<bool>,
    stack: &mut Vec<usize>,
    mut mark: impl FnMut(u32, usize),
) {
    fan_sides(fan, &faces, vn, reached, stack);
    if !reached.iter().any(|&r| r) {
        return;
    }
    for (&f, _) in fan.iter().zip(reached.iter()).filter(|&(_, &r)| !r) {
        let k = faces(f).iter().position(|&x| x == vn[0]).unwrap_or(0);
        mark(f, k);
    }
}

/// Twice the signed area of a triangle in texture space.
fn uv_area([a, b, c]: [Vec2; 3]) -> f32 {
    (b - a).perp_dot(c - a)
}

/// Sweeps of [`untangle_uv`]'s projections over a wedge's triangles.
const PROJECTION_SWEEPS: usize = 8;

/// Most rounds of [`untangle_uv`], a bound only: on spot at 2-50 % the first round moves all that
/// any round does, and the fandisk atlas, the knight and the horse have no fold left to untangle.
const UNTANGLE_ROUNDS: usize = 4;

/// Move the texture coordinates (components `at`, `at + 1` of each wedge's `stride` values) of
/// the `movable` corners of every folded triangle, a triangle whose orientation in texture space
/// is the reverse of `expected` (its input face's sign; 0: not checked), to the candidate with
/// the fewest folded triangles among the wedge's: its interpolated value (`lerp`), the centroid
/// of the other corners of its triangles, halfway to it, or its projection into every
/// triangle's unfolded side. A wedge moves only when that
/// lowers its count, so the number of folds never grows. Geometry is not touched.
fn untangle_uv(
    corners: &[[u32; 3]],
    expected: &[f32],
    values: &mut [f32],
    stride: usize,
    at: usize,
    movable: impl Fn(u32) -> bool,
    lerp: impl Fn(u32) -> Vec2,
) {
    let uv = |values: &[f32], w: u32| Vec2::from_slice(&values[w as usize * stride + at..][..2]);
    let folded =
        |values: &[f32], t: usize| expected[t] * uv_area(corners[t].map(|w| uv(values, w))) < 0.0;
    if !(0..corners.len()).any(|t| folded(values, t)) {
        return;
    }
    // Each wedge's triangles.
    let wedges = values.len() / stride;
    let mut start = vec![0u32; wedges + 1];
    for c in corners.iter().flatten() {
        start[*c as usize + 1] += 1;
    }
    for i in 0..wedges {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut tris = vec![0u32; corners.len() * 3];
    for (t, c) in corners.iter().enumerate() {
        for &w in c {
            tris[fill[w as usize] as usize] = t as u32;
            fill[w as usize] += 1;
        }
    }
    let around = |w: u32| &tris[start[w as usize] as usize..start[w as usize + 1] as usize];
    // Folded triangles around `w` with its coordinates at `p`.
    let count = |values: &[f32], w: u32, p: Vec2| {
        around(w)
            .iter()
            .filter(|&&t| {
                let t = t as usize;
                let c = corners[t].map(|x| if x == w { p } else { uv(values, x) });
                expected[t] * uv_area(c) < 0.0
            })
            .count()
    };
    // `w`'s coordinates moved into each of its triangles' unfolded side in turn (alternating
    // projections onto the half-planes, each to a tenth of the opposite edge inside): what
    // unfolds an open fan (a seam side), whose ring centroid need not lie in it.
    let project = |values: &[f32], w: u32| {
        let mut p = uv(values, w);
        for _ in 0..PROJECTION_SWEEPS {
            for &t in around(w) {
                let c = corners[t as usize];
                let k = c.iter().position(|&x| x == w).unwrap_or(0);
                let (a, b) = (uv(values, c[(k + 1) % 3]), uv(values, c[(k + 2) % 3]));
                let d = b - a;
                let len2 = d.length_squared();
                let sign = expected[t as usize];
                if len2 == 0.0 || sign == 0.0 {
                    continue;
                }
                // Twice the area of (p, a, b), `sign`-oriented; it grows by |d|² per step d⊥.
                let area = sign * uv_area([p, a, b]);
                let inside = 0.1 * len2;
                if area < inside {
                    p += sign * (inside - area) / len2 * d.perp();
                }
            }
        }
        p
    };
    for _ in 0..UNTANGLE_ROUNDS {
        let mut moved = false;
        for t in 0..corners.len() {
            if !folded(values, t) {
                continue;
            }
            for w in corners[t].into_iter().filter(|&w| movable(w)) {
                let here = uv(values, w);
                let now = count(values, w, here);
                if now == 0 {
                    continue;
                }
                let (mut sum, mut n) = (Vec2::ZERO, 0.0);
                for &x in around(w).iter().flat_map(|&u| &corners[u as usize]) {
                    if x != w {
                        sum += uv(values, x);
                        n += 1.0;
                    }
                }
                let centroid = sum / n;
                let best = [
                    lerp(w),
                    centroid,
                    0.5 * (here + centroid),
                    project(values, w),
                ]
                .into_iter()
                .map(|p| (count(values, w, p), p.distance_squared(here), p))
                .min_by(|a, b| {
                    (a.0, a.1)
                        .partial_cmp(&(b.0, b.1))
                        .unwrap_or(std::cmp::Ordering::Equal)
                });
                if let Some((_, _, p)) = best.filter(|b| b.0 < now) {
                    values[w as usize * stride + at..][..2].copy_from_slice(&p.to_array());
                    moved = true;
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// The engine's result as a mesh in model units with its attributes: the live faces less
/// duplicates (`mesh::clean`), each corner with its vertex's values on its side, or its own
/// input wedge where the vertex was never merged; materials per face. `face_origin[f]` is the
/// input face of engine face `f` (same corner order); `attributes` are the input's.
pub(super) fn output(
    e: &Engine,
    frame: &Frame,
    attributes: &Attributes,
    face_origin: &[u32],
) -> (TriMesh, Attributes) {
    let (Some(values), Some(seams)) = (&e.values, &e.seams) else {
        // Not reached: an attribute run's engine always holds its values and seams.
        return (e.output(frame).0, Attributes::default());
    };
    // 1. The live faces and their engine indices, degenerate and duplicate faces dropped.
    let mut face_id = Vec::with_capacity(e.live_faces);
    let mut triangles = Vec::with_capacity(e.live_faces);
    for (f, t) in e.faces.iter().enumerate() {
        if t[0] != DEAD {
            face_id.push(f as u32);
            triangles.push(*t);
        }
    }
    let mut out = TriMesh::new(Vec::new(), triangles);
    if let (_, Some(keep)) = mesh::clean::drop_faces_with_mask(&mut out) {
        let mut k = keep.iter();
        face_id.retain(|_| *k.next().unwrap_or(&false));
    }

    // 2. Side 1 corners of the merged seam vertices (bit k of the engine face's entry).
    let mut side1 = vec![0u8; e.faces.len()];
    let (mut fan, mut reached, mut stack) = (Vec::new(), Vec::new(), Vec::new());
    for v in 0..e.vx.len() {
        if !(values.merged[v] && seams.seam[v] && e.vx[v].alive) {
            continue;
        }
        fan.clear();
        fan.extend(
            e.list(v)
                .map(|i| e.refs[i])
                .filter(|&f| e.faces[f as usize][0] != DEAD),
        );
        let [n0, n1] = seams.along[v];
        let faces = |f: u32| e.faces[f as usize];
        let vn = [v as u32, n0, n1];
        mark_side1(&fan, faces, vn, &mut reached, &mut stack, |f, k| {
            side1[f as usize] |= 1 << k;
        });
    }

    // 3. One output wedge per (vertex, side) of the merged vertices and per input wedge of the
    // others, numbered in order of first use; `slot_of[w]`: the row of output wedge `w`
    // (`u32::MAX` for an input wedge).
    let layout = values.input.layout;
    let s = layout.stride;
    // Per row, its output wedge (only a seam vertex has side 1 corners, so no two merged
    // (vertex, side) pairs share a row).
    let mut row_wedge = vec![u32::MAX; values.rows()];
    let mut input_wedge = vec![u32::MAX; attributes.wedge_count()];
    let mut wedge_vertex = Vec::new();
    let mut slot_of = Vec::new();
    let mut wedge_values: Vec<f32> = Vec::new();
    let mut corners = Vec::with_capacity(face_id.len());
    for (t, &f) in out.triangles.iter().zip(&face_id) {
        let mut c = [0u32; 3];
        for k in 0..3 {
            let v = t[k] as usize;
            let input = values.corners[f as usize][k] as usize;
            let (id, slot) = if values.merged[v] {
                let row = values.row(v, usize::from(side1[f as usize] >> k & 1));
                debug_assert_ne!(row, values.zero_row as usize, "side 1 of a non-seam vertex");
                (&mut row_wedge[row], row as u32)
            } else {
                (&mut input_wedge[input], u32::MAX)
            };
            if *id == u32::MAX {
                *id = wedge_vertex.len() as u32;
                wedge_vertex.push(t[k]);
                slot_of.push(slot);
                let at = wedge_values.len();
                wedge_values.resize(at + s, 0.0);
                let out = &mut wedge_values[at..];
                match slot {
                    u32::MAX => out.copy_from_slice(values.input.wedge(input)),
                    slot => values.values_at(slot as usize, e.vx[v].p, out),
                }
            }
            c[k] = *id;
        }
        corners.push(c);
    }
    // A fitted value can fold a small triangle over in texture space where the interpolated
    // ones do not (fandisk atlas at 20 %: 19 of 2,588 triangles UV-flipped with fitted values
    // only, 0 with interpolated ones): the merged corners of such a triangle take their
    // interpolated values.
    for at in [layout.uv0, layout.uv1].into_iter().flatten() {
        let uv = |w: &[f32], c: u32| Vec2::from_slice(&w[c as usize * s + at..][..2]);
        let lerp = |c: u32| match slot_of[c as usize] {
            u32::MAX => uv(&wedge_values, c),
            slot => Vec2::from_slice(&values.lerp[slot as usize * s + at..][..2]),
        };
        let area = |[a, b, c]: [Vec2; 3]| (b - a).perp_dot(c - a);
        let mut fold: Vec<u32> = Vec::new();
        for c in &corners {
            if area(c.map(|w| uv(&wedge_values, w))) * area(c.map(lerp)) < 0.0 {
                fold.extend(c.iter().filter(|&&w| slot_of[w as usize] != u32::MAX));
            }
        }
        for w in fold {
            let slot = slot_of[w as usize] as usize;
            let from = layout.fit_from();
            wedge_values[w as usize * s + from..(w as usize + 1) * s]
                .copy_from_slice(&values.lerp[slot * s + from..(slot + 1) * s]);
        }
    }
    // Folds left by either value (spot at 10 %: 7 of 584 triangles, meshoptimizer 2): the merged
    // corners of each are moved, in texture space only, to where fewer triangles around them
    // fold ([`untangle_uv`]).
    for at in [layout.uv0, layout.uv1].into_iter().flatten() {
        let input_uv = |w: u32| Vec2::from_slice(&values.input.wedge(w as usize)[at..at + 2]);
        let expected: Vec<f32> = face_id
            .iter()
            .map(|&f| {
                let c = attributes.corners[face_origin[f as usize] as usize];
                uv_area(c.map(input_uv)).signum()
            })
            .collect();
        let lerp = |w: u32| {
            let slot = slot_of[w as usize] as usize;
            Vec2::from_slice(&values.lerp[slot * s + at..][..2])
        };
        let movable = |w: u32| slot_of[w as usize] != u32::MAX;
        untangle_uv(&corners, &expected, &mut wedge_values, s, at, movable, lerp);
    }

    // 4. The referenced vertices only, in engine order.
    let kept = mesh::clean::compact_vertex_indices(&mut out.triangles, e.vx.len());
    let mut new_index = vec![u32::MAX; e.vx.len()];
    for (i, &v) in kept.iter().enumerate() {
        new_index[v as usize] = i as u32;
    }
    out.positions = kept
        .iter()
        .map(|&v| frame.to_model(e.vx[v as usize].p))
        .collect();
    for v in &mut wedge_vertex {
        *v = new_index[*v as usize];
    }
    let column = |at: Option<usize>, dims: usize| {
        at.map(|at| {
            wedge_values
                .chunks_exact(s)
                .map(|w| &w[at..at + dims])
                .collect::<Vec<_>>()
        })
    };
    let mut result = Attributes {
        wedge_vertex,
        corners,
        // Interpolated normals are shorter than one: normalised (a zero one, from opposite
        // normals, stays as it is rather than becoming NaN).
        normals: column(layout.normals, 3).map(|c| {
            c.iter()
                .map(|n| {
                    let n = Vec3::from_slice(n);
                    n.try_normalize().unwrap_or(n)
                })
                .collect()
        }),
        uv0: column(layout.uv0, 2).map(|c| c.iter().map(|t| Vec2::from_slice(t)).collect()),
        uv1: column(layout.uv1, 2).map(|c| c.iter().map(|t| Vec2::from_slice(t)).collect()),
        // A fit can leave [0, 1] where the colours change fastest: clamped.
        colors: column(layout.colors, 4).map(|c| {
            c.iter()
                .map(|x| Vec4::from_slice(x).clamp(Vec4::ZERO, Vec4::ONE))
                .collect()
        }),
        face_material: attributes.face_material.as_ref().map(|m| {
            face_id
                .iter()
                .map(|&f| m[face_origin[f as usize] as usize])
                .collect()
        }),
    };
    // Input wedges of one vertex can hold equal values (an OBJ with repeated `vt` lines):
    // one wedge each, so that a format with one vertex per wedge splits no vertex for nothing.
    result.compact();
    (out, result)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hexagon fan in texture space: wedge 0 at the centre, 1-6 on the ring, one value per
    /// wedge (stride 2).
    fn fan(centre: Vec2) -> (Vec<[u32; 3]>, Vec<f32>) {
        let mut values = centre.to_array().to_vec();
        for k in 0..6 {
            let a = k as f32 * std::f32::consts::TAU / 6.0;
            values.extend([a.cos(), a.sin()]);
        }
        let corners = (0..6u32).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        (corners, values)
    }

    fn folds(corners: &[[u32; 3]], values: &[f32]) -> usize {
        let uv = |w: u32| Vec2::from_slice(&values[w as usize * 2..][..2]);
        corners.iter().filter(|c| uv_area(c.map(uv)) < 0.0).count()
    }

    #[test]
    fn a_corner_outside_its_ring_is_moved_back_inside() {
        // The centre pushed past the ring folds the two triangles on the far side.
        let (corners, mut values) = fan(Vec2::new(1.6, 0.1));
        let before = values.clone();
        assert!(folds(&corners, &values) >= 1);
        let expected = vec![1.0; corners.len()];
        // Its interpolated value folds too: the centroid of the ring is what unfolds it.
        let lerp = |_| Vec2::new(1.5, 0.0);
        untangle_uv(&corners, &expected, &mut values, 2, 0, |w| w == 0, lerp);
        assert_eq!(folds(&corners, &values), 0, "{values:?}");
        assert_eq!(values[2..], before[2..], "the fixed ring did not move");
        let centre = Vec2::from_slice(&values[..2]);
        assert!(centre.length() < 0.87, "{centre}: inside the ring");
    }

    #[test]
    fn nothing_moves_without_a_fold_or_a_movable_corner() {
        let (corners, mut values) = fan(Vec2::new(0.2, -0.1));
        let before = values.clone();
        let expected = vec![1.0; corners.len()];
        untangle_uv(
            &corners,
            &expected,
            &mut values,
            2,
            0,
            |_| true,
            |_| Vec2::ZERO,
        );
        assert_eq!(values, before, "no fold: nothing moves");
        // A fold whose corners are all fixed stays.
        let (corners, mut values) = fan(Vec2::new(1.6, 0.1));
        let before = values.clone();
        untangle_uv(
            &corners,
            &expected,
            &mut values,
            2,
            0,
            |_| false,
            |_| Vec2::ZERO,
        );
        assert_eq!(values, before);
        // A mirrored chart (negative expected orientation) is not folded when mirrored.
        let mirror =
            |v: Vec<f32>| -> Vec<f32> { v.chunks(2).flat_map(|p| [p[0], -p[1]]).collect() };
        let mut values = mirror(fan(Vec2::new(0.2, 0.1)).1);
        let kept = values.clone();
        untangle_uv(
            &corners,
            &[-1.0; 6],
            &mut values,
            2,
            0,
            |_| true,
            |_| Vec2::ZERO,
        );
        assert_eq!(values, kept);
    }
}

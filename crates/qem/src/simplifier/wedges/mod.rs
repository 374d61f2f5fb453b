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
//!
//! This module holds the values' table ([`WedgeValues`]) and its merge; [`sides`] finds the
//! side of each face around a seam vertex, [`output`](output::output) makes the result's wedges
//! and [`untangle`] undoes the folds they leave in texture space.

pub(super) mod output;
mod sides;
mod untangle;

pub(super) use sides::{fan_sides, mark_side1};

use super::prefetch::prefetch_ptr;
use super::seams::Seams;
use super::triangle::gradient_basis;
use super::view::View;
use glam::DVec3;
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
        let mut lerp = vec![0.0; rows * s];
        let mut fit = vec![0.0f64; if len > 1 { rows * len } else { 0 }];
        // Each row's interpolated values are those of its last corner in face order. A side's
        // corners nearly always hold the same values, but not always (on the 69k-face bunny
        // atlas the first corner's and the last corner's gave two rows different values), so
        // the last one stays the rule; the corner is noted here and its values copied once per
        // row below (copying at every corner was a third of the set-up's instructions on spot).
        let mut last = vec![u32::MAX; rows];
        let row = |v: u32, k: u8| {
            if k == 0 {
                v as usize
            } else {
                side1[v as usize] as usize
            }
        };
        let sums = FaceSums {
            view: &view,
            input: &input,
            pos,
            side,
        };
        // The usual layouts with their number of fitted components fixed, so that the loops over
        // a face's channels and a row's sums have known lengths (spot and the igea atlas: texture
        // coordinates only, 2; with colours 6): 120.6 → 97.5 M instructions of this set-up on the
        // 268k-face igea atlas at 10 %, 2.63 → 2.13 M on spot (callgrind), the same sums.
        match len {
            1 => sums.add::<0>(0, &mut fit, &mut last, row),
            9 => sums.add::<2>(2, &mut fit, &mut last, row),
            17 => sums.add::<4>(4, &mut fit, &mut last, row),
            25 => sums.add::<6>(6, &mut fit, &mut last, row),
            _ => sums.add::<{ usize::MAX }>(s - from, &mut fit, &mut last, row),
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
                prefetch_ptr(start.wrapping_add(offset));
            }
            prefetch_ptr(start.wrapping_add(bytes - 1));
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

/// The fit sums of the prepared faces, added to their corners' rows ([`WedgeValues::new`]).
struct FaceSums<'a> {
    view: &'a View<'a>,
    input: &'a InputValues,
    /// Prepared positions (normalised frame).
    pos: &'a [DVec3],
    /// Side of each prepared face corner (`3 f + k`).
    side: &'a [u8],
}

impl FaceSums<'_> {
    /// Add each face's fit sums (`1 + 4 fitted` numbers: the area, then per fitted component its
    /// gradient `G` and `D`) to the rows of its corners (`row(vertex, side)`) in `fit`, and note
    /// in `last` each row's last corner in face order. `F` is the number of fitted components
    /// when it is one of the usual ones (known lengths for the loops), `usize::MAX` otherwise,
    /// and then `fitted` is it; 0: nothing fitted, only `last` is noted.
    fn add<const F: usize>(
        &self,
        fitted: usize,
        fit: &mut [f64],
        last: &mut [u32],
        row: impl Fn(u32, u8) -> usize,
    ) {
        let fitted = if F == usize::MAX { fitted } else { F };
        let len = 1 + 4 * fitted;
        let (view, input, pos) = (self.view, self.input, self.pos);
        let from = input.layout.fit_from();
        let mut face_fit = vec![0.0f64; len];
        let face_fit = &mut face_fit[..len];
        for (f, t) in view.faces.iter().enumerate() {
            if fitted > 0 {
                let corner = [0, 1, 2].map(|k| {
                    let w = input.wedge(view.wedge(f, k) as usize);
                    &w[from..from + fitted]
                });
                let p = t.map(|v| pos[v as usize]);
                // A degenerate face adds its values with a negligible weight and no gradient, so
                // that a side with degenerate faces only still has a value.
                let (area, t1, t2) =
                    gradient_basis(p).unwrap_or((1e-300, DVec3::ZERO, DVec3::ZERO));
                // The face's fit sums, the same for its three corners: computed once, not per
                // corner.
                face_fit[0] = area;
                for (i, sums) in face_fit[1..].chunks_exact_mut(4).enumerate() {
                    let (s0, s1, s2) = (
                        f64::from(corner[0][i]),
                        f64::from(corner[1][i]),
                        f64::from(corner[2][i]),
                    );
                    let g = (s1 - s0) * t1 + (s2 - s0) * t2;
                    sums[0] = area * g.x;
                    sums[1] = area * g.y;
                    sums[2] = area * g.z;
                    sums[3] = area * (s0 - g.dot(p[0]));
                }
            }
            for (k, &v) in t.iter().enumerate() {
                let slot = row(v, self.side[f * 3 + k]);
                last[slot] = (f * 3 + k) as u32;
                if fitted > 0 {
                    let x = &mut fit[slot * len..(slot + 1) * len];
                    for (sum, add) in x.iter_mut().zip(face_fit.iter()) {
                        *sum += add;
                    }
                }
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

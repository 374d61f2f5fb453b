//! The attribute term of the collapse cost of attribute runs: Hoppe 1999's attribute quadrics
//! ("New quadric metric for simplifying meshes with appearance attributes"), evaluated at the
//! geometric placement with the attribute value that minimises them.
//!
//! Each triangle carries, for every weighted attribute channel `j` (u, v, normal x/y/z, r/g/b/a,
//! each multiplied by its weight), the linear function `s_j(p) = g_j·p + d_j` that interpolates
//! its three corners' values over its plane (`g_j` in the plane). A vertex sums, over its faces
//! with their areas `w`, the quadric `Σ w Σ_j (g_j·p + d_j)²` (one 3-D quadric for all channels),
//! the area `W = Σ w` and per channel `G_j = Σ w g_j`, `D_j = Σ w d_j`. The error of a merged
//! vertex at `p` with values `s` is `Σ w Σ_j (s_j − g_j·p − d_j)²`; its minimum over `s` is at
//! `s_j = (G_j·p + D_j) / W`, where it is `Σ w Σ_j (g_j·p + d_j)² − Σ_j (G_j·p + D_j)² / W`:
//! how far the attributes of the faces around the pair are from one linear function of the
//! position. A texture that stays linear over a region (no stretch change) costs nothing to
//! contract; one whose gradient changes (distortion, a colour edge) costs what fitting one
//! gradient leaves over.
//!
//! A seam vertex (exactly two seam edges; the rest of the seam vertices are locked) has two
//! sides, one fan of faces each, with separate sums; side 0 is the side on the left of the
//! seam walked from `along[0]` through the vertex to `along[1]` (the faces holding the directed
//! edge vertex → `along[1]`). A pair along the seam merges side with side by that orientation.

use super::seams::Seams;
use glam::DVec3;

/// Per-vertex attribute sums, two sides per vertex, in one flat array.
pub(super) struct AttributeError {
    /// Per vertex, two sides of [`AttributeError::side_len`] numbers: quadric upper triangle (6),
    /// linear term (3), constant (1), area `W` (1), then per channel `G` (3) and `D` (1).
    data: Vec<f64>,
    /// Weighted channels (u, v, normal x, ...).
    channels: usize,
}

/// Offset of `W` in a side.
const W: usize = 10;
/// Offset of the first channel in a side.
const CHANNELS: usize = 11;

impl AttributeError {
    /// Zero sums for `vertices` vertices and `channels` channels.
    pub(super) fn new(vertices: usize, channels: usize) -> AttributeError {
        let side = CHANNELS + 4 * channels;
        AttributeError {
            data: vec![0.0; vertices * 2 * side],
            channels,
        }
    }

    #[inline]
    fn side_len(&self) -> usize {
        CHANNELS + 4 * self.channels
    }

    /// Add a triangle with corners at `pos` (normalised frame) and channel values `values`
    /// (`values[k * channels + j]`: corner `k`, channel `j`, weighted) to side `side[k]` of
    /// vertex `vertex[k]` (`u32::MAX`: not an engine vertex).
    pub(super) fn add_triangle(
        &mut self,
        pos: [DVec3; 3],
        values: &[f64],
        vertex: [u32; 3],
        side: [u8; 3],
    ) {
        let Some((area, t1, t2)) = super::triangle::gradient_basis(pos) else {
            return;
        };
        let c = self.channels;
        let len = self.side_len();
        for k in 0..3 {
            if vertex[k] == u32::MAX {
                continue;
            }
            let at = (vertex[k] as usize * 2 + side[k] as usize) * len;
            let s = &mut self.data[at..at + len];
            s[W] += area;
            for j in 0..c {
                let s0 = values[j];
                let g = (values[c + j] - s0) * t1 + (values[2 * c + j] - s0) * t2;
                let d = s0 - g.dot(pos[0]);
                let (x, y, z) = (g.x * area, g.y * area, g.z * area);
                let add = [
                    x * g.x,
                    x * g.y,
                    x * g.z,
                    y * g.y,
                    y * g.z,
                    z * g.z,
                    x * d,
                    y * d,
                    z * d,
                    area * d * d,
                ];
                for (q, a) in s[..10].iter_mut().zip(add) {
                    *q += a;
                }
                let o = CHANNELS + 4 * j;
                s[o] += x;
                s[o + 1] += y;
                s[o + 2] += z;
                s[o + 3] += area * d;
            }
        }
    }

    /// The attribute error of contracting `a` and `b` to `p`. A vertex off the seams merged
    /// into one on a seam ([`Seams::pair_ok`]) joins one side of it; which one is not looked up
    /// for every pair costed: its error is taken with the sides apart (a lower bound of the
    /// joined one, exact when the two fit one linear function each).
    #[inline]
    pub(super) fn error(&self, a: usize, b: usize, p: DVec3, seams: &Seams) -> f64 {
        let len = self.side_len();
        let side = |v: usize, s: usize| &self.data[(v * 2 + s) * len..][..len];
        if seams.seam[a] != seams.seam[b] {
            let (on, off) = if seams.seam[a] { (a, b) } else { (b, a) };
            return self.residual(side(on, 0), None, p)
                + self.residual(side(on, 1), None, p)
                + self.residual(side(off, 0), None, p);
        }
        if let Some(f) = seams.anchor(a, b) {
            // Along a seam into a fixed vertex, which keeps its own values: the fit of the
            // moving vertex's two sides at `p`.
            let m = if f == a { b } else { a };
            return self.residual(side(m, 0), None, p) + self.residual(side(m, 1), None, p);
        }
        let m = seams.matching(a, b);
        let sides = if seams.seam[a] { 2 } else { 1 };
        m.iter()
            .enumerate()
            .take(sides)
            .map(|(sa, &sb)| self.residual(side(a, sa), Some(side(b, sb)), p))
            .sum()
    }

    /// What the sums `x` (plus `y`) leave over at `p` after the best values there.
    #[inline]
    fn residual(&self, x: &[f64], y: Option<&[f64]>, p: DVec3) -> f64 {
        let q = |i: usize| x[i] + y.map_or(0.0, |y| y[i]);
        let w = q(W);
        if w <= 0.0 {
            return 0.0;
        }
        let (a00, a01, a02, a11, a12, a22) = (q(0), q(1), q(2), q(3), q(4), q(5));
        let quad = p.x * (a00 * p.x + 2.0 * (a01 * p.y + a02 * p.z))
            + p.y * (a11 * p.y + 2.0 * a12 * p.z)
            + a22 * p.z * p.z
            + 2.0 * (q(6) * p.x + q(7) * p.y + q(8) * p.z)
            + q(9);
        let mut fit = 0.0;
        for j in 0..self.channels {
            let o = CHANNELS + 4 * j;
            let t = q(o) * p.x + q(o + 1) * p.y + q(o + 2) * p.z + q(o + 3);
            fit += t * t;
        }
        // A difference of two sums of squares: rounding can take it slightly below zero.
        (quad - fit / w).max(0.0)
    }

    /// `b` was contracted into `a` (called before the seams are merged); `side`: the side of
    /// seam vertex `a` that `b`, off the seams, joins (unused otherwise).
    pub(super) fn merge(&mut self, a: usize, b: usize, seams: &Seams, side: usize) {
        let len = self.side_len();
        let m = if seams.seam[a] && !seams.seam[b] {
            // b's one side into a's side `side` (and b's empty side 1 into the other).
            [side, 1 - side]
        } else {
            seams.matching(a, b)
        };
        for (sa, sb) in m.into_iter().enumerate() {
            let (from, to) = ((b * 2 + sb) * len, (a * 2 + sa) * len);
            for i in 0..len {
                self.data[to + i] += self.data[from + i];
            }
        }
    }
}

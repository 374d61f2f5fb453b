//! One triangle's helpers, shared by every layer: the dead-face marker, corner tests and walks,
//! the gradient basis of a linear function over it and a point's parameter along an edge.

use glam::DVec3;

/// Marks a dead face (in its first slot).
pub(super) const DEAD: u32 = u32::MAX;

/// Whether face `t` has corner `v`. Non-short-circuit: which corner matches is data, and as a
/// chain of branches it mispredicted 0.7 M times in 20 runs of fandisk at 10 % (cachegrind).
#[inline]
pub(super) fn contains(t: &[u32; 3], v: u32) -> bool {
    (t[0] == v) | (t[1] == v) | (t[2] == v)
}

/// The corner that follows `u` in face `t` (around a closed fan of `u`, every neighbour once;
/// `t[0]` when `u` is not a corner). Without branches: as an `if` chain it was the simplifier's
/// most mispredicted line (2.2 M of 12.4 M mispredictions in 20 runs of fandisk at 10 %,
/// cachegrind). With `contains` above: 12.4 → 10.6 M mispredictions for 4 % more instructions,
/// 4-12 % less time on the small meshes (fandisk, spot, gargoyle-10k at 10 %).
#[inline]
pub(super) fn corner_after(t: &[u32; 3], u: u32) -> u32 {
    let not0 = t[0] != u;
    let k = usize::from(not0) + usize::from(not0 & (t[1] != u));
    t[[1, 2, 0][k]]
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

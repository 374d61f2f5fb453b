//! f64 geometric primitives shared by every crate: the closest point on a segment and on a
//! triangle (Ericson, "Real-Time Collision Detection", 5.1.5: the Voronoi region of the query
//! point, 3 vertices, 3 edges or the interior, decides the answer), the bounding-box lower bound
//! that closest-face searches cull with, and the degeneracy test.
//! Degenerate triangles (collinear or coincident corners) fall back to the three segments.

use glam::DVec3;

/// Closest point to `p` on segment `ab` (f64).
#[inline]
pub fn closest_point_segment(p: DVec3, a: DVec3, b: DVec3) -> DVec3 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 <= 0.0 {
        return a;
    }
    a + ab * ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
}

/// True when the triangle has (numerically) no area: `|ab × ac|² ≤ 1e-14 · |ab|² · |ac|²`.
#[inline]
pub fn is_degenerate(a: DVec3, b: DVec3, c: DVec3) -> bool {
    let (ab, ac) = (b - a, c - a);
    let cross = ab.cross(ac).length_squared();
    // Written so that NaN inputs count as degenerate.
    let threshold = 1e-14 * ab.length_squared() * ac.length_squared();
    cross.partial_cmp(&threshold) != Some(std::cmp::Ordering::Greater)
}

/// Squared distance from `p` to the axis-aligned bounding box of triangle `abc`: a lower bound
/// of its squared distance to the triangle, so a search for the closest of many triangles can
/// skip the exact [`closest_point_triangle`] of every triangle whose box is no nearer than the
/// best so far (same answer, most tests skipped).
///
/// ```
/// use glam::DVec3;
/// use gng3d_mesh::geometry::{box_distance2, closest_point_triangle};
/// let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
/// let p = DVec3::new(2.0, 0.5, 1.0);
/// assert_eq!(box_distance2(p, a, b, c), 2.0); // 1 in x, 1 in z
/// assert!(box_distance2(p, a, b, c) <= (closest_point_triangle(p, a, b, c) - p).length_squared());
/// ```
#[inline]
pub fn box_distance2(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    (p.clamp(a.min(b).min(c), a.max(b).max(c)) - p).length_squared()
}

/// Closest point to `p` on triangle `abc` (f64, exact up to rounding, any triangle shape).
pub fn closest_point_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    if is_degenerate(a, b, c) {
        let candidates = [
            closest_point_segment(p, a, b),
            closest_point_segment(p, b, c),
            closest_point_segment(p, c, a),
        ];
        return candidates
            .into_iter()
            .min_by(|x, y| {
                (p - *x)
                    .length_squared()
                    .total_cmp(&(p - *y).length_squared())
            })
            .unwrap_or(a);
    }
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    let e = d4 - d3;
    let f = d5 - d6;
    if va <= 0.0 && e >= 0.0 && f >= 0.0 {
        return b + (c - b) * (e / (e + f));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

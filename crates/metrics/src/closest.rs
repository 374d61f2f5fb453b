//! Closest-point queries: the exact f64 primitives live in [`mesh::geometry`] (re-exported
//! here); this module adds their f32 twins for the distance index's hot loop.

use glam::{DVec3, Vec3A};
pub use mesh::geometry::{closest_point_segment, closest_point_triangle, is_degenerate};

/// A triangle prepared for fast f32 distance tests.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PackedTriangle {
    pub a: Vec3A,
    pub b: Vec3A,
    pub c: Vec3A,
}

/// The vector operations the region walk of [`squared_distance`] needs, for glam's f32
/// ([`Vec3A`]) and f64 ([`DVec3`]) vectors: one routine, two precisions.
pub(crate) trait Vector:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Self::Scalar, Output = Self>
{
    /// `f32` or `f64`.
    type Scalar: Copy
        + Default
        + PartialOrd
        + std::ops::Add<Output = Self::Scalar>
        + std::ops::Sub<Output = Self::Scalar>
        + std::ops::Mul<Output = Self::Scalar>
        + std::ops::Div<Output = Self::Scalar>;
    fn dot(self, other: Self) -> Self::Scalar;
    fn cross(self, other: Self) -> Self;
    fn length_squared(self) -> Self::Scalar;
}

macro_rules! vector {
    ($v:ty, $s:ty) => {
        impl Vector for $v {
            type Scalar = $s;
            #[inline(always)]
            fn dot(self, other: Self) -> $s {
                <$v>::dot(self, other)
            }
            #[inline(always)]
            fn cross(self, other: Self) -> Self {
                <$v>::cross(self, other)
            }
            #[inline(always)]
            fn length_squared(self) -> $s {
                <$v>::length_squared(self)
            }
        }
    };
}
vector!(Vec3A, f32);
vector!(DVec3, f64);

/// Squared distance from `p` to the non-degenerate triangle `abc`: the regions of
/// [`closest_point_triangle`] (Ericson's walk), and in the face region the distance to the
/// plane, which is cheaper and better conditioned than reconstructing the point (and exactly
/// zero for a point on an axis-aligned plane, so a search there stops at the first face holding
/// the point). When rounding makes a thin sliver look flat (the barycentric denominator is not
/// positive), `flat()` gives the answer.
#[inline(always)]
fn squared_distance<V: Vector>(
    p: V,
    [a, b, c]: [V; 3],
    flat: impl FnOnce() -> V::Scalar,
) -> V::Scalar {
    let zero = V::Scalar::default();
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= zero && d2 <= zero {
        return ap.length_squared();
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= zero && d4 <= d3 {
        return bp.length_squared();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= zero && d1 >= zero && d3 <= zero {
        return (p - (a + ab * (d1 / (d1 - d3)))).length_squared();
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= zero && d5 <= d6 {
        return cp.length_squared();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= zero && d2 >= zero && d6 <= zero {
        return (p - (a + ac * (d2 / (d2 - d6)))).length_squared();
    }
    let va = d3 * d6 - d5 * d4;
    let e = d4 - d3;
    let f = d5 - d6;
    if va <= zero && e >= zero && f >= zero {
        return (p - (b + (c - b) * (e / (e + f)))).length_squared();
    }
    if (va + vb + vc).partial_cmp(&zero) != Some(std::cmp::Ordering::Greater) {
        return flat();
    }
    let n = ab.cross(ac);
    let h = ap.dot(n);
    h * h / n.length_squared()
}

/// Squared distance from `p` to a non-degenerate packed triangle, in f32 (used to pick
/// candidates, the winner is re-evaluated in f64). A sliver that rounding makes look flat
/// gets the closest of its three edges.
#[inline(always)]
pub(crate) fn squared_distance_f32(p: Vec3A, t: &PackedTriangle) -> f32 {
    squared_distance(p, [t.a, t.b, t.c], || squared_distance_segments_f32(p, t))
}

/// The same in f64, for slivers, where the f32 routine's region tests and plane fail (see the
/// index's `Scoring::Exact`); a flat-looking one falls back to [`closest_point_triangle`].
#[inline]
pub(crate) fn squared_distance_f64(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    squared_distance(p, [a, b, c], || {
        (p - closest_point_triangle(p, a, b, c)).length_squared()
    })
}

/// Squared distance from `p` to the closest of the three edges of `t` (f32).
#[inline]
pub(crate) fn squared_distance_segments_f32(p: Vec3A, t: &PackedTriangle) -> f32 {
    let seg = |a: Vec3A, b: Vec3A| {
        let ab = b - a;
        let len2 = ab.length_squared();
        let s = if len2 > 0.0 {
            ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - (a + ab * s)).length_squared()
    };
    seg(t.a, t.b).min(seg(t.b, t.c)).min(seg(t.c, t.a))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    /// Independent reference: project onto the plane and keep the projection when it is inside
    /// (sign of the three edge functions), otherwise the best of the three clamped segment
    /// projections. For degenerate triangles only the segments count.
    fn reference(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
        let mut best = [(a, b), (b, c), (c, a)]
            .iter()
            .map(|&(u, w)| (p - closest_point_segment(p, u, w)).length())
            .fold(f64::INFINITY, f64::min);
        let n = (b - a).cross(c - a);
        if n.length_squared() > 1e-20 {
            let nn = n.normalize();
            let q = p - nn * (p - a).dot(nn);
            let inside = [(a, b), (b, c), (c, a)]
                .iter()
                .all(|&(u, w)| (w - u).cross(q - u).dot(n) >= 0.0);
            if inside {
                best = best.min((p - q).length());
            }
        }
        best
    }

    /// Dense barycentric grid: an upper bound on the true distance that converges to it.
    fn grid_min(p: DVec3, a: DVec3, b: DVec3, c: DVec3, n: usize) -> f64 {
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let q = a + (b - a) * u + (c - a) * v;
                best = best.min((p - q).length());
            }
        }
        best
    }

    fn random_point(rng: &mut Pcg64Mcg, scale: f64) -> DVec3 {
        DVec3::new(
            rng.random_range(-scale..scale),
            rng.random_range(-scale..scale),
            rng.random_range(-scale..scale),
        )
    }

    /// Three random corners in the unit cube around the origin.
    fn random_triangle(rng: &mut Pcg64Mcg) -> (DVec3, DVec3, DVec3) {
        (
            random_point(rng, 1.0),
            random_point(rng, 1.0),
            random_point(rng, 1.0),
        )
    }

    #[test]
    fn matches_reference_on_random_triangles_in_every_region() {
        let mut rng = Pcg64Mcg::seed_from_u64(11);
        let mut regions = [0usize; 7]; // 3 vertices, 3 edges, interior
        for _ in 0..20_000 {
            let (a, b, c) = random_triangle(&mut rng);
            // Points near and far, inside and outside of the triangle's prism.
            let p = random_point(&mut rng, 2.0);
            let q = closest_point_triangle(p, a, b, c);
            let d = (p - q).length();
            let r = reference(p, a, b, c);
            assert!((d - r).abs() <= 1e-9 * (1.0 + r), "{d} vs {r}");
            // The returned point lies on the triangle (barycentric coordinates in [0,1]).
            assert!(reference(q, a, b, c) < 1e-9);
            let region = if (q - a).length() < 1e-12 {
                0
            } else if (q - b).length() < 1e-12 {
                1
            } else if (q - c).length() < 1e-12 {
                2
            } else if (q - closest_point_segment(q, a, b)).length() < 1e-12 {
                3
            } else if (q - closest_point_segment(q, b, c)).length() < 1e-12 {
                4
            } else if (q - closest_point_segment(q, c, a)).length() < 1e-12 {
                5
            } else {
                6
            };
            regions[region] += 1;
        }
        for (i, &n) in regions.iter().enumerate() {
            assert!(n > 300, "region {i} hit only {n} times: {regions:?}");
        }
    }

    #[test]
    fn never_below_a_dense_grid_and_close_to_it() {
        let mut rng = Pcg64Mcg::seed_from_u64(5);
        for _ in 0..300 {
            let (a, b, c) = random_triangle(&mut rng);
            let p = random_point(&mut rng, 1.5);
            let d = (p - closest_point_triangle(p, a, b, c)).length();
            let g = grid_min(p, a, b, c, 200);
            let longest = (b - a).length().max((c - b).length()).max((a - c).length());
            assert!(d <= g + 1e-12, "exact {d} above grid {g}");
            assert!(g - d <= longest / 200.0, "grid {g} too far above exact {d}");
        }
    }

    #[test]
    fn degenerate_triangles() {
        let mut rng = Pcg64Mcg::seed_from_u64(3);
        for _ in 0..5000 {
            let a = random_point(&mut rng, 1.0);
            let dir = random_point(&mut rng, 1.0);
            let kind = rng.random_range(0..4);
            let (b, c) = match kind {
                // Collinear, c between a and b.
                0 => (a + dir, a + dir * rng.random_range(0.0..1.0)),
                // Collinear, c outside ab.
                1 => (a + dir, a + dir * rng.random_range(1.0..3.0)),
                // Two coincident corners.
                2 => (a, a + dir),
                // All three coincident.
                _ => (a, a),
            };
            let p = random_point(&mut rng, 2.0);
            for (x, y, z) in [(a, b, c), (b, c, a), (c, a, b), (a, c, b)] {
                let q = closest_point_triangle(p, x, y, z);
                assert!(q.is_finite());
                let d = (p - q).length();
                let r = reference(p, x, y, z);
                assert!((d - r).abs() <= 1e-9 * (1.0 + r), "kind {kind}: {d} vs {r}");
                let packed = PackedTriangle {
                    a: x.as_vec3a(),
                    b: y.as_vec3a(),
                    c: z.as_vec3a(),
                };
                let ds = squared_distance_segments_f32(p.as_vec3a(), &packed).sqrt() as f64;
                assert!((ds - r).abs() <= 1e-5 * (1.0 + r));
            }
        }
    }

    #[test]
    fn f64_scoring_matches_closest_point() {
        let mut rng = Pcg64Mcg::seed_from_u64(23);
        for _ in 0..20_000 {
            let (a, b, c) = random_triangle(&mut rng);
            if is_degenerate(a, b, c) {
                continue;
            }
            let p = random_point(&mut rng, 2.0);
            let exact = (p - closest_point_triangle(p, a, b, c)).length();
            let scored = squared_distance_f64(p, a, b, c).sqrt();
            assert!(
                (scored - exact).abs() <= 1e-12 * (1.0 + exact),
                "{scored} vs {exact}"
            );
        }
        // A sliver of a fan (length 2, 1e-3 wide) and points just beside it, in its plane: the
        // f32 routine called such points inside.
        let (a, b, c) = (
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1e-3, 0.0),
        );
        for k in 1..100 {
            let x = -1.0 + 0.02 * k as f64;
            let inside = DVec3::new(x, 0.25e-3 * (x + 1.0), 0.0);
            assert_eq!(squared_distance_f64(inside, a, b, c), 0.0);
            let beside = DVec3::new(x, -1e-5, 0.0);
            let d = squared_distance_f64(beside, a, b, c).sqrt();
            assert!((d - 1e-5).abs() < 1e-12, "{d}");
        }
    }

    #[test]
    fn f32_path_agrees_with_f64() {
        let mut rng = Pcg64Mcg::seed_from_u64(17);
        for _ in 0..20_000 {
            let (a, b, c) = random_triangle(&mut rng);
            if is_degenerate(a, b, c) {
                continue;
            }
            let p = random_point(&mut rng, 2.0);
            let t = PackedTriangle {
                a: a.as_vec3a(),
                b: b.as_vec3a(),
                c: c.as_vec3a(),
            };
            // Compare against the f64 routine on the same f32-rounded inputs.
            let exact = (p.as_vec3a().as_dvec3()
                - closest_point_triangle(
                    p.as_vec3a().as_dvec3(),
                    t.a.as_dvec3(),
                    t.b.as_dvec3(),
                    t.c.as_dvec3(),
                ))
            .length();
            let fast = (squared_distance_f32(p.as_vec3a(), &t) as f64).sqrt();
            assert!(
                (fast - exact).abs() <= 2e-5 * (1.0 + exact),
                "{fast} vs {exact}"
            );
        }
    }
}

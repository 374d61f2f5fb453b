//! Symmetric quadric error forms `E(v) = vᵀAv + 2bᵀv + c` in f64 (10 coefficients), the
//! Garland–Heckbert per-face primitives built from them (area-weighted face planes, boundary
//! constraint planes), and a rank-truncated minimiser for near-singular quadrics.
//!
//! Shared by QEM (`qem`, which builds its vertex quadrics from these primitives) and GNG3D-Q's
//! quadric vertex placement (`gng3d-core`), so both optimise the same error.

use glam::DVec3;
use std::ops::{Add, AddAssign};

/// Quadric `E(v) = vᵀAv + 2bᵀv + c` with symmetric `A`, stored as its 6 upper-triangle entries,
/// the 3-vector `b` and the scalar `c`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Quadric {
    /// Upper triangle of `A`: a00, a01, a02, a11, a12, a22.
    pub a: [f64; 6],
    /// Linear term `b`.
    pub b: [f64; 3],
    /// Constant term `c`.
    pub c: f64,
}

impl Quadric {
    /// Weighted squared-distance quadric of the plane `n·v + d = 0`; `n` should be unit length.
    #[inline]
    pub fn from_plane(n: DVec3, d: f64, weight: f64) -> Quadric {
        let (x, y, z) = (n.x * weight, n.y * weight, n.z * weight);
        Quadric {
            a: [x * n.x, x * n.y, x * n.z, y * n.y, y * n.z, z * n.z],
            b: [x * d, y * d, z * d],
            c: weight * d * d,
        }
    }

    /// `A v`.
    #[inline]
    pub fn mul_a(&self, v: DVec3) -> DVec3 {
        let a = &self.a;
        DVec3::new(
            a[0] * v.x + a[1] * v.y + a[2] * v.z,
            a[1] * v.x + a[3] * v.y + a[4] * v.z,
            a[2] * v.x + a[4] * v.y + a[5] * v.z,
        )
    }

    /// Linear term as a vector.
    #[inline]
    pub fn b_vec(&self) -> DVec3 {
        DVec3::new(self.b[0], self.b[1], self.b[2])
    }

    /// Error at `v`: `vᵀAv + 2bᵀv + c` (can be slightly negative through rounding).
    #[inline]
    pub fn eval(&self, v: DVec3) -> f64 {
        v.dot(self.mul_a(v) + 2.0 * self.b_vec()) + self.c
    }

    /// Trace of `A` (the summed weight for plane quadrics with unit normals).
    #[inline]
    pub fn trace(&self) -> f64 {
        self.a[0] + self.a[3] + self.a[5]
    }

    /// Area-weighted plane quadric of triangle `p0 p1 p2`: the squared distance to its plane
    /// times its area (model units⁴ when evaluated). Zero for degenerate or non-finite
    /// triangles. Same numbers as qem's vertex setup (see [`area_weighted_plane`]).
    #[inline]
    pub fn from_triangle(p0: DVec3, p1: DVec3, p2: DVec3) -> Quadric {
        let [gx, gy, gz, gd] = area_weighted_plane(p0, p1, p2);
        Quadric::from_plane(DVec3::new(gx, gy, gz), gd, 1.0)
    }

    /// Constraint quadric of the boundary edge `lo → hi` of a face with corners `face`: the
    /// plane through the edge perpendicular to the face, weighted by
    /// `boundary_weight · |hi − lo|²` (Garland–Heckbert's boundary preservation, with qem's
    /// weighting: `QemParams::boundary_weight`, default 1000). Zero when the face or the edge is
    /// degenerate. The plane does not depend on the edge direction, so both ends of an edge may
    /// add the same quadric.
    #[inline]
    pub fn from_boundary_edge(
        lo: DVec3,
        hi: DVec3,
        face: [DVec3; 3],
        boundary_weight: f64,
    ) -> Quadric {
        let [p0, p1, p2] = face;
        let face_normal = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        let edge = hi - lo;
        let m = edge.cross(face_normal).normalize_or_zero();
        if m == DVec3::ZERO {
            return Quadric::default();
        }
        Quadric::from_plane(m, -m.dot(lo), boundary_weight * edge.length_squared())
    }

    /// Minimiser of `E` restricted to the well-conditioned directions of `A`, found from `start`:
    /// with the eigen-decomposition `A = Σ λᵢ uᵢuᵢᵀ`, every direction with
    /// `λᵢ > rel_tol · λ_max` takes one Newton step, the others keep `start`'s coordinate:
    /// `v = start − Σ (uᵢ·(A start + b) / λᵢ) uᵢ`. On a flat cell (one large eigenvalue) this
    /// moves `start` onto the plane only; on a crease (two) onto the crease line; at a corner
    /// (three) to the corner. A plain determinant test instead accepts barely regular `A` and
    /// sends nearly flat cells far along their null direction. Returns `start` when `A` is zero
    /// or not finite.
    pub fn minimizer_near(&self, start: DVec3, rel_tol: f64) -> DVec3 {
        let (values, vectors) = symmetric_eigen(self.a);
        let max = values.iter().fold(0.0f64, |m, &l| m.max(l));
        if !(max > 0.0 && max.is_finite()) {
            return start;
        }
        let gradient = self.mul_a(start) + self.b_vec();
        let mut v = start;
        for (l, u) in values.iter().zip(vectors) {
            if *l > rel_tol * max {
                v -= u * (u.dot(gradient) / l);
            }
        }
        v
    }

    /// Minimiser of `E`, solving `A v = −b` by the closed-form inverse, or `None` when `A` is
    /// (relatively) singular: `|det A| ≤ 1e-12 · tr(A)³`.
    #[inline]
    pub fn minimizer(&self) -> Option<DVec3> {
        let [a00, a01, a02, a11, a12, a22] = self.a;
        let c00 = a11 * a22 - a12 * a12;
        let c01 = a02 * a12 - a01 * a22;
        let c02 = a01 * a12 - a02 * a11;
        let det = a00 * c00 + a01 * c01 + a02 * c02;
        let tr = self.trace();
        if tr.is_nan() || tr <= 0.0 || det.abs() <= 1e-12 * tr * tr * tr {
            return None;
        }
        let c11 = a00 * a22 - a02 * a02;
        let c12 = a01 * a02 - a00 * a12;
        let c22 = a00 * a11 - a01 * a01;
        let inv = 1.0 / det;
        let [b0, b1, b2] = self.b;
        let x = -(c00 * b0 + c01 * b1 + c02 * b2) * inv;
        let y = -(c01 * b0 + c11 * b1 + c12 * b2) * inv;
        let z = -(c02 * b0 + c12 * b1 + c22 * b2) * inv;
        Some(DVec3::new(x, y, z))
    }
}

/// Plane of triangle `p0 p1 p2` scaled so that its outer product is the area-weighted plane
/// quadric: `[g, gd]` with `g = n·√area`, `gd = −g·p0` (all zero for degenerate faces). qem's
/// vertex setup computes its face planes with this.
#[inline]
pub fn area_weighted_plane(p0: DVec3, p1: DVec3, p2: DVec3) -> [f64; 4] {
    let cross = (p1 - p0).cross(p2 - p0);
    let len = cross.length();
    if len > 0.0 && len.is_finite() {
        let g = cross * (0.5 / len).sqrt();
        [g.x, g.y, g.z, -g.dot(p0)]
    } else {
        [0.0; 4]
    }
}

/// Eigen-decomposition of the symmetric 3×3 matrix with upper triangle
/// `[a00, a01, a02, a11, a12, a22]` by cyclic Jacobi rotations: eigenvalues and orthonormal
/// eigenvectors (unordered). Converges to f64 precision in a handful of sweeps for any input;
/// non-finite input gives non-finite values.
pub fn symmetric_eigen(upper: [f64; 6]) -> ([f64; 3], [DVec3; 3]) {
    let [a00, a01, a02, a11, a12, a22] = upper;
    let mut m = [[a00, a01, a02], [a01, a11, a12], [a02, a12, a22]];
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..32 {
        let off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
        let diag = m[0][0] * m[0][0] + m[1][1] * m[1][1] + m[2][2] * m[2][2];
        // Converged (or not finite: NaN compares false).
        if off.partial_cmp(&(1e-30 * diag)) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if m[p][q] == 0.0 {
                continue;
            }
            // Rotation that zeroes m[p][q] (Numerical Recipes' stable form).
            let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // Columns p, q (M·J), then rows p, q (Jᵀ·M·J).
            for row in m.iter_mut() {
                let (mkp, mkq) = (row[p], row[q]);
                row[p] = c * mkp - s * mkq;
                row[q] = s * mkp + c * mkq;
            }
            let (row_p, row_q) = (m[p], m[q]);
            for k in 0..3 {
                m[p][k] = c * row_p[k] - s * row_q[k];
                m[q][k] = s * row_p[k] + c * row_q[k];
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let col = |j: usize| DVec3::new(v[0][j], v[1][j], v[2][j]);
    ([m[0][0], m[1][1], m[2][2]], [col(0), col(1), col(2)])
}

impl Add for Quadric {
    type Output = Quadric;
    #[inline]
    fn add(mut self, o: Quadric) -> Quadric {
        self += o;
        self
    }
}

impl AddAssign for Quadric {
    #[inline]
    fn add_assign(&mut self, o: Quadric) {
        for i in 0..6 {
            self.a[i] += o.a[i];
        }
        for i in 0..3 {
            self.b[i] += o.b[i];
        }
        self.c += o.c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_quadric_is_squared_distance() {
        let n = DVec3::new(1.0, 2.0, -2.0).normalize();
        let d = 0.7;
        let q = Quadric::from_plane(n, d, 3.0);
        let v = DVec3::new(0.3, -1.1, 2.5);
        let dist = n.dot(v) + d;
        assert!((q.eval(v) - 3.0 * dist * dist).abs() < 1e-12);
    }

    #[test]
    fn eigen_decomposition_reconstructs_the_matrix() {
        let upper = [4.0, 1.0, -2.0, 3.0, 0.5, 5.0];
        let (values, vectors) = symmetric_eigen(upper);
        let q = Quadric {
            a: upper,
            b: [0.0; 3],
            c: 0.0,
        };
        for (l, u) in values.iter().zip(vectors) {
            assert!((u.length() - 1.0).abs() < 1e-12);
            assert!((q.mul_a(u) - u * *l).length() < 1e-10);
        }
        let trace: f64 = values.iter().sum();
        assert!((trace - 12.0).abs() < 1e-10);
    }

    #[test]
    fn triangle_quadric_is_area_times_squared_plane_distance() {
        let (p0, p1, p2) = (
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 3.0, 0.0),
        );
        let q = Quadric::from_triangle(p0, p1, p2);
        // Area 3, plane z = 0.
        assert!((q.eval(DVec3::new(5.0, -1.0, 0.5)) - 3.0 * 0.25).abs() < 1e-12);
        assert_eq!(Quadric::from_triangle(p0, p1, p1 * 2.0), Quadric::default());
        // Boundary edge p0 -> p1 of that face: plane y = 0, weight 10 · 4.
        let b = Quadric::from_boundary_edge(p0, p1, [p0, p1, p2], 10.0);
        assert!((b.eval(DVec3::new(7.0, 0.5, 3.0)) - 40.0 * 0.25).abs() < 1e-9);
    }

    #[test]
    fn truncated_minimiser_stays_put_along_flat_directions() {
        // One plane z = 1 plus a tiny second plane: a determinant test would accept the
        // near-singular system and jump far along x; the truncated solve only fixes z.
        let q = Quadric::from_plane(DVec3::Z, -1.0, 1.0)
            + Quadric::from_plane(DVec3::new(1.0, 0.0, 1e-3).normalize(), -50.0, 1e-6);
        let start = DVec3::new(0.2, 0.3, 0.0);
        let v = q.minimizer_near(start, 1e-3);
        assert!((v - DVec3::new(0.2, 0.3, 1.0)).length() < 1e-6, "{v}");
        // Three planes: the exact corner.
        let p = DVec3::new(0.5, -0.25, 2.0);
        let mut corner = Quadric::default();
        for n in [DVec3::X, DVec3::Y, DVec3::Z] {
            corner += Quadric::from_plane(n, -n.dot(p), 1.0);
        }
        assert!((corner.minimizer_near(DVec3::ZERO, 1e-3) - p).length() < 1e-12);
        assert_eq!(Quadric::default().minimizer_near(start, 1e-3), start);
    }

    #[test]
    fn three_planes_minimise_at_their_intersection() {
        let p = DVec3::new(0.5, -0.25, 2.0);
        let mut q = Quadric::default();
        for n in [
            DVec3::X,
            DVec3::new(1.0, 1.0, 0.0).normalize(),
            DVec3::new(0.0, 1.0, 1.0).normalize(),
        ] {
            q += Quadric::from_plane(n, -n.dot(p), 1.0);
        }
        let m = q.minimizer().expect("non-singular");
        assert!((m - p).length() < 1e-12);
        assert!(q.eval(m).abs() < 1e-12);
        // Two planes only: singular.
        let q2 = Quadric::from_plane(DVec3::X, 0.0, 1.0) + Quadric::from_plane(DVec3::Y, 0.0, 1.0);
        assert!(q2.minimizer().is_none());
    }
}

//! Symmetric quadric error forms `E(v) = vᵀAv + 2bᵀv + c` in f64 (10 coefficients).

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

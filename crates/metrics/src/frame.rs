//! The frame distances are searched in: a mesh scaled by the power of two nearest to a bounding
//! box's diagonal and, when the box lies farther than one diagonal from the origin, translated
//! to the box's centre.
//!
//! The closest-point and nearest-vertex searches compare squared distances in f32, which
//! underflow below ~1e-19 model units and overflow above ~1e19: a sphere at 1e-25 or 1e10 picked
//! arbitrary faces and measured itself 0.6 % to 58 % of its diagonal away (issue 33, row 15). In
//! the frame every coordinate of the measured meshes is of order 1, whatever the model units,
//! and an off-origin model keeps the full f32 precision around its own centre. The scale is a
//! power of two, so multiplying a distance back into model units is exact, and a model near the
//! origin (not translated) is held exactly: every f32 coordinate divided by a power of two is
//! an f32 coordinate again.

use crate::MetricsError;
use glam::{DVec3, Vec3};
use mesh::{Aabb, TriMesh};

/// Largest distance, in frame units (about bounding-box diagonals of the mesh the frame was
/// made for), at which a point can be measured: squared in f32 it must stay below f32::MAX
/// (≈ 3.4e38) with room for three axes and rounding.
pub const MAX_SPAN: f64 = 1e18;

/// A similarity `model = frame · scale + center` with a power-of-two `scale`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    center: DVec3,
    scale: f64,
}

impl Frame {
    /// The frame of `bbox`: the power of two nearest to its diagonal (1 for an empty box or one
    /// of zero extent), and its centre when that is farther than one diagonal from the origin
    /// (else the origin, so the scaling is exact).
    pub(crate) fn of_box(bbox: &Aabb) -> Frame {
        if bbox.is_empty() {
            return Frame {
                center: DVec3::ZERO,
                scale: 1.0,
            };
        }
        let diagonal = bbox.diagonal();
        let mid = (bbox.min.as_dvec3() + bbox.max.as_dvec3()) * 0.5;
        let center = if mid.abs().max_element() > diagonal {
            mid
        } else {
            DVec3::ZERO
        };
        let scale = if diagonal > 0.0 && diagonal.is_finite() {
            power_of_two_near(diagonal)
        } else {
            1.0
        };
        Frame { center, scale }
    }

    /// The frame of `mesh`'s referenced vertices (see [`Frame::of_box`]).
    pub(crate) fn of_mesh(mesh: &TriMesh) -> Frame {
        Frame::of_box(&mesh.referenced_bounding_box())
    }

    /// The frame of `points`, or of `points` and `others` together when `points` alone has no
    /// extent.
    pub(crate) fn of_points(points: &[Vec3], others: &[Vec3]) -> Frame {
        let own = Aabb::from_points(points);
        if own.diagonal() > 0.0 {
            return Frame::of_box(&own);
        }
        Frame::of_box(&others.iter().fold(own, |b, p| b.grown(*p)))
    }

    /// Model units per frame unit (a power of two).
    pub(crate) fn scale(&self) -> f64 {
        self.scale
    }

    /// `p` in frame coordinates, f64 (exact up to one rounding of the translation).
    #[inline]
    pub(crate) fn to_frame(self, p: Vec3) -> DVec3 {
        (p.as_dvec3() - self.center) / self.scale
    }

    /// A frame point back in model coordinates.
    #[inline]
    pub(crate) fn to_model(self, q: DVec3) -> DVec3 {
        q * self.scale + self.center
    }

    /// A copy of `mesh` in frame coordinates (all vertex records, unreferenced ones included;
    /// the triangles are shared as they are).
    pub(crate) fn apply(&self, mesh: &TriMesh) -> TriMesh {
        TriMesh::new(
            mesh.positions
                .iter()
                .map(|&p| self.to_frame(p).as_vec3())
                .collect(),
            mesh.triangles.clone(),
        )
    }

    /// Checks that the referenced vertices of `mesh` (all of its vertex records when
    /// `all_vertices`) lie within [`MAX_SPAN`] frame units of the centre; `which` names the mesh
    /// in the error.
    pub(crate) fn check_span(
        &self,
        mesh: &TriMesh,
        which: &'static str,
        all_vertices: bool,
    ) -> Result<(), MetricsError> {
        let check = |v: usize| {
            let q = self.to_frame(mesh.positions[v]);
            // Written so that NaN fails too.
            if q.abs().max_element() <= MAX_SPAN {
                Ok(())
            } else {
                Err(MetricsError::CoordinateRange {
                    mesh: which,
                    vertex: v,
                    limit: MAX_SPAN,
                })
            }
        };
        if all_vertices {
            (0..mesh.positions.len()).try_for_each(check)
        } else {
            mesh.triangles
                .iter()
                .flatten()
                .try_for_each(|&v| check(v as usize))
        }
    }
}

/// The power of two nearest to `x` (in log scale); `x` positive and finite.
fn power_of_two_near(x: f64) -> f64 {
    let e = x.log2().round().clamp(-1022.0, 1023.0) as i32;
    // Built from the exponent bits: exact, where powi might round.
    f64::from_bits(((e + 1023) as u64) << 52)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_is_the_nearest_power_of_two_and_round_trips_exactly() {
        for (diag, expected) in [(1.0, 1.0), (3.0, 4.0), (0.7, 0.5), (1e-25, 2f64.powi(-83))] {
            assert_eq!(power_of_two_near(diag), expected, "{diag}");
        }
        // Near the origin: scaled only, exactly.
        let b = Aabb::from_points(&[Vec3::new(1e10, -2e10, 0.0), Vec3::new(3e10, 2e10, 1e10)]);
        let f = Frame::of_box(&b);
        assert_eq!(f.center, DVec3::ZERO);
        assert_eq!(f.scale(), 2f64.powi(35));
        let q = f.to_frame(b.max);
        assert_eq!(q.as_vec3().as_dvec3(), q);
        assert_eq!(f.to_model(q), b.max.as_dvec3());
        // Far from it: centred too.
        let b = Aabb::from_points(&[
            Vec3::new(1e6, 1e6, 1e6),
            Vec3::new(1e6 + 2.0, 1e6 + 1.0, 1e6),
        ]);
        let f = Frame::of_box(&b);
        assert_eq!(f.center, DVec3::new(1e6 + 1.0, 1e6 + 0.5, 1e6));
        let q = f.to_frame(b.max);
        assert!(q.abs().max_element() < 1.0, "{q}");
        assert_eq!(f.to_model(q), b.max.as_dvec3());
        // Zero extent and empty boxes get scale 1.
        assert_eq!(Frame::of_box(&Aabb::from_points(&[Vec3::ONE])).scale(), 1.0);
        assert_eq!(Frame::of_box(&Aabb::EMPTY).scale(), 1.0);
    }
}

//! The face-soundness guard shared by the passes that change output faces: the flips (a new
//! diagonal), the refit and the relaxation (a vertex move) and the deviation repair (a vertex
//! move or a split). A changed face is sound when it is not degenerate, its normal keeps a
//! minimum cosine with a reference normal (what the surface looked like there before the
//! change) and its smallest angle stays above the smaller of the old faces' smallest angle and
//! a floor. Each pass states its two thresholds as a named [`FaceRule`] (the numbers and their
//! measurements are documented at the constants they come from); what differs between passes is
//! only which normal is the reference.

use glam::DVec3;

/// One pass's thresholds for [`FaceRule::accepts`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct FaceRule {
    /// A changed face's unit normal must have at least this cosine with the reference normal.
    pub min_normal_cos: f64,
    /// A changed face's smallest angle may drop to the old smallest angle or to this many
    /// degrees, whichever is smaller.
    pub keep_angle_degrees: f64,
}

/// Each new face normal must have at least this cosine with the old pair's (area-weighted)
/// normal, as in qem's `min_normal_cos`.
pub const FLIP_MIN_NORMAL_COS: f64 = 0.2;

/// New faces may have a smallest angle down to the old pair's, or down to this many degrees
/// when the old pair's was larger.
pub const FLIP_KEEP_ANGLE_DEGREES: f64 = 25.0;

/// An incident face's normal must keep at least this cosine with its normal before the move
/// (~45°; not swept).
pub const REFIT_MAX_TURN_COS: f64 = 0.7;

/// An interior vertex's move must leave each of its faces with a smallest angle of at least
/// this, or at least the face's angle before the move when that was smaller; otherwise only the
/// move's component along the vertex normal is tried. Over the survey (45 runs) the refit
/// without this rule won triangle quality (median smallest angle and share under 20°) against
/// QEM in 40 runs instead of 41, share under 20° 42 instead of 44 (cow at 10 %: 9.9 → 13.9 %
/// of triangles under 20°), E_avg 41 instead of 43; with it the median mean-distance ratio is
/// 1.53 instead of 1.49. 25° (the flips' bound) cost more distance (gargoyle-10k 10 %: 1.23 vs
/// 1.19× QEM); holding border vertices to it too raised the survey's median Hausdorff ratio
/// from 2.75 to 2.82 (the bunny's rim at 10 %: 1.77 → 2.62× QEM).
pub const REFIT_KEEP_ANGLE_DEGREES: f64 = 20.0;

/// Each changed face's normal must have at least this cosine with the old faces' (area-weighted)
/// mean normal (as the flips' [`FLIP_MIN_NORMAL_COS`]).
pub const DEVIATION_MIN_NORMAL_COS: f64 = 0.2;

/// Changed faces may have a smallest angle down to the old faces' smallest, or down to this
/// many degrees when that was larger. The spikes are mostly vertices of valence 3 (a face split
/// in three), whose faces flatten into thinner ones: with 20° (the refit's bound) the bunny at
/// 50 % kept its two worst spikes (Hausdorff 3.3e-4, 1.34e-4 with 10°); 5° changed nothing
/// more. Over the 42 runs: 20° × 0.908, 10° × 0.810.
pub const DEVIATION_KEEP_ANGLE_DEGREES: f64 = 10.0;

/// The flips' rule (new diagonal's faces against the old pair's summed normal):
/// [`FLIP_MIN_NORMAL_COS`], [`FLIP_KEEP_ANGLE_DEGREES`]. The flips also refuse
/// folds sharper than [`crate::reconstruct::flip::MIN_FOLD_COS`] between the two new faces.
pub(crate) const FLIP: FaceRule = FaceRule {
    min_normal_cos: FLIP_MIN_NORMAL_COS,
    keep_angle_degrees: FLIP_KEEP_ANGLE_DEGREES,
};

/// The refit's and relaxation's rule (each face against its own normal before the move):
/// [`REFIT_MAX_TURN_COS`], [`REFIT_KEEP_ANGLE_DEGREES`].
pub(crate) const REFIT: FaceRule = FaceRule {
    min_normal_cos: REFIT_MAX_TURN_COS,
    keep_angle_degrees: REFIT_KEEP_ANGLE_DEGREES,
};

/// The deviation repair's rule (changed faces against the old faces' area-weighted mean
/// normal): [`DEVIATION_MIN_NORMAL_COS`], [`DEVIATION_KEEP_ANGLE_DEGREES`].
pub(crate) const DEVIATION: FaceRule = FaceRule {
    min_normal_cos: DEVIATION_MIN_NORMAL_COS,
    keep_angle_degrees: DEVIATION_KEEP_ANGLE_DEGREES,
};

impl FaceRule {
    /// Squared sine of the angle floor (compared with [`min_angle_sin2`]).
    #[inline]
    pub(crate) fn keep_sin2(&self) -> f64 {
        self.keep_angle_degrees.to_radians().sin().powi(2)
    }

    /// Whether unit normal `normal` agrees with unit normal `reference`.
    #[inline]
    pub(crate) fn normal_agrees(&self, normal: DVec3, reference: DVec3) -> bool {
        normal.dot(reference) >= self.min_normal_cos
    }

    /// Whether a face whose smallest angle has squared sine `new_sin2` keeps its shape against
    /// an old smallest angle of squared sine `old_sin2` (`keep_sin2` is [`FaceRule::keep_sin2`],
    /// passed in so that loops work it out once).
    #[inline]
    pub(crate) fn keeps_shape(new_sin2: f64, old_sin2: f64, keep_sin2: f64) -> bool {
        new_sin2 >= old_sin2.min(keep_sin2)
    }

    /// The whole rule for a changed face `new`: not degenerate, normal within the rule's cosine
    /// of `reference` (unit), smallest angle kept against `old_sin2`.
    #[inline]
    pub(crate) fn accepts(&self, new: [DVec3; 3], reference: DVec3, old_sin2: f64) -> bool {
        let [a, b, c] = new;
        !mesh::geometry::is_degenerate(a, b, c)
            && self.normal_agrees((b - a).cross(c - a).normalize_or_zero(), reference)
            && FaceRule::keeps_shape(min_angle_sin2(a, b, c), old_sin2, self.keep_sin2())
    }
}

/// Squared sine of the smallest interior angle of a triangle (0 for degenerate ones). The
/// smallest angle (≤ 60°) sits between the two longest edges, so
/// `sin² = |cross|² / (|e₁|²·|e₂|²)` over those two; monotone in the angle, no trigonometry.
#[inline]
pub(crate) fn min_angle_sin2(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let cross = (b - a).cross(c - a).length_squared();
    let (x, y, z) = (
        (b - a).length_squared(),
        (c - b).length_squared(),
        (a - c).length_squared(),
    );
    let shortest = x.min(y).min(z);
    let denom = x * y * z / shortest;
    if denom > 0.0 && denom.is_finite() {
        cross / denom
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_angle_matches_trigonometry() {
        // Independent computation: the three angles by acos of normalised edge dots.
        let tris = [
            [DVec3::ZERO, DVec3::X, DVec3::Y],
            [
                DVec3::ZERO,
                DVec3::new(3.0, 0.0, 0.0),
                DVec3::new(0.2, 0.1, 0.0),
            ],
            [
                DVec3::ZERO,
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(0.5, 3f64.sqrt() / 2.0, 0.0),
            ],
        ];
        for [a, b, c] in tris {
            let angle = |p: DVec3, q: DVec3, r: DVec3| (q - p).angle_between(r - p);
            let smallest = angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b));
            assert!((min_angle_sin2(a, b, c) - smallest.sin().powi(2)).abs() < 1e-12);
        }
        assert_eq!(min_angle_sin2(DVec3::ZERO, DVec3::X, 2.0 * DVec3::X), 0.0);
    }

    #[test]
    fn rule_refuses_turned_thin_and_degenerate_faces() {
        let up = DVec3::Z;
        let good = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let old = min_angle_sin2(good[0], good[1], good[2]); // 45°
        assert!(DEVIATION.accepts(good, up, old));
        // Turned upside down (normal -Z).
        assert!(!DEVIATION.accepts([good[0], good[2], good[1]], up, old));
        // A 5° sliver under the 10° floor when the old face had 45°.
        let sliver = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 5f64.to_radians().tan(), 0.0),
        ];
        assert!(!DEVIATION.accepts(sliver, up, old));
        // ... but allowed when the old face was already thinner.
        assert!(DEVIATION.accepts(
            sliver,
            up,
            min_angle_sin2(DVec3::ZERO, DVec3::X, DVec3::new(1.0, 0.01, 0.0))
        ));
        // Collinear corners.
        assert!(!DEVIATION.accepts([DVec3::ZERO, DVec3::X, 2.0 * DVec3::X], up, 0.0));
        // The passes' floors are ordered as documented: deviation 10° < refit 20° < flip 25°.
        assert!(DEVIATION.keep_sin2() < REFIT.keep_sin2() && REFIT.keep_sin2() < FLIP.keep_sin2());
    }
}

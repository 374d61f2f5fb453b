//! Whether a vertex move keeps its faces sound: the refit's rule, which the relaxation takes too.

use super::soundness::{FaceRule, min_angle_sin2};
use glam::DVec3;

/// The refit's step 4 rule for a vertex move from `old` to `pos` (the two differ in that vertex only,
/// whose faces are `fan`): no face turns by more than `acos(`[`super::soundness::REFIT_MAX_TURN_COS`]`)` and, when
/// `keep_shape`, every face keeps its smallest angle above [`super::soundness::REFIT_KEEP_ANGLE_DEGREES`] or above its
/// old one. The refit's and the relaxation's rule.
pub(crate) fn move_fits(
    fan: &[u32],
    triangles: &[[u32; 3]],
    old: &[DVec3],
    pos: &[DVec3],
    keep_shape: bool,
) -> bool {
    let rule = super::soundness::REFIT;
    let keep_sin2 = rule.keep_sin2();
    fan.iter().all(|&f| {
        let t = triangles[f as usize];
        let turns_little = rule.normal_agrees(normal(t, old), normal(t, pos));
        let keeps_shape = !keep_shape || {
            let [a0, b0, c0] = t.map(|u| old[u as usize]);
            let [a1, b1, c1] = t.map(|u| pos[u as usize]);
            FaceRule::keeps_shape(
                min_angle_sin2(a1, b1, c1),
                min_angle_sin2(a0, b0, c0),
                keep_sin2,
            )
        };
        turns_little && keeps_shape
    })
}

/// Unit normal of face `t` (zero when degenerate).
pub(crate) fn normal(t: [u32; 3], pos: &[DVec3]) -> DVec3 {
    let [a, b, c] = t.map(|v| pos[v as usize]);
    (b - a).cross(c - a).normalize_or_zero()
}

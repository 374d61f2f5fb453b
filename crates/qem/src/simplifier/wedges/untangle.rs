//! Folds in texture space left by the carried values, undone where they can be: the merged
//! corners of a folded triangle move, in texture space only, to where fewer triangles around
//! them fold ([`untangle_uv`]).

use glam::Vec2;

/// Twice the signed area of a triangle in texture space.
pub(super) fn uv_area([a, b, c]: [Vec2; 3]) -> f32 {
    (b - a).perp_dot(c - a)
}

/// Sweeps of [`untangle_uv`]'s projections over a wedge's triangles.
const PROJECTION_SWEEPS: usize = 8;

/// Most rounds of [`untangle_uv`], a bound only: on spot at 2-50 % the first round moves all that
/// any round does, and the fandisk atlas, the knight and the horse have no fold left to untangle.
const UNTANGLE_ROUNDS: usize = 4;

/// Move the texture coordinates (components `at`, `at + 1` of each wedge's `stride` values) of
/// the `movable` corners of every folded triangle, a triangle whose orientation in texture space
/// is the reverse of `expected` (its input face's sign; 0: not checked), to the candidate with
/// the fewest folded triangles among the wedge's: its interpolated value (`lerp`), the centroid
/// of the other corners of its triangles, halfway to it, or its projection into every
/// triangle's unfolded side. A wedge moves only when that
/// lowers its count, so the number of folds never grows. Geometry is not touched.
pub(super) fn untangle_uv(
    corners: &[[u32; 3]],
    expected: &[f32],
    values: &mut [f32],
    stride: usize,
    at: usize,
    movable: impl Fn(u32) -> bool,
    lerp: impl Fn(u32) -> Vec2,
) {
    let uv = |values: &[f32], w: u32| Vec2::from_slice(&values[w as usize * stride + at..][..2]);
    let folded =
        |values: &[f32], t: usize| expected[t] * uv_area(corners[t].map(|w| uv(values, w))) < 0.0;
    if !(0..corners.len()).any(|t| folded(values, t)) {
        return;
    }
    // Each wedge's triangles.
    let wedges = values.len() / stride;
    let mut start = vec![0u32; wedges + 1];
    for c in corners.iter().flatten() {
        start[*c as usize + 1] += 1;
    }
    for i in 0..wedges {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut tris = vec![0u32; corners.len() * 3];
    for (t, c) in corners.iter().enumerate() {
        for &w in c {
            tris[fill[w as usize] as usize] = t as u32;
            fill[w as usize] += 1;
        }
    }
    let around = |w: u32| &tris[start[w as usize] as usize..start[w as usize + 1] as usize];
    // Folded triangles around `w` with its coordinates at `p`.
    let count = |values: &[f32], w: u32, p: Vec2| {
        around(w)
            .iter()
            .filter(|&&t| {
                let t = t as usize;
                let c = corners[t].map(|x| if x == w { p } else { uv(values, x) });
                expected[t] * uv_area(c) < 0.0
            })
            .count()
    };
    // `w`'s coordinates moved into each of its triangles' unfolded side in turn (alternating
    // projections onto the half-planes, each to a tenth of the opposite edge inside): what
    // unfolds an open fan (a seam side), whose ring centroid need not lie in it.
    let project = |values: &[f32], w: u32| {
        let mut p = uv(values, w);
        for _ in 0..PROJECTION_SWEEPS {
            for &t in around(w) {
                let c = corners[t as usize];
                let k = c.iter().position(|&x| x == w).unwrap_or(0);
                let (a, b) = (uv(values, c[(k + 1) % 3]), uv(values, c[(k + 2) % 3]));
                let d = b - a;
                let len2 = d.length_squared();
                let sign = expected[t as usize];
                if len2 == 0.0 || sign == 0.0 {
                    continue;
                }
                // Twice the area of (p, a, b), `sign`-oriented; it grows by |d|² per step d⊥.
                let area = sign * uv_area([p, a, b]);
                let inside = 0.1 * len2;
                if area < inside {
                    p += sign * (inside - area) / len2 * d.perp();
                }
            }
        }
        p
    };
    for _ in 0..UNTANGLE_ROUNDS {
        let mut moved = false;
        for t in 0..corners.len() {
            if !folded(values, t) {
                continue;
            }
            for w in corners[t].into_iter().filter(|&w| movable(w)) {
                let here = uv(values, w);
                let now = count(values, w, here);
                if now == 0 {
                    continue;
                }
                let (mut sum, mut n) = (Vec2::ZERO, 0.0);
                for &x in around(w).iter().flat_map(|&u| &corners[u as usize]) {
                    if x != w {
                        sum += uv(values, x);
                        n += 1.0;
                    }
                }
                let centroid = sum / n;
                let best = [
                    lerp(w),
                    centroid,
                    0.5 * (here + centroid),
                    project(values, w),
                ]
                .into_iter()
                .map(|p| (count(values, w, p), p.distance_squared(here), p))
                .min_by(|a, b| {
                    (a.0, a.1)
                        .partial_cmp(&(b.0, b.1))
                        .unwrap_or(std::cmp::Ordering::Equal)
                });
                if let Some((_, _, p)) = best.filter(|b| b.0 < now) {
                    values[w as usize * stride + at..][..2].copy_from_slice(&p.to_array());
                    moved = true;
                }
            }
        }
        if !moved {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hexagon fan in texture space: wedge 0 at the centre, 1-6 on the ring, one value per
    /// wedge (stride 2).
    fn fan(centre: Vec2) -> (Vec<[u32; 3]>, Vec<f32>) {
        let mut values = centre.to_array().to_vec();
        for k in 0..6 {
            let a = k as f32 * std::f32::consts::TAU / 6.0;
            values.extend([a.cos(), a.sin()]);
        }
        let corners = (0..6u32).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        (corners, values)
    }

    fn folds(corners: &[[u32; 3]], values: &[f32]) -> usize {
        let uv = |w: u32| Vec2::from_slice(&values[w as usize * 2..][..2]);
        corners.iter().filter(|c| uv_area(c.map(uv)) < 0.0).count()
    }

    #[test]
    fn a_corner_outside_its_ring_is_moved_back_inside() {
        // The centre pushed past the ring folds the two triangles on the far side.
        let (corners, mut values) = fan(Vec2::new(1.6, 0.1));
        let before = values.clone();
        assert!(folds(&corners, &values) >= 1);
        let expected = vec![1.0; corners.len()];
        // Its interpolated value folds too: the centroid of the ring is what unfolds it.
        let lerp = |_| Vec2::new(1.5, 0.0);
        untangle_uv(&corners, &expected, &mut values, 2, 0, |w| w == 0, lerp);
        assert_eq!(folds(&corners, &values), 0, "{values:?}");
        assert_eq!(values[2..], before[2..], "the fixed ring did not move");
        let centre = Vec2::from_slice(&values[..2]);
        assert!(centre.length() < 0.87, "{centre}: inside the ring");
    }

    #[test]
    fn nothing_moves_without_a_fold_or_a_movable_corner() {
        let (corners, mut values) = fan(Vec2::new(0.2, -0.1));
        let before = values.clone();
        let expected = vec![1.0; corners.len()];
        untangle_uv(
            &corners,
            &expected,
            &mut values,
            2,
            0,
            |_| true,
            |_| Vec2::ZERO,
        );
        assert_eq!(values, before, "no fold: nothing moves");
        // A fold whose corners are all fixed stays.
        let (corners, mut values) = fan(Vec2::new(1.6, 0.1));
        let before = values.clone();
        untangle_uv(
            &corners,
            &expected,
            &mut values,
            2,
            0,
            |_| false,
            |_| Vec2::ZERO,
        );
        assert_eq!(values, before);
        // A mirrored chart (negative expected orientation) is not folded when mirrored.
        let mirror =
            |v: Vec<f32>| -> Vec<f32> { v.chunks(2).flat_map(|p| [p[0], -p[1]]).collect() };
        let mut values = mirror(fan(Vec2::new(0.2, 0.1)).1);
        let kept = values.clone();
        untangle_uv(
            &corners,
            &[-1.0; 6],
            &mut values,
            2,
            0,
            |_| true,
            |_| Vec2::ZERO,
        );
        assert_eq!(values, kept);
    }
}

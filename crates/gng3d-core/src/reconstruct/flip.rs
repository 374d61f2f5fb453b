//! Error-driven edge flips of phase 2 (GNG3D-Q): the reconstruction connects nodes by the
//! labels of the original faces, which picks one diagonal of every quad of nodes whether or not
//! it follows the surface (on a saddle, or across a crease, the other diagonal can be much
//! closer). This pass flips an interior edge when the two new triangles fit the original
//! surface clearly better.
//!
//! Steps:
//! 1. **Points**: every original vertex whose node is in the output is assigned to the closest
//!    face of its node's fan; each face caches the summed squared distance of its points
//!    ("face error", model units²). Points live in per-face linked lists, so a flip just
//!    redistributes the points of its two faces (the quad's points) over the two new faces;
//!    the lists start as runs of one array in face order (a quad's points are read from memory
//!    in sequence, not gathered from among all original vertices).
//! 2. **Passes** (at most [`MAX_PASSES`], deterministic face order): for each interior edge
//!    `a b` with faces `(a b c)` and `(b a d)`, the flip to `c d` is taken when
//!    - `c ≠ d` and the edge `c d` does not exist (no duplicate face, manifoldness kept),
//!    - both new faces are non-degenerate, face the way the old pair faced
//!      ([`crate::surface::soundness::FLIP_MIN_NORMAL_COS`]) and do not fold onto each other ([`MIN_FOLD_COS`]),
//!    - their smallest angle stays at least `min(old smallest angle, crate::surface::soundness::FLIP_KEEP_ANGLE_DEGREES)`
//!      (GNG3D's well-shaped triangles are one of its advantages),
//!    - and either the quad's points' summed squared distance to the new faces is below
//!      [`GAIN`] × the cached error of the old pair (clearly lower, so flips cannot cycle),
//!    - or the smallest angle grows by [`SHAPE_GAIN`] while that error does not grow and the
//!      two faces fold no sharper (a Delaunay-like flip: the reconstruction's diagonal is often
//!      the worse-shaped one, most at 50 % where cells hold two or three original vertices).
//!
//! The cost is one fan search per sampled point plus, per candidate edge, a few closest-point
//! tests per point of its quad (each fan face and each second new face is first tested by its
//! bounding box, [`mesh::geometry::box_distance2`]); no allocation in the loop.

use crate::surface::soundness::{FaceRule, min_angle_sin2};
use crate::surface::{apply_flip, faces_on_edge, fans, has_edge};
use glam::{DVec3, Vec3};
use mesh::geometry::{box_distance2, closest_point_triangle, is_degenerate};

/// Upper bound on passes over all faces; each pass only takes flips that lower the error by
/// [`GAIN`], and on the shared meshes the second or third pass finds (almost) nothing.
pub const MAX_PASSES: usize = 4;

/// A flip is taken when the new error is below this fraction of the old one.
pub const GAIN: f64 = 0.9;

/// The two new faces' normals must have at least this cosine (no fold sharper than ~120°).
pub const MIN_FOLD_COS: f64 = -0.5;

/// A flip for shape is taken when the pair's smallest angle grows by this factor (in sin², so
/// 1.05 is about +2.5 % in angle), the quad's error does not grow, the fold between the two
/// faces does not get sharper and the quad is nearly flat ([`SHAPE_MAX_BEND`]). Letting the
/// error grow by 5 % or 10 % gained only 0.1° more and cost another 0.5 % in mean distance.
pub const SHAPE_GAIN: f64 = 1.05;

/// A flip for shape needs a nearly flat quad: the height between its two diagonals (6 × the
/// volume of the tetrahedron a b c d over |ab|·|cd|) at most this share of the new edge. The
/// sampled points (≤ [`MAX_POINTS_PER_FACE`]) miss what happens between them; without this
/// bound shape flips raised the Hausdorff max of gargoyle-10k at 10 % by 14 %. Measured on
/// eight meshes at 10 % and 50 % (16 runs, `gng3d simplify` + `gng3d metrics`, 2026-12-02),
/// shape flips with 0.01 against none: median smallest angle 38.05° → 38.15° on average, runs
/// with fewer triangles under 20° than QEM 14 → 15 of 16, median mean-distance ratio to QEM
/// 1.953 → 1.951, median Hausdorff ratio unchanged (0.02: 38.18°, but gargoyle's +14 %).
pub const SHAPE_MAX_BEND: f64 = 0.01;

/// At most about this many points per output face take part: more only slow the candidate
/// evaluations down (on igea at 1 % there are ~50 original vertices per output face) without
/// changing which diagonal fits better. Points are taken at a fixed stride, so the choice is
/// deterministic.
pub const MAX_POINTS_PER_FACE: usize = 8;

/// Below this many sampled points per thread the assignment stays on one thread.
const MIN_POINTS_PER_THREAD: usize = 8_192;

/// What the flip pass did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlipStats {
    /// Edges flipped.
    pub flips: usize,
    /// Passes run.
    pub passes: usize,
    /// Summed squared distance of the assigned original vertices to their faces before and
    /// after the pass (model units²).
    pub error_before: f64,
    /// See `error_before`.
    pub error_after: f64,
}

/// Squared distance from `p` to triangle `t` of `pos`.
#[inline]
fn dist2(p: DVec3, t: [u32; 3], pos: &[DVec3]) -> f64 {
    let [a, b, c] = t.map(|v| pos[v as usize]);
    (closest_point_triangle(p, a, b, c) - p).length_squared()
}

/// Squared distance from `p` to the nearer of triangles `t1` and `t2` of `pos`, and whether that
/// is `t2` (ties go to `t1`). `t2` is tested exactly only when its bounding box is nearer than
/// `t1`: the two new faces of a flip split the quad, so a point is usually far from one of them.
#[inline]
fn nearer_of(p: DVec3, t1: [u32; 3], t2: [u32; 3], pos: &[DVec3]) -> (f64, bool) {
    let d1 = dist2(p, t1, pos);
    let [a, b, c] = t2.map(|v| pos[v as usize]);
    if box_distance2(p, a, b, c) >= d1 {
        return (d1, false);
    }
    let d2 = (closest_point_triangle(p, a, b, c) - p).length_squared();
    if d1 <= d2 { (d1, false) } else { (d2, true) }
}

/// Flip edges of the mesh (`positions`, `triangles`) toward the surface whose sample points are
/// `points` (the original vertices), `owner[i]` being the output vertex of point `i`
/// (`u32::MAX`: none). Faces keep their slots; only `triangles` changes.
pub(crate) fn flip_edges(
    positions: &[Vec3],
    triangles: &mut [[u32; 3]],
    points: &[Vec3],
    owner: &[u32],
    threads: usize,
) -> FlipStats {
    let mut stats = FlipStats::default();
    let n = positions.len();
    let pos: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
    // Vertex -> faces (dynamic: a flip moves one face from a to c and one from b to d).
    let mut fan = fans(triangles, n);

    // Step 1: assign points to the closest face of their owner's fan.
    const NONE: u32 = u32::MAX;
    let mut face_err = vec![0.0f64; triangles.len()];
    let stride = points
        .len()
        .div_ceil(MAX_POINTS_PER_FACE * triangles.len().max(1))
        .max(1);
    // The closest fan face of each sampled point, independent per point: on all cores (same
    // result for any count).
    let closest = {
        let triangles = &*triangles;
        let search = crate::surface::fan_search::FanSearch::new(&fan, triangles, &pos);
        crate::parallel::map_indexed(
            owner.len().div_ceil(stride),
            threads,
            MIN_POINTS_PER_THREAD,
            |k| {
                let (i, o) = (k * stride, owner[k * stride]);
                if o != NONE && (o as usize) < n {
                    let (d, f, _) = search.nearest(points[i].as_dvec3(), &[o]);
                    (d, f)
                } else {
                    (f64::INFINITY, NONE)
                }
            },
        )
    };
    // The assigned points, stored face by face in list order (latest point first), so that a
    // candidate flip reads its quad's points from two runs of memory instead of chasing them
    // through an array of every original vertex (igea at 1 %: 67k points among 134k).
    let mut head = vec![NONE; triangles.len()];
    let mut start = vec![0u32; triangles.len() + 1];
    for &(d, f) in &closest {
        if f != NONE {
            face_err[f as usize] += d;
            start[f as usize + 1] += 1;
        }
    }
    for f in 0..triangles.len() {
        start[f + 1] += start[f];
    }
    let assigned = start[triangles.len()] as usize;
    let mut pts = vec![DVec3::ZERO; assigned];
    let mut next = vec![NONE; assigned];
    for (k, &(_, f)) in closest.iter().enumerate().rev() {
        if f == NONE {
            continue;
        }
        // Slots ascend as k descends: each face's run is its list, latest point first.
        let j = start[f as usize];
        start[f as usize] += 1;
        pts[j as usize] = points[k * stride].as_dvec3();
        if head[f as usize] == NONE {
            head[f as usize] = j;
        } else {
            next[j as usize - 1] = j;
        }
    }
    stats.error_before = face_err.iter().sum();

    // Step 2: passes. After the first, only edges of faces near a flip (faces of the fans of
    // its four corners) are looked at again: an edge's verdict depends only on its two faces,
    // their points and the fans of its corners.
    let rule = crate::surface::soundness::FLIP;
    let keep_sin2 = rule.keep_sin2();
    let mut dirty = vec![true; triangles.len()];
    let mut next_dirty = vec![false; triangles.len()];
    for _ in 0..MAX_PASSES {
        stats.passes += 1;
        let mut flipped = 0;
        for f1 in 0..triangles.len() {
            for k in 0..3 {
                let t1 = triangles[f1];
                let (a, b, c) = (t1[k], t1[(k + 1) % 3], t1[(k + 2) % 3]);
                // The face across a -> b, and no third face on the edge.
                let (on_edge, across) = faces_on_edge(&fan, triangles, a, b, f1 as u32);
                let f2 = across.unwrap_or(NONE);
                if on_edge != 2 || f2 == NONE || (f2 as usize) < f1 {
                    continue;
                }
                if !dirty[f1] && !dirty[f2 as usize] {
                    continue;
                }
                let t2 = triangles[f2 as usize];
                let d = t2
                    .iter()
                    .copied()
                    .find(|&v| v != a && v != b)
                    .unwrap_or(NONE);
                if d == NONE || d == c {
                    continue;
                }
                if has_edge(&fan, triangles, c, d) {
                    continue;
                }
                let (e_old, accepted) = {
                    let e_old = face_err[f1] + face_err[f2 as usize];
                    // Geometry: new faces (c a d) and (d b c).
                    let (pa, pb, pc, pd) = (
                        pos[a as usize],
                        pos[b as usize],
                        pos[c as usize],
                        pos[d as usize],
                    );
                    if is_degenerate(pc, pa, pd) || is_degenerate(pd, pb, pc) {
                        continue;
                    }
                    let (o1, o2) = ((pb - pa).cross(pc - pa), (pa - pb).cross(pd - pb));
                    let old_n = (o1 + o2).normalize_or_zero();
                    let (o1, o2) = (o1.normalize_or_zero(), o2.normalize_or_zero());
                    let n1 = (pa - pc).cross(pd - pc).normalize_or_zero();
                    let n2 = (pb - pd).cross(pc - pd).normalize_or_zero();
                    if !rule.normal_agrees(n1, old_n)
                        || !rule.normal_agrees(n2, old_n)
                        || n1.dot(n2) < MIN_FOLD_COS
                    {
                        continue;
                    }
                    let old_angle = min_angle_sin2(pa, pb, pc).min(min_angle_sin2(pb, pa, pd));
                    let new_angle = min_angle_sin2(pc, pa, pd).min(min_angle_sin2(pd, pb, pc));
                    // Two reasons to flip: the surface (error clearly lower, shape kept) or the
                    // shape (smallest angle clearly larger, error and fold not worse). Neither
                    // can undo the other: a shape flip never raises the error, and undoing it
                    // would not lower the error by GAIN.
                    let for_error =
                        e_old > 0.0 && FaceRule::keeps_shape(new_angle, old_angle, keep_sin2);
                    let for_shape =
                        new_angle > SHAPE_GAIN * old_angle && n1.dot(n2) >= o1.dot(o2) && {
                            // Bend of the quad: the flip moves the surface across the
                            // tetrahedron a b c d, whose height between the diagonals is
                            // 6·volume / (|ab|·|cd|).
                            let (ab, cd) = (pb - pa, pd - pc);
                            let bend =
                                ab.cross(cd).dot(pc - pa).abs() / (ab.length() * cd.length());
                            bend <= SHAPE_MAX_BEND * cd.length()
                        };
                    if !for_error && !for_shape {
                        continue;
                    }
                    // Error of the quad's points on the new faces, with early exit.
                    let limit = if for_shape { e_old } else { GAIN * e_old };
                    let mut e_new = 0.0;
                    let (n1t, n2t) = ([c, a, d], [d, b, c]);
                    'lists: for list in [head[f1], head[f2 as usize]] {
                        let mut p = list;
                        while p != NONE {
                            let q = pts[p as usize];
                            e_new += nearer_of(q, n1t, n2t, &pos).0;
                            if e_new > limit {
                                break 'lists;
                            }
                            p = next[p as usize];
                        }
                    }
                    let accepted =
                        (for_error && e_new < GAIN * e_old) || (for_shape && e_new <= e_old);
                    (e_old, accepted)
                };
                if !accepted {
                    continue;
                }
                // Apply: f1 = (c a d), f2 = (d b c).
                let f2u = f2 as usize;
                apply_flip(triangles, &mut fan, [f1 as u32, f2], [a, b, c, d]);
                // Redistribute the quad's points.
                let mut p = head[f1];
                let mut tail = p;
                if p == NONE {
                    p = head[f2u];
                } else {
                    while next[tail as usize] != NONE {
                        tail = next[tail as usize];
                    }
                    next[tail as usize] = head[f2u];
                }
                head[f1] = NONE;
                head[f2u] = NONE;
                face_err[f1] = 0.0;
                face_err[f2u] = 0.0;
                while p != NONE {
                    let after = next[p as usize];
                    let q = pts[p as usize];
                    let (dd, second) = nearer_of(q, triangles[f1], triangles[f2u], &pos);
                    let f = if second { f2u } else { f1 };
                    face_err[f] += dd;
                    next[p as usize] = head[f];
                    head[f] = p;
                    p = after;
                }
                debug_assert!(face_err[f1] + face_err[f2u] <= e_old * (1.0 + 1e-9));
                for v in [a, b, c, d] {
                    for &g in &fan[v as usize] {
                        next_dirty[g as usize] = true;
                    }
                }
                flipped += 1;
            }
        }
        stats.flips += flipped;
        if flipped == 0 {
            break;
        }
        std::mem::swap(&mut dirty, &mut next_dirty);
        next_dirty.fill(false);
    }
    stats.error_after = face_err.iter().sum();
    stats
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flips_a_saddle_quad_to_the_diagonal_on_the_surface() {
        // Quad a(0,0,0) b(1,1,0) c(0,1,1) d(1,0,1): the ridge c-d is at height 1, the valley a-b
        // at 0; points on the line between c and d lie on the surface.
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
        ];
        // (a b c), (b a d): a->b shared.
        let mut tris = vec![[0, 1, 2], [1, 0, 3]];
        let points: Vec<Vec3> = (1..10)
            .map(|i| Vec3::new(0.0, 1.0, 1.0).lerp(Vec3::new(1.0, 0.0, 1.0), i as f32 / 10.0))
            .collect();
        let owner: Vec<u32> = (0..points.len() as u32).map(|i| i % 4).collect();
        let s = flip_edges(&positions, &mut tris, &points, &owner, 2);
        assert_eq!(s.flips, 1);
        assert!(s.error_after < 1e-10 && s.error_before > 0.1);
        assert_eq!(tris, vec![[2, 0, 3], [3, 1, 2]]);
    }

    #[test]
    fn flips_a_sliver_pair_on_a_plane_for_shape_only() {
        // Planar quad a(0,0) b(2,0) c(1,0.3) d(1,-0.3): the diagonal a-b makes two 16.7° slivers,
        // c-d two triangles with 33.4° smallest angle. Every point lies on the plane, so the
        // error is 0 both ways: only the shape rule can take this flip.
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(1.0, 0.3, 0.0),
            Vec3::new(1.0, -0.3, 0.0),
        ];
        let mut tris = vec![[0, 1, 2], [1, 0, 3]];
        let points: Vec<Vec3> = (0..12)
            .map(|i| Vec3::new(0.2 + 0.13 * i as f32, 0.02 * (i % 5) as f32 - 0.04, 0.0))
            .collect();
        let owner: Vec<u32> = (0..points.len() as u32).map(|i| i % 4).collect();
        let s = flip_edges(&positions, &mut tris, &points, &owner, 2);
        assert_eq!(s.flips, 1);
        assert_eq!(tris, vec![[2, 0, 3], [3, 1, 2]]);
        assert!(s.error_after <= s.error_before + 1e-12);
        // The same slivers folded into a valley along a-b (c and d raised), with the points on
        // the valley's faces: the c-d diagonal is still better shaped, but the quad is far from
        // flat and the new faces leave the points (error 0 → > 0), so the shape rule must not
        // take it.
        let mut valley = positions.clone();
        valley[2].z = 0.5;
        valley[3].z = 0.5;
        let mut tris = vec![[0, 1, 2], [1, 0, 3]];
        let points: Vec<Vec3> = [[0, 1, 2], [1, 0, 3]]
            .iter()
            .flat_map(|t: &[usize; 3]| {
                let [a, b, c] = t.map(|v| valley[v]);
                [
                    (a + b + c) / 3.0,
                    (a * 2.0 + b + c) / 4.0,
                    (a + b * 2.0 + c) / 4.0,
                ]
            })
            .collect();
        let owner: Vec<u32> = (0..points.len() as u32).map(|i| i % 4).collect();
        let s = flip_edges(&valley, &mut tris, &points, &owner, 2);
        assert_eq!((s.flips, tris), (0, vec![[0, 1, 2], [1, 0, 3]]));
    }
}

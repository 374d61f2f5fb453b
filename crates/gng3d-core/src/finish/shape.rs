//! Shape pass, option (k): GNG3D-Q's triangle shape after the decimation
//! ([`crate::Step::Shape`]), on the mesh that the decimation (and the relaxation) returns.
//!
//! Why: the QEM decimation to the exact count places each vertex where its quadric is
//! smallest and contracts the cheapest edges first, so it leaves slivers and vertices of
//! valence 3-4 or 9-10 where the network's mesh had well-shaped triangles: median smallest
//! angle 33-40° and 2-19 % of the angles under 20° on the organic meshes at 2 and 10 %, where
//! the isotropic remeshers reach 45-50° and ~0 % (docs/notes/shape.md).
//!
//! Steps ([`ROUNDS`] times):
//! 1. **Valence flips**: an interior edge `a b` with faces `(a b c)` and `(b a d)` flips to
//!    `c d` when that brings the four valences closer to 6 (4 on open borders), summed squared
//!    deviation, and the new faces are sound under the flips' rule
//!    ([`crate::surface::soundness::FLIP`]: facing the old pair's way, smallest angle kept
//!    against the old pair's or 25°) and fold no more than the old pair did or
//!    [`FLIP_FOLD_COS`] (a dihedral guard: the flip must not cut across a ridge of the
//!    surface), and the new diagonal's midpoint lies about as close to the original as the old
//!    one's ([`FLIP_SLACK`]). Edges between two seam vertices and edges with other than two faces stay.
//! 2. **Tangential smoothing**: every free vertex moves [`STEP`] of the way toward the
//!    centroid of its one-ring's face centroids, the move projected onto its tangent plane
//!    (the area-weighted normal of its faces), then onto the ORIGINAL surface (closest point,
//!    [`crate::surface::Surface`], the deviation repair's queries) plus the offset from it the
//!    vertex had (the decimation and the refit lift vertices off the surface so that the
//!    triangles fit it; dropping that lift cost 1.5-1.7× the mean distance). A move is taken under the
//!    refit's rule ([`crate::surface::move_fits`]: no face turns by more than 45°, every face
//!    keeps its smallest angle above 20° or its old one) and only when it keeps the faces
//!    around the vertex about as close to the original as they were ([`GUARD`]). Fixed: vertices of open borders, of
//!    edges with other than two faces, on seams, and feature vertices (an edge at them whose
//!    faces meet at more than `acos(`[`FEATURE_COS`]`)`): the projection would round a crease.
//!
//! Deterministic: the proposals of a round are computed from the same positions on all cores,
//! one per vertex; flips and acceptances run in a fixed order on one thread.

use crate::surface::soundness::{FLIP, min_angle_sin2};
use crate::surface::{
    Surface, apply_flip, faces_on_edge, fans, has_edge, move_fits, oriented, output_boundary,
};
use glam::{DVec3, Vec3};
use std::time::Instant;

/// Rounds of flips and smoothing (not swept).
pub const ROUNDS: usize = 3;

/// Share of the way to the one-ring's centroid a vertex moves per round. The bunny at 10 %
/// (mean distance / median smallest angle / share under 20°; without the pass 4.58e-5, 39.1°,
/// 3.95 %): 0.25 5.85e-5, 43.7°, 1.51 %; 0.5 6.71e-5, 45.4°, 1.57 %; 1.0 7.59e-5, 46.9°,
/// 1.24 %.
pub const STEP: f64 = 0.5;

/// A smoothing move is taken only when the distances to the original of the centroids of the
/// vertex's faces ([`local_gap`]) sum to at most `1 +` this times their sum before, and their
/// largest is at most `1 +` this times the largest before: the smoothing evens out the
/// triangles where that costs the surface little and leaves the decimation's placement where
/// it does not. Bunny, armadillo and igea at 10 and 2 % (docs/notes/shape.md, "A distance
/// guard"), mean distance × QEM's / median smallest angle / share under 20°: without the guard
/// 1.05-1.52 / 43-47° / 0.0-1.8 % and the Hausdorff distance up to 1.9 × the pass-less run's;
/// 0.1 with the largest allowed 1.2 × 0.88-1.10 / 40-44° / 0.5-2.5 %, igea's Hausdorff 1.1-1.2
/// × the pass-less run's; 0.1 as here (largest 1.1 ×) igea 1.06-1.08 / 43.3° / 0.6-0.7 % at
/// the pass-less run's Hausdorff; without the pass 0.82-1.03 / 37-41° / 1.7-5.6 %.
pub const GUARD: f64 = 0.1;

/// A vertex with an edge whose two faces' normals have a cosine below this (60°) is a feature
/// vertex and stays (not swept).
pub const FEATURE_COS: f64 = 0.5;

/// A valence flip may leave the two new faces folded (cosine of their normals) down to the old
/// pair's fold or this (20°), whichever is lower (not swept).
pub const FLIP_FOLD_COS: f64 = 0.94;

/// A valence flip is taken only when the new diagonal's midpoint lies no farther from the
/// original than the old one's plus this share of the new diagonal's length. The flips alone
/// (no smoothing), bunny at 10 %: with this guard mean distance +0.5 %, without it +7 %;
/// either way the angles hardly change (39.1° → 39.0-39.4°): the smoothing makes the shape,
/// and with the flips it reaches 46.9° instead of 45.2° at a full step.
pub const FLIP_SLACK: f64 = 0.01;

/// What [`shape`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ShapeStats {
    /// Vertex moves taken (summed over the rounds).
    pub moves: usize,
    /// Edges flipped.
    pub flips: usize,
}

fn face_normal(t: [u32; 3], pos: &[DVec3]) -> DVec3 {
    let [a, b, c] = t.map(|v| pos[v as usize]);
    (b - a).cross(c - a)
}

/// Improves the shape of the output's triangles (`positions`, `triangles`) by valence flips
/// and tangential smoothing projected onto the original (`surface`, [`super::surface`]: the
/// deviation repair's, built once for both; module docs), each move under the
/// distance guard ([`GUARD`]) when `guarded` ([`crate::Shape::Fit`]; without:
/// [`crate::Shape::Round`]). Vertices flagged in `seams` stay and edges between two of them
/// are not flipped. No round starts after `deadline`.
pub(crate) fn shape(
    guarded: bool,
    positions: &mut [Vec3],
    triangles: &mut [[u32; 3]],
    surface: &Surface,
    seams: Option<&[bool]>,
    deadline: Option<Instant>,
    threads: usize,
) -> ShapeStats {
    let n = positions.len();
    let mut stats = ShapeStats::default();
    if n == 0 || triangles.is_empty() {
        return stats;
    }
    let mut pos: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
    let mut fan = fans(triangles, n);
    let border: Vec<bool> = output_boundary(triangles, n)
        .iter()
        .map(|b| !b.is_empty())
        .collect();
    let seam = |v: u32| seams.is_some_and(|s| s[v as usize]);
    let fixed = fixed_vertices(triangles, &fan, &pos, &border, seams);
    for round in 0..ROUNDS {
        if round > 0 && deadline.is_some_and(|d| Instant::now() >= d) {
            break;
        }
        // Step 1: valence flips.
        for f in 0..triangles.len() as u32 {
            for i in 0..3 {
                let t = triangles[f as usize];
                let (a, b) = (t[i], t[(i + 1) % 3]);
                if a > b || (seam(a) && seam(b)) {
                    continue;
                }
                let (count, across) = faces_on_edge(&fan, triangles, a, b, f);
                let (2, Some(g)) = (count, across) else {
                    continue;
                };
                let Some((_, _, c)) = oriented(t, a, b) else {
                    continue;
                };
                let Some((_, _, d)) = oriented(triangles[g as usize], b, a) else {
                    continue;
                };
                if c == d || has_edge(&fan, triangles, c, d) {
                    continue;
                }
                let valence = |v: u32| fan[v as usize].len() as i64 + border[v as usize] as i64;
                let target = |v: u32| if border[v as usize] { 4 } else { 6 };
                let dev = |v: u32, delta: i64| (valence(v) + delta - target(v)).pow(2);
                let before = dev(a, 0) + dev(b, 0) + dev(c, 0) + dev(d, 0);
                let after = dev(a, -1) + dev(b, -1) + dev(c, 1) + dev(d, 1);
                if after >= before {
                    continue;
                }
                let (n1, n2) = (
                    face_normal(t, &pos).normalize_or_zero(),
                    face_normal(triangles[g as usize], &pos).normalize_or_zero(),
                );
                let Some(reference) = (n1 + n2).try_normalize() else {
                    continue;
                };
                let [pa, pb, pc, pd] = [a, b, c, d].map(|v| pos[v as usize]);
                let old_sin2 = min_angle_sin2(pa, pb, pc).min(min_angle_sin2(pb, pa, pd));
                let new1 = [pc, pa, pd];
                let new2 = [pd, pb, pc];
                if !FLIP.accepts(new1, reference, old_sin2)
                    || !FLIP.accepts(new2, reference, old_sin2)
                {
                    continue;
                }
                let m1 = (new1[1] - new1[0])
                    .cross(new1[2] - new1[0])
                    .normalize_or_zero();
                let m2 = (new2[1] - new2[0])
                    .cross(new2[2] - new2[0])
                    .normalize_or_zero();
                if m1.dot(m2) < n1.dot(n2).min(FLIP_FOLD_COS) {
                    continue;
                }
                // Distance guard: the new diagonal must lie about as close to the original as
                // the old one.
                let old_gap = surface.distance(0.5 * (pa + pb));
                let new_gap = surface.distance(0.5 * (pc + pd));
                if new_gap > old_gap + FLIP_SLACK * (pc - pd).length() {
                    continue;
                }
                apply_flip(triangles, &mut fan, [f, g], [a, b, c, d]);
                stats.flips += 1;
            }
        }
        // Step 2: tangential smoothing, proposals from this round's positions.
        let before = guarded.then(|| gaps(surface, &fan, triangles, &pos, threads));
        let proposals = crate::parallel::map_indexed(n, threads, 1024, |v| {
            if fixed[v] {
                return None;
            }
            // The centroid of the one-ring's face centroids, each face weighing 1: a face's
            // area is about the inverse of the local vertex density, so this is the
            // density-weighted centroid, which keeps the decimation's density (more vertices
            // where the surface bends) where the area-weighted one evens it out (bunny at 10 %,
            // no guard: mean distance 6.92e-5 area-weighted, 6.46e-5 so; 45.4° / 45.6°).
            let (mut centre, mut normal) = (DVec3::ZERO, DVec3::ZERO);
            for &f in &fan[v] {
                let t = triangles[f as usize];
                centre += (pos[t[0] as usize] + pos[t[1] as usize] + pos[t[2] as usize]) / 3.0;
                normal += face_normal(t, &pos);
            }
            let normal = normal.try_normalize()?;
            let to_centre = centre / fan[v].len() as f64 - pos[v];
            let tangent = to_centre - normal * normal.dot(to_centre);
            // Onto the original, keeping the vertex's offset from it: the decimation and the
            // refit lift vertices off the surface so that the triangles fit it, and dropping
            // that lift cost 1.5-1.7× the mean distance (docs/notes/shape.md).
            let offset = pos[v] - surface.closest(pos[v]).1;
            let onto = surface.closest(pos[v] + STEP * tangent).1 + offset;
            if !onto.is_finite() {
                return None;
            }
            let Some(before) = &before else {
                return Some(onto);
            };
            let (sum, worst) = before[v];
            let (new_sum, new_worst) = local_gap(surface, &fan[v], triangles, &pos, v, onto);
            // A millionth of the move's length per face of slack, so that on a plane (every
            // distance 0 up to rounding) the guard does not refuse the move for the rounding.
            let slack = 1e-6 * (onto - pos[v]).length();
            (new_sum <= sum * (1.0 + GUARD) + slack * fan[v].len() as f64
                && new_worst <= worst * (1.0 + GUARD) + slack)
                .then_some(onto)
        });
        let mut trial = pos.clone();
        for (v, proposal) in proposals.into_iter().enumerate() {
            let Some(p) = proposal else { continue };
            trial[v] = p;
            if move_fits(&fan[v], triangles, &pos, &trial, true) {
                pos[v] = p;
                stats.moves += 1;
            } else {
                trial[v] = pos[v];
            }
        }
    }
    for (p, q) in positions.iter_mut().zip(&pos) {
        *p = q.as_vec3();
    }
    stats
}

/// The distances to the original of the centroids of the faces around `v` (`fan`) with `v`
/// at `at` (the others at `pos`): their sum and their largest. (With the midpoints of `v`'s
/// edges too, twice the queries: bunny and armadillo at 10 % within 1 % of the same mean
/// distance and 0.1° of the same median angle.)
fn local_gap(
    surface: &Surface,
    fan: &[u32],
    triangles: &[[u32; 3]],
    pos: &[DVec3],
    v: usize,
    at: DVec3,
) -> (f64, f64) {
    let p = |u: u32| if u as usize == v { at } else { pos[u as usize] };
    fan.iter().fold((0.0, 0.0f64), |(sum, worst), &f| {
        let t = triangles[f as usize];
        let d = surface.distance((p(t[0]) + p(t[1]) + p(t[2])) / 3.0);
        (sum + d, worst.max(d))
    })
}

/// [`local_gap`] of every vertex at its own position, from one query per face.
fn gaps(
    surface: &Surface,
    fan: &[Vec<u32>],
    triangles: &[[u32; 3]],
    pos: &[DVec3],
    threads: usize,
) -> Vec<(f64, f64)> {
    let face = crate::parallel::map_indexed(triangles.len(), threads, 1024, |f| {
        let t = triangles[f];
        surface.distance((pos[t[0] as usize] + pos[t[1] as usize] + pos[t[2] as usize]) / 3.0)
    });
    fan.iter()
        .map(|faces| {
            faces.iter().fold((0.0, 0.0f64), |(sum, worst), &f| {
                (sum + face[f as usize], worst.max(face[f as usize]))
            })
        })
        .collect()
}

/// The vertices that stay (module docs, step 2).
fn fixed_vertices(
    triangles: &[[u32; 3]],
    fan: &[Vec<u32>],
    pos: &[DVec3],
    border: &[bool],
    seams: Option<&[bool]>,
) -> Vec<bool> {
    let mut fixed: Vec<bool> = border
        .iter()
        .enumerate()
        .map(|(v, &b)| b || fan[v].is_empty() || seams.is_some_and(|s| s[v]))
        .collect();
    for (f, t) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            let (count, across) = faces_on_edge(fan, triangles, a, b, f as u32);
            let sharp = match (count, across) {
                (2, Some(g)) => {
                    let n1 = face_normal(*t, pos).normalize_or_zero();
                    let n2 = face_normal(triangles[g as usize], pos).normalize_or_zero();
                    n1.dot(n2) < FEATURE_COS
                }
                _ => true,
            };
            if sharp {
                fixed[a as usize] = true;
                fixed[b as usize] = true;
            }
        }
    }
    fixed
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Smallest angle of every face, degrees (acos of the normalised edge dots).
    fn smallest_angles(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<f64> {
        triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| positions[v as usize].as_dvec3());
                let angle = |p: DVec3, q: DVec3, r: DVec3| (q - p).angle_between(r - p);
                angle(a, b, c)
                    .min(angle(b, c, a))
                    .min(angle(c, a, b))
                    .to_degrees()
            })
            .collect()
    }

    #[test]
    fn a_jittered_plane_rounds_out_in_the_plane_and_its_border_stays() {
        // With the distance guard and without: on a plane every move keeps the distance.
        for guarded in [true, false] {
            jittered_plane(guarded);
        }
    }

    fn jittered_plane(guarded: bool) {
        let original = mesh::procedural::unit_square_grid(24);
        let coarse = mesh::procedural::unit_square_grid(6);
        // Shear the interior vertices into thin triangles, inside the plane (deterministic).
        let mut positions = coarse.positions.clone();
        for (i, p) in positions.iter_mut().enumerate() {
            if p.x > 0.0 && p.x < 1.0 && p.y > 0.0 && p.y < 1.0 {
                let s = if i % 2 == 0 { 1.0 } else { -1.0 };
                p.x += s * 0.06;
                p.y += s * 0.05;
            }
        }
        let before = positions.clone();
        let mut triangles = coarse.triangles.clone();
        let worst = |a: &[f64]| a.iter().copied().fold(f64::INFINITY, f64::min);
        let a0 = smallest_angles(&positions, &triangles);
        let stats = shape(
            guarded,
            &mut positions,
            &mut triangles,
            &crate::finish::surface(&original).expect("the grid has faces"),
            None,
            None,
            2,
        );
        let a1 = smallest_angles(&positions, &triangles);
        assert!(stats.moves > 0);
        assert_eq!(triangles.len(), coarse.triangles.len());
        let mean = |a: &[f64]| a.iter().sum::<f64>() / a.len() as f64;
        assert!(
            worst(&a1) > worst(&a0) + 5.0 && mean(&a1) > mean(&a0),
            "smallest {:.1}° -> {:.1}°, mean {:.1}° -> {:.1}°",
            worst(&a0),
            worst(&a1),
            mean(&a0),
            mean(&a1)
        );
        for (p, q) in positions.iter().zip(&before) {
            assert!(p.z.abs() < 1e-6, "guarded {guarded}: left the plane: {p:?}");
            let border = q.x == 0.0 || q.x == 1.0 || q.y == 0.0 || q.y == 1.0;
            if border {
                assert_eq!(p, q);
            }
        }
    }
}

//! Surface refit, the last step of phase 2 for GNG3D-Q: moves the output vertices so that the
//! output *triangles*, not only their corners, fit the original surface (the distance energy of
//! Hoppe et al. 1993, "Mesh optimization", with point-to-plane residuals).
//!
//! Quadric placement puts each vertex where its cell's planes meet, which is right for the
//! vertex but leaves every triangle a chord: on a convex patch the whole triangle lies inside
//! the surface. Fitting sampled points of the original to the triangles lifts the vertices by
//! about the sagitta, so the triangles straddle the surface (mean surface distance to QEM on
//! spot, bunny, gargoyle-10k and rocker-arm at 10 %: 1.41-1.92 → 1.09-1.57; docs/notes/gngq.md).
//!
//! Steps:
//! 1. **Samples** (once): the centroid of every original face (its normal, weight: its area)
//!    and every original vertex (area-weighted vertex normal, a third of its faces' area), at a
//!    fixed stride so that at most about [`MAX_SAMPLES_PER_FACE`] per output face take part;
//!    plus the ends and midpoint of every original boundary edge, with the in-plane normal of
//!    the edge ([`BOUNDARY_WEIGHT`]).
//! 2. **Assignment** (steps 2-4 run [`ITERATIONS`] times): in the first iteration each surface
//!    sample goes to the closest face in the fans of its owners (the output vertices of its
//!    original corners), later ones re-project it onto that face; samples whose normal
//!    disagrees with their face's ([`MIN_SAMPLE_COS`]) are left out (the other side of a thin
//!    part, across a crease). Each boundary sample goes to the closest output boundary edge at
//!    its owners, every iteration.
//! 3. **Per-vertex quadric**: a sample `x` with normal `n` at barycentric `(b_u, b_v, b_w)` of
//!    face `(u v w)` asks `n · (b_u p_u + b_v p_v + b_w p_w − x) = 0`; for `p_v` with the other
//!    corners fixed that is the plane `n · p_v = n · (x − b_u p_u − b_w p_w) / b_v` with weight
//!    `w b_v²`, added to `v`'s quadric, which starts as [`ANCHOR_WEIGHT`] × the vertex's
//!    placement quadric (the vertex itself stays near its cell's planes; without it tips of thin
//!    parts were pulled out along their axis, spot's horns: Hausdorff 1.27 → 2.05× QEM).
//! 4. **Move** (Jacobi: every vertex from the previous positions): each vertex minimises its
//!    quadric from its current position along the well-conditioned directions
//!    ([`Quadric::minimizer_near`]); the move is clamped to [`MAX_STEP`] × its shortest incident
//!    edge. It is taken when no incident face turns by more than `acos(`[`crate::surface::soundness::REFIT_MAX_TURN_COS`]`)` and,
//!    for interior vertices, every incident face keeps its smallest angle above
//!    [`crate::surface::soundness::REFIT_KEEP_ANGLE_DEGREES`] (or above its old one); otherwise its component along the vertex
//!    normal is tried under the same rules, otherwise the vertex stays.
//!
//! Deterministic: the sample assignment runs on all cores but gives the same result for any
//! thread count, and the quadrics are summed in sample order.

use crate::surface::fan_search::FanSearch;
use crate::surface::{move_fits, normal, output_boundary};
use glam::{DVec3, Vec3};
use mesh::TriMesh;
use mesh::geometry::closest_point_triangle;
use mesh::quadric::Quadric;
use mesh::topology::EdgeTable;

/// Refit iterations. On eight runs (spot, stanford-bunny, gargoyle-10k, rocker-arm at 10 % and
/// 50 %) 2 → 4 iterations lowered the mean distance by another 0.2-2.6 % and the Hausdorff max
/// in 6 of the 8.
pub const ITERATIONS: usize = 4;

/// Weight of the placement quadric in each vertex's refit quadric: 1/3 counts each face plane
/// of the cell about once instead of once per cell corner. Best of 0.1, 1/3 and 1 on the eight
/// runs above (0.1: spot's horns poke out again, Hausdorff 1.45 → 1.70× QEM at 10 %; 1: mean
/// distance 5-8 % higher at 10 %).
pub const ANCHOR_WEIGHT: f64 = 1.0 / 3.0;

/// Eigenvalues below this fraction of the largest are left out of a vertex's solve (ten times
/// placement's [`crate::reconstruct::placement::EIGEN_REL_TOL`]: a refit moves a vertex mostly along its
/// normal, and the weak tangential directions only add drift).
pub const EIGEN_REL_TOL: f64 = 1e-2;

/// A vertex moves at most this share of its shortest incident edge per iteration, so that one
/// iteration cannot fold a fan (not swept).
pub const MAX_STEP: f64 = 0.25;

/// A sample only counts when its normal and its output face's have at least this cosine (60°;
/// added together with the boundary samples, see [`BOUNDARY_WEIGHT`]).
pub const MIN_SAMPLE_COS: f64 = 0.5;

/// Weight of a boundary sample relative to a surface sample of the same squared length: the
/// output's open borders follow the original's. Without boundary samples (and without the
/// normal filter, added in the same step) the refit raised the bunny's Hausdorff max at 10 %
/// from 4.3 to 5.0× QEM's, with them it went to 2.5× (the maxima sat on the rims of the
/// base's holes). Not swept.
pub const BOUNDARY_WEIGHT: f64 = 10.0;

/// At most about this many surface samples per output face (taken at a fixed stride), as for
/// the flips: at 1 % of igea there are ~75 per face. igea at 2 %, mean distance / Hausdorff to
/// QEM: 6 per face 1.186 / 1.80, 8: 1.182 / 1.57, 12: 1.176 / 1.62 (no refit: 1.48 / 1.97);
/// the refit of igea at 1 % takes ~30 ms with 8 and ~45 ms with 12.
pub const MAX_SAMPLES_PER_FACE: usize = 8;

/// Below this many samples per thread the assignment stays on one thread.
const MIN_SAMPLES_PER_THREAD: usize = 8_192;

/// Below this many vertices per thread the moves are worked out on one thread.
const MIN_VERTICES_PER_THREAD: usize = 4_096;

const NONE: u32 = u32::MAX;

/// A point of the original with the plane it asks the output to pass through.
#[derive(Clone, Copy)]
struct Sample {
    point: DVec3,
    normal: DVec3,
    weight: f64,
    /// Output vertices whose fans (surface samples) or boundary edges (boundary samples) are
    /// searched; `NONE` for unused slots.
    owners: [u32; 3],
}

/// What the refit did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RefitStats {
    /// Vertex moves taken, summed over the iterations.
    pub moves: usize,
    /// Surface and boundary samples used per iteration.
    pub samples: usize,
}

/// Refits `positions` (output vertices with faces `triangles`) to `original`; `owner[i]` is the
/// output vertex of original vertex `i` (or `u32::MAX`), `edges` the original's edge table and
/// `anchor[v]` vertex `v`'s placement quadric (zero for vertices without a cell).
pub(crate) fn refit(
    positions: &mut [Vec3],
    triangles: &[[u32; 3]],
    original: &TriMesh,
    edges: &EdgeTable,
    owner: &[u32],
    anchor: &[Quadric],
    threads: usize,
) -> RefitStats {
    let n = positions.len();
    if n == 0 || triangles.is_empty() {
        return RefitStats::default();
    }
    let fan = crate::surface::fans(triangles, n);
    let surface = surface_samples(original, owner, triangles.len());
    let boundary = boundary_samples(original, edges, owner);
    let out_boundary = output_boundary(triangles, n);
    let mut stats = RefitStats {
        samples: surface.len() + boundary.len(),
        ..RefitStats::default()
    };
    let anchor: Vec<Quadric> = anchor.iter().map(|q| scaled(*q, ANCHOR_WEIGHT)).collect();

    let mut pos: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
    let mut on_faces: Vec<Option<(u32, DVec3)>> = Vec::new();
    for iteration in 0..ITERATIONS {
        // Step 2: assignments, independent per sample. The fans are searched in the first
        // iteration only; later ones re-project onto the same face (a vertex moves by at most
        // a quarter edge per iteration, so the closest face seldom changes; searching again
        // every iteration cost igea at 1 % 95 ms instead of ~45 ms for the same distances).
        // Keeping the first iteration's barycentric coordinates instead saved ~8 ms more but
        // raised the mean distance 1-2 % and the Hausdorff max in 6 of 8 runs.
        on_faces = if iteration == 0 {
            let fans = FanSearch::new(&fan, triangles, &pos);
            crate::parallel::map_indexed(surface.len(), threads, MIN_SAMPLES_PER_THREAD, |i| {
                closest_face(&surface[i], &fans, triangles, &pos)
            })
        } else {
            crate::parallel::map_indexed(surface.len(), threads, MIN_SAMPLES_PER_THREAD, |i| {
                let (f, _) = on_faces[i]?;
                let [a, b, c] = triangles[f as usize].map(|v| pos[v as usize]);
                Some((f, closest_point_triangle(surface[i].point, a, b, c)))
            })
        };
        let on_edges =
            crate::parallel::map_indexed(boundary.len(), threads, MIN_SAMPLES_PER_THREAD, |i| {
                closest_boundary_edge(&boundary[i], &out_boundary, &pos)
            });
        // Step 3: per-vertex quadrics, in sample order.
        let mut quadric = anchor.clone();
        for (s, hit) in surface.iter().zip(&on_faces) {
            let Some((f, q)) = *hit else { continue };
            let t = triangles[f as usize];
            let [a, b, c] = t.map(|v| pos[v as usize]);
            add_sample(&mut quadric, s, &t, &barycentric(q, a, b, c), &pos);
        }
        for (s, hit) in boundary.iter().zip(&on_edges) {
            let Some((u, w, t)) = *hit else { continue };
            add_sample(&mut quadric, s, &[u, w], &[1.0 - t, t], &pos);
        }
        // Step 4: moves. What each vertex asks for depends only on the previous positions, so
        // it is worked out on all cores (the 3×3 eigen-solves are most of this step); the
        // moves are then checked and taken in vertex order, each against its neighbours'
        // current positions, as before (outputs identical).
        let old = pos.clone();
        let proposals = crate::parallel::map_indexed(n, threads, MIN_VERTICES_PER_THREAD, |v| {
            propose_move(v, &quadric[v], &fan[v], triangles, &old)
        });
        for (v, proposal) in proposals.into_iter().enumerate() {
            let Some((step, normal_dir)) = proposal else {
                continue;
            };
            let start = old[v];
            // The full move, else its part along the vertex normal (the fan keeps its shape in
            // the tangent plane), else none. Interior vertices must keep their faces' shape
            // (crate::surface::soundness::REFIT_KEEP_ANGLE_DEGREES); border vertices only their orientation, so that they can
            // follow the original's rim.
            let on_border = !out_boundary[v].is_empty();
            let mut taken = false;
            for candidate in [start + step, start + normal_dir * normal_dir.dot(step)] {
                pos[v] = candidate;
                if move_fits(&fan[v], triangles, &old, &pos, !on_border) {
                    taken = true;
                    break;
                }
            }
            if taken {
                stats.moves += 1;
            } else {
                pos[v] = start;
            }
        }
    }
    for (p, q) in positions.iter_mut().zip(&pos) {
        *p = q.as_vec3();
    }
    stats
}

/// Step 4's move of vertex `v` (faces `fan`) from `old`: toward its quadric's minimiser,
/// clamped to [`MAX_STEP`] × its shortest incident edge, with its area-weighted normal; `None`
/// when it has no quadric or no finite minimiser.
fn propose_move(
    v: usize,
    quadric: &Quadric,
    fan: &[u32],
    triangles: &[[u32; 3]],
    old: &[DVec3],
) -> Option<(DVec3, DVec3)> {
    if quadric.trace() <= 0.0 {
        return None;
    }
    let start = old[v];
    let p = quadric.minimizer_near(start, EIGEN_REL_TOL);
    if !p.is_finite() {
        return None;
    }
    let shortest = fan
        .iter()
        .flat_map(|&f| triangles[f as usize])
        .filter(|&u| u as usize != v)
        .map(|u| (old[u as usize] - start).length())
        .fold(f64::INFINITY, f64::min);
    let mut step = p - start;
    let limit = MAX_STEP * shortest;
    if step.length() > limit {
        step *= limit / step.length();
    }
    let normal_dir: DVec3 = fan
        .iter()
        .map(|&f| {
            let [a, b, c] = triangles[f as usize].map(|u| old[u as usize]);
            (b - a).cross(c - a)
        })
        .sum::<DVec3>()
        .normalize_or_zero();
    Some((step, normal_dir))
}

/// Step 1, surface samples: face centroids and vertices of the original, strided.
fn surface_samples(original: &TriMesh, owner: &[u32], output_faces: usize) -> Vec<Sample> {
    let faces = original.triangles.len();
    let vertices = original.positions.len();
    let stride = (faces + vertices)
        .div_ceil(MAX_SAMPLES_PER_FACE * output_faces.max(1))
        .max(1);
    let mut vertex_normal = vec![DVec3::ZERO; vertices];
    let mut vertex_area = vec![0.0f64; vertices];
    let mut samples = Vec::with_capacity((faces + vertices) / stride + 1);
    // Vertex samples are every stride-th vertex (numbered after the faces): only their normals
    // and areas are needed, so a face that is no sample and has no sampled corner is skipped
    // (about 60 % of them at igea's 1 %, where the stride is 7). The sampled vertices are marked
    // by stepping, not by a remainder per corner (800k divisions took ~5 of igea's 6 ms here).
    let vertex_samples = ((stride - faces % stride) % stride..vertices).step_by(stride);
    let mut sampled_vertex = vec![false; vertices];
    for v in vertex_samples.clone() {
        sampled_vertex[v] = true;
    }
    let mut face_phase = 0;
    for f in 0..faces {
        let sampled_face = face_phase == 0;
        face_phase = if face_phase + 1 == stride {
            0
        } else {
            face_phase + 1
        };
        let t = original.triangles[f];
        if !sampled_face && !t.iter().any(|&v| sampled_vertex[v as usize]) {
            continue;
        }
        let [a, b, c] = original.triangle_f64(f);
        let cross = (b - a).cross(c - a);
        let area = 0.5 * cross.length();
        if !(area > 0.0 && area.is_finite()) {
            continue;
        }
        for &v in &t {
            vertex_normal[v as usize] += cross;
            vertex_area[v as usize] += area / 3.0;
        }
        if sampled_face {
            let mut owners = t.map(|v| owner[v as usize]);
            // Each owner once: a fan is searched once.
            if owners[1] == owners[0] {
                owners[1] = NONE;
            }
            if owners[2] == owners[0] || owners[2] == owners[1] {
                owners[2] = NONE;
            }
            samples.push(Sample {
                point: (a + b + c) / 3.0,
                normal: cross / (2.0 * area),
                weight: area * stride as f64,
                owners,
            });
        }
    }
    for v in vertex_samples {
        let normal = vertex_normal[v].normalize_or_zero();
        if vertex_area[v] > 0.0 && normal != DVec3::ZERO {
            samples.push(Sample {
                point: original.positions[v].as_dvec3(),
                normal,
                weight: vertex_area[v] * stride as f64,
                owners: [owner[v], NONE, NONE],
            });
        }
    }
    samples
}

/// Step 1, boundary samples: ends and midpoint of each original boundary edge, with the
/// edge's in-plane normal (perpendicular to the edge, in its face's plane).
fn boundary_samples(original: &TriMesh, edges: &EdgeTable, owner: &[u32]) -> Vec<Sample> {
    let mut samples = Vec::new();
    for e in 0..edges.len() {
        if !edges.is_boundary(e) {
            continue;
        }
        let [lo, hi] = edges.edges[e];
        let [a, b, c] = original.triangle_f64((edges.corners(e)[0] / 3) as usize);
        let face_normal = (b - a).cross(c - a).normalize_or_zero();
        let (pl, ph) = (
            original.positions[lo as usize].as_dvec3(),
            original.positions[hi as usize].as_dvec3(),
        );
        let normal = (ph - pl).cross(face_normal).normalize_or_zero();
        if normal == DVec3::ZERO {
            continue;
        }
        let (ol, oh) = (owner[lo as usize], owner[hi as usize]);
        let owners = [ol, if oh != ol { oh } else { NONE }, NONE];
        let weight = BOUNDARY_WEIGHT * (ph - pl).length_squared() / 3.0;
        for point in [pl, 0.5 * (pl + ph), ph] {
            samples.push(Sample {
                point,
                normal,
                weight,
                owners,
            });
        }
    }
    samples
}

/// Step 2 for a surface sample: the closest face (and point on it) in its owners' fans, if
/// that face's normal agrees with the sample's.
fn closest_face(
    s: &Sample,
    fans: &FanSearch<'_>,
    triangles: &[[u32; 3]],
    pos: &[DVec3],
) -> Option<(u32, DVec3)> {
    let mut around = [NONE; 3];
    let mut count = 0;
    for &o in s.owners.iter().filter(|&&o| o != NONE) {
        around[count] = o;
        count += 1;
    }
    let (_, f, q) = fans.nearest(s.point, &around[..count]);
    (f != NONE && normal(triangles[f as usize], pos).dot(s.normal) >= MIN_SAMPLE_COS)
        .then_some((f, q))
}

/// Step 2 for a boundary sample: the closest output boundary edge `(u, w)` at its owners and
/// the parameter `t` of the closest point on it.
fn closest_boundary_edge(
    s: &Sample,
    out_boundary: &[Vec<u32>],
    pos: &[DVec3],
) -> Option<(u32, u32, f64)> {
    let mut best = (f64::INFINITY, NONE, NONE, 0.0);
    for &u in s.owners.iter().filter(|&&o| o != NONE) {
        for &w in &out_boundary[u as usize] {
            let (pu, d) = (pos[u as usize], pos[w as usize] - pos[u as usize]);
            let len2 = d.length_squared();
            let t = if len2 > 0.0 {
                ((s.point - pu).dot(d) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let dist = (pu + d * t - s.point).length_squared();
            if dist < best.0 {
                best = (dist, u, w, t);
            }
        }
    }
    (best.1 != NONE).then_some((best.1, best.2, best.3))
}

/// Step 3: the plane sample `s` asks of each corner of `corners` (with barycentric `bary`),
/// the other corners held at `pos`.
fn add_sample(quadric: &mut [Quadric], s: &Sample, corners: &[u32], bary: &[f64], pos: &[DVec3]) {
    for (k, (&v, &bk)) in corners.iter().zip(bary).enumerate() {
        // A corner that barely carries the sample would get a huge, meaningless target.
        if bk < 1e-3 {
            continue;
        }
        let rest: DVec3 = corners
            .iter()
            .zip(bary)
            .enumerate()
            .filter(|&(j, _)| j != k)
            .map(|(_, (&u, &bu))| bu * pos[u as usize])
            .sum();
        let target = s.normal.dot(s.point - rest) / bk;
        quadric[v as usize] += Quadric::from_plane(s.normal, -target, s.weight * bk * bk);
    }
}

/// Barycentric coordinates of `q` (a point of triangle `a b c`).
fn barycentric(q: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let (e0, e1, e2) = (b - a, c - a, q - a);
    let (d00, d01, d11) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
    let (d20, d21) = (e2.dot(e0), e2.dot(e1));
    let den = d00 * d11 - d01 * d01;
    if den.abs() <= 0.0 || !den.is_finite() {
        return [1.0 / 3.0; 3];
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    [1.0 - v - w, v, w]
}

/// `q` scaled by `s`.
fn scaled(q: Quadric, s: f64) -> Quadric {
    Quadric {
        a: q.a.map(|x| x * s),
        b: q.b.map(|x| x * s),
        c: q.c * s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::soundness::min_angle_sin2;

    /// Output vertex of each original vertex: the nearest output vertex (brute force).
    fn nearest_owner(original: &TriMesh, output: &[Vec3]) -> Vec<u32> {
        original
            .positions
            .iter()
            .map(|p| {
                (0..output.len())
                    .min_by(|&a, &b| {
                        (output[a] - *p)
                            .length_squared()
                            .total_cmp(&(output[b] - *p).length_squared())
                    })
                    .unwrap() as u32
            })
            .collect()
    }

    /// Face-plane cell quadrics, as placement builds them (each face once per corner).
    fn anchors(original: &TriMesh, owner: &[u32], n: usize) -> Vec<Quadric> {
        let mut q = vec![Quadric::default(); n];
        for (f, t) in original.triangles.iter().enumerate() {
            let [a, b, c] = original.triangle_f64(f);
            let face = Quadric::from_triangle(a, b, c);
            for &v in t {
                q[owner[v as usize] as usize] += face;
            }
        }
        q
    }

    /// `coarse`'s vertices refitted to `original` (owners: nearest coarse vertex), and the stats.
    fn refitted(original: &TriMesh, coarse: &TriMesh) -> (Vec<Vec3>, RefitStats) {
        let mut positions = coarse.positions.clone();
        let owner = nearest_owner(original, &positions);
        let anchor = anchors(original, &owner, positions.len());
        let edges = EdgeTable::new(original);
        let stats = refit(
            &mut positions,
            &coarse.triangles,
            original,
            &edges,
            &owner,
            &anchor,
            2,
        );
        (positions, stats)
    }

    /// Mean distance of the original's vertices to the closest output face (brute force).
    fn mean_distance(original: &TriMesh, positions: &[Vec3], triangles: &[[u32; 3]]) -> f64 {
        let sum: f64 = original
            .positions
            .iter()
            .map(|p| {
                let p = p.as_dvec3();
                triangles
                    .iter()
                    .map(|t| {
                        let [a, b, c] = t.map(|v| positions[v as usize].as_dvec3());
                        (closest_point_triangle(p, a, b, c) - p).length()
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .sum();
        sum / original.positions.len() as f64
    }

    #[test]
    fn chords_of_a_sphere_are_lifted_onto_it() {
        // The coarse icosphere's vertices lie on the unit sphere, so its triangles are chords
        // inside it; the fine one is the "original".
        let original = mesh::procedural::icosphere(4);
        let coarse = mesh::procedural::icosphere(1);
        let before = mean_distance(&original, &coarse.positions, &coarse.triangles);
        let angle = |pos: &[Vec3], t: &[u32; 3]| {
            let [a, b, c] = t.map(|v| pos[v as usize].as_dvec3());
            min_angle_sin2(a, b, c).sqrt().asin().to_degrees()
        };
        let angles_before: Vec<f64> = coarse
            .triangles
            .iter()
            .map(|t| angle(&coarse.positions, t))
            .collect();
        let (positions, stats) = refitted(&original, &coarse);
        let after = mean_distance(&original, &positions, &coarse.triangles);
        assert!(stats.moves > 0 && stats.samples > 0);
        assert!(
            after < 0.6 * before,
            "mean distance {before:.4e} -> {after:.4e}"
        );
        // Lifted outward, by less than the sagitta of an edge (~0.1 for icosphere(1)).
        for p in &positions {
            let r = p.length();
            assert!(r > 1.0 && r < 1.1, "radius {r}");
        }
        // Every face still faces outward and keeps its shape (no vertex is on a border).
        for (t, before) in coarse.triangles.iter().zip(&angles_before) {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
            let after = angle(&positions, t);
            assert!(
                after >= before.min(crate::surface::soundness::REFIT_KEEP_ANGLE_DEGREES) - 1e-6,
                "{before}° -> {after}°"
            );
        }
    }

    #[test]
    fn a_flat_patch_stays_flat_and_keeps_its_border() {
        // Unit square, fine 16 × 16 grid as the original, coarse 4 × 4 sub-grid as the output.
        let original = mesh::procedural::unit_square_grid(16);
        let coarse = mesh::procedural::unit_square_grid(4);
        let (positions, _) = refitted(&original, &coarse);
        for (p, q) in positions.iter().zip(&coarse.positions) {
            assert!(p.z.abs() < 1e-6, "left the plane: {p:?}");
            // Border vertices stay on their border line.
            for k in 0..2 {
                if q[k] == 0.0 || q[k] == 1.0 {
                    assert!((p[k] - q[k]).abs() < 1e-5, "border moved: {q:?} -> {p:?}");
                }
            }
        }
    }
}

//! Tangential relaxation, option (h): GNG3D-Q's last step, on the mesh that the decimation of
//! an oversampled run returns (for outputs of at most [`crate::RELAX_MAX_RATIO`] of the input's
//! vertices, the rule of [`crate::GngOptions::resolve`]).
//!
//! Why: the decimation puts each merged vertex at the minimum of its quadric on the network's
//! mesh, which is right for the surface but not for the paper's E_avg (squared distance from
//! each original vertex to its nearest output vertex), whose optimum is the centroid of the
//! original vertices a vertex stands for. Before this step GNG3D-Q lost E_avg to QEM in 5 of
//! the survey's 45 runs (the 502-vertex knight at 10/25/50 %, the cow and the armadillo at
//! 10 %, by 1-6 %), while the paper's GNG3D, whose nodes sit at those centroids, won 43. With
//! it: 42 of 45 (docs/notes/gngq.md, "Relaxation after the decimation").
//!
//! Steps:
//! 1. **Labels**: every original vertex's nearest output vertex (kd-tree, all cores); at a
//!    fixed stride when the cells are large, so that about [`MAX_VERTICES_PER_CELL`] a cell
//!    take part.
//! 2. **Cells**: per output vertex, the centroid `c` of its original vertices and the normal
//!    tensor `T = Σ w n nᵀ / Σ w` of their faces (`w`: twice the face's area, once per corner
//!    in the cell), whose large eigenvalues are the directions across the cell's planes.
//! 3. **Move**: `d = STEP · (T + μI)⁻¹ μ (c − x)`: toward the centroid along the directions in
//!    which the cell is flat (eigenvalues of `T` well below [`TANGENT_WEIGHT`] = μ), hardly
//!    across its normal or a crease. Vertices of the output's open borders stay (they would
//!    leave the border). A move is taken under the refit's rules ([`crate::surface::moves`]: no face
//!    turns by more than 45°, every face keeps its smallest angle above 20° or its old one),
//!    else the vertex stays. Every move is computed from the decimated positions; the rules are
//!    checked against the moves taken so far.
//!
//! Deterministic: the labels are per vertex and the sums run in vertex and face order.

use crate::surface::{move_fits, output_boundary};
use glam::{DMat3, DVec3, Vec3};
use mesh::TriMesh;

/// Share of the way to the (filtered) centroid a vertex moves. Measured with μ = 0.02 over 42
/// survey runs (all but igea-1m; median GNG3D-Q / QEM ratios): 0.5 won E_avg in 40 (37
/// without the step), mean surface distance 1.029 → 1.077, Hausdorff 1.336 → 1.328; 1.0 won
/// 40 too but cost more mean distance (1.163).
pub const STEP: f64 = 0.5;

/// μ, the eigenvalue of a cell's normalised normal tensor below which a direction counts as
/// tangential (the cell's normals spread by less than ~8° in it). 0.005 (full step) won E_avg
/// in 39 of the 42 runs at mean distance 1.081× QEM; a plain tangent-plane move (no tensor,
/// full step) slid vertices off fandisk's creases: Hausdorff 5.2 → 14× QEM at 10 %.
pub const TANGENT_WEIGHT: f64 = 0.02;

/// At most about this many original vertices per output vertex are labelled (at a fixed
/// stride): at 1 % of igea a cell holds ~50, and their centroid is estimated from a third of
/// them, for a third of the labelling (most of the step's time: 15-20 → 8-12 ms). The
/// survey's ratios (≥ 10 %) have fewer per cell, so there every vertex takes part.
pub const MAX_VERTICES_PER_CELL: usize = 16;

/// What [`relax`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RelaxStats {
    /// Vertices moved.
    pub moves: usize,
}

/// Relaxes the output vertices `positions` (faces `triangles`) toward the centroids of the
/// `original`'s vertices nearest to them, along the surface. Vertices flagged in `seams` (on
/// an attribute seam the decimation kept) stay, as border vertices do.
pub(crate) fn relax(
    positions: &mut [Vec3],
    triangles: &[[u32; 3]],
    original: &TriMesh,
    seams: Option<&[bool]>,
    threads: usize,
) -> RelaxStats {
    let n = positions.len();
    if n == 0 || triangles.is_empty() {
        return RelaxStats::default();
    }
    // Step 1: labels, of every `stride`-th original vertex (the others stay `u32::MAX`).
    let stride = original
        .positions
        .len()
        .div_ceil(MAX_VERTICES_PER_CELL * n)
        .max(1);
    let labelled: Vec<Vec3> = original.positions.iter().step_by(stride).copied().collect();
    let strided = crate::surface::label_with_threads(&labelled, positions, threads);
    let mut label = vec![u32::MAX; original.positions.len()];
    for (k, l) in strided.into_iter().enumerate() {
        label[k * stride] = l;
    }

    // Step 2: centroids and normal tensors.
    let mut sum = vec![DVec3::ZERO; n];
    let mut count = vec![0u32; n];
    for (p, &o) in original.positions.iter().zip(&label) {
        if o != u32::MAX {
            sum[o as usize] += p.as_dvec3();
            count[o as usize] += 1;
        }
    }
    let mut tensor = vec![DMat3::ZERO; n];
    let mut weight = vec![0.0f64; n];
    for (f, t) in original.triangles.iter().enumerate() {
        // A face with no labelled corner adds nothing (about 40 % of them at igea's 1 %, where
        // every fourth vertex is labelled): skip it before its geometry.
        if t.iter().all(|&v| label[v as usize] == u32::MAX) {
            continue;
        }
        let [a, b, c] = original.triangle_f64(f);
        let cross = (b - a).cross(c - a);
        let w = cross.length();
        if !(w > 0.0 && w.is_finite()) {
            continue;
        }
        let u = cross / w;
        let nnt = DMat3::from_cols(u * u.x, u * u.y, u * u.z) * w;
        for &v in t {
            let o = label[v as usize];
            if o != u32::MAX {
                tensor[o as usize] += nnt;
                weight[o as usize] += w;
            }
        }
    }

    // Step 3: moves.
    let fan = crate::surface::fans(triangles, n);
    let border = output_boundary(triangles, n);
    let old: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
    let mut pos = old.clone();
    let mut stats = RelaxStats::default();
    let mu = DMat3::from_diagonal(DVec3::splat(TANGENT_WEIGHT));
    for v in 0..n {
        if count[v] == 0
            || weight[v] <= 0.0
            || fan[v].is_empty()
            || !border[v].is_empty()
            || seams.is_some_and(|s| s[v])
        {
            continue;
        }
        let to_centroid = sum[v] / count[v] as f64 - old[v];
        let step = STEP * ((tensor[v] / weight[v] + mu).inverse() * (to_centroid * TANGENT_WEIGHT));
        if !step.is_finite() {
            continue;
        }
        pos[v] = old[v] + step;
        if move_fits(&fan[v], triangles, &old, &pos, true) {
            stats.moves += 1;
        } else {
            pos[v] = old[v];
        }
    }
    for (p, q) in positions.iter_mut().zip(&pos) {
        *p = q.as_vec3();
    }
    stats
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `(n + 1)²`-vertex grid over the unit square in the plane z = 0, bent by `fold` about
    /// the line x = 1/2 (the half x > 1/2 rises along z by `fold` × (x − 1/2)).
    fn grid(n: u32, fold: f32) -> TriMesh {
        let mut g = mesh::procedural::unit_square_grid(n);
        for p in &mut g.positions {
            p.z = fold * (p.x - 0.5).max(0.0);
        }
        g
    }

    /// Sum over the original's vertices of the squared distance to the nearest output vertex
    /// (the paper's E_avg times the vertex count), brute force.
    fn e_sum(original: &TriMesh, output: &[Vec3]) -> f64 {
        original
            .positions
            .iter()
            .map(|p| {
                output
                    .iter()
                    .map(|q| (*q - *p).as_dvec3().length_squared())
                    .fold(f64::INFINITY, f64::min)
            })
            .sum()
    }

    #[test]
    fn interior_vertices_move_toward_their_centroids_in_the_plane() {
        // 289 original vertices for 25 output vertices: below MAX_VERTICES_PER_CELL a cell, so
        // every original vertex is labelled and the centroids are exact.
        let original = grid(16, 0.0);
        let coarse = grid(4, 0.0);
        // Shift the interior vertices off their cells' centres, inside the plane.
        let mut positions = coarse.positions.clone();
        for p in positions.iter_mut() {
            if p.x > 0.0 && p.x < 1.0 && p.y > 0.0 && p.y < 1.0 {
                *p += Vec3::new(0.06, -0.04, 0.0);
            }
        }
        let before = e_sum(&original, &positions);
        let shifted = positions.clone();
        let stats = relax(&mut positions, &coarse.triangles, &original, None, 2);
        // All 9 interior vertices move; the 16 border vertices stay.
        assert_eq!(stats.moves, 9);
        let centroids = centroids(&original, &shifted);
        for (v, (p, q)) in positions.iter().zip(&shifted).enumerate() {
            assert!(p.z.abs() < 1e-6, "left the plane: {p:?}");
            let border = q.x == 0.0 || q.x == 1.0 || q.y == 0.0 || q.y == 1.0;
            assert_eq!(border, p == q, "{q:?} -> {p:?}");
            if !border {
                // Half-way to the centroid of its nearest original vertices (in a flat cell the
                // whole move is tangential).
                let (before, after) = ((*q - centroids[v]).length(), (*p - centroids[v]).length());
                assert!(
                    (after - 0.5 * before).abs() < 0.02 * before,
                    "{before} -> {after}"
                );
            }
        }
        let after = e_sum(&original, &positions);
        assert!(after < 0.99 * before, "E sum {before:.4} -> {after:.4}");
    }

    /// Centroid of the original vertices nearest to each output vertex, brute force.
    fn centroids(original: &TriMesh, output: &[Vec3]) -> Vec<Vec3> {
        let mut sum = vec![(Vec3::ZERO, 0.0f32); output.len()];
        for p in &original.positions {
            let o = (0..output.len())
                .min_by(|&a, &b| {
                    (output[a] - *p)
                        .length_squared()
                        .total_cmp(&(output[b] - *p).length_squared())
                })
                .unwrap();
            sum[o].0 += *p;
            sum[o].1 += 1.0;
        }
        sum.iter().map(|(s, c)| *s / *c).collect()
    }

    #[test]
    fn a_vertex_on_a_crease_moves_along_it_only() {
        // A right-angle fold along x = 1/2; the coarse grid has a column of vertices on it.
        let original = grid(24, 1.0);
        let coarse = grid(4, 1.0);
        let mut positions = coarse.positions.clone();
        // The crease vertex (x = 1/2, y = 1/2), pushed along the crease and across it.
        let v = (2 * 5 + 2) as usize;
        assert_eq!(positions[v], Vec3::new(0.5, 0.5, 0.0));
        positions[v] = Vec3::new(0.5, 0.56, 0.0);
        let on_crease = positions[v];
        relax(&mut positions, &coarse.triangles, &original, None, 2);
        let p = positions[v];
        // It came back toward y = 1/2 (its cell's centroid) ...
        assert!(p.y < on_crease.y - 0.01, "{on_crease:?} -> {p:?}");
        // ... and stayed near the crease line (x = 1/2, z = 0): measured 7 % of the move's
        // length (the centroid of a folded cell lies inside the fold, and the 45° fold's
        // tensor is not singular across it); a move in the vertex's tangent plane would take
        // the whole offset to the centroid, as much across the crease as along it.
        let across = ((p.x - 0.5).powi(2) + p.z.powi(2)).sqrt();
        assert!(across < 0.1 * (on_crease - p).length(), "{p:?}");
        // The other vertices were at their cells' centres already, up to the fold.
        for (u, (a, b)) in positions.iter().zip(&coarse.positions).enumerate() {
            if u != v {
                assert!((*a - *b).length() < 0.02, "{b:?} -> {a:?}");
            }
        }
    }
}

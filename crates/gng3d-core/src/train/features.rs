//! Curvature weights for training signals ([`crate::SignalSource::Curvature`]): faces where the
//! surface bends within one output edge length draw more signals, so the network puts more
//! nodes on high-curvature parts and creases (GNG node density grows with the square root of
//! the signal density on a surface).
//!
//! Steps:
//! 1. **Edge curvature**: for every interior manifold edge, the dihedral angle θ between its two
//!    faces over the distance between their centroids (radians per model unit, a discrete
//!    normal curvature across the edge).
//! 2. **Face curvature** κ_f: the largest of its edges' (creases count fully).
//! 3. **Weight**: `area · (1 + CURVATURE_STRENGTH · min(κ_f · h, 1))`, with `h = √(A / N)` the
//!    expected output edge length for N vertices on area A. κ·h is the angle the surface turns
//!    over one output edge; it saturates at 1 rad, so weights are bounded to
//!    `[area, (1 + CURVATURE_STRENGTH) · area]` and a single sharp crease cannot drain the
//!    signal budget.

use mesh::TriMesh;
use mesh::topology::EdgeTable;

/// Largest extra weight factor of a face (weights lie in `[1, 1 + this]` × area). 3 means at
/// most 4× the signals per area, i.e. about 2× the node density.
pub const CURVATURE_STRENGTH: f64 = 3.0;

/// Per-face signal weights (see the module docs) for a target of `target_vertices` vertices.
/// Degenerate or non-finite faces get weight 0.
pub fn curvature_face_weights(mesh: &TriMesh, target_vertices: usize) -> Vec<f64> {
    let faces = mesh.triangles.len();
    let mut area = vec![0.0f64; faces];
    let mut normal = vec![glam::DVec3::ZERO; faces];
    let mut centroid = vec![glam::DVec3::ZERO; faces];
    for f in 0..faces {
        let [a, b, c] = mesh.triangle_f64(f);
        let cross = (b - a).cross(c - a);
        let len = cross.length();
        if len > 0.0 && len.is_finite() {
            area[f] = 0.5 * len;
            normal[f] = cross / len;
        }
        centroid[f] = (a + b + c) / 3.0;
    }
    let total: f64 = area.iter().sum();
    let h = (total / target_vertices.max(1) as f64).sqrt();
    // Steps 1-2: largest edge curvature per face.
    let mut kappa = vec![0.0f64; faces];
    let edges = EdgeTable::new(mesh);
    for e in 0..edges.len() {
        if edges.face_count(e) != 2 {
            continue;
        }
        let c = edges.corners(e);
        let (f, g) = ((c[0] / 3) as usize, (c[1] / 3) as usize);
        if area[f] == 0.0 || area[g] == 0.0 {
            continue;
        }
        let dist = (centroid[f] - centroid[g]).length();
        let theta = normal[f].dot(normal[g]).clamp(-1.0, 1.0).acos();
        if dist > 0.0 {
            let k = theta / dist;
            kappa[f] = kappa[f].max(k);
            kappa[g] = kappa[g].max(k);
        }
    }
    // Step 3.
    area.iter()
        .zip(&kappa)
        .map(|(&a, &k)| a * (1.0 + CURVATURE_STRENGTH * (k * h).min(1.0)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    use mesh::procedural::grid_cube;

    #[test]
    fn flat_faces_keep_their_area_and_curved_ones_gain_boundedly() {
        // A cube: faces along its 12 edges see a 90° crease; the others are flat.
        let cube = grid_cube(8);
        let t = mesh::topology::analyze(&cube);
        assert!(t.closed && t.manifold && cube.signed_volume() > 0.0);
        let w = curvature_face_weights(&cube, 50);
        let mut flat = 0;
        let mut crease = 0;
        for (f, &wf) in w.iter().enumerate() {
            let a = cube.triangle_area(f);
            assert!(
                wf >= a * (1.0 - 1e-12) && wf <= a * (1.0 + CURVATURE_STRENGTH) * (1.0 + 1e-12)
            );
            if (wf - a).abs() < 1e-12 * a {
                flat += 1;
            } else {
                crease += 1;
                assert!((wf - a * (1.0 + CURVATURE_STRENGTH)).abs() < 1e-9 * a);
            }
        }
        assert!(flat > 0 && crease > 0, "flat {flat}, crease {crease}");
    }
}

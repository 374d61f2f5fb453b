//! Deterministic procedural models for tests, benchmarks and the viewer's default scene.

use crate::TriMesh;
use glam::Vec3;
use std::collections::HashMap;

/// A unit-radius icosphere centred at the origin: `subdivisions` Loop-style splits of an
/// icosahedron (0 gives 12 vertices/20 faces; each level multiplies faces by 4).
pub fn icosphere(subdivisions: u32) -> TriMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| Vec3::from_array(*p).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *midpoint.entry(key).or_insert_with(|| {
                let p = ((positions[a as usize] + positions[b as usize]) * 0.5).normalize();
                positions.push(p);
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for &[a, b, c] in &triangles {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    TriMesh::new(positions, triangles)
}

/// A torus (genus 1) around the z axis with major radius `major`, tube radius `minor`,
/// `rings` segments around the axis and `sides` segments around the tube (each at least 3).
pub fn torus(major: f32, minor: f32, rings: u32, sides: u32) -> TriMesh {
    let rings = rings.max(3);
    let sides = sides.max(3);
    let mut positions = Vec::with_capacity((rings * sides) as usize);
    for i in 0..rings {
        let u = i as f32 / rings as f32 * std::f32::consts::TAU;
        for j in 0..sides {
            let v = j as f32 / sides as f32 * std::f32::consts::TAU;
            let r = major + minor * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let idx = |i: u32, j: u32| (i % rings) * sides + (j % sides);
    let mut triangles = Vec::with_capacity((2 * rings * sides) as usize);
    for i in 0..rings {
        for j in 0..sides {
            let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    TriMesh::new(positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_counts_and_area() {
        let m = icosphere(3);
        assert_eq!(m.face_count(), 20 * 64);
        assert_eq!(m.vertex_count(), 10 * 64 + 2);
        let sphere = 4.0 * std::f64::consts::PI;
        assert!(m.area() < sphere && m.area() > 0.98 * sphere);
        assert!(m.signed_volume() > 0.0);
    }

    #[test]
    fn torus_counts_and_area() {
        let m = torus(1.0, 0.25, 64, 32);
        assert_eq!(m.vertex_count(), 64 * 32);
        assert_eq!(m.face_count(), 2 * 64 * 32);
        let exact = 4.0 * std::f64::consts::PI.powi(2) * 1.0 * 0.25;
        assert!((m.area() - exact).abs() / exact < 0.01);
        assert!(m.signed_volume() > 0.0);
    }
}

//! Synthetic fragmented texture atlases ([`fragmented_atlas`]): a mesh cut into many small UV
//! charts, as photogrammetry and automatic unwrappers produce, for tests and measurements of
//! simplifiers that keep seams.

use crate::TriMesh;
use crate::attributes::Attributes;
use glam::{Vec2, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::collections::{HashMap, VecDeque};

/// Texture coordinates for `mesh` cut into about `charts` charts: `charts` distinct seed faces
/// drawn with `seed`, grown together breadth first over the faces' shared edges (each face joins
/// the chart that reaches it first; a connected part no seed reaches starts a chart of its own),
/// each chart projected onto the plane of its area-weighted normal and packed, aspect kept, into
/// its own cell of a square grid over the unit square (a margin of a tenth of a cell). One wedge
/// per chart and vertex, so every edge between two charts is a UV seam. Deterministic for a given
/// mesh, `charts` and `seed`. Returns the attributes (`uv0` only) and the number of charts.
pub fn fragmented_atlas(mesh: &TriMesh, charts: usize, seed: u64) -> (Attributes, usize) {
    let tris = &mesh.triangles;
    let nf = tris.len();
    // Faces across each edge (edges of exactly two faces join faces).
    let mut by_edge: HashMap<[u32; 2], Vec<u32>> = HashMap::with_capacity(nf * 3 / 2);
    for (f, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            by_edge
                .entry([a.min(b), a.max(b)])
                .or_default()
                .push(f as u32);
        }
    }
    let by_edge = &by_edge;
    let neighbours = |f: usize| {
        let t = tris[f];
        (0..3).filter_map(move |k| {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            match by_edge[&[a.min(b), a.max(b)]].as_slice() {
                &[x, y] => Some(if x as usize == f { y } else { x }),
                _ => None,
            }
        })
    };

    let mut chart = vec![u32::MAX; nf];
    let mut queue = VecDeque::new();
    let mut count = 0u32;
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let wanted = charts.clamp(1, nf.max(1));
    let mut tries = 0;
    while (count as usize) < wanted && tries < 100 * wanted {
        tries += 1;
        let f = rng.random_range(0..nf);
        if chart[f] == u32::MAX {
            chart[f] = count;
            queue.push_back(f as u32);
            count += 1;
        }
    }
    let mut next_unreached = 0;
    loop {
        while let Some(f) = queue.pop_front() {
            let c = chart[f as usize];
            for g in neighbours(f as usize) {
                if chart[g as usize] == u32::MAX {
                    chart[g as usize] = c;
                    queue.push_back(g);
                }
            }
        }
        while next_unreached < nf && chart[next_unreached] != u32::MAX {
            next_unreached += 1;
        }
        if next_unreached == nf {
            break;
        }
        chart[next_unreached] = count;
        queue.push_back(next_unreached as u32);
        count += 1;
    }

    let total = count as usize;
    let p = |v: u32| mesh.positions[v as usize];
    let mut normal = vec![Vec3::ZERO; total];
    for (f, t) in tris.iter().enumerate() {
        normal[chart[f] as usize] += (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
    }
    // Per chart: a plane basis, then the bounds of the projected corners.
    let basis: Vec<(Vec3, Vec3)> = normal
        .iter()
        .map(|n| {
            let n = n.try_normalize().unwrap_or(Vec3::Z);
            let u = n.any_orthonormal_vector();
            (u, n.cross(u))
        })
        .collect();
    let project = |c: usize, v: u32| Vec2::new(p(v).dot(basis[c].0), p(v).dot(basis[c].1));
    let mut lo = vec![Vec2::splat(f32::INFINITY); total];
    let mut hi = vec![Vec2::splat(f32::NEG_INFINITY); total];
    for (f, t) in tris.iter().enumerate() {
        let c = chart[f] as usize;
        for &v in t {
            lo[c] = lo[c].min(project(c, v));
            hi[c] = hi[c].max(project(c, v));
        }
    }
    let side = (total as f32).sqrt().ceil() as usize;
    let cell = 1.0 / side as f32;
    let mut attributes = Attributes::default();
    let mut uv = Vec::new();
    let mut wedge_of: HashMap<(u32, u32), u32> = HashMap::new();
    for (f, t) in tris.iter().enumerate() {
        let c = chart[f] as usize;
        let corner = t.map(|v| {
            *wedge_of.entry((c as u32, v)).or_insert_with(|| {
                let extent = (hi[c] - lo[c]).max_element().max(f32::MIN_POSITIVE);
                let origin = Vec2::new((c % side) as f32, (c / side) as f32) * cell;
                let local = (project(c, v) - lo[c]) / extent;
                uv.push(origin + (0.1 + 0.8 * local) * cell);
                attributes.wedge_vertex.push(v);
                (uv.len() - 1) as u32
            })
        });
        attributes.corners.push(corner);
    }
    attributes.uv0 = Some(uv);
    (attributes, total)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charts_are_seams_and_deterministic() {
        let m = crate::procedural::icosphere(4);
        let (a, n) = fragmented_atlas(&m, 150, 3);
        assert_eq!(n, 150);
        a.validate(&m).unwrap();
        assert_eq!(a.charts(&m).iter().max().map(|&c| c as usize + 1), Some(n));
        assert!(!a.seam_edges(&m).is_empty());
        assert!(
            a.uv0
                .as_ref()
                .unwrap()
                .iter()
                .all(|u| u.cmpge(Vec2::ZERO).all() && u.cmple(Vec2::ONE).all())
        );
        assert_eq!(fragmented_atlas(&m, 150, 3).0, a);
    }
}

//! [`crate::Step::CutSeams`]: the network's mesh is cut along the original's attribute seams
//! (UV, normal and colour seams, material borders), so that the decimation that follows
//! ([`crate::finish::decimate::decimate_along_seams`]) keeps them as QEM keeps the original's: each
//! triangle on one side, seams contracted only along themselves.
//!
//! The network's triangulation does not know the seams: its triangles straddle them, a corner
//! on each side, and the texture is smeared across the atlas inside them (or, after the
//! chart-per-triangle transfer, stretched from the chart's border). The cut:
//! 1. each vertex of the network's mesh takes the chart
//!    ([`mesh::attributes::Attributes::charts`]) of the original triangle closest to it;
//! 2. on each edge whose ends lie in different charts, the crossing: where the chart of the
//!    closest original triangle changes along it (bisection on the edge, to 1/4096 of its
//!    length: on the network's mesh, so the faces stay where they were);
//! 3. a vertex within a tenth of an edge's length of its crossing ([`SNAP`]) moves onto it (the
//!    nearest crossing) and is on the seam from then on; every other crossing between two
//!    vertices off the seam becomes a new vertex;
//! 4. each triangle with new vertices on its edges is split along the segments between them
//!    and the corners on the seam: a corner alone in its chart keeps a corner triangle and the
//!    other two a quad (two triangles, the shorter diagonal); a triangle with three charts a
//!    corner triangle each and one in the middle (its chart: the original's at its centroid);
//!    a triangle with one crossing (its third corner on the seam) two.
//!
//! Every triangle of the result lies in one chart (returned per triangle); the seams run along
//! its edges, through the new and the moved vertices. Moving the vertices that are nearly on a
//! seam anyway spares the decimation a sliver (measured when QEM still contracted a vertex off
//! the seams only with another off them; now it may also merge one into a seam vertex, which
//! stays): on spot at 10 % the output's mean distance to the original was 4.6e-3 without the
//! moves and 4.1e-3 with them, on the fandisk atlas 1.15e-3 and 7.8e-4
//! (docs/notes/attributes.md).

use glam::Vec3;
use mesh::TriMesh;
use mesh::transfer::FaceGrid;
use rustc_hash::FxHashMap as HashMap;

/// Bisection steps per crossed edge (the crossing within 2⁻¹² of the edge's length).
const BISECTIONS: usize = 12;

/// A vertex this share of an edge's length or less from the edge's crossing moves onto it.
/// Swept at 0.05-0.45 on spot at 5, 10, 20 % and the fandisk atlas at 10 %: from 0.12 up the
/// mean distance falls by a few per cent more and the share of the area more than 0.05 UV off
/// rises by a third on spot at 10 % (0.6 → 0.9 %).
const SNAP: f32 = 0.1;

/// The chart label of a vertex moved onto a seam.
const ON_SEAM: u32 = u32::MAX - 1;

/// The network's mesh cut along the seams.
pub(crate) struct SeamCut {
    /// Vertices: the mesh's (those moved onto a seam moved), then one per crossing between two
    /// vertices off the seams.
    pub positions: Vec<Vec3>,
    /// Triangles, each within one chart.
    pub triangles: Vec<[u32; 3]>,
    /// Chart of each triangle (the original's chart numbers).
    pub charts: Vec<u32>,
    /// Vertices added on the seams.
    pub added: usize,
    /// Vertices moved onto the seams.
    pub snapped: usize,
}

/// Cuts the mesh `positions`, `triangles` along the seams between the `charts` (one per
/// triangle) of `original` (module docs).
pub(crate) fn cut(
    original: &TriMesh,
    grid: &FaceGrid,
    charts: &[u32],
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    threads: usize,
) -> SeamCut {
    debug_assert_eq!(charts.len(), original.triangles.len());
    let chart_at = |p: Vec3| {
        grid.closest(p, |_| true)
            .map_or(u32::MAX, |(f, _)| charts[f as usize])
    };
    let mut vertex_chart =
        crate::parallel::map_indexed(positions.len(), threads, 256, |v| chart_at(positions[v]));
    // The crossed edges, smaller end first, in a fixed order.
    let mut crossed: Vec<[u32; 2]> = triangles
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .filter(|&[u, v]| vertex_chart[u as usize] != vertex_chart[v as usize])
        .map(|[u, v]| [u.min(v), u.max(v)])
        .collect();
    crossed.sort_unstable();
    crossed.dedup();
    let points = crate::parallel::map_indexed(crossed.len(), threads, 64, |i| {
        let [u, v] = crossed[i];
        let (a, b) = (positions[u as usize], positions[v as usize]);
        let own = vertex_chart[u as usize];
        let (mut lo, mut hi) = (0.0f32, 1.0f32);
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if chart_at(a.lerp(b, mid)) == own {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    });
    // A vertex within SNAP of an edge's length from the edge's crossing moves onto it (the
    // nearest such crossing): it is then on the seam, and its edges cross nothing.
    let mut snap = vec![(f32::INFINITY, usize::MAX); positions.len()];
    for (i, &[u, v]) in crossed.iter().enumerate() {
        let t = points[i];
        let length = positions[u as usize].distance(positions[v as usize]);
        for (w, share) in [(u, t), (v, 1.0 - t)] {
            let near = &mut snap[w as usize];
            if share < SNAP && share * length < near.0 {
                *near = (share * length, i);
            }
        }
    }
    let point = |i: usize| {
        let [u, v] = crossed[i];
        positions[u as usize].lerp(positions[v as usize], points[i])
    };
    let mut out_positions = positions.to_vec();
    let mut snapped = 0;
    for (w, &(_, i)) in snap.iter().enumerate() {
        if i != usize::MAX {
            out_positions[w] = point(i);
            vertex_chart[w] = ON_SEAM;
            snapped += 1;
        }
    }
    let mut on_edge: HashMap<[u32; 2], u32> = HashMap::default();
    let mut added = 0;
    for (i, &[u, v]) in crossed.iter().enumerate() {
        if vertex_chart[u as usize] != ON_SEAM && vertex_chart[v as usize] != ON_SEAM {
            on_edge.insert([u, v], out_positions.len() as u32);
            out_positions.push(point(i));
            added += 1;
        }
    }
    let mut out_triangles = Vec::with_capacity(triangles.len() + 3 * added);
    let mut out_charts = Vec::with_capacity(triangles.len() + 3 * added);
    let at = |u: u32, v: u32| on_edge.get(&[u.min(v), u.max(v)]).copied();
    for t in triangles {
        let c = t.map(|v| vertex_chart[v as usize]);
        // The new vertex on the edge from corner k to corner k + 1.
        let x: [Option<u32>; 3] = [0, 1, 2].map(|k| at(t[k], t[(k + 1) % 3]));
        match x {
            [None, None, None] => {
                // One chart, or none but the seam's (corners on it).
                out_triangles.push(*t);
                let own = c.iter().copied().find(|&c| c != ON_SEAM);
                out_charts.push(own.unwrap_or_else(|| {
                    chart_at(t.iter().map(|&v| out_positions[v as usize]).sum::<Vec3>() / 3.0)
                }));
            }
            [Some(_), None, None] | [None, Some(_), None] | [None, None, Some(_)] => {
                // The third corner is on the seam: the triangle splits at the crossing.
                let k = (0..3).find(|&k| x[k].is_some()).unwrap_or(0);
                let (a, b, on) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let xab = x[k].unwrap_or(b);
                out_triangles.push([on, a, xab]);
                out_charts.push(c[k]);
                out_triangles.push([on, xab, b]);
                out_charts.push(c[(k + 1) % 3]);
            }
            [Some(x0), Some(x1), Some(x2)] => {
                // Three charts: a corner triangle each, one in the middle.
                for (k, tri) in [[t[0], x0, x2], [t[1], x1, x0], [t[2], x2, x1]]
                    .into_iter()
                    .enumerate()
                {
                    out_triangles.push(tri);
                    out_charts.push(c[k]);
                }
                let middle = [x0, x1, x2];
                let centroid = middle
                    .iter()
                    .map(|&v| out_positions[v as usize])
                    .sum::<Vec3>()
                    / 3.0;
                out_triangles.push(middle);
                out_charts.push(chart_at(centroid));
            }
            _ => {
                // Two crossed edges: the corner k between them is alone in its chart.
                let Some(k) = (0..3).find(|&k| x[k].is_some() && x[(k + 2) % 3].is_some()) else {
                    continue;
                };
                let (a, b, cc) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let (xab, xca) = (x[k].unwrap_or(b), x[(k + 2) % 3].unwrap_or(cc));
                out_triangles.push([a, xab, xca]);
                out_charts.push(c[k]);
                // The quad xab → b → c → xca, split along its shorter diagonal.
                let p = |v: u32| out_positions[v as usize];
                let other = c[(k + 1) % 3];
                if p(xab).distance_squared(p(cc)) <= p(b).distance_squared(p(xca)) {
                    out_triangles.push([xab, b, cc]);
                    out_triangles.push([xab, cc, xca]);
                } else {
                    out_triangles.push([xab, b, xca]);
                    out_triangles.push([b, cc, xca]);
                }
                out_charts.push(other);
                out_charts.push(other);
            }
        }
    }
    SeamCut {
        positions: out_positions,
        triangles: out_triangles,
        charts: out_charts,
        added,
        snapped,
    }
}

/// Shortest chain of seam edges inside one chart that [`split_inner_chains`] separates (a pole's fan of
/// one-edge seams is left alone).
const MIN_CHAIN: usize = 3;

/// Each triangle's side of the seams for the cut: its label in `sides` (one per triangle: the
/// attribute charts, [`mesh::attributes::Attributes::charts`], or crease patches,
/// [`crate::finish::creases`]), except where one label is on both sides of some of the `seams`
/// (vertex pairs, smaller first, sorted; [`mesh::attributes::Attributes::seam_edges`]): the
/// meridian of a UV sphere, the seam of an unwrapped
/// cylinder, a crease line that ends inside a smooth patch. There each chain of such seam edges
/// of at least [`MIN_CHAIN`] edges (through vertices on two of them) gets a label on its left
/// and one on its right, and the labels grow from those triangles across the other edges,
/// breadth first, until they meet (for a UV sphere: at the antipode of the meridian, where the
/// values are continuous: a border the cut follows for nothing, but only one).
pub(crate) fn split_inner_chains(
    mesh: &TriMesh,
    mut sides: Vec<u32>,
    seams: &[[u32; 2]],
) -> Vec<u32> {
    let mut faces_of: HashMap<[u32; 2], Vec<u32>> = HashMap::default();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            faces_of
                .entry([u.min(v), u.max(v)])
                .or_default()
                .push(f as u32);
        }
    }
    // Seam edges with the same chart on both sides, and their ends' count of them.
    let inner: Vec<[u32; 2]> = seams
        .iter()
        .copied()
        .filter(|e| {
            faces_of
                .get(e)
                .is_some_and(|f| f.len() == 2 && sides[f[0] as usize] == sides[f[1] as usize])
        })
        .collect();
    if inner.is_empty() {
        return sides;
    }
    let mut at: HashMap<u32, Vec<usize>> = HashMap::default();
    for (i, e) in inner.iter().enumerate() {
        at.entry(e[0]).or_default().push(i);
        at.entry(e[1]).or_default().push(i);
    }
    let mut next = sides.iter().copied().max().unwrap_or(0) + 1;
    let mut label = vec![u32::MAX; mesh.triangles.len()];
    let mut queue = std::collections::VecDeque::new();
    let mut done = vec![false; inner.len()];
    for first in 0..inner.len() {
        if done[first] {
            continue;
        }
        // The chain through `first`, oriented: walk back to an end, then forward.
        let through = |v: u32, from: usize| -> Option<usize> {
            match at.get(&v).map(Vec::as_slice) {
                Some(&[a, b]) => Some(if a == from { b } else { a }),
                _ => None,
            }
        };
        let (mut edge, mut v) = (first, inner[first][0]);
        let mut steps = 0;
        while let Some(e) = through(v, edge) {
            if e == first || steps > inner.len() {
                break;
            }
            let w = if inner[e][0] == v {
                inner[e][1]
            } else {
                inner[e][0]
            };
            (edge, v) = (e, w);
            steps += 1;
        }
        // `v` is an end (or the loop's start), `edge` the chain's first edge from it.
        let mut chain: Vec<(u32, u32)> = Vec::new();
        let (mut e, mut from) = (edge, v);
        loop {
            done[e] = true;
            let to = if inner[e][0] == from {
                inner[e][1]
            } else {
                inner[e][0]
            };
            chain.push((from, to));
            match through(to, e) {
                Some(n) if !done[n] => (e, from) = (n, to),
                _ => break,
            }
        }
        if chain.len() < MIN_CHAIN {
            continue;
        }
        let (left, right) = (next, next + 1);
        next += 2;
        for &(a, b) in &chain {
            for &f in &faces_of[&[a.min(b), a.max(b)]] {
                let t = mesh.triangles[f as usize];
                let forward = (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b);
                if label[f as usize] == u32::MAX {
                    label[f as usize] = if forward { left } else { right };
                    queue.push_back(f);
                }
            }
        }
    }
    // Grow the labels across the edges that are not seams (within the seeds' charts).
    let on_seam = |e: &[u32; 2]| seams.binary_search(e).is_ok();
    while let Some(f) = queue.pop_front() {
        let t = mesh.triangles[f as usize];
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            let e = [u.min(v), u.max(v)];
            if on_seam(&e) {
                continue;
            }
            for &g in &faces_of[&e] {
                if label[g as usize] == u32::MAX {
                    label[g as usize] = label[f as usize];
                    queue.push_back(g);
                }
            }
        }
    }
    for (s, l) in sides.iter_mut().zip(label) {
        if l != u32::MAX {
            *s = l;
        }
    }
    sides
}

/// Mean and largest distance to the original (`grid`, over its faces) of `mesh`'s vertices,
/// edge midpoints (each edge once per face) and face centroids.
pub(crate) fn distance_to(grid: &FaceGrid, original: &TriMesh, mesh: &TriMesh) -> (f64, f64) {
    let distance = |p: Vec3| {
        grid.closest(p, |_| true).map_or(0.0, |(f, w)| {
            let [a, b, c] = original.triangle_f64(f as usize);
            (a * w[0] + b * w[1] + c * w[2]).distance(p.as_dvec3())
        })
    };
    let (mut sum, mut max, mut count) = (0.0, 0.0f64, 0usize);
    let mut add = |d: f64| {
        sum += d;
        max = max.max(d);
        count += 1;
    };
    for &p in &mesh.positions {
        add(distance(p));
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        for p in [
            (a + b) * 0.5,
            (b + c) * 0.5,
            (c + a) * 0.5,
            (a + b + c) / 3.0,
        ] {
            add(distance(p));
        }
    }
    (sum / count.max(1) as f64, max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mesh::attributes::Attributes;

    /// A UV sphere's meridian lies inside its one chart; its sides differ across every
    /// meridian edge, and a chart without such seams keeps its charts.
    #[test]
    fn the_two_sides_of_a_seam_inside_a_chart_differ() {
        let (sphere, uv) = mesh::procedural::textured_sphere(12, 24);
        let charts = uv.charts(&sphere);
        let sides = split_inner_chains(&sphere, charts.clone(), &uv.seam_edges(&sphere));
        // The meridian: ring vertices 2 + (i - 1) * 24 for i = 1..12, j = 0.
        let meridian: Vec<u32> = (1..12).map(|i| 2 + (i - 1) * 24).collect();
        let faces_on = |a: u32, b: u32| -> Vec<usize> {
            (0..sphere.triangles.len())
                .filter(|&f| sphere.triangles[f].contains(&a) && sphere.triangles[f].contains(&b))
                .collect()
        };
        for w in meridian.windows(2) {
            let f = faces_on(w[0], w[1]);
            assert_eq!(f.len(), 2);
            assert_eq!(
                charts[f[0]], charts[f[1]],
                "the meridian is inside one chart"
            );
            assert_ne!(sides[f[0]], sides[f[1]], "{w:?}");
        }
        let (square, _) = (mesh::procedural::unit_square_grid(4), ());
        let plain = Attributes {
            face_material: Some((0..square.triangles.len() as u32).map(|f| f % 2).collect()),
            ..Attributes::per_vertex(&square)
        };
        assert_eq!(
            split_inner_chains(&square, plain.charts(&square), &plain.seam_edges(&square)),
            plain.charts(&square)
        );
    }

    /// A flat 1 × 1 square of 2 × 8 × 8 triangles whose charts are x < 0.375 and x > 0.375,
    /// and a coarse mesh over it of 2 × 2 × 2 triangles: every triangle of the cut lies on one
    /// side of x = 0.375, the new vertices on the line, and the cut covers the square.
    #[test]
    fn a_coarse_mesh_is_cut_along_the_charts_border() {
        let original = mesh::procedural::unit_square_grid(8);
        let border = 0.375;
        let charts: Vec<u32> = (0..original.triangles.len())
            .map(|f| {
                let [a, b, c] = original.triangles[f].map(|v| original.positions[v as usize]);
                u32::from((a + b + c).x / 3.0 >= border)
            })
            .collect();
        let coarse = mesh::procedural::unit_square_grid(2);
        let grid = FaceGrid::new(&original);
        let cut = cut(
            &original,
            &grid,
            &charts,
            &coarse.positions,
            &coarse.triangles,
            1,
        );
        assert!(cut.added >= 2, "{}", cut.added);
        for v in coarse.positions.len()..cut.positions.len() {
            assert!(
                (cut.positions[v].x - border).abs() < 1e-3,
                "{:?}",
                cut.positions[v]
            );
        }
        let area: f32 = (0..cut.triangles.len())
            .map(|f| {
                let [a, b, c] = cut.triangles[f].map(|v| cut.positions[v as usize]);
                let side = (a + b + c).x / 3.0 >= border;
                assert_eq!(u32::from(side), cut.charts[f]);
                assert!(
                    a.x.max(b.x).max(c.x) <= border + 1e-3
                        || a.x.min(b.x).min(c.x) >= border - 1e-3
                );
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        assert!((area - 1.0).abs() < 1e-4, "{area}");
    }
}

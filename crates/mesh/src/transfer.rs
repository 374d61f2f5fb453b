//! Attributes for a simplified mesh from the original surface: each output corner takes the
//! original's attribute values at the closest point of the original surface on its side of the
//! seams ([`transfer_attributes`]), so seams stay seams.
//!
//! ```
//! use gng3d_mesh::{procedural, transfer::transfer_attributes};
//! let (sphere, uv) = procedural::textured_sphere(16, 32);
//! // A "simplified" mesh: here the original itself; every corner gets its own values back.
//! let back = transfer_attributes(&sphere, &uv, &sphere);
//! back.validate(&sphere).unwrap();
//! assert_eq!(back.seam_edges(&sphere), uv.seam_edges(&sphere));
//! ```

use crate::TriMesh;
use crate::attributes::Attributes;
use glam::{DVec3, Vec2, Vec3, Vec4};
use rustc_hash::FxHashMap as HashMap;

/// A uniform hash grid over a mesh's triangles for closest-point queries.
pub struct FaceGrid<'a> {
    mesh: &'a TriMesh,
    cell: f64,
    origin: DVec3,
    cells: HashMap<[i32; 3], Vec<u32>>,
    /// Each triangle's bounding box (a lower bound of its distance before the exact test).
    bounds: Vec<(DVec3, DVec3)>,
    /// Smallest and largest cell coordinates used.
    lo: [i32; 3],
    hi: [i32; 3],
}

impl<'a> FaceGrid<'a> {
    /// The grid over `mesh`'s triangles (cells about twice the mean triangle size).
    pub fn new(mesh: &'a TriMesh) -> FaceGrid<'a> {
        let bbox = mesh.referenced_bounding_box();
        let origin = bbox.min.as_dvec3();
        let faces = mesh.triangles.len().max(1) as f64;
        let mean = (mesh.area() / faces).sqrt();
        let diag = bbox.diagonal().max(f64::MIN_POSITIVE);
        let mut cell = (2.0 * mean).max(diag / 2048.0).max(1e-30);
        // Long thin triangles (a fan's slivers) would each cover many cells of a size made for
        // their small area: grow the cells until the entries stay within 16 per triangle.
        let budget = 16.0 * faces + 1e6;
        loop {
            let entries: f64 = (0..mesh.triangles.len())
                .map(|f| {
                    let [a, b, c] = mesh.triangle_f64(f);
                    let span = (a.max(b).max(c) - a.min(b).min(c)) / cell;
                    (span.x.floor() + 1.0) * (span.y.floor() + 1.0) * (span.z.floor() + 1.0)
                })
                .sum();
            if entries <= budget || cell >= diag {
                break;
            }
            cell *= 2.0;
        }
        let mut grid = FaceGrid {
            mesh,
            cell,
            origin,
            cells: HashMap::default(),
            bounds: Vec::with_capacity(mesh.triangles.len()),
            lo: [i32::MAX; 3],
            hi: [i32::MIN; 3],
        };
        for (f, t) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = t.map(|v| mesh.positions[v as usize].as_dvec3());
            grid.bounds.push((a.min(b).min(c), a.max(b).max(c)));
            let lo = grid.cell_of(a.min(b).min(c));
            let hi = grid.cell_of(a.max(b).max(c));
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        grid.cells.entry([x, y, z]).or_default().push(f as u32);
                    }
                }
            }
            for k in 0..3 {
                grid.lo[k] = grid.lo[k].min(lo[k]);
                grid.hi[k] = grid.hi[k].max(hi[k]);
            }
        }
        grid
    }

    fn cell_of(&self, p: DVec3) -> [i32; 3] {
        let q = (p - self.origin) / self.cell;
        [q.x, q.y, q.z].map(|c| c.floor().clamp(-1e9, 1e9) as i32)
    }

    /// The triangle closest to `p` among those `accept` takes, with the closest point's
    /// barycentric coordinates on it; `None` when no triangle is accepted.
    pub fn closest(&self, p: Vec3, accept: impl Fn(u32) -> bool) -> Option<(u32, [f64; 3])> {
        let p = p.as_dvec3();
        let c = self.cell_of(p);
        let mut best: Option<(f64, u32, DVec3)> = None;
        let reach = (0..3)
            .map(|k| (c[k] - self.lo[k]).abs().max((self.hi[k] - c[k]).abs()))
            .max()
            .unwrap_or(0)
            + 1;
        let consider = |f: u32, best: &mut Option<(f64, u32, DVec3)>| {
            // A triangle whose box is farther than the best so far cannot be closer (nor as
            // close: ties go to the smaller index, so only a strictly farther box is skipped).
            if let Some((bd, _, _)) = *best {
                let (lo, hi) = self.bounds[f as usize];
                let gap = (lo - p).max(p - hi).max(DVec3::ZERO);
                if gap.length_squared() > bd {
                    return;
                }
            }
            if !accept(f) {
                return;
            }
            let [a, b, cc] = self.mesh.triangle_f64(f as usize);
            let q = crate::geometry::closest_point_triangle(p, a, b, cc);
            let d = q.distance_squared(p);
            if best.is_none_or(|(bd, bf, _)| (d, f) < (bd, bf)) {
                *best = Some((d, f, q));
            }
        };
        // Far from every triangle the shells would visit more cells than the grid has: then
        // every triangle is looked at once instead.
        let mut lookups = 0usize;
        for r in 0..=reach {
            let side = 2 * r as usize + 1;
            lookups += side * side * side - if r == 0 { 0 } else { (side - 2).pow(3) };
            if lookups > self.cells.len() + 4096 {
                best = None;
                for f in 0..self.mesh.triangles.len() as u32 {
                    consider(f, &mut best);
                }
                break;
            }
            for x in c[0] - r..=c[0] + r {
                for y in c[1] - r..=c[1] + r {
                    let on_shell_xy = (x - c[0]).abs() == r || (y - c[1]).abs() == r;
                    // Inside the shell's xy ring only the two z caps are new.
                    let step = if on_shell_xy {
                        1
                    } else {
                        (2 * r).max(1) as usize
                    };
                    for z in (c[2] - r..=c[2] + r).step_by(step) {
                        let Some(list) = self.cells.get(&[x, y, z]) else {
                            continue;
                        };
                        for &f in list {
                            consider(f, &mut best);
                        }
                    }
                }
            }
            // Every point within `wall` of `p` lies in the cells searched so far (the cube of
            // shells 0..=r around p's cell); a best strictly nearer than that is final. (Was
            // `d <= r · cell`, which ignored where p sits in its cell and so always searched
            // the first shell's 26 cells: spot's QEM with UVs spent 30 % of its time here.)
            if let Some((d, _, _)) = best {
                let wall = (0..3)
                    .map(|k| {
                        let lo = self.origin[k] + (c[k] - r) as f64 * self.cell;
                        let hi = self.origin[k] + (c[k] + r + 1) as f64 * self.cell;
                        (p[k] - lo).min(hi - p[k])
                    })
                    .fold(f64::INFINITY, f64::min);
                if d.sqrt() < wall {
                    break;
                }
            }
        }
        best.map(|(_, f, q)| {
            let [a, b, c] = self.mesh.triangle_f64(f as usize);
            (f, barycentric(q, a, b, c))
        })
    }
}

/// Barycentric coordinates of `p` (on the triangle's plane) in triangle `a b c`; for a
/// degenerate triangle, all weight on the nearest corner.
pub fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let denom = d00 * d11 - d01 * d01;
    if denom.abs() <= 1e-300 || !denom.is_finite() {
        let d = [a, b, c].map(|x| x.distance_squared(p));
        let k = (0..3).min_by(|&i, &j| d[i].total_cmp(&d[j])).unwrap_or(0);
        let mut w = [0.0; 3];
        w[k] = 1.0;
        return w;
    }
    let v = ((d11 * d20 - d01 * d21) / denom).clamp(0.0, 1.0);
    let w = ((d00 * d21 - d01 * d20) / denom).clamp(0.0, 1.0);
    let s = v + w;
    let (v, w) = if s > 1.0 { (v / s, w / s) } else { (v, w) };
    [1.0 - v - w, v, w]
}

/// The values of every attribute of `attributes` on triangle `face` of the original at the
/// barycentric coordinates `bary` (normals renormalised), appended to `out`.
fn interpolate(attributes: &Attributes, face: u32, bary: [f64; 3], out: &mut Attributes) {
    let c = attributes.corners[face as usize];
    let w = bary.map(|x| x as f32);
    if let (Some(src), Some(dst)) = (&attributes.normals, out.normals.as_mut()) {
        let n: Vec3 = (0..3).map(|k| src[c[k] as usize] * w[k]).sum();
        let fallback = src[c[(0..3).max_by(|&i, &j| w[i].total_cmp(&w[j])).unwrap_or(0)] as usize];
        dst.push(n.try_normalize().unwrap_or(fallback));
    }
    if let (Some(src), Some(dst)) = (&attributes.uv0, out.uv0.as_mut()) {
        dst.push((0..3).map(|k| src[c[k] as usize] * w[k]).sum::<Vec2>());
    }
    if let (Some(src), Some(dst)) = (&attributes.uv1, out.uv1.as_mut()) {
        dst.push((0..3).map(|k| src[c[k] as usize] * w[k]).sum::<Vec2>());
    }
    if let (Some(src), Some(dst)) = (&attributes.colors, out.colors.as_mut()) {
        dst.push((0..3).map(|k| src[c[k] as usize] * w[k]).sum::<Vec4>());
    }
}

/// Attributes for `simplified` from `original` and its `attributes` (which must fit it, see
/// [`Attributes::validate`]).
///
/// Each corner of `simplified` takes the attribute values of the closest point of the original
/// surface to the corner's position *on the corner's side of the seams*: the side is the
/// original triangle closest to a point just inside the corner's triangle, and the search
/// walks from there across edges that are not seams only ([`Attributes::seam_edges`]). The
/// values are interpolated barycentrically on the original triangle there (normals
/// renormalised). Corners of one vertex with equal values (within 1e-5, relative) share a
/// wedge, so a vertex whose triangles lie on both sides of a seam gets one wedge per side with
/// that side's values. A triangle whose corners fall in different charts
/// ([`Attributes::charts`]: it straddles a seam) takes the chart of the original triangle
/// closest to its centroid for every corner, a corner from elsewhere at its closest point of
/// that chart, so no triangle interpolates between two places of a texture atlas and the seam
/// runs along the output's edges. Each triangle takes the material of the original triangle
/// closest to its centroid. Works for any simplified mesh near the original (QEM's, GNG3D-Q's).
pub fn transfer_attributes(
    original: &TriMesh,
    attributes: &Attributes,
    simplified: &TriMesh,
) -> Attributes {
    let grid = FaceGrid::new(original);
    let sides = attributes.edge_sides(original);
    if !sides.iter().any(|e| e.seam) {
        return transfer_without_seams(attributes, simplified, &grid);
    }
    // Neighbours of each original triangle across edges that are not seams, and the charts
    // those edges join (Attributes::charts).
    let mut across = vec![[u32::MAX; 3]; original.triangles.len()];
    let mut fill = vec![0u8; original.triangles.len()];
    let mut near_seam = vec![false; original.positions.len()];
    for e in &sides {
        if e.seam {
            near_seam[e.edge[0] as usize] = true;
            near_seam[e.edge[1] as usize] = true;
        } else {
            for (f, g) in [(e.faces[0], e.faces[1]), (e.faces[1], e.faces[0])] {
                let k = &mut fill[f as usize];
                if *k < 3 {
                    across[f as usize][*k as usize] = g;
                    *k += 1;
                }
            }
        }
    }
    drop(fill);
    let chart = crate::attributes::charts_of(&sides, original.triangles.len());
    drop(sides);
    let mut out = Attributes {
        normals: attributes.normals.as_ref().map(|_| Vec::new()),
        uv0: attributes.uv0.as_ref().map(|_| Vec::new()),
        uv1: attributes.uv1.as_ref().map(|_| Vec::new()),
        colors: attributes.colors.as_ref().map(|_| Vec::new()),
        face_material: attributes.face_material.as_ref().map(|_| Vec::new()),
        ..Attributes::default()
    };
    // The wedges made so far for each output vertex.
    let mut wedges_of: Vec<Vec<u32>> = vec![Vec::new(); simplified.positions.len()];
    let mut scratch = Attributes {
        normals: out.normals.as_ref().map(|_| Vec::new()),
        uv0: out.uv0.as_ref().map(|_| Vec::new()),
        uv1: out.uv1.as_ref().map(|_| Vec::new()),
        colors: out.colors.as_ref().map(|_| Vec::new()),
        ..Attributes::default()
    };
    let mut walk = Walk::default();
    // Vertices whose closest original triangle touches no seam: one wedge, found once, and the
    // original triangle it came from.
    let mut settled: Vec<(u32, u32)> = vec![(u32::MAX, u32::MAX); simplified.positions.len()];
    let mut checked = vec![false; simplified.positions.len()];
    for t in &simplified.triangles {
        let [a, b, c] = t.map(|v| simplified.positions[v as usize]);
        let centroid = (a + b + c) / 3.0;
        // The original triangle closest to the centroid: the material, and the chart of a
        // triangle whose corners fall in different charts (below).
        let mut at_centroid = None;
        let mut centroid_face =
            || *at_centroid.get_or_insert_with(|| grid.closest(centroid, |_| true).map(|(f, _)| f));
        if let Some(dst) = out.face_material.as_mut() {
            let m = attributes
                .face_material
                .as_ref()
                .map_or(0, |m| centroid_face().map_or(0, |f| m[f as usize]));
            dst.push(m);
        }
        // Each corner's point of the original: the closest on its side of the seams.
        let mut found = [(u32::MAX, [0.0; 3]); 3];
        let mut wedge = [u32::MAX; 3];
        for k in 0..3 {
            let v = t[k];
            let p = simplified.positions[v as usize];
            if !checked[v as usize] {
                checked[v as usize] = true;
                if let Some((f, bary)) = grid.closest(p, |_| true)
                    && original.triangles[f as usize]
                        .iter()
                        .all(|&u| !near_seam[u as usize])
                {
                    clear(&mut scratch);
                    interpolate(attributes, f, bary, &mut scratch);
                    append(&mut out, &scratch);
                    out.wedge_vertex.push(v);
                    settled[v as usize] = (out.wedge_vertex.len() as u32 - 1, f);
                }
            }
            let (w, f) = settled[v as usize];
            if w != u32::MAX {
                (wedge[k], found[k].0) = (w, f);
                continue;
            }
            let inside = p + (centroid - p) * 0.05;
            let start = grid.closest(inside, |_| true).map_or(0, |(f, _)| f);
            found[k] = walk.closest_on_side(original, &across, start, p.as_dvec3());
        }
        // A triangle whose corners lie in different charts straddles a seam (GNG3D-Q's
        // triangulation does not follow the seams; QEM's does): interpolating one chart's
        // values at one corner and another's at the next would smear the texture across the
        // atlas inside it. All its corners take the chart at its centroid instead, the
        // corners from elsewhere at their closest point of that chart (on its border), so the
        // seam runs along the output's edges. Share of surface samples whose UV is more than
        // 0.05 off the original's (docs/notes/attributes.md): spot at 300 vertices, GNG3D-Q
        // 27.8 -> 2.5 %, QEM (whose seam vertices sit slightly off the seam) 4.3 -> 0 %.
        let charts = found.map(|(f, _)| chart[f as usize]);
        if (charts[0] != charts[1] || charts[1] != charts[2])
            && let Some(own) = centroid_face().map(|f| chart[f as usize])
        {
            for k in 0..3 {
                if charts[k] != own {
                    let p = simplified.positions[t[k] as usize];
                    if let Some(hit) = grid.closest(p, |g| chart[g as usize] == own) {
                        (found[k], wedge[k]) = (hit, u32::MAX);
                    }
                }
            }
        }
        let mut corner = [0u32; 3];
        for k in 0..3 {
            if wedge[k] != u32::MAX {
                corner[k] = wedge[k];
                continue;
            }
            let v = t[k];
            let (f, bary) = found[k];
            clear(&mut scratch);
            interpolate(attributes, f, bary, &mut scratch);
            let same = wedges_of[v as usize]
                .iter()
                .copied()
                .find(|&w| close(&out, w as usize, &scratch));
            corner[k] = match same {
                Some(w) => w,
                None => {
                    append(&mut out, &scratch);
                    out.wedge_vertex.push(v);
                    let w = out.wedge_vertex.len() as u32 - 1;
                    wedges_of[v as usize].push(w);
                    w
                }
            };
        }
        out.corners.push(corner);
    }
    out
}

/// [`transfer_attributes`] for attributes without seams: one wedge per output vertex, with the
/// values at the closest point of the original.
fn transfer_without_seams(
    attributes: &Attributes,
    simplified: &TriMesh,
    grid: &FaceGrid,
) -> Attributes {
    let mut out = Attributes {
        wedge_vertex: (0..simplified.positions.len() as u32).collect(),
        corners: simplified.triangles.clone(),
        normals: attributes.normals.as_ref().map(|_| Vec::new()),
        uv0: attributes.uv0.as_ref().map(|_| Vec::new()),
        uv1: attributes.uv1.as_ref().map(|_| Vec::new()),
        colors: attributes.colors.as_ref().map(|_| Vec::new()),
        face_material: None,
    };
    for &p in &simplified.positions {
        let (f, bary) = grid.closest(p, |_| true).unwrap_or((0, [1.0, 0.0, 0.0]));
        interpolate(attributes, f, bary, &mut out);
    }
    out.face_material = attributes.face_material.as_ref().map(|m| {
        simplified
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| simplified.positions[v as usize]);
                grid.closest((a + b + c) / 3.0, |_| true)
                    .map_or(0, |(f, _)| m[f as usize])
            })
            .collect()
    });
    out
}

/// The scratch state of [`Walk::closest_on_side`].
#[derive(Default)]
struct Walk {
    seen: HashMap<u32, ()>,
    queue: Vec<u32>,
}

impl Walk {
    /// From original triangle `start`, the closest point to `p` among the triangles reached
    /// across non-seam edges (`across`) that are no farther from `p` than `start` (plus a hair):
    /// that set holds the closest point of `start`'s side, and every corner of that side reaches
    /// the same triangle, so they get the same values. At most 4,096 triangles; the triangle and
    /// the point's barycentric coordinates.
    fn closest_on_side(
        &mut self,
        mesh: &TriMesh,
        across: &[[u32; 3]],
        start: u32,
        p: DVec3,
    ) -> (u32, [f64; 3]) {
        self.seen.clear();
        self.queue.clear();
        self.queue.push(start);
        self.seen.insert(start, ());
        let dist = |f: u32| {
            let [a, b, c] = mesh.triangle_f64(f as usize);
            crate::geometry::closest_point_triangle(p, a, b, c).distance(p)
        };
        let d_start = dist(start);
        let [a, b, _] = mesh.triangle_f64(start as usize);
        let limit = d_start + 1e-3 * a.distance(b);
        let mut best = (d_start, start);
        let mut head = 0;
        while head < self.queue.len() && self.queue.len() < 4096 {
            let f = self.queue[head];
            head += 1;
            let d = if f == start { d_start } else { dist(f) };
            if (d, f) < best {
                best = (d, f);
            }
            if d > limit {
                continue;
            }
            for g in across[f as usize] {
                if g != u32::MAX && self.seen.insert(g, ()).is_none() {
                    self.queue.push(g);
                }
            }
        }
        let [a, b, c] = mesh.triangle_f64(best.1 as usize);
        let q = crate::geometry::closest_point_triangle(p, a, b, c);
        (best.1, barycentric(q, a, b, c))
    }
}

/// Empty every attribute array of `a`.
fn clear(a: &mut Attributes) {
    if let Some(v) = a.normals.as_mut() {
        v.clear();
    }
    if let Some(v) = a.uv0.as_mut() {
        v.clear();
    }
    if let Some(v) = a.uv1.as_mut() {
        v.clear();
    }
    if let Some(v) = a.colors.as_mut() {
        v.clear();
    }
}

/// Append the one set of values in `one` to `out`'s arrays.
fn append(out: &mut Attributes, one: &Attributes) {
    fn push<T: Copy>(dst: &mut Option<Vec<T>>, src: &Option<Vec<T>>) {
        if let (Some(d), Some(s)) = (dst.as_mut(), src.as_ref()) {
            d.extend_from_slice(s);
        }
    }
    push(&mut out.normals, &one.normals);
    push(&mut out.uv0, &one.uv0);
    push(&mut out.uv1, &one.uv1);
    push(&mut out.colors, &one.colors);
}

/// Whether wedge `w` of `out` holds the values of `one` (each component within 1e-5, relative
/// to its size when above 1).
fn close(out: &Attributes, w: usize, one: &Attributes) -> bool {
    fn near(a: &[f32], b: &[f32]) -> bool {
        a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 1e-5 * x.abs().max(y.abs()).max(1.0))
    }
    let n = out.normals.as_ref().zip(one.normals.as_ref());
    let u = out.uv0.as_ref().zip(one.uv0.as_ref());
    let u1 = out.uv1.as_ref().zip(one.uv1.as_ref());
    let c = out.colors.as_ref().zip(one.colors.as_ref());
    n.is_none_or(|(o, s)| near(&o[w].to_array(), &s[0].to_array()))
        && u.is_none_or(|(o, s)| near(&o[w].to_array(), &s[0].to_array()))
        && u1.is_none_or(|(o, s)| near(&o[w].to_array(), &s[0].to_array()))
        && c.is_none_or(|(o, s)| near(&o[w].to_array(), &s[0].to_array()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_transfer_gives_the_values_back() {
        let (sphere, uv) = crate::procedural::textured_sphere(12, 24);
        let back = transfer_attributes(&sphere, &uv, &sphere);
        back.validate(&sphere).unwrap();
        // Every corner's values equal the original corner's.
        for (f, (c, d)) in uv.corners.iter().zip(&back.corners).enumerate() {
            for k in 0..3 {
                let a = uv.uv0.as_ref().unwrap()[c[k] as usize];
                let b = back.uv0.as_ref().unwrap()[d[k] as usize];
                assert!((a - b).length() < 1e-5, "face {f} corner {k}: {a} vs {b}");
                let na = uv.normals.as_ref().unwrap()[c[k] as usize];
                let nb = back.normals.as_ref().unwrap()[d[k] as usize];
                assert!(na.dot(nb) > 0.9999);
            }
        }
        assert_eq!(back.seam_edges(&sphere), uv.seam_edges(&sphere));
    }

    #[test]
    fn a_triangle_across_a_seam_takes_one_chart() {
        // A flat square whose left half (x <= 0.5) is mapped to u = x and right half to
        // u = x + 10: a seam along x = 0.5, every corner its own wedge.
        let grid = crate::procedural::unit_square_grid(4);
        let mut attributes = Attributes::default();
        let mut uv = Vec::new();
        for t in &grid.triangles {
            let right = t.iter().any(|&v| grid.positions[v as usize].x > 0.5 + 1e-6);
            let mut c = [0; 3];
            for k in 0..3 {
                let p = grid.positions[t[k] as usize];
                c[k] = uv.len() as u32;
                uv.push(Vec2::new(p.x + if right { 10.0 } else { 0.0 }, p.y));
                attributes.wedge_vertex.push(t[k]);
            }
            attributes.corners.push(c);
        }
        attributes.uv0 = Some(uv);
        attributes.validate(&grid).unwrap();
        assert_eq!(attributes.seam_edges(&grid).len(), 4);
        // Two output triangles that straddle the seam: the first mostly left (centroid
        // x = 0.23), the second mostly right (x = 0.57).
        let simplified = TriMesh::new(
            vec![
                Vec3::ZERO,
                Vec3::new(0.7, 0.0, 0.0),
                Vec3::Y,
                Vec3::new(1.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [1, 3, 2]],
        );
        let out = transfer_attributes(&grid, &attributes, &simplified);
        out.validate(&simplified).unwrap();
        let uv_at = |f: usize, k: usize| out.uv0.as_ref().unwrap()[out.corners[f][k] as usize];
        // Every corner of a triangle in its centroid's chart; a corner beyond the seam at the
        // closest point of that chart, on the seam.
        for k in 0..3 {
            assert!(
                uv_at(0, k).x < 1.0,
                "left triangle, corner {k}: {}",
                uv_at(0, k)
            );
            assert!(
                uv_at(1, k).x >= 10.0,
                "right triangle, corner {k}: {}",
                uv_at(1, k)
            );
        }
        assert!((uv_at(0, 1) - Vec2::new(0.5, 0.0)).length() < 1e-5);
        assert!((uv_at(1, 2) - Vec2::new(10.5, 1.0)).length() < 1e-5);
        // Corners on their own chart keep their own values.
        assert!((uv_at(0, 0) - Vec2::ZERO).length() < 1e-5);
        assert!((uv_at(1, 1) - Vec2::new(11.0, 1.0)).length() < 1e-5);
        // The shared vertices 1 and 2 have one wedge per side: the seam is the edge 1-2.
        assert_eq!(out.seam_edges(&simplified), vec![[1, 2]]);
    }

    #[test]
    fn a_fan_of_slivers_gets_a_grid_of_bounded_size() {
        // 20,000 slivers from a hub to a circle: cells sized by their area would hold each
        // sliver in hundreds of cells.
        let fan = crate::procedural::fan(20_000);
        let grid = FaceGrid::new(&fan);
        let entries: usize = grid.cells.values().map(Vec::len).sum();
        assert!(
            entries <= 16 * fan.face_count() + 1_000_000,
            "{entries} entries"
        );
        // A point far from the fan: the grid gives up its shells and looks at every sliver.
        let far = grid.closest(Vec3::new(0.0, 0.0, 50.0), |_| true).unwrap();
        assert!(far.0 < fan.face_count() as u32);
        let p = fan.positions[5] + Vec3::Z * 0.01;
        let (f, _) = grid.closest(p, |_| true).unwrap();
        let [a, b, c] = fan.triangle_f64(f as usize);
        let d =
            crate::geometry::closest_point_triangle(p.as_dvec3(), a, b, c).distance(p.as_dvec3());
        assert!((d - 0.01).abs() < 1e-6, "{d}");
    }

    #[test]
    fn barycentric_of_corners_and_degenerate() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert_eq!(barycentric(b, a, b, c), [0.0, 1.0, 0.0]);
        let w = barycentric(DVec3::new(0.25, 0.25, 0.0), a, b, c);
        assert!((w[0] - 0.5).abs() < 1e-12 && (w[1] - 0.25).abs() < 1e-12);
        assert_eq!(barycentric(b, a, a, a), [1.0, 0.0, 0.0]);
    }

    #[test]
    fn grid_closest_matches_brute_force() {
        let m = crate::procedural::icosphere(3);
        let grid = FaceGrid::new(&m);
        for i in 0..200 {
            let t = i as f32 * 0.37;
            let p = Vec3::new(t.sin() * 1.3, (t * 1.7).cos() * 0.8, (t * 0.3).sin() * 1.1);
            let (f, _) = grid.closest(p, |_| true).unwrap();
            let pd = p.as_dvec3();
            let brute = (0..m.face_count())
                .map(|g| {
                    let [a, b, c] = m.triangle_f64(g);
                    crate::geometry::closest_point_triangle(pd, a, b, c).distance_squared(pd)
                })
                .fold(f64::INFINITY, f64::min);
            let [a, b, c] = m.triangle_f64(f as usize);
            let got = crate::geometry::closest_point_triangle(pd, a, b, c).distance_squared(pd);
            assert!((got - brute).abs() <= 1e-12, "{got} vs {brute}");
        }
    }
}

//! Cleaning: welding exact duplicate positions, dropping degenerate/duplicate faces and
//! unreferenced vertices. [`prepare`] does all of it and is what algorithms get by default.

use crate::{Model, TriMesh};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Counts of faces removed by [`drop_degenerate_and_duplicate_faces`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DroppedFaces {
    /// Faces with a repeated vertex index.
    pub degenerate: usize,
    /// Faces whose vertex set equals that of an earlier face (any rotation or orientation).
    pub duplicate: usize,
}

/// What [`prepare`] changed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CleanReport {
    /// Vertex records before cleaning.
    pub input_vertices: usize,
    /// Faces before cleaning.
    pub input_faces: usize,
    /// Vertices merged into another vertex at the identical position.
    pub welded_vertices: usize,
    /// Faces dropped because two corners were the same vertex (after welding).
    pub degenerate_faces: usize,
    /// Faces dropped because they repeated an earlier face's vertex set (after welding).
    pub duplicate_faces: usize,
    /// Vertices dropped because no face used them.
    pub unreferenced_vertices: usize,
    /// Vertices after cleaning.
    pub vertices: usize,
    /// Faces after cleaning.
    pub faces: usize,
}

/// Bit pattern of a position with -0.0 folded into +0.0, so equal coordinates compare equal.
#[inline]
fn position_key(p: Vec3) -> [u32; 3] {
    [
        (p.x + 0.0).to_bits(),
        (p.y + 0.0).to_bits(),
        (p.z + 0.0).to_bits(),
    ]
}

/// Merge vertices with exactly equal positions where the surface continues across them, and
/// remap the faces; returns the welded mesh and the number of vertices merged away.
///
/// Two copies of a position are merged when they are the ends of a seam: an edge of one and an
/// edge of the other lie on the same two positions and are the only two open edges there (a
/// triangle soup, an STL file, the UV or normal seams of an OBJ), or when they are corners of
/// one face (which then collapses; see [`drop_degenerate_and_duplicate_faces`]). Copies that
/// merely touch (two sheets meeting at a point, a closed model whose surface pinches against
/// itself) stay apart, so a manifold input stays manifold; so do open edges where three or more
/// meet (merging them would make a non-manifold edge). Faces that repeat another face's
/// positions are left out of the seam count. The first index of each merged set is kept, in
/// order. O(V log V + F log F).
pub fn weld_exact(mesh: &TriMesh) -> (TriMesh, usize) {
    let (welded, _) = weld_exact_map(mesh);
    let merged = mesh.positions.len() - welded.positions.len();
    (welded, merged)
}

/// [`weld_exact`], returning for each input vertex its index in the welded mesh instead of the
/// count (so per-vertex data, e.g. [`Attributes`](crate::attributes::Attributes), can follow).
pub fn weld_exact_map(mesh: &TriMesh) -> (TriMesh, Vec<u32>) {
    let n = mesh.positions.len();
    // Step 1: each vertex's position group (the smallest index at its position).
    let mut order: Vec<u32> = (0..n as u32).collect();
    let keys: Vec<[u32; 3]> = mesh.positions.iter().map(|&p| position_key(p)).collect();
    order.sort_unstable_by_key(|&i| (keys[i as usize], i));
    let mut group: Vec<u32> = (0..n as u32).collect();
    let mut shared = false;
    let mut group_start = 0;
    for k in 1..=n {
        if k == n || keys[order[k] as usize] != keys[order[group_start] as usize] {
            let rep = order[group_start];
            for &i in &order[group_start..k] {
                group[i as usize] = rep;
            }
            shared |= k - group_start > 1;
            group_start = k;
        }
    }
    let mut sets = crate::topology::UnionFind::new(n);
    if shared {
        let valid = |v: u32| (v as usize) < n;
        // Step 2: corners of one face at one position.
        for t in &mesh.triangles {
            if !t.iter().all(|&v| valid(v)) {
                continue;
            }
            for (i, j) in [(0, 1), (1, 2), (0, 2)] {
                if group[t[i] as usize] == group[t[j] as usize] {
                    sets.union(t[i], t[j]);
                }
            }
        }
        // Step 3: open edges (one face, by index) of the faces that do not repeat an earlier
        // face's positions, keyed by their positions.
        let mut seen_faces: std::collections::HashSet<[u32; 3]> = Default::default();
        let mut edges: Vec<([u32; 2], [u32; 2])> = Vec::with_capacity(3 * mesh.triangles.len());
        for t in &mesh.triangles {
            if !t.iter().all(|&v| valid(v)) {
                continue;
            }
            let mut g = t.map(|v| group[v as usize]);
            g.sort_unstable();
            if g[0] == g[1] || g[1] == g[2] || !seen_faces.insert(g) {
                continue;
            }
            for i in 0..3 {
                let (u, v) = (t[i], t[(i + 1) % 3]);
                edges.push(([u.min(v), u.max(v)], [0, 0]));
            }
        }
        edges.sort_unstable();
        let mut open: Vec<([u32; 2], [u32; 2])> = Vec::new();
        for run in edges.chunk_by(|x, y| x.0 == y.0) {
            if let [([u, v], _)] = *run {
                let (gu, gv) = (group[u as usize], group[v as usize]);
                let key = if gu <= gv { [gu, gv] } else { [gv, gu] };
                open.push((key, [u, v]));
            }
        }
        // Step 4: a position pair with exactly two open edges is a seam: merge their ends.
        open.sort_unstable();
        for run in open.chunk_by(|x, y| x.0 == y.0) {
            if let [(_, [a, b]), (_, [c, d])] = *run {
                let (c, d) = if group[a as usize] == group[c as usize] {
                    (c, d)
                } else {
                    (d, c)
                };
                sets.union(a, c);
                sets.union(b, d);
            }
        }
    }
    // Step 5: the smallest index of each merged set represents it, in the original order.
    let mut smallest = vec![u32::MAX; n];
    for i in 0..n as u32 {
        let root = sets.find(i) as usize;
        smallest[root] = smallest[root].min(i);
    }
    let mut new_index = vec![u32::MAX; n];
    let mut positions = Vec::with_capacity(n);
    for i in 0..n {
        if smallest[sets.find(i as u32) as usize] == i as u32 {
            new_index[i] = positions.len() as u32;
            positions.push(mesh.positions[i]);
        }
    }
    let map: Vec<u32> = (0..n as u32)
        .map(|v| new_index[smallest[sets.find(v) as usize] as usize])
        .collect();
    let triangles = mesh
        .triangles
        .iter()
        .map(|t| t.map(|v| if (v as usize) < n { map[v as usize] } else { v }))
        .collect();
    (TriMesh::new(positions, triangles), map)
}

/// Drop vertices that no face references, keeping the order of the rest and remapping faces.
pub fn remove_unreferenced(mesh: &TriMesh) -> TriMesh {
    let mut triangles = mesh.triangles.clone();
    let kept = compact_vertex_indices(&mut triangles, mesh.positions.len());
    let positions = kept.iter().map(|&i| mesh.positions[i as usize]).collect();
    TriMesh::new(positions, triangles)
}

/// Renumber the vertices that `triangles` reference (indices below `vertex_count`) to `0..k`,
/// keeping their order, and rewrite `triangles` in place; returns the old index of each new
/// vertex, so the caller gathers whatever per-vertex data it keeps (e.g. positions). O(F + V).
/// The one implementation behind [`remove_unreferenced`] (and QEM's output step).
pub fn compact_vertex_indices(triangles: &mut [[u32; 3]], vertex_count: usize) -> Vec<u32> {
    let mut new_index = vec![u32::MAX; vertex_count];
    for t in triangles.iter() {
        for &v in t {
            new_index[v as usize] = 0;
        }
    }
    let mut kept = Vec::new();
    for (i, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = kept.len() as u32;
            kept.push(i as u32);
        }
    }
    for t in triangles.iter_mut() {
        for v in t.iter_mut() {
            *v = new_index[*v as usize];
        }
    }
    kept
}

/// Drop faces with a repeated vertex index and faces whose vertex set equals an earlier face's
/// (in any rotation or orientation; the first one in file order is kept). Vertices are
/// untouched. See [`drop_degenerate_and_duplicate_faces_in_place`] for the cost.
pub fn drop_degenerate_and_duplicate_faces(mesh: &TriMesh) -> (TriMesh, DroppedFaces) {
    let mut out = mesh.clone();
    let dropped = drop_degenerate_and_duplicate_faces_in_place(&mut out);
    (out, dropped)
}

/// [`drop_degenerate_and_duplicate_faces`] on `mesh` itself, without copying it. Faces are
/// grouped by their smallest vertex with a counting sort and only those small groups are
/// sorted, so this is O(F + V) apart from the per-group sorts.
pub fn drop_degenerate_and_duplicate_faces_in_place(mesh: &mut TriMesh) -> DroppedFaces {
    drop_faces_with_mask(mesh).0
}

/// [`drop_degenerate_and_duplicate_faces_in_place`], also returning which of the input faces
/// were kept (`None` when all were), so per-face data (attributes) can follow.
pub fn drop_faces_with_mask(mesh: &mut TriMesh) -> (DroppedFaces, Option<Vec<bool>>) {
    let mut dropped = DroppedFaces::default();
    let n = mesh.index_bound();
    let is_degenerate = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    // group_start[v]..group_start[v + 1]: non-degenerate faces whose smallest vertex is v.
    let mut group_start = vec![0u32; n + 1];
    for t in &mesh.triangles {
        if !is_degenerate(t) {
            group_start[*t.iter().min().unwrap_or(&0) as usize + 1] += 1;
        }
    }
    for v in 0..n {
        group_start[v + 1] += group_start[v];
    }
    // Each face packed as (middle << 64) | (largest << 32) | face: sorting a group orders it
    // by vertex set, and by file order within equal sets.
    let mut packed = vec![0u128; group_start[n] as usize];
    let mut fill: Vec<u32> = group_start[..n].to_vec();
    for (f, t) in mesh.triangles.iter().enumerate() {
        if is_degenerate(t) {
            dropped.degenerate += 1;
            continue;
        }
        let mut k = *t;
        k.sort_unstable();
        let slot = &mut fill[k[0] as usize];
        packed[*slot as usize] = ((k[1] as u128) << 64) | ((k[2] as u128) << 32) | f as u128;
        *slot += 1;
    }
    drop(fill);
    if dropped.degenerate == 0 && packed.is_empty() {
        return (dropped, None);
    }
    let mut keep = vec![true; mesh.triangles.len()];
    for v in 0..n {
        let group = &mut packed[group_start[v] as usize..group_start[v + 1] as usize];
        if group.len() < 2 {
            continue;
        }
        group.sort_unstable();
        for w in group.windows(2) {
            if w[0] >> 32 == w[1] >> 32 {
                keep[w[1] as u32 as usize] = false;
                dropped.duplicate += 1;
            }
        }
    }
    if dropped.degenerate + dropped.duplicate > 0 {
        for (k, t) in keep.iter_mut().zip(&mesh.triangles) {
            *k &= !is_degenerate(t);
        }
        let mut faces = keep.iter();
        mesh.triangles.retain(|_| *faces.next().unwrap_or(&false));
        return (dropped, Some(keep));
    }
    (dropped, None)
}

/// Weld exact duplicates, drop degenerate and duplicate faces, remove unreferenced vertices:
/// the cleaned model (materials and origin kept) and what changed. The attributes, when there
/// are any, follow: the wedges follow the weld and the renumbering, the corners and materials
/// follow the dropped faces, and wedges no corner uses (or that repeat another wedge of their
/// vertex) are dropped.
pub fn prepare(model: &Model) -> (Model, CleanReport) {
    let mesh = &model.mesh;
    let (mut welded, weld_map) = weld_exact_map(mesh);
    let welded_vertices = mesh.positions.len() - welded.positions.len();
    let mut attributes = model.attributes.clone();
    if let Some(a) = &mut attributes {
        a.remap_vertices(&weld_map);
    }
    let (dropped, mask) = drop_faces_with_mask(&mut welded);
    if let (Some(mask), Some(a)) = (mask, &mut attributes) {
        *a = a.select_faces(&mask);
    }
    let before = welded.positions.len();
    let mut triangles = welded.triangles;
    let kept = compact_vertex_indices(&mut triangles, before);
    let positions: Vec<Vec3> = kept.iter().map(|&i| welded.positions[i as usize]).collect();
    let out = TriMesh::new(positions, triangles);
    if let Some(a) = &mut attributes {
        let mut map = vec![u32::MAX; before];
        for (new, &old) in kept.iter().enumerate() {
            map[old as usize] = new as u32;
        }
        // Wedges of dropped vertices are unused by any corner: compact drops them first.
        a.compact();
        a.remap_vertices(&map);
    }
    let report = CleanReport {
        input_vertices: mesh.positions.len(),
        input_faces: mesh.triangles.len(),
        welded_vertices,
        degenerate_faces: dropped.degenerate,
        duplicate_faces: dropped.duplicate,
        unreferenced_vertices: before - out.positions.len(),
        vertices: out.positions.len(),
        faces: out.triangles.len(),
    };
    (model.with_mesh(out, attributes), report)
}

#[cfg(test)]
mod tests {
    use super::*;
    /// The previous whole-list sort implementation, kept as an independent check.
    /// Drop faces with a repeated vertex index and faces whose vertex set equals an earlier face's
    /// (in any rotation or orientation; the first one in file order is kept). Vertices are
    /// untouched. O(F log F).
    fn reference_drop_faces(mesh: &TriMesh) -> (TriMesh, DroppedFaces) {
        let mut dropped = DroppedFaces::default();
        let mut keep = vec![true; mesh.triangles.len()];
        let mut keyed: Vec<([u32; 3], u32)> = Vec::with_capacity(mesh.triangles.len());
        for (f, t) in mesh.triangles.iter().enumerate() {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                keep[f] = false;
                dropped.degenerate += 1;
            } else {
                let mut k = *t;
                k.sort_unstable();
                keyed.push((k, f as u32));
            }
        }
        keyed.sort_unstable();
        for w in keyed.windows(2) {
            if w[0].0 == w[1].0 {
                keep[w[1].1 as usize] = false;
                dropped.duplicate += 1;
            }
        }
        if dropped.degenerate + dropped.duplicate == 0 {
            return (mesh.clone(), dropped);
        }
        let triangles = mesh
            .triangles
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(t, _)| *t)
            .collect();
        (TriMesh::new(mesh.positions.clone(), triangles), dropped)
    }

    #[test]
    fn face_dropping_matches_the_sort_based_reference() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        for case in 0..300 {
            let vertices = rng.random_range(3..30u32);
            let faces = rng.random_range(0..120);
            let triangles = (0..faces)
                .map(|_| std::array::from_fn(|_| rng.random_range(0..vertices)))
                .collect();
            let m = TriMesh::new(vec![Vec3::ZERO; vertices as usize], triangles);
            let (a, da) = drop_degenerate_and_duplicate_faces(&m);
            let (b, db) = reference_drop_faces(&m);
            assert_eq!((a.triangles, da), (b.triangles, db), "case {case}");
        }
    }
    use crate::procedural::icosphere;

    /// An icosphere whose faces are given their own copies of the corner positions.
    fn unwelded(mesh: &TriMesh) -> TriMesh {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for f in 0..mesh.triangles.len() {
            let base = positions.len() as u32;
            positions.extend_from_slice(&mesh.triangle(f));
            triangles.push([base, base + 1, base + 2]);
        }
        TriMesh::new(positions, triangles)
    }

    #[test]
    fn weld_restores_shared_vertices() {
        let sphere = icosphere(2);
        let soup = unwelded(&sphere);
        let (welded, merged) = weld_exact(&soup);
        assert_eq!(welded.positions.len(), sphere.positions.len());
        assert_eq!(merged, soup.positions.len() - sphere.positions.len());
        // Same geometry, face by face.
        for f in 0..sphere.triangles.len() {
            assert_eq!(welded.triangle(f), sphere.triangle(f));
        }
    }

    /// Two closed spheres touching at one point (a pinch): as an indexed mesh with the point
    /// twice, and as a triangle soup. The weld restores each sphere but keeps the two copies of
    /// the touching point apart, so the result is two manifold spheres, not one non-manifold
    /// vertex; three sheets on one edge are not zipped into a non-manifold edge either.
    #[test]
    fn weld_keeps_touching_points_apart() {
        let sphere = icosphere(1);
        // The second sphere's vertex 0 lands on the first's vertex 0's mirror point.
        let p0 = sphere.positions[0];
        let n = sphere.positions.len() as u32;
        let mut positions = sphere.positions.clone();
        positions.extend(sphere.positions.iter().map(|&p| 2.0 * p0 - p));
        let mut triangles = sphere.triangles.clone();
        // Mirrored: flip the orientation back outward.
        triangles.extend(
            sphere
                .triangles
                .iter()
                .map(|t| [t[0] + n, t[2] + n, t[1] + n]),
        );
        let pinched = TriMesh::new(positions, triangles);
        assert_eq!(pinched.positions[0], pinched.positions[n as usize]);
        for input in [pinched.clone(), unwelded(&pinched)] {
            let (welded, _) = weld_exact(&input);
            assert_eq!(welded.positions.len(), 2 * sphere.positions.len());
            let r = crate::topology::analyze(&welded);
            assert!(r.manifold && r.closed && r.components == 2, "{r:?}");
        }
        // Three triangles on one edge (a soup): the edge stays open rather than non-manifold.
        let fin = |z: f32, y: f32| [Vec3::ZERO, Vec3::X, Vec3::new(0.5, y, z)];
        let soup: Vec<Vec3> = [fin(0.0, 1.0), fin(0.0, -1.0), fin(1.0, 0.0)].concat();
        let (welded, merged) =
            weld_exact(&TriMesh::new(soup, vec![[0, 1, 2], [4, 3, 5], [6, 7, 8]]));
        assert_eq!(merged, 0, "{:?}", welded.triangles);
        // Two of them alone are a seam, and are zipped.
        let soup: Vec<Vec3> = [fin(0.0, 1.0), fin(0.0, -1.0)].concat();
        let (welded, merged) = weld_exact(&TriMesh::new(soup, vec![[0, 1, 2], [4, 3, 5]]));
        assert_eq!(merged, 2);
        let r = crate::topology::analyze(&welded);
        assert!(r.manifold && r.boundary_edges == 4, "{r:?}");
    }

    #[test]
    fn weld_treats_negative_zero_as_zero() {
        let m = TriMesh::new(
            vec![Vec3::new(0.0, 1.0, 2.0), Vec3::new(-0.0, 1.0, 2.0), Vec3::X],
            vec![[0, 1, 2]],
        );
        let (w, merged) = weld_exact(&m);
        assert_eq!(merged, 1);
        assert_eq!(w.triangles, vec![[0, 0, 1]]);
    }

    #[test]
    fn drops_degenerate_and_rotated_or_flipped_duplicates() {
        let m = TriMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            vec![[0, 1, 2], [1, 2, 0], [2, 1, 0], [0, 0, 3], [0, 1, 3]],
        );
        let (out, d) = drop_degenerate_and_duplicate_faces(&m);
        assert_eq!(
            d,
            DroppedFaces {
                degenerate: 1,
                duplicate: 2
            }
        );
        assert_eq!(out.triangles, vec![[0, 1, 2], [0, 1, 3]]);
    }

    #[test]
    fn remove_unreferenced_keeps_order() {
        let m = TriMesh::new(
            vec![
                Vec3::splat(9.0),
                Vec3::ZERO,
                Vec3::X,
                Vec3::splat(7.0),
                Vec3::Y,
            ],
            vec![[1, 2, 4]],
        );
        let out = remove_unreferenced(&m);
        assert_eq!(out.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(out.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn compact_vertex_indices_keeps_order_and_reports_old_indices() {
        let mut tris = vec![[4, 1, 6], [6, 1, 3]];
        let kept = compact_vertex_indices(&mut tris, 8);
        assert_eq!(kept, vec![1, 3, 4, 6]);
        assert_eq!(tris, vec![[2, 0, 3], [3, 0, 1]]);
    }

    #[test]
    fn prepare_reports_every_step() {
        let mut soup = unwelded(&icosphere(1));
        soup.positions.push(Vec3::splat(5.0));
        let dup = soup.triangles[0];
        soup.triangles.push([dup[2], dup[0], dup[1]]);
        let (out, r) = prepare(&Model::from(soup));
        assert_eq!(r.input_faces, 81);
        assert_eq!(r.duplicate_faces, 1);
        assert_eq!(r.degenerate_faces, 0);
        assert_eq!(r.unreferenced_vertices, 1);
        assert_eq!(r.vertices, 42);
        assert_eq!(r.faces, 80);
        assert_eq!(r.welded_vertices, 240 - 42);
        assert_eq!(out.mesh.positions.len(), 42);
    }
}

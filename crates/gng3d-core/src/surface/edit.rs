//! The output mesh's fans and edges as the passes that edit it see them: the faces around each
//! vertex as editable lists, the faces on an edge, a face's orientation along an edge, the flip
//! of an edge, and the open border's edges.

/// The faces around each of `n` vertices, in face order, as lists a pass can edit (flips
/// change them as they go); shared by every pass that walks fans.
pub(crate) fn fans(triangles: &[[u32; 3]], n: usize) -> Vec<Vec<u32>> {
    mesh::topology::VertexFaces::new(triangles, n).to_lists()
}

/// The faces on edge `a b`, found in the smaller fan of `a` and `b` (a hub of thousands of
/// faces made every edge at it a scan of its whole fan): how many there are, and the last of
/// them other than `not` that runs `b → a` in that fan's order (the face across the edge from
/// one running `a → b`; the only one when the edge has two faces, which every caller checks).
pub(crate) fn faces_on_edge(
    fan: &[Vec<u32>],
    triangles: &[[u32; 3]],
    a: u32,
    b: u32,
    not: u32,
) -> (usize, Option<u32>) {
    let mut across = None;
    let mut on_edge = 0;
    let (from, to) = if fan[b as usize].len() < fan[a as usize].len() {
        (b, a)
    } else {
        (a, b)
    };
    for &g in &fan[from as usize] {
        let t = triangles[g as usize];
        if t.contains(&to) {
            on_edge += 1;
            if g != not && oriented(t, b, a).is_some() {
                across = Some(g);
            }
        }
    }
    (on_edge, across)
}

/// `(a, b, c)` when face `t` runs `a → b` (its third corner `c`).
pub(crate) fn oriented(t: [u32; 3], a: u32, b: u32) -> Option<(u32, u32, u32)> {
    (0..3)
        .find(|&i| t[i] == a && t[(i + 1) % 3] == b)
        .map(|i| (a, b, t[(i + 2) % 3]))
}

/// Whether some face has the edge `c d` (a flip to `c d` would then duplicate it), found in
/// the smaller of their fans.
pub(crate) fn has_edge(fan: &[Vec<u32>], triangles: &[[u32; 3]], c: u32, d: u32) -> bool {
    let (from, to) = if fan[d as usize].len() < fan[c as usize].len() {
        (d, c)
    } else {
        (c, d)
    };
    fan[from as usize]
        .iter()
        .any(|&g| triangles[g as usize].contains(&to))
}

/// Flips edge `a b` of faces `f1 = (a b c)` and `f2 = (b a d)` to `c d`: `f1` becomes
/// `(c a d)` and `f2` `(d b c)`; in the fans `a` leaves `f2`, `b` leaves `f1`, `c` joins `f2`
/// and `d` joins `f1`.
pub(crate) fn apply_flip(
    triangles: &mut [[u32; 3]],
    fan: &mut [Vec<u32>],
    [f1, f2]: [u32; 2],
    [a, b, c, d]: [u32; 4],
) {
    triangles[f1 as usize] = [c, a, d];
    triangles[f2 as usize] = [d, b, c];
    fan[a as usize].retain(|&g| g != f2);
    fan[b as usize].retain(|&g| g != f1);
    fan[c as usize].push(f2);
    fan[d as usize].push(f1);
}

/// The other ends of each output vertex's boundary edges (edges with one face).
pub(crate) fn output_boundary(triangles: &[[u32; 3]], n: usize) -> Vec<Vec<u32>> {
    let mut half: rustc_hash::FxHashSet<(u32, u32)> = Default::default();
    half.reserve(3 * triangles.len());
    for t in triangles {
        for k in 0..3 {
            half.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let mut out = vec![Vec::new(); n];
    for t in triangles {
        for k in 0..3 {
            let (u, w) = (t[k], t[(k + 1) % 3]);
            if !half.contains(&(w, u)) {
                out[u as usize].push(w);
                out[w as usize].push(u);
            }
        }
    }
    out
}

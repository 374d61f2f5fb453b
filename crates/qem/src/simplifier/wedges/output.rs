//! The output of an attribute run: the engine's live faces as a mesh in model units, each
//! corner with its vertex's carried values on its side (or its own input wedge where the vertex
//! was never merged), folds in texture space undone, the wedges compacted.

use super::WedgeValues;
use super::sides::mark_side1;
use super::untangle::{untangle_uv, uv_area};
use crate::simplifier::prepare::Frame;
use crate::simplifier::seams::Seams;
use crate::simplifier::triangle::DEAD;
use crate::simplifier::vertex::Vertex;
use glam::{Vec2, Vec3, Vec4};
use mesh::TriMesh;
use mesh::attributes::Attributes;

/// What the output reads of the engine once the contractions are done (borrowed from it).
pub(in crate::simplifier) struct Contracted<'a> {
    /// The vertex records.
    pub(in crate::simplifier) vx: &'a [Vertex],
    /// The faces ([`DEAD`] in the first slot once removed).
    pub(in crate::simplifier) faces: &'a [[u32; 3]],
    /// The face lists that the records point into.
    pub(in crate::simplifier) refs: &'a [u32],
    /// Faces not yet removed.
    pub(in crate::simplifier) live_faces: usize,
}

/// The engine's result `e`, with its carried `values` and its `seams`, as a mesh in model units
/// with its attributes: the live faces less duplicates (`mesh::clean`), each corner with its
/// vertex's values on its side, or its own input wedge where the vertex was never merged;
/// materials per face. `face_origin[f]` is the input face of engine face `f` (same corner
/// order); `attributes` are the input's.
pub(in crate::simplifier) fn output(
    e: Contracted,
    values: &WedgeValues,
    seams: &Seams,
    frame: &Frame,
    attributes: &Attributes,
    face_origin: &[u32],
) -> (TriMesh, Attributes) {
    // 1. The live faces and their engine indices, degenerate and duplicate faces dropped.
    let mut face_id = Vec::with_capacity(e.live_faces);
    let mut triangles = Vec::with_capacity(e.live_faces);
    for (f, t) in e.faces.iter().enumerate() {
        if t[0] != DEAD {
            face_id.push(f as u32);
            triangles.push(*t);
        }
    }
    let mut out = TriMesh::new(Vec::new(), triangles);
    if let (_, Some(keep)) = mesh::clean::drop_faces_with_mask(&mut out) {
        let mut k = keep.iter();
        face_id.retain(|_| *k.next().unwrap_or(&false));
    }

    // 2. Side 1 corners of the merged seam vertices (bit k of the engine face's entry).
    let mut side1 = vec![0u8; e.faces.len()];
    let (mut fan, mut reached, mut stack) = (Vec::new(), Vec::new(), Vec::new());
    for v in 0..e.vx.len() {
        if !(values.merged[v] && seams.seam[v] && e.vx[v].alive) {
            continue;
        }
        fan.clear();
        fan.extend(
            e.refs[e.vx[v].list()]
                .iter()
                .copied()
                .filter(|&f| e.faces[f as usize][0] != DEAD),
        );
        let [n0, n1] = seams.along[v];
        let faces = |f: u32| e.faces[f as usize];
        let vn = [v as u32, n0, n1];
        mark_side1(&fan, faces, vn, &mut reached, &mut stack, |f, k| {
            side1[f as usize] |= 1 << k;
        });
    }

    // 3. One output wedge per (vertex, side) of the merged vertices and per input wedge of the
    // others, numbered in order of first use; `slot_of[w]`: the row of output wedge `w`
    // (`u32::MAX` for an input wedge).
    let layout = values.input.layout;
    let s = layout.stride;
    // Per row, its output wedge (only a seam vertex has side 1 corners, so no two merged
    // (vertex, side) pairs share a row).
    let mut row_wedge = vec![u32::MAX; values.rows()];
    let mut input_wedge = vec![u32::MAX; attributes.wedge_count()];
    let mut wedge_vertex = Vec::new();
    let mut slot_of = Vec::new();
    let mut wedge_values: Vec<f32> = Vec::new();
    let mut corners = Vec::with_capacity(face_id.len());
    for (t, &f) in out.triangles.iter().zip(&face_id) {
        let mut c = [0u32; 3];
        for k in 0..3 {
            let v = t[k] as usize;
            let input = values.corners[f as usize][k] as usize;
            let (id, slot) = if values.merged[v] {
                let row = values.row(v, usize::from(side1[f as usize] >> k & 1));
                debug_assert_ne!(row, values.zero_row as usize, "side 1 of a non-seam vertex");
                (&mut row_wedge[row], row as u32)
            } else {
                (&mut input_wedge[input], u32::MAX)
            };
            if *id == u32::MAX {
                *id = wedge_vertex.len() as u32;
                wedge_vertex.push(t[k]);
                slot_of.push(slot);
                let at = wedge_values.len();
                wedge_values.resize(at + s, 0.0);
                let out = &mut wedge_values[at..];
                match slot {
                    u32::MAX => out.copy_from_slice(values.input.wedge(input)),
                    slot => values.values_at(slot as usize, e.vx[v].p, out),
                }
            }
            c[k] = *id;
        }
        corners.push(c);
    }
    // A fitted value can fold a small triangle over in texture space where the interpolated
    // ones do not (fandisk atlas at 20 %: 19 of 2,588 triangles UV-flipped with fitted values
    // only, 0 with interpolated ones): the merged corners of such a triangle take their
    // interpolated values.
    for at in [layout.uv0, layout.uv1].into_iter().flatten() {
        let uv = |w: &[f32], c: u32| Vec2::from_slice(&w[c as usize * s + at..][..2]);
        let lerp = |c: u32| match slot_of[c as usize] {
            u32::MAX => uv(&wedge_values, c),
            slot => Vec2::from_slice(&values.lerp[slot as usize * s + at..][..2]),
        };
        let area = |[a, b, c]: [Vec2; 3]| (b - a).perp_dot(c - a);
        let mut fold: Vec<u32> = Vec::new();
        for c in &corners {
            if area(c.map(|w| uv(&wedge_values, w))) * area(c.map(lerp)) < 0.0 {
                fold.extend(c.iter().filter(|&&w| slot_of[w as usize] != u32::MAX));
            }
        }
        for w in fold {
            let slot = slot_of[w as usize] as usize;
            let from = layout.fit_from();
            wedge_values[w as usize * s + from..(w as usize + 1) * s]
                .copy_from_slice(&values.lerp[slot * s + from..(slot + 1) * s]);
        }
    }
    // Folds left by either value (spot at 10 %: 7 of 584 triangles, meshoptimizer 2): the merged
    // corners of each are moved, in texture space only, to where fewer triangles around them
    // fold ([`untangle_uv`]).
    for at in [layout.uv0, layout.uv1].into_iter().flatten() {
        let input_uv = |w: u32| Vec2::from_slice(&values.input.wedge(w as usize)[at..at + 2]);
        let expected: Vec<f32> = face_id
            .iter()
            .map(|&f| {
                let c = attributes.corners[face_origin[f as usize] as usize];
                uv_area(c.map(input_uv)).signum()
            })
            .collect();
        let lerp = |w: u32| {
            let slot = slot_of[w as usize] as usize;
            Vec2::from_slice(&values.lerp[slot * s + at..][..2])
        };
        let movable = |w: u32| slot_of[w as usize] != u32::MAX;
        untangle_uv(&corners, &expected, &mut wedge_values, s, at, movable, lerp);
    }

    // 4. The referenced vertices only, in engine order.
    let kept = mesh::clean::compact_vertex_indices(&mut out.triangles, e.vx.len());
    let mut new_index = vec![u32::MAX; e.vx.len()];
    for (i, &v) in kept.iter().enumerate() {
        new_index[v as usize] = i as u32;
    }
    out.positions = kept
        .iter()
        .map(|&v| frame.to_model(e.vx[v as usize].p))
        .collect();
    for v in &mut wedge_vertex {
        *v = new_index[*v as usize];
    }
    let column = |at: Option<usize>, dims: usize| {
        at.map(|at| {
            wedge_values
                .chunks_exact(s)
                .map(|w| &w[at..at + dims])
                .collect::<Vec<_>>()
        })
    };
    let mut result = Attributes {
        wedge_vertex,
        corners,
        // Interpolated normals are shorter than one: normalised (a zero one, from opposite
        // normals, stays as it is rather than becoming NaN).
        normals: column(layout.normals, 3).map(|c| {
            c.iter()
                .map(|n| {
                    let n = Vec3::from_slice(n);
                    n.try_normalize().unwrap_or(n)
                })
                .collect()
        }),
        uv0: column(layout.uv0, 2).map(|c| c.iter().map(|t| Vec2::from_slice(t)).collect()),
        uv1: column(layout.uv1, 2).map(|c| c.iter().map(|t| Vec2::from_slice(t)).collect()),
        // A fit can leave [0, 1] where the colours change fastest: clamped.
        colors: column(layout.colors, 4).map(|c| {
            c.iter()
                .map(|x| Vec4::from_slice(x).clamp(Vec4::ZERO, Vec4::ONE))
                .collect()
        }),
        face_material: attributes.face_material.as_ref().map(|m| {
            face_id
                .iter()
                .map(|&f| m[face_origin[f as usize] as usize])
                .collect()
        }),
    };
    // Input wedges of one vertex can hold equal values (an OBJ with repeated `vt` lines):
    // one wedge each, so that a format with one vertex per wedge splits no vertex for nothing.
    result.compact();
    (out, result)
}

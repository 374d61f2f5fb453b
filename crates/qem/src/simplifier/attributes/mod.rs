//! QEM that keeps normals, texture coordinates, colours and materials
//! ([`crate::simplify`] on a model with attributes).
//!
//! The collapse order stays Garland–Heckbert's geometric one (plus the optional attribute
//! term, [`AttributeError`]); what changes is what may be contracted (seams only along
//! themselves and into their fixed ends and crossings, which never move, [`Seams`]), the
//! constraint planes along the seams (Garland–Heckbert 1997's boundary planes, which the paper
//! proposes for any discontinuity), and the values, which travel with the contractions
//! ([`wedges`](super::wedges)).

use super::attribute_error::AttributeError;
use super::checks::{check_cancel, check_pair_threshold, validate};
use super::outcome::{Run, report};
use super::passes::AttributeRun;
use super::prepare;
use super::seams::Seams;
use super::view::View;
use super::wedges::output::{Contracted, output};
use super::wedges::{InputValues, WedgeValues, mark_side1};
use crate::{QemError, QemParams, QemReport};
use glam::DVec3;
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::time::Instant;

/// The whole run with attributes.
pub(crate) fn run(
    input: &TriMesh,
    attributes: &Attributes,
    params: &QemParams,
    user_locked: Option<&[bool]>,
) -> Result<(TriMesh, Attributes, QemReport), QemError> {
    let started = Instant::now();
    validate(params)?;
    attributes
        .validate(input)
        .map_err(QemError::InvalidAttributes)?;
    check_cancel(params)?;
    let (prepared, index) = prepare::prepare_with_index(input, true)?;
    check_pair_threshold(params.pair_threshold, prepared.frame.scale)?;
    check_cancel(params)?;
    let (input_vertices, input_faces) = (prepared.pos.len(), prepared.faces.len());
    let n = prepared.pos.len();
    // Each input vertex's prepared index (`u32::MAX`: unreferenced).
    let to_prepared = index.vertex;
    let real = |i: u32| (i != u32::MAX).then_some(i as usize);
    let mut locked = vec![false; n];
    // The caller's locks (input numbering).
    for (v, _) in user_locked
        .unwrap_or_default()
        .iter()
        .enumerate()
        .filter(|&(_, &l)| l)
    {
        if let Some(k) = real(to_prepared[v]) {
            locked[k] = true;
        }
    }

    // The attribute steps read the prepared mesh (vertex → face lists already built) with each
    // face's input face for its wedges: no second adjacency over the input, no sort of its
    // half-edges (the input-numbered seam search was 2.0 of 10.2 ms on the fandisk atlas).
    let view = View {
        faces: &prepared.faces,
        refs: &prepared.refs,
        face_start: &prepared.face_start,
        origin: &index.face,
        corners: index
            .face
            .iter()
            .map(|&g| attributes.corners[g as usize])
            .collect(),
        attributes,
    };
    let found = find_seams(&view, n);
    let mut seam = vec![false; n];
    let mut along = vec![[u32::MAX; 2]; n];
    for k in 0..n {
        let count = found.count[k];
        // Vertices whose wedges differ without a seam through them (a cone, a pole) are fixed
        // like seam ends and crossings (no seam neighbours: `Seams::is_fixed`).
        if count > 0 || found.multi[k] {
            seam[k] = true;
            if count == 2 {
                along[k] = found.first[k];
            }
        }
    }
    let seams = Seams { seam, along };
    let side = corner_sides(&view, &seams, &locked);
    let input = InputValues::of(attributes);
    let attr = attribute_error(&view, &input, &prepared.pos, params, &side);
    let values = WedgeValues::new(view, input, &prepared.pos, &side, &seams.seam);
    let attribute_run = AttributeRun {
        seams,
        edges: found.edges,
        attr,
        values,
    };
    let face_origin = index.face;
    check_cancel(params)?;
    let (run, out) = super::passes::simplify_prepared_with(
        prepared,
        params,
        Some(&locked),
        Some(attribute_run),
        |e, frame| match (&e.values, &e.seams) {
            (Some(values), Some(seams)) => {
                let (vx, faces, refs, live_faces) = (&e.vx, &e.faces, &e.refs, e.live_faces);
                let e = Contracted {
                    vx,
                    faces,
                    refs,
                    live_faces,
                };
                output(e, values, seams, frame, attributes, &face_origin)
            }
            // Not reached: an attribute run's engine always holds its values and seams.
            _ => (e.output(frame).0, Attributes::default()),
        },
    )?;
    let report = report(&run, input_vertices, input_faces, started);
    let Run { mesh, .. } = run;
    Ok((mesh, out, report))
}

/// The seams of a prepared mesh ([`find_seams`]).
struct FoundSeams {
    /// Seam edges `[u, v]`, `u < v`.
    edges: Vec<[u32; 2]>,
    /// Per vertex, its number of seam edges (saturating at 255) and its first two seam
    /// neighbours.
    count: Vec<u8>,
    first: Vec<[u32; 2]>,
    /// Per vertex: its corners hold more than one set of values (every seam vertex's do).
    multi: Vec<bool>,
}

/// The seams as `Attributes::seam_edges` defines them (edges of exactly two faces across which
/// a wedge value or the material changes), found over the prepared mesh's vertex → face lists,
/// with each vertex's seam neighbours and whether its corners hold different values.
///
/// Two passes over the vertices, as the seams are a small part of a mesh:
/// 1. Each vertex's corners: its distinct sets of values (`same_values` once per input wedge,
///    not per corner pair), so that later comparisons are of set numbers, and whether it has
///    more than one (faces in order, then the fans of the vertices with more than one).
/// 2. The edges `u`–`v` (`u < v`), only around vertices where a seam can pass (`u` or a
///    higher-numbered neighbour with several sets, or materials that differ): `u`'s edges to
///    higher-numbered neighbours gathered from its fan into a short list and matched there, in
///    fan order.
///
/// Scanning the fan again for each neighbour's faces, at every vertex, was 0.68 of 5.0 ms on
/// spot at 10 % (mostly mispredicted branches); the two passes run 1.3 M instructions there
/// (callgrind), half of the first rewrite's one-pass list matching.
fn find_seams(view: &View, n: usize) -> FoundSeams {
    let a = view.attributes;
    let mut found = FoundSeams {
        edges: Vec::new(),
        count: vec![0; n],
        first: vec![[u32::MAX; 2]; n],
        multi: vec![false; n],
    };
    let corner_of = |t: [u32; 3], u: u32| usize::from(t[1] == u) + 2 * usize::from(t[2] == u);

    // 1. Each input wedge's set: a wedge of its prepared vertex with the same values (which one
    // does not matter: only whether two sets are the same is asked, and values are finite, so
    // `same_values` is an equivalence). Faces in order, each corner's wedge against its vertex's
    // first wedge; a wedge with other values flags its vertex, whose other wedges are then
    // sorted into sets from its fan. By the fans of every vertex, the seam search was 51.6 M
    // instructions on the 268k-face igea atlas at 10 %, in face order 32.7 M (callgrind).
    let mut set = vec![u32::MAX; a.wedge_count()];
    let mut first_wedge = vec![u32::MAX; n];
    for (t, c) in view.faces.iter().zip(&view.corners) {
        for (&v, &w) in t.iter().zip(c) {
            let (v, w) = (v as usize, w as usize);
            if set[w] != u32::MAX {
                continue;
            }
            match first_wedge[v] {
                u32::MAX => {
                    first_wedge[v] = w as u32;
                    set[w] = w as u32;
                }
                r if a.same_values(r, w as u32) => set[w] = r,
                _ => found.multi[v] = true,
            }
        }
    }
    let mut sets: Vec<u32> = Vec::new();
    for u in (0..n).filter(|&u| found.multi[u]) {
        sets.clear();
        sets.push(first_wedge[u]);
        for &f in view.fan(u) {
            let w = view.wedge(f as usize, corner_of(view.faces[f as usize], u as u32));
            if set[w as usize] == u32::MAX {
                let same = sets.iter().find(|&&x| a.same_values(x, w));
                set[w as usize] = *same.unwrap_or(&w);
                if same.is_none() {
                    sets.push(w);
                }
            }
        }
    }
    let materials_vary = a
        .face_material
        .as_ref()
        .is_some_and(|m| m.iter().any(|&x| x != m[0]));

    // 2. The seam edges. An edge u-v is a seam only where u or v has several sets, so only the
    // vertices u with several sets or a higher-numbered neighbour with several are visited,
    // flagged from the fans of the vertices with several sets (a fraction of the mesh) rather
    // than found by a look at every vertex's fan (the same edges in the same order: 71.4 → 51.6 M
    // instructions of the seam search on the 268k-face igea atlas at 10 %, callgrind).
    let mut may_pass = if materials_vary {
        vec![true; n]
    } else {
        found.multi.clone()
    };
    if !materials_vary {
        for v in (0..n).filter(|&v| found.multi[v]) {
            for &f in view.fan(v) {
                for x in view.faces[f as usize] {
                    if (x as usize) < v {
                        may_pass[x as usize] = true;
                    }
                }
            }
        }
    }
    // (neighbour v > u, face, corner of u, corner of v) for each fan face, in fan order.
    let mut near: Vec<(u32, u32, u8, u8)> = Vec::new();
    for u in (0..n).filter(|&u| may_pass[u]) {
        let fan = view.fan(u);
        let u32u = u as u32;
        near.clear();
        for &f in fan {
            let t = view.faces[f as usize];
            let ku = corner_of(t, u32u) as u8;
            for (kv, &v) in t.iter().enumerate() {
                if v > u32u {
                    near.push((v, f, ku, kv as u8));
                }
            }
        }
        for (i, &(v, f, fu, fv)) in near.iter().enumerate() {
            // The faces of the edge u-v: seams are edges of exactly two, counted once, at the
            // first of the two in fan order.
            if near[..i].iter().any(|x| x.0 == v) {
                continue;
            }
            let mut others = near[i + 1..].iter().filter(|x| x.0 == v);
            let (Some(&(_, g, gu, gv)), None) = (others.next(), others.next()) else {
                continue;
            };
            let (f, g) = (f as usize, g as usize);
            let set_of = |f: usize, k: u8| set[view.wedge(f, k.into()) as usize];
            let seam = set_of(f, fu) != set_of(g, gu)
                || set_of(f, fv) != set_of(g, gv)
                || (materials_vary && view.material(f as u32) != view.material(g as u32));
            if seam {
                found.edges.push([u32u, v]);
                for (x, y) in [(u, v), (v as usize, u32u)] {
                    let c = found.count[x] as usize;
                    if c < 2 {
                        found.first[x][c] = y;
                    }
                    found.count[x] = found.count[x].saturating_add(1);
                }
            }
        }
    }
    found
}

/// The side of every prepared face corner at a seam vertex that may be contracted (two seam
/// neighbours, not `locked`), `side[3 f + k]` for corner `k` of face `f`: 0 on the left of the
/// seam walked from `along[0]` through the vertex to `along[1]`
/// ([`fan_sides`](super::wedges::fan_sides)), 1 on the other side; 0 everywhere else.
fn corner_sides(view: &View, seams: &Seams, locked: &[bool]) -> Vec<u8> {
    let tris = view.faces;
    let mut side = vec![0u8; tris.len() * 3];
    let (mut reached, mut stack) = (Vec::new(), Vec::new());
    let movable = (0..seams.seam.len()).map(|v| seams.seam[v] && !seams.is_fixed(v) && !locked[v]);
    for (v, _) in movable.enumerate().filter(|&(_, m)| m) {
        let [n0, n1] = seams.along[v];
        let fan = view.fan(v);
        let faces = |f: u32| tris[f as usize];
        let vn = [v as u32, n0, n1];
        mark_side1(fan, faces, vn, &mut reached, &mut stack, |f, k| {
            side[f as usize * 3 + k] = 1;
        });
    }
    side
}

/// The attribute error sums of the prepared triangles ([`AttributeError`] over the vertices at
/// `pos`, the normalised frame), one channel per component of each attribute with a non-zero
/// weight (`params.attribute_weights`), scaled by it; `None` when there is none. Each corner
/// goes to its side ([`corner_sides`]).
fn attribute_error(
    view: &View,
    input: &InputValues,
    pos: &[DVec3],
    params: &QemParams,
    side: &[u8],
) -> Option<AttributeError> {
    let w = params.attribute_weights;
    let sets = input.weighted(w.uv, w.normal, w.color);
    let channels: usize = sets.iter().map(|s| s.2).sum();
    if channels == 0 {
        return None;
    }
    let wedges = view.attributes.wedge_count();
    let mut values = Vec::with_capacity(wedges * channels);
    for wedge in 0..wedges {
        let x = input.wedge(wedge);
        for &(weight, at, dims) in &sets {
            values.extend(x[at..at + dims].iter().map(|&x| weight * f64::from(x)));
        }
    }

    let mut out = AttributeError::new(pos.len(), channels);
    let mut corner_values = vec![0.0; 3 * channels];
    for (f, t) in view.faces.iter().enumerate() {
        for k in 0..3 {
            let at = view.wedge(f, k) as usize * channels;
            corner_values[k * channels..(k + 1) * channels]
                .copy_from_slice(&values[at..at + channels]);
        }
        out.add_triangle(
            t.map(|v| pos[v as usize]),
            &corner_values,
            *t,
            [side[f * 3], side[f * 3 + 1], side[f * 3 + 2]],
        );
    }
    Some(out)
}

//! QEM that keeps normals, texture coordinates, colours and materials
//! ([`crate::simplify_with_attributes`]).
//!
//! The collapse order stays Garland–Heckbert's geometric one (plus the optional attribute
//! term, [`AttributeError`]); what changes is what may be contracted (seams only along
//! themselves, seam ends and crossings locked, [`Seams`]), the constraint planes along the seams
//! (Garland–Heckbert 1997's boundary planes, which the paper proposes for any discontinuity),
//! and the values, which travel with the contractions ([`wedges`]).

use super::attribute_error::AttributeError;
use super::engine::{Seams, Vertex};
use super::wedges::{self, WedgeValues};
use super::{AttributeRun, Run, prepare};
use crate::{QemError, QemParams, QemReport, Quadric};
use glam::DVec3;
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::collections::HashMap;
use std::time::Instant;

/// Seam constraint planes: for each seam edge `[u, v]` (prepared numbering), the plane through
/// the edge perpendicular to its two faces' mean normal, weighted by
/// `params.boundary_weight × |edge|²` as a boundary edge's, added to both ends' quadrics.
pub(super) fn seam_planes(
    vx: &mut [Vertex],
    pos: &[DVec3],
    faces: &[[u32; 3]],
    refs: &[u32],
    face_start: &[u32],
    edges: &[[u32; 2]],
    params: &QemParams,
) {
    for &[u, v] in edges {
        let (u, v) = (u as usize, v as usize);
        let end = face_start.get(u + 1).map_or(refs.len(), |&e| e as usize);
        let mut normal = DVec3::ZERO;
        for &f in &refs[face_start[u] as usize..end] {
            let t = faces[f as usize];
            if t.contains(&(v as u32)) {
                let [p0, p1, p2] = t.map(|w| pos[w as usize]);
                normal += (p1 - p0).cross(p2 - p0).normalize_or_zero();
            }
        }
        let edge = pos[v] - pos[u];
        let m = edge.cross(normal).normalize_or_zero();
        if m != DVec3::ZERO {
            let w = params.boundary_weight * edge.length_squared();
            let q = Quadric::from_plane(m, -m.dot(pos[u]), w);
            vx[u].q += q;
            vx[v].q += q;
        }
    }
}

/// The whole run with attributes.
pub(crate) fn run(
    input: &TriMesh,
    attributes: &Attributes,
    params: &QemParams,
    user_locked: Option<&[bool]>,
) -> Result<(TriMesh, Attributes, QemReport), QemError> {
    let started = Instant::now();
    super::validate(params)?;
    attributes
        .validate(input)
        .map_err(QemError::InvalidAttributes)?;
    let (prepared, index) = prepare::prepare_with_index(input, true)?;
    super::check_pair_threshold(params.pair_threshold, prepared.frame.scale)?;
    let (input_vertices, input_faces) = (prepared.pos.len(), prepared.faces.len());
    let n = prepared.pos.len();
    let frame = prepared.frame;
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

    // Seams in input numbering: each vertex's seam neighbours; vertices whose wedges differ
    // without a seam through them (a cone, a pole) are locked like seam ends and crossings.
    let seam_edges = attributes.seam_edges(input);
    let mut along_input: HashMap<u32, Vec<u32>> = HashMap::new();
    for &[u, v] in &seam_edges {
        along_input.entry(u).or_default().push(v);
        along_input.entry(v).or_default().push(u);
    }
    let mut first_wedge = vec![u32::MAX; input.positions.len()];
    let mut multi = vec![false; input.positions.len()];
    for (t, c) in input.triangles.iter().zip(&attributes.corners) {
        for k in 0..3 {
            let v = t[k] as usize;
            if first_wedge[v] == u32::MAX {
                first_wedge[v] = c[k];
            } else if !attributes.same_values(first_wedge[v], c[k]) {
                multi[v] = true;
            }
        }
    }
    let mut seam = vec![false; n];
    let mut along = vec![[u32::MAX; 2]; n];
    for (v, is_multi) in multi.iter().enumerate() {
        let Some(k) = real(to_prepared[v]) else {
            continue;
        };
        let neighbours = along_input.get(&(v as u32));
        let count = neighbours.map_or(0, Vec::len);
        if count > 0 || *is_multi {
            seam[k] = true;
        }
        match neighbours {
            Some(list) if list.len() == 2 => {
                along[k] = [to_prepared[list[0] as usize], to_prepared[list[1] as usize]];
            }
            _ if count > 0 || *is_multi => locked[k] = true,
            _ => {}
        }
    }
    let edges: Vec<[u32; 2]> = seam_edges
        .iter()
        .filter_map(|&[u, v]| {
            Some([
                real(to_prepared[u as usize])? as u32,
                real(to_prepared[v as usize])? as u32,
            ])
        })
        .collect();
    let seams = Seams { seam, along };
    let side = corner_sides(input, &along_input);
    let attr = attribute_error(input, attributes, params, (&to_prepared, n), frame, &side);
    let values = WedgeValues::new(input, attributes, &to_prepared, n, &side, &frame);
    let attribute_run = AttributeRun {
        seams,
        edges,
        attr,
        values,
    };
    let face_origin = index.face;
    let (run, out) = super::simplify_prepared_with(
        prepared,
        params,
        Some(&locked),
        Some(attribute_run),
        |e, frame, carried| match carried {
            Some((values, seams)) => {
                wedges::output(e, values, seams, frame, attributes, &face_origin)
            }
            // Not reached: an attribute run always carries its values.
            None => (e.output(frame).0, Attributes::default()),
        },
    );
    let report = super::report(&run, input_vertices, input_faces, started);
    let Run { mesh, .. } = run;
    Ok((mesh, out, report))
}

/// The side of every input face corner at a seam vertex (`along_input`: each seam vertex's seam
/// neighbours; only those with two have sides), `side[3 f + k]` for corner `k` of face `f`: 0
/// on the left of the seam walked from the first neighbour through the vertex to the second
/// ([`wedges::fan_sides`]), 1 on the other side; 0 everywhere else.
fn corner_sides(input: &TriMesh, along_input: &HashMap<u32, Vec<u32>>) -> Vec<u8> {
    let tris = &input.triangles;
    let mut side = vec![0u8; tris.len() * 3];
    let vf = mesh::topology::VertexFaces::new(tris, input.positions.len());
    let (mut reached, mut stack) = (Vec::new(), Vec::new());
    for (&v, list) in along_input {
        let &[n0, n1] = list.as_slice() else {
            continue;
        };
        let fan = &vf.faces[vf.start[v as usize] as usize..vf.start[v as usize + 1] as usize];
        let faces = |f: u32| tris[f as usize];
        wedges::fan_sides(fan, faces, [v, n0, n1], &mut reached, &mut stack);
        if !reached.iter().any(|&r| r) {
            continue;
        }
        for (&f, &r) in fan.iter().zip(&reached) {
            if !r {
                let k = tris[f as usize].iter().position(|&x| x == v).unwrap_or(0);
                side[f as usize * 3 + k] = 1;
            }
        }
    }
    side
}

/// The attribute error sums of `input`'s triangles ([`AttributeError`] over the `vertices`
/// prepared vertices: `to_prepared`, positions in `frame`; ambiguous or unreferenced inputs map
/// to `u32::MAX - 1` or above and are left out), one channel per component of each attribute with a
/// non-zero weight (`params.attribute_weights`), scaled by it; `None` when there is none. The
/// corners of a seam vertex (`along_input`: its two seam neighbours) are split into the side on
/// the left of the seam walked from its first neighbour to its second (side 0: the faces
/// reached from the one holding the directed edge vertex → second neighbour without crossing
/// the seam) and the other (side 1).
fn attribute_error(
    input: &TriMesh,
    attributes: &Attributes,
    params: &QemParams,
    (to_prepared, vertices): (&[u32], usize),
    frame: super::prepare::Frame,
    side: &[u8],
) -> Option<AttributeError> {
    let w = params.attribute_weights;
    // (weight, per-wedge values, components)
    let mut sets: Vec<(f64, Vec<f64>, usize)> = Vec::new();
    for uv in [&attributes.uv0, &attributes.uv1].into_iter().flatten() {
        if w.uv > 0.0 {
            let flat = uv.iter().flat_map(|t| [t.x, t.y]).map(f64::from).collect();
            sets.push((w.uv, flat, 2));
        }
    }
    if let Some(normals) = attributes.normals.as_ref().filter(|_| w.normal > 0.0) {
        let flat = normals
            .iter()
            .flat_map(|n| n.to_array())
            .map(f64::from)
            .collect();
        sets.push((w.normal, flat, 3));
    }
    if let Some(colors) = attributes.colors.as_ref().filter(|_| w.color > 0.0) {
        let flat = colors
            .iter()
            .flat_map(|c| c.to_array())
            .map(f64::from)
            .collect();
        sets.push((w.color, flat, 4));
    }
    let channels: usize = sets.iter().map(|s| s.2).sum();
    if channels == 0 {
        return None;
    }
    let wedges = attributes.wedge_count();
    let mut values = Vec::with_capacity(wedges * channels);
    for wedge in 0..wedges {
        for (weight, flat, dims) in &sets {
            values.extend(
                flat[wedge * dims..(wedge + 1) * dims]
                    .iter()
                    .map(|x| weight * x),
            );
        }
    }

    let tris = &input.triangles;
    let mut out = AttributeError::new(vertices, channels);
    let mut corner_values = vec![0.0; 3 * channels];
    for (f, (t, c)) in tris.iter().zip(&attributes.corners).enumerate() {
        for k in 0..3 {
            let at = c[k] as usize * channels;
            corner_values[k * channels..(k + 1) * channels]
                .copy_from_slice(&values[at..at + channels]);
        }
        let vertex = t.map(|v| {
            let k = to_prepared[v as usize];
            if k < u32::MAX - 1 { k } else { u32::MAX }
        });
        out.add_triangle(
            t.map(|v| frame.to_frame(input.positions[v as usize])),
            &corner_values,
            vertex,
            [side[f * 3], side[f * 3 + 1], side[f * 3 + 2]],
        );
    }
    Some(out)
}

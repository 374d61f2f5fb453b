//! QEM that keeps normals, texture coordinates, colours and materials
//! ([`crate::simplify_with_attributes`]).
//!
//! The collapse order stays Garland–Heckbert's geometric one; what changes is what may be
//! contracted (seams only along themselves, seam ends and crossings locked, [`Seams`]), the
//! constraint planes along the seams (Garland–Heckbert 1997's boundary planes, which the paper
//! proposes for any discontinuity), and the attribute values of the output, taken from the
//! original surface at each output corner on its side of the seams
//! (`mesh::transfer::transfer_attributes`).

use super::attribute_error::AttributeError;
use super::engine::{Seams, Vertex};
use super::{Run, prepare};
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

/// Bit pattern of a normalised position (the key that finds an input vertex among the prepared
/// ones).
fn key(p: DVec3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
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
    let prepared = prepare::prepare(input)?;
    super::check_pair_threshold(params.pair_threshold, prepared.frame.scale)?;
    let (input_vertices, input_faces) = (prepared.pos.len(), prepared.faces.len());
    let n = prepared.pos.len();

    // Each referenced input vertex's prepared index, found by its normalised position (the
    // prepare pass renumbers along a Morton curve). Positions held by two vertices (touching
    // points the weld kept apart) are ambiguous: those vertices are locked.
    const AMBIGUOUS: u32 = u32::MAX - 1;
    let mut by_position: HashMap<[u64; 3], u32> = HashMap::with_capacity(n);
    for (k, &p) in prepared.pos.iter().enumerate() {
        by_position
            .entry(key(p))
            .and_modify(|e| *e = AMBIGUOUS)
            .or_insert(k as u32);
    }
    let frame = prepared.frame;
    let to_prepared: Vec<u32> = input
        .positions
        .iter()
        .map(|&p| {
            by_position
                .get(&key(frame.to_frame(p)))
                .copied()
                .unwrap_or(u32::MAX)
        })
        .collect();
    let mut locked = vec![false; n];
    for (k, &p) in prepared.pos.iter().enumerate() {
        if by_position.get(&key(p)) == Some(&AMBIGUOUS) {
            locked[k] = true;
        }
    }
    let real = |i: u32| (i < AMBIGUOUS).then_some(i as usize);
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
                along[k] = [to_prepared[list[0] as usize], to_prepared[list[1] as usize]]
                    .map(|i| if i < AMBIGUOUS { i } else { u32::MAX });
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
    let attr = attribute_error(
        input,
        attributes,
        params,
        (&to_prepared, n),
        frame,
        &along_input,
    );
    let (run, _kept) =
        super::simplify_prepared_with(prepared, params, Some(&locked), Some((seams, edges)), attr);
    let out = mesh::transfer::transfer_attributes(input, attributes, &run.mesh);
    let report = super::report(&run, input_vertices, input_faces, started);
    let Run { mesh, .. } = run;
    Ok((mesh, out, report))
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
    along_input: &HashMap<u32, Vec<u32>>,
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

    // Side 1 corners of the seam vertices, per face corner.
    let tris = &input.triangles;
    let mut side = vec![0u8; tris.len() * 3];
    let vf = mesh::topology::VertexFaces::new(tris, input.positions.len());
    let mut reached = Vec::new();
    let mut stack = Vec::new();
    for (&v, list) in along_input {
        let &[n0, n1] = list.as_slice() else {
            continue;
        };
        let fan = &vf.faces[vf.start[v as usize] as usize..vf.start[v as usize + 1] as usize];
        let corner = |f: u32| tris[f as usize].iter().position(|&x| x == v).unwrap_or(0);
        let first = fan
            .iter()
            .position(|&f| tris[f as usize][(corner(f) + 1) % 3] == n1)
            .or_else(|| fan.iter().position(|&f| tris[f as usize].contains(&n1)));
        let Some(first) = first else {
            continue;
        };
        reached.clear();
        reached.resize(fan.len(), false);
        reached[first] = true;
        stack.clear();
        stack.push(first);
        while let Some(i) = stack.pop() {
            for x in tris[fan[i] as usize] {
                if x == v || x == n0 || x == n1 {
                    continue;
                }
                for (j, &g) in fan.iter().enumerate() {
                    if !reached[j] && tris[g as usize].contains(&x) {
                        reached[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
        for (i, &f) in fan.iter().enumerate() {
            if !reached[i] {
                side[f as usize * 3 + corner(f)] = 1;
            }
        }
    }

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

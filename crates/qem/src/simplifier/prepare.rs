//! The prepare pass: validate the input, drop faces that repeat a vertex index, move the
//! referenced vertices into a normalised frame, renumber them along a Morton curve, sort the faces
//! by their smallest new index and build the vertex → face lists. Inputs are often in scan order;
//! after this, neighbouring vertices and faces sit close in memory for every later pass.

use super::triangle::DEAD;
use crate::QemError;
use crate::radix::sort_by_u32_key;
use glam::{DVec3, Vec3};
use mesh::TriMesh;

/// The normalised frame: model coordinates centred on the bounding box of the referenced
/// vertices and scaled to a unit box diagonal (for conditioning; all work happens in it).
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    /// Centre of the bounding box, model units.
    pub(super) center: DVec3,
    /// Frame units per model unit (1 / box diagonal; 1 for a single point).
    pub(super) scale: f64,
}

impl Frame {
    /// Model point `p` in this frame.
    #[inline]
    pub(super) fn to_frame(self, p: Vec3) -> DVec3 {
        (p.as_dvec3() - self.center) * self.scale
    }

    /// Back to model units (`f32`, as `TriMesh` stores them).
    #[inline]
    pub(super) fn to_model(self, p: DVec3) -> Vec3 {
        let p = p / self.scale + self.center;
        Vec3::new(p.x as f32, p.y as f32, p.z as f32)
    }
}

/// The prepared mesh, renumbered and in the normalised frame.
pub(super) struct Prepared {
    /// Referenced vertices only, in Morton order, normalised.
    pub(super) pos: Vec<DVec3>,
    /// Faces over the new indices, sorted by their smallest vertex.
    pub(super) faces: Vec<[u32; 3]>,
    /// Vertex → face lists: vertex `v`'s faces are `refs[face_start[v]..face_start[v + 1]]`.
    pub(super) refs: Vec<u32>,
    /// Start of each vertex's list in `refs` (length: vertices + 1).
    pub(super) face_start: Vec<u32>,
    /// The frame `pos` is in.
    pub(super) frame: Frame,
}

/// Run the prepare steps in order.
pub(super) fn prepare(input: &TriMesh) -> Result<Prepared, QemError> {
    prepare_with_index(input, false).map(|(p, _)| p)
}

/// Where the prepared vertices and faces came from ([`prepare_with_index`]).
pub(super) struct PreparedIndex {
    /// Each input vertex's prepared index (`u32::MAX` for an unreferenced one).
    pub(super) vertex: Vec<u32>,
    /// Each prepared face's input face (its corners in the same order).
    pub(super) face: Vec<u32>,
}

/// [`prepare`], also returning where the prepared vertices and faces came from when
/// `keep_index` (else empty lists: the vertex index is dropped as soon as the faces are
/// renumbered, which lowers the peak memory of ordinary runs).
pub(super) fn prepare_with_index(
    input: &TriMesh,
    keep_index: bool,
) -> Result<(Prepared, PreparedIndex), QemError> {
    let (faces, usable) = usable_faces(input, keep_index)?;
    let face_len = faces_per_vertex(input.positions.len(), &faces);
    let frame = normalised_frame(&input.positions, &face_len)?;
    let (pos, face_len, new_index) = morton_renumbering(&input.positions, face_len, &frame);
    let mut face_origin = Vec::new();
    let faces = sort_faces(
        &faces,
        &new_index,
        pos.len(),
        keep_index.then_some(&mut face_origin),
    );
    let index = if keep_index {
        for f in &mut face_origin {
            *f = usable[*f as usize];
        }
        PreparedIndex {
            vertex: new_index, // DEAD is u32::MAX
            face: face_origin,
        }
    } else {
        drop(new_index);
        PreparedIndex {
            vertex: Vec::new(),
            face: Vec::new(),
        }
    };
    let mesh::topology::VertexFaces {
        start: face_start,
        faces: refs,
    } = mesh::topology::VertexFaces::new(&faces, face_len.len());
    Ok((
        Prepared {
            pos,
            faces,
            refs,
            face_start,
            frame,
        },
        index,
    ))
}

/// Validate the indices and keep the faces with three distinct corners; with `keep_index`, also
/// the input index of each kept face (else an empty list).
fn usable_faces(input: &TriMesh, keep_index: bool) -> Result<(Vec<[u32; 3]>, Vec<u32>), QemError> {
    let n = input.positions.len();
    if n >= u32::MAX as usize || input.triangles.len() >= u32::MAX as usize / 2 {
        return Err(QemError::InvalidParameter(
            "mesh too large for 32-bit indices".into(),
        ));
    }
    let mut faces: Vec<[u32; 3]> = Vec::with_capacity(input.triangles.len());
    let mut kept = Vec::new();
    for (fi, t) in input.triangles.iter().enumerate() {
        for &v in t {
            if v as usize >= n {
                return Err(QemError::InvalidIndex {
                    face: fi,
                    index: v,
                    vertices: n,
                });
            }
        }
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            faces.push(*t);
            if keep_index {
                kept.push(fi as u32);
            }
        }
    }
    if faces.is_empty() {
        return Err(QemError::EmptyMesh);
    }
    Ok((faces, kept))
}

/// Number of faces around each of the `n` vertices (0: unreferenced).
fn faces_per_vertex(n: usize, faces: &[[u32; 3]]) -> Vec<u32> {
    let mut face_len = vec![0u32; n];
    for t in faces {
        for &v in t {
            face_len[v as usize] += 1;
        }
    }
    face_len
}

/// The frame of the referenced vertices' bounding box; a non-finite referenced vertex is an error.
fn normalised_frame(positions: &[Vec3], face_len: &[u32]) -> Result<Frame, QemError> {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for (i, p) in positions.iter().enumerate() {
        if face_len[i] > 0 {
            if !p.is_finite() {
                return Err(QemError::NonFiniteVertex(i));
            }
            lo = lo.min(p.as_dvec3());
            hi = hi.max(p.as_dvec3());
        }
    }
    let diag = (hi - lo).length();
    Ok(Frame {
        center: 0.5 * (lo + hi),
        scale: if diag > 0.0 { 1.0 / diag } else { 1.0 },
    })
}

/// Renumber the referenced vertices along a Morton curve: their normalised positions, their face
/// counts (the old ones permuted) and the new index of each old vertex ([`DEAD`] if unreferenced).
fn morton_renumbering(
    positions: &[Vec3],
    old_face_len: Vec<u32>,
    frame: &Frame,
) -> (Vec<DVec3>, Vec<u32>, Vec<u32>) {
    let n = positions.len();
    let mut order: Vec<u64> = (0..n)
        .filter(|&i| old_face_len[i] > 0)
        .map(|i| (morton(frame.to_frame(positions[i])) << 32) | i as u64)
        .collect();
    let mut scratch64: Vec<u64> = Vec::new();
    // The 22 high bits of the Morton code (7 per axis) are locality enough: two radix passes.
    sort_by_u32_key(&mut order, &mut scratch64, |&o| (o >> 40) as u32);
    drop(scratch64);
    let mut new_index = vec![DEAD; n];
    for (k, &o) in order.iter().enumerate() {
        new_index[o as u32 as usize] = k as u32;
    }
    let pos = order
        .iter()
        .map(|&o| frame.to_frame(positions[o as u32 as usize]))
        .collect();
    let face_len = order
        .iter()
        .map(|&o| old_face_len[o as u32 as usize])
        .collect();
    (pos, face_len, new_index)
}

/// 30-bit Morton code of a point of the normalised frame (coordinates within ±1).
fn morton(p: DVec3) -> u64 {
    fn spread(x: f64) -> u64 {
        let mut v = (((x + 1.0) * 512.0).clamp(0.0, 1023.0)) as u64;
        v = (v | (v << 16)) & 0x0300_00ff;
        v = (v | (v << 8)) & 0x0300_f00f;
        v = (v | (v << 4)) & 0x030c_30c3;
        (v | (v << 2)) & 0x0924_9249
    }
    spread(p.x) | (spread(p.y) << 1) | (spread(p.z) << 2)
}

/// The faces over the new indices, in order of their smallest vertex (a stable counting sort
/// over the `n` new vertices); with `origin`, also each sorted face's index in `faces`.
fn sort_faces(
    faces: &[[u32; 3]],
    new_index: &[u32],
    n: usize,
    mut origin: Option<&mut Vec<u32>>,
) -> Vec<[u32; 3]> {
    let renumbered = |t: &[u32; 3]| t.map(|v| new_index[v as usize]);
    let smallest = |t: &[u32; 3]| t[0].min(t[1]).min(t[2]) as usize;
    let mut slot = vec![0u32; n + 1];
    for t in faces {
        slot[smallest(&renumbered(t)) + 1] += 1;
    }
    for v in 0..n {
        slot[v + 1] += slot[v];
    }
    let mut sorted = vec![[0u32; 3]; faces.len()];
    if let Some(o) = origin.as_deref_mut() {
        o.resize(faces.len(), 0);
    }
    for (i, t) in faces.iter().enumerate() {
        let r = renumbered(t);
        let s = &mut slot[smallest(&r)];
        sorted[*s as usize] = r;
        if let Some(o) = origin.as_deref_mut() {
            o[*s as usize] = i as u32;
        }
        *s += 1;
    }
    sorted
}

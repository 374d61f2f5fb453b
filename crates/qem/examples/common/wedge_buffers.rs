//! meshoptimizer's input for a model with attributes, shared by the `attributes` bench and the
//! `attr_call` example (each includes this file by `#[path]`): one vertex per wedge (position
//! and attribute values, f32, normals then texture coordinates then colours) and the corners as
//! indices, and meshoptimizer's `simplifyWithAttributes` on them.

/// The wedge vertex buffers of a model with attributes.
pub struct WedgeBuffers {
    /// Position of each wedge's vertex, three floats a wedge.
    pub positions: Vec<f32>,
    /// Attribute values, `stride` floats a wedge.
    pub values: Vec<f32>,
    /// Floats of `values` a wedge.
    pub stride: usize,
    /// The corners' wedges, three a face.
    pub indices: Vec<u32>,
}

/// The buffers of `mesh` with its attributes `a`.
pub fn wedge_buffers(mesh: &mesh::TriMesh, a: &mesh::attributes::Attributes) -> WedgeBuffers {
    let (mut positions, mut values) = (Vec::new(), Vec::new());
    for (w, &v) in a.wedge_vertex.iter().enumerate() {
        positions.extend(mesh.positions[v as usize].to_array());
        if let Some(n) = &a.normals {
            values.extend(n[w].to_array());
        }
        for uv in [&a.uv0, &a.uv1].into_iter().flatten() {
            values.extend(uv[w].to_array());
        }
        if let Some(c) = &a.colors {
            values.extend(c[w].to_array());
        }
    }
    WedgeBuffers {
        stride: values.len() / a.wedge_count(),
        indices: a.corners.iter().flatten().copied().collect(),
        positions,
        values,
    }
}

impl WedgeBuffers {
    /// meshoptimizer's `simplifyWithAttributes` of these buffers down to `faces` faces: every
    /// attribute weight 0, no lock array, no error bound, no options; returns the faces kept.
    pub fn simplify(&self, faces: usize) -> usize {
        let weights = vec![0.0f32; self.stride];
        let mut dest = vec![0u32; self.indices.len()];
        // SAFETY: every pointer covers the counts passed with it; no lock array (null), as the
        // Python wrapper's callers pass.
        let n = unsafe {
            meshopt::ffi::meshopt_simplifyWithAttributes(
                dest.as_mut_ptr(),
                self.indices.as_ptr(),
                self.indices.len(),
                self.positions.as_ptr(),
                self.positions.len() / 3,
                12,
                self.values.as_ptr(),
                self.stride * 4,
                weights.as_ptr(),
                weights.len(),
                std::ptr::null(),
                faces * 3,
                f32::MAX,
                0,
                std::ptr::null_mut(),
            )
        };
        n / 3
    }
}

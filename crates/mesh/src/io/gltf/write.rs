//! The glTF writer: one mesh, one node, one primitive per material, all sharing one set of
//! vertex accessors (one glTF vertex per wedge), laid out in one buffer ([`write`]).

use super::glb::glb;
use super::uri::{base64_encode, percent_encode};
use crate::TriMesh;
use crate::attributes::{Attributes, Materials};
use glam::{DVec3, Vec3};
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;

#[derive(Default)]
struct Layout {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Layout {
    /// Appends `bytes` as a buffer view (4-byte aligned); returns its index.
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view =
            json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    /// Appends a float vertex attribute of `N` components; returns its accessor index.
    fn floats<const N: usize>(&mut self, values: &[[f32; N]], with_bounds: bool) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let view = self.view(&bytes, Some(34962));
        let kind = ["SCALAR", "VEC2", "VEC3", "VEC4"][N - 1];
        let mut accessor = json!({
            "bufferView": view, "componentType": 5126, "count": values.len(), "type": kind,
        });
        if with_bounds && !values.is_empty() {
            let mut min = [f32::INFINITY; N];
            let mut max = [f32::NEG_INFINITY; N];
            for v in values {
                for k in 0..N {
                    min[k] = min[k].min(v[k]);
                    max[k] = max[k].max(v[k]);
                }
            }
            accessor["min"] = json!(min.iter().map(|&x| f64::from(x)).collect::<Vec<_>>());
            accessor["max"] = json!(max.iter().map(|&x| f64::from(x)).collect::<Vec<_>>());
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Appends triangle indices (unsigned short when every index fits, else unsigned int);
    /// returns the accessor index.
    fn indices(&mut self, indices: &[u32], vertex_count: usize) -> usize {
        let (bytes, component): (Vec<u8>, u32) = if vertex_count <= 65535 {
            (
                indices
                    .iter()
                    .flat_map(|&i| (i as u16).to_le_bytes())
                    .collect(),
                5123,
            )
        } else {
            (
                indices.iter().flat_map(|&i| i.to_le_bytes()).collect(),
                5125,
            )
        };
        let view = self.view(&bytes, Some(34963));
        self.accessors.push(json!({
            "bufferView": view, "componentType": component, "count": indices.len(), "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }
}

/// How the buffer of a written `.gltf` is stored.
pub(crate) enum BufferStorage<'a> {
    /// In the GLB BIN chunk (a `.glb`).
    Glb,
    /// As a `data:` URI inside the JSON (a self-contained `.gltf`).
    DataUri,
    /// In a separate file of this name next to the `.gltf`.
    File(&'a str),
}

/// The bytes of a written glTF (JSON or GLB) and of its separate buffer file, if any.
pub(crate) struct Written {
    /// The `.gltf` JSON or the `.glb` container.
    pub main: Vec<u8>,
    /// The buffer, for [`BufferStorage::File`].
    pub bin: Option<Vec<u8>>,
}

/// Lays out `mesh` with `attributes` (already validated against it) as glTF: one glTF vertex
/// per wedge, one primitive per material; the non-geometry members from `materials`' glTF
/// assets, or plain materials named as in `materials`. Normals that are not of unit length
/// (the validator's rule) are normalized, zero ones replaced by their triangle's normal. With
/// `flip_v` (a texture converted from an OBJ material library), `TEXCOORD_0` is written as
/// `(u, 1 − v)`: OBJ's `v` runs up from the image's bottom edge, glTF's down from its top edge.
pub(crate) fn write(
    mesh: &TriMesh,
    attributes: &Attributes,
    materials: Option<&Materials>,
    storage: BufferStorage,
    flip_v: bool,
    origin: DVec3,
) -> Written {
    let wedges = attributes.wedge_count();
    let mut layout = Layout::default();
    let positions: Vec<[f32; 3]> = attributes
        .wedge_vertex
        .iter()
        .map(|&v| mesh.positions[v as usize].to_array())
        .collect();
    let mut vertex_attributes = Map::new();
    vertex_attributes.insert("POSITION".into(), json!(layout.floats(&positions, true)));
    if let Some(normals) = &attributes.normals {
        // Unit within the validator's tolerance: written as they are (bit for bit).
        let unit = |v: Vec3| (v.length_squared() - 1.0).abs() < 1e-5;
        let mut n: Vec<Vec3> = normals.clone();
        let face_normals = mesh.face_normals();
        for (f, c) in attributes.corners.iter().enumerate() {
            for &w in c {
                let v = n[w as usize];
                if !unit(v) {
                    n[w as usize] = v
                        .try_normalize()
                        .or_else(|| face_normals[f].try_normalize())
                        .unwrap_or(Vec3::Z);
                }
            }
        }
        // Wedges no corner uses.
        for v in &mut n {
            if !unit(*v) {
                *v = v.try_normalize().unwrap_or(Vec3::Z);
            }
        }
        let n: Vec<[f32; 3]> = n.iter().map(|x| x.to_array()).collect();
        vertex_attributes.insert("NORMAL".into(), json!(layout.floats(&n, false)));
    }
    if let Some(uv) = &attributes.uv0 {
        let uv: Vec<[f32; 2]> = uv
            .iter()
            .map(|x| {
                if flip_v {
                    [x.x, 1.0 - x.y]
                } else {
                    x.to_array()
                }
            })
            .collect();
        vertex_attributes.insert("TEXCOORD_0".into(), json!(layout.floats(&uv, false)));
    }
    if let Some(uv) = &attributes.uv1 {
        let uv: Vec<[f32; 2]> = uv.iter().map(|x| x.to_array()).collect();
        vertex_attributes.insert("TEXCOORD_1".into(), json!(layout.floats(&uv, false)));
    }
    if let Some(colors) = &attributes.colors {
        let c: Vec<[f32; 4]> = colors.iter().map(|x| x.to_array()).collect();
        vertex_attributes.insert("COLOR_0".into(), json!(layout.floats(&c, false)));
    }

    let assets = materials.and_then(|m| m.gltf.as_ref());
    let mut root = Map::new();
    let mut material_count = 0;
    if let Some(assets) = assets {
        root.extend(assets.json.clone());
        material_count = assets.material_count();
        if let Some(Value::Array(images)) = root.get_mut("images") {
            for (i, bytes) in &assets.embedded_images {
                let view = layout.view(bytes, None);
                if let Some(image) = images.get_mut(*i) {
                    image["bufferView"] = json!(view);
                }
            }
        }
    } else if let Some(m) = materials
        && attributes.face_material.is_some()
        && !m.names.is_empty()
    {
        material_count = m.names.len();
        root.insert(
            "materials".into(),
            Value::Array(m.names.iter().map(|n| json!({ "name": n })).collect()),
        );
    }
    root.entry("asset")
        .or_insert_with(|| json!({ "version": "2.0", "generator": "gng3d" }));

    // One primitive per material, in material order.
    let mut groups: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (f, c) in attributes.corners.iter().enumerate() {
        let m = attributes.face_material.as_ref().map_or(u32::MAX, |m| m[f]);
        groups.entry(m).or_default().extend_from_slice(c);
    }
    let mut primitives = Vec::new();
    for (m, indices) in &groups {
        let accessor = layout.indices(indices, wedges);
        let mut p = json!({ "attributes": vertex_attributes, "indices": accessor, "mode": 4 });
        if (*m as usize) < material_count {
            p["material"] = json!(m);
        }
        primitives.push(p);
    }
    while !layout.bin.len().is_multiple_of(4) {
        layout.bin.push(0);
    }
    root.insert("scene".into(), json!(0));
    root.insert("scenes".into(), json!([{ "nodes": [0] }]));
    // A model far from its coordinates' origin: the origin as the node's translation (f64 in
    // the JSON), the positions relative to it (f32 keeps them to the model's own precision).
    root.insert(
        "nodes".into(),
        if origin == DVec3::ZERO {
            json!([{ "mesh": 0 }])
        } else {
            json!([{ "mesh": 0, "translation": origin.to_array() }])
        },
    );
    root.insert("meshes".into(), json!([{ "primitives": primitives }]));
    root.insert("accessors".into(), Value::Array(layout.accessors));
    root.insert("bufferViews".into(), Value::Array(layout.views));
    let mut buffer = json!({ "byteLength": layout.bin.len() });
    let mut bin = None;
    match storage {
        BufferStorage::Glb => {}
        BufferStorage::DataUri => {
            buffer["uri"] = json!(format!(
                "data:application/octet-stream;base64,{}",
                base64_encode(&layout.bin)
            ));
        }
        BufferStorage::File(name) => {
            buffer["uri"] = json!(percent_encode(name));
        }
    }
    root.insert("buffers".into(), json!([buffer]));
    let text = serde_json::to_vec(&Value::Object(root)).expect("JSON values serialize");
    let main = match storage {
        BufferStorage::Glb => glb(text, &layout.bin),
        BufferStorage::File(_) => {
            bin = Some(layout.bin);
            text
        }
        BufferStorage::DataUri => text,
    };
    Written { main, bin }
}

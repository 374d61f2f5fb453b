//! glTF reading and writing: round trips, node transforms, index widths, strips and fans,
//! normalized colours, warnings, errors, and (when installed) the Khronos validator.

use super::*;
use crate::AttributeKind as K;
use crate::Model;
use crate::io::{Format, load, load_bytes, save};
use crate::procedural::textured_sphere;
use std::fs;

/// An 8 × 8 RGB checkerboard PNG (86 bytes), the procedural texture of the test assets.
const CHECKER_PNG: [u8; 86] = [
    137, 80, 78, 71, 13, 10, 26, 10, 0, 0, 0, 13, 73, 72, 68, 82, 0, 0, 0, 8, 0, 0, 0, 8, 8, 2, 0,
    0, 0, 75, 109, 41, 220, 0, 0, 0, 29, 73, 68, 65, 84, 120, 218, 99, 80, 112, 56, 0, 68, 255,
    193, 0, 153, 205, 128, 83, 2, 83, 8, 194, 198, 45, 65, 7, 59, 0, 90, 69, 131, 161, 176, 177,
    134, 134, 0, 0, 0, 0, 73, 69, 78, 68, 174, 66, 96, 130,
];

/// A hand-built glTF (independent of the writer under test): accessors appended to one buffer.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    /// Appends `bytes` as a buffer view and an accessor over it; returns the accessor index.
    fn accessor(&mut self, bytes: &[u8], component: u32, count: usize, kind: &str) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.accessors.push(json!({
            "bufferView": self.views.len() - 1, "componentType": component, "count": count, "type": kind
        }));
        self.accessors.len() - 1
    }

    fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        let bytes: Vec<u8> = p.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        let a = self.accessor(&bytes, 5126, p.len(), "VEC3");
        let min: Vec<f32> = (0..3)
            .map(|k| p.iter().map(|v| v[k]).fold(f32::INFINITY, f32::min))
            .collect();
        let max: Vec<f32> = (0..3)
            .map(|k| p.iter().map(|v| v[k]).fold(f32::NEG_INFINITY, f32::max))
            .collect();
        self.accessors[a]["min"] = json!(min);
        self.accessors[a]["max"] = json!(max);
        a
    }

    fn floats(&mut self, v: &[f32], kind: &str) -> usize {
        let n = match kind {
            "VEC2" => 2,
            "VEC3" => 3,
            _ => 4,
        };
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, 5126, v.len() / n, kind)
    }

    fn indices(&mut self, i: &[u32], component: u32) -> usize {
        let bytes: Vec<u8> = match component {
            5121 => i.iter().map(|&x| x as u8).collect(),
            5123 => i.iter().flat_map(|&x| (x as u16).to_le_bytes()).collect(),
            _ => i.iter().flat_map(|&x| x.to_le_bytes()).collect(),
        };
        self.accessor(&bytes, component, i.len(), "SCALAR")
    }

    /// The document: `rest` (meshes, nodes, scenes, ...) with the buffer, views and accessors.
    fn document(&self, mut rest: Value, uri: Option<&str>) -> Value {
        rest["asset"] = json!({"version": "2.0"});
        rest["accessors"] = json!(self.accessors);
        rest["bufferViews"] = json!(self.views);
        rest["buffers"] = json!([{"byteLength": self.bin.len()}]);
        if let Some(uri) = uri {
            rest["buffers"][0]["uri"] = json!(uri);
        }
        rest
    }

    /// A `.glb` container (written here, not by the module's writer).
    fn glb(&self, rest: Value) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.document(rest, None)).unwrap();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(((28 + json.len() + bin.len()) as u32).to_le_bytes());
        out.extend((json.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(json);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }
}

/// A unit quad in z = 0 (two triangles, four vertices) with normals +Z and per-vertex UVs.
fn quad(b: &mut Builder, index_component: u32) -> Value {
    let p = b.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let n = b.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3");
    let uv = b.floats(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], "VEC2");
    let i = b.indices(&[0, 1, 2, 0, 2, 3], index_component);
    json!({"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": uv}, "indices": i})
}

fn parse_glb(bytes: &[u8]) -> Result<crate::io::LoadedMesh, MeshError> {
    load_bytes(bytes, Format::Glb, Path::new("test.glb"))
}

/// Each corner's (position, uv0, uv1, normal, colour) as bits, in triangle order.
fn corner_bits(mesh: &TriMesh, a: &Attributes) -> Vec<Vec<u32>> {
    let mut out = Vec::new();
    for (t, c) in mesh.triangles.iter().zip(&a.corners) {
        for k in 0..3 {
            let w = c[k] as usize;
            let mut v: Vec<f32> = mesh.positions[t[k] as usize].to_array().to_vec();
            v.extend(a.uv0.as_ref().map_or([0.0; 2], |x| x[w].to_array()));
            v.extend(a.uv1.as_ref().map_or([0.0; 2], |x| x[w].to_array()));
            v.extend(a.normals.as_ref().map_or([0.0; 3], |x| x[w].to_array()));
            v.extend(a.colors.as_ref().map_or([0.0; 4], |x| x[w].to_array()));
            out.push(v.into_iter().map(f32::to_bits).collect());
        }
    }
    out
}

/// A textured sphere with every attribute the writer keeps: normals, two UV sets, colours and
/// two materials (the northern and southern faces), with glTF assets holding a checker texture
/// (embedded, or as `checker.png` next to the file when `external`).
fn textured_asset(external: bool) -> (TriMesh, Attributes, Materials) {
    let (mesh, mut a) = textured_sphere(12, 16);
    let uv0 = a.uv0.clone().unwrap();
    a.uv1 = Some(uv0.iter().map(|u| Vec2::new(u.y, u.x * 0.5)).collect());
    a.colors = Some(
        a.wedge_vertex
            .iter()
            .map(|&v| {
                let p = mesh.positions[v as usize];
                Vec4::new(p.x * 0.5 + 0.5, p.y * 0.5 + 0.5, p.z * 0.5 + 0.5, 1.0)
            })
            .collect(),
    );
    // Materials by hemisphere; the faces are reordered so that each material's faces are
    // consecutive (the writer writes one primitive per material, in material order).
    let north = |f: usize| mesh.triangle(f).iter().map(|p| p.z).sum::<f32>() > 0.0;
    let order: Vec<usize> = (0..mesh.face_count())
        .filter(|&f| north(f))
        .chain((0..mesh.face_count()).filter(|&f| !north(f)))
        .collect();
    let mesh = TriMesh::new(
        mesh.positions.clone(),
        order.iter().map(|&f| mesh.triangles[f]).collect(),
    );
    a.corners = order.iter().map(|&f| a.corners[f]).collect();
    a.face_material = Some(order.iter().map(|&f| u32::from(!north(f))).collect());
    a.validate(&mesh).unwrap();
    let image = if external {
        json!({"uri": "checker.png"})
    } else {
        json!({"mimeType": "image/png"})
    };
    let mut assets = GltfAssets {
        json: serde_json::from_value(json!({
            "asset": {"version": "2.0", "generator": "gng3d test", "copyright": "CC0"},
            "materials": [
                {"name": "checker", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
                  "extensions": {"KHR_texture_transform": {"scale": [2.0, 2.0]}}}, "metallicFactor": 0.0}},
                {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.0, 0.0, 1.0]},
                 "extensions": {"KHR_materials_unlit": {}}}
            ],
            "textures": [{"source": 0, "sampler": 0}],
            "samplers": [{"magFilter": 9728, "minFilter": 9728}],
            "images": [image],
            "extensionsUsed": ["KHR_texture_transform", "KHR_materials_unlit"],
        }))
        .unwrap(),
        ..GltfAssets::default()
    };
    if !external {
        assets
            .embedded_images
            .push((0, Arc::from(&CHECKER_PNG[..])));
    }
    let materials = Materials {
        names: vec!["checker".into(), "red".into()],
        libraries: Vec::new(),
        gltf: Some(assets),
    };
    (mesh, a, materials)
}

/// Checks that `back` holds what `mesh`/`a` held: counts, every corner's values bit for bit,
/// materials, seams.
fn assert_same(mesh: &TriMesh, a: &Attributes, back: &crate::io::LoadedMesh) {
    let b = back.attributes.as_ref().expect("attributes");
    b.validate(&back.mesh).unwrap();
    assert_eq!(back.mesh.vertex_count(), mesh.vertex_count());
    assert_eq!(back.mesh.face_count(), mesh.face_count());
    assert_eq!(b.wedge_count(), a.wedge_count());
    assert_eq!(b.kinds(), a.kinds());
    let (got, want) = (corner_bits(&back.mesh, b), corner_bits(mesh, a));
    assert_eq!(got.len(), want.len());
    if let Some(i) = (0..got.len()).find(|&i| got[i] != want[i]) {
        panic!("corner {i}: {:?} vs {:?}", got[i], want[i]);
    }
    assert_eq!(b.face_material, a.face_material);
    assert_eq!(b.seam_edges(&back.mesh).len(), a.seam_edges(mesh).len());
    assert_eq!(
        crate::topology::analyze(&back.mesh).genus,
        crate::topology::analyze(mesh).genus
    );
}

#[test]
fn textured_glb_and_gltf_round_trip_bit_exact() {
    let dir = tempfile::tempdir().unwrap();
    for (name, external) in [
        ("sphere.glb", false),
        ("sphere.gltf", false),
        ("ext.gltf", true),
        ("ext.glb", true),
    ] {
        let (mesh, a, materials) = textured_asset(external);
        let src = dir.path().join("src");
        fs::create_dir_all(&src).unwrap();
        fs::write(src.join("checker.png"), CHECKER_PNG).unwrap();
        let path = src.join(name);
        let mut m = materials.clone();
        m.gltf.as_mut().unwrap().source_dir = src.clone();
        let warnings = save(
            &Model::new(mesh.clone(), Some(a.clone()), Some(m.clone())),
            &path,
        )
        .unwrap()
        .dropped;
        assert!(warnings.is_empty(), "{warnings:?}");
        if name.ends_with(".gltf") {
            let stem = name.trim_end_matches(".gltf");
            assert!(src.join(format!("{stem}.bin")).exists());
        }
        let back = load(&path).unwrap();
        assert!(back.warnings.is_empty(), "{name}: {:?}", back.warnings);
        assert_same(&mesh, &a, &back);
        let got = back.materials.as_ref().unwrap();
        assert_eq!(got.names, materials.names);
        let assets = got.gltf.as_ref().unwrap();
        let want = materials.gltf.as_ref().unwrap();
        assert_eq!(assets.json, want.json, "{name}: carried JSON");
        assert_eq!(
            assets.embedded_images, want.embedded_images,
            "{name}: image bytes"
        );

        // glTF -> load -> save (another folder, the other container) -> load.
        let out_dir = dir.path().join(format!("out-{name}"));
        fs::create_dir_all(&out_dir).unwrap();
        for out_name in ["again.glb", "again.gltf"] {
            let out = out_dir.join(out_name);
            let w = save(
                &Model::new(
                    back.mesh.clone(),
                    Some(back.attributes.as_ref().unwrap().clone()),
                    back.materials.clone(),
                ),
                &out,
            )
            .unwrap()
            .dropped;
            assert!(w.is_empty(), "{w:?}");
            let again = load(&out).unwrap();
            assert_same(&mesh, &a, &again);
            let again_assets = again.materials.as_ref().unwrap().gltf.as_ref().unwrap();
            assert_eq!(again_assets.json, want.json);
            assert_eq!(again_assets.embedded_images, want.embedded_images);
            // An external texture is copied next to the output, byte for byte.
            assert_eq!(
                out_dir.join("checker.png").exists(),
                external,
                "{name} -> {out_name}"
            );
            if external {
                assert_eq!(fs::read(out_dir.join("checker.png")).unwrap(), CHECKER_PNG);
            }
            // Written again: the same bytes.
            let third = out_dir.join(format!("third-{out_name}"));
            save(
                &Model::new(
                    again.mesh.clone(),
                    Some(again.attributes.as_ref().unwrap().clone()),
                    again.materials.clone(),
                ),
                &third,
            )
            .unwrap();
            let strip = |p: &Path| fs::read(p).unwrap();
            if out_name.ends_with(".glb") {
                assert_eq!(
                    strip(&third),
                    strip(&out),
                    "{name} -> {out_name}: stable bytes"
                );
            } else {
                assert_eq!(
                    strip(&third.with_extension("bin")),
                    strip(&out.with_extension("bin"))
                );
            }
        }
    }
}

#[test]
fn hand_built_gltf_with_external_bin_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::default();
    let prim = quad(&mut b, 5123);
    let doc = b.document(
        json!({"meshes": [{"primitives": [prim]}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}),
        Some("quad%20data.bin"),
    );
    fs::write(dir.path().join("quad data.bin"), &b.bin).unwrap();
    let path = dir.path().join("quad.gltf");
    fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let l = load(&path).unwrap();
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    assert_eq!((l.mesh.vertex_count(), l.mesh.face_count()), (4, 2));
    let a = l.attributes.as_ref().unwrap();
    assert_eq!(a.kinds(), vec![K::Normals, K::Uv0]);
    assert_eq!(a.uv0.as_ref().unwrap()[2], Vec2::ONE);
    assert_eq!(l.mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
    let out = dir.path().join("out.glb");
    save(
        &Model::new(l.mesh.clone(), Some(a.clone()), l.materials.clone()),
        &out,
    )
    .unwrap();
    assert_same(&l.mesh, a, &load(&out).unwrap());
    // A data: URI buffer reads the same.
    let inline = b.document(
        json!({"meshes": [{"primitives": [quad(&mut Builder::default(), 5123)]}]}),
        Some(&format!(
            "data:application/octet-stream;base64,{}",
            base64_encode(&b.bin)
        )),
    );
    let l2 = load_bytes(
        &serde_json::to_vec(&inline).unwrap(),
        Format::Gltf,
        &dir.path().join("x.gltf"),
    )
    .unwrap();
    assert_eq!(l2.mesh, l.mesh);
}

#[test]
fn node_transforms_are_applied_in_world_space() {
    let mut b = Builder::default();
    let prim = quad(&mut b, 5123);
    // Scene: node 1 (scale 2) with child node 0 (translation (1, 2, 3), the quad); node 2: the
    // quad again, rotated 90° about z; node 3: mirrored in x (the winding must flip).
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let glb = b.glb(json!({
        "meshes": [{"primitives": [prim]}],
        "nodes": [
            {"mesh": 0, "translation": [1.0, 2.0, 3.0]},
            {"scale": [2.0, 2.0, 2.0], "children": [0]},
            {"mesh": 0, "rotation": [0.0, 0.0, s, s], "translation": [0.0, 0.0, 10.0]},
            {"mesh": 0, "matrix": [-1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 20.0, 1.0]},
            {"mesh": 0, "translation": [100.0, 0.0, 0.0]}
        ],
        "scenes": [{"nodes": [4]}, {"nodes": [1, 2, 3]}],
        "scene": 1
    }));
    let l = parse_glb(&glb).unwrap();
    assert_eq!(
        l.mesh.face_count(),
        6,
        "three instances of the quad, not node 4's scene"
    );
    let quad = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let a = l.attributes.as_ref().unwrap();
    let corner_pos = |f: usize, k: usize| l.mesh.positions[l.mesh.triangles[f][k] as usize];
    // Instance 1: p -> 2 (p + (1, 2, 3)).
    for (f, t) in [[0, 1, 2], [0, 2, 3]].iter().enumerate() {
        for k in 0..3 {
            let p = quad[t[k]];
            let want = Vec3::new(2.0 * (p[0] + 1.0), 2.0 * (p[1] + 2.0), 2.0 * (p[2] + 3.0));
            assert_eq!(corner_pos(f, k), want);
        }
    }
    // Instance 2: (x, y, z) -> (-y, x, z + 10); normals stay +z.
    for k in 0..3 {
        let p = quad[[0, 1, 2][k]];
        let got = corner_pos(2, k);
        assert!(
            (got - Vec3::new(-p[1], p[0], p[2] + 10.0)).length() < 1e-6,
            "{got}"
        );
    }
    // Instance 3: mirrored, so the face normal must still agree with the (mirrored) +z normal
    // only after the winding flip: the loaded triangles face +z.
    let normals = l.mesh.face_normals();
    assert_eq!(normals.len(), 6);
    for (f, (normal, corners)) in normals.iter().zip(&a.corners).enumerate() {
        assert!(normal.z > 0.99, "face {f}: {normal}");
        for &w in corners {
            assert!((a.normals.as_ref().unwrap()[w as usize] - Vec3::Z).length() < 1e-6);
        }
    }
    assert!(corner_pos(4, 0).x <= 0.0 && corner_pos(4, 0).z == 20.0);
    // A normal is transformed by the inverse transpose: a non-uniform scale of (1, 4, 1)
    // turns the normal (1, 1, 0)/√2 of a slanted plane into (4, 1, 0)/√17.
    let mut b = Builder::default();
    let p = b.positions(&[[0.0, 0.0, 0.0], [1.0, -1.0, 0.0], [0.0, 0.0, 1.0]]);
    let n = b.floats(&[s, s, 0.0].repeat(3), "VEC3");
    let glb = b.glb(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n}}]}],
        "nodes": [{"mesh": 0, "scale": [1.0, 4.0, 1.0]}],
        "scenes": [{"nodes": [0]}]
    }));
    let l = parse_glb(&glb).unwrap();
    let normal = l.attributes.unwrap().normals.unwrap()[0];
    let want = Vec3::new(4.0, 1.0, 0.0) / 17f32.sqrt();
    assert!((normal - want).length() < 1e-6, "{normal}");
    // The surface direction agrees: the scaled triangle's edge (1, -4, 0) is perpendicular.
    assert!(normal.dot(Vec3::new(1.0, -4.0, 0.0)).abs() < 1e-6);
}

#[test]
fn index_widths_and_no_indices_read_the_same() {
    let mut results = Vec::new();
    for component in [5121, 5123, 5125] {
        let mut b = Builder::default();
        let prim = quad(&mut b, component);
        results.push(parse_glb(&b.glb(json!({"meshes": [{"primitives": [prim]}]}))).unwrap());
    }
    for r in &results[1..] {
        assert_eq!(r.mesh, results[0].mesh);
        assert_eq!(r.attributes, results[0].attributes);
    }
    assert_eq!(results[0].mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    // No indices: vertices taken three by three.
    let mut b = Builder::default();
    let p = b.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
    ]);
    let l =
        parse_glb(&b.glb(json!({"meshes": [{"primitives": [{"attributes": {"POSITION": p}}]}]})))
            .unwrap();
    assert_eq!(l.mesh.triangles, vec![[0, 1, 2], [3, 4, 5]]);
    // More than 65,535 wedges are written with unsigned int indices and read back.
    let (mesh, a) = textured_sphere(200, 400);
    assert!(a.wedge_count() > 65535);
    let bytes = gltf_bytes(&mesh, &a, Format::Glb);
    let l = parse_glb(&bytes).unwrap();
    assert_same(&mesh, &a, &l);
    let text = String::from_utf8_lossy(&bytes);
    assert!(text.contains("\"componentType\":5125"));
}

fn gltf_bytes(mesh: &TriMesh, a: &Attributes, format: Format) -> Vec<u8> {
    crate::io::encode_with_attributes(mesh, a, None, format, Path::new("x"))
        .unwrap()
        .0
}

#[test]
fn strips_and_fans_are_triangulated_points_and_lines_dropped_with_a_warning() {
    let mut b = Builder::default();
    let grid = [
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
    ];
    let p = b.positions(&grid);
    let lifted: Vec<[f32; 3]> = grid.iter().map(|q| [q[0], q[1], 5.0]).collect();
    let q = b.positions(&lifted);
    let strip = b.indices(&[1, 0, 3, 2, 4], 5123);
    let fan = b.indices(&[0, 2, 3, 1], 5123);
    let glb = b.glb(json!({"meshes": [{"primitives": [
        {"attributes": {"POSITION": p}, "indices": strip, "mode": 5},
        {"attributes": {"POSITION": q}, "indices": fan, "mode": 6},
        {"attributes": {"POSITION": p}, "mode": 1},
        {"attributes": {"POSITION": p}, "mode": 0}
    ]}]}));
    let l = parse_glb(&glb).unwrap();
    // Strip 1 0 3 2 4: (1 0 3), (0 2 3) [odd: v1 v3 v2], (3 2 4); fan 0 2 3 1 on the second
    // vertex set (vertices 5..10): (2 3 0), (3 1 0). Positions only: no attributes.
    assert!(l.attributes.is_none());
    assert_eq!(
        l.mesh.triangles,
        vec![[1, 0, 3], [0, 2, 3], [3, 2, 4], [7, 8, 5], [8, 6, 5]]
    );
    assert!(
        l.warnings.iter().any(|w| w
            .to_string()
            .contains("2 glTF primitive(s) of points or lines")),
        "{:?}",
        l.warnings
    );
    // Every triangle is counter-clockwise seen from +z, as the strip's first one.
    assert!(l.mesh.face_normals().iter().all(|n| n.z > 0.99));
}

#[test]
fn points_and_lines_only_is_an_error_counting_their_vertices() {
    // Issue 46: a file of point and line primitives said "the mesh has no vertices".
    let mut b = Builder::default();
    let many: Vec<[f32; 3]> = (0..60).map(|i| [i as f32, (i % 7) as f32, 0.0]).collect();
    let p = b.positions(&many);
    let q = b.positions(&many[..6]);
    let glb = b.glb(json!({"meshes": [{"primitives": [
        {"attributes": {"POSITION": p}, "mode": 0},
        {"attributes": {"POSITION": p}, "mode": 1},
        {"attributes": {"POSITION": q}, "mode": 3}
    ]}]}));
    let e = parse_glb(&glb).expect_err("no triangles: an error");
    assert!(
        matches!(
            e,
            MeshError::NoTriangles {
                vertex_count: 66,
                primitives: 3,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "test.glb: the file has 66 vertices but only point/line primitives (3) and no triangles"
    );
}

#[test]
fn normalized_colours_and_sparse_accessors() {
    let mut b = Builder::default();
    let p = b.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let c8 = b.accessor(&[255, 0, 51, 0, 255, 0, 0, 0, 255], 5121, 3, "VEC3");
    b.accessors[c8]["normalized"] = json!(true);
    let c16: Vec<u8> = [65535u16, 0, 0, 32768, 0, 65535, 0, 65535, 0, 0, 65535, 0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let c16 = b.accessor(&c16, 5123, 3, "VEC4");
    b.accessors[c16]["normalized"] = json!(true);
    // TEXCOORD_0 all zero except a sparse override of vertex 2.
    let sparse_index = b.accessor(&2u16.to_le_bytes(), 5123, 1, "SCALAR");
    let sparse_value = b.floats(&[0.25, 0.75], "VEC2");
    let view_of = |b: &Builder, a: usize| b.accessors[a]["bufferView"].clone();
    let uv = json!({"componentType": 5126, "count": 3, "type": "VEC2", "sparse": {"count": 1,
        "indices": {"bufferView": view_of(&b, sparse_index), "componentType": 5123},
        "values": {"bufferView": view_of(&b, sparse_value)}}});
    b.accessors.push(uv);
    let uv = b.accessors.len() - 1;
    let glb8 = b.glb(json!({"meshes": [{"primitives": [{"attributes": {"POSITION": p, "COLOR_0": c8, "TEXCOORD_0": uv}}]}]}));
    let glb16 = b.glb(
        json!({"meshes": [{"primitives": [{"attributes": {"POSITION": p, "COLOR_0": c16}}]}]}),
    );
    let a = parse_glb(&glb8).unwrap().attributes.unwrap();
    assert_eq!(a.colors.as_ref().unwrap()[0], Vec4::new(1.0, 0.0, 0.2, 1.0));
    assert_eq!(
        a.uv0.as_ref().unwrap(),
        &vec![Vec2::ZERO, Vec2::ZERO, Vec2::new(0.25, 0.75)]
    );
    let a = parse_glb(&glb16).unwrap().attributes.unwrap();
    assert_eq!(
        a.colors.as_ref().unwrap()[0],
        Vec4::new(1.0, 0.0, 0.0, 32768.0 / 65535.0)
    );
}

#[test]
fn unknown_attributes_and_morph_targets_are_warnings() {
    let mut b = Builder::default();
    let mut prim = quad(&mut b, 5123);
    let t = b.floats(&[1.0, 0.0, 0.0, 1.0].repeat(4), "VEC4");
    prim["attributes"]["TANGENT"] = json!(t);
    prim["attributes"]["TEXCOORD_2"] = json!(prim["attributes"]["TEXCOORD_0"]);
    prim["targets"] = json!([{"POSITION": prim["attributes"]["NORMAL"]}]);
    let glb = b.glb(json!({"meshes": [{"primitives": [prim]}], "animations": []}));
    let l = parse_glb(&glb).unwrap();
    let text: Vec<String> = l.warnings.iter().map(ToString::to_string).collect();
    assert!(
        text.iter()
            .any(|w| w.contains("glTF vertex attributes TANGENT, TEXCOORD_2")),
        "{text:?}"
    );
    assert!(
        text.iter()
            .any(|w| w.contains("morph targets of 1 primitive")),
        "{text:?}"
    );
    assert_eq!(l.mesh.face_count(), 2);
}

#[test]
fn obj_materials_become_named_gltf_materials() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, mut a) = textured_sphere(6, 8);
    let half = mesh.face_count() / 2;
    a.face_material = Some(
        (0..mesh.face_count())
            .map(|f| u32::from(f >= half))
            .collect(),
    );
    let mut materials = Materials {
        names: vec!["wood".into(), "metal".into()],
        ..Materials::default()
    };
    let path = dir.path().join("m.glb");
    let warnings = save(
        &Model::new(mesh.clone(), Some(a.clone()), Some(materials.clone())),
        &path,
    )
    .unwrap()
    .dropped;
    assert!(warnings.is_empty(), "{warnings:?}");
    // With an OBJ material library that cannot be read: a warning naming it, the names kept.
    materials.libraries.push(dir.path().join("m.mtl"));
    let warnings = save(
        &Model::new(mesh.clone(), Some(a.clone()), Some(materials.clone())),
        &dir.path().join("lib.gltf"),
    )
    .unwrap()
    .dropped;
    let library = dir.path().join("m.mtl");
    assert!(
        matches!(&warnings[..], [w]
            if w.starts_with(&format!("material file {} not copied: ", library.display()))
                && w.contains("names only")),
        "{warnings:?}"
    );
    let names = load(&dir.path().join("lib.gltf"))
        .unwrap()
        .materials
        .unwrap()
        .names;
    assert_eq!(names, materials.names);
    materials.libraries.clear();
    let l = load(&path).unwrap();
    assert_eq!(l.materials.as_ref().unwrap().names, materials.names);
    assert_eq!(
        l.attributes.as_ref().unwrap().face_material,
        a.face_material
    );
    assert_same(&mesh, &a, &l);
    // glTF materials written to OBJ: named in usemtl, a library made from them; what the MTL
    // cannot express is one warning.
    let (mesh2, a2, m2) = textured_asset(false);
    let w = save(
        &Model::new(mesh2.clone(), Some(a2.clone()), Some(m2.clone())),
        &dir.path().join("t.obj"),
    )
    .unwrap()
    .dropped;
    assert_eq!(
        w,
        [
            "dropped uv1: OBJ has one set of texture coordinates",
            "dropped glTF material properties KHR_materials_unlit, KHR_texture_transform (of \
          baseColorTexture), texture sampler filters and wrapping: an OBJ material library takes \
          the base colour and texture, roughness, metallic and emissive colour only"
        ]
    );
    let mtl = fs::read_to_string(dir.path().join("t.mtl")).unwrap();
    assert!(
        mtl.contains("newmtl checker\nKd 1 1 1\nNs 0\nPr 1\nPm 0\nmap_Kd t_image0.png\n"),
        "{mtl}"
    );
    assert!(
        mtl.contains("newmtl red\nKd 1 0 0\nNs 0\nPr 1\nPm 1\n"),
        "{mtl}"
    );
    assert_eq!(
        fs::read(dir.path().join("t_image0.png")).unwrap(),
        CHECKER_PNG
    );
    let back = load(&dir.path().join("t.obj")).unwrap();
    assert_eq!(back.materials.unwrap().names, m2.names);
    // Positions only through `save`: a .gltf with its .bin.
    let path = dir.path().join("plain.gltf");
    save(&mesh.clone().into(), &path).unwrap();
    assert!(dir.path().join("plain.bin").exists());
    let l = load(&path).unwrap();
    assert_eq!(l.mesh.face_count(), mesh.face_count());
    assert_eq!(l.mesh.vertex_count(), mesh.vertex_count());
}

/// The error message of loading `bytes` as `name` in `dir`.
fn load_error(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let path = dir.join(name);
    fs::write(&path, bytes).unwrap();
    let e = load(&path).expect_err("must fail").to_string();
    assert!(e.starts_with(&path.display().to_string()), "{e}");
    e
}

#[test]
fn bad_files_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut b = Builder::default();
    let prim = quad(&mut b, 5123);
    let good = b.glb(json!({"meshes": [{"primitives": [prim.clone()]}]}));
    // Truncated .glb at several points: an error, never a panic.
    for cut in [0, 5, 12, 20, good.len() / 2, good.len() - 1] {
        let e = load_error(d, "cut.glb", &good[..cut]);
        assert!(
            e.contains("truncated") || e.contains("fewer than") || e.contains("bytes"),
            "{cut}: {e}"
        );
    }
    // A chunk length beyond the file.
    let mut bad = good.clone();
    bad[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(load_error(d, "chunk.glb", &bad).contains("runs past the end"));
    // Missing .bin.
    let doc = b.document(
        json!({"meshes": [{"primitives": [prim.clone()]}]}),
        Some("missing.bin"),
    );
    let e = load_error(d, "nobin.gltf", &serde_json::to_vec(&doc).unwrap());
    assert!(e.contains("missing.bin") && e.contains("buffer 0"), "{e}");
    // A .bin shorter than declared.
    fs::write(d.join("short.bin"), &b.bin[..10]).unwrap();
    let doc = b.document(
        json!({"meshes": [{"primitives": [prim.clone()]}]}),
        Some("short.bin"),
    );
    assert!(load_error(d, "short.gltf", &serde_json::to_vec(&doc).unwrap()).contains("truncated"));
    // Index out of range.
    let mut b2 = Builder::default();
    let mut p2 = quad(&mut b2, 5123);
    p2["indices"] = json!(b2.indices(&[0, 1, 9], 5121));
    let e = load_error(
        d,
        "range.glb",
        &b2.glb(json!({"meshes": [{"primitives": [p2]}]})),
    );
    assert!(
        e.contains("refers to vertex 9") && e.contains("4 vertices"),
        "{e}"
    );
    // An accessor beyond its buffer view.
    let mut b3 = Builder::default();
    let p3 = quad(&mut b3, 5123);
    b3.accessors[1]["count"] = json!(40);
    let e = load_error(
        d,
        "view.glb",
        &b3.glb(json!({"meshes": [{"primitives": [p3]}]})),
    );
    assert!(e.contains("do not fit in buffer view"), "{e}");
    // Draco: an error naming the extension.
    let draco = b.glb(json!({"meshes": [{"primitives": [prim.clone()]}],
        "extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"]}));
    let e = load_error(d, "draco.glb", &draco);
    assert!(e.contains("KHR_draco_mesh_compression"), "{e}");
    let e = load_error(d, "meshopt.glb", &b.glb(json!({"meshes": [{"primitives": [prim.clone()]}], "extensionsRequired": ["EXT_meshopt_compression"]})));
    assert!(e.contains("EXT_meshopt_compression"), "{e}");
    // Required instancing places the geometry several times: refused, not read once silently;
    // only used, the plain mesh is the fallback, with a warning.
    let e = load_error(d, "inst.glb", &b.glb(json!({"meshes": [{"primitives": [prim.clone()]}],
        "extensionsUsed": ["EXT_mesh_gpu_instancing"], "extensionsRequired": ["EXT_mesh_gpu_instancing"]})));
    assert!(e.contains("requires EXT_mesh_gpu_instancing"), "{e}");
    let used = parse_glb(&b.glb(json!({"meshes": [{"primitives": [prim.clone()]}],
        "extensionsUsed": ["EXT_mesh_gpu_instancing", "EXT_future_thing"],
        "extensionsRequired": ["EXT_future_thing"]})))
    .unwrap();
    let w: Vec<String> = used.warnings.iter().map(ToString::to_string).collect();
    assert!(
        w.iter().any(|w| w.contains("EXT_mesh_gpu_instancing")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|w| w.contains("required glTF extension EXT_future_thing")),
        "{w:?}"
    );
    // Not JSON; not a glTF document; a dangling index.
    assert!(load_error(d, "text.gltf", b"hello").contains("JSON"));
    assert!(load_error(d, "nodoc.gltf", b"{\"meshes\": []}").contains("asset"));
    // A POSITION index past the accessors (gltf-json's own validation panicked on it; found
    // by the CLI fuzz, a GLB whose "accessors" key was mangled).
    let mut p5 = prim.clone();
    p5["attributes"]["POSITION"] = json!(99);
    let e = load_error(
        d,
        "dangling-position.glb",
        &b.glb(json!({"meshes": [{"primitives": [p5]}]})),
    );
    assert!(
        e.contains("mesh 0, primitive 0: POSITION names accessor 99"),
        "{e}"
    );
    let mut p4 = prim;
    p4["attributes"]["NORMAL"] = json!(99);
    let e = load_error(
        d,
        "dangling.glb",
        &b.glb(json!({"meshes": [{"primitives": [p4]}]})),
    );
    assert!(e.contains("invalid glTF"), "{e}");
    // A node cycle.
    let e = load_error(
        d,
        "cycle.glb",
        &b.glb(
            json!({"meshes": [{"primitives": [quad(&mut Builder::default(), 5123)]}],
        "nodes": [{"children": [1]}, {"children": [0], "mesh": 0}], "scenes": [{"nodes": [0]}]}),
        ),
    );
    assert!(e.contains("node 0: the node is reached twice"), "{e}");
    // A node with two parents (a diamond), which could make the walk exponential.
    let e = load_error(d, "diamond.glb", &b.glb(json!({"meshes": [{"primitives": [quad(&mut Builder::default(), 5123)]}],
        "nodes": [{"children": [1, 2]}, {"children": [3]}, {"children": [3]}, {"mesh": 0}], "scenes": [{"nodes": [0]}]})));
    assert!(e.contains("node 3: the node is reached twice"), "{e}");
}

/// Runs the Khronos glTF-Validator (npm `gltf-validator`, through
/// `tests/support/validate_gltf.cjs`) on written files when `node` and the module are found
/// (set GLTF_VALIDATOR_MODULE to the module's folder); says so when it skips.
#[test]
fn written_files_pass_the_khronos_validator_when_installed() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for (name, external) in [("v.glb", false), ("v.gltf", false), ("ve.gltf", true)] {
        let (mesh, a, mut materials) = textured_asset(external);
        fs::write(dir.path().join("checker.png"), CHECKER_PNG).unwrap();
        materials.gltf.as_mut().unwrap().source_dir = dir.path().to_path_buf();
        let path = dir.path().join(name);
        save(
            &Model::new(mesh.clone(), Some(a.clone()), Some(materials.clone())),
            &path,
        )
        .unwrap();
        files.push(path);
    }
    let (mesh, a) = textured_sphere(200, 400);
    let big = dir.path().join("big.glb");
    save(&Model::new(mesh.clone(), Some(a.clone()), None), &big).unwrap();
    files.push(big);
    // OBJ materials converted: the fandisk atlas's MTL colour and texture, embedded in a .glb
    // and copied next to a .gltf.
    let atlas = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/fandisk_atlas.obj");
    let obj = load(&atlas).unwrap();
    let converted = tempfile::tempdir().unwrap();
    for name in ["atlas.glb", "atlas.gltf"] {
        let path = converted.path().join(name);
        let w = save(
            &Model::new(
                obj.mesh.clone(),
                Some(obj.attributes.as_ref().unwrap().clone()),
                obj.materials.clone(),
            ),
            &path,
        )
        .unwrap()
        .dropped;
        assert!(w.is_empty(), "{w:?}");
        files.push(path);
    }
    let Some(reports) = crate::fixtures::validate_gltf(&files) else {
        return;
    };
    for report in &reports {
        assert_eq!(report["errors"], 0, "{report}");
        assert_eq!(report["warnings"], 0, "{report}");
        eprintln!("{report}");
    }
    assert_eq!(reports.len(), files.len());
}

#[test]
fn base64_round_trip() {
    for n in 0..20u8 {
        let bytes: Vec<u8> = (0..n).map(|i| i.wrapping_mul(37).wrapping_add(n)).collect();
        assert_eq!(base64_decode(&base64_encode(&bytes)).unwrap(), bytes);
    }
    assert_eq!(base64_encode(b"Man"), "TWFu");
    assert_eq!(base64_encode(b"Ma"), "TWE=");
    assert_eq!(base64_decode("TWE=").unwrap(), b"Ma");
    assert!(base64_decode("T*E=").is_none());
}

#[test]
fn uris() {
    assert_eq!(percent_decode("a%20b.png"), "a b.png");
    assert_eq!(percent_decode("100%"), "100%");
    assert_eq!(percent_encode("my mesh.bin"), "my%20mesh.bin");
    assert_eq!(
        relative_uri("tex/a%20b.png"),
        Some(PathBuf::from("tex/a b.png"))
    );
    assert_eq!(relative_uri("../a.png"), None);
    assert_eq!(relative_uri("data:image/png;base64,AAAA"), None);
}

/// Mutated and truncated files (random bytes changed in the GLB header, the JSON and the
/// binary chunk; JSON numbers replaced by huge or negative ones) load or fail with an error
/// naming the file: never a panic, never an allocation the file does not back.
#[test]
fn mutated_files_never_panic() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_pcg::Pcg64::seed_from_u64(35);
    let (mesh, a, materials) = textured_asset(false);
    let bytes = gltf_glb_with(&mesh, &a, &materials);
    let json_end = 20 + u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let (mut errors, mut loaded) = (0, 0);
    for case in 0..400 {
        let mut m = bytes.clone();
        match case % 4 {
            0 => m.truncate(rng.random_range(0..bytes.len())),
            1 => {
                for _ in 0..rng.random_range(1..8) {
                    let i = rng.random_range(0..m.len());
                    m[i] = rng.random();
                }
            }
            2 => {
                // A digit of the JSON replaced: counts, offsets and indices change.
                let digits: Vec<usize> =
                    (20..json_end).filter(|&i| m[i].is_ascii_digit()).collect();
                let i = digits[rng.random_range(0..digits.len())];
                m[i] = b'0' + rng.random_range(0..10u8);
            }
            _ => {
                // A number of the JSON made huge.
                let text = String::from_utf8_lossy(&m[20..json_end]).into_owned();
                let keys = [
                    "\"count\":",
                    "\"byteOffset\":",
                    "\"byteLength\":",
                    "\"indices\":",
                    "\"bufferView\":",
                ];
                let key = keys[rng.random_range(0..keys.len())];
                let text = text.replacen(key, &format!("{key}9999999999999"), 1);
                let mut json = text.into_bytes();
                while !json.len().is_multiple_of(4) {
                    json.push(b' ');
                }
                let mut out = m[..12].to_vec();
                out.extend((json.len() as u32).to_le_bytes());
                out.extend(b"JSON");
                out.extend(&json);
                out.extend(&m[json_end..]);
                let total = out.len() as u32;
                out[8..12].copy_from_slice(&total.to_le_bytes());
                m = out;
            }
        }
        match parse_glb(&m) {
            Ok(_) => loaded += 1,
            Err(e) => {
                assert!(e.to_string().starts_with("test.glb: "), "{e}");
                errors += 1;
            }
        }
    }
    eprintln!("mutated GLB files: {errors} errors, {loaded} loaded");
    // Most mutations break the file; the test would be empty if none did.
    assert!(errors > 200, "{errors} errors, {loaded} loaded");
}

fn gltf_glb_with(mesh: &TriMesh, a: &Attributes, materials: &Materials) -> Vec<u8> {
    crate::io::encode_with_attributes(mesh, a, Some(materials), Format::Glb, Path::new("x"))
        .unwrap()
        .0
}

/// KHR_mesh_quantization: positions as unnormalized shorts, normals as normalized bytes; the
/// extension is required by the input and not carried to the output (which writes floats).
#[test]
fn quantized_attributes_are_read() {
    let mut b = Builder::default();
    let p: Vec<u8> = [0i16, 0, 0, 0, 100, 0, 0, 0, 0, 100, 3, 0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    // Three VEC3 shorts padded to 8 bytes each (byteStride 8, as the extension requires).
    let p = b.accessor(&p, 5122, 3, "VEC3");
    b.views[b.accessors[p]["bufferView"].as_u64().unwrap() as usize]["byteStride"] = json!(8);
    b.accessors[p]["min"] = json!([0, 0, 0]);
    b.accessors[p]["max"] = json!([100, 100, 3]);
    let n = b.accessor(&[0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0], 5120, 3, "VEC3");
    b.views[b.accessors[n]["bufferView"].as_u64().unwrap() as usize]["byteStride"] = json!(4);
    b.accessors[n]["normalized"] = json!(true);
    let glb = b.glb(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n}}]}],
        "extensionsUsed": ["KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"]
    }));
    let l = parse_glb(&glb).unwrap();
    assert_eq!(
        l.mesh.positions,
        vec![
            Vec3::ZERO,
            Vec3::new(100.0, 0.0, 0.0),
            Vec3::new(0.0, 100.0, 3.0)
        ]
    );
    assert_eq!(
        l.attributes.as_ref().unwrap().normals.as_ref().unwrap(),
        &vec![Vec3::Z; 3]
    );
    let assets = l.materials.as_ref().unwrap().gltf.as_ref().unwrap();
    assert!(!assets.json().contains_key("extensionsRequired"));
    assert!(!assets.json().contains_key("extensionsUsed"));
}

/// The validator requires unit normals: longer ones are normalized, zero ones (a corner that
/// had none) take their triangle's normal; unit ones keep their bits.
#[test]
fn normals_are_written_unit_length() {
    let mesh = TriMesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
        vec![[0, 1, 2], [1, 3, 2]],
    );
    let mut a = Attributes::per_vertex(&mesh);
    let tilted = Vec3::new(0.6, 0.0, 0.8);
    a.normals = Some(vec![Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, tilted, Vec3::Z]);
    let back = parse_glb(&gltf_bytes(&mesh, &a, Format::Glb)).unwrap();
    let n = back.attributes.unwrap().normals.unwrap();
    assert_eq!(n, vec![Vec3::Z, Vec3::Z, tilted, Vec3::Z]);
}

//! Attributes through the readers and writers: round trips, materials, warnings, errors.

use super::*;
use crate::AttributeKind as K;
use crate::Model;
use crate::attributes::Attributes;
use crate::procedural::textured_sphere;
use std::fs;

/// The values of every corner (uv0, normal, colour) in triangle order, for comparing two
/// attribute sets of the same triangles whatever their wedge numbering.
fn corner_values(a: &Attributes) -> Vec<[f32; 9]> {
    let mut out = Vec::new();
    for c in &a.corners {
        for &w in c {
            let w = w as usize;
            let uv = a.uv0.as_ref().map_or(Vec2::ZERO, |v| v[w]);
            let n = a.normals.as_ref().map_or(Vec3::ZERO, |v| v[w]);
            let col = a.colors.as_ref().map_or(Vec4::ZERO, |v| v[w]);
            out.push([uv.x, uv.y, n.x, n.y, n.z, col.x, col.y, col.z, col.w]);
        }
    }
    out
}

fn assert_values_close(a: &Attributes, b: &Attributes, tol: f32) {
    let (va, vb) = (corner_values(a), corner_values(b));
    assert_eq!(va.len(), vb.len());
    for (i, (x, y)) in va.iter().zip(&vb).enumerate() {
        for k in 0..9 {
            assert!(
                (x[k] - y[k]).abs() <= tol,
                "corner {i} value {k}: {x:?} vs {y:?}"
            );
        }
    }
}

#[test]
fn obj_round_trip_keeps_uvs_normals_and_seams() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, attributes) = textured_sphere(8, 16);
    let path = dir.path().join("sphere.obj");
    let warnings = save(
        &Model::new(mesh.clone(), Some(attributes.clone()), None),
        &path,
    )
    .unwrap()
    .dropped;
    assert!(warnings.is_empty(), "{warnings:?}");
    let back = load(&path).unwrap();
    assert!(back.warnings.is_empty(), "{:?}", back.warnings);
    assert_eq!(back.mesh, mesh);
    let a = back.attributes.expect("attributes read back");
    a.validate(&back.mesh).unwrap();
    assert_eq!(a.kinds(), vec![K::Normals, K::Uv0]);
    assert_eq!(a.wedge_count(), attributes.wedge_count());
    assert_values_close(&a, &attributes, 0.0);
    assert_eq!(a.seam_edges(&back.mesh), attributes.seam_edges(&mesh));
    // Saved again and read again: the same bytes (wedges are numbered by first use).
    let again = dir.path().join("again.obj");
    save(
        &Model::new(back.mesh.clone(), Some(a.clone()), None),
        &again,
    )
    .unwrap();
    let third = dir.path().join("third.obj");
    let reread = load(&again).unwrap();
    let ra = reread.attributes.unwrap();
    assert_values_close(&ra, &attributes, 0.0);
    save(
        &Model::new(reread.mesh.clone(), Some(ra.clone()), None),
        &third,
    )
    .unwrap();
    assert!(fs::read(&third).unwrap() == fs::read(&again).unwrap());
}

#[test]
fn ply_round_trip_keeps_normals_uvs_and_colours() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, mut attributes) = textured_sphere(6, 12);
    let w = attributes.wedge_count();
    // Colours that survive 8-bit storage exactly.
    attributes.colors = Some(
        (0..w)
            .map(|i| {
                let k = |j: usize| ((i * 37 + j * 11) % 256) as f64 / 255.0;
                Vec4::new(k(0) as f32, k(1) as f32, k(2) as f32, 1.0)
            })
            .collect(),
    );
    let path = dir.path().join("sphere.ply");
    assert!(
        save(
            &Model::new(mesh.clone(), Some(attributes.clone()), None),
            &path
        )
        .unwrap()
        .dropped
        .is_empty()
    );
    let back = load(&path).unwrap();
    assert!(back.warnings.is_empty(), "{:?}", back.warnings);
    // One vertex record per wedge: the seam is split in the file ...
    assert_eq!(back.mesh.vertex_count(), w);
    let a = back.attributes.unwrap();
    assert_eq!(a.kinds(), vec![K::Normals, K::Uv0, K::Colors]);
    assert_values_close(&a, &attributes, 1e-5);
    // ... and the weld joins it again: the sphere's vertices, the same seams.
    let model = crate::Model {
        attributes: Some(a),
        ..back.mesh.into()
    };
    let (welded, report) = crate::clean::prepare(&model);
    let (welded, wa) = (welded.mesh, welded.attributes.unwrap());
    assert_eq!(welded.vertex_count(), mesh.vertex_count());
    assert_eq!(report.faces, mesh.face_count());
    wa.validate(&welded).unwrap();
    assert_eq!(wa.wedge_count(), attributes.wedge_count());
    assert_eq!(
        wa.seam_edges(&welded).len(),
        attributes.seam_edges(&mesh).len()
    );
    assert_values_close(&wa, &attributes, 1e-6);
}

#[test]
fn obj_materials_are_read_written_and_copied() {
    let src = tempfile::tempdir().unwrap();
    fs::create_dir(src.path().join("tex")).unwrap();
    fs::write(src.path().join("tex/wood.png"), b"not really a png").unwrap();
    fs::write(
        src.path().join("box.mtl"),
        "newmtl wood\nKd 1 1 1\nmap_Kd -bm 1 tex/wood.png\nnewmtl red\nKd 1 0 0\n",
    )
    .unwrap();
    let obj = "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
               usemtl wood\nf 1/1 2/2 3/3\nusemtl red\nf 1/1 3/3 4/4\n";
    let path = src.path().join("box.obj");
    fs::write(&path, obj).unwrap();
    let loaded = load(&path).unwrap();
    let materials = loaded.materials.clone().unwrap();
    assert_eq!(materials.names, vec!["wood", "red"]);
    assert_eq!(materials.libraries, vec![src.path().join("box.mtl")]);
    let a = loaded.attributes.clone().unwrap();
    assert_eq!(a.face_material, Some(vec![0, 1]));
    assert_eq!(a.seam_edges(&loaded.mesh), vec![[0, 2]]);

    let model = Model::new(
        loaded.mesh.clone(),
        Some(a.clone()),
        Some(materials.clone()),
    );
    let save_to = |to: &std::path::Path| save(&model, to);
    let out = tempfile::tempdir().unwrap();
    let to = out.path().join("copy.obj");
    let warnings = save_to(&to).unwrap().dropped;
    assert!(warnings.is_empty(), "{warnings:?}");
    // The library is written under the output's name, which the output names.
    let text = |p: std::path::PathBuf| fs::read_to_string(p).unwrap();
    assert_eq!(
        text(out.path().join("copy.mtl")),
        text(src.path().join("box.mtl"))
    );
    assert!(text(to.clone()).contains("mtllib copy.mtl\n"));
    assert_eq!(text(out.path().join("tex/wood.png")), "not really a png");
    let back = load(&to).unwrap();
    assert_eq!(back.materials.unwrap().names, vec!["wood", "red"]);
    assert_eq!(back.attributes.unwrap().face_material, Some(vec![0, 1]));

    // Someone else's box.mtl and tex/wood.png already in the output's folder: neither is
    // named nor replaced; the texture is copied under a new name that the library names.
    let crowded = tempfile::tempdir().unwrap();
    fs::create_dir(crowded.path().join("tex")).unwrap();
    fs::write(crowded.path().join("box.mtl"), "newmtl other\nKd 0 1 0\n").unwrap();
    fs::write(crowded.path().join("tex/wood.png"), b"someone else's").unwrap();
    let to = crowded.path().join("result.obj");
    let dropped = save_to(&to).unwrap().dropped;
    assert_eq!(dropped.len(), 1, "{dropped:?}");
    assert!(
        dropped[0].contains("written as tex/result-wood.png"),
        "{dropped:?}"
    );
    let at = |name: &str| text(crowded.path().join(name));
    assert_eq!(at("tex/result-wood.png"), "not really a png");
    assert_eq!(at("tex/wood.png"), "someone else's");
    assert_eq!(at("box.mtl"), "newmtl other\nKd 0 1 0\n");
    assert!(at("result.obj").contains("mtllib result.mtl\n"));
    assert_eq!(
        at("result.mtl"),
        "newmtl wood\nKd 1 1 1\nmap_Kd -bm 1 tex/result-wood.png\nnewmtl red\nKd 1 0 0\n"
    );
    let back = load(&to).unwrap();
    assert_eq!(back.materials.unwrap().names, vec!["wood", "red"]);

    // A library that is gone: the mesh is written, the copy is a warning naming the file.
    fs::remove_file(src.path().join("box.mtl")).unwrap();
    let out2 = tempfile::tempdir().unwrap();
    let warnings = save_to(&out2.path().join("c.obj")).unwrap().dropped;
    let gone = src.path().join("box.mtl");
    assert!(
        matches!(&warnings[..], [w] if w.starts_with(&format!("material library {} not read", gone.display()))),
        "{warnings:?}"
    );
}

#[test]
fn unread_data_and_missing_corners_are_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
               property float quality\nelement face 1\nproperty list uchar int vertex_indices\n\
               property uchar flags\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
               0 0 0 255 0 0 1\n1 0 0 0 255 0 1\n0 1 0 0 0 255 1\n3 0 1 2 7\n0 1\n";
    let loaded = load(&write(dir.path(), "c.ply", ply.as_bytes())).unwrap();
    let text: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        text,
        vec![
            "ignored PLY vertex properties quality (not read, not written to any output)",
            "ignored PLY face properties flags (not read, not written to any output)",
            "ignored PLY element edge (1 records) (not read, not written to any output)",
        ]
    );
    let colors = loaded.attributes.unwrap().colors.unwrap();
    assert_eq!(colors[1], Vec4::new(0.0, 1.0, 0.0, 1.0));

    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvp 0.5\nf 1/1 2/1 3/1\nf 2 4 3\n";
    let loaded = load(&write(dir.path(), "m.obj", obj.as_bytes())).unwrap();
    assert!(
        loaded
            .warnings
            .contains(&MeshWarning::MissingCornerAttribute {
                attribute: "uv0".into(),
                count: 3
            })
    );
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.to_string().contains("1 OBJ vp"))
    );

    // Vertex colours in OBJ `v x y z r g b` (per vertex, no seams).
    let obj = "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n";
    let loaded = load(&write(dir.path(), "col.obj", obj.as_bytes())).unwrap();
    assert!(loaded.warnings.is_empty());
    let a = loaded.attributes.unwrap();
    assert_eq!(a.colors.as_ref().unwrap()[2], Vec4::new(0.0, 0.0, 1.0, 1.0));
    // STL keeps none of it: a warning says so.
    let (_, warnings) =
        encode_with_attributes(&loaded.mesh, &a, None, Format::Stl, Path::new("x.stl")).unwrap();
    assert_eq!(
        warnings[0].to_string(),
        "dropped colors: STL stores positions only"
    );
}

#[test]
fn obj_vt_and_vn_no_face_uses_are_ignored_with_one_warning_each() {
    // Issue 46: faces `f 1 2 3` in a file with `vt`/`vn` records gave every corner a zero
    // normal and UV, with a warning that corners lacked what others have.
    let dir = tempfile::tempdir().unwrap();
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n\
               f 1 2 3\nf 2 4 3\n";
    let loaded = load(&write(dir.path(), "unused.obj", obj.as_bytes())).unwrap();
    let text: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        text,
        vec![
            "ignored the file's 3 OBJ vt (texture coordinate) record(s), which no face uses \
             (not read, not written to any output)",
            "ignored the file's 1 OBJ vn (normal) record(s), which no face uses \
             (not read, not written to any output)",
        ]
    );
    assert!(
        loaded
            .attributes
            .as_ref()
            .is_none_or(|a| a.uv0.is_none() && a.normals.is_none()),
        "{:?}",
        loaded.attributes.map(|a| a.kinds())
    );

    // Normals used by every corner, `vt` by none: normals kept, texture coordinates ignored.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1//1 2//1 3//1\n";
    let loaded = load(&write(dir.path(), "normals.obj", obj.as_bytes())).unwrap();
    let text: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        text,
        vec![
            "ignored the file's 1 OBJ vt (texture coordinate) record(s), which no face uses \
             (not read, not written to any output)"
        ]
    );
    let a = loaded.attributes.unwrap();
    assert!(a.uv0.is_none());
    assert_eq!(a.normals.unwrap(), vec![Vec3::Z; 3]);

    // With a material: materials kept, still no texture coordinates or normals.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl red\nf 1 2 3\n";
    let loaded = load(&write(dir.path(), "mat.obj", obj.as_bytes())).unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    let a = loaded.attributes.unwrap();
    assert_eq!(a.kinds(), vec![K::Materials]);
}

#[test]
fn bad_attribute_references_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n";
    let err = load(&write(dir.path(), "bad.obj", obj.as_bytes())).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "{}: parse error at line 5: face refers to texture coordinate 2, but 1 are defined before it",
            dir.path().join("bad.obj").display()
        )
    );
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0\nf 1 2 3\n";
    let err = load(&write(dir.path(), "n.obj", obj.as_bytes())).unwrap_err();
    assert!(
        err.to_string()
            .contains("line 4: vertex normal needs 3 values")
    );
    // Attributes that do not fit the mesh are a write error, not a panic.
    let (mesh, mut a) = textured_sphere(3, 4);
    a.corners.pop();
    let err = save(
        &Model::new(mesh.clone(), Some(a.clone()), None),
        &dir.path().join("x.obj"),
    )
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("the attributes do not fit the mesh")
    );
}

#[test]
fn spot_loads_with_its_texture_coordinates() {
    let Some(dir) = crate::fixtures::shared_meshes_dir("spot.obj") else {
        return;
    };
    let loaded = load(&dir.join("spot.obj")).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let a = loaded.attributes.unwrap();
    a.validate(&loaded.mesh).unwrap();
    assert_eq!(a.kinds(), vec![K::Uv0]);
    assert_eq!(loaded.mesh.vertex_count(), 2930);
    assert!(a.wedge_count() >= 3225, "{} wedges", a.wedge_count());
    assert!(!a.seam_edges(&loaded.mesh).is_empty());
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    fs::write(&p, bytes).unwrap();
    p
}

#[test]
fn ply_without_seams_keeps_the_vertex_numbering() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = crate::procedural::icosphere(2);
    let mut a = Attributes::per_vertex(&mesh);
    a.normals = Some(mesh.vertex_normals());
    // Wedges listed in another order than the vertices: the file still follows the vertices.
    a.wedge_vertex.reverse();
    let n = mesh.vertex_count() as u32;
    for c in &mut a.corners {
        for w in c.iter_mut() {
            *w = n - 1 - *w;
        }
    }
    a.normals.as_mut().unwrap().reverse();
    a.validate(&mesh).unwrap();
    let path = dir.path().join("s.ply");
    save(&Model::new(mesh.clone(), Some(a.clone()), None), &path).unwrap();
    let back = load(&path).unwrap();
    assert_eq!(back.mesh, mesh);
    assert_eq!(back.vertex_normals.unwrap(), mesh.vertex_normals());
}

#[test]
fn non_finite_attribute_values_drop_that_attribute_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt nan 0\nvt 0 1\nvn 0 0 1\n\
               f 1/1/1 2/2/1 3/3/1\n";
    let loaded = load(&write(dir.path(), "nan.obj", obj.as_bytes())).unwrap();
    assert_eq!(
        loaded.warnings,
        vec![MeshWarning::AttributesDropped {
            attributes: "uv0".into(),
            reason: "value 1 is not a finite number".into()
        }]
    );
    let a = loaded.attributes.unwrap();
    assert_eq!(a.kinds(), vec![K::Normals]);
    a.validate(&loaded.mesh).unwrap();
}

#[test]
fn checked_save_keeps_what_the_format_stores_and_names_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, mut attributes) = textured_sphere(8, 16);
    // A second UV set, which OBJ does not store.
    attributes.uv1 = attributes.uv0.clone();
    let all = vec![K::Normals, K::Uv0, K::Uv1];
    for (name, kept) in [
        ("s.obj", vec![K::Normals, K::Uv0]),
        ("s.ply", vec![K::Normals, K::Uv0]),
        ("s.glb", all.clone()),
        ("s.gltf", all.clone()),
        ("s.stl", vec![]),
    ] {
        let path = dir.path().join(name);
        let report = save(
            &Model::new(mesh.clone(), Some(attributes.clone()), None),
            &path,
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(report.input, attributes.kinds(), "{name}");
        assert_eq!(report.kept, kept, "{name}");
        // Each attribute not kept is named in a sentence; nothing else is said.
        for lost in attributes.kinds().iter().filter(|n| !kept.contains(n)) {
            assert!(
                report
                    .dropped
                    .iter()
                    .any(|d| d.contains(lost.name()) || d.contains("STL")),
                "{name}: {lost} not named in {:?}",
                report.dropped
            );
        }
        assert_eq!(
            report.dropped.is_empty(),
            kept.len() == 3,
            "{name}: {:?}",
            report.dropped
        );
        // What was written reads back with exactly what is said to be kept.
        let back = load(&path).unwrap();
        let names = back.attributes.map(|a| a.kinds()).unwrap_or_default();
        assert_eq!(names, kept, "{name}");
    }
    // A mesh the writer cannot give faces to is refused and nothing is written.
    let empty = TriMesh::new(mesh.positions.clone(), Vec::new());
    let none = Attributes {
        corners: Vec::new(),
        ..Attributes::default()
    };
    let path = dir.path().join("empty.obj");
    let err = save(&Model::new(empty.clone(), Some(none.clone()), None), &path).unwrap_err();
    assert!(err.to_string().contains("nothing written"), "{err}");
    assert!(!path.exists());
}

#[test]
fn a_gltf_is_written_as_gltf_and_bin_and_reads_back_with_every_attribute() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, mut attributes) = textured_sphere(8, 16);
    attributes.uv1 = attributes.uv0.clone();
    attributes.colors = Some(vec![
        Vec4::new(0.25, 0.5, 0.75, 1.0);
        attributes.wedge_count()
    ]);
    let path = dir.path().join("globe.gltf");
    let report = save(
        &Model::new(mesh.clone(), Some(attributes.clone()), None),
        &path,
    )
    .unwrap();
    assert_eq!(report.kept, vec![K::Normals, K::Uv0, K::Uv1, K::Colors]);
    assert!(report.dropped.is_empty(), "{:?}", report.dropped);
    // Two files and nothing else: the JSON names its buffer file, which holds the data.
    let mut files: Vec<String> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files, ["globe.bin", "globe.gltf"]);
    let json: serde_json::Value = serde_json::from_slice(&fs::read(&path).unwrap()).unwrap();
    assert_eq!(json["buffers"][0]["uri"], "globe.bin");
    assert_eq!(
        json["buffers"][0]["byteLength"].as_u64().unwrap(),
        fs::metadata(dir.path().join("globe.bin")).unwrap().len()
    );
    let back = load(&path).unwrap();
    assert!(back.warnings.is_empty(), "{:?}", back.warnings);
    assert_eq!(back.mesh.face_count(), mesh.face_count());
    let a = back.attributes.unwrap();
    assert_eq!(a.kinds(), attributes.kinds());
    assert_values_close(&a, &attributes, 1e-5);
    // Positions only through `save`: the same two files, the same check.
    let plain = dir.path().join("plain.gltf");
    save(&mesh.clone().into(), &plain).unwrap();
    assert!(dir.path().join("plain.bin").exists());
    assert_eq!(load(&plain).unwrap().mesh, mesh);
}

#[test]
fn positions_only_and_attribute_saves_refuse_the_same_outputs_and_write_nothing() {
    let (mesh, attributes) = textured_sphere(4, 8);
    // No triangles; and a NaN position, which every format encodes but none reads back.
    let empty = TriMesh::new(mesh.positions.clone(), Vec::new());
    let no_corners = Attributes {
        corners: Vec::new(),
        ..Attributes::default()
    };
    let mut nan = mesh.clone();
    nan.positions[3].x = f32::NAN;
    for name in ["m.obj", "m.ply", "m.stl", "m.glb", "m.gltf"] {
        for (what, m, a, refusal) in [
            (
                "empty",
                &empty,
                &no_corners,
                "no triangles; nothing written",
            ),
            ("NaN", &nan, &attributes, "does not load back"),
        ] {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join(name);
            let plain = save(&m.clone().into(), &path).unwrap_err();
            let with = save(&Model::new(m.clone(), Some(a.clone()), None), &path).unwrap_err();
            for err in [&plain, &with] {
                assert!(
                    matches!(err, MeshError::Write { path: p, .. } if *p == path),
                    "{name} {what}: {err}"
                );
                let text = err.to_string();
                assert!(
                    text.contains(refusal) && text.contains("nothing written"),
                    "{name} {what}: {text}"
                );
            }
            // Neither the mesh nor a .bin, nor a temporary file.
            assert_eq!(
                fs::read_dir(dir.path()).unwrap().count(),
                0,
                "{name} {what}"
            );
        }
    }
}

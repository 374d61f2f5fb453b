//! Tests for loading, validation and saving.

use super::*;
use crate::procedural::{icosphere, torus};
use std::fs;

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    fs::write(&p, bytes).unwrap();
    p
}

fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

/// Positions equal (bit-exact after f32 round trip) and triangles equal.
fn assert_same(a: &TriMesh, b: &TriMesh) {
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.triangles, b.triangles);
}

#[test]
fn obj_and_ply_round_trip_exactly() {
    let dir = tmp();
    let mut m = torus(1.0, 0.3, 17, 11);
    // Values that need all f32 digits, plus an unreferenced vertex that must survive.
    m.positions[0] = Vec3::new(0.1, -1.0e-7, 12345.678);
    m.positions.push(Vec3::new(1.0 / 3.0, 2.0, 3.0));
    for name in ["m.obj", "m.ply", "M.PLY", "m.Obj"] {
        let p = dir.path().join(name);
        save(&m, &p).unwrap();
        let l = load(&p).unwrap();
        assert_same(&l.mesh, &m);
        assert!(l.warnings.is_empty());
    }
}

#[test]
fn stl_round_trip_keeps_every_triangle() {
    let dir = tmp();
    let m = icosphere(2);
    let p = dir.path().join("m.stl");
    save(&m, &p).unwrap();
    let l = load(&p).unwrap();
    // STL is unindexed: compare triangle by triangle, then the welded vertex count.
    assert_eq!(l.mesh.face_count(), m.face_count());
    for f in 0..m.face_count() {
        assert_eq!(l.mesh.triangle(f), m.triangle(f));
    }
    assert_eq!(l.mesh.vertex_count(), m.vertex_count());
}

#[test]
fn save_leaves_no_temp_files_and_reports_bad_directory() {
    let dir = tmp();
    let m = icosphere(0);
    save(&m, &dir.path().join("a.ply")).unwrap();
    let names: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("a.ply")]);
    let err = save(&m, &dir.path().join("missing/a.ply")).unwrap_err();
    assert!(matches!(err, MeshError::Write { .. }), "{err}");
    let err = save(&m, &dir.path().join("a.off")).unwrap_err();
    assert!(matches!(err, MeshError::UnknownFormat { .. }), "{err}");
    let bad = TriMesh::new(vec![Vec3::ZERO], vec![[0, 0, 5]]);
    let err = save(&bad, &dir.path().join("b.obj")).unwrap_err();
    assert!(
        matches!(err, MeshError::IndexOutOfRange { index: 5, .. }),
        "{err}"
    );
}

#[test]
fn obj_texcoord_corners_negative_indices_and_polygons() {
    let dir = tmp();
    let text = "# c\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\nvt 0 0\nvn 0 0 1\n\
                o a\nf 1/1 2/1 3/1\ng b\nf -5//1 -3//1 -2//1\nf 1 2 3 4\nl 1 2\n";
    let l = load(&write(dir.path(), "q.obj", text.as_bytes())).unwrap();
    assert_eq!(l.mesh.vertex_count(), 5);
    // Quad fans into [0,1,2] (duplicate of face 0, dropped) and [0,2,3] (duplicate of face 1).
    assert_eq!(l.mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert!(
        l.warnings
            .contains(&MeshWarning::PolygonsTriangulated { count: 1 })
    );
    assert!(
        l.warnings
            .contains(&MeshWarning::DuplicateFaces { count: 2 })
    );
    assert!(l.vertex_normals.is_none());
}

fn ply_header(format: &str, vertex_props: &str, face_prop: &str, nv: usize, nf: usize) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment test\nelement vertex {nv}\n{vertex_props}\
         element face {nf}\n{face_prop}\nend_header\n"
    )
}

/// Square of 4 vertices with normals +z, colours, and faces as one quad.
#[test]
fn ply_ascii_with_colours_normals_and_polygon() {
    let dir = tmp();
    let props = "property double x\nproperty double y\nproperty double z\nproperty float nx\n\
                 property float ny\nproperty float nz\nproperty uchar red\n";
    let mut s = ply_header(
        "ascii",
        props,
        "property list uchar int vertex_indices",
        4,
        1,
    );
    for p in ["0 0 0", "1 0 0", "1 1 0", "0 1 0"] {
        s.push_str(&format!("{p} 0 0 1 255\n"));
    }
    s.push_str("4 0 1 2 3\n");
    let l = load(&write(dir.path(), "a.ply", s.as_bytes())).unwrap();
    assert_eq!(l.mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(l.mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(l.vertex_normals.unwrap(), vec![Vec3::Z; 4]);
}

/// Binary PLY with the given endianness, double coordinates, a colour byte and the given face
/// list types, built by hand.
fn binary_ply(big: bool, count_ty: &str, index_ty: &str) -> Vec<u8> {
    let format = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let props = "property double x\nproperty double y\nproperty double z\nproperty uchar red\n";
    let face = format!("property list {count_ty} {index_ty} vertex_indices");
    let mut out = ply_header(format, props, &face, 4, 2).into_bytes();
    let m = icosphere(0);
    for p in &m.positions[..4] {
        for c in p.to_array() {
            let c = c as f64;
            out.extend_from_slice(&if big {
                c.to_be_bytes()
            } else {
                c.to_le_bytes()
            });
        }
        out.push(7);
    }
    for t in [[0u32, 1, 2], [0, 2, 3]] {
        match count_ty {
            "uchar" => out.push(3),
            _ => out.extend_from_slice(&if big {
                3i32.to_be_bytes()
            } else {
                3i32.to_le_bytes()
            }),
        }
        for i in t {
            out.extend_from_slice(&if big {
                i.to_be_bytes()
            } else {
                i.to_le_bytes()
            });
        }
    }
    out
}

#[test]
fn ply_binary_both_endians_and_list_types() {
    let dir = tmp();
    let expected: Vec<Vec3> = icosphere(0).positions[..4].to_vec();
    for (big, c, i) in [
        (false, "uchar", "int"),
        (true, "uchar", "int"),
        (false, "uchar", "uint"),
        (true, "int", "int"),
    ] {
        let l = load(&write(dir.path(), "b.ply", &binary_ply(big, c, i))).unwrap();
        assert_eq!(l.mesh.positions, expected, "{big} {c} {i}");
        assert_eq!(l.mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }
}

fn expect_err(name: &str, bytes: &[u8]) -> MeshError {
    let dir = tmp();
    let p = write(dir.path(), name, bytes);
    let err = load(&p).unwrap_err();
    assert!(
        err.to_string().contains(name),
        "error must name the file: {err}"
    );
    err
}

#[test]
fn missing_file_and_unknown_extension() {
    let dir = tmp();
    let err = load(&dir.path().join("nope.obj")).unwrap_err();
    assert!(matches!(err, MeshError::Io { .. }), "{err}");
    assert!(matches!(
        expect_err("x.off", b"OFF\n"),
        MeshError::UnknownFormat { .. }
    ));
    assert!(matches!(
        expect_err("noext", b""),
        MeshError::UnknownFormat { .. }
    ));
}

#[test]
fn parse_errors_name_the_line_or_element() {
    let e = expect_err("p.obj", b"v 0 0 0\nv 1 zero 0\n");
    assert!(
        matches!(&e, MeshError::Parse { location, .. } if location == "line 2"),
        "{e}"
    );
    let e = expect_err("p.obj", b"v 0 0\n");
    assert!(matches!(e, MeshError::Parse { .. }), "{e}");
    let e = expect_err("p.obj", b"v 0 0 0\nf 1 x 1\n");
    assert!(matches!(e, MeshError::Parse { .. }), "{e}");
    let e = expect_err("p.ply", b"plyx\n");
    assert!(matches!(e, MeshError::Parse { .. }), "{e}");
    let mut truncated = binary_ply(false, "uchar", "int");
    truncated.truncate(truncated.len() - 5);
    let e = expect_err("t.ply", &truncated);
    assert!(
        matches!(&e, MeshError::Parse { location, .. } if location == "face 1"),
        "{e}"
    );
    let e = expect_err(
        "s.stl",
        b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n",
    );
    assert!(matches!(e, MeshError::Parse { .. }), "{e}");
}

#[test]
fn non_finite_coordinates() {
    let e = expect_err("n.obj", b"v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
    assert!(matches!(e, MeshError::NonFinite { vertex: 2, .. }), "{e}");
    let e = expect_err("n.obj", b"v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(matches!(e, MeshError::NonFinite { vertex: 1, .. }), "{e}");
    let props = "property float x\nproperty float y\nproperty float z\n";
    let mut s = ply_header(
        "ascii",
        props,
        "property list uchar int vertex_indices",
        3,
        1,
    );
    s.push_str("0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n");
    let e = expect_err("n.ply", s.as_bytes());
    assert!(matches!(e, MeshError::NonFinite { vertex: 1, .. }), "{e}");
}

#[test]
fn out_of_range_indices() {
    let e = expect_err("r.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n");
    assert!(
        matches!(
            e,
            MeshError::IndexOutOfRange {
                face: 1,
                index: 3,
                vertex_count: 3,
                ..
            }
        ),
        "{e}"
    );
    let e = expect_err("r.obj", b"v 0 0 0\nf 0 1 1\n");
    assert!(
        matches!(e, MeshError::IndexOutOfRange { face: 0, .. }),
        "{e}"
    );
    let props = "property float x\nproperty float y\nproperty float z\n";
    let mut s = ply_header(
        "ascii",
        props,
        "property list uchar int vertex_indices",
        3,
        1,
    );
    s.push_str("0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n");
    let e = expect_err("r.ply", s.as_bytes());
    assert!(
        matches!(e, MeshError::IndexOutOfRange { index: -1, .. }),
        "{e}"
    );
}

#[test]
fn empty_and_point_cloud() {
    assert!(matches!(
        expect_err("e.obj", b"# nothing\n"),
        MeshError::Empty { .. }
    ));
    assert!(matches!(
        expect_err("e.obj", b"v 0 0 0\nv 1 0 0\n"),
        MeshError::NoFaces {
            vertex_count: 2,
            ..
        }
    ));
    let props = "property float x\nproperty float y\nproperty float z\n";
    let s = ply_header(
        "ascii",
        props,
        "property list uchar int vertex_indices",
        0,
        0,
    );
    assert!(matches!(
        expect_err("e.ply", s.as_bytes()),
        MeshError::Empty { .. }
    ));
    // Only degenerate faces: nothing left, so it is a point cloud.
    let e = expect_err("d.obj", b"v 0 0 0\nv 1 0 0\nf 1 1 2\n");
    assert!(matches!(e, MeshError::NoFaces { .. }), "{e}");
    assert!(matches!(
        expect_err("e.stl", &[0u8; 84]),
        MeshError::Empty { .. }
    ));
}

#[test]
fn degenerate_and_duplicate_faces_are_warnings() {
    let dir = tmp();
    let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 1 2\nf 3 2 1\nf 2 3 1\nf 1 2 4\n";
    let l = load(&write(dir.path(), "w.obj", text)).unwrap();
    assert_eq!(l.mesh.triangles, vec![[0, 1, 2], [0, 1, 3]]);
    assert!(
        l.warnings
            .contains(&MeshWarning::DegenerateFaces { count: 1 })
    );
    assert!(
        l.warnings
            .contains(&MeshWarning::DuplicateFaces { count: 2 })
    );
    assert!(l.warnings.iter().all(|w| !w.to_string().is_empty()));
}

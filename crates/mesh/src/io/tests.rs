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
        save(&m.clone().into(), &p).unwrap();
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
    save(&m.clone().into(), &p).unwrap();
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
    save(&m.clone().into(), &dir.path().join("a.ply")).unwrap();
    let names: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("a.ply")]);
    let err = save(&m.clone().into(), &dir.path().join("missing/a.ply")).unwrap_err();
    assert!(matches!(err, MeshError::Write { .. }), "{err}");
    let err = save(&m.clone().into(), &dir.path().join("a.off")).unwrap_err();
    assert!(matches!(err, MeshError::UnknownFormat { .. }), "{err}");
    let bad = TriMesh::new(vec![Vec3::ZERO], vec![[0, 0, 5]]);
    let err = save(&bad.clone().into(), &dir.path().join("b.obj")).unwrap_err();
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

/// Binary PLY face indices stored as floats: whole numbers load like integers; NaN, infinite
/// and fractional ones are refused with the face named, as the ASCII reader refuses them (they
/// were read as vertex 0 and truncated).
#[test]
fn ply_binary_float_indices_must_be_whole() {
    let dir = tmp();
    let with_indices = |indices: [f32; 6]| {
        let props = "property float x\nproperty float y\nproperty float z\n";
        let face = "property list uchar float vertex_indices";
        let mut out = ply_header("binary_little_endian", props, face, 4, 2).into_bytes();
        for p in &icosphere(0).positions[..4] {
            for c in p.to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        for t in indices.chunks(3) {
            out.push(3);
            for &i in t {
                out.extend_from_slice(&i.to_le_bytes());
            }
        }
        out
    };
    let l = load(&write(
        dir.path(),
        "f.ply",
        &with_indices([0.0, 1.0, 2.0, 0.0, 2.0, 3.0]),
    ))
    .unwrap();
    assert_eq!(l.mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    for bad in [f32::NAN, 2.7, f32::INFINITY] {
        let e = load(&write(
            dir.path(),
            "g.ply",
            &with_indices([0.0, 1.0, 2.0, 0.0, bad, 3.0]),
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("not an integer") && e.contains("face 1"),
            "{bad}: {e}"
        );
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
            MeshError::ObjIndex {
                line: 5,
                index: 4,
                vertex_count: 3,
                ..
            }
        ),
        "{e}"
    );
    let e = expect_err("r.obj", b"v 0 0 0\nf 0 1 1\n");
    assert!(
        matches!(
            e,
            MeshError::ObjIndex {
                line: 2,
                index: 0,
                ..
            }
        ),
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

/// Issue 12: indices as written in the file (1-based), with the line number.
#[test]
fn obj_index_errors_name_the_index_as_written_and_the_line() {
    let four = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    for (face, line, index) in [("f 1 2 5", 5, 5), ("f 0", 5, 0), ("f -5 1 2", 5, -5)] {
        let text = format!("{four}{face}\n");
        let e = expect_err("i.obj", text.as_bytes());
        assert!(
            matches!(e, MeshError::ObjIndex { line: l, index: i, vertex_count: 4, .. } if l == line && i == index),
            "{face}: {e}"
        );
        let msg = e.to_string();
        assert!(msg.contains(&format!("line {line}")), "{msg}");
        assert!(msg.contains(&format!("vertex {index},")), "{msg}");
        assert!(msg.contains("i.obj"), "{msg}");
    }
}

/// ASCII STL with `facet normal -nan -nan -nan` (what exporters write for zero-area facets)
/// loads like the same file with real normals: the normals are not used.
#[test]
fn ascii_stl_with_nan_normals_loads() {
    let dir = tmp();
    let facet = |n: &str, c: [&str; 3]| {
        format!(
            "  facet normal {n}\n    outer loop\n      vertex {}\n      vertex {}\n      vertex {}\n    endloop\n  endfacet\n",
            c[0], c[1], c[2]
        )
    };
    let tri = ["0 0 0", "1 0 0", "0 1 0"];
    let other = ["0 0 0", "0 1 0", "0 0 1"];
    let text = |n: &str| {
        format!(
            "solid t\n{}{}endsolid t\n",
            facet("0 0 1", tri),
            facet(n, other)
        )
    };
    let want = load(&write(dir.path(), "ok.stl", text("-1 0 0").as_bytes()))
        .unwrap()
        .mesh;
    assert_eq!(want.triangles.len(), 2);
    for n in ["-nan -nan -nan", "nan nan nan", "NaN NaN NaN"] {
        let got = load(&write(dir.path(), "nan.stl", text(n).as_bytes()))
            .unwrap()
            .mesh;
        assert_eq!(got, want, "{n}");
    }
}

/// Lines ending in a lone CR (classic Mac OS) read as lines, as LF and CRLF do: the same mesh,
/// and an error names the right line.
#[test]
fn obj_with_cr_line_ends_reads_like_lf() {
    let dir = tmp();
    let lf = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";
    let want = load(&write(dir.path(), "lf.obj", lf)).unwrap().mesh;
    assert_eq!(want.triangles.len(), 2);
    for (name, sep) in [("cr.obj", "\r"), ("crlf.obj", "\r\n")] {
        let text = String::from_utf8(lf.to_vec()).unwrap().replace('\n', sep);
        let got = load(&write(dir.path(), name, text.as_bytes()))
            .unwrap()
            .mesh;
        assert_eq!(got, want, "{name}");
    }
    let bad = b"v 0 0 0\rv 1 0 0\rf 1 2 9\r";
    let e = load(&write(dir.path(), "badcr.obj", bad))
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 3"), "{e}");
}

/// Issue 12: a UTF-8 byte order mark does not eat the first `v` line.
#[test]
fn obj_with_bom_keeps_the_first_vertex() {
    let dir = tmp();
    let mut bytes = b"\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n".to_vec();
    let l = load(&write(dir.path(), "bom.obj", &bytes)).unwrap();
    assert_eq!(l.mesh.positions.len(), 4);
    assert_eq!(l.mesh.positions[0], Vec3::ZERO);
    assert_eq!(l.mesh.triangles, vec![[0, 1, 2], [0, 1, 3]]);
    let t = load_obj_with_tobj(&write(dir.path(), "bom2.obj", &bytes)).unwrap();
    assert_eq!(t.mesh.triangles.len(), 2);
    // Without the BOM the same mesh comes back.
    bytes.drain(..3);
    assert_eq!(
        load(&write(dir.path(), "nobom.obj", &bytes)).unwrap().mesh,
        l.mesh
    );
}

/// Issue 12: comments and other records are not decoded, so non-UTF-8 bytes there are fine;
/// a non-UTF-8 byte inside a `v` record is an error with its line.
#[test]
fn obj_non_utf8_comment_is_ignored() {
    let dir = tmp();
    let bytes = b"# caf\xE9 \xFF\nv 0 0 0\nv 1 0 0\no \xFEname\nv 0 1 0\nf 1 2 3\n";
    let l = load(&write(dir.path(), "latin1.obj", bytes)).unwrap();
    assert_eq!(l.mesh.positions.len(), 3);
    assert_eq!(l.mesh.triangles, vec![[0, 1, 2]]);
    let e = expect_err("bad.obj", b"v 0 0 0\nv 1 \xFF 0\n");
    assert!(e.to_string().contains("line 2"), "{e}");
}

/// Issue 12: an ASCII STL whose first line is just `solid` is read as ASCII.
#[test]
fn ascii_stl_with_bare_solid_line() {
    let dir = tmp();
    for first in ["solid", "solid\r", "  solid  ", "solid name"] {
        let l = load(&write(
            dir.path(),
            "a.stl",
            crate::fixtures::ascii_stl(first).as_bytes(),
        ))
        .unwrap();
        assert_eq!(l.mesh.triangles.len(), 2, "{first:?}");
        assert_eq!(l.mesh.positions.len(), 4, "{first:?}");
        assert!(l.warnings.is_empty());
    }
}

/// Issue 12: binary STL sizes are checked against the header count.
#[test]
fn binary_stl_count_mismatch() {
    let dir = tmp();
    let m = icosphere(0); // 20 faces
    let p = dir.path().join("m.stl");
    save(&m.clone().into(), &p).unwrap();
    let good = fs::read(&p).unwrap();
    assert_eq!(good.len(), 84 + 50 * 20);
    // Header says 2, file holds 20 records: 2 faces and a warning.
    let mut fewer = good.clone();
    fewer[80..84].copy_from_slice(&2u32.to_le_bytes());
    let l = load(&write(dir.path(), "fewer.stl", &fewer)).unwrap();
    assert_eq!(l.mesh.triangles.len(), 2);
    assert!(
        l.warnings.contains(&MeshWarning::StlSizeMismatch {
            header_triangles: 2,
            file_bytes: good.len() as u64
        }),
        "{:?}",
        l.warnings
    );
    assert!(
        l.warnings
            .iter()
            .any(|w| w.to_string().contains("says 2 triangles"))
    );
    // Header says 30: the error says what was expected.
    let mut more = good.clone();
    more[80..84].copy_from_slice(&30u32.to_le_bytes());
    let e = expect_err("more.stl", &more);
    let msg = e.to_string();
    assert!(
        msg.contains("30 triangles (1584 bytes)") && msg.contains("1084 bytes"),
        "{msg}"
    );
    // Too short for a header.
    let e = expect_err("short.stl", &good[..40]);
    assert!(e.to_string().contains("84-byte header"), "{e}");
    // A binary file whose 80-byte header starts with "solid" is still binary.
    let mut solid_header = good.clone();
    solid_header[..11].copy_from_slice(b"solid facet");
    assert_eq!(
        load(&write(dir.path(), "sh.stl", &solid_header))
            .unwrap()
            .mesh
            .triangles
            .len(),
        20
    );
}

/// Writing through a symbolic link writes the file it points to and keeps the link; a name
/// near the 255-byte limit works (the temporary name no longer repeats it); a temporary left
/// by a process that no longer runs is removed by the next write in that folder.
#[cfg(unix)]
#[test]
fn atomic_writes_follow_links_take_long_names_and_clean_stale_temporaries() {
    let dir = tmp();
    let m = icosphere(1);
    // Through a link.
    let real = dir.path().join("real.obj");
    save(&icosphere(0).into(), &real).unwrap();
    let link = dir.path().join("link.obj");
    std::os::unix::fs::symlink("real.obj", &link).unwrap();
    save(&m.clone().into(), &link).unwrap();
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(load(&real).unwrap().mesh.triangles, m.triangles);
    // A 250-byte name.
    let long = dir.path().join(format!("{}.obj", "n".repeat(246)));
    save(&m.clone().into(), &long).unwrap();
    assert_eq!(load(&long).unwrap().mesh.triangles, m.triangles);
    // A stale temporary of a dead process (no pid is this large) goes; one of this process,
    // still running, stays.
    let stale = dir.path().join(".gng3d.4294967295.0.tmp");
    let live = dir
        .path()
        .join(format!(".gng3d.{}.999999.tmp", std::process::id()));
    std::fs::write(&stale, b"partial").unwrap();
    std::fs::write(&live, b"partial").unwrap();
    save(&m.clone().into(), &dir.path().join("next.obj")).unwrap();
    assert!(!stale.exists(), "stale temporary left");
    assert!(live.exists(), "a running process's temporary removed");
}

/// A write registers its temporary while it is in progress (what a signal handler removes with
/// `remove_unfinished_writes`) and unregisters it when done, failed or not; the writability
/// probe leaves nothing behind.
#[test]
fn writes_in_progress_are_registered_until_they_end() {
    let dir = tmp();
    let temp = dir.path().join(".gng3d.1.2.tmp");
    {
        let _guard = super::InFlight::register(&temp);
        assert!(super::unfinished_writes().contains(&temp));
    }
    assert!(!super::unfinished_writes().contains(&temp));
    let out = dir.path().join("m.obj");
    save(&icosphere(1).into(), &out).unwrap();
    assert!(
        super::unfinished_writes()
            .iter()
            .all(|p| !p.starts_with(dir.path())),
        "a finished write is still registered"
    );
    super::check_writable(&dir.path().join("later.obj")).unwrap();
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, vec![std::ffi::OsString::from("m.obj")]);
    let missing = dir.path().join("no/such/folder/x.obj");
    let err = super::check_writable(&missing).unwrap_err().to_string();
    assert!(err.contains("does not exist"), "{err}");
}

/// Files written together (a `.gltf` and its `.bin`): when one cannot be written, none is
/// renamed, so the earlier one keeps its old content, and no temporary is left.
#[test]
fn files_written_together_are_all_kept_as_they_were_when_one_fails() {
    let dir = tmp();
    let bin = dir.path().join("m.bin");
    std::fs::write(&bin, b"old").unwrap();
    let unwritable = dir.path().join("no/such/folder/m.gltf");
    let err = super::write_atomic_all(&[(&bin, b"new"), (&unwritable, b"{}")]).unwrap_err();
    assert!(err.to_string().contains("m.gltf"), "{err}");
    assert_eq!(std::fs::read(&bin).unwrap(), b"old");
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, vec![std::ffi::OsString::from("m.bin")]);
}

/// Colour ranges and partial properties (issue 46): never silently wrong colours or dropped
/// values.
#[test]
fn colour_ranges_and_partial_properties_are_read_or_named() {
    let dir = tmp();
    let warned =
        |l: &LoadedMesh, needle: &str| l.warnings.iter().any(|w| w.to_string().contains(needle));
    // OBJ colours in 0-255: orange stays orange.
    let obj = b"v 0 0 0 255 128 0\nv 1 0 0 255 128 0\nv 0 1 0 0 0 255\nf 1 2 3\n";
    let l = load(&write(dir.path(), "c.obj", obj)).unwrap();
    let c = l.attributes.as_ref().unwrap().colors.as_ref().unwrap();
    assert!(
        (c[0].y - 128.0 / 255.0).abs() < 1e-6 && c[0].x == 1.0,
        "{c:?}"
    );
    assert!(warned(&l, "read as 0-255"), "{:?}", l.warnings);
    // 0-1 colours are untouched, without a warning.
    let l = load(&write(
        dir.path(),
        "d.obj",
        b"v 0 0 0 1 0.5 0\nv 1 0 0 1 0.5 0\nv 0 1 0 0 0 1\nf 1 2 3\n",
    ))
    .unwrap();
    assert_eq!(l.attributes.unwrap().colors.unwrap()[0].y, 0.5);
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    // PLY int colours holding 8-bit values.
    let ply = |props: &str, row: &str| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
             property float z\n{props}element face 1\nproperty list uchar int vertex_indices\n\
             end_header\n0 0 0 {row}\n1 0 0 {row}\n0 1 0 {row}\n3 0 1 2\n"
        )
    };
    let text = ply(
        "property int red\nproperty int green\nproperty int blue\n",
        "255 128 0",
    );
    let l = load(&write(dir.path(), "i.ply", text.as_bytes())).unwrap();
    let c = l.attributes.as_ref().unwrap().colors.as_ref().unwrap()[0];
    assert!(
        (c.y - 128.0 / 255.0).abs() < 1e-6 && (c.x - 1.0).abs() < 1e-6,
        "{c:?}"
    );
    assert!(
        warned(&l, "int colours all at most 255"),
        "{:?}",
        l.warnings
    );
    // Wide values keep the type's range.
    let text = ply(
        "property ushort red\nproperty ushort green\nproperty ushort blue\n",
        "65535 0 1000",
    );
    let l = load(&write(dir.path(), "u.ply", text.as_bytes())).unwrap();
    assert_eq!(l.attributes.unwrap().colors.unwrap()[0].x, 1.0);
    // Partial groups and lists are named.
    let text = ply(
        "property uchar red\nproperty uchar green\nproperty float nx\nproperty float ny\n",
        "1 2 0.5 0.5",
    );
    let l = load(&write(dir.path(), "p.ply", text.as_bytes())).unwrap();
    assert!(
        warned(&l, "properties red, green (without blue)"),
        "{:?}",
        l.warnings
    );
    assert!(
        warned(&l, "properties nx, ny (without nz)"),
        "{:?}",
        l.warnings
    );
    let text = ply(
        "property list uchar uchar red\nproperty uchar green\nproperty uchar blue\n",
        "1 9 2 3",
    );
    let l = load(&write(dir.path(), "l.ply", text.as_bytes())).unwrap();
    assert!(warned(&l, "property red (a list"), "{:?}", l.warnings);
}

/// Recentring happens only where f32 would move a vertex by more than 1e-6 of the extent.
#[test]
fn far_models_are_recentred_and_near_ones_are_not() {
    let box_at =
        |centre: Vec3, size: f32| [Vec3::splat(-0.5), Vec3::splat(0.5)].map(|c| centre + c * size);
    // A 0.1-unit scan at z = 1.6 (16 extents away) rounds by 6e-7 of its extent: kept.
    assert_eq!(far_origin(&box_at(Vec3::new(0.0, 0.0, 1.6), 0.057)), None);
    assert_eq!(far_origin(&box_at(Vec3::ZERO, 1.0)), None);
    assert_eq!(far_origin(&[Vec3::ONE; 3]), None);
    let o = far_origin(&box_at(Vec3::new(450_000.0, 5_400_000.0, 0.0), 20.0)).unwrap();
    assert!(
        (o - glam::DVec3::new(450_000.0, 5_400_000.0, 0.0)).length() < 1.0,
        "{o}"
    );
}

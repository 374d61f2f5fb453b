//! The partitioned simplification end to end on small meshes (a few cells): counts, topology,
//! seams, quality against single-process QEM, resume, and bad input.

use mesh::TriMesh;
use partition::{PartitionError, PartitionParams, generate, simplify};
use qem::Target;
use std::path::Path;

/// A budget of 1 MiB a cell: 5,242 faces, so a 40k-face mesh takes a few cells.
const SMALL_BUDGET: u64 = 1 << 20;

fn params(target: Target, work: &Path) -> PartitionParams {
    PartitionParams {
        memory_budget: SMALL_BUDGET,
        threads: 2,
        ..PartitionParams::new(target, work.to_path_buf())
    }
}

fn load(path: &Path) -> TriMesh {
    mesh::io::load(path).unwrap().mesh
}

/// Closed, manifold, and no two vertices at one position (a border vertex kept twice).
fn assert_watertight(m: &TriMesh) {
    let topo = mesh::topology::analyze(m);
    assert!(topo.closed, "{topo:?}");
    assert!(topo.manifold, "{topo:?}");
    assert_eq!(topo.referenced_vertices, m.vertex_count());
    let mut seen: Vec<[u32; 3]> = m
        .positions
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    seen.sort_unstable();
    seen.dedup();
    assert_eq!(seen.len(), m.vertex_count(), "duplicated vertices");
}

#[test]
fn generated_sphere_is_closed_manifold_with_the_requested_faces() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.ply");
    for faces in [12, 1_000, 30_000] {
        let grid = generate::write_displaced_sphere(&path, faces, 3).unwrap();
        let m = load(&path);
        // The grid's count is 2·cols·(rows−1): the nearest to the request within one band.
        assert_eq!(m.face_count(), grid.faces());
        assert!(
            grid.faces().abs_diff(faces) <= 2 * (grid.rows - 1),
            "{grid:?}"
        );
        let topo = mesh::topology::analyze(&m);
        assert!(topo.closed && topo.manifold, "{topo:?}");
        assert_eq!(topo.genus, Some(0));
        assert!(m.signed_volume() > 0.0, "outward oriented");
        // The displacement stays within its bound: radius in [0.67, 1.33].
        assert!(
            m.positions
                .iter()
                .all(|p| (0.66..1.34).contains(&p.length()))
        );
    }
    // Same seed, same bytes; another seed, another surface.
    let again = dir.path().join("t.ply");
    generate::write_displaced_sphere(&again, 30_000, 3).unwrap();
    assert_eq!(
        std::fs::read(&path).unwrap(),
        std::fs::read(&again).unwrap()
    );
    generate::write_displaced_sphere(&again, 30_000, 4).unwrap();
    assert_ne!(
        std::fs::read(&path).unwrap(),
        std::fs::read(&again).unwrap()
    );
}

#[test]
fn partitioned_output_is_watertight_with_the_exact_count() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    generate::write_displaced_sphere(&input, 40_000, 1).unwrap();
    let output = dir.path().join("out.ply");
    let calls = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let counter = calls.clone();
    let mut p = params(Target::Faces(4_000), &dir.path().join("work"));
    p.progress = Some(std::sync::Arc::new(move |_, total| {
        counter.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        assert!(total > 1);
    }));
    let report = simplify(&input, &output, &p).unwrap();
    assert!(report.cells >= 4, "{report:?}");
    assert_eq!(
        calls.load(std::sync::atomic::Ordering::Relaxed),
        report.cells
    );
    assert!(report.shared_vertices > 0);
    let m = load(&output);
    eprintln!("{report:?} {:?}", mesh::topology::analyze(&m));
    assert_eq!(m.face_count(), 4_000);
    assert_eq!(m.vertex_count(), 2_002); // closed genus 0: V = F/2 + 2
    assert_watertight(&m);
    // Vertex target.
    let report = simplify(
        &input,
        &output,
        &PartitionParams {
            target: Target::Vertices(1_500),
            ..p
        },
    )
    .unwrap();
    let m = load(&output);
    assert_eq!((m.vertex_count(), report.vertices), (1_500, 1_500));
    assert_watertight(&m);
}

/// Symmetric Hausdorff (max, mean) of `coarse` against `original`.
fn distance(original: &TriMesh, coarse: &TriMesh) -> (f64, f64) {
    let h = metrics::hausdorff(
        original,
        coarse,
        &metrics::HausdorffParams::with_samples(200_000),
    )
    .unwrap();
    (h.max, h.mean)
}

/// The partitioned result at `faces` against `qem::simplify` at the same count.
fn quality_against_qem(input: &Path, faces: usize, work: &Path) {
    let output = work.with_extension("ply");
    let report = simplify(input, &output, &params(Target::Faces(faces), work)).unwrap();
    assert!(report.cells > 1, "{report:?}");
    let original = load(input);
    let parts = load(&output);
    let (whole, _) = qem::simplify(
        &mesh::Model::from(original.clone()),
        &qem::QemParams::with_target(Target::Faces(faces)),
    )
    .unwrap();
    assert_eq!(parts.face_count(), whole.mesh.face_count());
    let (p, w) = (
        distance(&original, &parts),
        distance(&original, &whole.mesh),
    );
    eprintln!(
        "{}: partitioned {p:?}, whole {w:?}, {report:?}",
        input.display()
    );
    assert!(p.0 <= 1.1 * w.0, "Hausdorff {} > 1.1 × {}", p.0, w.0);
    assert!(p.1 <= 1.1 * w.1, "mean {} > 1.1 × {}", p.1, w.1);
}

#[test]
fn quality_matches_single_process_qem_on_a_generated_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    generate::write_displaced_sphere(&input, 60_000, 5).unwrap();
    quality_against_qem(&input, 3_000, &dir.path().join("work"));
}

#[test]
fn quality_matches_single_process_qem_on_a_shared_mesh() {
    let Some(dir) = mesh::fixtures::shared_meshes_dir("horse.ply") else {
        return;
    };
    let work = tempfile::tempdir().unwrap();
    quality_against_qem(&dir.join("horse.ply"), 9_700, &work.path().join("work"));
}

#[test]
fn a_resumed_run_redoes_only_the_missing_cell_and_writes_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    generate::write_displaced_sphere(&input, 30_000, 2).unwrap();
    let work = dir.path().join("work");
    let (first, second) = (dir.path().join("a.ply"), dir.path().join("b.ply"));
    let p = params(Target::Ratio(0.1), &work);
    let report = simplify(&input, &first, &p).unwrap();
    assert_eq!(report.cells_resumed, 0);
    let outputs: Vec<_> = std::fs::read_dir(&work)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "out"))
        .collect();
    assert_eq!(outputs.len(), report.cells);
    std::fs::remove_file(&outputs[outputs.len() / 2]).unwrap();
    // The cell a driver elsewhere would run, by the manifest's names.
    let manifest = partition::Manifest::load(&work).unwrap();
    assert_eq!(manifest.faces as usize, report.input_faces);
    let again = simplify(&input, &second, &p).unwrap();
    assert_eq!(again.cells_resumed, report.cells - 1);
    assert_eq!(
        std::fs::read(&first).unwrap(),
        std::fs::read(&second).unwrap()
    );
    // A truncated cell output is not taken as done.
    let cut = &outputs[0];
    let bytes = std::fs::read(cut).unwrap();
    std::fs::write(cut, &bytes[..bytes.len() - 1]).unwrap();
    let third = simplify(&input, &second, &p).unwrap();
    assert_eq!(third.cells_resumed, report.cells - 1);
    assert_eq!(
        std::fs::read(&first).unwrap(),
        std::fs::read(&second).unwrap()
    );
    // Another target in the same folder: the partition is reused, no cell output is.
    let other = simplify(&input, &second, &params(Target::Ratio(0.2), &work)).unwrap();
    assert_eq!(other.cells_resumed, 0);
    let want = (0.2 * report.input_faces as f64).round() as usize;
    assert_eq!(load(&second).face_count(), want);
}

#[test]
fn bad_input_gives_a_typed_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.ply");
    let grid = generate::write_displaced_sphere(&good, 1_000, 1).unwrap();
    let n = grid.vertices();
    let bytes = std::fs::read(&good).unwrap();
    let out = dir.path().join("out.ply");
    let p = params(Target::Ratio(0.5), &dir.path().join("work"));
    let run = |name: &str, content: &[u8]| {
        let path = dir.path().join(name);
        std::fs::write(&path, content).unwrap();
        let e = simplify(&path, &out, &p).unwrap_err();
        assert!(e.to_string().contains(name), "{e}");
        e
    };
    // Cut short: the header's counts are more than the file holds.
    let e = run("short.ply", &bytes[..bytes.len() - 5]);
    assert!(matches!(e, PartitionError::Truncated { .. }), "{e}");
    // A count claiming a billion vertices is refused before anything is sized from it.
    let text = String::from_utf8_lossy(&bytes[..300]).replace(
        &format!("element vertex {n}\n"),
        "element vertex 1000000000\n",
    );
    let header_end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let mut huge = text.as_bytes()[..text.find("end_header\n").unwrap() + 11].to_vec();
    huge.extend_from_slice(&bytes[header_end..]);
    let e = run("huge.ply", &huge);
    assert!(matches!(e, PartitionError::Truncated { .. }), "{e}");
    // A face naming vertex n of n.
    let last_face = bytes.len() - 12;
    let mut wrong = bytes.clone();
    wrong[last_face..last_face + 4].copy_from_slice(&(n as u32).to_le_bytes());
    let e = run("index.ply", &wrong);
    assert!(
        matches!(e, PartitionError::IndexOutOfRange { index, .. } if index == n as f64),
        "{e}"
    );
    let e = run("text.ply", b"hello\n");
    assert!(matches!(e, PartitionError::Malformed { .. }), "{e}");
    let e = run("mesh.glb", b"glTF");
    assert!(matches!(e, PartitionError::UnsupportedFormat { .. }), "{e}");
    // OBJ: a face naming vertex 4 of 3 (and a relative index before the first vertex).
    let e = run("index.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    assert!(
        matches!(e, PartitionError::IndexOutOfRange { index: 4.0, .. }),
        "{e}"
    );
    let e = run("relative.obj", b"f -1 -2 -3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    assert!(matches!(e, PartitionError::IndexOutOfRange { .. }), "{e}");
    let e = run("words.obj", b"v 0 zero 0\n");
    assert!(matches!(e, PartitionError::Malformed { .. }), "{e}");
}

#[test]
fn ascii_binary_and_obj_inputs_give_the_same_output() {
    let dir = tempfile::tempdir().unwrap();
    let binary = dir.path().join("b.ply");
    generate::write_displaced_sphere(&binary, 20_000, 9).unwrap();
    // The same mesh as ASCII PLY, written by the project's writer's independent path: by hand.
    let m = load(&binary);
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n\
         property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        m.vertex_count(),
        m.face_count()
    );
    for p in &m.positions {
        text += &format!("{:?} {:?} {:?}\n", p.x, p.y, p.z);
    }
    for t in &m.triangles {
        text += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    let ascii = dir.path().join("a.ply");
    std::fs::write(&ascii, text).unwrap();
    let out = |input: &Path, name: &str| {
        let o = dir.path().join(name);
        simplify(
            input,
            &o,
            &params(
                Target::Faces(2_000),
                &dir.path().join(name).with_extension("w"),
            ),
        )
        .unwrap();
        std::fs::read(o).unwrap()
    };
    // And as OBJ, with relative indices and corner attributes to skip.
    let mut obj = String::from("# hand-written\no sphere\n");
    for p in &m.positions {
        obj += &format!("v {:?} {:?} {:?}\nvt 0 0\n", p.x, p.y, p.z);
    }
    let n = m.vertex_count() as i64;
    for t in &m.triangles {
        let [a, b, c] = t.map(|v| v as i64 - n);
        obj += &format!("f {a}/{a} {b}/{b} {c}/{c}\n");
    }
    let obj_path = dir.path().join("o.obj");
    std::fs::write(&obj_path, obj).unwrap();
    let reference = out(&binary, "x.ply");
    assert_eq!(reference, out(&ascii, "y.ply"));
    assert_eq!(reference, out(&obj_path, "z.ply"));
}

#[test]
fn inspect_counts_and_names_what_a_positions_only_run_ignores() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("quad.obj");
    std::fs::write(
        &obj,
        "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nusemtl m\nf 1/1/1 2/2/1 3/3/1 4/3/1\n",
    )
    .unwrap();
    let info = partition::inspect(&obj).unwrap();
    assert_eq!((info.vertices, info.faces), (Some(4), 1));
    assert_eq!(
        info.ignored,
        [
            "3 vt lines",
            "1 vn lines",
            "1 usemtl lines",
            "1 mtllib lines"
        ]
    );
    let ply = dir.path().join("sphere.ply");
    let grid = generate::write_displaced_sphere(&ply, 2_000, 3).unwrap();
    let info = partition::inspect(&ply).unwrap();
    assert_eq!(info.vertices, Some(grid.vertices() as u64));
    assert_eq!(info.faces as usize, grid.faces());
    assert!(info.ignored.is_empty(), "{:?}", info.ignored);
}

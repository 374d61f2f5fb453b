//! `simplify --partition auto` (issue 50): the exact count, a closed output from a closed input,
//! the JSON report of the cells, resume from the finished cells, the work folder's lifetime,
//! the attributes named when dropped, and the combinations refused.

mod common;
use common::{gng3d, json_of, s, stderr, succeeded};
use std::path::Path;

/// A closed sphere of 20,480 faces (10,242 vertices) saved as PLY in `dir`.
fn sphere(dir: &Path) -> std::path::PathBuf {
    let input = dir.join("sphere.ply");
    let mesh = gng3d::mesh::procedural::icosphere(5);
    assert_eq!(mesh.face_count(), 20_480);
    gng3d::mesh::io::save(&mesh.into(), &input).unwrap();
    input
}

/// Cell output files of a work folder.
fn cell_outputs(work: &Path) -> Vec<std::path::PathBuf> {
    let mut outs: Vec<_> = std::fs::read_dir(work)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "out"))
        .collect();
    outs.sort();
    outs
}

#[test]
fn partitioned_run_is_exact_closed_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path());
    let out = dir.path().join("coarse.ply");
    let work = dir.path().join("work");
    // 256 KiB a cell: about 1,300 faces a cell, so many cells and borders to stitch.
    let run = |extra: &[&str]| {
        let mut args = vec!["simplify", s(&input), s(&out), "--partition", "auto"];
        args.extend_from_slice(&["--memory-budget", "256KiB", "--json"]);
        args.extend_from_slice(extra);
        json_of(&gng3d(&args))
    };
    let first = run(&["--faces", "2000", "--work-dir", s(&work), "--keep-work"]);
    let cells = first["cells"].as_u64().unwrap();
    assert!(cells > 4, "{first}");
    assert_eq!(first["cells_resumed"], 0);
    assert_eq!(first["partition"], "auto");
    assert!(first["step_seconds"]["cells"].as_f64().unwrap() >= 0.0);
    let coarse = gng3d::mesh::io::load(&out).unwrap().mesh;
    assert!((1_999..=2_000).contains(&coarse.face_count()));
    assert_eq!(
        first["faces"].as_u64().unwrap() as usize,
        coarse.face_count()
    );
    let topology = gng3d::mesh::topology::analyze(&coarse);
    assert!(topology.closed && topology.manifold, "{topology:?}");
    let bytes = std::fs::read(&out).unwrap();

    // A run killed after some cells: their outputs are there, the others not.
    let outs = cell_outputs(&work);
    assert_eq!(outs.len() as u64, cells);
    for lost in &outs[..2] {
        std::fs::remove_file(lost).unwrap();
    }
    let again = run(&["--faces", "2000", "--work-dir", s(&work)]);
    assert_eq!(again["cells_resumed"].as_u64().unwrap(), cells - 2);
    assert_eq!(again["cells"].as_u64().unwrap(), cells);
    assert_eq!(std::fs::read(&out).unwrap(), bytes, "resumed run differs");
    assert!(!work.exists(), "work folder left after success");

    // --ratio: a share of the vertices, rounded to a count of them; the default work folder
    // beside the output, removed at the end.
    let by_ratio = run(&["--ratio", "0.1"]);
    assert_eq!(by_ratio["vertices"].as_u64().unwrap(), 1024); // round(0.1 × 10,242)
    assert!(!job_default_work(&out).exists());
}

/// The default work folder of `out` (the CLI documents it: OUT's name with `.gng3d-work`).
fn job_default_work(out: &Path) -> std::path::PathBuf {
    out.with_file_name(format!(
        "{}.gng3d-work",
        out.file_name().unwrap().to_string_lossy()
    ))
}

#[test]
fn partitioned_run_names_dropped_attributes_and_refuses_bad_combinations() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = gng3d::mesh::procedural::icosphere(3);
    // Normals (the unit positions) written by hand: an ASCII PLY with nx, ny, nz.
    let mut ply = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.vertex_count(),
        mesh.face_count()
    );
    for p in &mesh.positions {
        let n = p.normalize();
        ply += &format!("{} {} {} {} {} {}\n", p.x, p.y, p.z, n.x, n.y, n.z);
    }
    for t in &mesh.triangles {
        ply += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    let input = dir.path().join("normals.ply");
    std::fs::write(&input, ply).unwrap();
    let out = dir.path().join("out.ply");
    let base = ["simplify", s(&input), s(&out), "--partition", "auto"];
    let with = |extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        gng3d(&args)
    };
    let o = succeeded(with(&["--faces", "300"]));
    let err = stderr(&o);
    assert!(
        err.contains("positions only") && err.contains("vertex property nx"),
        "{err}"
    );
    let o = succeeded(with(&["--faces", "300", "--attributes", "drop"]));
    assert!(!stderr(&o).contains("positions only"), "{}", stderr(&o));

    for (extra, expected) in [
        (
            &["--ratio", "0.2", "--method", "gng"][..],
            "--partition applies to QEM only",
        ),
        (
            &["--faces", "300", "--lock-border"],
            "--lock-border does not apply with --partition auto",
        ),
        (
            &["--faces", "300", "--memory-budget", "2 parsecs"],
            "--memory-budget",
        ),
        (
            &["--faces", "300", "--memory-budget", "1kB"],
            "at least 64 KiB",
        ),
        (&["--faces", "300", "--lods", "0.5,0.2"], "--lods"),
    ] {
        let o = with(extra);
        assert!(!o.status.success(), "{extra:?} accepted");
        assert!(stderr(&o).contains(expected), "{extra:?}: {}", stderr(&o));
    }
    let o = gng3d(&[
        "simplify",
        s(&input),
        s(&out),
        "--faces",
        "300",
        "--keep-work",
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--partition auto only"),
        "{}",
        stderr(&o)
    );
    // glTF is not read by the streaming partition (PLY, OBJ and STL are).
    let stl = dir.path().join("sphere.glb");
    gng3d::mesh::io::save(&gng3d::mesh::Model::from(mesh), &stl).unwrap();
    let o = gng3d(&[
        "simplify",
        s(&stl),
        s(&out),
        "--faces",
        "300",
        "--partition",
        "auto",
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("only PLY, OBJ and STL"),
        "{}",
        stderr(&o)
    );
}

//! `simplify --max-error E` (a distance as a share of the bounding-box diagonal, alone or with
//! a target) and `--attribute-weights`: the reached error in `--json`, bad values refused before
//! anything is written.

mod common;
use common::{gng3d, succeeded};

#[test]
fn max_error_alone_and_with_a_target() {
    let dir = tempfile::tempdir().unwrap();
    let torus = gng3d::mesh::procedural::torus(1.0, 0.35, 48, 24);
    let input = dir.path().join("torus.ply");
    gng3d::mesh::io::save(&torus.clone().into(), &input).unwrap();
    let out = dir.path().join("out.ply");
    let run = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["simplify", input.to_str().unwrap(), out.to_str().unwrap()];
        args.extend_from_slice(extra);
        args.push("--json");
        let o = succeeded(gng3d(&args));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let mut faces = Vec::new();
    for e in ["0.001", "0.01"] {
        let j = run(&["--max-error", e]);
        let reached = j["report"]["max_relative_error"].as_f64().unwrap();
        assert!(reached <= e.parse::<f64>().unwrap(), "{j}");
        assert_eq!(j["report"]["stop_reason"], "max_error");
        // The file holds what the summary says.
        let written = gng3d::mesh::io::load(&out).unwrap().mesh;
        assert_eq!(written.face_count() as u64, j["faces"].as_u64().unwrap());
        faces.push(written.face_count());
    }
    assert!(
        faces[1] < faces[0] && faces[0] < torus.face_count(),
        "{faces:?}"
    );
    // With a target: a loose bound lets the target through, a tight one stops first.
    let j = run(&["--faces", "1000", "--max-error", "0.5"]);
    assert!(j["faces"].as_u64().unwrap() <= 1000, "{j}");
    assert_eq!(j["report"]["stop_reason"], "target_reached");
    let j = run(&["--faces", "100", "--max-error", "0.001"]);
    assert_eq!(j["report"]["stop_reason"], "max_error");
    assert_eq!(j["faces"].as_u64().unwrap() as usize, faces[0]);
    // Without the flag no relative error is measured.
    let j = run(&["--faces", "1000"]);
    assert!(j["report"]["max_relative_error"].is_null(), "{j}");
}

#[test]
fn bad_bounds_and_weights_are_refused_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("grid.ply");
    gng3d::mesh::io::save(&gng3d::mesh::procedural::unit_square_grid(8).into(), &input).unwrap();
    let out = dir.path().join("out.ply");
    for (extra, message) in [
        (vec!["--max-error=-1"], "max relative error -1"),
        (vec!["--max-error", "nan"], "max relative error NaN"),
        (
            vec!["--ratio", "0.5", "--attribute-weights", "uv=-2"],
            "attribute weight uv=-2",
        ),
        (
            vec!["--ratio", "0.5", "--attribute-weights", "uv=1,shine=2"],
            "unknown attribute \"shine\"",
        ),
        (
            vec!["--ratio", "0.5", "--attribute-weights", "uv"],
            "expected NAME=W",
        ),
        (
            vec!["--ratio", "0.5", "--attribute-weights", "uv=1,uv=2"],
            "uv given twice",
        ),
        (
            vec!["--ratio", "0.5", "--method", "gng", "--max-error", "0.01"],
            "to QEM only",
        ),
    ] {
        let mut args = vec!["simplify", input.to_str().unwrap(), out.to_str().unwrap()];
        args.extend_from_slice(&extra);
        let o = gng3d(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{extra:?}: {stderr}");
        assert!(stderr.contains(message), "{extra:?}: {stderr}");
        assert!(!out.exists());
    }
}

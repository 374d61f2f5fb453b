//! End-to-end tests of the `gng3d` binary on real meshes (GNG3D_MESHES).

use std::process::Command;

fn gng3d(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(args)
        .output()
        .expect("run gng3d")
}

#[test]
fn compare_writes_json_and_meshes() {
    let Some(dir) = gng3d::mesh::fixtures::shared_meshes_dir("README.md") else {
        return;
    };
    let input = dir.join("spot.obj");
    let out = tempfile::tempdir().unwrap();
    let o = gng3d(&[
        "compare",
        input.to_str().unwrap(),
        "--vertices",
        "700",
        "--samples",
        "30000",
        "--json",
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(report["target_vertices"], 700);
    for method in ["qem", "gng"] {
        let m = &report[method];
        assert!(m["metrics"]["hausdorff"]["max"].as_f64().unwrap() > 0.0);
        assert!(m["vertices"].as_u64().unwrap() <= 701);
    }
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("compare.json")).unwrap())
            .unwrap();
    assert_eq!(saved, report);
    for name in ["qem.obj", "gng.obj"] {
        let info = gng3d(&["info", out.path().join(name).to_str().unwrap(), "--json"]);
        assert!(info.status.success());
        let v: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
        assert_eq!(v["vertices"], report[&name[..3]]["vertices"]);
    }
}

#[test]
fn reproduce_small_run_writes_table() {
    let Some(dir) = gng3d::mesh::fixtures::shared_meshes_dir("README.md") else {
        return;
    };
    let input = dir.join("decimated-knight.obj");
    let out = tempfile::tempdir().unwrap();
    let o = gng3d(&[
        "reproduce",
        input.to_str().unwrap(),
        "--epochs",
        "5",
        "--samples",
        "10000",
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.path().join("table.md")).unwrap();
    assert!(md.contains("| iteration"));
    assert!(out.path().join("figure1_esur.png").exists());
}

#[test]
fn bad_input_fails_with_message_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nf 1 2 9\n").unwrap();
    for args in [
        vec!["compare", bad.to_str().unwrap(), "--vertices", "3"],
        vec!["reproduce", bad.to_str().unwrap()],
        vec!["info", "/nonexistent/mesh.obj"],
    ] {
        let o = gng3d(&args);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.starts_with("error:"), "{err}");
        assert!(
            err.contains("broken.obj") || err.contains("mesh.obj"),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn simplify_gng_json_reports_the_count_and_warnings_and_empty_results_fail() {
    use gng3d::mesh::{self, TriMesh};
    let glam_vec3 = glam::Vec3::new;
    let dir = tempfile::tempdir().unwrap();
    // A sphere plus one far stray triangle (a scanner outlier).
    let mut m: TriMesh = mesh::procedural::icosphere(3);
    let base = m.positions.len() as u32;
    let far = glam_vec3(1e8, 0.0, 0.0);
    m.positions.extend([
        far,
        far + glam_vec3(100.0, 0.0, 0.0),
        far + glam_vec3(0.0, 100.0, 0.0),
    ]);
    m.triangles.push([base, base + 1, base + 2]);
    let input = dir.path().join("outlier.obj");
    mesh::io::save(&m, &input).unwrap();
    let out = dir.path().join("out.obj");
    let args = |extra: &[&str]| {
        let mut a = vec![
            "simplify",
            input.to_str().unwrap(),
            out.to_str().unwrap(),
            "--method",
            "gng",
            "--vertices",
            "200",
            "--json",
        ];
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let run = |a: Vec<String>| {
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        gng3d(&refs)
    };
    let o = run(args(&[]));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["target_vertices"], 200);
    assert_eq!(v["vertices"], 200);
    assert_eq!(v["warnings"][0]["kind"], "dropped_components");
    assert!(String::from_utf8_lossy(&o.stderr).contains("warning:"));
    let info = gng3d(&["info", out.to_str().unwrap(), "--json"]);
    assert!(info.status.success());
    // A time limit too short for any network is an error, and no file is written.
    std::fs::remove_file(&out).unwrap();
    let o = run(args(&["--time-limit", "1e-9"]));
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.starts_with("error:") && err.contains("too few"),
        "{err}"
    );
    assert!(!out.exists());
}

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

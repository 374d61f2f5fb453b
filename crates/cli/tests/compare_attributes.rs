//! `compare` measures attribute deviation per method but writes positions only: a file with
//! texture coordinates or normals says so on stderr instead of losing them silently; a
//! positions-only file does not.

use std::process::Command;

/// `compare --json` on `input`: stderr and the report.
fn compare(input: &std::path::Path) -> (String, serde_json::Value) {
    let o = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(["compare", input.to_str().unwrap(), "--vertices", "60"])
        .args(["--samples", "2000", "--json"])
        .output()
        .expect("run gng3d");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (
        String::from_utf8_lossy(&o.stderr).into_owned(),
        serde_json::from_slice(&o.stdout).unwrap(),
    )
}

#[test]
fn compare_names_the_attributes_it_does_not_keep() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, attributes) = gng3d::mesh::procedural::textured_sphere(12, 16);
    let textured = dir.path().join("textured.obj");
    gng3d::mesh::io::save(
        &gng3d::mesh::Model::new(mesh.clone(), Some(attributes.clone()), None),
        &textured,
    )
    .unwrap();
    let (stderr, report) = compare(&textured);
    let line = stderr
        .lines()
        .find(|l| l.contains("not written"))
        .unwrap_or_else(|| panic!("no warning about the attributes: {stderr}"));
    assert!(
        line.starts_with("warning: ") && line.contains("textured.obj"),
        "{line}"
    );
    assert!(
        line.contains("texture coordinates") && line.contains("normals"),
        "{line}"
    );

    let plain = dir.path().join("plain.obj");
    gng3d::mesh::io::save(&mesh.clone().into(), &plain).unwrap();
    // Each method's attribute deviation: QEM keeps the seams, GNG3D's transfer smears its
    // triangles that straddle the meridian; both have their UVs and normals measured.
    for method in ["qem", "gng"] {
        let a = &report[method]["metrics"]["attributes"];
        assert_eq!(a["compared"], serde_json::json!(["normals", "uv0"]), "{a}");
        let uv = &a["backward"]["uv0"];
        let mean = uv["uv"]["mean"].as_f64().unwrap();
        assert!(mean > 0.0 && mean < 0.1, "{method}: {uv}");
        assert_eq!(a["backward"]["samples"], 2000);
    }
    let (stderr, report) = compare(&plain);
    assert!(!stderr.contains("not used"), "{stderr}");
    assert!(!stderr.contains("not written"), "{stderr}");
    assert!(report["qem"]["metrics"].get("attributes").is_none());
}

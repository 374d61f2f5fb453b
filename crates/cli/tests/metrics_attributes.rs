//! `gng3d metrics` measures attribute deviation (issue 35 item 5) when the original has
//! texture coordinates, normals or colours: a JSON `"attributes"` section and text lines, and
//! neither for a positions-only original.

use std::path::Path;
use std::process::Command;

fn metrics(original: &Path, simplified: &Path, extra: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(["metrics", original.to_str().unwrap()])
        .arg(simplified)
        .args(["--samples", "4000"])
        .args(extra)
        .output()
        .expect("run gng3d")
}

fn json(original: &Path, simplified: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["--json"];
    args.extend_from_slice(extra);
    let o = metrics(original, simplified, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

#[test]
fn shifted_texture_coordinates_are_reported_in_uv_units_and_texels() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, attributes) = gng3d::mesh::procedural::textured_sphere(12, 24);
    let original = dir.path().join("original.obj");
    gng3d::mesh::io::save(
        &gng3d::mesh::Model::new(mesh.clone(), Some(attributes.clone()), None),
        &original,
    )
    .unwrap();
    let mut shifted = attributes.clone();
    for uv in shifted.uv0.as_mut().unwrap() {
        uv.x += 0.03;
        uv.y -= 0.04;
    }
    let moved = dir.path().join("moved.obj");
    gng3d::mesh::io::save(
        &gng3d::mesh::Model::new(mesh.clone(), Some(shifted.clone()), None),
        &moved,
    )
    .unwrap();
    let r = json(&original, &moved, &["--texture-size", "512"]);
    let a = &r["attributes"];
    assert_eq!(a["compared"], serde_json::json!(["normals", "uv0"]), "{a}");
    assert_eq!(a["texture_size"], 512);
    for dir in ["backward", "forward"] {
        let uv = &a[dir]["uv0"];
        for stat in ["mean", "max"] {
            // The shift is 0.05 UV units, 25.6 texels of 512 (OBJ keeps 6 digits).
            assert!((f(&uv["uv"][stat]) - 0.05).abs() < 1e-5, "{uv}");
            assert!((f(&uv["texels"][stat]) - 25.6).abs() < 5e-3, "{uv}");
        }
        assert!(f(&a[dir]["normals"]["max_degrees"]) < 0.1, "{a}");
        assert_eq!(f(&a[dir]["samples"]), 4000.0);
    }
    // Every sample is 0.05 off: all over a 0.04 threshold, none over 0.06.
    let r = json(&original, &moved, &["--uv-threshold", "0.04"]);
    assert_eq!(
        f(&r["attributes"]["backward"]["uv0"]["over_threshold"]),
        1.0
    );
    let r = json(&original, &moved, &["--uv-threshold", "0.06"]);
    assert_eq!(
        f(&r["attributes"]["backward"]["uv0"]["over_threshold"]),
        0.0
    );
    // The text report has the lines.
    let o = metrics(&original, &moved, &[]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("attributes            compared normals, uv0"),
        "{text}"
    );
    assert!(
        text.contains("uv0 backward") && text.contains("texels of 1024²"),
        "{text}"
    );

    // A positions-only simplified mesh: nothing compared, what it lost is named.
    let plain = dir.path().join("plain.obj");
    gng3d::mesh::io::save(&mesh.clone().into(), &plain).unwrap();
    let r = json(&original, &plain, &[]);
    assert_eq!(r["attributes"]["compared"], serde_json::json!([]));
    assert_eq!(
        r["attributes"]["missing"],
        serde_json::json!(["normals", "uv0"])
    );
    // A positions-only original: no attribute section at all.
    let r = json(&plain, &plain, &[]);
    assert!(r.get("attributes").is_none(), "{r}");
    let o = metrics(&plain, &plain, &[]);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("attributes"));
}

#[test]
fn an_atlas_against_itself_deviates_by_nothing_across_its_seams() {
    let atlas = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/fandisk_atlas.obj");
    let r = json(&atlas, &atlas, &[]);
    let a = &r["attributes"];
    assert!(
        a["compared"].as_array().unwrap().contains(&"uv0".into()),
        "{a}"
    );
    for dir in ["backward", "forward"] {
        // Thousands of samples, some on the atlas's seams: each takes its own side's value.
        assert!(f(&a[dir]["uv0"]["uv"]["max"]) < 1e-5, "{a}");
        assert_eq!(f(&a[dir]["uv0"]["over_threshold"]), 0.0);
    }
    let colors = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/knight_colors.ply");
    let r = json(&colors, &colors, &[]);
    assert!(
        f(&r["attributes"]["backward"]["colors"]["max"]) < 1e-5,
        "{r}"
    );
}

//! `reproduce IN` on an input with attributes: table.csv and table.md get the attribute-deviation
//! columns of the survey (UV mean in texels, share of UV samples off, normal and colour
//! deviation) for GNG3D, QEM at the same count and QEM at the target, report.json each
//! checkpoint's deviations, and the terminal a second table; a positions-only input's files and
//! output are as before (the 17 columns, no key, no paragraph).

use gng3d::report::paper::CHECKPOINT_COLUMNS as PAPER_COLUMNS;
use std::path::Path;
use std::process::Output;
mod common;
use common::{gng3d, succeeded};

/// `reproduce input --out out` (2 epochs, 2,000 samples).
fn reproduce(input: &Path, out: &Path) -> Output {
    let (input, out) = (input.to_str().unwrap(), out.to_str().unwrap());
    succeeded(gng3d(&[
        "reproduce",
        input,
        "--epochs",
        "2",
        "--samples",
        "2000",
        "--out",
        out,
    ]))
}

/// The CSV's headers and rows (no cell of these tables is quoted).
fn csv(out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(out.join("table.csv")).unwrap();
    let mut lines = text
        .lines()
        .map(|l| l.split(',').map(String::from).collect::<Vec<_>>());
    let headers = lines.next().unwrap();
    (headers, lines.collect())
}

const UV_MEAN: &str = "UV deviation mean (texels of 1024²)";
const UV_OFF: &str = "UV samples off by > 0.05 UV";
const NORMALS: &str = "attribute normal deviation mean (degrees)";
const COLOURS: &str = "colour deviation mean (linear RGB distance)";

/// The measures' columns for the three meshes, in table order.
fn columns(measures: &[&str]) -> Vec<String> {
    let mut all: Vec<String> = PAPER_COLUMNS.map(String::from).to_vec();
    for m in measures {
        all.extend([
            m.to_string(),
            format!("QEM= {m}"),
            format!("QEM@target {m}"),
        ]);
    }
    all
}

#[test]
fn reproduce_has_attribute_columns_only_for_inputs_with_attributes() {
    let dir = tempfile::tempdir().unwrap();
    let (sphere, attributes) = mesh::procedural::textured_sphere(10, 16);
    let globe = dir.path().join("globe.obj");
    mesh::io::save(
        &mesh::Model::new(sphere.clone(), Some(attributes.clone()), None),
        &globe,
    )
    .unwrap();
    let out = dir.path().join("globe");
    let o = reproduce(&globe, &out);
    let (headers, rows) = csv(&out);
    assert_eq!(headers, columns(&[UV_MEAN, UV_OFF, NORMALS]));
    assert!(rows.len() >= 2, "one row per epoch");
    for row in &rows {
        for (h, cell) in headers.iter().zip(row).skip(17) {
            let v: f64 = cell
                .trim_end_matches(" %")
                .trim_end_matches('°')
                .parse()
                .unwrap_or_else(|_| panic!("{h}: {cell:?}"));
            assert!(v.is_finite() && v >= 0.0, "{h}: {v}");
            if h.contains("samples off") {
                assert!(v <= 100.0, "{h}: {v}");
            }
            if h.contains("normal") {
                assert!(v < 45.0, "{h}: {v}");
            }
        }
    }
    let md = std::fs::read_to_string(out.join("table.md")).unwrap();
    assert!(md.contains(&format!("| QEM@target {UV_MEAN} |")), "{md}");
    assert!(md.contains("Attribute columns"), "{md}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    for c in json["checkpoints"].as_array().unwrap() {
        for mesh in ["gng", "qem_equal"] {
            let a = &c["attributes"][mesh];
            assert_eq!(a["compared"], serde_json::json!(["normals", "uv0"]), "{a}");
            assert_eq!(a["backward"]["samples"], 2000);
        }
    }
    assert_eq!(
        json["qem_fixed_attributes"]["compared"],
        serde_json::json!(["normals", "uv0"])
    );
    // The terminal: the paper's table, then the attribute table and its legend.
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("E_avg GNG"), "{stdout}");
    for needle in [
        "UV GNG",
        "UV QEM",
        "UV off GNG",
        "normal QEM",
        "QEM at the target",
    ] {
        assert!(stdout.contains(needle), "{needle:?} missing in {stdout}");
    }
    assert!(!stdout.contains("RGB GNG"), "{stdout}");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!stderr.contains("not used"), "{stderr}");

    // Colours only: the colour column alone.
    let knight = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/knight_colors.ply");
    let out = dir.path().join("knight");
    let o = reproduce(&knight, &out);
    assert_eq!(csv(&out).0, columns(&[COLOURS]));
    assert!(String::from_utf8_lossy(&o.stdout).contains("RGB GNG"));

    // Positions only: the 17 columns, no key, no paragraph, no second table.
    let ball = dir.path().join("ball.obj");
    mesh::io::save(&mesh::procedural::icosphere(2).into(), &ball).unwrap();
    let out = dir.path().join("ball");
    let o = reproduce(&ball, &out);
    assert_eq!(csv(&out).0, columns(&[]));
    let md = std::fs::read_to_string(out.join("table.md")).unwrap();
    assert!(!md.contains("UV deviation") && !md.contains("Attribute columns"));
    let json = std::fs::read_to_string(out.join("report.json")).unwrap();
    assert!(!json.contains("attributes"), "{json}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(!stdout.contains("UV GNG") && !stdout.contains("Attribute deviation"));
}

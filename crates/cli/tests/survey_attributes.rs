//! `reproduce --all` measures the attribute deviation of every method's output when an input
//! has attributes (issue 35 item 5): summary.csv gets UV, normal and colour columns per method
//! with finite values for the inputs that have them ("-" for those that do not), summary.md a
//! column per measure, summary.json each run's deviations; a survey of positions-only inputs
//! has none of them.

use std::path::Path;
mod common;
use common::{csv_cells, gng3d, succeeded};

/// `reproduce --all meshes --out out` (2 epochs, 2,000 samples): the CSV's headers and rows.
fn survey(meshes: &Path, out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let (meshes, out_arg) = (meshes.to_str().unwrap(), out.to_str().unwrap());
    succeeded(gng3d(&[
        "reproduce",
        "--all",
        meshes,
        "--epochs",
        "2",
        "--samples",
        "2000",
        "--out",
        out_arg,
    ]));
    let text = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut lines = text.lines().map(csv_cells);
    let headers = lines.next().unwrap();
    (headers, lines.collect())
}

const METHODS: [&str; 3] = ["GNG3D (paper)", "GNG3D-Q", "QEM"];
const UV_MEAN: &str = "UV deviation mean (texels of 1024²)";
const UV_OFF: &str = "UV samples off by > 0.05 UV";
const NORMALS: &str = "attribute normal deviation mean (degrees)";
const COLOURS: &str = "colour deviation mean (linear RGB distance)";

#[test]
fn survey_measures_attributes_of_inputs_that_have_them() {
    let dir = tempfile::tempdir().unwrap();
    let meshes = dir.path().join("meshes");
    std::fs::create_dir(&meshes).unwrap();
    let (sphere, attributes) = mesh::procedural::textured_sphere(10, 16);
    mesh::io::save(
        &mesh::Model::new(sphere.clone(), Some(attributes.clone()), None),
        &meshes.join("globe.obj"),
    )
    .unwrap();
    mesh::io::save(
        &mesh::procedural::icosphere(2).into(),
        &meshes.join("ball.obj"),
    )
    .unwrap();
    let knight = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/knight_colors.ply");
    std::fs::copy(knight, meshes.join("knight.ply")).unwrap();
    let out = dir.path().join("survey");
    let (headers, rows) = survey(&meshes, &out);
    let col = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name:?} in {headers:?}"))
    };
    assert_eq!(rows.len(), 9, "3 meshes at 10, 25 and 50 %");
    let mut globe_uv = Vec::new();
    for r in &rows {
        let mesh = r[col("mesh")].as_str();
        for method in METHODS {
            let cell = |measure: &str| r[col(&format!("{measure} {method}"))].clone();
            let value = |measure: &str| {
                let c = cell(measure);
                let v: f64 = c
                    .trim_end_matches(" %")
                    .trim_end_matches('°')
                    .parse()
                    .unwrap_or_else(|_| panic!("{mesh} {method} {measure}: {c:?}"));
                assert!(v.is_finite() && v >= 0.0, "{mesh} {method} {measure}: {v}");
                v
            };
            match mesh {
                "globe.obj" => {
                    // Texture coordinates and normals kept: under a texture's width off on
                    // average and normals within 30° even at 10 % of a coarse sphere's 146
                    // vertices; at 50 % QEM and GNG3D-Q within a few dozen texels and 5°.
                    let (uv, angle) = (value(UV_MEAN), value(NORMALS));
                    assert!(uv < 1024.0 && angle < 30.0, "{mesh} {method}: {uv} {angle}");
                    assert!(value(UV_OFF) <= 100.0, "{mesh} {method}");
                    if r[col("ratio")] == "0.50" && method != "GNG3D (paper)" {
                        assert!(uv < 40.0 && angle < 5.0, "{mesh} {method}: {uv} {angle}");
                    }
                    globe_uv.push((method, r[col("ratio")].clone(), uv));
                    assert_eq!(cell(COLOURS), "-", "{mesh} {method}");
                }
                "knight.ply" => {
                    // Colours only (channels 0 to 1: a distance of at most √3).
                    assert!(value(COLOURS) < 3f64.sqrt(), "{mesh} {method}");
                    for measure in [UV_MEAN, UV_OFF, NORMALS] {
                        assert_eq!(cell(measure), "-", "{mesh} {method} {measure}");
                    }
                }
                _ => {
                    for measure in [UV_MEAN, UV_OFF, NORMALS, COLOURS] {
                        assert_eq!(cell(measure), "-", "{mesh} {method} {measure}");
                    }
                }
            }
        }
    }
    // More vertices, closer texture coordinates (QEM and GNG3D-Q, 10 % against 50 %).
    for method in ["GNG3D-Q", "QEM"] {
        let at = |ratio: &str| {
            globe_uv
                .iter()
                .find(|(m, r, _)| *m == method && r == ratio)
                .unwrap()
                .2
        };
        assert!(at("0.50") < at("0.10"), "{method}: {globe_uv:?}");
    }
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains(&format!("| {UV_MEAN} GNG3D (paper) / GNG3D-Q / QEM |")),
        "{md}"
    );
    assert!(md.contains("Attribute columns"), "{md}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    for run in json.as_array().unwrap() {
        let a = &run["attributes"];
        match run["mesh"].as_str().unwrap() {
            "globe.obj" => {
                for method in ["gng", "qem", "gngq", "qem_at_gngq"] {
                    assert_eq!(a[method]["compared"], serde_json::json!(["normals", "uv0"]));
                    assert_eq!(a[method]["backward"]["samples"], 2000);
                }
            }
            "knight.ply" => assert_eq!(a["gngq"]["compared"], serde_json::json!(["colors"])),
            _ => assert!(a.is_null(), "{run}"),
        }
    }

    // Positions only: no attribute column, no key, no paragraph.
    std::fs::remove_file(meshes.join("globe.obj")).unwrap();
    std::fs::remove_file(meshes.join("knight.ply")).unwrap();
    let plain = dir.path().join("plain");
    let (headers, _) = survey(&meshes, &plain);
    for h in &headers {
        for measure in [UV_MEAN, UV_OFF, NORMALS, COLOURS] {
            assert!(!h.starts_with(measure), "{h}");
        }
    }
    let md = std::fs::read_to_string(plain.join("summary.md")).unwrap();
    assert!(!md.contains("UV deviation") && !md.contains("Attribute columns"));
    let json = std::fs::read_to_string(plain.join("summary.json")).unwrap();
    assert!(!json.contains("\"attributes\""), "{json}");
}

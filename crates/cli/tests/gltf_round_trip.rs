//! glTF in, `gng3d simplify` with either method, glTF out (issue 35's round trip): the output
//! (`.glb`, or `.gltf` + `.bin`) keeps every attribute, reloads, and passes the Khronos glTF-Validator with no error and no
//! warning (npm `gltf-validator`, found through GLTF_VALIDATOR_MODULE or Node's lookup; the
//! validation says SKIPPED when node or the module is missing; CI installs both).

use mesh::attributes::Attributes;
use std::path::Path;
use std::process::Command;

fn simplify(input: &Path, output: &Path, method: &str) -> serde_json::Value {
    let o = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args([
            "simplify",
            input.to_str().unwrap(),
            output.to_str().unwrap(),
            "--method",
            method,
            "--ratio",
            "0.25",
            "--json",
        ])
        .output()
        .expect("run gng3d");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn gltf_with_normals_and_uvs_survives_both_simplifiers_and_validates() {
    let dir = tempfile::tempdir().unwrap();
    // A textured sphere (UV seam along a meridian, normals) as .glb and as .gltf + .bin.
    let (sphere, attributes): (mesh::TriMesh, Attributes) =
        mesh::procedural::textured_sphere(24, 48);
    let mut outputs = Vec::new();
    for input_name in ["sphere.glb", "sphere.gltf"] {
        let input = dir.path().join(input_name);
        mesh::io::save(
            &mesh::Model::new(sphere.clone(), Some(attributes.clone()), None),
            &input,
        )
        .unwrap();
        for method in ["qem", "gng"] {
            let output = dir.path().join(format!("{method}-{input_name}"));
            let j = simplify(&input, &output, method);
            let names = serde_json::json!(["normals", "uv0"]);
            assert_eq!(j["attributes"]["input"], names, "{j}");
            assert_eq!(j["attributes"]["kept"], names, "{j}");
            assert_eq!(j["attributes"]["dropped"], serde_json::json!([]), "{j}");
            if input_name.ends_with(".gltf") {
                // A .gltf output is written with its buffer in `<stem>.bin` next to it.
                let bin = format!("{method}-sphere.bin");
                let json: serde_json::Value =
                    serde_json::from_slice(&std::fs::read(&output).unwrap()).unwrap();
                assert_eq!(json["buffers"][0]["uri"], bin.as_str(), "{method}");
                assert_eq!(
                    json["buffers"][0]["byteLength"].as_u64(),
                    Some(std::fs::metadata(dir.path().join(&bin)).unwrap().len()),
                    "{method}"
                );
            }
            let back = mesh::io::load(&output).unwrap();
            assert!(back.warnings.is_empty(), "{:?}", back.warnings);
            let a = back.attributes.expect("attributes in the output");
            a.validate(&back.mesh).unwrap();
            assert_eq!(
                a.kinds(),
                vec![mesh::AttributeKind::Normals, mesh::AttributeKind::Uv0]
            );
            // A quarter of the vertices (the sphere's poles and seam are welded first).
            let n = back.mesh.vertex_count();
            let expected = j["vertices"].as_u64().unwrap() as usize;
            assert_eq!(n, expected, "{method} {input_name}");
            assert!(n > 200 && n < 400, "{method} {input_name}: {n} vertices");
            // The seam is still a seam, and every normal is a unit vector near the sphere's.
            assert!(!a.seam_edges(&back.mesh).is_empty(), "{method}: no seam");
            for (w, nrm) in a.normals.as_ref().unwrap().iter().enumerate() {
                let p = back.mesh.positions[a.wedge_vertex[w] as usize].normalize();
                assert!((nrm.length() - 1.0).abs() < 1e-4);
                assert!(nrm.dot(p) > 0.95, "{method}: wedge {w} normal {nrm} at {p}");
            }
            outputs.push(output);
        }
    }
    let Some(reports) = mesh::fixtures::validate_gltf(&outputs) else {
        return;
    };
    assert_eq!(reports.len(), outputs.len());
    for r in &reports {
        assert_eq!(r["errors"], 0, "{r}");
        assert_eq!(r["warnings"], 0, "{r}");
    }
}

//! Georeferenced models keep their coordinates (issue 46): a 20 m scan placed at UTM-like
//! coordinates (x = 450,000, y = 5,400,000) goes through `gng3d simplify --ratio 1` to OBJ,
//! PLY, glTF and GLB, and every output vertex lies within 1e-6 of the model's extent of an input
//! vertex, read back independently in f64 (the OBJ text, the PLY doubles, the glTF positions
//! plus the node's translation). Without recentring, f32 moves such vertices by up to 0.25 m.

use std::path::Path;
mod common;
use common::{gng3d, s, succeeded};

const OFFSET: [f64; 3] = [450_000.0, 5_400_000.0, 120.0];

/// The input in f64: an icosphere of radius 10 m at OFFSET, written as OBJ with millimetres.
fn input(dir: &Path) -> (std::path::PathBuf, Vec<[f64; 3]>) {
    let sphere = mesh::procedural::icosphere(3);
    let points: Vec<[f64; 3]> = sphere
        .positions
        .iter()
        .map(|p| {
            let q = p.as_dvec3() * 10.0;
            // Millimetre coordinates, as survey data comes.
            [0, 1, 2].map(|k| ((q[k] + OFFSET[k]) * 1000.0).round() / 1000.0)
        })
        .collect();
    let mut text = String::new();
    for p in &points {
        text.push_str(&format!("v {:.3} {:.3} {:.3}\n", p[0], p[1], p[2]));
    }
    for t in &sphere.triangles {
        text.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    let path = dir.join("scan.obj");
    std::fs::write(&path, text).unwrap();
    (path, points)
}

/// The output's positions in f64, read without the project's loader.
fn read_f64(path: &Path) -> Vec<[f64; 3]> {
    let bytes = std::fs::read(path).unwrap();
    match path.extension().unwrap().to_str().unwrap() {
        "obj" => String::from_utf8(bytes)
            .unwrap()
            .lines()
            .filter_map(|l| l.strip_prefix("v "))
            .map(|l| {
                let v: Vec<f64> = l
                    .split_whitespace()
                    .take(3)
                    .map(|t| t.parse().unwrap())
                    .collect();
                [v[0], v[1], v[2]]
            })
            .collect(),
        "ply" => {
            let text = String::from_utf8_lossy(&bytes);
            let end = text.find("end_header\n").unwrap() + "end_header\n".len();
            let header = &text[..end];
            assert!(header.contains("property double x"), "{header}");
            let count: usize = header
                .lines()
                .find_map(|l| l.strip_prefix("element vertex "))
                .unwrap()
                .parse()
                .unwrap();
            (0..count)
                .map(|i| {
                    [0, 1, 2].map(|k| {
                        let at = end + i * 24 + k * 8;
                        f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap())
                    })
                })
                .collect()
        }
        _ => {
            // glTF / GLB: positions (f32) plus the node's translation (f64 in the JSON).
            let (json, bin) = if bytes.starts_with(b"glTF") {
                let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
                let json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
                (json, bytes[20 + len + 8..].to_vec())
            } else {
                let json: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
                let uri = json["buffers"][0]["uri"].as_str().unwrap().to_string();
                (json, std::fs::read(path.with_file_name(uri)).unwrap())
            };
            let t: Vec<f64> = json["nodes"][0]["translation"]
                .as_array()
                .expect("a node translation")
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect();
            let position = json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
                .as_u64()
                .unwrap() as usize;
            let accessor = &json["accessors"][position];
            let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
            let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
                + accessor["byteOffset"].as_u64().unwrap_or(0) as usize;
            let count = accessor["count"].as_u64().unwrap() as usize;
            (0..count)
                .map(|i| {
                    [0, 1, 2].map(|k| {
                        let at = start + i * 12 + k * 4;
                        f32::from_le_bytes(bin[at..at + 4].try_into().unwrap()) as f64 + t[k]
                    })
                })
                .collect()
        }
    }
}

#[test]
fn georeferenced_models_keep_their_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    let (scan, points) = input(dir.path());
    let extent = 20.0;
    for ext in ["obj", "ply", "gltf", "glb"] {
        let out = dir.path().join(format!("out.{ext}"));
        succeeded(gng3d(&["simplify", s(&scan), s(&out), "--ratio", "1"]));
        let back = read_f64(&out);
        assert_eq!(back.len(), points.len(), "{ext}");
        let mut worst = 0.0f64;
        for q in &back {
            let d = points
                .iter()
                .map(|p| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>())
                .fold(f64::INFINITY, f64::min)
                .sqrt();
            worst = worst.max(d);
        }
        assert!(
            worst <= 1e-6 * extent,
            "{ext}: a vertex moved by {worst} m (limit {})",
            1e-6 * extent
        );
        // The project's loader reads it back recentred, at the same place.
        let loaded = mesh::io::load(&out).unwrap();
        let o = loaded.origin;
        assert!(
            (o.x - OFFSET[0]).abs() < 20.0 && (o.y - OFFSET[1]).abs() < 20.0,
            "{o}"
        );
    }
    // STL stores f32: written with a warning naming the rounding.
    let out = dir.path().join("out.stl");
    let result = succeeded(gng3d(&["simplify", s(&scan), s(&out), "--ratio", "1"]));
    let err = String::from_utf8_lossy(&result.stderr);
    assert!(err.contains("STL stores 32-bit coordinates"), "{err}");
}

#[test]
fn models_near_the_origin_are_not_moved() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.obj");
    mesh::io::save(&mesh::procedural::icosphere(2).into(), &path).unwrap();
    let loaded = mesh::io::load(&path).unwrap();
    assert_eq!(loaded.origin, glam::DVec3::ZERO);
}

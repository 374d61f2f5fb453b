//! Oracle test: our two-sided surface distance with [`HausdorffParams::meshlab`] (MeshLab's
//! sampling plan: all vertices + N edge + N face samples) against MeshLab's
//! `get_hausdorff_distance` figures: max, mean and RMS within 1 % per direction, on
//!
//! - the two shared reference pairs in `reference/hausdorff.json` (N = 1,000,000), and
//! - ten pairs made here with pymeshlab from five other shared meshes at 1 % and 10 % of the
//!   faces (`tests/meshlab/`: the simplified meshes, 1.6-50 kB each, and the MeshLab figures
//!   at N = 300,000 in `meshlab_pairs.json`; `tests/meshlab/make_pairs.py` regenerates them).
//!
//! The reference folder comes from `GNG3D_REFERENCE`, else `$GNG3D_MESHES/../reference`. When
//! it is missing the test fails under `CI` and is skipped (with a message) otherwise.

// Published as gng3d-metrics; this file keeps the workspace's name for it.
extern crate gng3d_metrics as metrics;

use metrics::{HausdorffParams, OneSided, SurfaceDistanceIndex, one_sided};
use std::path::{Path, PathBuf};

/// The reference folder, or `None` (after failing under CI) when it is not available.
fn reference_dir() -> Option<PathBuf> {
    let dir = match std::env::var_os("GNG3D_REFERENCE") {
        Some(dir) => Ok(PathBuf::from(dir)),
        None => mesh::fixtures::find_shared_meshes("README.md").map(|m| m.join("../reference")),
    };
    match dir {
        Ok(d) if d.join("hausdorff.json").is_file() => Some(d),
        other => {
            let why = match other {
                Ok(d) => format!("no hausdorff.json in {} (set GNG3D_REFERENCE)", d.display()),
                Err(why) => format!("GNG3D_REFERENCE not set and {why}"),
            };
            mesh::fixtures::skip_unless_ci(&format!("MeshLab reference not found: {why}"));
            None
        }
    }
}

/// The mesh folder holding the originals.
fn meshes_dir(reference: &Path) -> PathBuf {
    mesh::fixtures::find_shared_meshes("README.md").unwrap_or_else(|_| reference.join("../meshes"))
}

fn load(path: &Path) -> mesh::TriMesh {
    mesh::io::load(path)
        .unwrap_or_else(|e| panic!("cannot load {}: {e}", path.display()))
        .mesh
}

fn check(name: &str, ours: &OneSided, theirs: &serde_json::Value) {
    let get = |k: &str| {
        theirs[k]
            .as_f64()
            .unwrap_or_else(|| panic!("{name}: no {k}"))
    };
    for (label, ours, theirs) in [
        ("max", ours.max, get("max")),
        ("mean", ours.mean, get("mean")),
        ("RMS", ours.rms, get("RMS")),
    ] {
        let rel = (ours - theirs).abs() / theirs;
        eprintln!(
            "{name} {label}: ours {ours:.6e} meshlab {theirs:.6e} ({:+.2}%)",
            100.0 * (ours - theirs) / theirs
        );
        assert!(
            rel <= 0.01,
            "{name} {label}: ours {ours} vs MeshLab {theirs} ({rel:.4} relative)"
        );
    }
}

#[test]
fn agrees_with_meshlab_reference_pairs() {
    let Some(reference) = reference_dir() else {
        return;
    };
    let meshes = meshes_dir(&reference);
    let text = std::fs::read_to_string(reference.join("hausdorff.json")).unwrap();
    let cases: serde_json::Value = serde_json::from_str(&text).unwrap();
    let cases = cases.as_array().expect("hausdorff.json is a list");
    assert!(cases.len() >= 2);
    for case in cases {
        let original_name = case["original"].as_str().unwrap();
        let simplified_name = case["simplified"].as_str().unwrap();
        let original = load(&meshes.join(original_name));
        let simplified = load(&reference.join(simplified_name));
        let fwd = &case["meshlab_hausdorff"]["forward_original_to_simplified"];
        let bwd = &case["meshlab_hausdorff"]["backward_simplified_to_original"];
        // The reference counts (e.g. 2,043,253 = 43,243 vertices + 2,000,010 for armadillo's
        // forward pass, 2,000,648 = 649 vertices + 1,999,999 for fandisk's backward pass) match
        // MeshLab with samplevert + sampleedge + sampleface and samplenum = 1M: every vertex,
        // ~1M edge points (its float remainder drifts by a few) and exactly 1M Monte Carlo face
        // points. Use the same plan: all vertices, then half edges and half faces.
        let start = std::time::Instant::now();
        let original_index = SurfaceDistanceIndex::new(&original).unwrap();
        let simplified_index = SurfaceDistanceIndex::new(&simplified).unwrap();
        let diag = case["bbox_diagonal"].as_f64().unwrap();
        assert!((original.bbox_diagonal() - diag).abs() <= 1e-6 * diag);
        let run =
            |source: &mesh::TriMesh, target: &SurfaceDistanceIndex, theirs: &serde_json::Value| {
                // MeshLab's n_samples = vertices + 2 N, so N = (n_samples - vertices) / 2.
                let n = theirs["n_samples"].as_u64().unwrap() as usize;
                let vertices = referenced(source);
                let params = HausdorffParams::meshlab((n - vertices) / 2);
                let ours = one_sided(source, target, &params, diag).unwrap();
                assert_eq!(ours.excluded, 0);
                assert!(
                    ours.samples
                        .abs_diff(theirs["n_samples"].as_u64().unwrap() as usize)
                        <= 16
                );
                ours
            };
        let forward = run(&original, &simplified_index, fwd);
        let backward = run(&simplified, &original_index, bwd);
        eprintln!(
            "{original_name}: both directions in {:.2?}",
            start.elapsed()
        );
        check(&format!("{original_name} forward"), &forward, fwd);
        check(&format!("{original_name} backward"), &backward, bwd);
    }
}

/// Vertices used by a triangle.
fn referenced(m: &mesh::TriMesh) -> usize {
    let mut used = vec![false; m.positions.len()];
    for &v in m.triangles.iter().flatten() {
        used[v as usize] = true;
    }
    used.iter().filter(|&&u| u).count()
}

#[test]
fn agrees_with_meshlab_on_pairs_made_from_other_shared_meshes() {
    let Some(meshes) = mesh::fixtures::shared_meshes_dir("README.md") else {
        return;
    };
    let here = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/meshlab");
    let text = std::fs::read_to_string(here.join("meshlab_pairs.json")).unwrap();
    let fixture: serde_json::Value = serde_json::from_str(&text).unwrap();
    let pairs = fixture["pairs"].as_array().unwrap();
    assert_eq!(pairs.len(), 10, "five meshes at 1 % and 10 %");
    let mut worst = 0.0f64;
    for case in pairs {
        let original = load(&meshes.join(case["original"].as_str().unwrap()));
        let simplified = load(&here.join(case["simplified"].as_str().unwrap()));
        assert_eq!(
            simplified.face_count() as u64,
            case["simplified_faces"].as_u64().unwrap()
        );
        let n = case["samplenum"].as_u64().unwrap() as usize;
        let diag = original.bbox_diagonal();
        let oi = SurfaceDistanceIndex::new(&original).unwrap();
        let si = SurfaceDistanceIndex::new(&simplified).unwrap();
        let params = HausdorffParams::meshlab(n);
        let name = case["simplified"].as_str().unwrap();
        for (label, source, target, theirs) in [
            (
                "forward",
                &original,
                &si,
                &case["meshlab_hausdorff"]["forward_original_to_simplified"],
            ),
            (
                "backward",
                &simplified,
                &oi,
                &case["meshlab_hausdorff"]["backward_simplified_to_original"],
            ),
        ] {
            let ours = one_sided(source, target, &params, diag).unwrap();
            // Same plan: every vertex, N edge and N face samples (edge count within a few).
            let theirs_n = theirs["n_samples"].as_u64().unwrap() as usize;
            assert!(
                ours.samples.abs_diff(theirs_n) <= 16,
                "{name} {label}: {} vs {theirs_n}",
                ours.samples
            );
            for k in ["max", "mean", "RMS"] {
                let t = theirs[k].as_f64().unwrap();
                let o = match k {
                    "max" => ours.max,
                    "mean" => ours.mean,
                    _ => ours.rms,
                };
                worst = worst.max((o - t).abs() / t);
            }
            check(&format!("{name} {label}"), &ours, theirs);
        }
    }
    eprintln!(
        "worst relative difference to MeshLab: {:.3}%",
        100.0 * worst
    );
}

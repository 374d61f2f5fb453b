//! Issue 33, rows 15 and 16, through the `gng3d` binary: `metrics --json` on meshes in 1e-25 to
//! 1e15 model units gives the same figures relative to the model's size (a sphere against itself
//! was 0.6 % to 58 % of its diagonal away from itself before), in the model's units; meshes too
//! far apart are refused naming the file; `--meshlab` samples the unreferenced vertices, as
//! MeshLab does. Inputs are generated here, so these need no shared data.

use glam::Vec3;
use mesh::TriMesh;
use std::path::{Path, PathBuf};
mod common;
use common::{gng3d, json_of, s, stderr};

fn save(dir: &Path, name: &str, m: &TriMesh) -> PathBuf {
    let p = dir.join(name);
    mesh::io::save(&m.clone().into(), &p).unwrap();
    p
}

fn scaled(m: &TriMesh, factor: f32) -> TriMesh {
    TriMesh::new(
        m.positions.iter().map(|p| *p * factor).collect(),
        m.triangles.clone(),
    )
}

/// A flat `n` × `n` grid of unit squares at height `z`.
fn grid(n: u32, z: f32) -> TriMesh {
    let mut g = mesh::procedural::unit_square_grid(n);
    for p in &mut g.positions {
        *p = Vec3::new(p.x * n as f32, p.y * n as f32, z);
    }
    g
}

fn num(v: &serde_json::Value, path: &[&str]) -> f64 {
    path.iter()
        .fold(v, |v, k| &v[*k])
        .as_f64()
        .unwrap_or_else(|| panic!("{path:?} is not a number in {v}"))
}

#[test]
fn metrics_of_a_sphere_against_itself_vanish_at_every_scale() {
    let dir = tempfile::tempdir().unwrap();
    let unit = mesh::procedural::icosphere(3);
    for factor in [1e-25f32, 1e-10, 1.0, 1e10, 1e15] {
        let m = scaled(&unit, factor);
        let p = save(dir.path(), &format!("sphere-{factor:e}.ply"), &m);
        let v = json_of(&gng3d(&[
            "metrics",
            s(&p),
            s(&p),
            "--samples",
            "20000",
            "--json",
        ]));
        let diag = num(&v, &["bbox_diagonal"]);
        assert!(
            (diag / m.bbox_diagonal() - 1.0).abs() < 1e-12,
            "{factor:e}: diagonal {diag:e} in the model's units"
        );
        for key in [
            ["hausdorff", "max"],
            ["hausdorff", "mean"],
            ["hausdorff", "rms"],
        ] {
            let d = num(&v, &key);
            assert!(d <= 1e-6 * diag, "{factor:e}: {key:?} = {d:e} of {diag:e}");
        }
        assert!(num(&v, &["hausdorff", "relative", "max"]) <= 1e-6);
        assert!(num(&v, &["e_max"]) <= (1e-6 * diag).powi(2));
        assert!(num(&v, &["e_sur_abs"]) <= 1e-6 * num(&v, &["original_area"]));
        let angle = num(&v, &["normal_deviation", "forward", "mean_degrees"]);
        assert!(angle < 0.1, "{factor:e}: normals {angle}° apart");
    }
}

#[test]
fn a_known_offset_comes_out_in_the_models_units_at_every_scale() {
    let dir = tempfile::tempdir().unwrap();
    // 8 × 8 squares, the copy 1 % of the diagonal above: every point's closest point on the
    // other plane is straight above or below it.
    let diag = 8.0 * 2f64.sqrt();
    for factor in [1e-25f32, 1e-10, 1e10, 1e15] {
        let offset = (0.01 * diag) as f32;
        let a = save(dir.path(), "a.ply", &scaled(&grid(8, 0.0), factor));
        let b = save(dir.path(), "b.ply", &scaled(&grid(8, offset), factor));
        let v = json_of(&gng3d(&[
            "metrics",
            s(&a),
            s(&b),
            "--samples",
            "20000",
            "--json",
        ]));
        let expected = (offset * factor) as f64;
        for key in [
            ["forward", "max"],
            ["forward", "mean"],
            ["backward", "max"],
            ["backward", "rms"],
        ] {
            let d = num(&v["hausdorff"], &key);
            assert!(
                (d / expected - 1.0).abs() < 1e-6,
                "{factor:e}: {key:?} = {d:e}, expected {expected:e}"
            );
        }
        let rel = num(&v, &["hausdorff", "relative", "max"]);
        assert!((rel - 0.01).abs() < 1e-6, "{factor:e}: {rel}");
    }
}

#[test]
fn meshes_too_far_apart_are_refused_naming_the_file_and_huge_ones_are_measured() {
    let dir = tempfile::tempdir().unwrap();
    let unit = mesh::procedural::icosphere(1);
    let a = save(dir.path(), "unit.ply", &unit);
    // 3e38, near f32::MAX: a pair at that scale is measured (it was refused beyond 1e18)...
    let huge = save(dir.path(), "huge.ply", &scaled(&unit, 3e38));
    let v = json_of(&gng3d(&[
        "metrics",
        s(&huge),
        s(&huge),
        "--samples",
        "2000",
        "--json",
    ]));
    assert!(num(&v, &["hausdorff", "relative", "max"]) <= 1e-6);
    // ... but a unit sphere against it spans 1e38 unit diagonals: refused, naming the file.
    let o = gng3d(&["metrics", s(&a), s(&huge), "--samples", "2000"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for needle in ["huge.ply", "simplified mesh", "1e18"] {
        assert!(err.contains(needle), "missing {needle:?} in {err}");
    }
}

#[test]
fn meshlab_mode_samples_unreferenced_vertices() {
    let dir = tempfile::tempdir().unwrap();
    // A 4 × 4 plane with three unreferenced vertices above its interior, at heights 0.5, 2.5
    // and 1: MeshLab samples every vertex, so the forward max is the highest of them, 2.5.
    let mut original = grid(4, 0.0);
    original.positions.extend([
        Vec3::new(1.5, 1.5, 0.5),
        Vec3::new(2.25, 1.75, 2.5),
        Vec3::new(3.0, 0.5, 1.0),
    ]);
    let farthest = 2.5;
    let o = save(dir.path(), "unreferenced.ply", &original);
    // The same square in 2 × 2 cells.
    let t = save(dir.path(), "plane.ply", &scaled(&grid(2, 0.0), 2.0));
    let run = |extra: &[&str]| {
        let mut args = vec!["metrics", s(&o), s(&t), "--samples", "5000", "--json"];
        args.extend_from_slice(extra);
        json_of(&gng3d(&args))
    };
    let v = run(&["--meshlab"]);
    let forward = &v["hausdorff"]["forward"];
    assert_eq!(forward["vertex_samples"], 25 + 3);
    assert!(
        (num(forward, &["max"]) - farthest).abs() < 1e-6,
        "{forward}"
    );
    // Metro's plan samples the surface only.
    let v = run(&[]);
    assert!(num(&v, &["hausdorff", "forward", "max"]) < 1e-6);
}

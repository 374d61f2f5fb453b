//! The viewer and the CLI measure a simplified mesh with the same code (`metrics::Evaluator`) and
//! the same sampling parameters, so `gng3d metrics --samples 200000` and the viewer's table must
//! report identical numbers for the same pair (issue: one evaluation record).

use std::process::Command;

#[test]
fn viewer_and_cli_report_identical_numbers_for_the_same_pair() {
    let dir = tempfile::tempdir().unwrap();
    let original = mesh::procedural::icosphere(4);
    let params = qem::QemParams::with_target(qem::Target::Vertices(300));
    let (simplified, _) = qem::simplify(&mesh::Model::from(original.clone()), &params).unwrap();
    let simplified = simplified.mesh;
    let (a, b) = (dir.path().join("a.ply"), dir.path().join("b.ply"));
    mesh::io::save(&original.clone().into(), &a).unwrap();
    mesh::io::save(&simplified.clone().into(), &b).unwrap();

    let out = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .arg("metrics")
        .arg(&a)
        .arg(&b)
        .args([
            "--samples",
            &viewer::engine::HAUSDORFF_SAMPLES.to_string(),
            "--json",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cli: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();

    // The viewer evaluates the meshes as loaded (binary PLY round-trips f32 exactly).
    let load = |p: &std::path::Path| mesh::io::load(p).unwrap().mesh;
    let shown = viewer::engine::evaluate(&load(&a), &load(&b)).unwrap();

    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    assert_eq!(shown.e_avg, f(&cli["e_avg"]));
    assert_eq!(shown.e_max, f(&cli["e_max"]));
    assert_eq!(shown.e_sur, f(&cli["e_sur_signed"]));
    assert_eq!(shown.hausdorff, Some(f(&cli["hausdorff"]["max"])));
    let quality = &cli["quality"]["simplified"];
    assert_eq!(
        shown.median_min_angle_degrees,
        f(&quality["median_min_angle_degrees"])
    );
    assert_eq!(shown.below_20_degrees, f(&quality["below_20_degrees"]));
    assert!(shown.hausdorff.unwrap() > 0.0 && shown.e_sur > 0.0);
}

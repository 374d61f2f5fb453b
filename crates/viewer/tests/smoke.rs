//! Smoke run of the real binary under `xvfb-run`: open a shared mesh, train for a few seconds,
//! save a screenshot and exit by itself. Fails under CI when xvfb-run or the meshes are missing,
//! skips otherwise.

use std::process::Command;

fn requirement_missing(what: &str) {
    if std::env::var_os("CI").is_some() {
        panic!("CI: {what}");
    }
    eprintln!("skipping viewer smoke test: {what}");
}

#[test]
fn binary_opens_mesh_trains_and_saves_non_blank_screenshot() {
    let Some(meshes) = mesh::fixtures::shared_meshes_dir("spot.obj") else {
        return;
    };
    let mesh = meshes.join("spot.obj");
    if Command::new("xvfb-run").arg("--help").output().is_err() {
        requirement_missing("xvfb-run not installed (apt-get install xvfb xauth)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("shot.png");
    let output = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1600x900x24"])
        .arg(env!("CARGO_BIN_EXE_viewer"))
        .arg(&mesh)
        .args(["--target", "400", "--quit-after", "3", "--screenshot"])
        .arg(&shot)
        .output()
        .expect("run xvfb-run");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "viewer failed: {}\n{stdout}\n{stderr}",
        output.status
    );
    assert!(stdout.contains("viewer stats:"), "no stats line: {stdout}");
    let image = image::open(&shot)
        .unwrap_or_else(|e| panic!("screenshot {}: {e}\n{stderr}", shot.display()))
        .to_rgba8();
    assert!(
        image.width() >= 800 && image.height() >= 500,
        "{}x{}",
        image.width(),
        image.height()
    );
    let drawn = viewer::io::non_background_fraction(&image);
    assert!(
        drawn > 0.2,
        "screenshot looks blank: {drawn:.3} non-background"
    );
    // Both meshes are lit: many distinct colours, not a flat fill.
    let distinct: std::collections::HashSet<[u8; 4]> = image.pixels().map(|p| p.0).collect();
    assert!(
        distinct.len() > 500,
        "only {} distinct colours",
        distinct.len()
    );
}

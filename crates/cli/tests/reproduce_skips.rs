//! `reproduce --all --max-faces` names each mesh it leaves out (issue 37: it skipped them
//! without a word).

use std::process::Command;

#[test]
fn max_faces_skips_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let meshes = dir.path().join("meshes");
    std::fs::create_dir(&meshes).unwrap();
    mesh::io::save(&mesh::procedural::icosphere(2), &meshes.join("ball.ply")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args([
            "reproduce",
            "--all",
            meshes.to_str().unwrap(),
            "--max-faces",
            "100",
        ])
        .arg("--out")
        .arg(dir.path().join("survey"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("ball.ply") && stderr.contains("320 faces, more than --max-faces 100"),
        "{stderr}"
    );
}

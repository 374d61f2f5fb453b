//! `compare` and `reproduce` measure and write positions only: a file with texture coordinates
//! or normals says so on stderr instead of losing them silently; a positions-only file does not.

use std::process::Command;

fn compare_stderr(input: &std::path::Path) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(["compare", input.to_str().unwrap(), "--vertices", "60"])
        .args(["--samples", "2000"])
        .output()
        .expect("run gng3d");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn compare_names_the_attributes_it_does_not_keep() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, attributes) = gng3d::mesh::procedural::textured_sphere(12, 16);
    let textured = dir.path().join("textured.obj");
    gng3d::mesh::io::save_with_attributes(&mesh, &attributes, None, &textured).unwrap();
    let stderr = compare_stderr(&textured);
    let line = stderr
        .lines()
        .find(|l| l.contains("not used"))
        .unwrap_or_else(|| panic!("no warning about the attributes: {stderr}"));
    assert!(
        line.starts_with("warning: ") && line.contains("textured.obj"),
        "{line}"
    );
    assert!(
        line.contains("texture coordinates") && line.contains("normals"),
        "{line}"
    );

    let plain = dir.path().join("plain.obj");
    gng3d::mesh::io::save(&mesh, &plain).unwrap();
    let stderr = compare_stderr(&plain);
    assert!(!stderr.contains("not used"), "{stderr}");
}

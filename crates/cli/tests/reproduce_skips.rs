//! `reproduce --all --max-faces` names each mesh it leaves out (issue 37: it skipped them
//! without a word).

use std::process::Command;
mod common;
use common::csv_cells;

#[test]
fn max_faces_skips_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let meshes = dir.path().join("meshes");
    std::fs::create_dir(&meshes).unwrap();
    mesh::io::save(
        &mesh::procedural::icosphere(2).into(),
        &meshes.join("ball.ply"),
    )
    .unwrap();
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

/// `reproduce --all` writes and prints the three methods (issue 37 item 6): summary.csv has
/// GNG3D-Q's columns and a verdict per metric that agrees with the values beside it,
/// summary.md the verdict table of both GNG3D variants and the skipped mesh with its reason,
/// the terminal the same verdict table, and the charts are written.
#[test]
fn survey_reports_gng3d_q_and_the_verdict() {
    let dir = tempfile::tempdir().unwrap();
    let meshes = dir.path().join("meshes");
    std::fs::create_dir(&meshes).unwrap();
    mesh::io::save(
        &mesh::procedural::icosphere(2).into(),
        &meshes.join("ball.obj"),
    )
    .unwrap();
    mesh::io::save(
        &mesh::procedural::icosphere(4).into(),
        &meshes.join("big.obj"),
    )
    .unwrap();
    let out = dir.path().join("survey");
    let o = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(["reproduce", "--all", meshes.to_str().unwrap()])
        .args(["--max-faces", "1000", "--epochs", "2", "--samples", "2000"])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    for needle in [
        "GNG3D (paper) wins",
        "GNG3D-Q wins",
        "GNG3D-Q / QEM",
        "mean distance",
    ] {
        assert!(stdout.contains(needle), "{needle:?} missing in {stdout}");
    }

    let text = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let mut lines = text.lines().map(csv_cells);
    let headers = lines.next().unwrap();
    let col = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name:?} in {headers:?}"))
    };
    let rows: Vec<Vec<String>> = lines.collect();
    assert_eq!(rows.len(), 3, "ball.obj at 10, 25 and 50 %");
    let m = "mean surface distance (area-weighted, units)";
    for r in &rows {
        assert_eq!(&r[col("mesh")], "ball.obj");
        assert_eq!(r[col("vertices GNG3D-Q")], r[col("vertices QEM")]);
        // The verdict column says which of the two values beside it is lower.
        let q: f64 = r[col(&format!("{m} GNG3D-Q"))].parse().unwrap();
        let e: f64 = r[col(&format!("{m} QEM"))].parse().unwrap();
        let verdict = r[col(&format!("{m} better: GNG3D-Q or QEM"))].as_str();
        let expected = if q < e {
            "GNG3D-Q"
        } else if e < q {
            "QEM"
        } else {
            "tie"
        };
        assert_eq!(verdict, expected, "{q} vs {e}");
        let paper = r[col(&format!("{m} better: GNG3D (paper) or QEM"))].as_str();
        assert!(["GNG3D (paper)", "QEM", "tie"].contains(&paper), "{paper}");
    }

    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    for needle in [
        "GNG3D (paper) wins",
        "GNG3D-Q wins",
        "| mean surface distance (area-weighted, units) ",
        "of 3",
        "- big.obj: skipped: 5120 faces, more than --max-faces 1000",
    ] {
        assert!(md.contains(needle), "{needle:?} missing in {md}");
    }
    for chart in ["survey_mean_distance", "survey_hausdorff"] {
        for ext in ["svg", "png"] {
            assert!(
                out.join(format!("{chart}.{ext}")).is_file(),
                "{chart}.{ext}"
            );
        }
    }
}

/// Issue 46: a mesh that cleaning reduces to nothing (every face degenerate once duplicate
/// vertices are welded), or whose faces all have zero area, blamed "parameter signal budget =
/// 0" (or failed after training, at the sampler): the error names the file and says it has no
/// usable faces after cleaning, in one mesh and in a survey.
#[test]
fn no_usable_faces_after_cleaning_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let meshes = dir.path().join("meshes");
    std::fs::create_dir(&meshes).unwrap();
    let welded = meshes.join("welded.obj");
    std::fs::write(
        &welded,
        "v 0 0 0\nv 0 0 0\nv 1 0 0\nv 1 0 0\nf 1 2 3\nf 2 3 4\n",
    )
    .unwrap();
    let flat = meshes.join("flat.obj");
    std::fs::write(
        &flat,
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n",
    )
    .unwrap();
    for (path, why) in [
        (&welded, "the mesh has no usable faces after cleaning"),
        (&flat, "the mesh has no usable faces after cleaning"),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_gng3d"))
            .arg("reproduce")
            .arg(path)
            .args(["--epochs", "1", "--samples", "100", "--out"])
            .arg(dir.path().join("r"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains(&format!("{}: {why}", path.display())),
            "{stderr}"
        );
        assert!(!stderr.contains("signal budget"), "{stderr}");
    }
    let o = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(["reproduce", "--all", meshes.to_str().unwrap()])
        .args(["--epochs", "1", "--samples", "100", "--out"])
        .arg(dir.path().join("survey"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    for path in [&welded, &flat] {
        assert!(
            stderr.contains(&format!(
                "{}: the mesh has no usable faces after cleaning",
                path.display()
            )),
            "{stderr}"
        );
    }
    assert!(!stderr.contains("signal budget"), "{stderr}");
}

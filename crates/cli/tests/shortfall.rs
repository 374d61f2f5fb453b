//! A run that cannot reach its target says so in every front end of the binary: `simplify`,
//! each `--lods` level, a `batch` row, `compare` (which compares at the count QEM reached) and
//! `reproduce --all` (whose verdict leaves out runs at unequal counts). The input is ten
//! separate icospheres: QEM cannot take a closed component below a tetrahedron, so 120 vertices
//! never go below 40.

mod common;
use common::{gng3d, json_of, s, stderr, succeeded};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// Ten icospheres of 12 vertices in a row, apart: 120 vertices, at least 40 after QEM.
fn spheres(dir: &Path) -> PathBuf {
    let one = gng3d::mesh::procedural::icosphere(0);
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for k in 0..10 {
        let base = positions.len() as u32;
        positions.extend(
            one.positions
                .iter()
                .map(|p| *p + Vec3::X * (3.0 * k as f32)),
        );
        triangles.extend(one.triangles.iter().map(|t| t.map(|v| v + base)));
    }
    let path = dir.join("spheres.ply");
    let model = gng3d::mesh::TriMesh::new(positions, triangles);
    gng3d::mesh::io::save(&model.into(), &path).unwrap();
    path
}

#[test]
fn simplify_and_each_lod_level_say_they_stopped_short() {
    let dir = tempfile::tempdir().unwrap();
    let input = spheres(dir.path());
    assert_eq!(
        gng3d::mesh::io::load(&input).unwrap().mesh.vertex_count(),
        120
    );
    let out = dir.path().join("out.ply");
    let o = succeeded(gng3d(&["simplify", s(&input), s(&out), "--vertices", "20"]));
    assert!(
        stderr(&o).contains("stopped at 40 of 20 vertices"),
        "{}",
        stderr(&o)
    );
    let v = json_of(&gng3d(&[
        "simplify",
        s(&input),
        s(&out),
        "--vertices",
        "20",
        "--json",
    ]));
    assert_eq!(v["vertices"], 40);
    assert_eq!(v["warnings"][0]["kind"], "target_not_reached", "{v}");

    let o = succeeded(gng3d(&[
        "simplify",
        s(&input),
        s(&out),
        "--lods",
        "0.5,0.2",
    ]));
    let err = stderr(&o);
    // Level 1 (60 vertices) is reachable; level 2 (24) is not.
    assert!(!err.contains("level 1"), "{err}");
    assert!(
        err.contains("level 2") && err.contains("of 24 vertices"),
        "{err}"
    );
}

#[test]
fn a_batch_row_carries_the_shortfall() {
    let dir = tempfile::tempdir().unwrap();
    let inputs = dir.path().join("in");
    std::fs::create_dir(&inputs).unwrap();
    spheres(&inputs);
    let out = dir.path().join("out");
    let o = succeeded(gng3d(&[
        "batch",
        s(&inputs),
        "--out",
        s(&out),
        "--vertices",
        "20",
    ]));
    let row: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().next().unwrap()).unwrap();
    assert_eq!(row["vertices"], 40, "{row}");
    assert!(
        row["warnings"]
            .as_str()
            .unwrap()
            .contains("stopped at 40 of 20"),
        "{row}"
    );
}

#[test]
fn compare_measures_both_at_the_count_qem_reached() {
    let dir = tempfile::tempdir().unwrap();
    let input = spheres(dir.path());
    let o = gng3d(&[
        "compare",
        s(&input),
        "--vertices",
        "20",
        "--samples",
        "2000",
        "--json",
    ]);
    let v = json_of(&o);
    assert_eq!(v["target_vertices"], 20);
    assert_eq!(v["qem"]["vertices"], 40, "{v}");
    assert_eq!(v["gng"]["vertices"], 40, "{v}");
    let warnings = v["warnings"].to_string();
    assert!(warnings.contains("stopped at 40 of 20"), "{warnings}");
    assert!(
        warnings.contains("GNG3D runs to QEM's 40 vertices"),
        "{warnings}"
    );
    assert!(stderr(&o).contains("warning: "), "{}", stderr(&o));
}

#[test]
fn the_survey_verdict_leaves_out_runs_at_unequal_counts() {
    let dir = tempfile::tempdir().unwrap();
    let inputs = dir.path().join("in");
    std::fs::create_dir(&inputs).unwrap();
    spheres(&inputs);
    let out = dir.path().join("survey");
    let o = succeeded(gng3d(&[
        "reproduce",
        "--all",
        s(&inputs),
        "--out",
        s(&out),
        "--epochs",
        "2",
        "--samples",
        "2000",
    ]));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let rows: Vec<serde_json::Value> = serde_json::from_str(&summary).unwrap();
    // QEM runs to each variant's count and stops at 40 where that is lower (at 10 % and 25 %
    // the paper's GNG3D has 12 and 30 vertices).
    let unequal = |ours: &str, qem: &str| {
        rows.iter()
            .filter(|r| r[ours]["vertices"] != r[qem]["vertices"])
            .count()
    };
    let text = String::from_utf8_lossy(&o.stdout);
    for (name, k) in [
        ("GNG3D (paper)", unequal("gng", "qem")),
        ("GNG3D-Q", unequal("gngq", "qem_at_gngq")),
    ] {
        let line = text
            .lines()
            .find(|l| l.starts_with(&format!("{name}: output closed")))
            .unwrap_or_else(|| panic!("no totals line for {name}: {text}"));
        let said =
            format!("QEM stopped at another vertex count in {k} of 3 (left out of the verdict)");
        assert_eq!(line.contains(&said), k > 0, "{line}");
    }
    assert_eq!(unequal("gng", "qem"), 2, "{summary}");
    // The paper's verdicts count its one run at equal counts.
    assert!(text.contains(" of 1"), "{text}");
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(md.contains("left out of the verdict"), "{md}");
}

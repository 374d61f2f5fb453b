//! `gng3d batch`: the rows, the stats table, resuming, sharding and option errors, on
//! procedural meshes written to a temporary folder (no shared meshes needed).

use std::path::Path;
use std::process::{Command, Output};

fn gng3d(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(args)
        .output()
        .expect("run gng3d")
}

fn rows(o: &Output) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect()
}

fn row<'a>(rows: &'a [serde_json::Value], name: &str) -> &'a serde_json::Value {
    rows.iter()
        .find(|r| r["input"].as_str().unwrap().ends_with(name))
        .unwrap_or_else(|| panic!("no row for {name}"))
}

/// A folder with two good meshes and a broken one.
fn inputs(dir: &Path) {
    gng3d::mesh::io::save(
        &gng3d::mesh::procedural::icosphere(3),
        &dir.join("sphere.ply"),
    )
    .unwrap();
    gng3d::mesh::io::save(
        &gng3d::mesh::procedural::torus(1.0, 0.3, 24, 12),
        &dir.join("torus.obj"),
    )
    .unwrap();
    std::fs::write(
        dir.join("broken.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\n",
    )
    .unwrap();
}

#[test]
fn batch_rows_match_simplify_and_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let (input, out) = (tmp.path().join("in"), tmp.path().join("out"));
    std::fs::create_dir(&input).unwrap();
    inputs(&input);
    let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());

    let first = gng3d(&["batch", i, "--out", o, "--ratio", "0.2", "--jobs", "2"]);
    // A broken file is a row, not a stop; the run says so in its exit status and summary.
    assert_eq!(first.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&first.stderr);
    assert!(
        stderr.contains("3 files: 2 ok, 0 skipped, 1 errors"),
        "{stderr}"
    );
    let got = rows(&first);
    assert_eq!(got.len(), 3);
    let broken = row(&got, "broken.ply");
    assert_eq!(broken["status"], "error");
    assert!(
        broken["error"].as_str().unwrap().contains("broken.ply"),
        "{broken}"
    );
    assert!(!out.join("broken.ply").exists());

    // Each ok row is what `gng3d simplify` gives for the same options, byte for byte.
    for name in ["sphere.ply", "torus.obj"] {
        let r = row(&got, name);
        assert_eq!(r["status"], "ok", "{r}");
        let direct = tmp.path().join(format!("direct-{name}"));
        let s = gng3d(&[
            "simplify",
            input.join(name).to_str().unwrap(),
            direct.to_str().unwrap(),
            "--ratio",
            "0.2",
            "--json",
        ]);
        assert!(s.status.success());
        let summary: serde_json::Value = serde_json::from_slice(&s.stdout).unwrap();
        assert_eq!(r["vertices"], summary["vertices"]);
        assert_eq!(r["faces"], summary["faces"]);
        assert!(r["input_faces"].as_u64().unwrap() > r["faces"].as_u64().unwrap());
        assert_eq!(
            std::fs::read(out.join(name)).unwrap(),
            std::fs::read(&direct).unwrap(),
            "{name}"
        );
    }
    let stats = std::fs::read_to_string(out.join("stats.csv")).unwrap();
    assert_eq!(stats.lines().count(), 4, "{stats}");
    assert!(stats.starts_with("input,output,status,error,warnings,method,input_vertices"));

    // Resume: the finished files are skipped with their first run's counts; only the broken
    // file runs (and is recorded) again.
    let again = gng3d(&["batch", i, "--out", o, "--ratio", "0.2", "--skip-existing"]);
    let got2 = rows(&again);
    for name in ["sphere.ply", "torus.obj"] {
        let (r1, r2) = (row(&got, name), row(&got2, name));
        assert_eq!(r2["status"], "skipped");
        assert_eq!(r2["vertices"], r1["vertices"]);
    }
    assert_eq!(row(&got2, "broken.ply")["status"], "error");
    let stats = std::fs::read_to_string(out.join("stats.csv")).unwrap();
    assert_eq!(stats.lines().count(), 5, "{stats}");
}

#[test]
fn shards_split_a_manifest_and_bad_options_stop_before_any_file() {
    let tmp = tempfile::tempdir().unwrap();
    inputs(tmp.path());
    let manifest = tmp.path().join("list.txt");
    std::fs::write(&manifest, "# two meshes\nsphere.ply\n\ntorus.obj\n").unwrap();
    let out = tmp.path().join("out");
    let (m, o) = (manifest.to_str().unwrap(), out.to_str().unwrap());

    let mut seen = Vec::new();
    for rank in ["0", "1"] {
        let run = gng3d(&[
            "batch",
            m,
            "--out",
            o,
            "--vertices",
            "60",
            "--method",
            "gng",
            "--rank",
            rank,
            "--world-size",
            "2",
        ]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let got = rows(&run);
        assert_eq!(got.len(), 1);
        assert_eq!(got[0]["vertices"], 60);
        // GNG3D rows carry the input's counts too (from simplify's --json).
        assert!(
            got[0]["input_vertices"].as_u64().unwrap() > 60,
            "{}",
            got[0]
        );
        seen.push(got[0]["input"].as_str().unwrap().to_string());
        assert!(out.join(format!("stats-{rank}-of-2.csv")).exists());
    }
    seen.sort();
    assert!(
        seen[0].ends_with("sphere.ply") && seen[1].ends_with("torus.obj"),
        "{seen:?}"
    );

    // Option errors name the option, before any file is read or written.
    let fresh = tmp.path().join("fresh");
    let f = fresh.to_str().unwrap();
    for (args, says) in [
        (vec!["--ratio", "1.5"], "--ratio"),
        (vec!["--ratio", "0.5", "--", "--bogus"], "--bogus"),
        (
            vec!["--ratio", "0.5", "--rank", "2", "--world-size", "2"],
            "--rank",
        ),
        (
            vec![
                "--method",
                "gng",
                "--ratio",
                "0.5",
                "--",
                "--oversample",
                "9",
            ],
            "oversample",
        ),
    ] {
        let mut a = vec!["batch", m, "--out", f];
        a.extend(args);
        let run = gng3d(&a);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(says), "{says}: {stderr}");
        assert!(stdout_is_empty(&run), "{a:?}");
        let written: Vec<_> = std::fs::read_dir(&fresh)
            .map(|d| d.filter_map(|e| e.ok()).map(|e| e.file_name()).collect())
            .unwrap_or_default();
        assert!(written.is_empty(), "{a:?}: {written:?}");
    }
}

fn stdout_is_empty(o: &Output) -> bool {
    o.stdout.is_empty()
}

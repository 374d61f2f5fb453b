//! `gng3d batch`: the rows, the stats table, resuming, sharding and option errors, on
//! procedural meshes written to a temporary folder (no shared meshes needed).

mod common;
use common::{gng3d, succeeded};
use std::path::Path;
use std::process::{Command, Output};

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
    good_inputs(dir);
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
        let run = succeeded(gng3d(&[
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
        ]));
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

/// A folder with two good meshes (every row ok).
fn good_inputs(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    gng3d::mesh::io::save(
        &gng3d::mesh::procedural::icosphere(3).into(),
        &dir.join("sphere.ply"),
    )
    .unwrap();
    gng3d::mesh::io::save(
        &gng3d::mesh::procedural::torus(1.0, 0.3, 24, 12).into(),
        &dir.join("torus.obj"),
    )
    .unwrap();
}

/// The bytes of every file in `dir`, by name.
fn snapshot(dir: &Path) -> Vec<(std::ffi::OsString, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| (e.file_name(), std::fs::read(e.path()).unwrap()))
        .collect();
    files.sort();
    files
}

/// `--out` the source folder (however spelt), or an output folder where a result would land on
/// a manifest's input, is refused before anything is written, naming both paths; a folder
/// inside the source folder is fine.
#[test]
fn an_output_over_an_input_is_refused_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    good_inputs(&input);
    let before = snapshot(&input);
    let i = input.to_str().unwrap();
    // The same folder spelt another way (canonical paths are compared).
    let same = tmp.path().join("in").join("..").join("in");
    let s = same.to_str().unwrap();
    for extra in [&[][..], &["--skip-existing"][..], &["--format", "ply"][..]] {
        let mut a = vec!["batch", i, "--out", s, "--ratio", "0.2"];
        a.extend(extra);
        let run = gng3d(&a);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{extra:?}: {stderr}");
        assert!(
            stderr.contains("the output folder is the source folder")
                && stderr.contains(i)
                && stderr.contains(s),
            "{extra:?}: {stderr}"
        );
        assert!(stdout_is_empty(&run), "{extra:?}");
        assert_eq!(snapshot(&input), before, "{extra:?}: the inputs changed");
    }

    // A manifest's inputs can be anywhere: a result that would replace one is refused.
    let manifest = tmp.path().join("list.txt");
    std::fs::write(&manifest, "in/sphere.ply\nin/torus.obj\n").unwrap();
    let m = manifest.to_str().unwrap();
    let run = gng3d(&["batch", m, "--out", i, "--ratio", "0.2"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("would be written over the input")
            && stderr.contains(&format!("{i}/sphere.ply"))
            && stderr.contains("in/sphere.ply"),
        "{stderr}"
    );
    assert!(stdout_is_empty(&run));
    assert_eq!(snapshot(&input), before, "the inputs changed");
    // ... but into the same folder in another format, no input is replaced.
    succeeded(gng3d(&[
        "batch", m, "--out", i, "--ratio", "0.2", "--format", "stl",
    ]));
    assert!(input.join("sphere.stl").exists() && input.join("torus.stl").exists());
    for (name, bytes) in &before {
        assert_eq!(&std::fs::read(input.join(name)).unwrap(), bytes, "{name:?}");
    }

    // An output folder inside the source folder replaces nothing.
    let src = tmp.path().join("src");
    good_inputs(&src);
    let before = snapshot(&src);
    let inner = src.join("out");
    let run = succeeded(gng3d(&[
        "batch",
        src.to_str().unwrap(),
        "--out",
        inner.to_str().unwrap(),
        "--ratio",
        "0.2",
    ]));
    assert_eq!(rows(&run).len(), 2);
    assert_eq!(snapshot(&src), before);
}

/// Two files whose results would share a file, a `.gltf`'s buffer `<stem>.bin` included, or
/// whose output names differ only in case, are refused up front: never two ok rows with one
/// result overwritten.
#[test]
fn side_files_and_names_differing_in_case_collide() {
    let tmp = tempfile::tempdir().unwrap();
    let sphere = gng3d::mesh::procedural::icosphere(2);
    for (folder, names, says) in [
        // m.gltf and m.GLTF both write out/m.bin.
        ("gltf", ["m.gltf", "m.GLTF"], "m.bin (the buffer file of"),
        // One file on a case-insensitive file system.
        ("obj", ["a.obj", "A.OBJ"], "differ only in case"),
    ] {
        let input = tmp.path().join(folder);
        std::fs::create_dir(&input).unwrap();
        for name in names {
            gng3d::mesh::io::save(&sphere.clone().into(), &input.join(name)).unwrap();
        }
        let out = tmp.path().join(format!("out-{folder}"));
        let run = gng3d(&[
            "batch",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--ratio",
            "0.5",
        ]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{folder}: {stderr}");
        assert!(
            stderr.contains("would both be written to") && stderr.contains(says),
            "{folder}: {stderr}"
        );
        for name in names {
            assert!(stderr.contains(name), "{folder}: {stderr}");
        }
        assert!(stdout_is_empty(&run), "{folder}");
        let written: Vec<_> = std::fs::read_dir(&out)
            .map(|d| d.filter_map(|e| e.ok()).map(|e| e.file_name()).collect())
            .unwrap_or_default();
        assert!(written.is_empty(), "{folder}: {written:?}");
    }

    // Two inputs converted to one name collide though the shards split them (every shard
    // writes into the one folder).
    let input = tmp.path().join("mixed");
    std::fs::create_dir(&input).unwrap();
    gng3d::mesh::io::save(&sphere.clone().into(), &input.join("m.ply")).unwrap();
    gng3d::mesh::io::save(&sphere.clone().into(), &input.join("m.stl")).unwrap();
    let out = tmp.path().join("out-mixed");
    let run = gng3d(&[
        "batch",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--ratio",
        "0.5",
        "--format",
        "gltf",
        "--rank",
        "1",
        "--world-size",
        "2",
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("would both be written to"), "{stderr}");
}

/// A run killed after writing an output but before recording its row: the resume gives that
/// output a skipped row with its counts (read from the files), so the table has one row per
/// input, and a second resume adds none.
#[test]
fn resume_records_outputs_without_a_row() {
    let tmp = tempfile::tempdir().unwrap();
    let (input, out) = (tmp.path().join("in"), tmp.path().join("out"));
    good_inputs(&input);
    let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());
    let first = gng3d(&["batch", i, "--out", o, "--ratio", "0.2"]);
    assert!(first.status.success());
    let got = rows(&first);
    let stats_path = out.join("stats.csv");
    let stats = std::fs::read_to_string(&stats_path).unwrap();
    // Keep the header and sphere's row: torus.obj was written but not recorded.
    let kept: String = stats
        .split_inclusive('\n')
        .filter(|l| !l.contains("torus.obj"))
        .collect();
    assert_eq!(kept.lines().count(), 2, "{stats}");
    std::fs::write(&stats_path, &kept).unwrap();

    for _ in 0..2 {
        let again = gng3d(&["batch", i, "--out", o, "--ratio", "0.2", "--skip-existing"]);
        assert!(again.status.success());
        let got2 = rows(&again);
        for name in ["sphere.ply", "torus.obj"] {
            let (r1, r2) = (row(&got, name), row(&got2, name));
            assert_eq!(r2["status"], "skipped", "{r2}");
            assert_eq!(r2["error"], serde_json::Value::Null, "{r2}");
            for key in ["vertices", "faces", "input_vertices", "input_faces"] {
                assert_eq!(r2[key], r1[key], "{name} {key}: {r2} vs {r1}");
            }
        }
        let stats = std::fs::read_to_string(&stats_path).unwrap();
        assert_eq!(stats.lines().count(), 3, "{stats}");
        assert!(stats.starts_with(&kept), "{stats}");
        let torus: Vec<_> = stats.lines().filter(|l| l.contains("torus.obj")).collect();
        assert_eq!(torus.len(), 1, "{stats}");
        assert!(torus[0].contains(",skipped,"), "{stats}");
    }

    // No table at all: every existing output gets its row.
    std::fs::remove_file(&stats_path).unwrap();
    let again = gng3d(&["batch", i, "--out", o, "--ratio", "0.2", "--skip-existing"]);
    assert!(again.status.success());
    let stats = std::fs::read_to_string(&stats_path).unwrap();
    assert_eq!(stats.lines().count(), 3, "{stats}");
    assert_eq!(
        stats.lines().filter(|l| l.starts_with("input,")).count(),
        1,
        "{stats}"
    );
}

/// Two batches into one folder share its stats table: each waits for the other's lock on it
/// (held here first, as another batch would), so the header is written once and every row is
/// whole.
#[test]
fn concurrent_batches_write_one_header() {
    let tmp = tempfile::tempdir().unwrap();
    let (input, out) = (tmp.path().join("in"), tmp.path().join("out"));
    good_inputs(&input);
    std::fs::create_dir(&out).unwrap();
    let stats_path = out.join("stats.csv");
    let holder = std::fs::File::create(&stats_path).unwrap();
    holder.lock().unwrap();
    let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());
    let mut batches: Vec<_> = (0..2)
        .map(|_| {
            Command::new(env!("CARGO_BIN_EXE_gng3d"))
                .args(["batch", i, "--out", o, "--ratio", "0.2", "--jobs", "1"])
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    // While the table is locked, neither batch writes it (nor finishes).
    std::thread::sleep(std::time::Duration::from_secs(3));
    for b in &mut batches {
        assert!(b.try_wait().unwrap().is_none(), "a batch ignored the lock");
    }
    assert_eq!(std::fs::read_to_string(&stats_path).unwrap(), "");
    holder.unlock().unwrap();
    for b in batches {
        let run = b.wait_with_output().unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        assert_eq!(rows(&run).len(), 2);
    }
    let stats = std::fs::read_to_string(&stats_path).unwrap();
    let lines: Vec<_> = stats.lines().collect();
    assert_eq!(lines.len(), 5, "{stats}");
    assert!(lines[0].starts_with("input,output,status"), "{stats}");
    assert_eq!(
        lines.iter().filter(|l| l.starts_with("input,")).count(),
        1,
        "{stats}"
    );
    assert!(lines[1..].iter().all(|l| l.contains(",ok,")), "{stats}");
}

/// The live processes running `gng3d simplify` with an argument containing `needle`: pid,
/// parent pid.
#[cfg(target_os = "linux")]
fn simplify_runs(needle: &str) -> Vec<(u32, u32)> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().filter_map(|e| e.ok()) {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let (Ok(cmdline), Ok(stat)) = (
            std::fs::read(entry.path().join("cmdline")),
            std::fs::read_to_string(entry.path().join("stat")),
        ) else {
            continue;
        };
        let args: Vec<_> = cmdline
            .split(|&b| b == 0)
            .map(String::from_utf8_lossy)
            .collect();
        // After the command name in parentheses: state, parent pid.
        let fields: Vec<_> = stat
            .rsplit_once(')')
            .map_or("", |(_, rest)| rest)
            .split_whitespace()
            .collect();
        let live = fields.first().is_some_and(|&s| s != "Z" && s != "X");
        if live
            && args.get(1).is_some_and(|a| a == "simplify")
            && args.iter().any(|a| a.contains(needle))
        {
            found.push((pid, fields[1].parse().unwrap_or(0)));
        }
    }
    found
}

/// The meshes of the kill test: big enough that a GNG run to this many vertices takes seconds.
#[cfg(target_os = "linux")]
const KILL_SUBDIVISIONS: u32 = 6;
#[cfg(target_os = "linux")]
const KILL_VERTICES: &str = "4000";

/// `kill -9` of a batch ends its `gng3d simplify` runs too (they do not go on writing).
#[cfg(target_os = "linux")]
#[test]
fn killing_a_batch_ends_its_simplify_runs() {
    use std::time::{Duration, Instant};
    let tmp = tempfile::tempdir().unwrap();
    let (input, out) = (tmp.path().join("in"), tmp.path().join("out-killed"));
    std::fs::create_dir(&input).unwrap();
    let big = gng3d::mesh::procedural::icosphere(KILL_SUBDIVISIONS);
    for k in 0..4 {
        gng3d::mesh::io::save(&big.clone().into(), &input.join(format!("m{k}.ply"))).unwrap();
    }
    let mut batch = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args([
            "batch",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args([
            "--method",
            "gng",
            "--vertices",
            KILL_VERTICES,
            "--jobs",
            "2",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let needle = input.join("m").to_str().unwrap().to_string();
    let start = Instant::now();
    let children = loop {
        let runs: Vec<_> = simplify_runs(&needle)
            .into_iter()
            .filter(|&(_, parent)| parent == batch.id())
            .collect();
        if !runs.is_empty() {
            break runs;
        }
        assert!(
            batch.try_wait().unwrap().is_none(),
            "the batch ended before a run was seen"
        );
        assert!(start.elapsed() < Duration::from_secs(120), "no run started");
        std::thread::sleep(Duration::from_millis(10));
    };
    // Let the run get going, then kill the batch without a chance to clean up.
    std::thread::sleep(Duration::from_millis(300));
    batch.kill().unwrap();
    batch.wait().unwrap();
    let killed = Instant::now();
    let out_name = out.to_str().unwrap();
    loop {
        let left = simplify_runs(out_name);
        if left.is_empty() {
            break;
        }
        assert!(
            killed.elapsed() < Duration::from_secs(2),
            "simplify runs {left:?} outlived their batch (first seen {children:?})"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

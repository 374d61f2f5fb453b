//! Fuzzing the whole CLI path: mutated OBJ/PLY/STL files (the seeds and mutations of
//! `mesh::fixtures::fuzz`) go through `gng3d info`, `gng3d simplify --method qem` and
//! `gng3d simplify --method gng`, in process through `gng3d_cli::run_args` (the same code the
//! binary runs after argument parsing). The property: no run panics or hangs; every run that
//! succeeds wrote a mesh that the project's own loader reads back with at least one triangle;
//! every run that fails returned an error with a message and wrote nothing.
//!
//! `cli_fuzz_quick` runs a few hundred CLI runs in CI. The long variant is ignored:
//! `GNG3D_FUZZ_RUNS=300000 cargo test -p gng3d-cli --release --test fuzz -- --ignored --nocapture`
//! (it prints its counts; see docs/notes/cli.md for the measured run).

mod hostile;

use mesh::fixtures::fuzz::{apply, random_mutation, seeds};
use mesh::io::Format;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Counts of one fuzz session.
#[derive(Debug, Default)]
struct Counts {
    /// CLI invocations.
    runs: u64,
    /// Mutants that the loader accepted.
    loaded: u64,
    /// Simplify runs that exited 0 (all checked by reloading the output).
    simplified_ok: u64,
    /// Runs that returned an error.
    errors: u64,
}

/// splitmix64 step: the driver's deterministic random source.
fn next(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn ext(format: Format) -> &'static str {
    match format {
        Format::Obj => "obj",
        Format::Ply => "ply",
        Format::Stl => "stl",
        Format::Gltf => "gltf",
        Format::Glb => "glb",
    }
}

/// Milliseconds since `START` when the current run began (0: idle), for the hang watchdog.
static RUN_STARTED_MS: AtomicU64 = AtomicU64::new(0);

/// Aborts the process (failing the test loudly) if one CLI run takes longer than `limit`.
fn watchdog(start: Instant, limit: Duration) {
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_millis(500));
            let began = RUN_STARTED_MS.load(Ordering::Relaxed);
            if began > 0 {
                let now = start.elapsed().as_millis() as u64;
                if now.saturating_sub(began) > limit.as_millis() as u64 {
                    eprintln!("HANG: one CLI run took over {limit:?}");
                    std::process::abort();
                }
            }
        }
    });
}

/// One CLI run in process; panics become test failures naming the input.
fn cli(args: &[&str], start: Instant, input: &[u8]) -> anyhow::Result<()> {
    RUN_STARTED_MS.store(start.elapsed().as_millis().max(1) as u64, Ordering::Relaxed);
    let mut full = vec!["gng3d"];
    full.extend_from_slice(args);
    let result = catch_unwind(AssertUnwindSafe(|| gng3d_cli::run_args(&full)));
    RUN_STARTED_MS.store(0, Ordering::Relaxed);
    match result {
        Ok(r) => r,
        Err(_) => panic!(
            "PANIC in {args:?} on input {:?}",
            String::from_utf8_lossy(&input[..input.len().min(2000)])
        ),
    }
}

/// Runs `mutants` mutants through info + both simplifiers and checks the property.
fn fuzz(mutants: u64, seed: u64, report_every: u64) -> Counts {
    let seeds = seeds();
    let dir = tempfile::tempdir().unwrap();
    let start = Instant::now();
    watchdog(start, Duration::from_secs(60));
    let mut state = seed;
    let mut counts = Counts::default();
    for k in 0..mutants {
        let (format, mut bytes) = seeds[(next(&mut state) % seeds.len() as u64) as usize].clone();
        let edits = 1 + next(&mut state) % 3;
        for _ in 0..edits {
            apply(&mut bytes, &random_mutation(next(&mut state)));
        }
        let input = dir.path().join(format!("m.{}", ext(format)));
        std::fs::write(&input, &bytes).unwrap();
        let input_s = input.to_str().unwrap();
        counts.runs += 1;
        let info = cli(&["info", input_s, "--json"], start, &bytes);
        let loads = mesh::io::load(&input).is_ok();
        assert_eq!(
            info.is_ok(),
            loads,
            "info and the loader disagree on {input:?}"
        );
        counts.loaded += u64::from(loads);
        if let Err(e) = &info {
            counts.errors += 1;
            if std::env::var_os("GNG3D_FUZZ_DEBUG").is_some() {
                eprintln!("DEBUG info error: {e:#}");
            }
        }
        for (method, out_ext) in [("qem", "ply"), ("gng", "obj")] {
            let out = dir.path().join(format!("out-{method}.{out_ext}"));
            let _ = std::fs::remove_file(&out);
            counts.runs += 1;
            let target = if next(&mut state).is_multiple_of(2) {
                "--ratio=0.5"
            } else {
                "--vertices=6"
            };
            let result = cli(
                &[
                    "simplify",
                    input_s,
                    out.to_str().unwrap(),
                    "--method",
                    method,
                    target,
                ],
                start,
                &bytes,
            );
            match result {
                Ok(()) => {
                    assert!(loads, "{method} succeeded on an input the loader refuses");
                    let back = mesh::io::load(&out).unwrap_or_else(|e| {
                        panic!("{method} exit 0 but its output does not load: {e}")
                    });
                    assert!(back.mesh.face_count() > 0, "{method}: empty output");
                    counts.simplified_ok += 1;
                }
                Err(e) => {
                    assert!(!format!("{e:#}").is_empty());
                    assert!(!out.exists(), "{method} failed but wrote {out:?}");
                    counts.errors += 1;
                }
            }
        }
        if report_every > 0 && (k + 1) % report_every == 0 {
            eprintln!(
                "fuzz: {} mutants, {:?} in {:.0} s",
                k + 1,
                counts,
                start.elapsed().as_secs_f64()
            );
        }
    }
    counts
}

#[test]
fn cli_fuzz_quick() {
    let counts = fuzz(150, 0xC11, 0);
    assert_eq!(counts.runs, 450);
    // The mutants are mostly still loadable, and both simplifiers produce real meshes on them.
    assert!(counts.loaded > 8, "{counts:?}");
    assert!(counts.simplified_ok > 10, "{counts:?}");
}

#[test]
#[ignore = "long: GNG3D_FUZZ_RUNS CLI runs (default 300,000)"]
fn cli_fuzz_long() {
    let runs: u64 = std::env::var("GNG3D_FUZZ_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300_000);
    let seed: u64 = std::env::var("GNG3D_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let start = Instant::now();
    let counts = fuzz(runs.div_ceil(3), seed, 2_000);
    eprintln!(
        "fuzz done: {counts:?}, 0 panics, 0 hangs, 0 exit-0 runs with an unloadable output, in {:.0} s",
        start.elapsed().as_secs_f64()
    );
}

/// The hostile corpus: models whose references point outside their folder, at devices, FIFOs
/// and links, with hostile media types and names (`hostile::models`), each run as it is and
/// then mutated, through `info` and `simplify` to PLY, OBJ and GLB. Besides the property of
/// [`fuzz`] (no panic, no hang, no exit 0 with an unloadable output), the canary: after every
/// run no file outside the working folder changed or appeared and no file in it holds a
/// canary's bytes.
fn fuzz_hostile(mutants: u64, seed: u64) -> Counts {
    let arena = hostile::Arena::new();
    let corpus = hostile::models(&arena);
    hostile::write_models(&arena);
    let start = Instant::now();
    watchdog(start, Duration::from_secs(60));
    let mut state = seed;
    let mut counts = Counts::default();
    for k in 0..corpus.len() as u64 + mutants {
        let (name, mut bytes) = corpus[(k % corpus.len() as u64) as usize].clone();
        if k >= corpus.len() as u64 {
            for _ in 0..1 + next(&mut state) % 3 {
                apply(&mut bytes, &random_mutation(next(&mut state)));
            }
        }
        let input = arena.work.join(format!("fuzz-{name}"));
        std::fs::write(&input, &bytes).unwrap();
        let input_s = input.to_str().unwrap();
        counts.runs += 1;
        let loads = cli(&["info", input_s, "--json"], start, &bytes).is_ok();
        counts.loaded += u64::from(loads);
        for ext in ["ply", "obj", "glb"] {
            let out_dir = arena.work.join(format!("fuzz-out-{ext}"));
            std::fs::create_dir_all(out_dir.join("x_image1.x")).unwrap();
            let out = out_dir.join(format!("x.{ext}"));
            let _ = std::fs::remove_file(&out);
            counts.runs += 1;
            let args = ["simplify", input_s, out.to_str().unwrap(), "--ratio=1"];
            match cli(&args, start, &bytes) {
                Ok(()) => {
                    let back = mesh::io::load(&out)
                        .unwrap_or_else(|e| panic!("{name}: exit 0, unloadable output: {e}"));
                    assert!(back.mesh.face_count() > 0, "{name}: empty output");
                    counts.simplified_ok += 1;
                }
                Err(e) => {
                    assert!(!format!("{e:#}").is_empty());
                    assert!(!out.exists(), "{name}: failed but wrote {out:?}");
                    counts.errors += 1;
                }
            }
            arena.check(&format!("mutant {k} of {name} -> {ext}"));
        }
    }
    counts
}

#[test]
fn hostile_fuzz_quick() {
    let counts = fuzz_hostile(400, 0x0405_711E);
    eprintln!("hostile fuzz: {counts:?}");
    // The unmutated corpus alone has 21 files that load (all but the 10 traversal buffers),
    // each simplified to three formats.
    assert!(counts.loaded > 21, "{counts:?}");
    assert!(counts.simplified_ok > 63, "{counts:?}");
}

#[test]
#[ignore = "long: GNG3D_FUZZ_RUNS hostile CLI runs (default 20,000)"]
fn hostile_fuzz_long() {
    let runs: u64 = std::env::var("GNG3D_FUZZ_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000);
    let counts = fuzz_hostile(runs.div_ceil(4), 7);
    eprintln!("hostile fuzz done: {counts:?}, the canary intact after every run");
}

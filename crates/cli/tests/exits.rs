//! How `gng3d` ends when it cannot go on (issue 33, rows 8-10): out of memory, a file-size
//! limit, a signal, an output folder that takes no files. Each is an error message and a clean
//! exit, with no temporary file left beside the output.

#![cfg(target_os = "linux")]

use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Command, Output, Stdio};

fn gng3d() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gng3d"))
}

/// `command` with resource limit `resource` set to `bytes` in the child only.
fn limited(mut command: Command, resource: libc::__rlimit_resource_t, bytes: u64) -> Output {
    // SAFETY: setrlimit is async-signal-safe; it runs in the child between fork and exec.
    unsafe {
        command.pre_exec(move || {
            let limit = libc::rlimit {
                rlim_cur: bytes,
                rlim_max: bytes,
            };
            if libc::setrlimit(resource, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    command.output().unwrap()
}

/// The hidden temporaries of atomic writes in `dir`.
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".gng3d.") && n.ends_with(".tmp"))
        .collect()
}

fn write_sphere(dir: &Path, subdivisions: u32) -> std::path::PathBuf {
    let path = dir.join("sphere.ply");
    mesh::io::save(&mesh::procedural::icosphere(subdivisions).into(), &path).unwrap();
    path
}

/// A file-size limit (`ulimit -f`) makes the write fail with an error, not a SIGXFSZ death,
/// and the partial temporary is removed; the old output survives.
#[test]
fn a_file_size_limit_is_an_error_and_leaves_no_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sphere(dir.path(), 5);
    let output = dir.path().join("out.obj");
    std::fs::write(&output, b"old").unwrap();
    let mut command = gng3d();
    command.args([
        "simplify",
        input.to_str().unwrap(),
        output.to_str().unwrap(),
    ]);
    command.args(["--method", "qem", "--ratio", "0.9"]);
    let out = limited(command, libc::RLIMIT_FSIZE, 64 * 1024);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{:?}: {stderr}", out.status);
    assert!(
        stderr.contains("out.obj") && stderr.contains("File too large"),
        "{stderr}"
    );
    assert_eq!(std::fs::read(&output).unwrap(), b"old");
    assert_eq!(temporaries(dir.path()), Vec::<String>::new());
}

/// Running out of address space while loading is "not enough memory" with the file's name and
/// exit status 1, not an abort (134) with a backtrace.
#[test]
fn out_of_memory_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    // 330k faces: loading needs more than 24 MiB of address space (the program starts in
    // under 16 MiB; measured with `ulimit -v`: fails at 16-32 MiB, loads at 48 MiB).
    let input = write_sphere(dir.path(), 7);
    let mut command = gng3d();
    command.args(["info", input.to_str().unwrap()]);
    let out = limited(command, libc::RLIMIT_AS, 24 << 20);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{:?}: {stderr}", out.status);
    assert!(stderr.contains("sphere.ply"), "{stderr}");
    assert!(stderr.contains("memory"), "{stderr}");
    assert!(
        !stderr.contains("backtrace") && !stderr.contains("panicked"),
        "{stderr}"
    );
}

/// SIGTERM (as SIGINT and SIGHUP) ends the run by that signal, with no output and no
/// temporary left. (Whether the signal lands inside the write is up to timing; the removal of a
/// write in progress is `mesh::io`'s unit test.)
#[test]
fn sigterm_ends_the_run_by_the_signal_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sphere(dir.path(), 6);
    let output = dir.path().join("out.ply");
    let mut child = gng3d()
        .args([
            "simplify",
            input.to_str().unwrap(),
            output.to_str().unwrap(),
        ])
        .args(["--method", "gng", "--ratio", "0.5", "--epochs", "300"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(300));
    // SAFETY: signalling our own child by its pid.
    unsafe {
        libc::kill(child.id() as i32, libc::SIGTERM);
    }
    let status = child.wait().unwrap();
    assert!(
        status.signal() == Some(libc::SIGTERM) || status.success(),
        "{status:?}"
    );
    if status.signal().is_some() {
        assert!(!output.exists());
    }
    assert_eq!(temporaries(dir.path()), Vec::<String>::new());
}

/// A folder that takes no new files is found before any work, for `simplify`, `compare --out`
/// and `reproduce --out` (root can write to read-only folders, so the test uses `/sys` and
/// `/proc`, which nobody can).
#[test]
fn unwritable_output_folders_fail_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_sphere(dir.path(), 3);
    let input = input.to_str().unwrap();
    for args in [
        vec!["simplify", input, "/sys/out.ply", "--ratio", "0.5"],
        vec!["compare", input, "--vertices", "100", "--out", "/sys/cmp"],
        vec!["reproduce", input, "--out", "/proc/rep"],
    ] {
        let start = std::time::Instant::now();
        let out = gng3d().args(&args).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("/sys") || stderr.contains("/proc"),
            "{stderr}"
        );
        assert!(out.stdout.is_empty(), "{args:?} reported results");
        // No training happened (a run of reproduce takes seconds).
        assert!(start.elapsed().as_secs_f64() < 5.0, "{args:?}");
    }
}

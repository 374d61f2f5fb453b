//! One run per work folder: a second run on a folder in use is refused naming it; the lock of a
//! killed run (its process gone) does not block the resume.

use partition::{PartitionError, PartitionParams, WorkLock, generate, simplify};
use qem::Target;
use std::io::BufRead;
use std::path::Path;
use std::process::{Command, Stdio};

/// The variable that makes [`helper_holds_the_lock_of_the_folder_it_is_given`] a lock holder.
const HOLDER: &str = "GNG3D_PARTITION_TEST_LOCK_HOLDER";

/// Not a test on its own: run by the tests below as a separate process (this test binary,
/// filtered to this test, with [`HOLDER`] naming a folder), it locks that folder, says so on
/// stdout and waits to be killed. Without the variable it does nothing.
#[test]
fn helper_holds_the_lock_of_the_folder_it_is_given() {
    if let Some(work) = std::env::var_os(HOLDER) {
        let _lock = WorkLock::acquire(Path::new(&work)).unwrap();
        println!("locked");
        std::thread::sleep(std::time::Duration::from_secs(120));
    }
}

/// Another process holding the lock of `work`, once it says it holds it.
fn holder(work: &Path) -> std::process::Child {
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "helper_holds_the_lock_of_the_folder_it_is_given",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(HOLDER, work)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut lines = std::io::BufReader::new(child.stdout.take().unwrap()).lines();
    assert!(
        lines.any(|l| l.is_ok_and(|l| l.contains("locked"))),
        "the holder did not lock"
    );
    child
}

fn params(work: &Path) -> PartitionParams {
    PartitionParams {
        memory_budget: 1 << 20,
        threads: 2,
        ..PartitionParams::new(Target::Ratio(0.1), work.to_path_buf())
    }
}

#[test]
fn a_second_run_is_refused_and_a_killed_runs_lock_does_not_block_the_resume() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    generate::write_displaced_sphere(&input, 20_000, 4).unwrap();
    let work = dir.path().join("work");
    let (first, second) = (dir.path().join("a.ply"), dir.path().join("b.ply"));
    let report = simplify(&input, &first, &params(&work)).unwrap();
    assert!(report.cells > 1);
    // A run in another process holds the folder: this one is refused, naming the folder and
    // the holder, and writes nothing.
    let mut other = holder(&work);
    let e = simplify(&input, &second, &params(&work)).unwrap_err();
    assert!(matches!(e, PartitionError::Locked { .. }), "{e}");
    let message = e.to_string();
    assert!(message.contains(&work.display().to_string()), "{message}");
    assert!(
        message.contains(&format!("process {}", other.id())),
        "{message}"
    );
    assert!(!second.exists());
    // In this process too: a second lock while the first is held.
    other.kill().unwrap();
    other.wait().unwrap();
    {
        let _held = WorkLock::acquire(&work).unwrap();
        let e = WorkLock::acquire(&work).unwrap_err();
        assert!(matches!(e, PartitionError::Locked { .. }), "{e}");
    }
    // The killed holder left its lock file: the resume runs, from the finished cells.
    let killed = holder(&work);
    let id = killed.id();
    let mut killed = killed;
    killed.kill().unwrap();
    killed.wait().unwrap();
    let left = std::fs::read_to_string(work.join("lock")).unwrap();
    assert_eq!(left, format!("process {id}"));
    let again = simplify(&input, &second, &params(&work)).unwrap();
    assert_eq!(again.cells_resumed, report.cells);
    assert_eq!(
        std::fs::read(&first).unwrap(),
        std::fs::read(&second).unwrap()
    );
}

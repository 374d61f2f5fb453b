//! Atomic writes: every file the project writes goes to a hidden temporary sibling and is
//! renamed over its name when complete ([`write_atomic`]; [`write_atomic_all`] for files that
//! belong together), so a failed or interrupted write never leaves a partial file; a signal
//! handler removes the temporaries in flight ([`remove_unfinished_writes`]).

use crate::error::MeshError;
use std::path::{Path, PathBuf};

/// Write `bytes` to `path` atomically: into a hidden temporary sibling (same folder, so the
/// rename cannot cross file systems), then renamed over `path`. A failure leaves `path` as it
/// was (absent or the previous content) and removes the temporary file. Every file the project
/// writes (meshes, tables, reports, plots) goes through here.
///
/// When `path` is a symbolic link the file it points to is written (the link stays a link).
/// The temporary name is short and does not repeat the file's (`.gng3d.<pid>.<n>.tmp`), so a
/// name near the file system's 255-byte limit still works; temporaries that a process which no
/// longer runs left in that folder (killed during a write) are removed on the way.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), MeshError> {
    write_atomic_all(&[(path, bytes)])
}

/// [`write_atomic`] for files that belong together (a `.gltf` and its `.bin`): every file is
/// written to its temporary sibling first, and only when all of them are complete are they
/// renamed over their names, in the order given. A failed write removes every temporary and
/// leaves all the files as they were.
pub(crate) fn write_atomic_all(files: &[(&Path, &[u8])]) -> Result<(), MeshError> {
    let write_err = |path: &Path, message: String| MeshError::Write {
        path: path.to_path_buf(),
        message,
    };
    let mut written: Vec<(PathBuf, PathBuf, InFlight)> = Vec::with_capacity(files.len());
    let remove_all = |written: &[(PathBuf, PathBuf, InFlight)]| {
        for (temp, _, _) in written {
            let _ = std::fs::remove_file(temp);
        }
    };
    for &(path, bytes) in files {
        let target = through_links(path);
        remove_stale_temporaries(&target);
        let temp = temp_path(&target);
        let in_flight = InFlight::register(&temp);
        if let Err(e) = std::fs::write(&temp, bytes) {
            let _ = std::fs::remove_file(&temp);
            remove_all(&written);
            return Err(write_err(path, e.to_string()));
        }
        written.push((temp, target, in_flight));
    }
    for (i, (temp, target, _)) in written.iter().enumerate() {
        if let Err(e) = std::fs::rename(temp, target) {
            remove_all(&written[i..]);
            return Err(write_err(files[i].0, e.to_string()));
        }
    }
    Ok(())
}

/// Checks, before any work, that [`write_atomic`] can write `path`: its folder (after
/// following links) exists and takes a new file. A short probe file is created and removed
/// there, so a read-only folder, a full quota or a name the file system refuses is found before
/// minutes of work rather than after them.
pub fn check_writable(path: &Path) -> Result<(), MeshError> {
    let write_err = |message: String| MeshError::Write {
        path: path.to_path_buf(),
        message,
    };
    let target = through_links(path);
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(write_err(format!(
            "the folder {} does not exist",
            dir.display()
        )));
    }
    let probe = temp_path(&target);
    let _in_flight = InFlight::register(&probe);
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(write_err(format!(
            "the folder {} does not take new files: {e}",
            dir.display()
        ))),
    }
}

/// Temporary files being written now, so that a signal can remove them
/// ([`remove_unfinished_writes`]).
static IN_FLIGHT: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// A temporary file in [`IN_FLIGHT`] while this guard lives.
pub(crate) struct InFlight(PathBuf);

impl InFlight {
    pub(crate) fn register(path: &Path) -> InFlight {
        if let Ok(mut list) = IN_FLIGHT.lock() {
            list.push(path.to_path_buf());
        }
        InFlight(path.to_path_buf())
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        if let Ok(mut list) = IN_FLIGHT.lock()
            && let Some(i) = list.iter().position(|p| *p == self.0)
        {
            list.swap_remove(i);
        }
    }
}

/// The temporaries registered now (for the tests).
#[cfg(test)]
pub(crate) fn unfinished_writes() -> Vec<PathBuf> {
    IN_FLIGHT.lock().map(|l| l.clone()).unwrap_or_default()
}

/// Removes the temporary files of the writes in progress in this process, for a program that
/// is about to exit on a signal (SIGINT, SIGTERM, SIGHUP) in the middle of a write: the output
/// keeps its previous content and no partial file is left beside it. Holds the list until the
/// process exits, so a write that finishes meanwhile cannot rename a removed file; call it only
/// right before exiting.
pub fn remove_unfinished_writes() {
    let list = match IN_FLIGHT.lock() {
        Ok(list) => list,
        Err(poisoned) => poisoned.into_inner(),
    };
    for temp in list.iter() {
        let _ = std::fs::remove_file(temp);
    }
    // Keep the lock: the caller exits.
    std::mem::forget(list);
}

/// The file `path` names after following symbolic links (itself when it is none; a dangling
/// link's target is resolved against the link's folder).
fn through_links(path: &Path) -> PathBuf {
    let mut current = path.to_path_buf();
    // A bounded walk: a link loop ends at the last link, whose write then fails with the OS's
    // error.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&current) {
            Ok(m) if m.file_type().is_symlink() => match std::fs::read_link(&current) {
                Ok(to) if to.is_absolute() => current = to,
                Ok(to) => {
                    current = current
                        .parent()
                        .map_or_else(|| to.clone(), |dir| dir.join(&to));
                }
                Err(_) => break,
            },
            _ => break,
        }
    }
    current
}

/// Prefix of the temporary files [`write_atomic`] writes.
const TEMP_PREFIX: &str = ".gng3d.";

/// A hidden sibling of `path` unique to this process and call, with a short name.
fn temp_path(path: &Path) -> PathBuf {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!("{TEMP_PREFIX}{}.{unique}.tmp", std::process::id()))
}

/// Remove the temporaries of [`write_atomic`] in `path`'s folder whose process is gone (on
/// Linux, no `/proc/<pid>`; elsewhere nothing is removed).
fn remove_stale_temporaries(path: &Path) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some(pid) = name
            .strip_prefix(TEMP_PREFIX)
            .and_then(|rest| rest.strip_suffix(".tmp"))
            .and_then(|rest| rest.split('.').next())
            .and_then(|pid| pid.parse::<u32>().ok())
        else {
            continue;
        };
        if !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

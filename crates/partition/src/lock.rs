//! One run per work folder: [`WorkLock`] holds an operating-system lock on `WORK/lock` (`flock`
//! on Unix, `LockFileEx` on Windows, through `std::fs::File::try_lock`) for the whole run. A
//! second run on the same folder is refused with [`PartitionError::Locked`] naming the folder
//! and the holder's process id. The system drops the lock when its process ends, killed or
//! not, so the file a killed run leaves behind is no lock: a resume takes it (no process id to
//! check, no stale-lock timeout to guess).
//!
//! On a network file system the lock is as good as the server's `flock` support (NFSv4: yes).

use crate::PartitionError;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The lock of a work folder, held until dropped.
#[derive(Debug)]
pub struct WorkLock {
    /// Locked while open.
    _file: File,
    path: PathBuf,
}

impl WorkLock {
    /// Lock the work folder `work` (created if missing) for this run, or
    /// [`PartitionError::Locked`] when another run holds it.
    pub fn acquire(work: &Path) -> Result<WorkLock, PartitionError> {
        let path = work.join("lock");
        let io = |source| PartitionError::Io {
            path: path.clone(),
            source,
        };
        std::fs::create_dir_all(work).map_err(|source| PartitionError::Io {
            path: work.to_path_buf(),
            source,
        })?;
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(io)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                let mut holder = String::new();
                let _ = file.read_to_string(&mut holder);
                return Err(PartitionError::Locked {
                    path: work.to_path_buf(),
                    holder: holder.trim().to_string(),
                });
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(io(e)),
        }
        // Who holds it, for the message of a run refused.
        file.set_len(0).map_err(io)?;
        file.rewind().map_err(io)?;
        write!(file, "process {}", std::process::id()).map_err(io)?;
        file.flush().map_err(io)?;
        Ok(WorkLock { _file: file, path })
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

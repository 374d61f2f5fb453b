//! Phase 2's tables of the original, built on a helper thread while training runs.

use crate::reconstruct::OriginalTables;
use mesh::TriMesh;
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::JoinHandle;

/// Phase 2's tables of the original ([`OriginalTables`]: edge table, vertex adjacency), built
/// on a helper thread started with the trainer, so that they are ready when training ends
/// (igea: ~45 ms of work that phase 2 no longer waits for, and both cores label). Shared by
/// clones of the trainer; every reconstruction (the viewer's checkpoints too) reuses them.
pub(super) struct BackgroundTables {
    handle: Mutex<Option<JoinHandle<OriginalTables>>>,
    tables: OnceLock<Option<OriginalTables>>,
}

impl BackgroundTables {
    /// Start building the tables of `original` on a helper thread when `spawn` (nothing when
    /// not, or when no thread can be started: phase 2 then builds them itself).
    pub(super) fn start(original: &Arc<TriMesh>, spawn: bool) -> BackgroundTables {
        let mesh = Arc::clone(original);
        let handle = spawn
            .then(|| {
                std::thread::Builder::new()
                    .name("gng3d-tables".into())
                    .spawn(move || OriginalTables::of(&mesh))
                    .ok()
            })
            .flatten();
        BackgroundTables {
            handle: Mutex::new(handle),
            tables: OnceLock::new(),
        }
    }

    /// The tables, waiting for the helper thread if needed; `None` when it could not run.
    pub(super) fn get(&self) -> Option<&OriginalTables> {
        self.tables
            .get_or_init(|| {
                let handle = self.handle.lock().ok()?.take()?;
                handle.join().ok()
            })
            .as_ref()
    }
}

impl std::fmt::Debug for BackgroundTables {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BackgroundTables")
            .field("ready", &self.tables.get().is_some())
            .finish()
    }
}

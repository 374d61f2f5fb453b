//! [`Cancel`]: the flag that stops a long call from another thread (training, GNG3D's steps
//! after training, QEM, the metrics), shared by every algorithm crate of the workspace.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A shared flag that asks a running call to stop. Clones share the flag: keep one, give a clone
/// to the call (or its parameters), and [`cancel`](Cancel::cancel) from any thread. A call that
/// sees it set stops at its next check and returns its crate's `Cancelled` error (or, for
/// training, stops with its reason), never a partial result.
///
/// ```
/// let cancel = gng3d_mesh::cancel::Cancel::default();
/// let handle = cancel.clone();
/// assert!(!cancel.is_cancelled());
/// handle.cancel();
/// assert!(cancel.is_cancelled());
/// ```
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// Ask the calls that watch this flag to stop at their next check.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether cancellation was requested.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Two handles are equal when they share one flag (clones of each other).
impl PartialEq for Cancel {
    fn eq(&self, other: &Cancel) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

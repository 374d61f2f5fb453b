//! [`Cancel`]: the flag that stops a long call from another thread (training, GNG3D's steps
//! after training, QEM, the metrics), shared by every algorithm crate of the workspace.

use std::fmt::Debug;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

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

/// Test support for the algorithm crates' cancel tests, not part of the API: checks that `run`
/// stops soon after its flag is set during a run. The flag is set halfway through the time an
/// uncancelled `run` takes (measured first, with a flag never set), then a quarter, an eighth,
/// a sixteenth, until one run sees it (a fixed delay raced a fast machine: the run ended
/// first); that run must return `cancelled`, less than `bound` after the flag was set. Panics
/// when not.
#[doc(hidden)]
pub fn assert_stops_within<T, E: PartialEq + Debug>(
    run: impl Fn(&Cancel) -> Result<T, E>,
    cancelled: E,
    bound: Duration,
) {
    let started = Instant::now();
    if let Err(e) = run(&Cancel::default()) {
        panic!("the uncancelled run failed: {e:?}");
    }
    let whole = started.elapsed();
    let mut delay = whole / 2;
    for _ in 0..4 {
        let cancel = Cancel::default();
        let setter = cancel.clone();
        let timer = std::thread::spawn(move || {
            std::thread::sleep(delay);
            setter.cancel();
            Instant::now()
        });
        let result = run(&cancel);
        let ended = Instant::now();
        let set = timer.join().unwrap();
        let Err(e) = result else {
            delay /= 2;
            continue;
        };
        assert_eq!(e, cancelled);
        let latency = ended.saturating_duration_since(set);
        println!("{latency:?} from the flag to the return (a whole run: {whole:?})");
        assert!(latency < bound, "{latency:?} from the flag to the return");
        return;
    }
    panic!("no run saw the flag (a whole run takes {whole:?})");
}

//! One-shot background jobs: a named thread computes one value, the UI polls for it each frame
//! and never blocks. Used for mesh loading, file dialogs, QEM and evaluations.

use crate::error::ViewerError;
use std::sync::mpsc::{self, Receiver, TryRecvError};

/// A value being computed on its own thread.
pub struct Job<T> {
    name: &'static str,
    result: Receiver<T>,
}

impl<T: Send + 'static> Job<T> {
    /// Run `work` on a new thread called `name`; `repaint` (if any) is asked for a repaint when
    /// the value is ready, so an idle UI wakes up to show it.
    pub fn spawn(
        name: &'static str,
        repaint: Option<egui::Context>,
        work: impl FnOnce() -> T + Send + 'static,
    ) -> Job<T> {
        let (tx, result) = mpsc::channel();
        // If the thread cannot be started, `tx` is dropped and `poll` reports the job lost.
        let _ = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                let _ = tx.send(work());
                if let Some(ctx) = repaint {
                    ctx.request_repaint();
                }
            });
        Job { name, result }
    }

    /// [`Job::spawn`] at a lower scheduling priority (Linux: nice 10): for analysis the user
    /// waits for anyway (QEM and its evaluation, checkpoint evaluations), so that on a machine
    /// with few cores it yields to the UI thread, the CPU renderer and the training thread
    /// instead of taking their time (with lavapipe on two cores, QEM's 200k-sample evaluation
    /// took ~2.4 s of CPU from the first seconds of a run).
    pub fn spawn_background(
        name: &'static str,
        repaint: Option<egui::Context>,
        work: impl FnOnce() -> T + Send + 'static,
    ) -> Job<T> {
        Job::spawn(name, repaint, move || {
            lower_thread_priority();
            work()
        })
    }

    /// The value once it is ready (`None` while the job runs); an error when the job's thread
    /// died without one. After `Some`, the job is spent.
    pub fn poll(&self) -> Option<Result<T, ViewerError>> {
        match self.result.try_recv() {
            Ok(value) => Some(Ok(value)),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(ViewerError::JobLost(self.name))),
        }
    }
}

/// Lower the calling thread's scheduling priority (nice 10; Linux only, elsewhere a no-op).
fn lower_thread_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority only reads its arguments; on Linux the nice value belongs to the
    // thread named by its id, here the calling thread. A failure just leaves the priority.
    unsafe {
        let _ = libc::setpriority(libc::PRIO_PROCESS, libc::gettid() as libc::id_t, 10);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    fn wait<T: Send + 'static>(job: &Job<T>) -> Result<T, ViewerError> {
        let start = Instant::now();
        loop {
            if let Some(r) = job.poll() {
                return r;
            }
            assert!(start.elapsed() < Duration::from_secs(10), "job hung");
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    #[test]
    fn job_delivers_its_value_and_a_panicking_job_is_reported_lost() {
        let job = Job::spawn("test-job", None, || 6 * 7);
        assert_eq!(wait(&job), Ok(42));
        let lost: Job<u32> = Job::spawn("test-panic", None, || panic!("boom"));
        assert_eq!(wait(&lost), Err(ViewerError::JobLost("test-panic")));
    }
}

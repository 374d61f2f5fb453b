//! How a run uses the machine: whether work is split over the rayon pool ([`parallel`], off on a
//! thread that already runs one part of a partitioned run: [`sequential`]) and handing freed heap
//! memory back to the system ([`release_freed_memory`]).

/// Work lists shorter than this are processed on the calling thread only.
pub(super) const PARALLEL_MIN: usize = 32_768;
/// Items per parallel task.
pub(super) const PARALLEL_CHUNK: usize = 8_192;

thread_local! {
    /// Set while this thread simplifies one part of a partitioned run: the parts already occupy
    /// the pool, and nested splitting would only add memory (per-chunk buffers, more arenas).
    static SEQUENTIAL: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether `len` work items (at least `min`) are worth splitting over the rayon pool; with one
/// thread (`RAYON_NUM_THREADS=1`) everything runs on the calling thread.
pub(super) fn parallel(len: usize, min: usize) -> bool {
    len >= min && rayon::current_num_threads() > 1 && !SEQUENTIAL.with(|s| s.get())
}

/// Run `f` with [`parallel`] off on this thread.
pub(super) fn sequential<R>(f: impl FnOnce() -> R) -> R {
    let before = SEQUENTIAL.with(|s| s.replace(true));
    let out = f();
    SEQUENTIAL.with(|s| s.set(before));
    out
}

/// Hand the heap memory freed so far (the whole mesh's preparation, ~64 B a face) back to the
/// system. glibc keeps freed memory for reuse by the arena that freed it, but the parts run on
/// pool threads with arenas of their own, so without this the process holds both: on igea-1m at
/// 10 % on two threads the peak RSS was 280 MiB with it kept and 216 MiB with it released
/// (one thread: 200). Elsewhere a no-op. Also called by the passes when the candidate list gives
/// back its emptied capacity (`Schedule::next_list`).
pub(super) fn release_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `malloc_trim` only returns free pages to the system; no live allocation is touched.
    unsafe {
        libc::malloc_trim(0);
    }
}

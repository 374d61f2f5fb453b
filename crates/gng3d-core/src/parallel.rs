//! Deterministic fork-join for phase 2: an index range split into contiguous chunks, one scoped
//! thread per chunk, results concatenated in index order, so the output is the same for any
//! thread count. No pool and no dependency: phase 2 forks a handful of times per run, and a
//! scoped thread start (~20 µs) is noise next to the chunks it is used for.

/// Threads phase 2 forks into: the machine's parallelism, at most four (the chunks are memory
/// bound beyond that).
pub(crate) fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().min(4))
}

/// `(0..len).map(f)` on up to `threads` threads, each taking at least `min_per_thread` indices.
pub(crate) fn map_indexed<T, F>(len: usize, threads: usize, min_per_thread: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync,
{
    let threads = threads.min(len / min_per_thread.max(1)).max(1);
    if threads == 1 {
        return (0..len).map(f).collect();
    }
    let chunk = len.div_ceil(threads);
    let f = &f;
    std::thread::scope(|scope| {
        let parts: Vec<_> = (0..len)
            .step_by(chunk)
            .map(|lo| scope.spawn(move || (lo..(lo + chunk).min(len)).map(f).collect::<Vec<T>>()))
            .collect();
        let mut out = Vec::with_capacity(len);
        for part in parts {
            match part.join() {
                Ok(v) => out.extend(v),
                // A panic in `f` is a bug; re-raise it on the caller's thread.
                Err(e) => std::panic::resume_unwind(e),
            }
        }
        out
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_result_for_every_thread_count() {
        let want: Vec<u64> = (0..10_001u64).map(|i| i * i % 977).collect();
        for threads in [1, 2, 3, 4, 7] {
            let got = map_indexed(10_001, threads, 100, |i| (i as u64) * (i as u64) % 977);
            assert_eq!(got, want, "{threads} threads");
        }
        assert!(map_indexed(0, 4, 1, |i| i).is_empty());
    }
}

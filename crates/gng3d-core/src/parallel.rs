//! Deterministic fork-join: work split into contiguous chunks, one scoped thread per chunk,
//! results combined in order, so the output is the same for any thread count. Phase 2 maps
//! index ranges ([`map_indexed`]); training runs the parts of a round side by side
//! ([`sum_over_groups`]). No pool and no dependency: a scoped thread start (~20-50 µs) is noise
//! next to the chunks it is used for.

/// Threads a run uses, the caller's included: `setting` ([`crate::GngParams::threads`], at
/// least 1), or by default the machine's parallelism, at most four (the chunks are memory bound
/// beyond that).
pub(crate) fn threads(setting: Option<usize>) -> usize {
    setting.map_or_else(
        || std::thread::available_parallelism().map_or(1, |n| n.get().min(4)),
        |n| n.max(1),
    )
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

/// `f` applied to every item of `items` (each item once, in order within its group), the
/// items dealt to up to `threads` scoped threads in contiguous groups; returns the sum of
/// `f`'s results. Items must not depend on one another: then the result is the same for any
/// thread count.
pub(crate) fn sum_over_groups<T, F>(items: &mut [T], threads: usize, f: F) -> u64
where
    T: Send,
    F: Fn(&mut T) -> u64 + Sync,
{
    let threads = threads.min(items.len());
    if threads <= 1 {
        return items.iter_mut().map(&f).sum();
    }
    let per_thread = items.len().div_ceil(threads);
    let f = &f;
    std::thread::scope(|scope| {
        let mut groups = items.chunks_mut(per_thread);
        let first = groups.next();
        let handles: Vec<_> = groups
            .map(|g| scope.spawn(move || g.iter_mut().map(f).sum::<u64>()))
            .collect();
        let mut total: u64 = first.map_or(0, |g| g.iter_mut().map(f).sum());
        for h in handles {
            match h.join() {
                Ok(n) => total += n,
                // A panic in `f` is a bug; re-raise it on the caller's thread.
                Err(e) => std::panic::resume_unwind(e),
            }
        }
        total
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

    #[test]
    fn groups_see_every_item_once_on_any_thread_count() {
        for threads in [1, 2, 3, 4, 9] {
            let mut items: Vec<u64> = (0..7).collect();
            let sum = sum_over_groups(&mut items, threads, |x| {
                *x *= 10;
                *x
            });
            assert_eq!(sum, 210, "{threads} threads");
            assert_eq!(items, (0..7).map(|x| 10 * x).collect::<Vec<u64>>());
        }
        assert_eq!(sum_over_groups(&mut Vec::<u64>::new(), 2, |x| *x), 0);
    }
}

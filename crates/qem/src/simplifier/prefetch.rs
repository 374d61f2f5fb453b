//! Software prefetch for the walks in cost order (the pass loop, the initial costing, the pair
//! generation between passes): they read vertex records, face lists, faces and neighbour records
//! at random, a chain of dependent cache misses. This file holds the hint ([`prefetch_ptr`]), how
//! far ahead each link of that chain is hinted and when the stages pay ([`worth_it`]); the
//! engine's stages are `engine::stages`. The distances were tuned on igea and armadillo
//! (docs/notes/qem.md, "Prefetch pipeline": the staged pipeline took the pass walk from 145 to
//! ~56 ms on igea 10 %).

/// How many list entries ahead the pass loop prefetches the ends' contraction generations
/// (`Engine::contracted`).
pub(super) const CONTRACTED: usize = 32;
/// How many live candidates (or survivors, in the pair generation) ahead the vertex records of
/// the endpoints are prefetched.
pub(super) const RECORDS: usize = 16;
/// How many live candidates (survivors) ahead the face lists are prefetched.
pub(super) const LISTS: usize = 8;
/// How many live candidates (survivors) ahead the faces are prefetched.
pub(super) const FACES: usize = 4;
/// How many live candidates (survivors) ahead the records around the endpoints are prefetched.
pub(super) const RING: usize = 2;
/// The walks over a face list (`prefetch_faces_of`, `prefetch_ring_of`) stop after this many
/// entries. Ordinary lists are far shorter (valence 6, a few more entries for dead faces not yet
/// compacted); a hub's list is as long as its fan (issue 33: a flat fan of 110,000 triangles
/// took 23 s at 10 %, 84 % of it in these walks, repeated for every queued candidate on the hub,
/// i.e. quadratic), and the lines of a list that long would not stay in cache until its turn.
pub(super) const LIST_WALK: usize = 32;

/// Meshes with fewer vertices than this are walked without the prefetch stages: their vertex
/// records (128 B each: 1 MiB at this count, this VM's L2), faces and face lists stay in cache,
/// and the stages' own walks over face lists (`prefetch_faces_of`, `prefetch_ring_of`) are pure
/// overhead there. Measured with the `compare` example, one thread, alternating, output
/// byte-identical: without the stages fandisk (6,475 vertices), cow (2,903) and casting (5,096)
/// at 10 % and 1 % took 5-11 % less time (ratio to meshoptimizer 1.47 → 1.34, 1.67 → 1.51, 1.48
/// → 1.35 at 10 %); at 10,000 vertices (gargoyle-10k, rocker-arm) the stages already pay (ratio
/// 1.20 with them, 1.30 without) and at 36k (stanford-bunny) they halve the time.
pub(super) const MIN_VERTICES: usize = 8_192;

/// Whether a mesh of `vertices` vertices is walked with the prefetch stages ([`MIN_VERTICES`]).
pub(super) fn worth_it(vertices: usize) -> bool {
    #[cfg(test)]
    if let Some(forced) = FORCE.with(std::cell::Cell::get) {
        return forced;
    }
    vertices >= MIN_VERTICES
}

/// Hint the CPU to load the cache line at `p` (a hint only: any address is fine).
#[inline(always)]
pub(super) fn prefetch_ptr<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: prefetching is only a hint; it never faults, whatever the address.
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

#[cfg(test)]
thread_local! {
    /// Overrides [`worth_it`] on this thread (tests only).
    pub(super) static FORCE: std::cell::Cell<Option<bool>> = const { std::cell::Cell::new(None) };
}

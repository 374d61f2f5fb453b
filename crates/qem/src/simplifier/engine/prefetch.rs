//! Software prefetch for the walks in cost order (the pass loop, the initial costing, the pair
//! generation between passes): they read vertex records, face lists, faces and neighbour records
//! at random, a chain of dependent cache misses. Each helper hints one link of that chain for a
//! vertex a few steps ahead; the distances were tuned on igea and armadillo (docs/notes/qem.md,
//! "Prefetch pipeline": the staged pipeline took the pass walk from 145 to ~56 ms on igea 10 %).

use super::Engine;
use crate::simplifier::triangle::corner_after;

/// How many list entries ahead the pass loop prefetches the ends' contraction generations
/// (`Engine::contracted`).
pub(in crate::simplifier) const CONTRACTED: usize = 32;
/// How many live candidates (or survivors, in the pair generation) ahead the vertex records of
/// the endpoints are prefetched.
pub(in crate::simplifier) const RECORDS: usize = 16;
/// How many live candidates (survivors) ahead the face lists are prefetched.
pub(in crate::simplifier) const LISTS: usize = 8;
/// How many live candidates (survivors) ahead the faces are prefetched.
pub(in crate::simplifier) const FACES: usize = 4;
/// How many live candidates (survivors) ahead the records around the endpoints are prefetched.
pub(in crate::simplifier) const RING: usize = 2;
/// The walks over a face list (`prefetch_faces_of`, `prefetch_ring_of`) stop after this many
/// entries. Ordinary lists are far shorter (valence 6, a few more entries for dead faces not yet
/// compacted); a hub's list is as long as its fan (issue 33: a flat fan of 110,000 triangles
/// took 23 s at 10 %, 84 % of it in these walks, repeated for every queued candidate on the hub,
/// i.e. quadratic), and the lines of a list that long would not stay in cache until its turn.
pub(in crate::simplifier) const LIST_WALK: usize = 32;

/// Meshes with fewer vertices than this are walked without the prefetch stages: their vertex
/// records (128 B each: 1 MiB at this count, this VM's L2), faces and face lists stay in cache,
/// and the stages' own walks over face lists (`prefetch_faces_of`, `prefetch_ring_of`) are pure
/// overhead there. Measured with the `compare` example, one thread, alternating, output
/// byte-identical: without the stages fandisk (6,475 vertices), cow (2,903) and casting (5,096)
/// at 10 % and 1 % took 5-11 % less time (ratio to meshoptimizer 1.47 → 1.34, 1.67 → 1.51, 1.48
/// → 1.35 at 10 %); at 10,000 vertices (gargoyle-10k, rocker-arm) the stages already pay (ratio
/// 1.20 with them, 1.30 without) and at 36k (stanford-bunny) they halve the time.
pub(in crate::simplifier) const MIN_VERTICES: usize = 8_192;

/// Whether a mesh of `vertices` vertices is walked with the prefetch stages ([`MIN_VERTICES`]).
pub(in crate::simplifier) fn worth_it(vertices: usize) -> bool {
    #[cfg(test)]
    if let Some(forced) = tests::FORCE.with(std::cell::Cell::get) {
        return forced;
    }
    vertices >= MIN_VERTICES
}

/// Hint the CPU to load the cache line at `p` (a hint only: any address is fine).
#[inline(always)]
pub(in crate::simplifier) fn prefetch_ptr<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: prefetching is only a hint; it never faults, whatever the address.
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

impl Engine {
    /// Hint the CPU to load both cache lines of vertex record `i` (a no-op out of range).
    #[inline]
    pub(in crate::simplifier) fn prefetch_record(&self, i: usize) {
        if i < self.vx.len() {
            let d = self.vx.as_ptr().wrapping_add(i).cast::<u8>();
            prefetch_ptr(d);
            prefetch_ptr(d.wrapping_add(64));
        }
    }

    /// Hint the CPU to load the face list of `i` (its record should be cached).
    #[inline]
    pub(in crate::simplifier) fn prefetch_list(&self, i: usize) {
        if let Some(info) = self.vx.get(i) {
            let s = info.start as usize;
            prefetch_ptr(self.refs.as_ptr().wrapping_add(s));
            prefetch_ptr(self.refs.as_ptr().wrapping_add(s + info.len as usize));
        }
    }

    /// Hint the CPU to load the faces of `i` (its list should be cached; the first [`LIST_WALK`]).
    #[inline]
    pub(in crate::simplifier) fn prefetch_faces_of(&self, i: usize) {
        if i < self.vx.len() {
            for &f in self.refs[self.list(i)].iter().take(LIST_WALK) {
                prefetch_ptr(self.faces.as_ptr().wrapping_add(f as usize));
            }
        }
    }

    /// Hint the CPU to load the records of the vertices around `i` (its faces should be cached; the
    /// first [`LIST_WALK`] faces):
    /// the first line only (position, mark and valence: what the topology and flip checks read),
    /// or the whole record when `whole` (the pair generation also reads the quadric).
    #[inline]
    pub(in crate::simplifier) fn prefetch_ring_of(&self, i: usize, whole: bool) {
        if i < self.vx.len() {
            for &f in self.refs[self.list(i)].iter().take(LIST_WALK) {
                let w = corner_after(&self.faces[f as usize], i as u32) as usize;
                if whole {
                    self.prefetch_record(w);
                } else {
                    prefetch_ptr(self.vx.as_ptr().wrapping_add(w));
                }
            }
        }
    }

    /// First prefetch stage of a candidate walk (cost order, i.e. at random): the records of
    /// `a` and `b`.
    #[inline]
    pub(in crate::simplifier) fn prefetch(&self, a: usize, b: usize) {
        self.prefetch_record(a);
        self.prefetch_record(b);
    }

    /// Second prefetch stage: the face lists of `a` and `b`, and their carried values in an
    /// attribute run.
    #[inline]
    pub(in crate::simplifier) fn prefetch_lists(&self, a: usize, b: usize) {
        self.prefetch_list(a);
        self.prefetch_list(b);
        if let Some(values) = &self.values {
            values.prefetch(a);
            values.prefetch(b);
        }
    }

    /// Third prefetch stage: the faces of `a` and `b`.
    #[inline]
    pub(in crate::simplifier) fn prefetch_faces(&self, a: usize, b: usize) {
        self.prefetch_faces_of(a);
        self.prefetch_faces_of(b);
    }

    /// Fourth prefetch stage: the positions of the vertices around `a` and `b`.
    #[inline]
    pub(in crate::simplifier) fn prefetch_ring(&self, a: usize, b: usize) {
        self.prefetch_ring_of(a, false);
        self.prefetch_ring_of(b, false);
    }

    /// Prefetch, in stages, the records, face lists, faces and neighbour records for the pair
    /// generation of the survivors a few places after `i`.
    #[inline]
    pub(in crate::simplifier) fn prefetch_survivors(&self, survivors: &[u32], i: usize) {
        if let Some(&ahead) = survivors.get(i + RECORDS) {
            self.prefetch_record(ahead as usize);
        }
        if let Some(&ahead) = survivors.get(i + LISTS) {
            self.prefetch_list(ahead as usize);
        }
        if let Some(&ahead) = survivors.get(i + FACES) {
            self.prefetch_faces_of(ahead as usize);
        }
        if let Some(&ahead) = survivors.get(i + RING) {
            self.prefetch_ring_of(ahead as usize, true);
        }
    }
}

#[cfg(test)]
pub(in crate::simplifier) mod tests {
    thread_local! {
        /// Overrides [`super::worth_it`] on this thread (tests only).
        pub(in super::super) static FORCE: std::cell::Cell<Option<bool>> =
            const { std::cell::Cell::new(None) };
    }

    /// The plain run (`simplify` of a mesh alone) with the prefetch stages forced on or off.
    fn simplified(mesh: &mesh::TriMesh, faces: usize, prefetch: bool) -> mesh::TriMesh {
        FORCE.with(|f| f.set(Some(prefetch)));
        let params = crate::QemParams::with_target(crate::Target::Faces(faces));
        let out = crate::simplifier::run(mesh, &params).expect("simplify").0;
        FORCE.with(|f| f.set(None));
        out
    }

    #[test]
    fn the_walk_without_prefetch_contracts_the_same_pairs() {
        // One mesh below and one above MIN_VERTICES, each simplified both ways, to 10 % and 1 %.
        for mesh in [
            mesh::procedural::icosphere(4),
            mesh::procedural::icosphere(5),
        ] {
            for faces in [mesh.face_count() / 10, mesh.face_count() / 100] {
                let with = simplified(&mesh, faces, true);
                let without = simplified(&mesh, faces, false);
                assert!(with.face_count() <= faces && with.face_count() > 0);
                assert_eq!(with.triangles, without.triangles);
                assert_eq!(with.positions, without.positions);
            }
        }
    }
}

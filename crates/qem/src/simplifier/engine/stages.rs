//! The engine's prefetch stages: each hints one link of the chain of cache misses of the walks in
//! cost order ([`super::super::prefetch`]) for a vertex a few steps ahead.

use super::Engine;
use crate::simplifier::prefetch::{FACES, LIST_WALK, LISTS, RECORDS, RING, prefetch_ptr};
use crate::simplifier::triangle::corner_after;

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

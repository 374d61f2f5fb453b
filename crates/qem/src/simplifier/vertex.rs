//! The per-vertex record ([`Vertex`]) that the set-up fills and the engine contracts with.

use crate::Quadric;
use glam::DVec3;

/// Everything per vertex, in two cache lines: the first holds what the checks read for the
/// neighbours of a pair (position, scratch mark, valence), the second the rest of the quadric and
/// the face-list bookkeeping; a record never straddles more lines than it needs (one record
/// instead of three arrays: pass walk 70 → 58 ms on igea 10 %, docs/notes/qem.md, "Engine design").
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(64))]
pub(super) struct Vertex {
    /// Position in the normalised frame.
    pub(super) p: DVec3,
    /// Scratch mark (compared with `Engine::tick`).
    pub(super) mark: u32,
    /// Live faces around the vertex.
    pub(super) valence: u32,
    /// Quadric (face planes plus boundary planes) in the normalised frame.
    pub(super) q: Quadric,
    /// Start of the face list in `refs`.
    pub(super) start: u32,
    /// Length of the face list (may include dead faces).
    pub(super) len: u32,
    /// Pass in which the vertex was last touched by a contraction.
    pub(super) touched: u32,
    /// Not merged into another vertex.
    pub(super) alive: bool,
    /// On a boundary edge (or a non-manifold edge).
    pub(super) boundary: bool,
    /// Never contracted (shared with another part of a partitioned run).
    pub(super) locked: bool,
}

impl Vertex {
    /// Where its face list lies in the face lists (`refs`).
    #[inline]
    pub(super) fn list(&self) -> std::ops::Range<usize> {
        let s = self.start as usize;
        s..s + self.len as usize
    }
}

// Two whole cache lines per vertex.
const _: () = assert!(std::mem::size_of::<Vertex>() == 128);

//! The candidate list: pairs with their cost key and the generation they were costed in, kept
//! sorted by cost (stable radix sort on the top 22 bits of the key) and carried from pass to
//! pass, with stale entries dropped when the fresh pairs are merged in.
//!
//! A candidate is 12 bytes: the sort needs only the top 22 bits of the cost's `f32` bits, so the
//! low [`GENERATION_BITS`] carry the generation (the pass) it was costed in, and an entry is
//! live while neither end has been contracted in a later generation ([`is_live`]). (Until
//! 2026-12-02 a fourth word held the sum of the ends' version stamps: 16 bytes, a third more
//! memory in the list, its merge buffer and the fresh pairs.)

/// Low bits of [`Cand::key`] that hold the generation instead of cost mantissa bits.
pub(super) const GENERATION_BITS: u32 = 10;
/// Mask of those bits.
pub(super) const GENERATION_MASK: u32 = (1 << GENERATION_BITS) - 1;
/// Generations before the numbering has to restart (the run then re-costs every pair; see
/// `simplify_prepared`).
pub(super) const GENERATIONS: u32 = GENERATION_MASK;

/// A candidate pair with its cost (as `f32` bits, which order like the non-negative cost) and
/// the generation it was costed in (the low bits of `key`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Cand {
    /// Cost as `f32` bits (see [`cost_key`]) with the low [`GENERATION_BITS`] replaced by the
    /// generation.
    pub(super) key: u32,
    /// One end.
    pub(super) a: u32,
    /// The other end.
    pub(super) b: u32,
}

const _: () = assert!(std::mem::size_of::<Cand>() == 12);

impl Cand {
    /// The pair `(a, b)`, not yet costed.
    #[inline]
    pub(super) fn pair(a: u32, b: u32) -> Cand {
        Cand {
            a,
            b,
            ..Cand::default()
        }
    }
}

/// The part of a cost key that orders candidates: the low 10 mantissa bits are dropped (costs
/// within a relative 2⁻¹³ count as equal and keep their order), so the radix sort needs two
/// 11-bit digits instead of three (−5 M instructions on armadillo 10 %); those bits hold the
/// generation.
#[inline]
pub(super) fn sort_key(key: u32) -> u32 {
    key >> GENERATION_BITS
}

/// The cost a key stands for, with its generation bits cleared (at most 2⁻¹³ below the cost).
#[inline]
pub(super) fn key_cost(key: u32) -> f32 {
    f32::from_bits(key & !GENERATION_MASK)
}

/// The key of `cost` costed in `generation` (< [`GENERATIONS`]).
#[inline]
pub(super) fn key_of(cost: f64, generation: u32) -> u32 {
    (cost_key(cost) & !GENERATION_MASK) | generation
}

/// The sortable key of a cost: its `f32` bits (NaN sorts last, negative rounding noise as 0).
#[inline]
pub(super) fn cost_key(cost: f64) -> u32 {
    let c = cost as f32;
    if c.is_nan() {
        f32::MAX.to_bits()
    } else {
        c.max(0.0).to_bits()
    }
}

/// Whether the candidate still describes the current pair: neither end contracted (or merged
/// away) since it was evaluated. `contracted[v]` is the generation in which `v` was last
/// contracted (0: never); pairs are costed after the contractions of their generation, so a
/// contraction in the same generation is already in the cost.
#[inline]
pub(super) fn is_live(c: &Cand, contracted: &[u16]) -> bool {
    let g = (c.key & GENERATION_MASK) as u16;
    contracted[c.a as usize] <= g && contracted[c.b as usize] <= g
}

/// Write into `out` the merge of the sorted unvisited rest `list[consumed..]` of the candidate
/// list (dropping stale entries, so that later passes neither copy nor walk them) with the sorted
/// fresh list `fresh` (all live); on equal sort keys carried entries come first. One sequential
/// read and write; the caller swaps `out` and `list` (both buffers are kept for the whole run).
pub(super) fn merge_live(
    list: &[Cand],
    consumed: usize,
    fresh: &[Cand],
    contracted: &[u16],
    out: &mut Vec<Cand>,
) {
    out.clear();
    out.reserve(list.len() - consumed + fresh.len());
    let mut j = 0;
    for c in &list[consumed..] {
        if !is_live(c, contracted) {
            continue;
        }
        let k = sort_key(c.key);
        while j < fresh.len() && sort_key(fresh[j].key) < k {
            out.push(fresh[j]);
            j += 1;
        }
        out.push(*c);
    }
    out.extend_from_slice(&fresh[j..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_drops_stale_entries_and_keeps_carried_first_on_ties() {
        // Vertex 1 was contracted in generation 1.
        let contracted = vec![0u16, 1, 0, 0];
        let c = |key: u32, a: u32, b: u32, generation: u32| Cand {
            key: (key << 10) | generation,
            a,
            b,
        };
        // Entry 0 is consumed; (1, 2) was costed in generation 0, before vertex 1 changed: stale.
        let list = [c(0, 0, 2, 0), c(5, 1, 2, 0), c(7, 2, 3, 0)];
        let fresh = [c(7, 0, 1, 1), c(9, 1, 3, 1)];
        let mut out = Vec::new();
        merge_live(&list, 1, &fresh, &contracted, &mut out);
        assert_eq!(out, vec![list[2], fresh[0], fresh[1]]);
    }

    #[test]
    fn keys_keep_the_cost_order_and_carry_the_generation() {
        let (lo, hi) = (key_of(1.0, 7), key_of(1.5, 0));
        assert!(sort_key(lo) < sort_key(hi));
        assert_eq!(lo & GENERATION_MASK, 7);
        let back = key_cost(key_of(1.25, 1000));
        assert!(back <= 1.25 && back > 1.25 * (1.0 - 1.3e-4), "{back}");
        let contracted = vec![3u16, 0];
        let pair = |generation| Cand {
            key: key_of(2.0, generation),
            a: 0,
            b: 1,
        };
        assert!(!is_live(&pair(2), &contracted));
        assert!(is_live(&pair(3), &contracted));
    }
}

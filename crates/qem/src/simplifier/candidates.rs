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

/// Merge, in `list` itself, its sorted unvisited rest `list[consumed..]` (stale entries dropped,
/// so that later passes neither copy nor walk them) with the sorted fresh list `fresh` (all
/// live); on equal sort keys carried entries come first.
///
/// Two sequential steps in one buffer: the live rest moves to the front, then the two sorted runs
/// merge from the back (the write position never overtakes the carried entry it reads). Until
/// 2026-12-03 the merge wrote into a second buffer the size of the list, kept for the whole run:
/// 12 bytes per candidate, ~19 MB of the peak on igea-1m (docs/notes/qem.md, "Engine design").
pub(super) fn merge_live(
    list: &mut Vec<Cand>,
    consumed: usize,
    fresh: &[Cand],
    contracted: &[u16],
) {
    // Step 1: the live rest, in order, to the front.
    let mut carried = 0;
    for i in consumed..list.len() {
        let c = list[i];
        if is_live(&c, contracted) {
            list[carried] = c;
            carried += 1;
        }
    }
    list.truncate(carried);
    // Exactly the room needed: growing by doubling would reserve (and later touch) far more.
    list.reserve_exact(fresh.len());
    list.resize(carried + fresh.len(), Cand::default());
    // Step 2: merge from the back; fresh entries go after carried ones of equal key.
    let (mut i, mut j) = (carried, fresh.len());
    while j > 0 {
        let k = i + j - 1;
        if i > 0 && sort_key(list[i - 1].key) > sort_key(fresh[j - 1].key) {
            list[k] = list[i - 1];
            i -= 1;
        } else {
            list[k] = fresh[j - 1];
            j -= 1;
        }
    }
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
        let mut merged = list.to_vec();
        merge_live(&mut merged, 1, &fresh, &contracted);
        assert_eq!(merged, vec![list[2], fresh[0], fresh[1]]);
    }

    #[test]
    fn merge_in_place_matches_a_stable_sort_of_the_live_rest_and_the_fresh_pairs() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move |m: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % m
        };
        const VERTICES: u64 = 64;
        for round in 0..200 {
            let contracted: Vec<u16> = (0..VERTICES).map(|_| next(4) as u16).collect();
            // Few distinct keys, so that ties between carried and fresh entries are common.
            let cand = |generation: u64, next: &mut dyn FnMut(u64) -> u64| Cand {
                key: ((next(40) as u32) << GENERATION_BITS) | generation as u32,
                a: next(VERTICES) as u32,
                b: next(VERTICES) as u32,
            };
            let carried = next(300);
            let mut list: Vec<Cand> = (0..carried)
                .map(|_| {
                    let generation = next(4);
                    cand(generation, &mut next)
                })
                .collect();
            let fresh_len = next(if round % 2 == 0 { 20 } else { 400 });
            let mut fresh: Vec<Cand> = (0..fresh_len).map(|_| cand(3, &mut next)).collect();
            list.sort_by_key(|c| sort_key(c.key));
            fresh.sort_by_key(|c| sort_key(c.key));
            let consumed = next(list.len() as u64 + 1) as usize;
            let mut want: Vec<Cand> = list[consumed..]
                .iter()
                .filter(|c| is_live(c, &contracted))
                .chain(fresh.iter())
                .copied()
                .collect();
            want.sort_by_key(|c| sort_key(c.key)); // stable: carried before fresh on ties
            merge_live(&mut list, consumed, &fresh, &contracted);
            assert_eq!(list, want, "round {round}");
        }
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

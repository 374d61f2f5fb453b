//! Stable LSD radix sort by a `u32` key (three 11-bit digits), used for the candidate lists and
//! the locality reordering; small slices fall back to a comparison sort.

/// Sort `items` stably by `key`, using `tmp` as scratch space.
pub fn sort_by_u32_key<T: Copy, F: Fn(&T) -> u32>(items: &mut Vec<T>, tmp: &mut Vec<T>, key: F) {
    if items.len() <= 256 {
        items.sort_by_key(|x| key(x));
        return;
    }
    tmp.clear();
    tmp.extend_from_slice(items);
    if radix_between(items, tmp, &key) {
        std::mem::swap(items, tmp);
    }
}

/// [`sort_by_u32_key`] with scratch for one part of `items` only (`parts` parts of equal
/// length): each part is sorted on its own and merged from the back into the sorted parts before
/// it, so the result is the same stable order. Costs about `(parts + 1) / 2` more moves of the
/// whole list than one sort; saves `(parts - 1) / parts` of its scratch (the candidate list's
/// whole-list sorts: docs/notes/qem.md, "Memory, traced over the passes").
pub fn sort_by_u32_key_in_parts<T: Copy, F: Fn(&T) -> u32>(items: &mut [T], parts: usize, key: F) {
    let n = items.len();
    let part = n.div_ceil(parts.max(1));
    let mut buf: Vec<T> = Vec::with_capacity(part);
    let mut done = 0;
    while done < n {
        let end = (done + part).min(n);
        buf.clear();
        buf.extend_from_slice(&items[done..end]);
        // The part's own slots are free now: the radix passes' other buffer.
        if radix_between(&mut buf, &mut items[done..end], &key) {
            buf.copy_from_slice(&items[done..end]);
        }
        // Merge from the back: the write position stays at or past the sorted entry being read;
        // on equal keys the earlier parts' entries come first (a stable sort).
        let (mut i, mut j) = (done, buf.len());
        while i > 0 && j > 0 {
            let (a, b) = (items[i - 1], buf[j - 1]);
            let earlier = key(&a) > key(&b);
            items[i + j - 1] = if earlier { a } else { b };
            i -= usize::from(earlier);
            j -= usize::from(!earlier);
        }
        // What is left of the part goes first (the earlier parts' rest is in place already).
        items[..j].copy_from_slice(&buf[..j]);
        done = end;
    }
}

/// Stable LSD radix sort of `a` by `key` with `b` (as long) as the other buffer; returns whether
/// the sorted items ended in `b`.
fn radix_between<T: Copy, F: Fn(&T) -> u32>(a: &mut [T], b: &mut [T], key: &F) -> bool {
    if a.len() <= 256 {
        a.sort_by_key(|x| key(x));
        return false;
    }
    let mut counts = [[0u32; 2048]; 3];
    let mut max = 0u32;
    for x in a.iter() {
        let k = key(x);
        max |= k;
        counts[0][(k & 0x7ff) as usize] += 1;
        counts[1][((k >> 11) & 0x7ff) as usize] += 1;
        counts[2][(k >> 22) as usize] += 1;
    }
    let scatter = |src: &[T], dst: &mut [T], count: &mut [u32; 2048], shift: u32| {
        for x in src {
            let d = ((key(x) >> shift) & 0x7ff) as usize;
            dst[count[d] as usize] = *x;
            count[d] += 1;
        }
    };
    let mut in_b = false;
    for (digit, count) in counts.iter_mut().enumerate() {
        let shift = 11 * digit as u32;
        // Skip digits that are zero for every key.
        if (max >> shift) & 0x7ff == 0 && digit > 0 {
            continue;
        }
        let mut sum = 0u32;
        for c in count.iter_mut() {
            let n = *c;
            *c = sum;
            sum += n;
        }
        if in_b {
            scatter(b, a, count, shift);
        } else {
            scatter(a, b, count, shift);
        }
        in_b = !in_b;
    }
    in_b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_a_stable_comparison_sort() {
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut v: Vec<(u32, u32)> = (0..5000)
            .map(|i| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                ((x >> 20) as u32 % 100_000 * (1 + (i % 3) * 4000), i)
            })
            .collect();
        let mut want = v.clone();
        want.sort_by_key(|p| p.0);
        let mut tmp = Vec::new();
        sort_by_u32_key(&mut v, &mut tmp, |p| p.0);
        assert_eq!(v, want);
    }

    #[test]
    fn sorting_in_parts_matches_a_stable_comparison_sort() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for (len, parts, keys) in [
            (0usize, 4usize, 10u64),
            (1, 4, 10),
            (300, 1, 7),
            (5000, 2, 50),
            (5000, 4, 1 << 22),
            (4999, 3, 3),
            (100_003, 4, 1 << 30),
            (100_003, 7, 400),
        ] {
            let mut v: Vec<(u32, u32)> = (0..len as u32)
                .map(|i| {
                    x ^= x << 13;
                    x ^= x >> 7;
                    x ^= x << 17;
                    ((x % keys) as u32, i)
                })
                .collect();
            let mut want = v.clone();
            want.sort_by_key(|p| p.0); // stable: equal keys keep their input order
            sort_by_u32_key_in_parts(&mut v, parts, |p| p.0);
            assert_eq!(v, want, "{len} items, {parts} parts, {keys} keys");
        }
    }
}

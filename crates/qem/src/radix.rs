//! Stable LSD radix sort by a `u32` key (three 11-bit digits), used for the candidate lists and
//! the locality reordering; small slices fall back to a comparison sort.

/// Sort `items` stably by `key`, using `tmp` as scratch space.
pub fn sort_by_u32_key<T: Copy, F: Fn(&T) -> u32>(items: &mut Vec<T>, tmp: &mut Vec<T>, key: F) {
    if items.len() <= 256 {
        items.sort_by_key(|x| key(x));
        return;
    }
    let mut counts = [[0u32; 2048]; 3];
    let mut max = 0u32;
    for x in items.iter() {
        let k = key(x);
        max |= k;
        counts[0][(k & 0x7ff) as usize] += 1;
        counts[1][((k >> 11) & 0x7ff) as usize] += 1;
        counts[2][(k >> 22) as usize] += 1;
    }
    tmp.clear();
    tmp.extend_from_slice(items);
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
        for x in items.iter() {
            let d = ((key(x) >> shift) & 0x7ff) as usize;
            tmp[count[d] as usize] = *x;
            count[d] += 1;
        }
        std::mem::swap(items, tmp);
    }
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
}

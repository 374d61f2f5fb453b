//! Non-edge vertex pairs closer than the threshold `t`, found with a uniform grid of cell size `t`
//! (Garland & Heckbert 1997, §3).

use glam::DVec3;
use std::collections::HashMap;

/// Pairs `(u, v)`, `u < v`, of used vertices with `|p_u − p_v| < t`, at most `max_per_vertex` (the
/// closest) per vertex `u`; the caller filters out pairs that are already mesh edges.
pub fn close_pairs(pos: &[DVec3], used: &[bool], t: f64, max_per_vertex: usize) -> Vec<[u32; 2]> {
    if t.is_nan() || t <= 0.0 || max_per_vertex == 0 {
        return Vec::new();
    }
    let cell_of = |p: DVec3| -> [i64; 3] {
        let c = (p / t).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    };
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (i, &p) in pos.iter().enumerate() {
        if used[i] {
            grid.entry(cell_of(p)).or_default().push(i as u32);
        }
    }
    let t2 = t * t;
    let mut pairs = Vec::new();
    let mut near: Vec<(f64, u32)> = Vec::new();
    for (u, &p) in pos.iter().enumerate() {
        if !used[u] {
            continue;
        }
        near.clear();
        let c = cell_of(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(cell) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &v in cell {
                        let d2 = pos[v as usize].distance_squared(p);
                        if v as usize != u && d2 < t2 {
                            near.push((d2, v));
                        }
                    }
                }
            }
        }
        if near.len() > max_per_vertex {
            near.select_nth_unstable_by(max_per_vertex, |x, y| x.0.total_cmp(&y.0));
            near.truncate(max_per_vertex);
        }
        for &(_, v) in &near {
            let u = u as u32;
            pairs.push(if u < v { [u, v] } else { [v, u] });
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_exactly_the_close_pairs() {
        let pos: Vec<DVec3> = (0..40)
            .map(|i| {
                DVec3::new(
                    (i % 7) as f64 * 0.3,
                    (i / 7) as f64 * 0.45,
                    (i % 3) as f64 * 0.2,
                )
            })
            .collect();
        let used = vec![true; pos.len()];
        let t = 0.5;
        let got = close_pairs(&pos, &used, t, usize::MAX);
        let mut want = Vec::new();
        for u in 0..pos.len() {
            for v in u + 1..pos.len() {
                if pos[u].distance(pos[v]) < t {
                    want.push([u as u32, v as u32]);
                }
            }
        }
        assert!(!want.is_empty());
        assert_eq!(got, want);
    }
}

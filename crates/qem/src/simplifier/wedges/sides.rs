//! Which side of a seam each face around a seam vertex lies on: a walk over the vertex's fan
//! that does not cross the seam ([`fan_sides`]), and the corners on side 1 ([`mark_side1`]),
//! the one rule of the input's corners and the output's.

use crate::simplifier::triangle::corner_after;

/// The sides of the faces `fan` around seam vertex `v` with seam neighbours `n0`, `n1`
/// (`faces(f)` gives face `f`'s corners): `reached[i]` is true for side 0, the faces reached from
/// the one holding the directed edge `v → n1` (else one holding `n1`) through edges off the seam.
/// With no such face every entry stays false. `stack` is scratch.
pub(in crate::simplifier) fn fan_sides(
    fan: &[u32],
    faces: impl Fn(u32) -> [u32; 3],
    [v, n0, n1]: [u32; 3],
    reached: &mut Vec<bool>,
    stack: &mut Vec<usize>,
) {
    reached.clear();
    reached.resize(fan.len(), false);
    let first = fan
        .iter()
        .position(|&f| corner_after(&faces(f), v) == n1)
        .or_else(|| fan.iter().position(|&f| faces(f).contains(&n1)));
    let Some(first) = first else {
        return;
    };
    reached[first] = true;
    stack.clear();
    stack.push(first);
    while let Some(i) = stack.pop() {
        for x in faces(fan[i]) {
            if x == v || x == n0 || x == n1 {
                continue;
            }
            for (j, &g) in fan.iter().enumerate() {
                if !reached[j] && faces(g).contains(&x) {
                    reached[j] = true;
                    stack.push(j);
                }
            }
        }
    }
}

/// [`fan_sides`], then `mark(face, corner)` for each corner of `v` (`vn[0]`) on side 1; none
/// when no face starts side 0 (the fan is one side). The one rule of the input's corners and
/// the output's.
pub(in crate::simplifier) fn mark_side1(
    fan: &[u32],
    faces: impl Fn(u32) -> [u32; 3],
    vn: [u32; 3],
    reached: &mut Vec<bool>,
    stack: &mut Vec<usize>,
    mut mark: impl FnMut(u32, usize),
) {
    fan_sides(fan, &faces, vn, reached, stack);
    if !reached.iter().any(|&r| r) {
        return;
    }
    for (&f, _) in fan.iter().zip(reached.iter()).filter(|&(_, &r)| !r) {
        let k = faces(f).iter().position(|&x| x == vn[0]).unwrap_or(0);
        mark(f, k);
    }
}

//! The nearest-child-first walk shared by the index's two trees (the box tree over ordinary
//! triangles and the sliver tree over long thin ones): both store a node's children at
//! `first` and `first + 1`, and a leaf's slots at `first..first + count`.

/// A tree node as the walk sees it: `count == 0` for an inner node whose children sit at
/// `first` and `first + 1`, else a leaf holding slots `first..first + count`.
pub(crate) struct Node {
    pub(crate) first: usize,
    pub(crate) count: usize,
}

/// The nearest slot closer than `best_d2` (else `best`) with its squared distance: the root
/// first, then at each inner node the nearer child, with the farther one pushed on `stack`
/// while it can still hold something closer. `node(i)` reads node `i`, `box_d2(i)` bounds the
/// squared distance to anything below it, and `slot_d2(s)` is the squared distance to slot `s`.
#[inline(always)]
pub(crate) fn nearest(
    mut best: u32,
    mut best_d2: f32,
    stack: &mut Vec<(u32, f32)>,
    node: impl Fn(usize) -> Node,
    box_d2: impl Fn(usize) -> f32,
    slot_d2: impl Fn(usize) -> f32,
) -> (u32, f32) {
    stack.clear();
    if box_d2(0) >= best_d2 {
        return (best, best_d2);
    }
    let mut current = 0usize;
    loop {
        let Node { first, count } = node(current);
        if count > 0 {
            for slot in first..first + count {
                let d2 = slot_d2(slot);
                if d2 < best_d2 {
                    best_d2 = d2;
                    best = slot as u32;
                }
            }
        } else {
            let (left, right) = (first, first + 1);
            let (dl, dr) = (box_d2(left), box_d2(right));
            let (near, dn, far, df) = if dl <= dr {
                (left, dl, right, dr)
            } else {
                (right, dr, left, dl)
            };
            if dn < best_d2 {
                if df < best_d2 {
                    stack.push((far as u32, df));
                }
                current = near;
                continue;
            }
        }
        // Pop the next subtree that can still hold something closer.
        loop {
            match stack.pop() {
                None => return (best, best_d2),
                Some((node, d2)) if d2 < best_d2 => {
                    current = node as usize;
                    break;
                }
                Some(_) => {}
            }
        }
    }
}

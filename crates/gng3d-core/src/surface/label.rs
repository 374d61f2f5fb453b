//! Nearest-node labels: a kd-tree over points and each original vertex's nearest node, on
//! several threads (the reconstruction's labels, the relaxation's cells).

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};

/// f64 kd-tree over `points` (f64 so that squared distances of 1e30-sized coordinates do not
/// overflow); `None` when empty.
pub(crate) fn kd_tree(points: &[Vec3]) -> Option<ImmutableKdTree<f64, 3>> {
    if points.is_empty() {
        return None;
    }
    let pts: Vec<[f64; 3]> = points.iter().map(|p| p.as_dvec3().to_array()).collect();
    ImmutableKdTree::<f64, 3>::new_from_slice(&pts).ok()
}

/// Index of the point of `tree` nearest to `p`.
#[inline]
pub(crate) fn nearest(tree: &ImmutableKdTree<f64, 3>, p: Vec3) -> u32 {
    tree.query(&p.as_dvec3().to_array())
        .nearest_one::<SquaredEuclidean<f64>>()
        .execute()
        .item
}

/// Below this many vertices per thread the labelling stays on one (a thread start costs more
/// than it saves).
const MIN_VERTICES_PER_LABEL_THREAD: usize = 16_384;

/// Each original vertex's nearest node (`u32::MAX` when there are no nodes), on up to
/// `threads` threads (same labels for any count).
pub(crate) fn label_with_threads(original: &[Vec3], nodes: &[Vec3], threads: usize) -> Vec<u32> {
    let Some(tree) = kd_tree(nodes) else {
        return vec![u32::MAX; original.len()];
    };
    crate::parallel::map_indexed(
        original.len(),
        threads,
        MIN_VERTICES_PER_LABEL_THREAD,
        |v| nearest(&tree, original[v]),
    )
}

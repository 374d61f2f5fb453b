//! What the QEM examples share: meshoptimizer's simplifier in the one configuration they compare
//! against (no error bound, no options).

/// meshoptimizer's view of `positions` (packed `f32` triples).
pub fn meshopt_adapter(positions: &[glam::Vec3]) -> meshopt::VertexDataAdapter<'_> {
    meshopt::VertexDataAdapter::new(meshopt::typed_to_bytes(positions), 12, 0).expect("adapter")
}

/// meshoptimizer's `simplify` of the flat index list `indices` over `adapter` down to `faces`
/// faces, with no error bound and no options; returns the kept index list.
pub fn meshopt_simplify(
    indices: &[u32],
    adapter: &meshopt::VertexDataAdapter,
    faces: usize,
) -> Vec<u32> {
    meshopt::simplify(
        indices,
        adapter,
        faces * 3,
        f32::MAX,
        meshopt::SimplifyOptions::None,
        None,
    )
}

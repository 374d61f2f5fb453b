//! Fuzz-style property tests: random bytes and mutated valid files never make a loader panic;
//! they either load or return a typed error, and whatever loads is a valid mesh.
//!
//! Seeds cover every encoding the loaders read: OBJ (also with a BOM and polygons), binary
//! little- and big-endian PLY, ASCII PLY, binary STL and ASCII STL (also with a bare `solid`
//! first line), small (< 600 bytes) and a few kB (an icosphere with 162 vertices). The
//! simplifiers' side of the property (every mutant that loads gives a loadable non-empty mesh or
//! a typed error from both QEM and GNG3D, through the CLI's code path) lives in
//! `crates/cli/tests/fuzz.rs`, so that `mesh` does not depend on the algorithm crates.
//! `long_mutation_run` (ignored) runs many more cases: `cargo test -p gng3d-mesh --release
//! --test fuzz -- --ignored`.

// Published as gng3d-mesh; this file keeps the workspace's name for it.
extern crate gng3d_mesh as mesh;

// The crate's own `fixtures` module (behind the `fixtures` feature for other crates).
#[path = "../src/fixtures.rs"]
#[allow(dead_code)]
mod fixtures;

use fixtures::fuzz::{Mutation, apply};
use mesh::AttributeKind as K;
use mesh::io::{Format, load_bytes};
use proptest::prelude::*;
use std::path::Path;

const FORMATS: [(Format, &str); 3] = [
    (Format::Obj, "obj"),
    (Format::Ply, "ply"),
    (Format::Stl, "stl"),
];

/// Number of seeds (kept in sync with `seeds()`).
const SEEDS: usize = 22;

/// The shared seeds, built once.
fn seeds() -> Vec<(Format, Vec<u8>)> {
    static SEEDS_CACHE: std::sync::OnceLock<Vec<(Format, Vec<u8>)>> = std::sync::OnceLock::new();
    SEEDS_CACHE.get_or_init(fixtures::fuzz::seeds).clone()
}

#[test]
fn every_seed_loads() {
    let seeds = seeds();
    assert_eq!(seeds.len(), SEEDS);
    for (i, (format, bytes)) in seeds.iter().enumerate() {
        let l = load_bytes(bytes, *format, Path::new("seed"))
            .unwrap_or_else(|e| panic!("seed {i} ({format:?}): {e}"));
        assert!(!l.mesh.triangles.is_empty(), "seed {i}");
    }
    // Seeds 18-21 carry attributes: UVs and normals (OBJ, PLY, GLB), colours (PLY).
    for (i, names) in [
        (18, vec![K::Normals, K::Uv0]),
        (19, vec![K::Normals, K::Uv0]),
        (20, vec![K::Normals, K::Uv0]),
        (21, vec![K::Colors]),
    ] {
        let (format, bytes) = &seeds[i];
        let l = load_bytes(bytes, *format, Path::new("seed")).unwrap();
        assert_eq!(l.attributes.expect("attributes").kinds(), names, "seed {i}");
    }
    // The big-endian seed decodes to the same mesh as the little-endian one.
    let le = load_bytes(&seeds[1].1, Format::Ply, Path::new("le.ply")).unwrap();
    let be = load_bytes(&seeds[6].1, Format::Ply, Path::new("be.ply")).unwrap();
    assert_eq!(le.mesh, be.mesh);
}

/// Checks the loader's contract on one mutant.
fn check_mutant(format: Format, bytes: &[u8]) -> Result<(), TestCaseError> {
    if let Ok(l) = load_bytes(bytes, format, Path::new("mutated")) {
        // Whatever loads must be valid: indices in range, finite positions, faces present.
        let n = l.mesh.positions.len() as u32;
        prop_assert!(l.mesh.triangles.iter().flatten().all(|&i| i < n));
        prop_assert!(l.mesh.positions.iter().all(|p| p.is_finite()));
        prop_assert!(!l.mesh.triangles.is_empty());
    }
    Ok(())
}

/// A proptest strategy over the shared [`Mutation`]s.
fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Set(i, b)),
        any::<usize>().prop_map(Mutation::Truncate),
        (
            any::<usize>(),
            prop::sample::select(fixtures::fuzz::INSERTED.to_vec())
        )
            .prop_map(|(i, b)| Mutation::Insert(i, b)),
        any::<usize>().prop_map(Mutation::Remove),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512), which in 0usize..3) {
        let (format, ext) = FORMATS[which];
        let path = format!("random.{ext}");
        let _ = load_bytes(&bytes, format, Path::new(&path));
        // Also with a valid-looking PLY header in front of the noise.
        let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
            property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
        ply.extend_from_slice(&bytes);
        let _ = load_bytes(&ply, Format::Ply, Path::new("random.ply"));
    }

    #[test]
    fn mutated_files_never_panic(which in 0usize..SEEDS, edits in prop::collection::vec(mutation(), 1..6)) {
        let (format, mut bytes) = seeds().swap_remove(which);
        for e in &edits {
            apply(&mut bytes, e);
        }
        check_mutant(format, &bytes)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200_000, ..ProptestConfig::default() })]

    /// The long variant: `cargo test -p gng3d-mesh --release --test fuzz -- --ignored`.
    #[test]
    #[ignore = "long: ~200k mutants"]
    fn long_mutation_run(which in 0usize..SEEDS, edits in prop::collection::vec(mutation(), 1..12)) {
        let (format, mut bytes) = seeds().swap_remove(which);
        for e in &edits {
            apply(&mut bytes, e);
        }
        check_mutant(format, &bytes)?;
    }
}

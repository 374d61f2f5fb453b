//! Fuzz-style property tests: random bytes and mutated valid files never make a loader panic;
//! they either load or return a typed error.

use mesh::io::{Format, load_bytes, save};
use mesh::procedural::icosphere;
use proptest::prelude::*;
use std::path::Path;

const FORMATS: [(Format, &str); 3] = [
    (Format::Obj, "obj"),
    (Format::Ply, "ply"),
    (Format::Stl, "stl"),
];

/// Valid files of every kind we read: OBJ, binary PLY, ASCII PLY, binary STL, ASCII STL.
fn seeds() -> Vec<(Format, Vec<u8>)> {
    let dir = tempfile::tempdir().unwrap();
    let m = icosphere(0);
    let mut out = Vec::new();
    for (format, ext) in FORMATS {
        let p = dir.path().join(format!("seed.{ext}"));
        save(&m, &p).unwrap();
        out.push((format, std::fs::read(&p).unwrap()));
    }
    let mut ascii_ply = String::from(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nproperty uchar red\nelement face 2\n\
         property list uchar int vertex_indices\nend_header\n",
    );
    ascii_ply.push_str("0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n3 0 1 2\n4 0 1 2 3\n");
    out.push((Format::Ply, ascii_ply.into_bytes()));
    let ascii_stl = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                     vertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
    out.push((Format::Stl, ascii_stl.as_bytes().to_vec()));
    out
}

/// One edit to a byte string.
#[derive(Debug, Clone)]
enum Mutation {
    Set(usize, u8),
    Truncate(usize),
    Insert(usize, u8),
    Remove(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Set(i, b)),
        any::<usize>().prop_map(Mutation::Truncate),
        (
            any::<usize>(),
            prop::sample::select(b"0123456789-. \nefv/".to_vec())
        )
            .prop_map(|(i, b)| Mutation::Insert(i, b)),
        any::<usize>().prop_map(Mutation::Remove),
    ]
}

fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
    if bytes.is_empty() {
        return;
    }
    let n = bytes.len();
    match *m {
        Mutation::Set(i, b) => bytes[i % n] = b,
        Mutation::Truncate(i) => bytes.truncate(i % n),
        Mutation::Insert(i, b) => bytes.insert(i % (n + 1), b),
        Mutation::Remove(i) => {
            bytes.remove(i % n);
        }
    }
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
    fn mutated_files_never_panic(which in 0usize..5, edits in prop::collection::vec(mutation(), 1..6)) {
        let (format, mut bytes) = seeds().swap_remove(which);
        for e in &edits {
            apply(&mut bytes, e);
        }
        if let Ok(l) = load_bytes(&bytes, format, Path::new("mutated")) {
            // Whatever loads must be valid: indices in range, finite positions, faces present.
            let n = l.mesh.positions.len() as u32;
            prop_assert!(l.mesh.triangles.iter().flatten().all(|&i| i < n));
            prop_assert!(l.mesh.positions.iter().all(|p| p.is_finite()));
            prop_assert!(!l.mesh.triangles.is_empty());
        }
    }
}

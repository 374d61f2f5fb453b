//! Independent oracles for the hand-written readers: tobj for OBJ and ply-rs-bw for PLY.
//!
//! OBJ: tobj renumbers vertices by first use, so both readers' triangles are compared as
//! position triples (corner order kept, list sorted, bit-exact), and the number of vertices
//! tobj keeps is compared with the number of vertex records our reader sees referenced.
//! PLY: no renumbering, so positions and fan-triangulated faces must be identical.
//! Shared meshes come from `GNG3D_MESHES` (skipped without it, failing when `CI` is set).

use super::{RawMesh, obj, ply};
use crate::topology::analyze;
use glam::Vec3;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{Property, PropertyAccess, PropertyAccessResult};
use rand::{Rng, SeedableRng};
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Shared mesh files with extension `ext`, sorted by name.
fn shared_files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("readable meshes folder")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    files
}

/// Each triangle as the bit patterns of its three corner positions (corner order kept), sorted.
fn position_triangles(raw: &RawMesh) -> Vec<[[u32; 3]; 3]> {
    let bits = |i: u32| raw.positions[i as usize].to_array().map(f32::to_bits);
    let mut out: Vec<[[u32; 3]; 3]> = raw.triangles.iter().map(|t| t.map(bits)).collect();
    out.sort_unstable();
    out
}

/// Number of distinct vertex records used by at least one triangle.
fn referenced_records(raw: &RawMesh) -> usize {
    raw.triangles
        .iter()
        .flatten()
        .collect::<BTreeSet<_>>()
        .len()
}

/// Parse `text` with both OBJ readers and check they agree; returns (ours, tobj's).
fn check_obj_against_tobj(bytes: &[u8], path: &Path) -> (RawMesh, RawMesh) {
    let ours = obj::parse(bytes, path, glam::DVec3::ZERO).expect("our OBJ reader");
    let oracle = obj::parse_with_tobj(bytes, path).expect("tobj");
    assert_eq!(
        ours.triangles.len(),
        oracle.triangles.len(),
        "{}: triangle count",
        path.display()
    );
    assert!(
        position_triangles(&ours) == position_triangles(&oracle),
        "{}: the two readers give different triangles",
        path.display()
    );
    (ours, oracle)
}

#[test]
fn obj_reader_matches_tobj_on_shared_meshes() {
    let Some(dir) = crate::fixtures::shared_meshes_dir("README.md") else {
        return;
    };
    let files = shared_files(&dir, "obj");
    assert!(
        files.len() >= 10,
        "expected the shared OBJ files in {dir:?}"
    );
    for path in files {
        let bytes = std::fs::read(&path).expect("readable mesh");
        let (ours, oracle) = check_obj_against_tobj(&bytes, &path);
        // tobj keeps exactly the referenced records (single object per shared file).
        assert_eq!(
            referenced_records(&ours),
            oracle.positions.len(),
            "{}: referenced vertex count",
            path.display()
        );
        // The public tobj-based loader agrees with `load` after validation as well.
        let ours = super::load(&path).expect("load");
        let theirs = super::load_obj_with_tobj(&path).expect("load_obj_with_tobj");
        let (a, b) = (analyze(&ours.mesh), analyze(&theirs.mesh));
        assert_eq!(
            (a.faces, a.referenced_vertices, a.edges, a.boundary_edges),
            (b.faces, b.vertices, b.edges, b.boundary_edges),
            "{}",
            path.display()
        );
        assert_eq!(ours.warnings, theirs.warnings, "{}", path.display());
    }
}

#[test]
fn obj_reader_matches_tobj_on_handwritten_cases() {
    let text = "# polygons, v/vt/vn, negative indices, unreferenced records\n\
        mtllib missing.mtl\n\
        v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 9 9 9\nv 0.5 1.5 0\n\
        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
        vn 0 0 1\n\
        o first\n\
        usemtl none\ns off\n\
        f 1/1/1 2/2/1 3/3/1 4/4/1\n\
        f -3//1 -1//1 -4//1\n\
        f 2/1 3/2 6/3 4/4 1/1\n\
        v -1 -1 -1\n\
        f -1 1 2\n";
    let path = Path::new("handwritten.obj");
    let (ours, oracle) = check_obj_against_tobj(text.as_bytes(), path);
    // Quad → 2, triangle → 1, pentagon → 3, triangle → 1.
    assert_eq!(ours.triangles.len(), 7);
    assert_eq!(ours.polygons, 2);
    // Record 5 (9 9 9) is never referenced: we keep it, tobj drops it.
    assert_eq!(ours.positions.len(), 7);
    assert_eq!(referenced_records(&ours), 6);
    assert_eq!(oracle.positions.len(), 6);
}

#[test]
fn tobj_counts_a_vertex_once_per_group() {
    // Two groups sharing vertex 2 and 3: same triangles, but tobj numbers per group.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng a\nf 1 2 3\ng b\nf 1 3 4\n";
    let (ours, oracle) = check_obj_against_tobj(text.as_bytes(), Path::new("groups.obj"));
    assert_eq!(referenced_records(&ours), 4);
    assert_eq!(oracle.positions.len(), 6);
}

/// A random OBJ: vertex records interleaved with faces of 3 to 6 distinct, already defined
/// corners written in all four corner forms, with positive or negative indices.
fn random_obj(seed: u64) -> String {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let mut text = String::new();
    let mut defined = 0usize;
    for _ in 0..rng.random_range(1..12) {
        for _ in 0..rng.random_range(3..10) {
            let p: [f32; 3] = std::array::from_fn(|_| rng.random_range(-10.0..10.0));
            let _ = writeln!(text, "v {} {} {}", p[0], p[1], p[2]);
            let _ = writeln!(text, "vt {} {}\nvn 0 0 1", p[0], p[1]);
            defined += 1;
        }
        for _ in 0..rng.random_range(0..8) {
            let corners = rng.random_range(3..=6.min(defined));
            let mut used = BTreeSet::new();
            text.push('f');
            while used.len() < corners {
                let index = rng.random_range(1..=defined);
                if !used.insert(index) {
                    continue;
                }
                let written = if rng.random_bool(0.3) {
                    index as i64 - defined as i64 - 1
                } else {
                    index as i64
                };
                let _ = match rng.random_range(0..4) {
                    0 => write!(text, " {written}"),
                    1 => write!(text, " {written}/{written}"),
                    2 => write!(text, " {written}//{written}"),
                    _ => write!(text, " {written}/{written}/{written}"),
                };
            }
            text.push('\n');
        }
    }
    text
}

#[test]
fn obj_reader_matches_tobj_on_random_files() {
    for seed in 0..100 {
        let text = random_obj(seed);
        let (ours, oracle) = check_obj_against_tobj(text.as_bytes(), Path::new("random.obj"));
        assert_eq!(
            referenced_records(&ours),
            oracle.positions.len(),
            "seed {seed}"
        );
    }
}

/// One PLY element as ply-rs-bw reads it: `x y z` as f64 and the face index list.
#[derive(Debug, Default)]
struct OracleElement {
    position: [f64; 3],
    indices: Vec<i64>,
}

impl PropertyAccess for OracleElement {
    fn new() -> Self {
        OracleElement::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            "vertex_indices" | "vertex_index" => {
                self.indices = match property {
                    Property::ListChar(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListUChar(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListShort(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListUShort(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListInt(v) => v.into_iter().map(i64::from).collect(),
                    Property::ListUInt(v) => v.into_iter().map(i64::from).collect(),
                    _ => return PropertyAccessResult::UnsupportedType,
                };
                return PropertyAccessResult::Set;
            }
            _ => return PropertyAccessResult::Ignored,
        };
        self.position[axis] = match property {
            Property::Float(v) => f64::from(v),
            Property::Double(v) => v,
            other => match other.to_f32_lossy() {
                Some(v) => f64::from(v),
                None => return PropertyAccessResult::UnsupportedType,
            },
        };
        PropertyAccessResult::Set
    }
}

/// Read a PLY file with ply-rs-bw into positions (rounded to f32 like our reader) and
/// fan-triangulated faces.
fn read_with_ply_rs(path: &Path) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let file = std::fs::File::open(path).expect("readable mesh");
    let ply = Parser::<OracleElement>::new()
        .read_ply(&mut std::io::BufReader::new(file))
        .unwrap_or_else(|e| panic!("ply-rs-bw cannot read {}: {e}", path.display()));
    let positions = ply.payload["vertex"]
        .iter()
        .map(|v| Vec3::from_array(v.position.map(|c| c as f32)))
        .collect();
    let mut triangles = Vec::new();
    for face in &ply.payload["face"] {
        let i = &face.indices;
        for k in 1..i.len().saturating_sub(1) {
            triangles.push([i[0], i[k], i[k + 1]].map(|x| u32::try_from(x).expect("index")));
        }
    }
    (positions, triangles)
}

#[test]
fn ply_reader_matches_ply_rs_on_shared_meshes() {
    let Some(dir) = crate::fixtures::shared_meshes_dir("README.md") else {
        return;
    };
    for name in [
        "many_small_holes.ply",
        "horse.ply",
        "igea.ply",
        "igea-1m.ply",
    ] {
        let path = dir.join(name);
        let bytes = std::fs::read(&path).expect("readable mesh");
        let ours = ply::parse(&bytes, &path, glam::DVec3::ZERO).expect("our PLY reader");
        let (positions, triangles) = read_with_ply_rs(&path);
        assert_eq!(ours.positions.len(), positions.len(), "{name}: vertices");
        assert_eq!(ours.triangles.len(), triangles.len(), "{name}: triangles");
        assert!(ours.positions == positions, "{name}: positions differ");
        assert!(ours.triangles == triangles, "{name}: triangles differ");
    }
}

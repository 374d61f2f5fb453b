//! STL input of the partitioned simplification: welded per cell by the loader's rule, so a
//! closed mesh stays closed; bad STL files refused with an error naming them.

use mesh::TriMesh;
use partition::{PartitionParams, generate, simplify};
use qem::Target;
use std::path::Path;

fn params(target: Target, work: &Path) -> PartitionParams {
    PartitionParams {
        memory_budget: 1 << 20, // 5,242 faces a cell: a few cells
        threads: 2,
        ..PartitionParams::new(target, work.to_path_buf())
    }
}

fn load(path: &Path) -> TriMesh {
    mesh::io::load(path).unwrap().mesh
}

/// The mesh as ASCII STL, written by hand (an independent path from the project's writer).
fn ascii_stl(m: &TriMesh) -> String {
    let mut text = String::from("solid sphere\n");
    for f in 0..m.face_count() {
        text += "  facet normal 0 0 0\n    outer loop\n";
        for p in m.triangle(f) {
            text += &format!("      vertex {:?} {:?} {:?}\n", p.x, p.y, p.z);
        }
        text += "    endloop\n  endfacet\n";
    }
    text + "endsolid sphere\n"
}

#[test]
fn a_closed_stl_gives_a_closed_manifold_output_with_the_exact_count() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("in.ply");
    generate::write_displaced_sphere(&ply, 40_000, 5).unwrap();
    let m = load(&ply);
    let binary = dir.path().join("in.stl");
    mesh::io::save(&mesh::Model::from(m.clone()), &binary).unwrap();
    let ascii = dir.path().join("ascii.stl");
    std::fs::write(&ascii, ascii_stl(&m)).unwrap();
    let info = partition::inspect(&binary).unwrap();
    assert_eq!((info.vertices, info.faces), (None, m.face_count() as u64));
    assert_eq!(
        partition::inspect(&ascii).unwrap().faces,
        m.face_count() as u64
    );
    let mut outputs = Vec::new();
    for (input, name) in [(&binary, "b.ply"), (&ascii, "a.ply")] {
        let out = dir.path().join(name);
        let work = dir.path().join(name).with_extension("work");
        let report = simplify(input, &out, &params(Target::Faces(4_000), &work)).unwrap();
        assert!(report.cells >= 4, "{report:?}");
        // Welded as the loader welds: every vertex once, shared across the cells.
        assert_eq!(report.input_vertices, m.vertex_count());
        assert_eq!(report.input_faces, m.face_count());
        assert!(report.shared_vertices > 0);
        let coarse = load(&out);
        assert_eq!(coarse.face_count(), 4_000);
        assert_eq!(coarse.vertex_count(), 2_002); // closed genus 0: V = F/2 + 2
        let topo = mesh::topology::analyze(&coarse);
        assert!(topo.closed && topo.manifold, "{topo:?}");
        assert_eq!(topo.genus, Some(0));
        let mut keys: Vec<_> = coarse
            .positions
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        assert_eq!(keys.len(), coarse.vertex_count(), "duplicated vertices");
        outputs.push(std::fs::read(&out).unwrap());
    }
    // Binary and ASCII: the same triangles, the same output.
    assert_eq!(outputs[0], outputs[1]);
}

#[test]
fn a_truncated_or_lying_stl_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("in.ply");
    generate::write_displaced_sphere(&ply, 2_000, 5).unwrap();
    let m = load(&ply);
    let good = dir.path().join("good.stl");
    mesh::io::save(&mesh::Model::from(m.clone()), &good).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let out = dir.path().join("out.ply");
    let p = params(Target::Ratio(0.5), &dir.path().join("work"));
    let refused = |name: &str, content: &[u8], what: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, content).unwrap();
        let e = simplify(&path, &out, &p).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(what), "{e}");
        assert!(!out.exists());
    };
    // Cut inside the last record: the header's count is more than the file holds.
    refused("short.stl", &bytes[..bytes.len() - 7], "triangles");
    // A header claiming more triangles than there are.
    let mut lying = bytes.clone();
    let count = u32::from_le_bytes(lying[80..84].try_into().unwrap());
    lying[80..84].copy_from_slice(&(count + 1000).to_le_bytes());
    refused("lying.stl", &lying, "triangles");
    refused("tiny.stl", b"solid x\n", "too short");
    // ASCII cut inside a facet.
    let text = ascii_stl(&m);
    refused(
        "cut.stl",
        &text.as_bytes()[..text.len() / 2],
        "ascii stl data",
    );
    refused(
        "words.stl",
        b"solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 zero 0\n",
        "ascii stl data",
    );
}

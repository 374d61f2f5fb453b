//! Symmetric Hausdorff (metrics crate) of QEM's result and of a reference simplification:
//! `cargo run --release --example qem_quality -- ORIGINAL FACES [REFERENCE|""] [SAMPLES]`
//! (also shows meshoptimizer's result at the same face count).

// meshoptimizer as the QEM crate's examples call it (one configuration for every comparison).
#[path = "../crates/qem/examples/common/mod.rs"]
mod common;

use common::{meshopt_adapter, meshopt_simplify};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let load = |p: &str| mesh::io::load(std::path::Path::new(p)).expect("load").mesh;
    let original = mesh::clean::prepare(&load(&args[1]).into()).0.mesh;
    let faces: usize = args[2].parse().expect("faces");
    let samples = args
        .get(4)
        .map_or(1_000_000, |s| s.parse().expect("samples"));
    let hp = metrics::HausdorffParams::with_samples(samples);
    let show = |name: &str, m: &mesh::TriMesh| {
        let h = metrics::hausdorff(&original, m, &hp).expect("hausdorff");
        println!(
            "{name}: {} faces  fwd max {:.6e} mean {:.6e} | bwd max {:.6e} mean {:.6e} | sym max {:.6e} mean {:.6e}",
            m.face_count(),
            h.forward.max,
            h.forward.mean,
            h.backward.max,
            h.backward.mean,
            h.max,
            h.mean
        );
    };
    let params = qem::QemParams::with_target(qem::Target::Faces(faces));
    let (q, report) = qem::simplify(&mesh::Model::from(original.clone()), &params).expect("qem");
    let q = q.mesh;
    println!("{report:?}");
    show("qem", &q);
    // meshoptimizer at the same target, for context (vertices unreferenced by its output dropped).
    let indices: Vec<u32> = original.triangles.iter().flatten().copied().collect();
    let out = meshopt_simplify(&indices, &meshopt_adapter(&original.positions), faces);
    let tris: Vec<[u32; 3]> = out.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mo =
        mesh::clean::remove_unreferenced(&mesh::TriMesh::new(original.positions.clone(), tris));
    show("meshopt", &mo);
    if let Some(r) = args.get(3).filter(|s| !s.is_empty()) {
        show("reference", &load(r));
    }
}

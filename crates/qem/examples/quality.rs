//! Symmetric Hausdorff (metrics crate) of QEM's result and of a reference simplification:
//! `cargo run --release -p qem --example quality -- ORIGINAL FACES [REFERENCE]`.

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let load = |p: &str| mesh::io::load(std::path::Path::new(p)).expect("load").mesh;
    let original = mesh::clean::prepare(&load(&args[1])).0;
    let faces: usize = args[2].parse().expect("faces");
    let samples = args.get(4).map_or(1_000_000, |s| s.parse().expect("samples"));
    let hp = metrics::HausdorffParams::with_samples(samples);
    let show = |name: &str, m: &mesh::TriMesh| {
        let h = metrics::hausdorff(&original, m, &hp).expect("hausdorff");
        println!(
            "{name}: {} faces  fwd max {:.6e} mean {:.6e} | bwd max {:.6e} mean {:.6e} | sym max {:.6e} mean {:.6e}",
            m.face_count(), h.forward.max, h.forward.mean, h.backward.max, h.backward.mean, h.max, h.mean
        );
    };
    let mut params = qem::QemParams::with_target(qem::Target::Faces(faces));
    if let Some(c) = std::env::var("MINCOS").ok().and_then(|s| s.parse().ok()) { params.min_normal_cos = c; }
    let (q, report) = qem::simplify(&original, &params).expect("qem");
    println!("{report:?}");
    show("qem", &q);
    if let Some(r) = args.get(3).filter(|s| !s.is_empty()) {
        show("reference", &load(r));
    }
}

fn main() {
    for a in std::env::args().skip(1) {
        let t = std::time::Instant::now();
        let l = mesh::io::load(std::path::Path::new(&a)).unwrap();
        let lt = t.elapsed().as_secs_f64();
        let r = mesh::topology::analyze(&l.mesh);
        println!("{a} load {lt:.3}s total {:.3}s {:?} warn {:?} diag {}", t.elapsed().as_secs_f64(), r, l.warnings, l.mesh.bbox_diagonal());
    }
}

//! Hostile inputs against ordinary ones of the same size (issue 33's cliffs): each group times
//! GNG3D on an input that once took minutes next to a mesh of the same face count that never
//! did, so the ratio of the two is the figure to quote.
//!
//! - `fan_capped_cylinder`: GNG3D-Q (the defaults) at 50 % of the vertices of a closed cylinder
//!   of 16,384 segments with a fan cap at each end (65,536 faces, two vertices of valence
//!   16,384; 137 s before the fan trees), against a torus of 65,536 faces.
//! - `many_pieces`: the paper's GNG3D (`GngParams::paper`'s placement, no oversampling) with 3
//!   vertices on 300,000 disjoint triangles (28 s before the pieces' prefix sums), against an
//!   icosphere of 327,680 faces.
//!
//! Inputs are generated here. `cargo bench -p gng3d-core --bench cliffs`

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use gng3d_core::{GngOptions, GngTarget, ReconstructionParams, simplify};
use mesh::TriMesh;
use std::time::Duration;

/// `n` disjoint triangles on a grid, each its own piece.
fn disjoint_triangles(n: u32) -> TriMesh {
    let side = (n as f64).sqrt().ceil() as u32;
    let mut positions = Vec::with_capacity(3 * n as usize);
    let mut triangles = Vec::with_capacity(n as usize);
    for i in 0..n {
        let (x, y) = ((i % side) as f32, (i / side) as f32);
        let base = positions.len() as u32;
        positions.push(Vec3::new(x, y, 0.0));
        positions.push(Vec3::new(x + 0.5, y, 0.1));
        positions.push(Vec3::new(x, y + 0.5, 0.2));
        triangles.push([base, base + 1, base + 2]);
    }
    TriMesh::new(positions, triangles)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("fan_capped_cylinder");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(100));
    group.measurement_time(Duration::from_secs(30));
    let options = GngOptions {
        seed: 1,
        ..GngOptions::for_target(GngTarget::VertexRatio(0.5))
    };
    for (name, input) in [
        (
            "cylinder_16384_segments",
            mesh::procedural::fan_capped_cylinder(16_384),
        ),
        (
            "torus_65536_faces",
            mesh::procedural::torus(1.0, 0.3, 256, 128),
        ),
    ] {
        assert_eq!(input.face_count(), 65_536);
        let input = mesh::clean::prepare(&input.into()).0;
        group.bench_function(name, |b| b.iter(|| simplify(&input, &options).unwrap()));
    }
    group.finish();

    let mut group = c.benchmark_group("many_pieces");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(100));
    group.measurement_time(Duration::from_secs(20));
    let options = GngOptions {
        seed: 1,
        reconstruction: ReconstructionParams::paper(),
        ..GngOptions::for_target(GngTarget::Vertices(3))
    };
    for (name, input) in [
        ("disjoint_triangles_300000", disjoint_triangles(300_000)),
        ("icosphere_327680_faces", mesh::procedural::icosphere(7)),
    ] {
        let input = mesh::clean::prepare(&input.into()).0;
        group.bench_function(name, |b| b.iter(|| simplify(&input, &options).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

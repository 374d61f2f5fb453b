//! Write a synthetic fragmented texture atlas ([`gng3d_mesh::procedural::fragmented_atlas`]) as
//! an OBJ with per-corner UVs, for measuring simplifiers on many small charts (issue 48):
//!
//! ```text
//! cargo run --release -p gng3d-mesh --example atlas -- gargoyle-10k.obj 190 1 /tmp/atlas.obj
//! cargo run --release -p gng3d-mesh --example atlas -- icosphere:5 200 1 /tmp/sphere-atlas.obj
//! ```
//!
//! The input is a mesh file or `icosphere:S` (S subdivisions); then the number of charts, the
//! seed, and the output file.

use gng3d_mesh::procedural::{fragmented_atlas, icosphere};
use std::path::Path;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, charts, seed, out] = args.as_slice() else {
        eprintln!("usage: atlas IN|icosphere:S CHARTS SEED OUT.obj");
        return ExitCode::FAILURE;
    };
    let (Ok(charts), Ok(seed)) = (charts.parse::<usize>(), seed.parse::<u64>()) else {
        eprintln!("CHARTS and SEED must be whole numbers");
        return ExitCode::FAILURE;
    };
    let mesh = match input.strip_prefix("icosphere:").map(str::parse::<u32>) {
        Some(Ok(s)) => icosphere(s.min(8)),
        Some(Err(e)) => {
            eprintln!("{input}: {e}");
            return ExitCode::FAILURE;
        }
        None => match gng3d_mesh::io::load(Path::new(input)) {
            Ok(loaded) => loaded.mesh,
            Err(e) => {
                eprintln!("{input}: {e}");
                return ExitCode::FAILURE;
            }
        },
    };
    let (attributes, made) = fragmented_atlas(&mesh, charts, seed);
    if let Err(e) = gng3d_mesh::io::save(
        &gng3d_mesh::Model::new(mesh.clone(), Some(attributes.clone()), None),
        Path::new(out),
    ) {
        eprintln!("{out}: {e}");
        return ExitCode::FAILURE;
    }
    println!(
        "{input}: {} vertices, {} faces, {made} charts, {} wedges, {} seam edges -> {out}",
        mesh.vertex_count(),
        mesh.face_count(),
        attributes.wedge_count(),
        attributes.seam_edges(&mesh).len()
    );
    ExitCode::SUCCESS
}

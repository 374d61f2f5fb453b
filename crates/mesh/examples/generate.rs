//! Write a procedural model to a mesh file, for timing the command-line tool on inputs that are
//! not in the shared set (issue 33's hostile inputs):
//!
//! ```text
//! cargo run --release -p gng3d-mesh --example generate -- fan 1000000 fan-1m.ply
//! cargo run --release -p gng3d-mesh --example generate -- fan-capped-cylinder 16384 cyl.ply
//! cargo run --release -p gng3d-mesh --example generate -- icosphere 7 sphere.ply
//! cargo run --release -p gng3d-mesh --example generate -- grid 707 grid.ply
//! ```
//!
//! `fan N`: N triangles around one hub ([`gng3d_mesh::procedural::fan`]);
//! `fan-capped-cylinder N`: a closed cylinder of N segments with a fan cap at each end (4N
//! faces); `icosphere S`: S subdivisions (20 · 4^S faces); `grid N`: the unit square as N × N
//! squares (2N² faces).

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [kind, size, out] = args.as_slice() else {
        eprintln!("usage: generate fan|fan-capped-cylinder|icosphere|grid SIZE OUT.(ply|obj|stl)");
        return ExitCode::FAILURE;
    };
    let Ok(size) = size.parse::<u32>() else {
        eprintln!("SIZE must be a whole number, got {size}");
        return ExitCode::FAILURE;
    };
    let m = match kind.as_str() {
        "fan" => gng3d_mesh::procedural::fan(size),
        "fan-capped-cylinder" => gng3d_mesh::procedural::fan_capped_cylinder(size),
        "icosphere" => gng3d_mesh::procedural::icosphere(size.min(9)),
        "grid" => gng3d_mesh::procedural::unit_square_grid(size),
        _ => {
            eprintln!("unknown model {kind}");
            return ExitCode::FAILURE;
        }
    };
    if let Err(e) = gng3d_mesh::io::save(&m.clone().into(), std::path::Path::new(out)) {
        eprintln!("{out}: {e}");
        return ExitCode::FAILURE;
    }
    println!(
        "{kind} {size}: {} vertices, {} faces -> {out}",
        m.vertex_count(),
        m.face_count()
    );
    ExitCode::SUCCESS
}

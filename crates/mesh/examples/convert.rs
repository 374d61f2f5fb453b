//! Convert a mesh file with its attributes and materials (e.g. OBJ to glTF), timing the load
//! and the save, and reading the output back:
//!
//! ```text
//! cargo run --release -p gng3d-mesh --example convert -- $GNG3D_MESHES/spot.obj spot.glb
//! ```
//!
//! Prints one line per step: counts (vertices, faces, wedges, attributes) and seconds.

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

fn describe(l: &gng3d_mesh::io::LoadedMesh) -> String {
    let a = l.attributes.as_ref();
    format!(
        "{} vertices, {} faces, {} wedges, attributes [{}], {} materials, {} warnings",
        l.mesh.vertex_count(),
        l.mesh.face_count(),
        a.map_or(0, |a| a.wedge_count()),
        a.map_or_else(String::new, |a| gng3d_mesh::AttributeKind::list(&a.kinds())),
        l.materials.as_ref().map_or(0, |m| m.names.len()),
        l.warnings.len()
    )
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: convert INPUT OUTPUT");
        return ExitCode::FAILURE;
    };
    let run = || -> Result<(), gng3d_mesh::error::MeshError> {
        let t = Instant::now();
        let l = gng3d_mesh::io::load(Path::new(input))?;
        println!(
            "load {input}: {} ({:.4} s)",
            describe(&l),
            t.elapsed().as_secs_f64()
        );
        let attributes = l
            .attributes
            .clone()
            .unwrap_or_else(|| gng3d_mesh::attributes::Attributes::per_vertex(&l.mesh));
        let t = Instant::now();
        let warnings = gng3d_mesh::io::save(
            &gng3d_mesh::Model::new(
                l.mesh.clone(),
                Some(attributes.clone()),
                l.materials.clone(),
            ),
            Path::new(output),
        )?
        .dropped;
        println!(
            "save {output}: {} warnings ({:.4} s)",
            warnings.len(),
            t.elapsed().as_secs_f64()
        );
        for w in &warnings {
            println!("  warning: {w}");
        }
        let t = Instant::now();
        let back = gng3d_mesh::io::load(Path::new(output))?;
        println!(
            "load {output}: {} ({:.4} s)",
            describe(&back),
            t.elapsed().as_secs_f64()
        );
        for w in &back.warnings {
            println!("  warning: {w}");
        }
        Ok(())
    };
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}

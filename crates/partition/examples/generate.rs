//! Write a displaced sphere of about FACES faces as binary PLY (streaming; any size):
//! `cargo run --release -p gng3d-partition --example generate -- FACES OUT.ply [SEED]`.

use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: generate FACES OUT.ply [SEED]";
    let faces: usize = args.first().ok_or(usage)?.replace('_', "").parse()?;
    let out = PathBuf::from(args.get(1).ok_or(usage)?);
    let seed: u64 = args.get(2).map_or(Ok(1), |s| s.parse())?;
    let grid = partition::generate::write_displaced_sphere(&out, faces, seed)?;
    println!(
        "{}: {} vertices, {} faces (rows {}, cols {})",
        out.display(),
        grid.vertices(),
        grid.faces(),
        grid.rows,
        grid.cols
    );
    Ok(())
}

//! Measurement driver (docs/notes/partition.md): run under `/usr/bin/time -v` for peak RSS.
//!
//! - `measure partition IN OUT TARGET BUDGET_MB THREADS WORK`: the partitioned run;
//! - `measure whole IN OUT TARGET`: load the whole mesh, `qem::simplify`, save;
//! - `measure split IN BUDGET_MB WORK`: the streaming partition alone;
//! - `measure load IN`: load the whole mesh only;
//! - `measure distance ORIGINAL A`: symmetric Hausdorff max / mean of A against ORIGINAL
//!   (1M samples), in % of ORIGINAL's bounding-box diagonal.
//!
//! TARGET: a ratio (`0.01`) or a face count (`10000f`).

use qem::Target;
use std::path::PathBuf;
use std::time::Instant;

fn target(s: &str) -> Target {
    match s.strip_suffix('f') {
        Some(f) => Target::Faces(f.parse().expect("face count")),
        None => Target::Ratio(s.parse().expect("ratio")),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let p = |i: usize| PathBuf::from(&a[i]);
    let start = Instant::now();
    match a[0].as_str() {
        "partition" => {
            let params = partition::PartitionParams {
                memory_budget: a[4].parse::<u64>()? << 20,
                threads: a[5].parse()?,
                ..partition::PartitionParams::new(target(&a[3]), p(6))
            };
            let r = partition::simplify(&p(1), &p(2), &params)?;
            println!("{r:?}");
        }
        "whole" => {
            let m = mesh::io::load(&p(1))?.mesh;
            let (out, _) = qem::simplify(
                &mesh::Model::from(m),
                &qem::QemParams::with_target(target(&a[3])),
            )?;
            println!("{} faces", out.mesh.face_count());
            mesh::io::save(&out, &p(2))?;
        }
        "split" => {
            let m = partition::partition(&p(1), &p(3), a[2].parse::<u64>()? << 20)?;
            println!(
                "{} cells with faces, {} shared vertices",
                m.cell_faces.iter().filter(|&&c| c > 0).count(),
                m.shared
            );
        }
        "load" => {
            let m = mesh::io::load(&p(1))?.mesh;
            println!("{} faces", m.face_count());
        }
        "distance" => {
            let original = mesh::io::load(&p(1))?.mesh;
            let other = mesh::io::load(&p(2))?.mesh;
            let h = metrics::hausdorff(
                &original,
                &other,
                &metrics::HausdorffParams::with_samples(1_000_000),
            )?;
            let d = original.bbox_diagonal() / 100.0;
            println!(
                "faces {} hausdorff {:.4} % mean {:.5} %",
                other.face_count(),
                h.max / d,
                h.mean / d
            );
        }
        other => return Err(format!("unknown mode {other}").into()),
    }
    eprintln!("seconds {:.3}", start.elapsed().as_secs_f64());
    Ok(())
}

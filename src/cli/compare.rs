//! `gng3d compare`: QEM and GNG3D to the same vertex count, all metrics, an aligned table.

use super::load_prepared;
use anyhow::Context;
use clap::Args;
use gng3d::experiment::compare::{CompareParams, compare, comparison_table};
use std::path::PathBuf;

/// Arguments of `gng3d compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Input mesh (.obj, .ply, .stl).
    pub input: PathBuf,
    /// Vertex count both methods aim for.
    #[arg(long)]
    pub vertices: usize,
    /// Folder for compare.json, qem.obj and gng.obj (created if missing).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Surface samples per direction for the Hausdorff distance (default: 10 × faces).
    #[arg(long)]
    pub samples: Option<usize>,
    /// Random seed for GNG3D and the surface sampler.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// GNG3D maximum training time in seconds.
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// Print the JSON report instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Run `gng3d compare`.
pub fn run(args: CompareArgs) -> anyhow::Result<()> {
    let original = load_prepared(&args.input, false)?;
    let mut params = CompareParams::new(args.vertices);
    params.gng.seed = args.seed;
    params.gng.time_limit = args.time_limit.map(std::time::Duration::from_secs_f64);
    params.metrics.hausdorff.seed = args.seed;
    params.metrics.hausdorff.samples = args.samples;
    let result = compare(&original, &params)
        .with_context(|| format!("comparing on {}", args.input.display()))?;
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let json = dir.join("compare.json");
        super::write_atomic(
            &json,
            serde_json::to_string_pretty(&result.report)?.as_bytes(),
        )?;
        mesh::io::save(&result.qem_mesh, &dir.join("qem.obj"))?;
        mesh::io::save(&result.gng_mesh, &dir.join("gng.obj"))?;
    }
    if args.json {
        super::print_json(&result.report)
    } else {
        println!(
            "{}: {} vertices, {} faces -> {} vertices",
            args.input.display(),
            result.report.original_vertices,
            result.report.original_faces,
            result.report.target_vertices
        );
        print!("{}", comparison_table(&result.report).to_text());
        Ok(())
    }
}

//! `gng3d simplify`: reduce a mesh with QEM or GNG3D and write the result atomically.

mod attributes;
mod gng;
mod qem;

use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// Simplification method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Garland–Heckbert quadric error metrics (pair contraction).
    Qem,
    /// GNG3D: Growing Neural Gas training plus reconstruction.
    Gng,
}

/// Arguments of `gng3d simplify`.
#[derive(Debug, Args)]
pub struct SimplifyArgs {
    /// Input mesh (.obj, .ply, .stl, .gltf, .glb).
    pub input: PathBuf,
    /// Output mesh (.obj, .ply, .stl, .gltf with its .bin beside it, .glb); written to a temporary
    /// file, then renamed, after the output was read back (nothing is written when it does not
    /// load back with what the format stores).
    pub output: PathBuf,
    /// Simplification method.
    #[arg(long, value_enum, default_value_t = Method::Qem)]
    pub method: Method,
    /// Target vertex count.
    #[arg(long, group = "target")]
    pub vertices: Option<usize>,
    /// Target face count (QEM only).
    #[arg(long, group = "target")]
    pub faces: Option<usize>,
    /// Target as a share of the input's vertices, in (0, 1], for every method: 0.1 gives the
    /// same vertex count with --method gng and --method qem (rounded to the nearest count).
    #[arg(long, group = "target")]
    pub ratio: Option<f64>,
    /// Target as a share of the input's faces, in (0, 1] (QEM only).
    #[arg(long, group = "target")]
    pub face_ratio: Option<f64>,
    /// QEM: a chain of levels of detail in one run, each a share of the input's vertices
    /// (decreasing, in (0, 1]), each simplified from the one before: OUT's name with `-lod1`,
    /// `-lod2`, ... (e.g. `--lods 0.5,0.25,0.1` writes out-lod1.ply, out-lod2.ply, out-lod3.ply).
    #[arg(long, group = "target", value_delimiter = ',')]
    pub lods: Option<Vec<f64>>,
    /// QEM pair distance threshold t in model units (0: edges only): also contract each vertex
    /// with its 8 closest vertices within t. At most the mesh's bounding-box diagonal (larger
    /// values are refused, naming the limit).
    #[arg(long, default_value_t = 0.0)]
    pub threshold: f64,
    /// QEM: never contract the vertices on the input's border edges (edges with one face), so
    /// the border keeps every vertex where it was: meshes that meet along their borders (tiles,
    /// parts of an assembly) still meet after simplification.
    #[arg(long)]
    pub lock_border: bool,
    /// QEM stop rule as a distance, a share of the input's bounding-box diagonal (e.g. 0.001):
    /// no contraction whose error exceeds it (the area-weighted RMS distance of the merged vertex
    /// to the planes of the original faces around it, plus the weighted attribute error with
    /// attributes). With a target, whichever comes first; alone, simplifies as far as it allows.
    #[arg(long, value_name = "E")]
    pub max_error: Option<f64>,
    /// QEM with attributes: weights of the attribute error in the collapse cost, e.g.
    /// `normal=0.05` (a deviation δ costs as much as a distance weight·δ of the bounding-box
    /// diagonal; all 0 by default: the geometric order, seams still held and values carried
    /// with the contractions; names not given stay 0).
    #[arg(long, value_name = "NAME=W,...")]
    pub attribute_weights: Option<String>,
    /// GNG3D maximum running time in seconds: training and every step after it, from the start
    /// of the algorithm to the returned mesh (loading and saving not counted). Steps are left
    /// out in a documented order when time is short (each is a warning); the vertex count stays
    /// exact. Below the minimum a run needs, a warning gives that minimum and the run is the
    /// fastest one.
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// GNG3D random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// GNG3D variant: placement, flips, paper protocol.
    #[command(flatten)]
    pub gng: crate::cli::GngVariantArgs,
    /// Keep exact duplicate positions unwelded (welding is on by default).
    #[arg(long)]
    pub no_weld: bool,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Run `gng3d simplify`.
pub fn run(args: SimplifyArgs) -> anyhow::Result<()> {
    // The output path is checked before loading or training, so a typo costs nothing.
    crate::cli::check_output_mesh_path(&args.output)?;
    for (flag, r) in [("--ratio", args.ratio), ("--face-ratio", args.face_ratio)] {
        if let Some(r) = r
            && !(r > 0.0 && r <= 1.0)
        {
            anyhow::bail!("{flag} must be in (0, 1], got {r}");
        }
    }
    match args.method {
        Method::Qem => qem::run(&args),
        Method::Gng => gng::run(&args),
    }
}

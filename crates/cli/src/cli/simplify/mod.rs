//! `gng3d simplify`: the flags mapped onto one `job::Request`, then the job
//! (`job::simplify_file`: load, clean, simplify, carry the attributes, save atomically), with
//! progress on stderr; `--lods` runs the job's steps once per level.

mod lods;
mod progress;

use anyhow::bail;
use clap::{Args, ValueEnum};
use job::{AttributePolicy, Method, Request, Target};
use std::path::PathBuf;

/// Simplification method (`job::Method`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// Garland–Heckbert quadric error metrics (pair contraction); the default.
    Qem,
    /// GNG3D-Q: Growing Neural Gas training plus reconstruction, quadric placement, exactly the
    /// vertex count asked for.
    Gng,
    /// The published GNG3D (node placement, 30 epochs, no oversampling).
    Paper,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Method {
        match m {
            MethodArg::Qem => Method::Qem,
            MethodArg::Gng => Method::Gng,
            MethodArg::Paper => Method::Paper,
        }
    }
}

/// What happens to the input's normals, texture coordinates, colours and materials
/// (`job::AttributePolicy`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum AttributesArg {
    /// Carry them to the output where its format stores them (the default).
    Keep,
    /// Positions and triangles only, as if the file had none.
    Drop,
}

impl From<AttributesArg> for AttributePolicy {
    fn from(a: AttributesArg) -> AttributePolicy {
        match a {
            AttributesArg::Keep => AttributePolicy::Keep,
            AttributesArg::Drop => AttributePolicy::Drop,
        }
    }
}

/// Whether the mesh is held in memory or streamed through the partition (`job::Partition`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PartitionArg {
    /// The whole mesh in memory (the default).
    Off,
    /// A mesh larger than memory: cut into cells that fit --memory-budget, each simplified
    /// with its border locked, stitched, finished to the exact target (QEM on positions only;
    /// PLY, OBJ or STL input).
    Auto,
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
    #[arg(long, value_enum, default_value_t = MethodArg::Qem)]
    pub method: MethodArg,
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
    /// It bounds an RMS distance, not the largest: the Hausdorff distance measured 2.9-5.9 × E.
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
    #[arg(long, default_value_t = job::DEFAULT_SEED)]
    pub seed: u64,
    /// Most threads the run uses, 1 to 256 (default: the machine's cores, GNG3D's training at
    /// most 4). The mesh is the same for any count, except QEM on 500,000 faces or more.
    #[arg(long)]
    pub threads: Option<usize>,
    /// The input's normals, texture coordinates, colours and materials: keep them (written
    /// where the output format stores them) or drop them (positions only, as if the file had
    /// none).
    #[arg(long, value_enum, default_value_t = AttributesArg::Keep)]
    pub attributes: AttributesArg,
    /// GNG3D variant: placement, flips, paper protocol.
    #[command(flatten)]
    pub gng: crate::cli::GngVariantArgs,
    /// One mesh larger than memory: `auto` streams it through the partitioned simplification
    /// (QEM on positions only, PLY, OBJ or STL input, never held whole; PLY/OBJ vertices are
    /// not welded, STL corners are welded by exact position as the loader welds them).
    #[arg(long, value_enum, default_value_t = PartitionArg::Off)]
    pub partition: PartitionArg,
    /// With --partition auto: memory one cell may take while it is simplified, e.g. 2GB or
    /// 512MiB (default 1GiB; a cell takes about 200 bytes a face).
    #[arg(long, value_name = "SIZE")]
    pub memory_budget: Option<String>,
    /// With --partition auto: the folder of the chunk files (default: OUT's name with
    /// `.gng3d-work`, beside it). A run killed before the end resumes from its finished cells
    /// when rerun with the same folder.
    #[arg(long, value_name = "DIR")]
    pub work_dir: Option<PathBuf>,
    /// With --partition auto: keep the work folder after a successful run.
    #[arg(long)]
    pub keep_work: bool,
    /// Keep exact duplicate positions unwelded (welding is on by default).
    #[arg(long)]
    pub no_weld: bool,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    pub json: bool,
}

/// The request of `args`: the one mapping from these flags (the batch passes the same flags to
/// its children).
fn request(args: &SimplifyArgs) -> anyhow::Result<Request> {
    let method = Method::from(args.method);
    if let Some(lods) = &args.lods {
        if method.is_gng() {
            bail!("--lods applies to QEM only; use --vertices or --ratio with --method gng");
        }
        lods::check(lods)?;
    }
    let given = crate::cli::target(args.vertices, args.faces, args.ratio, args.face_ratio);
    let target = match given {
        Some(target) => target,
        // --lods: each level's share is checked as a ratio (the levels are checked apart).
        None => match (&args.lods, args.max_error) {
            (Some(lods), _) => Target::Ratio(lods.first().copied().unwrap_or(1.0)),
            (None, Some(_)) if !method.is_gng() => Target::MaxErrorOnly,
            _ if method.is_gng() => bail!("give a target with --vertices N or --ratio R"),
            _ => bail!(
                "give a target with --vertices N, --ratio R, --faces N or --face-ratio R, or a bound with --max-error E"
            ),
        },
    };
    let mut request =
        crate::cli::gng_request(method, target, args.seed, args.time_limit, &args.gng);
    request.threads = args.threads;
    request.attributes = args.attributes.into();
    request.weld = !args.no_weld;
    request.qem = job::QemOptions {
        threshold: args.threshold,
        lock_border: args.lock_border,
        max_error: args.max_error,
        attribute_weights: args
            .attribute_weights
            .as_deref()
            .map(attribute_weights)
            .transpose()?,
    };
    request.partition = partition(args)?;
    request.validate().map_err(crate::cli::job_error)?;
    Ok(request)
}

/// The partition of `--partition`, `--memory-budget`, `--work-dir` and `--keep-work`.
fn partition(args: &SimplifyArgs) -> anyhow::Result<job::Partition> {
    if args.partition == PartitionArg::Off {
        let given: Vec<&str> = [
            (args.memory_budget.is_some(), "--memory-budget"),
            (args.work_dir.is_some(), "--work-dir"),
            (args.keep_work, "--keep-work"),
        ]
        .into_iter()
        .filter_map(|(given, flag)| given.then_some(flag))
        .collect();
        if !given.is_empty() {
            bail!("{} applies with --partition auto only", given.join(", "));
        }
        return Ok(job::Partition::Off);
    }
    if args.lods.is_some() {
        bail!("--lods does not apply with --partition auto: give one target");
    }
    let mut options = job::PartitionOptions {
        work_dir: args.work_dir.clone(),
        keep_work: args.keep_work,
        ..job::PartitionOptions::default()
    };
    if let Some(size) = &args.memory_budget {
        options.memory_budget = job::parse_size(size).map_err(crate::cli::job_error)?;
    }
    Ok(job::Partition::Auto(options))
}

/// `--attribute-weights uv=W,normal=W,color=W`: any of the three names, each at most once; the
/// others keep their defaults. The values are checked with the other options by
/// `QemParams::validate`.
fn attribute_weights(list: &str) -> anyhow::Result<qem::AttributeWeights> {
    let mut w = qem::AttributeWeights::default();
    let mut seen = Vec::new();
    for item in list.split(',') {
        let Some((name, value)) = item.split_once('=') else {
            bail!("--attribute-weights: expected NAME=W (uv, normal or color), got {item:?}");
        };
        let name = name.trim();
        let value: f64 = value.trim().parse().map_err(|_| {
            anyhow::anyhow!("--attribute-weights: {name}={value:?} is not a number")
        })?;
        let slot = match name {
            "uv" => &mut w.uv,
            "normal" => &mut w.normal,
            "color" | "colour" => &mut w.color,
            _ => bail!("--attribute-weights: unknown attribute {name:?} (uv, normal or color)"),
        };
        if seen.contains(&name) {
            bail!("--attribute-weights: {name} given twice");
        }
        seen.push(name);
        *slot = value;
    }
    Ok(w)
}

/// Run `gng3d simplify`.
pub fn run(args: SimplifyArgs) -> anyhow::Result<()> {
    // The output path is checked before loading or training, so a typo costs nothing.
    job::check_output(&args.output).map_err(crate::cli::job_error)?;
    let request = request(&args)?;
    if let Some(lods) = &args.lods {
        return lods::run(&args, &request, lods);
    }
    crate::process::working_on(&args.input);
    let mut bar = progress::JobBar::new(args.json);
    let done = job::simplify_file(
        &args.input,
        &args.output,
        &request,
        |warnings| {
            for w in warnings {
                eprintln!("warning: {}: {w}", args.input.display());
            }
        },
        &mut bar,
    );
    bar.finish();
    let done = done.map_err(|e| {
        crate::cli::job_error(e).context(format!(
            "{} on {}",
            request.method.label(),
            args.input.display()
        ))
    })?;
    for w in &done.kept.dropped {
        eprintln!("warning: {}: {w}", args.output.display());
    }
    for w in &done.outcome.warnings {
        eprintln!("warning: {w}");
    }
    if args.json {
        return crate::cli::print_json(&done.to_json());
    }
    outln!(
        "{} -> {}: {}",
        args.input.display(),
        args.output.display(),
        done.outcome.line()
    );
    if let job::Summary::Qem(s) = &done.outcome.summary
        && let Some(e) = s.report.max_relative_error
    {
        outln!("qem: largest contraction error {e:.3e} of the bounding-box diagonal");
    }
    Ok(())
}

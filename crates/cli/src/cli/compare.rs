//! `gng3d compare`: QEM and GNG3D-Q (or, with `--paper`, GNG3D as published) to the same
//! vertex count, all metrics, an aligned table; with `--image-error`, each output rendered
//! against the original (`metrics`' image-space error, its flags, texture and PNGs).

use super::image;
use anyhow::Context;
use clap::Args;
use gng3d::experiment::compare::{CompareParams, compare_with_attributes};
use gng3d::report::compare::comparison_table;
use metrics::Surface;
use std::path::{Path, PathBuf};

/// Arguments of `gng3d compare`.
#[derive(Debug, Args)]
#[group(id = "target", required = true, multiple = false)]
pub struct CompareArgs {
    /// Input mesh (.obj, .ply, .stl, .gltf, .glb).
    pub input: PathBuf,
    /// Vertex count both methods aim for.
    #[arg(long, group = "target")]
    pub vertices: Option<usize>,
    /// Target as a share of the input's vertices, in (0, 1]: the same vertex count for both
    /// methods, as `simplify --ratio` gives it (rounded to the nearest count).
    #[arg(long, group = "target")]
    pub ratio: Option<f64>,
    /// Folder for compare.json, qem.obj and gng.obj (created if missing).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Surface samples per direction for the Hausdorff distance (default: 10 × faces).
    #[arg(long)]
    pub samples: Option<usize>,
    /// Random seed for GNG3D and the surface sampler.
    #[arg(long, default_value_t = job::DEFAULT_SEED)]
    pub seed: u64,
    /// GNG3D maximum running time in seconds: training and every step after it, from the start
    /// of the algorithm to the returned mesh (loading and saving not counted). Steps are left
    /// out in a documented order when time is short (each is a warning); the vertex count stays
    /// exact. Below the minimum a run needs, a warning gives that minimum and the run is the
    /// fastest one.
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// Side of the texture, in texels, that UV deviations are given in (inputs with texture
    /// coordinates).
    #[arg(long, default_value_t = 1024)]
    pub texture_size: u32,
    /// UV distance above which a sample counts as off (inputs with texture coordinates).
    #[arg(long, default_value_t = 0.05)]
    pub uv_threshold: f64,
    /// The image-space error of each method's output.
    #[command(flatten)]
    pub image: image::ImageErrorArgs,
    /// Print the JSON report instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Run GNG3D as published (node placement, no flips, 30 epochs of |V| signals) instead of
    /// GNG3D-Q; `--epochs K` still overrides the 30.
    #[arg(
        long,
        conflicts_with_all = [
            "placement",
            "no_flips",
            "no_refit",
            "no_relax",
            "no_deviation_repair",
            "shape",
            "creases"
        ]
    )]
    pub paper: bool,
    /// GNG3D variant: placement, flips, paper protocol.
    #[command(flatten)]
    pub gng: super::GngVariantArgs,
}

/// The request of `args`: GNG3D-Q (or with `--paper` the published GNG3D) to the target, mapped
/// as `simplify`'s flags are (`super::target`, `super::gng_request`), and validated with the
/// same messages.
fn request(args: &CompareArgs) -> anyhow::Result<job::Request> {
    let target = super::target(args.vertices, None, args.ratio, None)
        .ok_or_else(|| anyhow::anyhow!("give a target with --vertices N or --ratio R"))?;
    let method = if args.paper {
        job::Method::Paper
    } else {
        job::Method::Gng
    };
    let request = super::gng_request(method, target, args.seed, args.time_limit, &args.gng);
    request.validate().map_err(super::job_error)?;
    Ok(request)
}

/// Run `gng3d compare`.
pub fn run(args: CompareArgs) -> anyhow::Result<()> {
    // Options and the output folder are checked before loading or simplifying anything; the
    // GNG3D options go through the same `job::Request` as `simplify`, with the same messages.
    let mut params = CompareParams::for_request(request(&args)?);
    params.metrics.hausdorff.seed = args.seed;
    params.metrics.hausdorff.samples = args.samples;
    params.metrics.hausdorff.validate()?;
    params.attributes = metrics::AttributeParams {
        samples: args.samples,
        seed: args.seed,
        texture_size: args.texture_size,
        uv_threshold: args.uv_threshold,
    };
    params.attributes.validate()?;
    let image_params = args.image.params()?;
    if let Some(dir) = &args.out {
        super::prepare_output_folder(dir)?;
    }
    args.image.prepare_out(&["qem", "gng"])?;
    let (original, attributes, materials) = load(&args.input, image_params.is_some())?;
    // The texture the image error draws with (the outputs, positions and attributes only,
    // are drawn with the original's).
    let texture = match image_params {
        Some(_) => image::texture(materials.as_ref())?,
        None => None,
    };
    let progress = super::progress::spinner(args.json);
    let result = compare_with_attributes(&original, attributes.as_ref(), &params, |stage| {
        progress.set_message(stage.to_string())
    })
    .map_err(anyhow::Error::from)
    .and_then(|mut result| {
        let Some(image_params) = &image_params else {
            return Ok(result);
        };
        progress.set_message(
            "measuring: image-space error (rendering 14 views of the original and both outputs)",
        );
        let original = Surface::new(&original)
            .with_attributes(attributes.as_ref())
            .with_texture(texture.as_ref());
        let keep = args.image.image_out.is_some();
        let (qem, gng) = rayon::join(
            || {
                let qem =
                    Surface::new(&result.qem_mesh).with_attributes(result.qem_attributes.as_ref());
                metrics::image_error_with_images(&original, &qem, image_params, keep)
            },
            || {
                let gng =
                    Surface::new(&result.gng_mesh).with_attributes(result.gng_attributes.as_ref());
                metrics::image_error_with_images(&original, &gng, image_params, keep)
            },
        );
        for (method, measured) in [("qem", qem), ("gng", gng)] {
            let (image, views) =
                measured.with_context(|| format!("rendering {method}'s output"))?;
            if let Some(dir) = &args.image.image_out {
                image::write_views(&dir.join(method), &views)?;
            }
            let run = if method == "qem" {
                &mut result.report.qem
            } else {
                &mut result.report.gng
            };
            run.metrics.image_error = Some(image);
        }
        Ok(result)
    });
    progress.finish_and_clear();
    let result = result.with_context(|| format!("comparing on {}", args.input.display()))?;
    for warning in &result.report.warnings {
        eprintln!("warning: {}: {warning}", args.input.display());
    }
    if let Some(dir) = &args.out {
        super::save_checked(&result.qem_mesh, &dir.join("qem.obj"), "QEM")?;
        super::save_checked(&result.gng_mesh, &dir.join("gng.obj"), "GNG3D")?;
        let json = dir.join("compare.json");
        super::write_atomic(
            &json,
            serde_json::to_string_pretty(&result.report)?.as_bytes(),
        )?;
    }
    if args.json {
        super::print_json(&result.report)
    } else {
        let report = &result.report;
        let reached = if report.qem.vertices == report.target_vertices {
            String::new()
        } else {
            format!(" asked, QEM reached {}", report.qem.vertices)
        };
        outln!(
            "{}: {} vertices, {} faces -> {} vertices{reached}",
            args.input.display(),
            report.original_vertices,
            report.original_faces,
            report.target_vertices
        );
        outln!("GNG3D column: {}", result.report.gng_variant);
        out!("{}", comparison_table(&result.report).to_text());
        if let Some(image) = &result.report.qem.metrics.image_error {
            outln!(
                "image rows: each output rendered against the original, over the pixels covered \
                 in either image;\n  {}",
                image::setup_in_words(image)
            );
            if let Some(dir) = &args.image.image_out {
                outln!(
                    "images: {0}/qem/view*.png, {0}/gng/view*.png (original | output | difference)",
                    dir.display()
                );
            }
        }
        Ok(())
    }
}

/// A mesh with its attributes and materials, as [`load`] returns it.
type Loaded = (
    mesh::TriMesh,
    Option<mesh::attributes::Attributes>,
    Option<mesh::attributes::Materials>,
);

/// The input, cleaned (`super::load_input`), with its normals, texture coordinates and colours
/// following the cleaning (`None` without any) and its materials; what compare does not use or
/// write is a warning: attributes are measured (attribute-deviation rows) but `--out` writes
/// positions only, and materials are used only for the image error's texture (`rendering`).
fn load(path: &Path, rendering: bool) -> anyhow::Result<Loaded> {
    let input = super::load_input(path, true)?;
    if input.has_materials {
        let used = if rendering {
            "materials used for the image error's texture only: --out writes positions only"
        } else {
            "materials not used: this command measures and writes positions only"
        };
        eprintln!(
            "warning: {}: {used} (`gng3d simplify` keeps them)",
            path.display()
        );
    }
    if let Some(attributes) = input.attributes.as_ref().filter(|a| a.has_values()) {
        eprintln!(
            "warning: {}: {} measured (attribute deviation) but not written: --out writes \
             positions only (`gng3d simplify` keeps them)",
            path.display(),
            super::attributes_in_words(attributes).join(", ")
        );
    }
    Ok((input.mesh, input.attributes, input.materials))
}

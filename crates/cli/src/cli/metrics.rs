//! `gng3d metrics`: paper errors and symmetric surface distance between two meshes.

use super::Input;
use super::image::{self, texture};
use anyhow::Context;
use clap::Args;
use gng3d::report::eng;
use mesh::attributes::Attributes;
use metrics::{
    AttributeDeviation, AttributeErrors, AttributeParams, HausdorffParams, MetricsParams,
    MetricsReport, OneSided, SamplingPlan, Surface, attribute_deviation, evaluate,
};
use std::path::PathBuf;

/// Arguments of `gng3d metrics`.
#[derive(Debug, Args)]
pub struct MetricsArgs {
    /// The original mesh.
    pub original: PathBuf,
    /// The simplified mesh.
    pub simplified: PathBuf,
    /// Surface samples per direction for the Hausdorff distance (vertices + edges + faces;
    /// default: 10 × the larger face count, as Metro); 1 to 50,000,000.
    #[arg(long)]
    pub samples: Option<usize>,
    /// MeshLab's sampling plan: every vertex record (unreferenced ones too, as MeshLab samples
    /// them; a random --samples of them when there are more), plus --samples edge samples, plus
    /// --samples face samples per direction (MeshLab's `samplenum`), instead of --samples in
    /// total.
    #[arg(long)]
    pub meshlab: bool,
    /// Seed of the surface sampler.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Side of the texture, in texels, that UV deviations are also given in (when both meshes
    /// have texture coordinates; 1 UV unit = this many texels).
    #[arg(long, default_value_t = 1024)]
    pub texture_size: u32,
    /// UV distance (UV units) above which a sample counts as off in the share reported.
    #[arg(long, default_value_t = 0.05)]
    pub uv_threshold: f64,
    /// The image-space error.
    #[command(flatten)]
    pub image: super::image::ImageErrorArgs,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Run `gng3d metrics`.
pub fn run(args: MetricsArgs) -> anyhow::Result<()> {
    let params = MetricsParams {
        hausdorff: HausdorffParams {
            samples: args.samples,
            seed: args.seed,
            plan: if args.meshlab {
                SamplingPlan::MeshLab
            } else {
                SamplingPlan::Budget
            },
            ..Default::default()
        },
    };
    let attribute_params = AttributeParams {
        samples: args.samples,
        seed: args.seed,
        texture_size: args.texture_size,
        uv_threshold: args.uv_threshold,
    };
    // Checked before loading: --samples 0 or a count beyond the memory limit is an error.
    params.hausdorff.validate().context("--samples")?;
    attribute_params.validate()?;
    let image_params = args.image.params()?;
    args.image.prepare_out(&[])?;
    let progress = super::progress::spinner(args.json);
    progress.set_message("loading both meshes");
    // As the files are: not welded or cleaned (the measures are of the files).
    let (original, simplified) = rayon::join(
        || super::load_input(&args.original, false),
        || super::load_input(&args.simplified, false),
    );
    let (
        Input {
            mesh: original,
            attributes: original_attributes,
            materials: original_materials,
            ..
        },
        Input {
            mesh: simplified,
            attributes: simplified_attributes,
            materials: simplified_materials,
            ..
        },
    ) = (original?, simplified?);
    // Each mesh's own texture (a simplified mesh without one, e.g. a PLY output, is drawn with
    // the original's); read only when rendering.
    let (original_texture, simplified_texture) = if image_params.is_some() {
        (
            texture(original_materials.as_ref())?,
            texture(simplified_materials.as_ref())?,
        )
    } else {
        (None, None)
    };
    progress.set_message("measuring: paper errors, surface distance both ways, quality");
    let report = evaluate(&original, &simplified, &params).and_then(|mut report| {
        // The original's attributes against the simplified mesh's (all missing when it has
        // none, so a dropped texture is said, not silently left out).
        if let Some(a) = original_attributes.as_ref().filter(|a| a.has_values()) {
            progress.set_message("measuring: attribute deviation both ways");
            let none = Attributes::per_vertex(&simplified);
            let b = simplified_attributes.as_ref().unwrap_or(&none);
            report.attributes = Some(attribute_deviation(
                &original,
                a,
                &simplified,
                b,
                &attribute_params,
            )?);
        }
        Ok(report)
    });
    let image = match (&report, &image_params) {
        (Ok(_), Some(image_params)) => {
            progress.set_message("measuring: image-space error (rendering 14 views of both)");
            Some(metrics::image_error_with_images(
                &Surface::new(&original)
                    .with_attributes(original_attributes.as_ref())
                    .with_texture(original_texture.as_ref()),
                &Surface::new(&simplified)
                    .with_attributes(simplified_attributes.as_ref())
                    .with_texture(simplified_texture.as_ref()),
                image_params,
                args.image.image_out.is_some(),
            ))
        }
        _ => None,
    };
    progress.finish_and_clear();
    let mut report = report.with_context(|| {
        format!(
            "measuring {} against {}",
            args.simplified.display(),
            args.original.display()
        )
    })?;
    if let Some((image, views)) = image.transpose().with_context(|| {
        format!(
            "rendering {} against {}",
            args.simplified.display(),
            args.original.display()
        )
    })? {
        if let Some(dir) = &args.image.image_out {
            image::write_views(dir, &views)?;
        }
        report.image_error = Some(image);
    }
    if args.json {
        return super::print_json(&report);
    }
    print_text(&args, &report)?;
    if let Some(image) = &report.image_error {
        image::print(image, args.image.image_out.as_deref())?;
    }
    Ok(())
}

/// One line of one-sided distances.
fn one_sided_line(label: &str, d: &OneSided) -> String {
    format!(
        "{label:<22}max {}  mean {}  rms {}  (units; {} samples: {} vertex, {} edge, {} face)",
        eng(d.max),
        eng(d.mean),
        eng(d.rms),
        d.samples,
        d.vertex_samples,
        d.edge_samples,
        d.face_samples
    )
}

/// Human-readable report.
fn print_text(args: &MetricsArgs, r: &MetricsReport) -> anyhow::Result<()> {
    let h = &r.hausdorff;
    let (o, s) = (&r.meshes.original, &r.meshes.simplified);
    outln!(
        "original              {} ({} vertices, {} faces)",
        args.original.display(),
        o.referenced_vertices,
        o.faces
    );
    outln!(
        "simplified            {} ({} vertices, {} faces)",
        args.simplified.display(),
        s.referenced_vertices,
        s.faces
    );
    outln!("bbox diagonal         {} units", eng(r.bbox_diagonal));
    outln!("E_avg                 {} units²", eng(r.e_avg));
    outln!("E_max                 {} units²", eng(r.e_max));
    outln!(
        "E_sur (signed)        {} units²  (|E_sur| {}, {:.3} % of the original area)",
        eng(r.e_sur_signed),
        eng(r.e_sur_abs),
        100.0 * r.e_sur_relative
    );
    outln!("{}", one_sided_line("forward  (orig→simp)", &h.forward));
    outln!("{}", one_sided_line("backward (simp→orig)", &h.backward));
    outln!(
        "hausdorff             max {}  mean {}  rms {}  (units)",
        eng(h.max),
        eng(h.mean),
        eng(h.rms)
    );
    outln!(
        "area-weighted mean    forward {}  backward {}  (units; headline mean: (1/A)∫d dA)",
        eng(h.forward.area_mean),
        eng(h.backward.area_mean)
    );
    outln!(
        "  / bbox diagonal     max {}  mean {}  rms {}",
        eng(h.relative.max),
        eng(h.relative.mean),
        eng(h.relative.rms)
    );
    let (nf, nb) = (&r.normal_deviation.forward, &r.normal_deviation.backward);
    outln!(
        "normal deviation      forward mean {:.2}° p95 {:.0}° max {:.1}°; backward mean {:.2}° p95 {:.0}° max {:.1}°",
        nf.mean_degrees,
        nf.p95_degrees,
        nf.max_degrees,
        nb.mean_degrees,
        nb.p95_degrees,
        nb.max_degrees
    );
    for (label, q) in [
        ("original", &r.quality.original),
        ("simplified", &r.quality.simplified),
    ] {
        outln!(
            "quality {label:<13} min angle {:.2}° (median {:.1}°, mean {:.1}°, {:.2} % < 20°, {:.2} % < 10°), aspect mean {:.2} max {:.1}, {} degenerate",
            q.min_angle_degrees,
            q.median_min_angle_degrees,
            q.mean_min_angle_degrees,
            100.0 * q.below_20_degrees,
            100.0 * q.below_10_degrees,
            q.mean_aspect_ratio,
            q.max_aspect_ratio,
            q.degenerate
        );
    }
    for (label, t) in [
        ("original", &r.topology.original),
        ("simplified", &r.topology.simplified),
    ] {
        let genus = t
            .genus
            .map_or_else(|| "undefined".to_string(), |g| g.to_string());
        outln!(
            "topology {label:<12} genus {genus}, {} components, {} boundary loops, {} non-manifold edges, {} non-manifold vertices",
            t.components,
            t.boundary_loops,
            t.non_manifold_edges,
            t.non_manifold_vertices
        );
    }
    if let Some(a) = &r.attributes {
        print_attributes(a)?;
    }
    outln!("time                  {:.3} s", r.seconds);
    Ok(())
}

/// The attribute deviation's lines.
fn print_attributes(a: &AttributeDeviation) -> anyhow::Result<()> {
    let list = |v: &[String]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    outln!(
        "attributes            compared {}; not in the simplified mesh: {} ({:.3} s)",
        list(&a.compared),
        list(&a.missing),
        a.seconds
    );
    if a.compared.is_empty() {
        return Ok(());
    }
    outln!(
        "  samples             {} per direction (backward: on the simplified mesh, against the original at the closest point; forward: the reverse)",
        a.backward.samples
    );
    let dirs = [("backward", &a.backward), ("forward ", &a.forward)];
    for (name, pick) in [
        (
            "uv0",
            (|e: &AttributeErrors| e.uv0) as fn(&AttributeErrors) -> _,
        ),
        ("uv1", |e: &AttributeErrors| e.uv1),
    ] {
        for (dir, e) in dirs {
            if let Some(u) = pick(e) {
                outln!(
                    "  {name} {dir}        mean {:.3}  rms {:.3}  max {:.1} texels of {}²  (max {} UV; {:.2} % of samples > {} UV)",
                    u.texels.mean,
                    u.texels.rms,
                    u.texels.max,
                    a.texture_size,
                    eng(u.uv.max),
                    100.0 * u.over_threshold,
                    a.uv_threshold
                );
            }
        }
    }
    for (dir, e) in dirs {
        if let Some(n) = e.normals {
            outln!(
                "  normals {dir}    mean {:.2}°  max {:.1}°",
                n.mean_degrees,
                n.max_degrees
            );
        }
    }
    for (dir, e) in dirs {
        if let Some(c) = e.colors {
            outln!(
                "  colors {dir}     mean {}  rms {}  max {}  (RGB distance, channels 0-1)",
                eng(c.mean),
                eng(c.rms),
                eng(c.max)
            );
        }
    }
    Ok(())
}

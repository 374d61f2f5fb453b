//! `gng3d metrics`: paper errors and symmetric surface distance between two meshes.

use anyhow::Context;
use clap::Args;
use gng3d::report::eng;
use metrics::{HausdorffParams, MetricsParams, MetricsReport, OneSided, SamplingPlan, evaluate};
use std::path::{Path, PathBuf};

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
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Loads a mesh, naming the file in errors and printing loader warnings to stderr.
fn load(path: &Path) -> anyhow::Result<mesh::TriMesh> {
    // MeshError names the file already; no extra context, so the path is said once.
    crate::process::working_on(path);
    let loaded = mesh::io::load(path)?;
    for warning in &loaded.warnings {
        eprintln!("warning: {}: {warning}", path.display());
    }
    Ok(loaded.mesh)
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
    // Checked before loading: --samples 0 or a count beyond the memory limit is an error.
    params.hausdorff.validate().context("--samples")?;
    let progress = super::progress::spinner(args.json);
    progress.set_message("loading both meshes");
    let (original, simplified) = rayon::join(|| load(&args.original), || load(&args.simplified));
    let (original, simplified) = (original?, simplified?);
    progress.set_message("measuring: paper errors, surface distance both ways, quality");
    let report = evaluate(&original, &simplified, &params);
    progress.finish_and_clear();
    let report = report.with_context(|| {
        format!(
            "measuring {} against {}",
            args.simplified.display(),
            args.original.display()
        )
    })?;
    if args.json {
        return super::print_json(&report);
    }
    print_text(&args, &report)
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
    outln!("time                  {:.3} s", r.seconds);
    Ok(())
}

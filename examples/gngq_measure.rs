//! GNG3D-Q measurement harness: one GNG3D training per (mesh, ratio), reconstructed with every
//! placement / flip / refit combination, plus optional curvature-weighted training, against QEM at the
//! same output vertex count. Prints one Markdown row per variant and a summary of ratios to QEM.
//!
//! ```text
//! GNG3D_MESHES=/work/shared/meshes cargo run --release --example gngq_measure -- \
//!     [--meshes a.obj,b.ply] [--ratios 0.1,0.25,0.5] [--samples 200000] [--curvature] [--surface]
//!     [--default-only] [--json out.jsonl]
//! ```
//!
//! Mean surface distance and Hausdorff come from the metrics crate (symmetric, Metro-style
//! sampling); triangle quality (median smallest angle, share under 20°) is computed here.

use gng3d::experiment::PaperEvaluator;
use gng3d_core::{GngParams, Placement, ReconstructionParams, SignalSource, Trainer};
use mesh::TriMesh;
use metrics::HausdorffParams;
use std::path::PathBuf;
use std::time::Instant;

/// Median smallest angle (degrees) and share of triangles with a smallest angle under 20°.
fn quality(m: &TriMesh) -> (f64, f64) {
    let mut angles: Vec<f64> = m
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| m.positions[v as usize].as_dvec3());
            let ang = |p: glam::DVec3, q: glam::DVec3, r: glam::DVec3| {
                let (u, v) = (q - p, r - p);
                u.cross(v).length().atan2(u.dot(v)).to_degrees()
            };
            ang(a, b, c).min(ang(b, c, a)).min(ang(c, a, b))
        })
        .collect();
    if angles.is_empty() {
        return (0.0, 1.0);
    }
    angles.sort_by(f64::total_cmp);
    let below = angles.iter().filter(|&&a| a < 20.0).count() as f64 / angles.len() as f64;
    (angles[angles.len() / 2], below)
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

struct Row {
    mesh: String,
    ratio: f64,
    variant: String,
    vertices: usize,
    mean: f64,
    hausdorff: f64,
    e_avg: f64,
    e_max: f64,
    e_sur_rel: f64,
    min_angle_median: f64,
    below20: f64,
    manifold: bool,
    seconds: f64,
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let dir = PathBuf::from(std::env::var("GNG3D_MESHES").unwrap_or("../shared/meshes".into()));
    let meshes: Vec<String> = get("--meshes")
        .unwrap_or("armadillo.obj,stanford-bunny.obj,fandisk.obj,gargoyle-10k.obj,horse.ply,rocker-arm.obj".into())
        .split(',')
        .map(String::from)
        .collect();
    let ratios: Vec<f64> = get("--ratios")
        .unwrap_or("0.1,0.25".into())
        .split(',')
        .map(|s| s.parse().expect("ratio"))
        .collect();
    let samples: usize = get("--samples").map_or(200_000, |s| s.parse().expect("samples"));
    let curvature = args.iter().any(|a| a == "--curvature");
    let surface = args.iter().any(|a| a == "--surface");
    let only_default = args.iter().any(|a| a == "--default-only");
    let mut rows: Vec<Row> = Vec::new();
    println!(
        "| mesh | ratio | variant | V | mean dist | Hausdorff | E_avg | E_max | E_sur/S | med min angle | <20° | manifold | s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in &meshes {
        let loaded = mesh::io::load(&dir.join(name))?;
        let original = mesh::clean::prepare(&loaded.mesh.into()).0.mesh;
        let evaluator = PaperEvaluator::new(&original, HausdorffParams::with_samples(samples))?;
        let area = original.area();
        for &ratio in &ratios {
            let target = ((original.vertex_count() as f64 * ratio).round() as usize).max(4);
            let mut emit = |variant: &str, m: &TriMesh, seconds: f64| -> anyhow::Result<usize> {
                let r = evaluator.evaluate(m)?;
                let (med, below) = quality(m);
                let t = mesh::topology::analyze(m);
                let row = Row {
                    mesh: name.clone(),
                    ratio,
                    variant: variant.into(),
                    vertices: m.vertex_count(),
                    mean: r.hausdorff_mean,
                    hausdorff: r.hausdorff_max,
                    e_avg: r.e_avg,
                    e_max: r.e_max,
                    e_sur_rel: r.e_sur_signed / area,
                    min_angle_median: med,
                    below20: below,
                    manifold: t.manifold,
                    seconds,
                };
                println!(
                    "| {} | {} | {} | {} | {:.3e} | {:.3e} | {:.3e} | {:.3e} | {:+.4} | {:.1} | {:.1}% | {} | {:.3} |",
                    row.mesh,
                    row.ratio,
                    row.variant,
                    row.vertices,
                    row.mean,
                    row.hausdorff,
                    row.e_avg,
                    row.e_max,
                    row.e_sur_rel,
                    row.min_angle_median,
                    100.0 * row.below20,
                    row.manifold,
                    row.seconds
                );
                rows.push(row);
                Ok(m.vertex_count())
            };
            let mut sources = vec![SignalSource::Vertices];
            if curvature {
                sources.push(SignalSource::Curvature);
            }
            if surface {
                sources.push(SignalSource::Surface);
            }
            let mut qem_vertices = 0;
            for source in sources {
                let mut params = GngParams::for_target(target);
                params.signal_source = source;
                let t = Instant::now();
                let mut trainer = Trainer::new(&original.clone().into(), params)?;
                while !trainer.is_finished() {
                    trainer.step(u64::MAX);
                }
                let train_s = t.elapsed().as_secs_f64();
                let tag = match source {
                    SignalSource::Curvature => "curv ",
                    SignalSource::Surface => "surf ",
                    SignalSource::Vertices => "",
                };
                // (label, placement, flips, refit); the last is the library default.
                let mut variants = vec![
                    ("node", Placement::Node, false, false),
                    ("project", Placement::Project, false, false),
                    ("quadric", Placement::Quadric, false, false),
                    ("project+flip", Placement::Project, true, false),
                    ("quadric+flip", Placement::Quadric, true, false),
                    ("quadric+flip+refit", Placement::Quadric, true, true),
                ];
                if only_default || source != SignalSource::Vertices {
                    variants.retain(|v| v.0 == "quadric+flip+refit" || v.0 == "node");
                }
                for (label, placement, flip, refit) in variants {
                    let rp = ReconstructionParams {
                        placement,
                        flip_edges: flip,
                        refit,
                        ..ReconstructionParams::default()
                    };
                    let t = Instant::now();
                    let rec = trainer.reconstruct(&rp);
                    let rec_s = t.elapsed().as_secs_f64();
                    let v = emit(&format!("{tag}{label}"), &rec.mesh, train_s + rec_s)?;
                    if label == "quadric+flip+refit" && tag.is_empty() {
                        qem_vertices = v;
                    }
                    eprintln!(
                        "{name} {ratio} {tag}{label}: reconstruct {:.4} s ({} flips)",
                        rec_s, rec.report.flipped_edges
                    );
                }
            }
            let qp = qem::QemParams::with_target(qem::Target::Vertices(qem_vertices.max(4)));
            let input = mesh::Model::from(original.clone());
            let t = Instant::now();
            let (qm, _) = qem::simplify(&input, &qp)?;
            let qm = qm.mesh;
            let qs = t.elapsed().as_secs_f64();
            emit("qem", &qm, qs)?;
        }
    }
    // Summary: per variant, medians of the ratios to QEM and win shares.
    println!();
    println!(
        "| variant | runs | median mean/QEM | median Haus/QEM | E_avg wins | E_max wins | quality wins (med angle & <20°) | manifold |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let variants: Vec<String> = {
        let mut v: Vec<String> = rows
            .iter()
            .map(|r| r.variant.clone())
            .filter(|v| v != "qem")
            .collect();
        v.dedup();
        let mut seen = Vec::new();
        for x in v {
            if !seen.contains(&x) {
                seen.push(x);
            }
        }
        seen
    };
    for variant in variants {
        let (mut mr, mut hr) = (Vec::new(), Vec::new());
        let (mut ea, mut em, mut qw, mut mf, mut n) = (0, 0, 0, 0, 0);
        for r in rows.iter().filter(|r| r.variant == variant) {
            let Some(q) = rows
                .iter()
                .find(|q| q.variant == "qem" && q.mesh == r.mesh && q.ratio == r.ratio)
            else {
                continue;
            };
            n += 1;
            mr.push(r.mean / q.mean);
            hr.push(r.hausdorff / q.hausdorff);
            ea += usize::from(r.e_avg < q.e_avg);
            em += usize::from(r.e_max < q.e_max);
            qw += usize::from(r.min_angle_median > q.min_angle_median && r.below20 < q.below20);
            mf += usize::from(r.manifold);
        }
        println!(
            "| {variant} | {n} | {:.2} | {:.2} | {ea}/{n} | {em}/{n} | {qw}/{n} | {mf}/{n} |",
            median(mr),
            median(hr)
        );
    }
    if let Some(path) = get("--json") {
        let mut out = String::new();
        for r in &rows {
            out.push_str(&serde_json::to_string(&serde_json::json!({
                "mesh": r.mesh, "ratio": r.ratio, "variant": r.variant, "vertices": r.vertices,
                "mean": r.mean, "hausdorff": r.hausdorff, "e_avg": r.e_avg, "e_max": r.e_max,
                "e_sur_rel": r.e_sur_rel, "min_angle_median": r.min_angle_median,
                "below20": r.below20, "manifold": r.manifold, "seconds": r.seconds,
            }))?);
            out.push('\n');
        }
        std::fs::write(path, out)?;
    }
    Ok(())
}

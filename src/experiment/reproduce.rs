//! The paper's protocol: train GNG3D with a checkpoint every |V| signals, reconstruct at each
//! checkpoint, and measure it against QEM at the same vertex count and at the final target.
//!
//! An original with attributes (normals, texture coordinates, colours:
//! [`reproduce_with_attributes`]) also gets each mesh's attribute deviation
//! ([`metrics::attribute_deviation`]): QEM keeps the attributes through its contractions, as
//! `gng3d simplify --method qem` and the survey run it (its seams then shape the geometry too);
//! each GNG3D checkpoint is the protocol's reconstruction of the network as it stands (the
//! paper's, without the seam cuts of a full `gng3d simplify` run) and takes the original's
//! values at its corners' places (`mesh::transfer::transfer_attributes`), so a triangle that
//! straddles a seam shows in the figures.

use super::{ExperimentError, PaperEvaluator, PaperRow};
use gng3d_core::{GngOptions, Trainer};
use job::{GngVariant, Method, Request, Target};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use metrics::{AttributeDeviation, AttributeParams, HausdorffParams};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::time::Instant;

/// Most epochs `reproduce` and the survey take: one checkpoint (a copy of the network) is kept
/// per epoch, and `--epochs 1000000` kept snapshots until it ran out of memory (the paper uses
/// 30).
pub const MAX_EPOCHS: u64 = 300;

/// The one check of an epoch count for `reproduce` and the survey (the CLI calls it before
/// loading anything): at least 1, at most [`MAX_EPOCHS`].
pub fn check_epochs(epochs: u64) -> Result<(), String> {
    if epochs == 0 {
        return Err("epochs must be at least 1".into());
    }
    if epochs > MAX_EPOCHS {
        return Err(format!(
            "epochs must be at most {MAX_EPOCHS} (one checkpoint is kept per epoch), got {epochs}"
        ));
    }
    Ok(())
}

/// Parameters of [`reproduce`].
#[derive(Debug, Clone)]
pub struct ReproduceParams {
    /// Training length in epochs of |V| signals (the paper: 30).
    pub epochs: u64,
    /// Target vertex count as a fraction of the original vertex count (the paper: 0.5).
    pub target_ratio: f64,
    /// GNG3D's random seed (the job's [`job::DEFAULT_SEED`] by default).
    pub seed: u64,
    /// The variant of the paper's GNG3D ([`Method::Paper`]) that trains, as the job maps it;
    /// the target and the signal budget are set from the fields above (the protocol counts
    /// signals, so there is no time limit). QEM runs with the job's defaults.
    pub gng: GngVariant,
    /// Surface sampling of the Hausdorff distance at every checkpoint.
    pub hausdorff: HausdorffParams,
    /// Attribute-deviation settings, used by [`reproduce_with_attributes`] for an original
    /// with attributes.
    pub attributes: AttributeParams,
}

impl Default for ReproduceParams {
    fn default() -> Self {
        ReproduceParams {
            epochs: 30,
            target_ratio: 0.5,
            seed: job::DEFAULT_SEED,
            // The paper's method as published (node placement, no flips).
            gng: GngVariant::default(),
            hausdorff: HausdorffParams::with_samples(100_000),
            attributes: AttributeParams::default(),
        }
    }
}

/// One row of the paper's Table 1, extended with QEM at the same vertex count.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Signals presented so far (the paper's "iteration").
    pub iteration: u64,
    /// Live GNG nodes at this checkpoint.
    pub nodes: usize,
    /// GNG3D reconstructed at this checkpoint.
    pub gng: PaperRow,
    /// QEM simplified to the reconstructed mesh's vertex count.
    pub qem_equal: PaperRow,
    /// Both meshes' attribute deviation, when the original has attributes (absent from the
    /// JSON otherwise, so a positions-only report is as before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attributes: Option<CheckpointAttributes>,
}

/// The attribute deviation of both meshes of one [`Checkpoint`] against the original.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckpointAttributes {
    /// GNG3D's reconstruction at the checkpoint (values taken from the original).
    pub gng: AttributeDeviation,
    /// QEM's at the same vertex count (attributes kept through its contractions).
    pub qem_equal: AttributeDeviation,
}

/// Wall-clock seconds spent in each stage.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Timings {
    /// GNG3D phase 1 (all checkpoints).
    pub training: f64,
    /// Reconstruction, QEM and metrics at every checkpoint.
    pub evaluation: f64,
    /// Everything.
    pub total: f64,
}

/// The whole protocol's output.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReproduceReport {
    /// Vertices of the (welded) original.
    pub original_vertices: usize,
    /// Faces of the original.
    pub original_faces: usize,
    /// Original surface area.
    pub original_area: f64,
    /// Bounding-box diagonal of the original (model units).
    pub bbox_diagonal: f64,
    /// GNG3D target vertex count.
    pub target_vertices: usize,
    /// Signals per checkpoint (|V|).
    pub signals_per_epoch: u64,
    /// Table rows, in increasing iteration.
    pub checkpoints: Vec<Checkpoint>,
    /// QEM held at the target vertex count, as in the paper.
    pub qem_fixed: PaperRow,
    /// QEM's attribute deviation at the target vertex count, when the original has attributes
    /// (absent from the JSON otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub qem_fixed_attributes: Option<AttributeDeviation>,
    /// Time per stage.
    pub seconds: Timings,
}

/// The stage [`reproduce`] is in, for progress bars.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Training GNG3D: one step per checkpoint.
    Training,
    /// Reconstructing and measuring each GNG3D checkpoint (most of the run time).
    Evaluating,
    /// Simplifying with QEM at each distinct vertex count and measuring it.
    Qem,
}

/// Progress of [`reproduce`]: `done` of `total` steps of `stage`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    /// The current stage.
    pub stage: Stage,
    /// Steps of this stage finished.
    pub done: u64,
    /// Steps of this stage in all.
    pub total: u64,
}

/// Run the paper's protocol on `original` (expected welded, e.g. by `mesh::clean::prepare`).
///
/// `on_progress` is called after each training checkpoint, each evaluated checkpoint and each
/// QEM run (from worker threads, one call at a time), for progress bars.
pub fn reproduce(
    original: &TriMesh,
    params: &ReproduceParams,
    on_progress: impl FnMut(Progress) + Send,
) -> Result<ReproduceReport, ExperimentError> {
    reproduce_with_attributes(original, None, params, on_progress)
}

/// [`reproduce`] for an original with `attributes` (which must fit it; `None`: positions only,
/// exactly [`reproduce`]): every checkpoint and QEM run also gets its attribute deviation,
/// measured with `params.attributes` (see the module docs for how each method keeps them).
pub fn reproduce_with_attributes(
    original: &TriMesh,
    attributes: Option<&Attributes>,
    params: &ReproduceParams,
    on_progress: impl FnMut(Progress) + Send,
) -> Result<ReproduceReport, ExperimentError> {
    let on_progress = std::sync::Mutex::new(on_progress);
    let report = |stage, done, total| {
        if let Ok(mut f) = on_progress.lock() {
            f(Progress { stage, done, total });
        }
    };
    let done_count = std::sync::atomic::AtomicU64::new(0);
    let tick = |stage, total| {
        let done = done_count.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        report(stage, done, total);
    };
    let start = Instant::now();
    let n = original.vertex_count();
    if !(params.target_ratio > 0.0 && params.target_ratio <= 1.0) {
        return Err(ExperimentError::BadTarget(format!(
            "target ratio {} is not in (0, 1]",
            params.target_ratio
        )));
    }
    check_epochs(params.epochs).map_err(ExperimentError::BadTarget)?;
    if let Some(a) = attributes {
        params.attributes.validate()?;
        a.validate(original)
            .map_err(|problem| metrics::MetricsError::Attributes {
                mesh: "original",
                problem,
            })?;
    }
    // The attribute deviation of an output with attributes `kept` (None without attributes).
    let deviation = |mesh: &TriMesh, kept: Option<&Attributes>| {
        super::deviation(original, attributes, mesh, kept, &params.attributes)
    };
    let target = ((n as f64 * params.target_ratio).round() as usize).max(4);
    let per_epoch = n as u64;
    let request = Request {
        seed: params.seed,
        gng: params.gng,
        ..Request::new(Target::Vertices(target)).with_method(Method::Paper)
    };
    request.validate()?;
    let options = GngOptions {
        max_signals: Some(per_epoch * params.epochs),
        epochs: None,
        ..request.gng_options()?
    };
    let mut trainer = Trainer::new(&original.clone().into(), options.resolve(original)?)?;

    // Phase 1 with snapshots; reconstruction and metrics run afterwards, in parallel.
    let mut snapshots = Vec::new();
    while !trainer.is_finished() {
        let done = trainer.step(per_epoch);
        if done == 0 {
            break;
        }
        snapshots.push(trainer.snapshot());
        report(Stage::Training, snapshots.len() as u64, params.epochs);
    }
    // A network that needed no training (a target of every vertex) is its own checkpoint; a
    // run with nothing to show is an error, not an empty table.
    if snapshots.is_empty() {
        let last = trainer.snapshot();
        if last.positions.len() < 3 {
            return Err(ExperimentError::BadTarget(format!(
                "no checkpoint: training ended with {} nodes before its first epoch (no piece of the mesh can hold a node's share of the target)",
                last.positions.len()
            )));
        }
        snapshots.push(last);
    }
    let training = start.elapsed().as_secs_f64();

    let eval_start = Instant::now();
    let evaluator = PaperEvaluator::new(original, params.hausdorff)?;
    type Measured = (PaperRow, Option<AttributeDeviation>);
    let model = super::model(original, attributes);
    let qem_at = |vertices: usize| -> Result<Measured, ExperimentError> {
        let (mesh, kept, _) = super::run(&model, &super::qem_request(&request, vertices.max(4)))?;
        Ok((evaluator.evaluate(&mesh)?, deviation(&mesh, kept.as_ref())?))
    };
    let evaluations = snapshots.len() as u64;
    report(Stage::Evaluating, 0, evaluations);
    let gng_rows: Vec<(u64, usize, Measured)> = snapshots
        .par_iter()
        .map(|snap| {
            let rec = snap.reconstruct(original, &options.reconstruction);
            let row = evaluator.evaluate(&rec.mesh)?;
            let kept =
                attributes.map(|a| mesh::transfer::transfer_attributes(original, a, &rec.mesh));
            let measured = (row, deviation(&rec.mesh, kept.as_ref())?);
            tick(Stage::Evaluating, evaluations);
            Ok((snap.signals, snap.positions.len(), measured))
        })
        .collect::<Result<_, ExperimentError>>()?;
    // Many checkpoints share a vertex count once the network holds its target: QEM runs once each.
    let mut counts: Vec<usize> = gng_rows.iter().map(|r| r.2.0.vertices).collect();
    counts.push(target);
    counts.sort_unstable();
    counts.dedup();
    let qem_runs = counts.len() as u64;
    done_count.store(0, std::sync::atomic::Ordering::Relaxed);
    report(Stage::Qem, 0, qem_runs);
    let qem_rows: BTreeMap<usize, Measured> = counts
        .par_iter()
        .map(|&v| {
            let row = qem_at(v)?;
            tick(Stage::Qem, qem_runs);
            Ok((v, row))
        })
        .collect::<Result<_, ExperimentError>>()?;
    let checkpoints = gng_rows
        .into_iter()
        .map(|(iteration, nodes, (gng, gng_attributes))| {
            let (qem_equal, qem_attributes) = &qem_rows[&gng.vertices];
            Checkpoint {
                iteration,
                nodes,
                gng,
                qem_equal: *qem_equal,
                attributes: gng_attributes
                    .zip(qem_attributes.clone())
                    .map(|(gng, qem_equal)| CheckpointAttributes { gng, qem_equal }),
            }
        })
        .collect();
    let (qem_fixed, qem_fixed_attributes) = qem_rows[&target].clone();
    let evaluation = eval_start.elapsed().as_secs_f64();
    Ok(ReproduceReport {
        original_vertices: n,
        original_faces: original.face_count(),
        original_area: original.area(),
        bbox_diagonal: original.bbox_diagonal(),
        target_vertices: target,
        signals_per_epoch: per_epoch,
        checkpoints,
        qem_fixed,
        qem_fixed_attributes,
        seconds: Timings {
            training,
            evaluation,
            total: start.elapsed().as_secs_f64(),
        },
    })
}

//! Metro-style sampled surface distance between two meshes (Cignoni, Rocchini, Scopigno 1998).
//!
//! One direction samples the *source* surface (vertices, edges, area-weighted faces; see
//! [`mesh::sampling::sample_stratified`]) and finds each sample's exact closest point on the
//! *target* through a [`SurfaceDistanceIndex`]. Statistics per direction follow Metro and
//! MeshLab: max, mean and RMS over all samples (vertices, edges and faces alike). The
//! area-weighted figures over the face samples alone, which estimate `(1/A)∫d dA` and
//! `sqrt((1/A)∫d² dA)` whatever share of the budget went to vertices and edges, are reported
//! as well. The symmetric Hausdorff distance is the larger of the two maxima.
//!
//! Work is split into fixed-size chunks of samples, each chunk processed sequentially and the
//! chunk results reduced in chunk order, so results are bit-identical for any thread count.
//!
//! Each direction is measured in the target index's [`Frame`] (for a pair: the original's,
//! scaled by a power of two near its diagonal), so the figures are the same, up to rounding of
//! the model's own coordinates, at any model scale; they are reported in model units.
//!
//! (Over ~700 lines only with its unit tests, the last ~127 lines.)

use crate::frame::Frame;
use crate::index::{NO_SLOT, SurfaceDistanceIndex, bound_f32};
use crate::{MetricsError, check_cancel, validate_all_vertices, validate_mesh};
use glam::{Vec3, Vec3A};
use mesh::TriMesh;
use mesh::cancel::Cancel;
use mesh::sampling::{
    EdgeSampling, FaceSampling, StratifiedParams, StratifiedSamples, SurfaceSample,
    sample_stratified,
};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Samples per work chunk (fixed so that results do not depend on the thread count).
const CHUNK: usize = 8192;

/// Bins of the normal-deviation histogram (one per degree).
const ANGLE_BINS: usize = 180;

/// Most samples one direction may draw (each costs 16 bytes while it is measured, so two
/// directions at this limit hold about 1.6 GB). Larger requests are refused with
/// [`MetricsError::Parameter`] instead of aborting on allocation; Metro's default
/// (10 × faces) is capped here.
pub const MAX_SAMPLES_PER_DIRECTION: usize = 50_000_000;

/// How `samples` is turned into vertex, edge and face samples per direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum SamplingPlan {
    /// `samples` is the total per direction (vertices + edges + faces), split as `vertices`,
    /// `edges` and `faces` say (Metro's plan; the default).
    #[default]
    Budget,
    /// MeshLab's Hausdorff filter with vertex, edge and face sampling and `samplenum = samples`:
    /// every vertex record of the source, **unreferenced ones included** (MeshLab's
    /// `VertexUniform` takes every vertex of the mesh), or a random `samples` of them when there
    /// are more; plus `samples` edge samples, plus `samples` face samples (e.g. 2,001,407
    /// samples for `samples` = 1,000,000 on a 1,407-vertex mesh). The `vertices` and `edges`
    /// fields are ignored. Every vertex record must then be finite.
    MeshLab,
}

/// Parameters of the sampled surface distance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HausdorffParams {
    /// Samples per direction (see `plan`); `None` uses Metro's default, 10 × the larger face
    /// count (at most [`MAX_SAMPLES_PER_DIRECTION`]). At least 1, at most
    /// [`MAX_SAMPLES_PER_DIRECTION`].
    pub samples: Option<usize>,
    /// How `samples` is split into vertex, edge and face samples.
    #[serde(default)]
    pub plan: SamplingPlan,
    /// Seed of the sampler (the two directions use seeds derived from it).
    pub seed: u64,
    /// Sample the source's referenced vertices.
    pub vertices: bool,
    /// Number of edge samples (Metro's `sqrt(density)` per unit length by default).
    pub edges: EdgeSampling,
    /// Placement of the face samples.
    pub faces: FaceSampling,
    /// Samples with no target point within this distance (model units) are excluded from all
    /// statistics and counted in `excluded` (MeshLab's `maxdist`); `None` keeps every sample.
    pub max_distance: Option<f64>,
}

impl Default for HausdorffParams {
    fn default() -> Self {
        HausdorffParams {
            samples: None,
            plan: SamplingPlan::Budget,
            seed: 1,
            vertices: true,
            edges: EdgeSampling::Metro,
            faces: FaceSampling::Random,
            max_distance: None,
        }
    }
}

impl HausdorffParams {
    /// Default parameters with `samples` samples per direction.
    pub fn with_samples(samples: usize) -> HausdorffParams {
        HausdorffParams {
            samples: Some(samples),
            ..Default::default()
        }
    }

    /// MeshLab's plan ([`SamplingPlan::MeshLab`]) with `samplenum` = `samples`.
    pub fn meshlab(samples: usize) -> HausdorffParams {
        HausdorffParams {
            samples: Some(samples),
            plan: SamplingPlan::MeshLab,
            ..Default::default()
        }
    }

    /// Checks the parameters: `samples` in 1..=[`MAX_SAMPLES_PER_DIRECTION`], an edge share in
    /// [0, 1], a `max_distance` that is a number ≥ 0.
    pub fn validate(&self) -> Result<(), MetricsError> {
        if let Some(n) = self.samples {
            if n == 0 {
                return Err(MetricsError::Parameter {
                    name: "samples",
                    message: "must be at least 1 (0 samples would measure nothing)".into(),
                });
            }
            let factor = if self.plan == SamplingPlan::MeshLab {
                2
            } else {
                1
            };
            if n.saturating_mul(factor) > MAX_SAMPLES_PER_DIRECTION {
                return Err(MetricsError::Parameter {
                    name: "samples",
                    message: format!(
                        "{n} is above the limit of {} samples per direction{}",
                        MAX_SAMPLES_PER_DIRECTION / factor,
                        if factor == 2 {
                            " for the MeshLab plan (edge and face samples each)"
                        } else {
                            ""
                        }
                    ),
                });
            }
        }
        if let EdgeSampling::Share(x) = self.edges
            && !(0.0..=1.0).contains(&x)
        {
            return Err(MetricsError::Parameter {
                name: "edge share",
                message: format!("{x} is outside [0, 1]"),
            });
        }
        if let Some(d) = self.max_distance
            && (d.is_nan() || d < 0.0)
        {
            return Err(MetricsError::Parameter {
                name: "max_distance",
                message: format!("{d} is not a distance >= 0"),
            });
        }
        Ok(())
    }

    /// The stratified plan of one direction for `samples` requested samples (for MeshLab's
    /// plan: its edge and face samples; the vertices are drawn by [`meshlab_vertices`]).
    fn plan_for(&self, samples: usize) -> StratifiedParams {
        match self.plan {
            SamplingPlan::Budget => StratifiedParams {
                total: samples,
                vertices: self.vertices,
                edges: self.edges,
                faces: self.faces,
            },
            SamplingPlan::MeshLab => StratifiedParams {
                total: 2 * samples,
                vertices: false,
                edges: EdgeSampling::Share(0.5),
                faces: self.faces,
            },
        }
    }

    /// True when the plan samples every vertex record, unreferenced ones included.
    pub(crate) fn samples_every_vertex(&self) -> bool {
        self.plan == SamplingPlan::MeshLab
    }
}

/// MeshLab's vertex samples (`VertexUniform`): every vertex record of `mesh`, referenced or not,
/// in index order, or a seeded random `samples` of them when there are more. A vertex sample's
/// face is its first incident face (`u32::MAX` for an unreferenced vertex; vertex samples'
/// faces are never read).
fn meshlab_vertices(mesh: &TriMesh, samples: usize, seed: u64) -> Vec<SurfaceSample> {
    let mut incident = vec![u32::MAX; mesh.positions.len()];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            if incident[v as usize] == u32::MAX {
                incident[v as usize] = f as u32;
            }
        }
    }
    let mut chosen: Vec<u32> = (0..mesh.positions.len() as u32).collect();
    if chosen.len() > samples {
        // Partial Fisher-Yates: a uniform random subset, then back into index order.
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        for i in 0..samples {
            let j = rng.random_range(i..chosen.len());
            chosen.swap(i, j);
        }
        chosen.truncate(samples);
        chosen.sort_unstable();
    }
    chosen
        .into_iter()
        .map(|v| SurfaceSample {
            position: mesh.positions[v as usize],
            face: incident[v as usize],
        })
        .collect()
}

/// Max, mean and RMS of a distance, in model units (or relative to a diagonal).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct DistanceStats {
    /// Largest sampled distance.
    pub max: f64,
    /// Mean distance.
    pub mean: f64,
    /// Root mean square distance.
    pub rms: f64,
}

/// One-sided distance from a source surface to a target surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OneSided {
    /// Largest distance over all counted samples (vertices, edges, faces), model units.
    pub max: f64,
    /// Mean distance over all counted samples (Metro/MeshLab convention), model units.
    pub mean: f64,
    /// Root mean square distance over all counted samples, model units.
    pub rms: f64,
    /// Mean over the counted face samples only: the area-weighted mean `(1/A)∫d dA`.
    pub area_mean: f64,
    /// RMS over the counted face samples only: `sqrt((1/A)∫d² dA)`.
    pub area_rms: f64,
    /// Counted samples (all kinds, excluding `excluded`).
    pub samples: usize,
    /// Vertex samples drawn.
    pub vertex_samples: usize,
    /// Edge samples drawn.
    pub edge_samples: usize,
    /// Face samples drawn.
    pub face_samples: usize,
    /// Samples dropped because no target point was within `max_distance`.
    pub excluded: usize,
    /// Position of the sample that attained `max`.
    pub max_at: Vec3,
    /// `max`, `mean`, `rms` divided by the original mesh's bounding-box diagonal.
    pub relative: DistanceStats,
}

/// Symmetric sampled surface distance between an original and a simplified mesh.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Hausdorff {
    /// Original → simplified (samples on the original).
    pub forward: OneSided,
    /// Simplified → original (samples on the simplified mesh).
    pub backward: OneSided,
    /// Symmetric Hausdorff distance: the larger of the two maxima, model units.
    pub max: f64,
    /// Mean of the two one-sided means, model units.
    pub mean: f64,
    /// `sqrt((forward.rms² + backward.rms²) / 2)`, model units.
    pub rms: f64,
    /// Bounding-box diagonal of the original's referenced vertices, model units.
    pub bbox_diagonal: f64,
    /// `max`, `mean`, `rms` divided by `bbox_diagonal`.
    pub relative: DistanceStats,
}

/// Angle between each face sample's source face normal and the normal of the target face
/// holding its closest point, in degrees (0 = parallel, 180 = flipped).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct NormalDeviation {
    /// Mean angle over face samples.
    pub mean_degrees: f64,
    /// 95th percentile (1° resolution, upper bin edge).
    pub p95_degrees: f64,
    /// Largest angle.
    pub max_degrees: f64,
    /// Face samples with a defined angle (both faces non-degenerate).
    pub samples: usize,
}

/// Per-chunk partial sums, merged in chunk order.
#[derive(Clone)]
struct Partial {
    max: f64,
    max_at: Vec3,
    face_sum: f64,
    face_sum2: f64,
    face_n: usize,
    all_sum: f64,
    all_sum2: f64,
    all_n: usize,
    excluded: usize,
    angle_sum: f64,
    angle_max: f64,
    angle_hist: [u32; ANGLE_BINS],
    angle_n: usize,
}

impl Partial {
    fn new() -> Partial {
        Partial {
            max: 0.0,
            max_at: Vec3::ZERO,
            face_sum: 0.0,
            face_sum2: 0.0,
            face_n: 0,
            all_sum: 0.0,
            all_sum2: 0.0,
            all_n: 0,
            excluded: 0,
            angle_sum: 0.0,
            angle_max: 0.0,
            angle_hist: [0; ANGLE_BINS],
            angle_n: 0,
        }
    }

    fn merge(mut self, o: Partial) -> Partial {
        if o.all_n > 0 && (self.all_n == 0 || o.max > self.max) {
            self.max = o.max;
            self.max_at = o.max_at;
        }
        self.face_sum += o.face_sum;
        self.face_sum2 += o.face_sum2;
        self.face_n += o.face_n;
        self.all_sum += o.all_sum;
        self.all_sum2 += o.all_sum2;
        self.all_n += o.all_n;
        self.excluded += o.excluded;
        self.angle_sum += o.angle_sum;
        self.angle_max = self.angle_max.max(o.angle_max);
        for (a, b) in self.angle_hist.iter_mut().zip(o.angle_hist.iter()) {
            *a += b;
        }
        self.angle_n += o.angle_n;
        self
    }
}

/// Derives the per-direction seed (splitmix64 finaliser of `seed + salt`).
pub(crate) fn derive_seed(seed: u64, salt: u64) -> u64 {
    let mut z = seed.wrapping_add(salt.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Metro's default sample count: 10 × the larger face count, capped at the limit.
fn default_samples(a: &TriMesh, b: &TriMesh) -> usize {
    (10 * a.face_count().max(b.face_count())).clamp(1, MAX_SAMPLES_PER_DIRECTION / 2)
}

/// One-sided distance from `source` to the mesh behind `target`, with statistics made relative
/// to `diagonal` (normally the original's bounding-box diagonal). `params.samples = None` means
/// 10 × the source's face count. The source is sampled in the target index's frame, so the
/// source must lie within [`crate::MAX_SPAN`] of the target's bounding-box diagonals.
pub fn one_sided(
    source: &TriMesh,
    target: &SurfaceDistanceIndex,
    params: &HausdorffParams,
    diagonal: f64,
) -> Result<OneSided, MetricsError> {
    params.validate()?;
    validate_mesh(source, "source")?;
    let samples = params
        .samples
        .unwrap_or((10 * source.face_count()).clamp(1, MAX_SAMPLES_PER_DIRECTION / 2));
    one_sided_inner(source, target, params, samples, params.seed, diagonal).map(|(o, _)| o)
}

/// The samples of one direction, ready to be measured, in the frame of the target.
pub(crate) struct Drawn {
    samples: StratifiedSamples,
    normals: Vec<Vec3>,
}

impl Drawn {
    /// The samples, in the target's frame.
    pub(crate) fn samples(&self) -> &[SurfaceSample] {
        &self.samples.samples
    }
}

/// Draws the samples of one direction on `source` (validated), held in `frame` (the target
/// index's).
pub(crate) fn draw(
    source: &TriMesh,
    frame: &Frame,
    params: &HausdorffParams,
    samples: usize,
    seed: u64,
) -> Result<Drawn, MetricsError> {
    if source.triangles.is_empty() {
        return Err(MetricsError::NoTriangles { mesh: "source" });
    }
    let every_vertex = params.samples_every_vertex();
    if every_vertex {
        validate_all_vertices(source, "source")?;
    }
    frame.check_span(source, "source", every_vertex)?;
    let local = frame.apply(source);
    let plan = params.plan_for(samples);
    let mut drawn =
        sample_stratified(&local, &plan, seed).map_err(|problem| MetricsError::Invalid {
            mesh: "source",
            problem,
        })?;
    if every_vertex {
        // Own seed, so the edge and face samples are those of a mesh without the extra vertices.
        let mut all = meshlab_vertices(&local, samples, derive_seed(seed, 3));
        drawn.vertex_count = all.len();
        all.append(&mut drawn.samples);
        drawn.samples = all;
    }
    Ok(Drawn {
        samples: drawn,
        normals: local.face_normals(),
    })
}

/// The work of one direction: sample, query in fixed chunks, reduce in order.
pub(crate) fn one_sided_inner(
    source: &TriMesh,
    target: &SurfaceDistanceIndex,
    params: &HausdorffParams,
    samples: usize,
    seed: u64,
    diagonal: f64,
) -> Result<(OneSided, NormalDeviation), MetricsError> {
    let drawn = draw(source, target.frame(), params, samples, seed)?;
    let (one, normals) = measure(&drawn, target, params, diagonal, None);
    check_counted(&one, "source")?;
    Ok((one, normals))
}

/// Measures drawn samples against `target`: fixed chunks, each sequential, reduced in order.
/// The samples are in the target's frame; the distances are measured there and reported in
/// model units. Once `cancel` is set the chunks not yet started are skipped (the figures are
/// then partial: the caller returns [`MetricsError::Cancelled`] instead).
pub(crate) fn measure(
    drawn: &Drawn,
    target: &SurfaceDistanceIndex,
    params: &HausdorffParams,
    diagonal: f64,
    cancel: Option<&Cancel>,
) -> (OneSided, NormalDeviation) {
    let source_normals = &drawn.normals;
    let drawn = &drawn.samples;
    let face_start = drawn.vertex_count + drawn.edge_count;
    let frame = *target.frame();
    let scale = frame.scale();
    // The exclusion bound in frame units.
    let bound2 = params
        .max_distance
        .map_or(f32::INFINITY, |d| bound_f32(d / scale));
    let max_distance = params.max_distance.map_or(f64::INFINITY, |d| d / scale);

    let partials: Vec<Partial> = drawn
        .samples
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(chunk, batch)| {
            let mut acc = Partial::new();
            if cancel.is_some_and(Cancel::is_cancelled) {
                return acc;
            }
            let mut stack = Vec::with_capacity(64);
            let mut hint = NO_SLOT;
            for (k, s) in batch.iter().enumerate() {
                let i = chunk * CHUNK + k;
                let slot = target.nearest_slot(Vec3A::from(s.position), hint, bound2, &mut stack);
                if slot == NO_SLOT {
                    acc.excluded += 1;
                    continue;
                }
                hint = slot;
                let hit = target.exact(s.position.as_dvec3(), slot);
                let d = hit.distance;
                if d > max_distance {
                    acc.excluded += 1;
                    continue;
                }
                if acc.all_n == 0 || d > acc.max {
                    acc.max = d;
                    acc.max_at = s.position;
                }
                acc.all_sum += d;
                acc.all_sum2 += d * d;
                acc.all_n += 1;
                if i >= face_start {
                    acc.face_sum += d;
                    acc.face_sum2 += d * d;
                    acc.face_n += 1;
                    let n_src = source_normals[s.face as usize];
                    let n_dst = target.face_normal(hit.face);
                    if n_src != Vec3::ZERO && n_dst != Vec3::ZERO {
                        let cos = (n_src.as_dvec3().dot(n_dst.as_dvec3())).clamp(-1.0, 1.0);
                        let angle = cos.acos().to_degrees();
                        acc.angle_sum += angle;
                        acc.angle_max = acc.angle_max.max(angle);
                        acc.angle_hist[(angle as usize).min(ANGLE_BINS - 1)] += 1;
                        acc.angle_n += 1;
                    }
                }
            }
            acc
        })
        .collect();
    let total = partials.into_iter().fold(Partial::new(), Partial::merge);

    let stats = |sum: f64, sum2: f64, n: usize| {
        if n > 0 {
            (sum / n as f64, (sum2 / n as f64).sqrt())
        } else {
            (0.0, 0.0)
        }
    };
    let (mean, rms) = stats(total.all_sum, total.all_sum2, total.all_n);
    // Area-weighted figures fall back to all samples if no face sample was drawn.
    let (area_mean, area_rms) = if total.face_n > 0 {
        stats(total.face_sum, total.face_sum2, total.face_n)
    } else {
        (mean, rms)
    };
    // Back to model units (the scale is a power of two: exact).
    let [max, mean, rms, area_mean, area_rms] =
        [total.max, mean, rms, area_mean, area_rms].map(|d| d * scale);
    let rel = |x: f64| if diagonal > 0.0 { x / diagonal } else { 0.0 };
    let one = OneSided {
        max,
        mean,
        rms,
        area_mean,
        area_rms,
        samples: total.all_n,
        vertex_samples: drawn.vertex_count,
        edge_samples: drawn.edge_count,
        face_samples: drawn.face_count,
        excluded: total.excluded,
        max_at: frame.to_model(total.max_at.as_dvec3()).as_vec3(),
        relative: DistanceStats {
            max: rel(max),
            mean: rel(mean),
            rms: rel(rms),
        },
    };
    let p95 = {
        let target_count = (total.angle_n as f64 * 0.95).ceil() as u64;
        let mut seen = 0u64;
        let mut edge = 0.0;
        for (bin, &c) in total.angle_hist.iter().enumerate() {
            seen += c as u64;
            if seen >= target_count {
                edge = (bin + 1) as f64;
                break;
            }
        }
        edge.min(total.angle_max.ceil().max(0.0))
    };
    let normals = NormalDeviation {
        mean_degrees: if total.angle_n > 0 {
            total.angle_sum / total.angle_n as f64
        } else {
            0.0
        },
        p95_degrees: if total.angle_n > 0 { p95 } else { 0.0 },
        max_degrees: total.angle_max,
        samples: total.angle_n,
    };
    (one, normals)
}

/// Combines the two directions into the symmetric figures.
fn combine(forward: OneSided, backward: OneSided, diagonal: f64) -> Hausdorff {
    let max = forward.max.max(backward.max);
    let mean = 0.5 * (forward.mean + backward.mean);
    let rms = (0.5 * (forward.rms * forward.rms + backward.rms * backward.rms)).sqrt();
    let rel = |x: f64| if diagonal > 0.0 { x / diagonal } else { 0.0 };
    Hausdorff {
        forward,
        backward,
        max,
        mean,
        rms,
        bbox_diagonal: diagonal,
        relative: DistanceStats {
            max: rel(max),
            mean: rel(mean),
            rms: rel(rms),
        },
    }
}

/// An error when every sample of a direction was excluded: a distance over no sample is no
/// distance (it would read as 0).
fn check_counted(one: &OneSided, direction: &'static str) -> Result<(), MetricsError> {
    if one.samples == 0 {
        Err(MetricsError::NoSamplesCounted {
            direction,
            excluded: one.excluded,
        })
    } else {
        Ok(())
    }
}

/// Validates both meshes and returns the samples per direction and the original's diagonal.
fn check_pair(
    original: &TriMesh,
    simplified: &TriMesh,
    params: &HausdorffParams,
) -> Result<(usize, f64), MetricsError> {
    params.validate()?;
    validate_mesh(original, "original")?;
    validate_mesh(simplified, "simplified")?;
    let samples = params
        .samples
        .unwrap_or_else(|| default_samples(original, simplified));
    Ok((samples, original.bbox_diagonal()))
}

/// Both directions with prebuilt indices; returns the distances and the normal deviations
/// (forward, backward).
pub(crate) fn hausdorff_full(
    original: &TriMesh,
    original_index: &SurfaceDistanceIndex,
    simplified: &TriMesh,
    simplified_index: &SurfaceDistanceIndex,
    params: &HausdorffParams,
) -> Result<(Hausdorff, NormalDeviation, NormalDeviation), MetricsError> {
    let (samples, diagonal) = check_pair(original, simplified, params)?;
    let (fwd, bwd) = rayon::join(
        || {
            let frame = simplified_index.frame();
            draw(
                original,
                frame,
                params,
                samples,
                derive_seed(params.seed, 1),
            )
        },
        || {
            let frame = original_index.frame();
            draw(
                simplified,
                frame,
                params,
                samples,
                derive_seed(params.seed, 2),
            )
        },
    );
    let fwd = fwd.map_err(|e| rename(e, "original"))?;
    let bwd = bwd.map_err(|e| rename(e, "simplified"))?;
    let ((fwd, nf), (bwd, nb)) = rayon::join(
        || measure(&fwd, simplified_index, params, diagonal, None),
        || measure(&bwd, original_index, params, diagonal, None),
    );
    check_counted(&fwd, "forward (original to simplified)")?;
    check_counted(&bwd, "backward (simplified to original)")?;
    Ok((combine(fwd, bwd, diagonal), nf, nb))
}

/// Both directions, building the two indices on the way and overlapping the (sequential) build
/// of the larger one with sampling and the forward queries. Both are measured in the
/// original's frame. With `cancel` set, [`MetricsError::Cancelled`] after the step running
/// (a batch of samples at most, in the queries).
pub(crate) fn hausdorff_pipelined(
    original: &TriMesh,
    simplified: &TriMesh,
    params: &HausdorffParams,
    cancel: Option<&Cancel>,
) -> Result<(Hausdorff, NormalDeviation, NormalDeviation), MetricsError> {
    let (samples, diagonal) = check_pair(original, simplified, params)?;
    check_cancel(cancel)?;
    let frame = Frame::of_mesh(original);
    frame.check_span(simplified, "simplified", false)?;
    let (original_index, rest) = rayon::join(
        || SurfaceDistanceIndex::in_frame(original, frame).map_err(|e| rename(e, "original")),
        || -> Result<_, MetricsError> {
            let simplified_index = SurfaceDistanceIndex::in_frame(simplified, frame)
                .map_err(|e| rename(e, "simplified"))?;
            let fwd = draw(
                original,
                &frame,
                params,
                samples,
                derive_seed(params.seed, 1),
            )
            .map_err(|e| rename(e, "original"))?;
            let bwd = draw(
                simplified,
                &frame,
                params,
                samples,
                derive_seed(params.seed, 2),
            )
            .map_err(|e| rename(e, "simplified"))?;
            check_cancel(cancel)?;
            let forward = measure(&fwd, &simplified_index, params, diagonal, cancel);
            check_cancel(cancel)?;
            Ok((forward, bwd))
        },
    );
    let original_index = original_index?;
    let ((fwd, nf), bwd_drawn) = rest?;
    check_cancel(cancel)?;
    let (bwd, nb) = measure(&bwd_drawn, &original_index, params, diagonal, cancel);
    check_cancel(cancel)?;
    check_counted(&fwd, "forward (original to simplified)")?;
    check_counted(&bwd, "backward (simplified to original)")?;
    Ok((combine(fwd, bwd, diagonal), nf, nb))
}

/// Replaces the generic mesh role in an error with the caller's name for it.
pub(crate) fn rename(e: MetricsError, which: &'static str) -> MetricsError {
    match e {
        MetricsError::NoTriangles { .. } => MetricsError::NoTriangles { mesh: which },
        MetricsError::NoVertices { .. } => MetricsError::NoVertices { mesh: which },
        MetricsError::Invalid { problem, .. } => MetricsError::Invalid {
            mesh: which,
            problem,
        },
        MetricsError::CoordinateRange { vertex, limit, .. } => MetricsError::CoordinateRange {
            mesh: which,
            vertex,
            limit,
        },
        other => other,
    }
}

/// Symmetric sampled surface distance with prebuilt indices (reuse them across many calls).
pub fn hausdorff_indexed(
    original: &TriMesh,
    original_index: &SurfaceDistanceIndex,
    simplified: &TriMesh,
    simplified_index: &SurfaceDistanceIndex,
    params: &HausdorffParams,
) -> Result<Hausdorff, MetricsError> {
    hausdorff_full(
        original,
        original_index,
        simplified,
        simplified_index,
        params,
    )
    .map(|(h, _, _)| h)
}

/// Symmetric Metro-style surface distance between `original` and `simplified`
/// (forward = original → simplified). Deterministic for a given `params.seed`.
pub fn hausdorff(
    original: &TriMesh,
    simplified: &TriMesh,
    params: &HausdorffParams,
) -> Result<Hausdorff, MetricsError> {
    hausdorff_pipelined(original, simplified, params, None).map(|(h, _, _)| h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mesh::procedural::{icosphere, torus};

    #[test]
    fn mesh_to_itself_is_zero() {
        let m = torus(1.0, 0.3, 32, 16);
        let h = hausdorff(&m, &m, &HausdorffParams::with_samples(50_000)).unwrap();
        let diag = m.bbox_diagonal();
        assert!(h.max <= 1e-6 * diag, "{h:?}");
        assert!(h.mean <= 1e-7 * diag);
        assert_eq!(h.forward.samples, 50_000);
        assert_eq!(h.forward.excluded, 0);
    }

    #[test]
    fn sphere_against_scaled_copy_gives_the_offset() {
        // A fine icosphere against a copy scaled by s: away from the facets the distance is
        // (s - 1) · r up to the facet sag (1 - cos of half the edge angle), which at 5 levels of
        // subdivision is ~2e-4; so max, mean and RMS must all be within that of 0.1.
        let m = icosphere(5);
        let s = 1.1f32;
        let scaled = TriMesh::new(
            m.positions.iter().map(|p| *p * s).collect(),
            m.triangles.clone(),
        );
        let h = hausdorff(&m, &scaled, &HausdorffParams::with_samples(200_000)).unwrap();
        let sag = 1e-3;
        for d in [
            h.forward.max,
            h.forward.mean,
            h.forward.rms,
            h.backward.max,
            h.backward.mean,
            h.backward.rms,
        ] {
            assert!((d - 0.1).abs() < sag, "{d} vs 0.1: {h:?}");
        }
        // Relative figures use the original's diagonal (2 · sqrt(3) for the unit sphere's box,
        // computed from the vertices).
        assert!((h.relative.max - h.max / m.bbox_diagonal()).abs() < 1e-15);
    }

    #[test]
    fn deterministic_regardless_of_thread_count() {
        let a = torus(1.0, 0.3, 40, 20);
        let b = icosphere(3);
        let params = HausdorffParams::with_samples(40_000);
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| hausdorff(&a, &b, &params).unwrap());
        let three = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap()
            .install(|| hausdorff(&a, &b, &params).unwrap());
        assert_eq!(one, three);
        // The pipelined path (building indices on the way) equals the prebuilt-index path.
        let (ai, bi) = (
            SurfaceDistanceIndex::new(&a).unwrap(),
            SurfaceDistanceIndex::new(&b).unwrap(),
        );
        assert_eq!(one, hausdorff_indexed(&a, &ai, &b, &bi, &params).unwrap());
        let other_seed = hausdorff(&a, &b, &HausdorffParams { seed: 2, ..params }).unwrap();
        assert_ne!(one.forward.mean, other_seed.forward.mean);
    }

    #[test]
    fn max_distance_excludes_far_samples() {
        // A unit square and a copy of it with one far-away extra triangle: samples on the extra
        // triangle are excluded when max_distance is below their distance.
        let square = TriMesh::new(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        let mut far = square.clone();
        far.positions.extend([
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::new(1.0, 0.0, 5.0),
            Vec3::new(0.0, 1.0, 5.0),
        ]);
        far.triangles.push([4, 5, 6]);
        let all = hausdorff(&square, &far, &HausdorffParams::with_samples(3000)).unwrap();
        assert!((all.backward.max - 5.0).abs() < 1e-6);
        let cut = hausdorff(
            &square,
            &far,
            &HausdorffParams {
                max_distance: Some(1.0),
                ..HausdorffParams::with_samples(3000)
            },
        )
        .unwrap();
        assert!(cut.backward.excluded > 0);
        assert!(cut.backward.max < 1e-6);
        assert_eq!(
            cut.backward.samples + cut.backward.excluded,
            all.backward.samples
        );
    }

    #[test]
    fn bad_input_is_an_error() {
        let good = icosphere(1);
        let no_faces = TriMesh::new(vec![Vec3::ZERO], vec![]);
        assert!(matches!(
            hausdorff(&good, &no_faces, &HausdorffParams::default()),
            Err(MetricsError::NoTriangles { mesh: "simplified" })
        ));
        let bad = TriMesh::new(vec![Vec3::ZERO], vec![[0, 0, 9]]);
        assert!(matches!(
            hausdorff(&bad, &good, &HausdorffParams::default()),
            Err(MetricsError::Invalid {
                mesh: "original",
                ..
            })
        ));
    }
}

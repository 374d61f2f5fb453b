//! What one direction measures and reports: each drawn sample's exact closest point on the
//! target, in fixed chunks reduced in chunk order ([`measure`]), and the figures made of them
//! ([`OneSided`], [`NormalDeviation`], and the symmetric [`Hausdorff`] of two directions).

use super::sampling::Drawn;
use crate::HausdorffParams;
use crate::index::{NO_SLOT, SurfaceDistanceIndex, bound_f32};
use glam::{Vec3, Vec3A};
use mesh::cancel::Cancel;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Samples per work chunk (fixed so that results do not depend on the thread count).
const CHUNK: usize = 8192;

/// Bins of the normal-deviation histogram (one per degree).
const ANGLE_BINS: usize = 180;

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

/// Measures drawn samples against `target`: fixed chunks, each sequential, reduced in order.
/// The samples are in the target's frame; the distances are measured there and reported in
/// model units. Once `cancel` is set the chunks not yet started are skipped (the figures are
/// then partial: the caller returns [`MetricsError::Cancelled`](crate::MetricsError::Cancelled) instead).
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
pub(super) fn combine(forward: OneSided, backward: OneSided, diagonal: f64) -> Hausdorff {
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

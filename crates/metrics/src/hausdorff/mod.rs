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
//! This module runs the directions ([`hausdorff`], [`one_sided`]); the samples are drawn in
//! [`sampling`] and measured in [`measure`](mod@measure).

mod measure;
mod sampling;

pub use measure::{DistanceStats, Hausdorff, NormalDeviation, OneSided};
use measure::{combine, measure};
pub use sampling::{HausdorffParams, MAX_SAMPLES_PER_DIRECTION, SamplingPlan};
pub(crate) use sampling::{derive_seed, draw};

use crate::frame::Frame;
use crate::index::SurfaceDistanceIndex;
use crate::{MetricsError, check_cancel, validate_mesh};
use mesh::TriMesh;
use mesh::cancel::Cancel;

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
    use glam::Vec3;
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

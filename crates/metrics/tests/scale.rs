//! Issue 33, row 15: the metrics hold at any model scale. A sphere measured against itself was
//! 0.6 % to 58 % of its diagonal away from itself at 1e-25, 1e-10, 1e10 and 1e15 (f32 squared
//! distances under- and overflowing in the closest-point search); here every measure must give
//! the same figure relative to the model's size at every scale, in the model's own units.
//!
//! Row 16 (MeshLab's plan samples unreferenced vertices) is tested at the end.

// Published as gng3d-metrics; this file keeps the workspace's name for it.
extern crate gng3d_metrics as metrics;

use glam::{DVec3, Vec3};
use mesh::TriMesh;
use metrics::{
    Evaluator, HausdorffParams, MetricsError, MetricsParams, SurfaceDistanceIndex, evaluate,
    hausdorff, hausdorff_indexed, one_sided, vertex_errors,
};

/// The scales of the issue.
const SCALES: [f32; 5] = [1e-25, 1e-10, 1.0, 1e10, 1e15];

/// A UV sphere of radius `r` around `center` (made here, not by the crate under test).
fn uv_sphere(r: f64, center: DVec3, rings: u32, segments: u32) -> TriMesh {
    let mut positions = vec![(center + DVec3::Z * r).as_vec3()];
    for i in 1..rings {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let phi = std::f64::consts::TAU * j as f64 / segments as f64;
            let d = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            positions.push((center + d * r).as_vec3());
        }
    }
    positions.push((center - DVec3::Z * r).as_vec3());
    let ring = |i: u32, j: u32| 1 + i * segments + j % segments;
    let mut triangles = Vec::new();
    for j in 0..segments {
        triangles.push([0, ring(0, j), ring(0, j + 1)]);
    }
    for i in 0..rings - 2 {
        for j in 0..segments {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j),
                ring(i + 1, j + 1),
            );
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    let last = positions.len() as u32 - 1;
    for j in 0..segments {
        triangles.push([ring(rings - 2, j), last, ring(rings - 2, j + 1)]);
    }
    TriMesh::new(positions, triangles)
}

/// An `n` × `n` grid of squares of side `side` in the plane z = `z`, corner at the origin.
fn plane(n: u32, side: f32, z: f32) -> TriMesh {
    let mut g = mesh::procedural::unit_square_grid(n);
    let width = n as f32 * side;
    for p in &mut g.positions {
        *p = Vec3::new(p.x * width, p.y * width, z);
    }
    g
}

fn params(samples: usize) -> MetricsParams {
    MetricsParams {
        hausdorff: HausdorffParams::with_samples(samples),
    }
}

/// Every distance-like figure of a report of a mesh against itself is at most `tol` × the
/// diagonal (squared figures: `tol²` × diagonal²; areas: `tol` × area), and the normals agree.
fn assert_self_distance_vanishes(r: &metrics::MetricsReport, diag: f64, tol: f64, label: &str) {
    let h = &r.hausdorff;
    for (name, d) in [
        ("max", h.max),
        ("forward.max", h.forward.max),
        ("backward.max", h.backward.max),
        ("mean", h.mean),
        ("rms", h.rms),
        ("forward.area_mean", h.forward.area_mean),
    ] {
        assert!(
            d.is_finite() && d <= tol * diag,
            "{label}: {name} = {d:e} > {tol:e} × diagonal {diag:e}"
        );
    }
    assert!(
        h.relative.max <= tol,
        "{label}: relative max {}",
        h.relative.max
    );
    assert!(
        r.e_max <= (tol * diag).powi(2),
        "{label}: E_max {:e}",
        r.e_max
    );
    assert!(
        r.e_avg <= (tol * diag).powi(2),
        "{label}: E_avg {:e}",
        r.e_avg
    );
    assert!(
        r.e_sur_abs <= tol * r.original_area,
        "{label}: E_sur {:e} of area {:e}",
        r.e_sur_abs,
        r.original_area
    );
    for n in [&r.normal_deviation.forward, &r.normal_deviation.backward] {
        assert!(n.samples > 0, "{label}");
        assert!(n.mean_degrees < 0.1, "{label}: normals {n:?}");
        assert!(n.max_degrees < 1.0, "{label}: normals {n:?}");
    }
    assert_eq!(h.forward.excluded + h.backward.excluded, 0, "{label}");
}

#[test]
fn a_sphere_against_itself_is_at_distance_zero_at_every_scale() {
    let unit = uv_sphere(1.0, DVec3::ZERO, 24, 48);
    let unit_quality = metrics::triangle_quality(&unit);
    for s in SCALES {
        let m = TriMesh::new(
            unit.positions.iter().map(|p| *p * s).collect(),
            unit.triangles.clone(),
        );
        let diag = m.bbox_diagonal();
        assert!((diag / (2.0 * 3f64.sqrt() * s as f64) - 1.0).abs() < 1e-3);
        let label = format!("scale {s:e}");
        let r = evaluate(&m, &m, &params(30_000)).unwrap();
        assert_self_distance_vanishes(&r, diag, 1e-6, &label);
        // Reported in the model's units.
        assert_eq!(r.bbox_diagonal, diag);
        assert!(
            (r.original_area / (m.area()) - 1.0).abs() < 1e-12,
            "{label}"
        );
        assert!(
            (r.original_area / (4.0 * std::f64::consts::PI * (s as f64).powi(2)) - 1.0).abs()
                < 0.01
        );
        // Shape figures do not depend on the scale.
        let q = &r.quality.original;
        assert!(
            (q.min_angle_degrees - unit_quality.min_angle_degrees).abs() < 1e-3,
            "{label}"
        );
        assert_eq!(q.degenerate, unit_quality.degenerate, "{label}");
        // The same through the evaluator (the survey's path), MeshLab's plan and the bare
        // Hausdorff functions.
        let e = Evaluator::new(&m, &params(30_000))
            .unwrap()
            .evaluate(&m)
            .unwrap();
        assert_self_distance_vanishes(&e, diag, 1e-6, &label);
        let ml = MetricsParams {
            hausdorff: HausdorffParams::meshlab(10_000),
        };
        assert_self_distance_vanishes(&evaluate(&m, &m, &ml).unwrap(), diag, 1e-6, &label);
        let h = hausdorff(&m, &m, &HausdorffParams::with_samples(30_000)).unwrap();
        assert!(h.max <= 1e-6 * diag, "{label}: {h:?}");
        let index = SurfaceDistanceIndex::new(&m).unwrap();
        let h = hausdorff_indexed(
            &m,
            &index,
            &m,
            &index,
            &HausdorffParams::with_samples(30_000),
        )
        .unwrap();
        assert!(h.max <= 1e-6 * diag, "{label}: {h:?}");
        let v = vertex_errors(&m.positions, &m.positions).unwrap();
        assert_eq!((v.e_avg, v.e_max), (0.0, 0.0), "{label}");
    }
}

#[test]
fn a_sphere_far_from_the_origin_against_itself_is_at_distance_zero() {
    // Radius 1 at 1000 diagonals from the origin: its own coordinates carry 1e-4 of its size in
    // f32; samples kept in model coordinates would round by that much.
    for s in [1e-20, 1.0, 1e12] {
        let m = uv_sphere(s, DVec3::splat(3464.0 * s), 16, 32);
        let diag = m.bbox_diagonal();
        let r = evaluate(&m, &m, &params(20_000)).unwrap();
        assert_self_distance_vanishes(&r, diag, 1e-6, &format!("offset sphere {s:e}"));
    }
}

#[test]
fn a_plane_against_a_copy_one_percent_of_its_diagonal_above_gives_that_offset_at_every_scale() {
    for s in SCALES {
        let side = s / 16.0;
        let a = plane(16, side, 0.0);
        let diag = a.bbox_diagonal(); // sqrt(2) · s, the plane being flat
        let offset = (0.01 * diag) as f32;
        let b = plane(16, side, offset);
        let offset = offset as f64; // as stored
        let label = format!("scale {s:e}");
        let r = evaluate(&a, &b, &params(20_000)).unwrap();
        let h = &r.hausdorff;
        for (name, d) in [
            ("forward.max", h.forward.max),
            ("forward.mean", h.forward.mean),
            ("forward.rms", h.forward.rms),
            ("forward.area_mean", h.forward.area_mean),
            ("backward.max", h.backward.max),
            ("backward.mean", h.backward.mean),
            ("backward.rms", h.backward.rms),
        ] {
            assert!(
                (d / offset - 1.0).abs() < 1e-6,
                "{label}: {name} = {d:e}, offset {offset:e}"
            );
        }
        assert!(
            (h.relative.max - 0.01).abs() < 1e-6,
            "{label}: {}",
            h.relative.max
        );
        // Every vertex lies straight below one of the copy: E = offset².
        assert!(
            (r.e_max / (offset * offset) - 1.0).abs() < 1e-6,
            "{label}: {}",
            r.e_max
        );
        assert!(
            (r.e_avg / (offset * offset) - 1.0).abs() < 1e-6,
            "{label}: {}",
            r.e_avg
        );
        assert!(r.e_sur_abs <= 1e-6 * r.original_area, "{label}");
        assert!(r.normal_deviation.forward.max_degrees < 1e-3, "{label}");
        // The one-sided function and a bare index, each in the target's own frame.
        let index = SurfaceDistanceIndex::new(&b).unwrap();
        let one = one_sided(&a, &index, &HausdorffParams::with_samples(5_000), diag).unwrap();
        assert!((one.max / offset - 1.0).abs() < 1e-6, "{label}: {one:?}");
        let c = index.closest(Vec3::new(0.3 * s, 0.6 * s, -s));
        assert!(
            (c.distance / (s as f64 + offset) - 1.0).abs() < 1e-6,
            "{label}: {c:?}"
        );
        assert!((c.point.z / offset - 1.0).abs() < 1e-6, "{label}: {c:?}");
        let within = index.closest_within(Vec3::new(0.3 * s, 0.6 * s, 0.0), 2.0 * offset);
        assert!(within.is_some_and(|c| (c.distance / offset - 1.0).abs() < 1e-6));
        assert!(
            index
                .closest_within(Vec3::new(0.3 * s, 0.6 * s, 0.0), 0.5 * offset)
                .is_none()
        );
    }
}

#[test]
fn meshes_too_far_apart_for_the_frame_are_refused_and_a_small_one_inside_a_big_one_is_measured() {
    let unit = uv_sphere(1.0, DVec3::ZERO, 8, 16);
    let far = uv_sphere(1.0, DVec3::new(1e20, 0.0, 0.0), 8, 16);
    for e in [
        evaluate(&unit, &far, &params(1000)).unwrap_err(),
        Evaluator::new(&unit, &params(1000))
            .unwrap()
            .evaluate(&far)
            .unwrap_err(),
        hausdorff(&unit, &far, &HausdorffParams::with_samples(1000)).unwrap_err(),
    ] {
        assert!(
            matches!(
                e,
                MetricsError::CoordinateRange {
                    mesh: "simplified",
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("1e18"), "{e}");
    }
    // A sphere of radius 1e20 around a unit sphere: both directions about 1e20 apart.
    let big = uv_sphere(1e20, DVec3::ZERO, 8, 16);
    let r = evaluate(&big, &unit, &params(2000)).unwrap();
    assert!(
        (r.hausdorff.forward.max / 1e20 - 1.0).abs() < 1e-6,
        "{:?}",
        r.hausdorff
    );
    assert!(
        (r.hausdorff.backward.max / 1e20 - 1.0).abs() < 0.1,
        "{:?}",
        r.hausdorff
    );
}

#[test]
fn meshlab_plan_samples_unreferenced_vertices_as_meshlab_does() {
    // A sphere with 40 vertices no face uses, 0.5 to 2 radii off its surface, measured against
    // a coarser sphere: MeshLab samples every vertex, so the forward max is the distance of the
    // farthest unreferenced vertex to the coarse sphere.
    let coarse = uv_sphere(1.0, DVec3::ZERO, 8, 16);
    let mut original = uv_sphere(1.0, DVec3::ZERO, 24, 48);
    let referenced = original.positions.len();
    let mut state = 7u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..40 {
        let d = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
        original
            .positions
            .push((d * (1.5 + 1.5 * next())).as_vec3());
    }
    let farthest = original.positions[referenced..]
        .iter()
        .map(|p| {
            (0..coarse.face_count())
                .map(|f| {
                    let [a, b, c] = coarse.triangle_f64(f);
                    (p.as_dvec3() - metrics::closest_point_triangle(p.as_dvec3(), a, b, c)).length()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    assert!(farthest > 1.0, "{farthest}");
    for s in [1e-10f32, 1.0, 1e10] {
        let scaled = |m: &TriMesh| {
            TriMesh::new(
                m.positions.iter().map(|p| *p * s).collect(),
                m.triangles.clone(),
            )
        };
        let (o, c) = (scaled(&original), scaled(&coarse));
        let expected = farthest * s as f64;
        let ml = evaluate(
            &o,
            &c,
            &MetricsParams {
                hausdorff: HausdorffParams::meshlab(20_000),
            },
        )
        .unwrap();
        let f = &ml.hausdorff.forward;
        assert_eq!(
            f.vertex_samples,
            original.positions.len(),
            "every vertex record"
        );
        assert!(
            (f.max / expected - 1.0).abs() < 1e-6,
            "scale {s:e}: forward max {} vs farthest unreferenced vertex {expected}",
            f.max
        );
        // Metro's budget plan samples the surface only: the max is the facet sag.
        let budget = evaluate(&o, &c, &params(40_000)).unwrap();
        assert!(
            budget.hausdorff.forward.max < 0.1 * s as f64,
            "{:?}",
            budget.hausdorff
        );
        // Fewer samples than vertex records: a random `samples` of all of them, as MeshLab.
        let few = evaluate(
            &o,
            &c,
            &MetricsParams {
                hausdorff: HausdorffParams::meshlab(500),
            },
        )
        .unwrap();
        assert_eq!(few.hausdorff.forward.vertex_samples, 500);
    }
    // MeshLab's plan needs every vertex record finite; the budget plan only the referenced ones.
    let mut bad = original.clone();
    bad.positions.push(Vec3::NAN);
    let nan = bad.positions.len() - 1;
    let e = evaluate(
        &bad,
        &coarse,
        &MetricsParams {
            hausdorff: HausdorffParams::meshlab(1000),
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains(&format!("vertex {nan}")), "{e}");
    assert!(e.to_string().contains("original"), "{e}");
    assert!(evaluate(&bad, &coarse, &params(1000)).is_ok());
}

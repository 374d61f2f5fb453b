//! The attribute term of the collapse cost and the relative error bound, checked against
//! independent computations: an analytic texture's interpolation error, and brute-force
//! point-to-triangle distances between input and output.

use glam::{DVec3, Vec2};
use gng3d_qem::{AttributeWeights, QemError, QemParams, StopReason, Target};
use mesh::attributes::Attributes;
use mesh::{Model, TriMesh};

/// The analytic texture of the grid tests: `u = x⁴` (stretched more and more towards x = 1),
/// `v = y`.
fn warped_uv(x: f32, y: f32) -> Vec2 {
    Vec2::new(x.powi(4), y)
}

/// Mean |interpolated u − analytic u| over 21 points of every output triangle of a flat grid
/// (z = 0, so every point of a triangle is a point of the square).
fn mean_u_error(out: &TriMesh, attributes: &Attributes) -> f64 {
    let uv = attributes.uv0.as_ref().unwrap();
    let (mut sum, mut n) = (0.0, 0usize);
    for (t, c) in out.triangles.iter().zip(&attributes.corners) {
        for i in 0..=5 {
            for j in 0..=(5 - i) {
                let w = [i as f32 / 5.0, j as f32 / 5.0, (5 - i - j) as f32 / 5.0];
                let p = (0..3).fold(glam::Vec3::ZERO, |s, k| {
                    s + out.positions[t[k] as usize] * w[k]
                });
                let got: f32 = (0..3).map(|k| uv[c[k] as usize].x * w[k]).sum();
                sum += f64::from((got - warped_uv(p.x, p.y).x).abs());
                n += 1;
            }
        }
    }
    sum / n as f64
}

#[test]
fn uv_stretch_steers_the_collapse_order() {
    // Flat: every interior contraction costs 0 geometrically, so without the attribute term
    // the order ignores the texture and the triangles are as large where u bends as elsewhere.
    let grid = mesh::procedural::unit_square_grid(40);
    let mut attributes = Attributes::per_vertex(&grid);
    attributes.uv0 = Some(grid.positions.iter().map(|p| warped_uv(p.x, p.y)).collect());
    let model = Model {
        attributes: Some(attributes),
        ..Model::from(grid)
    };
    let run = |weights: AttributeWeights| {
        let params = QemParams {
            attribute_weights: weights,
            ..QemParams::with_target(Target::Ratio(0.1))
        };
        let (out, report) = gng3d_qem::simplify(&model, &params).unwrap();
        assert!(report.target_reached, "{report:?}");
        let (out, a) = (out.mesh, out.attributes.unwrap());
        a.validate(&out).unwrap();
        (mean_u_error(&out, &a), out)
    };
    let (without, plain) = run(AttributeWeights::NONE);
    let (with, steered) = run(AttributeWeights {
        uv: 0.25,
        ..AttributeWeights::NONE
    });
    // Same size, within the one face an interior collapse can overshoot by.
    assert!(plain.face_count().abs_diff(steered.face_count()) <= 1);
    // Measured: 1.6e-4 with uv = 1, 2.8e-3 without (17 × less); uv = 0.25 passes too.
    assert!(
        with < 0.2 * without,
        "mean u error {with:.2e} with the UV term, {without:.2e} without"
    );
}

/// Points of `m`: its vertices and the centroid and edge midpoints of every face.
fn points(m: &TriMesh) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = m.positions.iter().map(|p| p.as_dvec3()).collect();
    for t in &m.triangles {
        let [a, b, c] = t.map(|v| m.positions[v as usize].as_dvec3());
        out.extend([
            (a + b + c) / 3.0,
            (a + b) / 2.0,
            (b + c) / 2.0,
            (c + a) / 2.0,
        ]);
    }
    out
}

/// Largest distance from the points of `from` to the surface of `to` (brute force).
fn one_sided(from: &TriMesh, to: &TriMesh) -> f64 {
    let tris: Vec<[DVec3; 3]> = to
        .triangles
        .iter()
        .map(|t| t.map(|v| to.positions[v as usize].as_dvec3()))
        .collect();
    points(from)
        .into_iter()
        .map(|p| {
            tris.iter()
                .map(|&[a, b, c]| mesh::geometry::closest_point_triangle(p, a, b, c).distance(p))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

fn diagonal(m: &TriMesh) -> f64 {
    let (lo, hi) = m.positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p.as_dvec3()), hi.max(p.as_dvec3())),
    );
    (hi - lo).length()
}

#[test]
fn a_relative_error_bound_stops_within_a_measured_distance() {
    let torus = mesh::procedural::torus(1.0, 0.35, 48, 24);
    let diag = diagonal(&torus);
    let mut previous = usize::MAX;
    for e in [0.001, 0.003, 0.01] {
        // No size target: the bound alone stops the run.
        let params = QemParams {
            max_relative_error: Some(e),
            ..QemParams::with_target(Target::Faces(0))
        };
        let (out, report) = gng3d_qem::simplify(&Model::from(torus.clone()), &params).unwrap();
        let out = out.mesh;
        assert_eq!(report.stop_reason, StopReason::MaxError, "{report:?}");
        let reached = report.max_relative_error.unwrap();
        assert!(
            reached <= e && reached > 0.3 * e,
            "E = {e}: reached {reached}"
        );
        assert!(
            out.face_count() < previous,
            "E = {e}: {} faces",
            out.face_count()
        );
        previous = out.face_count();
        // Hausdorff distance (both directions, brute force) within 3.5 × E of the diagonal:
        // the bound is an area-weighted RMS distance to the planes of the faces merged, not a
        // largest distance; measured 1.98e-3 / 8.2e-3 / 2.94e-2 at E = 0.001 / 0.003 / 0.01
        // (2.0-2.9 × E; 1,318 / 414 / 102 faces of 2,304).
        let hausdorff = one_sided(&torus, &out).max(one_sided(&out, &torus)) / diag;
        assert!(hausdorff <= 3.5 * e, "E = {e}: Hausdorff {hausdorff:.2e}");
    }
    assert!(previous < torus.face_count() / 4, "{previous}");
}

#[test]
fn a_bound_with_a_target_stops_at_whichever_comes_first() {
    let torus = Model::from(mesh::procedural::torus(1.0, 0.35, 48, 24));
    let bound = |target, e| {
        let params = QemParams {
            max_relative_error: Some(e),
            ..QemParams::with_target(target)
        };
        gng3d_qem::simplify(&torus, &params).unwrap().1
    };
    // A loose bound: the target is reached, and the order is the plain run's.
    let loose = bound(Target::Ratio(0.5), 1.0);
    let (plain_mesh, plain) =
        gng3d_qem::simplify(&torus, &QemParams::with_target(Target::Ratio(0.5))).unwrap();
    assert!(loose.target_reached);
    assert_eq!(
        (loose.faces, loose.collapses),
        (plain.faces, plain.collapses)
    );
    assert_eq!(plain.max_relative_error, None);
    assert_eq!(plain_mesh.mesh.face_count(), plain.faces);
    // A tight one stops first.
    let tight = bound(Target::Ratio(0.05), 0.001);
    assert_eq!(tight.stop_reason, StopReason::MaxError);
    assert!(tight.faces > torus.mesh.face_count() / 20);
}

#[test]
fn bad_weights_and_bounds_are_refused() {
    let grid = Model::from(mesh::procedural::unit_square_grid(4));
    let mut params = QemParams::with_target(Target::Ratio(0.5));
    params.attribute_weights.uv = -1.0;
    assert!(matches!(params.validate(), Err(QemError::InvalidParameter(m)) if m.contains("uv")));
    assert!(gng3d_qem::simplify(&grid, &params).is_err());
    params.attribute_weights.uv = 1.0;
    params.attribute_weights.color = f64::NAN;
    assert!(params.validate().is_err());
    params.attribute_weights.color = 1.0;
    assert!(params.validate().is_ok());
    for bad in [f64::NAN, -0.1, f64::INFINITY] {
        params.max_relative_error = Some(bad);
        assert!(params.validate().is_err(), "{bad}");
    }
    params.max_relative_error = None;
    for bad in [f64::NAN, -1.0, f64::INFINITY] {
        params.seam_weight = bad;
        assert!(
            matches!(params.validate(), Err(QemError::InvalidParameter(ref m)) if m.contains("seam weight")),
            "{bad}"
        );
    }
    params.seam_weight = 0.0;
    assert!(params.validate().is_ok());
}

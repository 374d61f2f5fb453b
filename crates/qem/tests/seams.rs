//! QEM on a fragmented texture atlas (`mesh::procedural::fragmented_atlas`: 300 charts on a
//! 20,480-face sphere, every chart border a UV seam): the seams bend instead of breaking the
//! run, so it reaches the count the positions-only run reaches, keeps the sphere closed and
//! manifold, and stays within 15 × the positions-only run's distance from the sphere. Where
//! the charts are so small that the seams' crossings alone outnumber the target, the run stops
//! there and says so ([`StopReason::Seams`]).

use gng3d_qem::{QemParams, StopReason, Target, simplify};
use mesh::procedural::{fragmented_atlas, icosphere};
use mesh::{Model, TriMesh};
use std::collections::HashMap;

/// The largest distance from the unit sphere of the mesh's vertices and face centroids (the
/// input's vertices lie on it).
fn off_sphere(m: &TriMesh) -> f32 {
    let p = |v: u32| m.positions[v as usize];
    let centroids = m
        .triangles
        .iter()
        .map(|t| (p(t[0]) + p(t[1]) + p(t[2])) / 3.0);
    m.positions
        .iter()
        .copied()
        .chain(centroids)
        .map(|x| (x.length() - 1.0).abs())
        .fold(0.0, f32::max)
}

/// Every edge is shared by exactly two faces, in opposite directions.
fn closed_manifold(m: &TriMesh) -> bool {
    let mut directed: HashMap<[u32; 2], usize> = HashMap::new();
    for t in &m.triangles {
        for k in 0..3 {
            *directed.entry([t[k], t[(k + 1) % 3]]).or_default() += 1;
        }
    }
    directed
        .iter()
        .all(|(&[a, b], &n)| n == 1 && directed.get(&[b, a]) == Some(&1))
}

#[test]
fn a_fragmented_atlas_reaches_the_positions_only_count_near_its_error() {
    let sphere = icosphere(5);
    let (attributes, charts) = fragmented_atlas(&sphere, 300, 1);
    assert_eq!(charts, 300);
    let textured = Model {
        attributes: Some(attributes),
        ..Model::from(sphere.clone())
    };
    for share in [0.3, 0.2, 0.1] {
        let params = QemParams::with_target(Target::Ratio(share));
        let (plain, plain_report) = simplify(&Model::from(sphere.clone()), &params).unwrap();
        let (out, report) = simplify(&textured, &params).unwrap();
        assert!(report.target_reached, "{share}: {report:?}");
        assert_eq!(report.stop_reason, StopReason::TargetReached);
        assert_eq!(report.faces, plain_report.faces, "{share}");
        assert!(
            closed_manifold(&out.mesh),
            "{share}: not closed and manifold"
        );
        let kept = out.attributes.as_ref().unwrap();
        kept.validate(&out.mesh).unwrap();
        let (ours, theirs) = (off_sphere(&out.mesh), off_sphere(&plain.mesh));
        eprintln!("{share}: off the sphere {ours:.3e} with the atlas, {theirs:.3e} without");
        // Measured 4.1, 9.9, 5.4 × at 30, 20, 10 %: not yet explained
        // (docs/notes/attributes.md, "Seams that bend"); the bound catches a break.
        assert!(
            ours <= 15.0 * theirs,
            "{share}: {ours} against {theirs} positions-only"
        );
    }
}

#[test]
fn an_atlas_whose_seam_crossings_outnumber_the_target_stops_there_and_says_so() {
    let sphere = icosphere(5); // 10,242 vertices, 20,480 faces
    let (attributes, charts) = fragmented_atlas(&sphere, 3000, 2);
    assert_eq!(charts, 3000);
    // Independently of the simplifier's seam search: one wedge per chart at a vertex, so a
    // vertex with three wedges or more is where three charts meet, a crossing of seams.
    let mut wedges = vec![0usize; sphere.positions.len()];
    for &v in &attributes.wedge_vertex {
        wedges[v as usize] += 1;
    }
    let crossings = wedges.iter().filter(|&&n| n >= 3).count();
    let target = Target::Ratio(0.1);
    assert!(
        crossings > 1100,
        "{crossings} crossings: too few to be the floor at 10 %"
    );
    let textured = Model {
        attributes: Some(attributes),
        ..Model::from(sphere.clone())
    };
    let params = QemParams::with_target(target);
    let (_, plain) = simplify(&Model::from(sphere), &params).unwrap();
    assert!(plain.target_reached, "positions only: {plain:?}");
    let (out, report) = simplify(&textured, &params).unwrap();
    assert_eq!(report.stop_reason, StopReason::Seams, "{report:?}");
    assert!(!report.target_reached);
    // Every crossing survives, and the report counts at least those.
    assert!(
        report.vertices >= crossings,
        "{} < {crossings}",
        report.vertices
    );
    assert!(
        report.fixed_seam_vertices >= crossings && report.fixed_seam_vertices <= report.vertices
    );
    assert!(2 * report.fixed_seam_vertices >= report.vertices);
    let note = report.shortfall(target).unwrap();
    assert!(
        note.contains(&format!(
            "{} of the vertices left",
            report.fixed_seam_vertices
        )),
        "{note}"
    );
    assert!(note.contains("seams"), "{note}");
    assert!(closed_manifold(&out.mesh));
    out.attributes
        .as_ref()
        .unwrap()
        .validate(&out.mesh)
        .unwrap();
}

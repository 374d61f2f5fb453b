//! Lock masks (`simplify_locked`, `border_vertices`): locked vertices stay where they were, with
//! and without attributes; an all-false mask changes nothing; a mask of the wrong length is an
//! error.

use glam::Vec3;
use gng3d_qem::{QemError, QemParams, Target, border_vertices, simplify, simplify_locked};

fn kept(output: &[Vec3], input: &[Vec3], locked: &[bool]) -> usize {
    input
        .iter()
        .zip(locked)
        .filter(|&(p, &l)| l && output.contains(p))
        .count()
}

#[test]
fn border_vertices_are_the_ends_of_single_face_edges() {
    let grid = mesh::procedural::unit_square_grid(10); // 11 x 11 vertices
    let border = border_vertices(&grid);
    // Independent: the vertices on the square's sides.
    let on_side = |p: &Vec3| p.x == 0.0 || p.y == 0.0 || p.x == 1.0 || p.y == 1.0;
    let sides: Vec<bool> = grid.positions.iter().map(on_side).collect();
    assert_eq!(border, sides);
    assert_eq!(border.iter().filter(|&&b| b).count(), 40);
    assert!(
        border_vertices(&mesh::procedural::icosphere(2))
            .iter()
            .all(|&b| !b)
    );
}

#[test]
fn locked_border_stays_and_unlocked_runs_remove_border_vertices() {
    let grid = mesh::procedural::unit_square_grid(20);
    let border = border_vertices(&grid);
    let n_border = border.iter().filter(|&&b| b).count();
    let params = QemParams::with_target(Target::Ratio(0.1));
    let (free, _) = simplify(&grid, &params).unwrap();
    let (locked, attributes, _) = simplify_locked(&grid, None, &params, &border).unwrap();
    assert!(attributes.is_none());
    assert_eq!(kept(&locked.positions, &grid.positions, &border), n_border);
    // Without the locks the flat border's straight runs are contracted.
    assert!(kept(&free.positions, &grid.positions, &border) < n_border / 2);
}

#[test]
fn any_mask_with_and_without_attributes() {
    let (sphere, uv) = mesh::procedural::textured_sphere(24, 48);
    let mask: Vec<bool> = (0..sphere.positions.len()).map(|v| v % 17 == 3).collect();
    let count = mask.iter().filter(|&&l| l).count();
    let params = QemParams::with_target(Target::Ratio(0.2));
    let (plain, _, _) = simplify_locked(&sphere, None, &params, &mask).unwrap();
    assert_eq!(kept(&plain.positions, &sphere.positions, &mask), count);
    let (textured, attributes, report) =
        simplify_locked(&sphere, Some(&uv), &params, &mask).unwrap();
    attributes.unwrap().validate(&textured).unwrap();
    assert_eq!(kept(&textured.positions, &sphere.positions, &mask), count);
    assert!(report.faces < sphere.face_count() / 2);
}

#[test]
fn an_empty_mask_changes_nothing_and_a_short_one_is_an_error() {
    let sphere = mesh::procedural::icosphere(3);
    let params = QemParams::with_target(Target::Ratio(0.25));
    let none = vec![false; sphere.positions.len()];
    let (free, _) = simplify(&sphere, &params).unwrap();
    let (locked, _, _) = simplify_locked(&sphere, None, &params, &none).unwrap();
    assert_eq!(free, locked);
    let err = simplify_locked(&sphere, None, &params, &none[1..]).unwrap_err();
    assert!(
        matches!(err, QemError::InvalidParameter(ref m) if m.contains("lock mask")),
        "{err}"
    );
}

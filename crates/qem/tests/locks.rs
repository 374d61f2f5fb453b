//! Locks (`QemParams::lock`, `border_vertices`): locked vertices stay where they were, with
//! and without attributes; `Lock::Border` is the mask of `border_vertices`; an all-false mask
//! changes nothing; a mask of the wrong length is an error.

use glam::Vec3;
use gng3d_qem::{Lock, QemError, QemParams, Target, border_vertices, simplify};
use mesh::Model;

/// `params` with `lock`.
fn locking(params: &QemParams, lock: Lock) -> QemParams {
    QemParams {
        lock,
        ..params.clone()
    }
}

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
    let grid = Model::from(mesh::procedural::unit_square_grid(20));
    let border = border_vertices(&grid.mesh);
    let n_border = border.iter().filter(|&&b| b).count();
    let params = QemParams::with_target(Target::Ratio(0.1));
    let (free, _) = simplify(&grid, &params).unwrap();
    let (locked, _) = simplify(&grid, &locking(&params, Lock::Border)).unwrap();
    assert!(locked.attributes.is_none());
    let positions = &grid.mesh.positions;
    assert_eq!(kept(&locked.mesh.positions, positions, &border), n_border);
    // The same as the border's mask given vertex by vertex.
    let (masked, _) = simplify(&grid, &locking(&params, Lock::Vertices(border.clone()))).unwrap();
    assert_eq!(locked.mesh, masked.mesh);
    // Without the locks the flat border's straight runs are contracted.
    assert!(kept(&free.mesh.positions, positions, &border) < n_border / 2);
}

#[test]
fn any_mask_with_and_without_attributes() {
    let (sphere, uv) = mesh::procedural::textured_sphere(24, 48);
    let mask: Vec<bool> = (0..sphere.positions.len()).map(|v| v % 17 == 3).collect();
    let count = mask.iter().filter(|&&l| l).count();
    let params = locking(
        &QemParams::with_target(Target::Ratio(0.2)),
        Lock::Vertices(mask.clone()),
    );
    let plain = Model::from(sphere.clone());
    let (out, _) = simplify(&plain, &params).unwrap();
    assert_eq!(kept(&out.mesh.positions, &sphere.positions, &mask), count);
    let textured = Model {
        attributes: Some(uv),
        ..plain
    };
    let (out, report) = simplify(&textured, &params).unwrap();
    out.attributes.unwrap().validate(&out.mesh).unwrap();
    assert_eq!(kept(&out.mesh.positions, &sphere.positions, &mask), count);
    assert!(report.faces < sphere.face_count() / 2);
}

#[test]
fn an_empty_mask_changes_nothing_and_a_short_one_is_an_error() {
    let sphere = Model::from(mesh::procedural::icosphere(3));
    let params = QemParams::with_target(Target::Ratio(0.25));
    let none = vec![false; sphere.mesh.positions.len()];
    let (free, _) = simplify(&sphere, &params).unwrap();
    let (locked, _) = simplify(&sphere, &locking(&params, Lock::Vertices(none.clone()))).unwrap();
    assert_eq!(free.mesh, locked.mesh);
    let short = Lock::Vertices(none[1..].to_vec());
    let err = simplify(&sphere, &locking(&params, short)).unwrap_err();
    assert!(
        matches!(err, QemError::InvalidParameter(ref m) if m.contains("lock mask")),
        "{err}"
    );
}

#[test]
fn a_border_lock_on_a_face_naming_a_missing_vertex_is_the_index_error() {
    let mut bad = mesh::procedural::unit_square_grid(4);
    bad.triangles.push([0, 1, 999]);
    let params = locking(&QemParams::default(), Lock::Border);
    assert!(matches!(
        simplify(&Model::from(bad), &params),
        Err(QemError::InvalidIndex { index: 999, .. })
    ));
}

#[test]
fn the_lock_is_serialized_only_when_there_is_one() {
    let plain = serde_json::to_string(&QemParams::default()).unwrap();
    assert!(!plain.contains("lock"), "{plain}");
    let border = locking(&QemParams::default(), Lock::Border);
    let text = serde_json::to_string(&border).unwrap();
    assert!(text.contains(r#""lock":"border""#), "{text}");
    let back: QemParams = serde_json::from_str(&text).unwrap();
    assert_eq!(back, border);
    let old: QemParams = serde_json::from_str(&plain).unwrap();
    assert_eq!(old.lock, Lock::None);
}

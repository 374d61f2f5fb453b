//! `QemParams::cancel`: a set flag makes every path of `simplify` (plain, with attributes,
//! locked) return `QemError::Cancelled` (before any work when set beforehand, within a pass when
//! set during a run), and a flag that is never set changes nothing.

use gng3d_qem::{Lock, QemError, QemParams, Target, simplify};
use mesh::Model;
use mesh::cancel::Cancel;
use std::time::{Duration, Instant};

fn params(cancel: &Cancel) -> QemParams {
    QemParams {
        cancel: Some(cancel.clone()),
        ..QemParams::with_target(Target::Ratio(0.1))
    }
}

#[test]
fn a_cancelled_flag_stops_every_entry_point_before_any_work() {
    let cancel = Cancel::default();
    cancel.cancel();
    let p = params(&cancel);
    let sphere = Model::from(mesh::procedural::icosphere(6)); // 40,962 vertices
    let (uv_sphere, uv) = mesh::procedural::textured_sphere(128, 256);
    let uv_sphere = Model {
        attributes: Some(uv),
        ..Model::from(uv_sphere)
    };
    let unlocked = |model: &Model| QemParams {
        lock: Lock::Vertices(vec![false; model.mesh.positions.len()]),
        ..p.clone()
    };
    let started = Instant::now();
    assert_eq!(simplify(&sphere, &p).unwrap_err(), QemError::Cancelled);
    assert_eq!(simplify(&uv_sphere, &p).unwrap_err(), QemError::Cancelled);
    assert_eq!(
        simplify(&sphere, &unlocked(&sphere)).unwrap_err(),
        QemError::Cancelled
    );
    assert_eq!(
        simplify(&uv_sphere, &unlocked(&uv_sphere)).unwrap_err(),
        QemError::Cancelled
    );
    assert!(
        started.elapsed() < Duration::from_millis(200),
        "{:?}",
        started.elapsed()
    );
}

#[test]
fn a_flag_set_during_a_run_stops_it_within_a_pass() {
    // 1.3 M faces: the partitioned engine on a pool of two threads or more, the sequential one
    // otherwise. The flag is set at a shrinking share of an uncancelled run's time until one run
    // sees it (`assert_stops_within`). The bound leaves room for the longest step without a check (the vertex
    // set-up of a part: ~0.3 s on a loaded two-core machine) and for a busy machine; within a
    // pass the flag is seen within 4,096 contractions.
    let big = Model::from(mesh::procedural::icosphere(8));
    mesh::cancel::assert_stops_within(
        |cancel| simplify(&big, &params(cancel)),
        QemError::Cancelled,
        Duration::from_millis(1000),
    );
}

#[test]
fn a_flag_never_set_changes_nothing() {
    let sphere = Model::from(mesh::procedural::icosphere(5));
    let (uv_sphere, uv) = mesh::procedural::textured_sphere(32, 64);
    let uv_sphere = Model {
        attributes: Some(uv),
        ..Model::from(uv_sphere)
    };
    let plain = QemParams::with_target(Target::Ratio(0.1));
    let watched = params(&Cancel::default());
    assert_eq!(
        simplify(&sphere, &plain).unwrap().0.mesh,
        simplify(&sphere, &watched).unwrap().0.mesh
    );
    let (m0, _) = simplify(&uv_sphere, &plain).unwrap();
    let (m1, _) = simplify(&uv_sphere, &watched).unwrap();
    assert_eq!((m0.mesh, m0.attributes), (m1.mesh, m1.attributes));
}

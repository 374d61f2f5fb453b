//! `QemParams::cancel`: a set flag makes every entry point return `QemError::Cancelled` (before
//! any work when set beforehand, within a pass when set during a run), and a flag that is never
//! set changes nothing.

use gng3d_qem::{QemError, QemParams, Target, simplify, simplify_locked, simplify_with_attributes};
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
    let sphere = mesh::procedural::icosphere(6); // 40,962 vertices
    let (uv_sphere, uv) = mesh::procedural::textured_sphere(128, 256);
    let started = Instant::now();
    assert_eq!(simplify(&sphere, &p).unwrap_err(), QemError::Cancelled);
    assert_eq!(
        simplify_with_attributes(&uv_sphere, &uv, &p).unwrap_err(),
        QemError::Cancelled
    );
    let unlocked = vec![false; sphere.positions.len()];
    assert_eq!(
        simplify_locked(&sphere, None, &p, &unlocked).unwrap_err(),
        QemError::Cancelled
    );
    let unlocked = vec![false; uv_sphere.positions.len()];
    assert_eq!(
        simplify_locked(&uv_sphere, Some(&uv), &p, &unlocked).unwrap_err(),
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
    // otherwise. The flag is set halfway through the time an uncancelled run takes here (a
    // fixed delay raced a fast machine: the run ended first), then a quarter, an eighth, until
    // one run sees it. The bound leaves room for the longest step without a check (the vertex
    // set-up of a part: ~0.3 s on a loaded two-core machine) and for a busy machine; within a
    // pass the flag is seen within 4,096 contractions.
    let big = mesh::procedural::icosphere(8);
    let started = Instant::now();
    simplify(&big, &QemParams::with_target(Target::Ratio(0.1))).unwrap();
    let whole = started.elapsed();
    let mut delay = whole / 2;
    for _ in 0..4 {
        let cancel = Cancel::default();
        let p = params(&cancel);
        let setter = cancel.clone();
        let timer = std::thread::spawn(move || {
            std::thread::sleep(delay);
            setter.cancel();
            Instant::now()
        });
        let result = simplify(&big, &p);
        let ended = Instant::now();
        let set = timer.join().unwrap();
        if result.is_ok() {
            delay /= 2;
            continue;
        }
        assert_eq!(result.unwrap_err(), QemError::Cancelled);
        let latency = ended.saturating_duration_since(set);
        println!("{latency:?} from the flag to the return (a whole run: {whole:?})");
        assert!(
            latency < Duration::from_millis(1000),
            "{latency:?} from the flag to the return"
        );
        return;
    }
    panic!("no run saw the flag (a whole run takes {whole:?})");
}

#[test]
fn a_flag_never_set_changes_nothing() {
    let sphere = mesh::procedural::icosphere(5);
    let (uv_sphere, uv) = mesh::procedural::textured_sphere(32, 64);
    let plain = QemParams::with_target(Target::Ratio(0.1));
    let watched = params(&Cancel::default());
    assert_eq!(
        simplify(&sphere, &plain).unwrap().0,
        simplify(&sphere, &watched).unwrap().0
    );
    let (m0, a0, _) = simplify_with_attributes(&uv_sphere, &uv, &plain).unwrap();
    let (m1, a1, _) = simplify_with_attributes(&uv_sphere, &uv, &watched).unwrap();
    assert_eq!((m0, a0), (m1, a1));
}

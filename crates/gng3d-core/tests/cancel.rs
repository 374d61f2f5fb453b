//! `finish_cancellable`: a set flag stops the steps after training with `GngError::Cancelled`
//! (before the first step, or at the next step when set during the run), and a flag never set
//! gives `finish`'s mesh.

use gng3d_core::{Cancel, GngError, GngOptions, GngTarget, Trainer, finish, finish_cancellable};
use std::time::{Duration, Instant};

/// A trained GNG3D-Q trainer (oversampled: its plan ends with the QEM decimation).
fn trained() -> Trainer {
    let sphere = mesh::procedural::icosphere(4);
    let options = GngOptions::for_target(GngTarget::Vertices(300));
    let mut trainer =
        Trainer::new(&sphere.clone().into(), options.resolve(&sphere).unwrap()).unwrap();
    while !trainer.is_finished() {
        trainer.step(u64::MAX);
    }
    trainer
}

#[test]
fn a_cancelled_flag_stops_finish_before_any_step() {
    let trainer = trained();
    let cancel = Cancel::default();
    cancel.cancel();
    let mut steps = 0;
    let started = Instant::now();
    let result = finish_cancellable(&trainer, &cancel, |_| steps += 1);
    assert_eq!(result.unwrap_err(), GngError::Cancelled);
    assert_eq!(steps, 0);
    assert!(started.elapsed() < Duration::from_millis(100));
}

#[test]
fn a_flag_set_during_finish_stops_it_at_the_next_step() {
    let trainer = trained();
    let cancel = Cancel::default();
    let setter = cancel.clone();
    let mut steps = 0;
    let result = finish_cancellable(&trainer, &cancel, |_| {
        steps += 1;
        setter.cancel();
    });
    assert_eq!(result.unwrap_err(), GngError::Cancelled);
    assert_eq!(steps, 1);
}

#[test]
fn a_flag_never_set_gives_finish_s_mesh() {
    let trainer = trained();
    let plain = finish(&trainer, |_| {}).unwrap();
    let watched = finish_cancellable(&trainer, &Cancel::default(), |_| {}).unwrap();
    assert_eq!(plain.mesh, watched.mesh);
    assert_eq!(plain.report.warnings, watched.report.warnings);
}

#[test]
fn the_trainer_s_token_is_the_workspace_s_cancel_flag() {
    let trainer = trained();
    let token: Cancel = trainer.cancel_token();
    assert!(!token.is_cancelled());
}

//! `evaluate_cancellable` and `Surface::with_cancel`: a set flag returns
//! `MetricsError::Cancelled` (quickly, before the work or within a batch of samples), and a
//! flag never set gives the figures of the plain calls.

use gng3d_metrics::{
    HausdorffParams, ImageErrorParams, MetricsError, MetricsParams, Surface, evaluate,
    evaluate_cancellable, image_error,
};
use mesh::cancel::Cancel;
use std::time::{Duration, Instant};

fn pair() -> (mesh::TriMesh, mesh::TriMesh) {
    (
        mesh::procedural::icosphere(6),
        mesh::procedural::icosphere(3),
    )
}

#[test]
fn a_cancelled_flag_stops_evaluate_and_the_image_error() {
    let (original, simplified) = pair();
    let cancel = Cancel::default();
    cancel.cancel();
    let started = Instant::now();
    let params = MetricsParams::default();
    assert_eq!(
        evaluate_cancellable(&original, &simplified, &params, &cancel).unwrap_err(),
        MetricsError::Cancelled
    );
    let watched = Surface::new(&original).with_cancel(&cancel);
    assert_eq!(
        image_error(
            &watched,
            &Surface::new(&simplified),
            &ImageErrorParams::default()
        )
        .unwrap_err(),
        MetricsError::Cancelled
    );
    // Either side's flag counts.
    let watched = Surface::new(&simplified).with_cancel(&cancel);
    assert_eq!(
        image_error(
            &Surface::new(&original),
            &watched,
            &ImageErrorParams::default()
        )
        .unwrap_err(),
        MetricsError::Cancelled
    );
    assert!(started.elapsed() < Duration::from_millis(100));
}

#[test]
fn a_flag_set_during_evaluate_stops_it_within_a_batch() {
    let (original, simplified) = pair();
    // Far more samples than a batch (seconds of queries). The flag is set at a shrinking share
    // of an uncancelled run's time until one run sees it (`assert_stops_within`).
    let params = MetricsParams {
        hausdorff: HausdorffParams::with_samples(4_000_000),
    };
    mesh::cancel::assert_stops_within(
        |cancel| evaluate_cancellable(&original, &simplified, &params, cancel),
        MetricsError::Cancelled,
        Duration::from_millis(1000),
    );
}

#[test]
fn a_flag_never_set_changes_no_figure() {
    let (original, simplified) = pair();
    let params = MetricsParams {
        hausdorff: HausdorffParams::with_samples(20_000),
    };
    let cancel = Cancel::default();
    let plain = evaluate(&original, &simplified, &params).unwrap();
    let watched = evaluate_cancellable(&original, &simplified, &params, &cancel).unwrap();
    assert_eq!(plain.hausdorff, watched.hausdorff);
    assert_eq!((plain.e_avg, plain.e_max), (watched.e_avg, watched.e_max));
    let image = ImageErrorParams {
        size: 64,
        ..ImageErrorParams::default()
    };
    let a = image_error(&Surface::new(&original), &Surface::new(&simplified), &image).unwrap();
    let b = image_error(
        &Surface::new(&original).with_cancel(&cancel),
        &Surface::new(&simplified),
        &image,
    )
    .unwrap();
    assert_eq!(a.overall, b.overall);
}

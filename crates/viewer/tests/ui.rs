//! egui_kittest harness tests with the wgpu renderer (lavapipe in CI, no X server needed): the
//! viewports render the model, controls change state, the plots fill while training runs.

use egui_kittest::kittest::Queryable;
use egui_kittest::{Harness, wgpu::WgpuTestRenderer};
use std::time::{Duration, Instant};
use viewer::app::Side;
use viewer::render::Shading;
use viewer::{ViewerApp, ViewerOptions};

/// Window size of the harness, in points (pixels_per_point = 1).
const SIZE: egui::Vec2 = egui::vec2(1400.0, 900.0);

/// A harness around the app with a wgpu render state shared by the app and the snapshot
/// renderer; `None` (skip) when no wgpu adapter exists, except under CI where that fails.
fn harness(options: ViewerOptions) -> Option<Harness<'static, ViewerApp>> {
    let render_state = std::panic::catch_unwind(|| {
        egui_kittest::wgpu::create_render_state(
            egui_kittest::wgpu::default_wgpu_setup(),
            egui_wgpu::RendererOptions::PREDICTABLE,
        )
    });
    let render_state = match render_state {
        Ok(rs) => rs,
        Err(_) if std::env::var_os("CI").is_some() => {
            panic!("CI: no wgpu adapter (install mesa-vulkan-drivers for lavapipe)")
        }
        Err(_) => {
            eprintln!("skipping: no wgpu adapter (install mesa-vulkan-drivers)");
            return None;
        }
    };
    let app = ViewerApp::new(
        &egui::Context::default(),
        Some(render_state.clone()),
        options,
    );
    Some(
        Harness::builder()
            .with_size(SIZE)
            .renderer(WgpuTestRenderer::from_render_state(render_state))
            .build_ui_state(|ui, app: &mut ViewerApp| app.show(ui), app),
    )
}

/// Step frames until `done` holds (panics after `timeout`).
fn step_until(
    harness: &mut Harness<'static, ViewerApp>,
    timeout: Duration,
    what: &str,
    done: impl Fn(&ViewerApp) -> bool,
) {
    let start = Instant::now();
    loop {
        harness.step();
        if done(harness.state()) {
            return;
        }
        assert!(start.elapsed() < timeout, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A harness whose QEM result exists and whose network has grown to `target` nodes (`None`: no
/// wgpu adapter, see [`harness`]).
fn trained_harness(target: usize) -> Option<Harness<'static, ViewerApp>> {
    let mut h = harness(ViewerOptions {
        target: Some(target),
        ..Default::default()
    })?;
    step_until(
        &mut h,
        Duration::from_secs(60),
        "QEM result and a trained network",
        |a| a.has_qem_mesh() && a.live().snapshot.positions.len() >= target,
    );
    Some(h)
}

/// Pixels in `rect` (points = pixels here) below the label strip that differ by more than a few
/// levels from the background (read at the bottom-right corner, which the framed model never
/// reaches), and the number of pixels examined.
fn count_drawn(image: &image::RgbaImage, rect: egui::Rect) -> (usize, usize) {
    let clear = image
        .get_pixel(rect.max.x as u32 - 3, rect.max.y as u32 - 3)
        .0;
    // The background is the renderer's clear colour (render::CLEAR_COLOR): dark, slightly blue.
    assert!(
        clear[2] >= clear[0] && clear[0] < 60,
        "unexpected background {clear:?}"
    );
    let (mut drawn, mut total) = (0, 0);
    let y0 = rect.min.y as u32 + 30; // skip the text label in the top-left corner
    for y in y0..(rect.max.y as u32).min(image.height()) {
        for x in (rect.min.x as u32)..(rect.max.x as u32).min(image.width()) {
            let p = image.get_pixel(x, y).0;
            total += 1;
            if (0..3).any(|c| p[c].abs_diff(clear[c]) > 6) {
                drawn += 1;
            }
        }
    }
    (drawn, total)
}

/// Save the current frame under `$VIEWER_TEST_SNAPSHOTS` (for looking at it), if set.
fn save_snapshot(h: &mut Harness<'static, ViewerApp>, name: &str) {
    if let Some(dir) = std::env::var_os("VIEWER_TEST_SNAPSHOTS") {
        let image = h.render().expect("render");
        image.save(std::path::Path::new(&dir).join(name)).unwrap();
    }
}

#[test]
fn model_renders_in_both_viewports() {
    let Some(mut h) = trained_harness(300) else {
        return;
    };
    h.step();
    save_snapshot(&mut h, "model_renders_in_both_viewports.png");
    let image = h.render().expect("render");
    let app = h.state();
    let [Some(left), Some(right)] = app.viewport_rects else {
        panic!("viewports were not laid out");
    };
    assert!(left.width() > 300.0 && right.width() > 300.0);
    for (side, rect) in [("GNG3D", left), ("QEM", right)] {
        let (drawn, total) = count_drawn(&image, rect);
        let share = drawn as f64 / total as f64;
        // The framed model covers a good part of the view but not all of it: both a model and
        // the clear colour must be visible.
        assert!(
            share > 0.03,
            "{side} viewport nearly empty: {drawn}/{total} pixels drawn"
        );
        assert!(
            share < 0.9,
            "{side} viewport has no background: {drawn}/{total}"
        );
    }
    assert!(app.viewport_texture(Side::Gng).is_some());
    // The QEM side is a real simplification at the requested vertex count.
    let qem = app.history.qem.as_ref().expect("QEM row");
    assert!(
        qem.vertices <= 300 && qem.vertices > 200,
        "QEM vertices {}",
        qem.vertices
    );
    assert!(qem.faces > 0 && qem.faces < app.original().face_count());
}

#[test]
fn unchanged_viewports_are_reused_and_a_camera_move_redraws_them() {
    let Some(mut h) = trained_harness(200) else {
        return;
    };
    h.state_mut().set_running(false);
    // Let the last snapshot of the running trainer arrive and the panel layout settle: then a
    // frame redraws neither viewport.
    let mut settled = 0;
    for _ in 0..200 {
        let redraws = h.state().stats.viewport_redraws;
        h.step();
        settled = if h.state().stats.viewport_redraws == redraws {
            settled + 1
        } else {
            0
        };
        if settled == 3 {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(settled, 3, "the viewports never stopped redrawing");
    let before = h.state().stats.viewport_redraws;
    let image_before = h.render().expect("render");
    for _ in 0..3 {
        h.step();
    }
    assert_eq!(
        h.state().stats.viewport_redraws,
        before,
        "an unchanged scene must not be redrawn (paused: {})",
        h.state().live().running
    );
    let image_still = h.render().expect("render");
    let right = h.state().viewport_rects[1].expect("QEM viewport");
    let differing = |a: &image::RgbaImage, b: &image::RgbaImage| {
        let mut n = 0;
        for y in right.min.y as u32 + 30..right.max.y as u32 {
            for x in right.min.x as u32..right.max.x as u32 {
                let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
                n += usize::from((0..3).any(|c| p[c].abs_diff(q[c]) > 6));
            }
        }
        n
    };
    assert_eq!(
        differing(&image_before, &image_still),
        0,
        "the reused viewport must show the same image"
    );
    // Orbit by a quarter turn: both viewports are redrawn once and the QEM view changes.
    h.state_mut().camera.orbit(300.0, 0.0);
    h.step();
    let after = h.state().stats.viewport_redraws;
    assert_eq!([after[0] - before[0], after[1] - before[1]], [1, 1]);
    let image_after = h.render().expect("render");
    let changed = differing(&image_before, &image_after);
    assert!(
        changed > 500,
        "orbiting changed only {changed} pixels of the QEM view"
    );
}

#[test]
fn controls_change_state() {
    let Some(mut h) = harness(ViewerOptions {
        target: Some(200),
        ..Default::default()
    }) else {
        return;
    };
    // Effectively unlimited training so Play/Pause have something to act on.
    h.state_mut().params.max_signals = Some(u64::MAX / 4);
    h.state_mut().reset_training();
    step_until(&mut h, Duration::from_secs(30), "training to run", |a| {
        a.live().running && a.live().snapshot.signals > 0
    });

    h.get_by_label("Pause").click();
    step_until(&mut h, Duration::from_secs(10), "pause", |a| {
        !a.live().running
    });
    let paused_at = h.state().live().snapshot.signals;
    for _ in 0..5 {
        h.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(
        h.state().live().snapshot.signals,
        paused_at,
        "training continued while paused"
    );

    h.get_by_label("Step").click();
    step_until(&mut h, Duration::from_secs(10), "a step", |a| {
        a.live().snapshot.signals > paused_at
    });
    assert!(!h.state().live().running);

    h.get_by_label("Play").click();
    step_until(&mut h, Duration::from_secs(10), "play", |a| {
        a.live().running
    });

    assert_eq!(h.state().display.shading, Shading::Smooth);
    h.get_by_label("flat").click();
    h.step();
    assert_eq!(h.state().display.shading, Shading::Flat);
    assert!(!h.state().display.wireframe);
    h.get_by_label("wireframe").click();
    h.step();
    assert!(h.state().display.wireframe);
    assert!(!h.state().display.show_original);
    h.get_by_label("original overlay").click();
    h.step();
    assert!(h.state().display.show_original);
    save_snapshot(&mut h, "flat_wireframe_overlay.png");

    let session = h.state().live().session;
    h.get_by_label("Reset").click();
    step_until(&mut h, Duration::from_secs(10), "a new session", |a| {
        a.live().session > session
    });

    // A new vertex target recomputes QEM at that size.
    h.state_mut().set_target(150);
    step_until(
        &mut h,
        Duration::from_secs(60),
        "QEM at 150 vertices",
        |a| a.history.qem.as_ref().is_some_and(|q| q.vertices <= 150),
    );
    assert_eq!(h.state().params.target_vertices, 150);
}

#[test]
fn plot_gains_points_as_training_runs() {
    let Some(mut h) = harness(ViewerOptions {
        target: Some(400),
        ..Default::default()
    }) else {
        return;
    };
    h.state_mut().params.max_signals = Some(u64::MAX / 4);
    h.state_mut().reset_training();
    step_until(&mut h, Duration::from_secs(30), "first error points", |a| {
        a.history.errors.len() >= 2
    });
    let first = h.state().history.errors.len();
    step_until(&mut h, Duration::from_secs(30), "more error points", |a| {
        a.history.errors.len() >= first + 3
    });
    let errors = &h.state().history.errors;
    assert!(
        errors.windows(2).all(|w| w[0][0] < w[1][0]),
        "iterations not increasing"
    );
    assert!(
        errors.iter().all(|e| e[1] > 0.0 && e[2] >= e[1]),
        "E_max < E_avg somewhere"
    );
    // The network approaches the surface: the last E_avg is below the first one.
    assert!(errors.last().unwrap()[1] < errors[0][1]);

    // "Reconstruct now" adds an evaluated checkpoint row.
    h.get_by_label("Reconstruct now").click();
    step_until(&mut h, Duration::from_secs(60), "a checkpoint row", |a| {
        !a.history.reconstructions.is_empty()
    });
    let row = h.state().history.reconstructions[0].clone();
    assert!(row.vertices <= 400 && row.faces > 0, "{row:?}");
    assert!(row.e_sur >= 0.0 && row.e_avg > 0.0);
    let csv = h.state().history.csv_string().unwrap();
    assert!(csv.lines().count() >= 2, "{csv}");
}

#[test]
fn bad_files_show_an_error_and_exports_round_trip() {
    let Some(mut h) = harness(ViewerOptions {
        target: Some(250),
        ..Default::default()
    }) else {
        return;
    };
    step_until(
        &mut h,
        Duration::from_secs(60),
        "QEM and a reconstruction",
        |a| a.has_qem_mesh() && a.live().finished && !a.history.reconstructions.is_empty(),
    );
    let dir = tempfile::tempdir().unwrap();
    let faces_before = h.state().original().face_count();

    // A missing file and a garbage file: an error message, the model stays.
    let garbage = dir.path().join("garbage.obj");
    std::fs::write(&garbage, "v 1 2\nf 1 2 99\nthis is not obj\n").unwrap();
    for path in [dir.path().join("missing.obj"), garbage.clone()] {
        let errors = h.state().messages.iter().filter(|m| m.is_error).count();
        h.state_mut().open_path(path.clone());
        step_until(&mut h, Duration::from_secs(20), "the load to fail", |a| {
            !a.is_loading()
        });
        let app = h.state();
        assert_eq!(app.original().face_count(), faces_before);
        let new_errors: Vec<_> = app.messages.iter().filter(|m| m.is_error).collect();
        assert_eq!(new_errors.len(), errors + 1, "{:?}", app.messages);
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            new_errors.last().unwrap().text.contains(&name),
            "{:?}",
            new_errors
        );
    }

    // Exports write files that load back with the same counts.
    for (side, file) in [(Side::Qem, "qem.ply"), (Side::Gng, "gng.obj")] {
        let path = dir.path().join(file);
        h.state_mut().export(side, &path).unwrap();
        let back = mesh::io::load(&path).unwrap().mesh;
        let expected = match side {
            Side::Qem => h.state().history.qem.clone().unwrap(),
            Side::Gng => h.state().history.reconstructions.last().cloned().unwrap(),
        };
        assert_eq!(back.face_count(), expected.faces, "{file}");
    }
    // Exporting into a missing directory is an error, not a panic.
    assert!(
        h.state_mut()
            .export(Side::Qem, &dir.path().join("no/such/dir/x.obj"))
            .is_err()
    );

    // A real file opens and replaces the model.
    let good = dir.path().join("sphere.obj");
    let sphere = mesh::procedural::icosphere(2);
    mesh::io::save(&sphere, &good).unwrap();
    h.state_mut().open_path(good);
    step_until(&mut h, Duration::from_secs(20), "the sphere to load", |a| {
        !a.is_loading()
    });
    assert_eq!(h.state().original().face_count(), sphere.face_count());
    assert_eq!(h.state().model_name, "sphere.obj");
}

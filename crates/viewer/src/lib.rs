//! gng3d viewer: watch a GNG3D network learn a mesh next to Garland-Heckbert QEM at the same
//! vertex count, with live error plots in the style of the GNG3D paper.
//!
//! The application is [`app::ViewerApp`]; [`run`] opens it in an eframe window with the wgpu
//! renderer. Tests build the app directly against an `egui_kittest` harness.

pub mod app;
pub mod engine;
pub mod io;
pub mod plots;
pub mod render;
pub mod worker;

pub use app::{ViewerApp, ViewerOptions};

/// Train without a window for `options.quit_after` seconds (default 5) on the same worker thread
/// the viewer uses, and return a one-line summary with the mean signals/s (the headless baseline
/// for the viewer's throughput target).
pub fn run_headless(options: &ViewerOptions) -> Result<String, String> {
    use std::sync::Arc;
    use std::time::{Duration, Instant};
    let (name, mesh) = match &options.path {
        Some(path) => {
            let loaded = engine::load_mesh(path)?;
            (path.display().to_string(), loaded.mesh)
        }
        None => engine::default_model(),
    };
    let mut params = engine::default_params(options.target.unwrap_or(1000));
    params.max_signals = options.max_signals;
    params.lambda = options.lambda;
    params.time_limit = options.time_limit.map(Duration::from_secs_f64);
    if let Some(seed) = options.seed {
        params.seed = seed;
    }
    let trainer = worker::Trainer::spawn();
    trainer.send(worker::Command::Reset(Box::new(worker::Session {
        mesh: Arc::new(mesh),
        params,
        checkpoint_every: None,
        autoplay: true,
    })));
    let seconds = options.quit_after.unwrap_or(5.0);
    let start = Instant::now();
    let mut rates = Vec::new();
    let mut live = trainer.live();
    while start.elapsed().as_secs_f64() < seconds {
        std::thread::sleep(Duration::from_millis(16));
        let _ = trainer.drain_events();
        live = trainer.live();
        if live.running && live.signals_per_second > 0.0 && start.elapsed().as_secs_f64() > 1.0 {
            rates.push(live.signals_per_second);
        }
    }
    let mean = if rates.is_empty() {
        0.0
    } else {
        rates.iter().sum::<f64>() / rates.len() as f64
    };
    Ok(format!(
        "headless stats: model={name} nodes={} signals={} mean_signals_per_s={mean:.0} train_s={:.2}",
        live.snapshot.positions.len(),
        live.snapshot.signals,
        live.train_seconds
    ))
}

/// Open the viewer window and run until it is closed.
pub fn run(options: ViewerOptions) -> Result<(), String> {
    let mut wgpu_options = egui_wgpu::WgpuConfiguration::default();
    wgpu_options.surface.present_mode = wgpu::PresentMode::AutoNoVsync;
    let native = eframe::NativeOptions {
        wgpu_options,
        renderer: eframe::Renderer::Wgpu,
        // Frames are paced by the app (at most 40 fps while training); on a CPU rasterizer
        // vsync waits and dithering only cost time.
        dithering: false,
        viewport: egui::ViewportBuilder::default()
            .with_title("gng3d viewer — GNG3D vs QEM")
            .with_inner_size(options.window_size.unwrap_or([1600.0, 900.0]))
            .with_drag_and_drop(true),
        ..Default::default()
    };
    eframe::run_native(
        "gng3d viewer",
        native,
        Box::new(move |cc| {
            Ok(Box::new(ViewerApp::new(
                &cc.egui_ctx,
                cc.wgpu_render_state.clone(),
                options,
            )))
        }),
    )
    .map_err(|e| e.to_string())
}

//! gng3d viewer: watch a GNG3D network learn a mesh next to Garland-Heckbert QEM at the same
//! vertex count, with live error plots in the style of the GNG3D paper.
//!
//! [`session::Session`] holds everything that is not UI (model, training thread, QEM,
//! evaluations, plot history) and is tested without a window; [`app::ViewerApp`] draws it.
//! [`run`] opens the app in an eframe window with the wgpu renderer (Vulkan, Metal, DX12 or
//! OpenGL, whatever the adapter offers); tests build the app against an `egui_kittest` harness.

pub mod app;
pub mod automation;
pub mod camera;
pub mod diagnostics;
pub mod engine;
pub mod error;
pub mod io;
pub mod jobs;
pub mod layout;
pub mod panels;
pub mod plots;
pub mod render;
pub mod scene;
pub mod session;
pub mod shortcuts;
pub mod steps;
pub mod worker;

pub use app::{PanelRects, ViewerApp};
pub use error::ViewerError;
pub use session::{Session, ViewerOptions};

/// Train without a window, at full speed, on the same worker thread and with the same defaults
/// as the window (the vertex target of [`session::default_target`], a checkpoint every |V|
/// signals), until the run's final mesh is built, or for `options.quit_after` seconds when
/// given; return a one-line summary with the mean signals/s (the headless baseline for the
/// viewer's throughput target). Options are validated by the same [`session::train_params`] as
/// in the window.
pub fn run_headless(options: &ViewerOptions) -> error::Result<String> {
    use std::sync::Arc;
    use std::time::{Duration, Instant};
    let mut params = session::train_params(options)?;
    let (name, mesh, attributes, place) = match &options.path {
        Some(path) => {
            let loaded = engine::load_mesh(path)?;
            let attributes = loaded.attributes.map(Arc::new);
            (
                path.display().to_string(),
                loaded.mesh,
                attributes,
                loaded.place,
            )
        }
        None => {
            let (name, mesh) = engine::default_model();
            (name, mesh, None, mesh::Model::default())
        }
    };
    let vertices = mesh.vertex_count();
    if options.target.is_none() {
        params.target_vertices = session::default_target(vertices);
    }
    let target = params.target_vertices;
    let trainer = worker::Trainer::spawn();
    trainer.send(worker::Command::Reset(Box::new(worker::TrainingJob {
        mesh: Arc::new(mesh),
        attributes,
        place: Arc::new(place),
        params,
        checkpoint_every: match options.checkpoint_every {
            Some(0) => None,
            Some(every) => Some(every),
            None => Some(vertices as u64),
        },
        autoplay: true,
    })));
    let limit = options.quit_after.map(Duration::from_secs_f64);
    let start = Instant::now();
    let mut rates = Vec::new();
    let mut live = trainer.live();
    let mut run_seconds = None;
    let mut mesh_vertices = None;
    while limit.is_none_or(|l| start.elapsed() < l) && mesh_vertices.is_none() {
        std::thread::sleep(Duration::from_millis(16));
        // A run that cannot start (a target above the vertex count) is an error, not a
        // summary of zero nodes with exit 0.
        for event in trainer.drain_events() {
            match event {
                worker::Event::Failed { message, .. } => {
                    return Err(error::ViewerError::Gng(message));
                }
                worker::Event::PipelineDone { run_seconds: s, .. } => run_seconds = Some(s),
                worker::Event::Reconstructed { mesh, .. } if run_seconds.is_some() => {
                    mesh_vertices = Some(mesh.vertex_count());
                }
                _ => {}
            }
        }
        live = trainer.live();
        if live.running && live.signals_per_second > 0.0 && start.elapsed().as_secs_f64() > 1.0 {
            rates.push(live.signals_per_second);
        }
    }
    let mean = if !rates.is_empty() {
        rates.iter().sum::<f64>() / rates.len() as f64
    } else if live.train_seconds > 0.0 {
        // Training ended within the warm-up: the whole run's rate.
        live.snapshot.signals as f64 / live.train_seconds
    } else {
        0.0
    };
    let shown = |v: Option<String>| v.unwrap_or_else(|| "none".into());
    Ok(format!(
        "headless stats: model={name} target={target} nodes={} signals={} \
         mean_signals_per_s={mean:.0} train_s={:.2} run_s={} mesh_vertices={}",
        live.snapshot.positions.len(),
        live.snapshot.signals,
        live.train_seconds,
        shown(run_seconds.map(|s| format!("{s:.2}"))),
        shown(mesh_vertices.map(|v| v.to_string())),
    ))
}

/// Open the viewer window and run until it is closed. Options are validated before the window
/// opens.
pub fn run(options: ViewerOptions) -> error::Result<()> {
    session::train_params(&options)?;
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
            let app = ViewerApp::new(&cc.egui_ctx, cc.wgpu_render_state.clone(), options)?;
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| ViewerError::Window(e.to_string()))?;
    // A scripted run whose screenshot failed ends with an error (non-zero exit), not 0.
    match automation::take_scripted_failure() {
        Some(message) => Err(ViewerError::Window(message)),
        None => Ok(()),
    }
}

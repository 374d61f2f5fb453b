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

/// Open the viewer window and run until it is closed.
pub fn run(options: ViewerOptions) -> Result<(), String> {
    let native = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default()
            .with_title("gng3d viewer — GNG3D vs QEM")
            .with_inner_size([1600.0, 900.0])
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

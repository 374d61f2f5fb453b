//! Frame rate of a bare eframe window (wgpu renderer) whose central panel fills the window: the
//! floor under the viewer's own frame cost on the machine's renderer. Used to measure the
//! vendored egui-wgpu shader patch (see `vendor/README.md`).
//!
//! `cargo run --release -p viewer --example bare_window -- [WIDTHxHEIGHT] [SECONDS]`
//! (default 1280x720, 6 s); prints `bare window: WxH fps=…` and exits.

use std::time::Instant;

/// Counts frames and quits after the requested time.
struct BareWindow {
    started: Instant,
    frames: u64,
    seconds: f64,
    label: String,
}

impl eframe::App for BareWindow {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frames += 1;
        let elapsed = self.started.elapsed().as_secs_f64();
        if elapsed > self.seconds {
            println!(
                "bare window: {} fps={:.1}",
                self.label,
                self.frames as f64 / elapsed
            );
            std::process::exit(0);
        }
        egui::CentralPanel::default().show(ui, |ui| {
            ui.label(format!("frame {}", self.frames));
        });
        ui.ctx().request_repaint();
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size = args.first().map_or("1280x720", String::as_str);
    let Some((width, height)) = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<f32>().ok()?, h.parse::<f32>().ok()?)))
    else {
        eprintln!("error: window size must look like 1280x720, got {size:?}");
        std::process::exit(2);
    };
    let seconds = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(6.0);
    let mut wgpu_options = egui_wgpu::WgpuConfiguration::default();
    wgpu_options.surface.present_mode = wgpu::PresentMode::AutoNoVsync;
    let native = eframe::NativeOptions {
        wgpu_options,
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default().with_inner_size([width, height]),
        ..Default::default()
    };
    let label = size.to_string();
    let result = eframe::run_native(
        "bare window",
        native,
        Box::new(move |_cc| {
            Ok(Box::new(BareWindow {
                started: Instant::now(),
                frames: 0,
                seconds,
                label,
            }))
        }),
    );
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

//! The window: [`ViewerApp`] owns the UI-free [`Session`], the viewports' GPU [`Scene`], the
//! shared camera and the display toggles, and draws one frame per [`ViewerApp::show`]. Background
//! work is polled in [`eframe::App::logic`] (in tests, at the start of `show`). The panels live in
//! [`crate::panels`], keyboard shortcuts in [`crate::shortcuts`], screenshot-and-quit automation in
//! [`crate::automation`], frame statistics in [`crate::diagnostics`], the display toggles and the
//! panels' layout state in [`crate::layout`].

use crate::automation::Automation;
use crate::camera::OrbitCamera;
use crate::diagnostics::FrameStats;
use crate::error::Result;
use crate::io::{DialogPurpose, Dialogs};
use crate::layout::ControlsStart;
pub use crate::layout::{Display, PanelRects, Panels};
use crate::scene::Scene;
use crate::session::{Session, Side, ViewerOptions};
use egui::Color32;
use egui_wgpu::RenderState;
use std::path::PathBuf;
use std::time::Instant;

/// The viewer application.
pub struct ViewerApp {
    /// Everything that is not UI: model, training, QEM, evaluations, history, messages.
    pub session: Session,
    pub(crate) scene: Option<Scene>,
    /// The shared camera.
    pub camera: OrbitCamera,
    /// Display toggles.
    pub display: Display,
    /// Open panels (`None` until the first frame knows the window size).
    pub panels: Option<Panels>,
    pub(crate) dialogs: Dialogs,
    /// Frame statistics.
    pub stats: FrameStats,
    pub(crate) started: Instant,
    pub(crate) automation: Automation,
    /// Screen rectangles of the two viewports in the last frame (GNG3D, QEM), in points.
    pub viewport_rects: [Option<egui::Rect>; 2],
    /// Where Table 1 was laid out in the last frame (`None`: not shown).
    pub table_layout: Option<crate::plots::TableLayout>,
    /// Height of the step strip in the last frame, points (the plots' height cap counts it).
    pub(crate) strip_height: f32,
    /// Where the panels were drawn in the last frame.
    pub panel_rects: PanelRects,
    /// Width of the parameter panel's rows in the last frame, points.
    pub(crate) controls_width: f32,
    /// Whether the first frame has decided if the parameter panel starts open.
    pub(crate) controls_start: ControlsStart,
    /// The model the camera was last framed on (re-framed when the session replaces it).
    framed: Option<std::sync::Arc<mesh::TriMesh>>,
    /// The context that draws (for screenshots requested outside a frame).
    pub(crate) automation_ctx: Option<egui::Context>,
    ctx_bound: bool,
    polled_this_frame: bool,
}

impl ViewerApp {
    /// Create the app: validates `options` (an error names the bad option), starts the session.
    /// `render_state` is eframe's (or a test harness') wgpu state; without it the viewports show
    /// a note instead of the models.
    pub fn new(
        ctx: &egui::Context,
        render_state: Option<RenderState>,
        options: ViewerOptions,
    ) -> Result<ViewerApp> {
        let session = Session::new(options, Some(ctx.clone()))?;
        Ok(ViewerApp {
            session,
            scene: render_state.map(Scene::new),
            camera: OrbitCamera::default(),
            display: Display::default(),
            panels: None,
            dialogs: Dialogs::default(),
            stats: FrameStats::default(),
            started: Instant::now(),
            automation: Automation::default(),
            viewport_rects: [None, None],
            table_layout: None,
            strip_height: crate::layout::STRIP_HEIGHT_GUESS,
            panel_rects: PanelRects::default(),
            controls_width: 0.0,
            controls_start: ControlsStart::Undecided,
            framed: None,
            automation_ctx: Some(ctx.clone()),
            ctx_bound: false,
            polled_this_frame: false,
        })
    }

    /// The graphics backend drawing the viewports (`None` without a renderer).
    pub fn backend(&self) -> Option<wgpu::Backend> {
        self.scene.as_ref().map(Scene::backend)
    }

    /// The offscreen colour texture of a viewport (for tests).
    pub fn viewport_texture(&self, side: Side) -> Option<&wgpu::Texture> {
        Some(self.scene.as_ref()?.color_texture(side as usize))
    }

    /// The size in texels of the model's base-colour texture as uploaded for the viewports
    /// (`None` without one or without a renderer; for tests).
    pub fn model_texture_size(&self) -> Option<[u32; 2]> {
        self.scene.as_ref()?.texture_size()
    }

    /// Frame the camera on the whole model.
    pub fn reset_camera(&mut self) {
        self.camera = OrbitCamera::framing(&self.session.original().referenced_bounding_box());
    }

    /// Open a file dialog for `purpose` (native, or the in-app picker where there is none).
    pub fn open_dialog(&mut self, purpose: DialogPurpose) {
        let name = match purpose {
            DialogPurpose::OpenMesh => "",
            DialogPurpose::ExportGng => "gng3d.obj",
            DialogPurpose::ExportQem => "qem.obj",
            DialogPurpose::ExportCsv => "checkpoints.csv",
            DialogPurpose::Screenshot => "viewer.png",
        };
        self.dialogs.open(purpose, name);
    }

    fn handle_dialog(&mut self, purpose: DialogPurpose, path: PathBuf) {
        // Errors are already in the message strip (the session reports them).
        match purpose {
            DialogPurpose::OpenMesh => self.session.open_path(path),
            DialogPurpose::ExportGng => {
                let _ = self.session.export(Side::Gng, &path);
            }
            DialogPurpose::ExportQem => {
                let _ = self.session.export(Side::Qem, &path);
            }
            DialogPurpose::ExportCsv => {
                let _ = self.session.export_csv(&path);
            }
            DialogPurpose::Screenshot => self.request_screenshot(path),
        }
    }

    /// Collect background results: the session's jobs and the file dialogs. Idempotent within a
    /// frame (eframe calls it from `logic`, test harnesses through `show`).
    pub fn poll(&mut self, ctx: &egui::Context) {
        if !self.ctx_bound {
            // The context given at construction may not be the one that draws (test harnesses).
            self.session.set_repaint_context(ctx);
            self.automation_ctx = Some(ctx.clone());
            self.ctx_bound = true;
        }
        self.session.poll();
        if self
            .framed
            .as_ref()
            .is_none_or(|m| !std::sync::Arc::ptr_eq(m, self.session.original()))
        {
            self.reset_camera();
            self.framed = Some(std::sync::Arc::clone(self.session.original()));
        }
        if let Some(message) = self.dialogs.take_notice() {
            self.session.info(message);
        }
        if let Some((purpose, Some(path))) = self.dialogs.poll() {
            self.handle_dialog(purpose, path);
        }
        self.polled_this_frame = true;
    }

    /// Draw one frame.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        if !std::mem::take(&mut self.polled_this_frame) {
            self.poll(&ctx);
        }
        if ctx.tessellation_options(|o| o.feathering) != self.display.smooth_ui {
            ctx.tessellation_options_mut(|o| o.feathering = self.display.smooth_ui);
        }
        // Dragging a panel edge or a plot must not start selecting label text.
        ui.style_mut().interaction.selectable_labels = false;
        let since_start = self.started.elapsed().as_secs_f64();
        self.stats.tick(since_start);
        let live = self.session.live().clone();
        if live.running {
            self.stats.record_training(
                since_start,
                live.snapshot.positions.len(),
                live.signals_per_second,
            );
            ctx.request_repaint_after(crate::worker::TRAINING_FRAME_INTERVAL);
        }
        if let Some(path) = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .find_map(|f| Some(f.path().to_path_buf()).filter(|p| !p.as_os_str().is_empty()))
        }) {
            self.session.open_path(path);
        }
        self.shortcuts(&ctx);
        self.layout(ui);
        self.dialogs.show_fallback(&ctx);
        self.help_overlay(&ctx);
        self.automation(&ctx);
    }

    /// Save a PNG of the whole window to `path` once the next frame is rendered.
    pub fn request_screenshot(&self, path: PathBuf) {
        if let Some(ctx) = &self.automation_ctx {
            self.automation.request_screenshot(ctx, path);
        }
    }

    /// Screenshot-and-quit automation ([`Automation::update`]); closing prints the
    /// [`ViewerApp::summary`] with `--stats`.
    fn automation(&mut self, ctx: &egui::Context) {
        self.automation_ctx = Some(ctx.clone());
        let elapsed = self.started.elapsed().as_secs_f64();
        if self.automation.update(ctx, &mut self.session, elapsed) && self.automation.begin_close()
        {
            if self.session.options().print_stats {
                println!("{}", self.summary());
            }
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    /// The one-line `viewer stats:` summary ([`crate::automation::summary`]).
    pub fn summary(&self) -> String {
        let ppp = self
            .automation_ctx
            .as_ref()
            .map_or(1.0, egui::Context::pixels_per_point);
        crate::automation::summary(
            &self.session,
            &self.stats,
            self.backend(),
            self.viewport_rects,
            ppp,
        )
    }

    /// The central viewports: allocate, handle camera input, render, label.
    pub(crate) fn viewports(&mut self, ui: &mut egui::Ui) {
        let full = ui.available_rect_before_wrap();
        let gap = 4.0;
        let half = (full.width() - gap) * 0.5;
        let rects = [
            egui::Rect::from_min_size(full.min, egui::vec2(half, full.height())),
            egui::Rect::from_min_size(
                egui::pos2(full.min.x + half + gap, full.min.y),
                egui::vec2(half, full.height()),
            ),
        ];
        ui.allocate_rect(full, egui::Sense::hover());
        for (i, rect) in rects.iter().enumerate() {
            let response = ui.interact(
                *rect,
                ui.scope_id().with(("viewport", i)),
                egui::Sense::click_and_drag(),
            );
            self.camera_input(ui, &response, rect.height());
        }
        self.viewport_rects = [Some(rects[0]), Some(rects[1])];
        let ppp = ui.ctx().pixels_per_point();
        let sizes = rects.map(|r| {
            [
                (r.width() * ppp).round().max(1.0) as u32,
                (r.height() * ppp).round().max(1.0) as u32,
            ]
        });
        let painter = ui.painter();
        match self.scene.as_mut() {
            Some(scene) => {
                let drew = scene.render(&self.session, &self.camera, &self.display, sizes);
                for (count, drew) in self.stats.viewport_redraws.iter_mut().zip(drew) {
                    *count += u64::from(drew);
                }
                for (i, rect) in rects.iter().enumerate() {
                    painter.add(scene.paint_callback(i, *rect));
                }
            }
            None => {
                for rect in &rects {
                    painter.rect_filled(*rect, 0.0, Color32::from_gray(20));
                    painter.text(
                        rect.center(),
                        egui::Align2::CENTER_CENTER,
                        "no wgpu renderer",
                        egui::FontId::proportional(16.0),
                        Color32::GRAY,
                    );
                }
            }
        }
        let font = egui::FontId::proportional(15.0);
        let session = &self.session;
        let snapshot = &session.live().snapshot;
        let state = session.training_state().label();
        let method = crate::engine::Method::of(session.applied_params()).name();
        let left = match session.reconstruction() {
            Some(m) => format!(
                "{method} — {} nodes ({state}) · mesh {} V / {} F",
                snapshot.positions.len(),
                m.vertex_count(),
                m.face_count()
            ),
            None => format!(
                "{method} — {} nodes, {} edges ({state})",
                snapshot.positions.len(),
                snapshot.edges.len()
            ),
        };
        let right = match (
            session.qem_mesh(),
            session.qem_pending(),
            session.qem_error(),
        ) {
            (Some(_), true, _) => format!(
                "QEM — computing {} vertices… (previous result shown)",
                session.qem_target()
            ),
            (None, true, _) => format!(
                "QEM — computing {} vertices… (original shown)",
                session.qem_target()
            ),
            (Some(m), false, _) => format!("QEM — {} V / {} F", m.vertex_count(), m.face_count()),
            (None, false, Some(e)) => format!("QEM failed: {e} (original shown)"),
            (None, false, None) => "QEM".into(),
        };
        // Each title wraps inside its view (in a narrow window the left one ran into the right).
        let color = Color32::from_gray(230);
        let mut title_bottom = rects[0].min.y;
        for (i, (rect, text)) in rects.iter().zip([left, right]).enumerate() {
            let galley = painter.layout(text, font.clone(), color, (rect.width() - 16.0).max(1.0));
            let at = rect.min + egui::vec2(8.0, 6.0);
            if i == 0 {
                title_bottom = at.y + galley.size().y;
            }
            painter.galley(at, galley, color);
        }
        self.method_switch(ui, rects[0], title_bottom);
    }

    /// A one-click switch between the paper's GNG3D and GNG3D-Q under the left view's title
    /// (whose bottom is at `title_bottom`): sets the method's parameters and restarts the run
    /// with them (issue 37).
    fn method_switch(&mut self, ui: &mut egui::Ui, view: egui::Rect, title_bottom: f32) {
        use crate::engine::Method;
        let current = Method::of(self.session.applied_params());
        let (other, text) = match current {
            Method::Q => (Method::Paper, "Switch to the paper's GNG3D"),
            Method::Paper | Method::Custom => (Method::Q, "Switch to GNG3D-Q"),
        };
        let at = egui::Rect::from_min_size(
            egui::pos2(view.min.x + 8.0, title_bottom + 2.0),
            egui::vec2(view.width() - 16.0, 22.0),
        );
        let clicked = ui
            .scope_builder(egui::UiBuilder::new().max_rect(at), |ui| {
                ui.button(text)
                    .on_hover_text(
                        "GNG3D-Q: quadric placement, flips, refit, oversampled and decimated \
                         (the library's default). Paper: vertices at the nodes, 30 epochs. \
                         Restarts the run.",
                    )
                    .clicked()
            })
            .inner;
        if clicked {
            self.session.switch_method(other);
        }
    }

    fn camera_input(&mut self, ui: &egui::Ui, response: &egui::Response, height: f32) {
        let delta = response.drag_delta();
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(egui::PointerButton::Primary) && !shift {
            self.camera.orbit(delta.x, delta.y);
        } else if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Primary) && shift)
        {
            self.camera.pan(delta.x, delta.y, height);
        }
        if response.hovered() {
            let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
            if scroll != 0.0 {
                self.camera.zoom((scroll * 0.002).exp());
            }
            if zoom != 1.0 {
                self.camera.zoom(zoom);
            }
        }
        if response.double_clicked() {
            self.reset_camera();
        }
    }
}

impl eframe::App for ViewerApp {
    fn logic(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        self.poll(ctx);
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        // The panels are transparent (see `panels`): the clear colour is their background.
        visuals.panel_fill.to_normalized_gamma_f32()
    }
}

//! The window's panels around the viewports: menu bar, status bar, the parameter panel (left)
//! and the plots/table panel (bottom), laid out so that the two viewports keep at least half of
//! the window's area at every size down to 800×600 (both panels collapse; the plots panel's
//! height is capped by that rule and the table scrolls).
//!
//! The parameter panel's contents are in `controls`.

mod controls;

use crate::app::ViewerApp;
use crate::io::DialogPurpose;
use crate::layout::{ControlsStart, PanelRects, Panels};
use crate::plots;
use crate::render::Shading;
use egui::{Color32, RichText};

/// Smallest useful height of the plots panel, points (a plot with its axis labels and legend).
pub const PLOTS_MIN_HEIGHT: f32 = 120.0;
/// Height the plots panel starts with at least, when the viewports' share allows it: its
/// button row and Table 1's nine rows (issue 37: the whole table without scrolling).
pub const PLOTS_WANTED_HEIGHT: f32 = 190.0;
/// Share of the window the viewports keep at least (issue 13).
pub const VIEWPORT_AREA_SHARE: f32 = 0.5;
/// Width at which a plot column stops being readable; narrower windows scroll the row.
const MIN_COLUMN_WIDTH: f32 = 160.0;

/// Tallest plots panel that leaves the viewports [`VIEWPORT_AREA_SHARE`] of the `window`, when
/// `rest` is the space left after the menu, status and parameter panels:
/// `rest.x × (rest.y − h) ≥ share × window.x × window.y`. Never below [`PLOTS_MIN_HEIGHT`].
pub fn plots_max_height(window: egui::Vec2, rest: egui::Vec2) -> f32 {
    // A point of slack: the panel is laid out before the viewports know their exact margins.
    let needed = VIEWPORT_AREA_SHARE * window.x * window.y / rest.x.max(1.0) + 4.0;
    (rest.y - needed).max(PLOTS_MIN_HEIGHT)
}

impl ViewerApp {
    /// Lay out all panels and the viewports.
    pub(crate) fn layout(&mut self, ui: &mut egui::Ui) {
        let window = ui.max_rect();
        if self.panels.is_some() && self.controls_start == ControlsStart::Undecided {
            // Set before the first layout (a shortcut): the user's.
            self.controls_start = ControlsStart::Decided;
        }
        let forced = self.session.options().controls;
        let mut panels = self
            .panels
            .get_or_insert_with(|| {
                let mut panels = Panels::for_width(window.width());
                panels.controls = forced.unwrap_or(panels.controls);
                panels
            })
            .clone();
        if forced.is_some() || !panels.controls {
            self.controls_start = ControlsStart::Decided;
        }
        // Panels paint no background: the window's clear colour is the panel colour
        // (`clear_color`), so a CPU rasterizer does not shade every pixel a second time.
        let bar = egui::Frame::side_top_panel(ui.style()).fill(Color32::TRANSPARENT);
        let central = egui::Frame::central_panel(ui.style()).fill(Color32::TRANSPARENT);
        egui::Panel::top("menu")
            .frame(bar)
            .show(ui, |ui| self.menu_bar(ui));
        let mut rects = PanelRects {
            status: Some(
                egui::Panel::bottom("status")
                    .frame(bar)
                    .show(ui, |ui| self.status_bar(ui))
                    .response
                    .rect,
            ),
            ..PanelRects::default()
        };
        // What the plots panel and the viewports share when `beside` points are taken on the
        // left: less the central panel's margins and the step strip (between the plots and
        // the viewports).
        let strip = if panels.steps { self.strip_height } else { 0.0 };
        let rest = |ui: &egui::Ui, beside: f32| {
            ui.available_rect_before_wrap().size()
                - central.total_margin().sum()
                - egui::vec2(beside, strip)
        };
        if panels.controls && self.controls_start != ControlsStart::Decided {
            // The window is wide enough for the parameter panel: it starts open only if the
            // plots panel still gets its wanted height beside it. Its width is its rows' (up
            // to its widest), measured on an unseen copy. egui lays a new grid out narrow in
            // its first pass, so the first pass lays out the copy and the panel (sizing their
            // grids) and is discarded; the second measures the copy and decides.
            let mut unseen = ui.new_child(
                egui::UiBuilder::new()
                    .id_salt("controls_measure")
                    .max_rect(ui.available_rect_before_wrap())
                    .invisible(),
            );
            let width = self
                .controls_panel(&mut unseen, bar, window.width())
                .width();
            if self.controls_start == ControlsStart::Undecided {
                self.controls_panel(ui, bar, window.width());
                self.controls_start = ControlsStart::Primed;
                ui.ctx()
                    .request_discard("measuring the parameter panel's start-up width");
                // Should the discard be refused (no pass left), the next frame decides.
                ui.ctx().request_repaint();
                // Nothing more: a panel shown now would keep this pass' size (egui stores it).
                return;
            }
            let cap = plots_max_height(ui.ctx().content_rect().size(), rest(ui, width));
            panels.controls = cap >= PLOTS_WANTED_HEIGHT;
            self.panels_mut().controls = panels.controls;
            self.controls_start = ControlsStart::Decided;
        }
        if panels.controls {
            rects.controls = Some(self.controls_panel(ui, bar, window.width()));
        }
        if panels.plots {
            // The share is of the whole window (the root ui may have a margin: test harnesses).
            let max = plots_max_height(ui.ctx().content_rect().size(), rest(ui, 0.0));
            let shown = egui::Panel::bottom("plots")
                .frame(bar)
                .resizable(true)
                .default_size(
                    (0.32 * window.height())
                        .max(PLOTS_WANTED_HEIGHT)
                        .clamp(PLOTS_MIN_HEIGHT, max),
                )
                .size_range(PLOTS_MIN_HEIGHT..=max)
                .show(ui, |ui| {
                    rects.plots = Some(ui.max_rect());
                    rects.plots_toolbar = Some(self.plots(ui));
                    rects.plots_content = Some(ui.min_rect());
                });
            rects.plots_panel = Some(shown.response.rect);
        }
        if panels.steps {
            let strip = egui::Panel::bottom("steps")
                .frame(bar)
                .resizable(false)
                .show(ui, |ui| {
                    let clock = self.session.training_clock();
                    let mut details = panels.step_details;
                    crate::steps::strip_ui(ui, &self.session.steps, clock, &mut details);
                    self.panels_mut().step_details = details;
                });
            self.strip_height = strip.response.rect.height();
            rects.strip = Some(strip.response.rect);
        }
        self.panel_rects = rects;
        if panels.history {
            let mut open = true;
            egui::Window::new("All checkpoints (Table 1 history)")
                .open(&mut open)
                .default_size([900.0, 300.0])
                .show(ui.ctx(), |ui| {
                    plots::history_table(ui, &self.session.history)
                });
            if !open {
                self.panels_mut().history = false;
            }
        }
        if panels.step_details {
            let clock = self.session.training_clock();
            let mut open = true;
            crate::steps::details_window(ui.ctx(), &self.session.steps, clock, &mut open);
            if !open {
                self.panels_mut().step_details = false;
            }
        }
        egui::CentralPanel::default()
            .frame(central)
            .show(ui, |ui| self.viewports(ui));
    }

    /// The parameter panel on the left of `ui` in a window `window_width` points wide; its
    /// rectangle.
    fn controls_panel(
        &mut self,
        ui: &mut egui::Ui,
        bar: egui::Frame,
        window_width: f32,
    ) -> egui::Rect {
        let max_width = (0.3 * window_width).clamp(180.0, 380.0);
        // The panel grows to its rows up to its widest; rows wider than that (a narrow
        // window) scroll sideways instead of being cut off.
        let sideways = self.controls_width > max_width - bar.total_margin().sum().x + 0.5;
        egui::Panel::left("controls")
            .frame(bar)
            .resizable(true)
            .default_size(250.0)
            .size_range(180.0..=max_width)
            .show(ui, |ui| {
                let scroll =
                    egui::ScrollArea::new([sideways, true]).show(ui, |ui| self.controls(ui));
                self.controls_width = scroll.content_size.x;
            })
            .response
            .rect
    }

    fn panels_mut(&mut self) -> &mut Panels {
        self.panels.get_or_insert_with(|| Panels::for_width(1600.0))
    }

    fn menu_bar(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui.button("Open mesh…  (Ctrl+O)").clicked() {
                    self.open_dialog(DialogPurpose::OpenMesh);
                }
                ui.separator();
                if ui
                    .add_enabled(
                        self.session.reconstruction().is_some(),
                        egui::Button::new("Export GNG3D mesh…"),
                    )
                    .clicked()
                {
                    self.open_dialog(DialogPurpose::ExportGng);
                }
                if ui
                    .add_enabled(
                        self.session.has_qem_mesh(),
                        egui::Button::new("Export QEM mesh…"),
                    )
                    .clicked()
                {
                    self.open_dialog(DialogPurpose::ExportQem);
                }
                if ui.button("Export checkpoint table (CSV)…").clicked() {
                    self.open_dialog(DialogPurpose::ExportCsv);
                }
                if ui.button("Save screenshot (PNG)…  (Ctrl+S)").clicked() {
                    self.open_dialog(DialogPurpose::Screenshot);
                }
                ui.separator();
                if ui.button("Quit  (Ctrl+Q)").clicked() {
                    ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
                }
            });
            ui.menu_button("View", |ui| {
                ui.radio_value(&mut self.display.shading, Shading::Smooth, "Smooth shading");
                ui.radio_value(
                    &mut self.display.shading,
                    Shading::Flat,
                    "Flat shading  (F)",
                );
                ui.checkbox(&mut self.display.wireframe, "Wireframe  (W)");
                ui.checkbox(&mut self.display.show_original, "Original overlay  (O)");
                self.texture_toggle(ui, "Texture  (T)");
                let panels = self.panels_mut();
                ui.checkbox(&mut panels.controls, "Parameter panel  (C)");
                ui.checkbox(&mut panels.plots, "Plots and table  (P)");
                ui.checkbox(&mut panels.steps, "GNG3D step strip");
                ui.checkbox(&mut panels.step_details, "GNG3D step table");
                ui.checkbox(&mut self.display.smooth_ui, "Anti-aliased UI")
                    .on_hover_text("Off saves about 1 ms per frame on a software renderer");
                if ui.button("Reset camera  (Home)").clicked() {
                    self.reset_camera();
                }
            });
            if ui.button("Help (F1)").clicked() {
                self.panels_mut().help ^= true;
            }
            ui.separator();
            let panels = self.panels_mut();
            ui.toggle_value(&mut panels.controls, "Parameters")
                .on_hover_text("show/hide the parameter panel (C)");
            ui.separator();
            ui.label(RichText::new(&self.session.model_name).strong());
            let original = self.session.original();
            ui.label(format!(
                "{} vertices, {} faces",
                original.vertex_count(),
                original.face_count()
            ));
            if let Some(path) = self.session.loading() {
                ui.spinner();
                ui.label(format!("loading {} …", path.display()));
            }
        });
    }

    fn status_bar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            let live = self.session.live();
            let snapshot = &live.snapshot;
            let state = self.session.training_state().label();
            let progress = if live.max_signals > 0 {
                format!(
                    " ({:.0} %)",
                    100.0 * snapshot.signals as f64 / live.max_signals as f64
                )
            } else {
                String::new()
            };
            ui.label(format!(
                "GNG3D [{state}]: {} nodes, {} signals{progress}",
                snapshot.positions.len(),
                plots::format_count(snapshot.signals as f64),
            ));
            if let Some(m) = self.session.reconstruction() {
                ui.label(format!(
                    "mesh {} V / {} F",
                    m.vertex_count(),
                    m.face_count()
                ));
            }
            let pending = self.session.evaluations_pending();
            if pending > 0 {
                ui.label(format!("evaluating {pending}…"));
            }
            ui.separator();
            match (self.session.qem_mesh(), self.session.qem_pending()) {
                (_, true) => ui.label("QEM: computing…"),
                (Some(m), false) => ui.label(format!(
                    "QEM: {} V / {} F",
                    m.vertex_count(),
                    m.face_count()
                )),
                (None, false) => ui.label("QEM: –"),
            };
            ui.separator();
            if live.running {
                ui.label(format!(
                    "{} signals/s",
                    plots::format_count(live.signals_per_second)
                ));
                ui.separator();
                let ms = self.stats.frame_ms();
                if ms > 0.0 {
                    ui.label(format!("frame {ms:.1} ms ({:.0} fps)", 1000.0 / ms));
                }
            } else {
                // Idle frames are drawn only on input: their interval is not a frame rate.
                ui.label(RichText::new("idle").weak());
            }
        });
        if let Some(m) = self.session.messages.last() {
            let color = if m.is_error {
                Color32::from_rgb(255, 110, 110)
            } else {
                ui.visuals().weak_text_color()
            };
            ui.add(egui::Label::new(RichText::new(&m.text).color(color)).truncate())
                .on_hover_text(&m.text);
        }
    }

    /// The plots panel's contents; returns where its button row went.
    fn plots(&mut self, ui: &mut egui::Ui) -> egui::Rect {
        let columns = self.panels_mut().columns;
        // Wrapped, so a narrow panel (the parameter panel open in a small window) puts the
        // buttons on a second line instead of cutting them off.
        let toolbar = ui.horizontal_wrapped(|ui| {
            if ui
                .small_button("Hide plots")
                .on_hover_text("hide the plots panel (P)")
                .clicked()
            {
                self.panels_mut().plots = false;
            }
            let panels = self.panels_mut();
            for (shown, name) in
                panels
                    .columns
                    .iter_mut()
                    .zip(["vertex errors", "E_sur", "Hausdorff", "table"])
            {
                ui.toggle_value(shown, name);
            }
            ui.toggle_value(&mut panels.history, "all checkpoints")
                .on_hover_text(
                    "every checkpoint of the run in a window (the CSV export has them too)",
                );
            if ui.small_button("Export CSV…").clicked() {
                self.open_dialog(DialogPurpose::ExportCsv);
            }
        });
        let toolbar = toolbar.response.rect;
        let shown: Vec<usize> = (0..4).filter(|&i| columns[i]).collect();
        if shown.is_empty() {
            self.table_layout = None;
            return toolbar;
        }
        // The table takes the width it needs (Table 1 fits without scrolling, issue 37); the
        // plots share the rest.
        let gap = 10.0;
        let table = if columns[3] { plots::TABLE_WIDTH } else { 0.0 };
        let plot_count = shown.iter().filter(|&&i| i != 3).count();
        let available = ui.available_width() - gap * (shown.len() as f32 - 1.0);
        let plot_width = if plot_count > 0 {
            ((available - table) / plot_count as f32).max(MIN_COLUMN_WIDTH)
        } else {
            0.0
        };
        let total = plot_width * plot_count as f32 + table;
        let height = ui.available_height();
        let x_max = self.session.live().max_signals as f64;
        let method = crate::engine::Method::of(self.session.applied_params()).name();
        let history = &self.session.history;
        let mut layout = None;
        let row = |ui: &mut egui::Ui| {
            ui.horizontal_top(|ui| {
                ui.spacing_mut().item_spacing.x = gap;
                for &i in &shown {
                    let w = if i == 3 { table } else { plot_width };
                    ui.allocate_ui_with_layout(
                        egui::vec2(w, height),
                        egui::Layout::top_down(egui::Align::Min),
                        |ui| {
                            ui.set_width(w);
                            let legend: &[plots::LegendEntry] = match i {
                                0 => &plots::VERTEX_LEGEND,
                                1 => &plots::SURFACE_LEGEND,
                                2 => &plots::HAUSDORFF_LEGEND,
                                _ => &[],
                            };
                            if i < 3 {
                                // Titles wrap rather than being cut (issue 37).
                                ui.add(
                                    egui::Label::new(RichText::new(plots::TITLES[i]).strong())
                                        .wrap(),
                                );
                                plots::legend_row(ui, legend);
                                // Keep the top y tick label clear of the legend.
                                ui.add_space(4.0);
                            }
                            let h = ui.available_height().max(40.0);
                            match i {
                                0 => plots::vertex_error_plot(ui, history, h, x_max),
                                1 => plots::surface_error_plot(ui, history, h, x_max),
                                2 => plots::hausdorff_plot(ui, history, h, x_max),
                                _ => {
                                    // Table 1 scrolls when its rows (a textured input adds
                                    // some) are taller than the panel may be.
                                    ui.spacing_mut().scroll = egui::style::ScrollStyle::solid();
                                    egui::ScrollArea::vertical()
                                        .id_salt("table1")
                                        .show(ui, |ui| {
                                            layout =
                                                Some(plots::comparison_table(ui, history, method));
                                        });
                                }
                            }
                        },
                    );
                }
            });
        };
        // Nothing the panel draws may be taller than the panel: egui lays a bottom panel's
        // contents out from its top and, when they are taller than the panel's size cap,
        // reports the panel's top lower by the overflow, so the step strip above it was laid
        // out over the button row (1400×800 with the parameter panel open, Table 1 with
        // attribute rows). The row scrolls instead: sideways when its columns do not fit, down
        // when a column (a narrow plot's wrapped title and legend) is taller than the panel.
        egui::ScrollArea::new([total > available + 1.0, true])
            .id_salt("plots_row")
            .show(ui, row);
        self.table_layout = layout;
        toolbar
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plots_cap_keeps_half_the_window_for_the_viewports() {
        for (w, h, controls) in [
            (800.0, 600.0, 0.0),
            (1024.0, 600.0, 0.0),
            (1024.0, 768.0, 0.0),
            (1280.0, 720.0, 250.0),
            (1600.0, 900.0, 250.0),
        ] {
            let window = egui::vec2(w, h);
            // Menu and status bars take about 60 points.
            let rest = egui::vec2(w - controls, h - 60.0);
            let max = plots_max_height(window, rest);
            let area = rest.x * (rest.y - max);
            assert!(
                area >= VIEWPORT_AREA_SHARE * w * h - 1.0,
                "{w}x{h}: viewports {area} of {}",
                w * h
            );
            assert!(max >= PLOTS_MIN_HEIGHT, "{w}x{h}: plots {max}");
        }
        assert!(!Panels::for_width(1024.0).controls);
        assert!(!Panels::for_width(1280.0).controls);
        assert!(Panels::for_width(1600.0).controls);
    }
}

//! The parameter panel (left): run controls (run/pause, step, reset, method), speed and
//! checkpoint interval, the GNG3D parameters and the display switches.

use crate::app::ViewerApp;
use crate::render::Shading;
use crate::session::DEFAULT_WATCH_SECONDS;
use crate::worker::Speed;
use egui::{Color32, RichText};
use std::time::Duration;
/// One row of the parameter grid: a label, `widget` labelled by it, end of row.
fn param_row(ui: &mut egui::Ui, label: &str, widget: impl egui::Widget) -> egui::Response {
    let label = ui.label(label);
    let response = ui.add(widget).labelled_by(label.id);
    ui.end_row();
    response
}

/// A parameter row choosing `value` among `choices` (value, label) in a drop-down.
fn choice_row<T: PartialEq + Copy>(
    ui: &mut egui::Ui,
    label: &str,
    value: &mut T,
    choices: &[(T, &'static str)],
) {
    let label_response = ui.label(label);
    let selected = choices
        .iter()
        .find(|(choice, _)| choice == value)
        .map_or("?", |(_, text)| text);
    egui::ComboBox::from_id_salt(label)
        .selected_text(selected)
        .show_ui(ui, |ui| {
            for &(choice, text) in choices {
                ui.selectable_value(value, choice, text);
            }
        })
        .response
        .labelled_by(label_response.id);
    ui.end_row();
}

/// A parameter row of a rate in [0, 1] dragged by `speed`, shown with at most `decimals`
/// decimals (`None`: as many as the speed suggests).
fn rate_row<N: egui::emath::Numeric>(
    ui: &mut egui::Ui,
    label: &str,
    value: &mut N,
    speed: f64,
    decimals: Option<usize>,
) {
    let drag = egui::DragValue::new(value).range(0.0..=1.0).speed(speed);
    param_row(ui, label, drag.max_decimals_opt(decimals));
}

impl ViewerApp {
    pub(super) fn controls(&mut self, ui: &mut egui::Ui) {
        ui.heading("Training");
        ui.horizontal(|ui| {
            let live = self.session.live().clone();
            if ui
                .add_enabled(
                    !live.finished,
                    egui::Button::new(if live.running { "Pause" } else { "Play" }),
                )
                .on_hover_text("Space")
                .clicked()
            {
                self.session.set_running(!live.running);
            }
            if ui
                .button("Step")
                .on_hover_text("present λ signals (100 with auto λ) · S")
                .clicked()
            {
                self.step_once();
            }
            let pending = self.session.params_pending();
            let reset = egui::Button::new(if pending { "Apply + Reset" } else { "Reset" });
            let reset = if pending {
                reset.fill(Color32::from_rgb(120, 90, 20))
            } else {
                reset
            };
            if ui
                .add(reset)
                .on_hover_text("restart with the parameters below · R")
                .clicked()
            {
                self.session.reset_training();
            }
        });
        if ui
            .button("Reconstruct now")
            .on_hover_text("build and measure the neural mesh from the current network · N")
            .clicked()
        {
            self.session.reconstruct_now();
        }
        self.speed_controls(ui);
        ui.add_space(4.0);
        if self.session.params_pending() {
            ui.label(
                RichText::new("parameters changed: Apply + Reset (R) to use them")
                    .color(Color32::from_rgb(240, 200, 90)),
            );
        } else {
            ui.label(
                RichText::new("parameter edits apply on Reset")
                    .small()
                    .weak(),
            );
        }
        let params = &mut self.session.params;
        egui::Grid::new("params").num_columns(2).show(ui, |ui| {
            param_row(
                ui,
                "target vertices",
                egui::DragValue::new(&mut params.target_vertices)
                    .range(4..=1_000_000)
                    .speed(10.0),
            );
            let label = ui.label("time limit (s)");
            ui.horizontal(|ui| {
                let mut limited = params.time_limit.is_some();
                ui.checkbox(&mut limited, "limit");
                let mut seconds = params.time_limit.map_or(30.0, |d| d.as_secs_f64());
                ui.add_enabled(
                    limited,
                    egui::DragValue::new(&mut seconds).range(0.1..=3600.0),
                )
                .labelled_by(label.id);
                params.time_limit = limited.then(|| Duration::from_secs_f64(seconds));
            });
            ui.end_row();
            let label = ui.label("λ (insert every)");
            ui.horizontal(|ui| {
                let mut auto = params.lambda.is_none();
                ui.checkbox(&mut auto, "auto");
                let mut lambda = params.lambda.unwrap_or(100);
                ui.add_enabled(!auto, egui::DragValue::new(&mut lambda).range(1..=100_000))
                    .labelled_by(label.id);
                params.lambda = (!auto).then_some(lambda);
            });
            ui.end_row();
            rate_row(ui, "ε_b (winner)", &mut params.eps_winner, 0.001, None);
            rate_row(
                ui,
                "ε_n (neighbours)",
                &mut params.eps_neighbour,
                0.0001,
                Some(5),
            );
            rate_row(ui, "α (insertion)", &mut params.alpha, 0.01, None);
            rate_row(
                ui,
                "d (error decay)",
                &mut params.error_decay,
                0.0001,
                Some(5),
            );
            param_row(
                ui,
                "a_max (edge age)",
                egui::DragValue::new(&mut params.max_edge_age).range(1..=100_000),
            );
            param_row(
                ui,
                "μ (removal window)",
                egui::DragValue::new(&mut params.removal_window).range(0.0..=1000.0),
            )
            .on_hover_text("nodes without a win in the last μ·|A| signals are removed (0: off)");
            param_row(ui, "seed", egui::DragValue::new(&mut params.seed));
            choice_row(
                ui,
                "signal source",
                &mut params.signal_source,
                &crate::engine::SIGNAL_SOURCES,
            );
            // Vertex placement of the reconstruction (GNG3D-Q: quadric placement + edge flips).
            let rec = &mut params.reconstruction;
            choice_row(
                ui,
                "vertex placement",
                &mut rec.placement,
                &crate::engine::PLACEMENTS,
            );
            ui.label("edge flips");
            ui.checkbox(&mut rec.flip_edges, "toward the surface (GNG3D-Q)");
            ui.end_row();
            ui.label("surface refit");
            ui.add_enabled(
                rec.placement == gng3d_core::Placement::Quadric,
                egui::Checkbox::new(&mut rec.refit, "fit the triangles (GNG3D-Q)"),
            )
            .on_disabled_hover_text("needs quadric placement");
            ui.end_row();
            ui.label("relaxation");
            ui.checkbox(&mut rec.relax, "to centroids (GNG3D-Q)")
                .on_hover_text(
                    "after the decimation of an oversampled run, for outputs of at most 30 % of \
                     the input's vertices: each vertex moves half-way toward the centroid of the \
                     original vertices nearest to it (E_avg)",
                );
            ui.end_row();
            ui.label("deviation repair");
            ui.checkbox(&mut rec.repair_deviations, "spikes and bridges (GNG3D-Q)")
                .on_hover_text(
                    "after the decimation of an oversampled run, for outputs of at least 5 % of \
                     the input's vertices: vertices standing off the original move back onto it \
                     and edges spanning a groove of it flip (Hausdorff)",
                );
            ui.end_row();
            // The CLI's `--shape[=fit|round]` and `--creases` (docs/notes/shape.md, creases.md).
            choice_row(ui, "triangle shape", &mut rec.shape, &crate::engine::SHAPES);
            ui.label("CAD creases");
            ui.checkbox(&mut rec.creases, "kept as edges (GNG3D-Q)")
                .on_hover_text(
                    "on a CAD part (sharp edges at least 2 % of its edges): cut and decimate \
                     along its creases, kept only where no farther from the original",
                );
            ui.end_row();
        });
        ui.separator();
        ui.heading("Display");
        ui.horizontal(|ui| {
            ui.radio_value(&mut self.display.shading, Shading::Smooth, "smooth");
            ui.radio_value(&mut self.display.shading, Shading::Flat, "flat");
        });
        ui.checkbox(&mut self.display.wireframe, "wireframe");
        ui.checkbox(&mut self.display.show_original, "original overlay");
        self.texture_toggle(ui, "texture");
        ui.checkbox(&mut self.display.show_network, "GNG network");
        ui.checkbox(&mut self.display.show_gng_mesh, "GNG3D reconstruction");
        ui.add(egui::Slider::new(&mut self.display.point_px, 1.0..=12.0).text("node size (px)"));
        if ui.button("Reset camera").clicked() {
            self.reset_camera();
        }
        ui.label(
            RichText::new("drag: orbit · right/middle drag or shift: pan · wheel: zoom · F1: help")
                .small()
                .weak(),
        );
    }

    /// The texture switch labelled `label`: greyed out when the model has no base-colour
    /// texture (or no texture coordinates to map one by).
    pub(super) fn texture_toggle(&mut self, ui: &mut egui::Ui, label: &str) {
        let available = self.session.texture().is_some();
        ui.add_enabled(
            available,
            egui::Checkbox::new(&mut self.display.texture, label),
        )
        .on_hover_text(
            "draw the model's base-colour texture (OBJ map_Kd, glTF baseColorTexture) on the \
             original and on both outputs, which keep its texture coordinates",
        )
        .on_disabled_hover_text("the model has no base-colour texture with texture coordinates");
    }

    /// Speed (watch … as fast as possible) and checkpoint interval: both apply at once.
    fn speed_controls(&mut self, ui: &mut egui::Ui) {
        let mut speed = self.session.speed;
        let mut fast = speed == Speed::Unlimited;
        ui.horizontal(|ui| {
            ui.checkbox(&mut fast, "as fast as possible");
            let mut seconds = match speed {
                Speed::Paced { seconds } => seconds,
                Speed::Unlimited => DEFAULT_WATCH_SECONDS,
            };
            let label = ui.label("run length");
            ui.add_enabled(
                !fast,
                egui::DragValue::new(&mut seconds)
                    .range(1.0..=600.0)
                    .speed(0.5)
                    .suffix(" s"),
            )
            .labelled_by(label.id)
            .on_hover_text(
                "the whole run (training, then the steps after it) takes about this wall time: \
                 the training is paced to end where the steps have their estimated time left, \
                 the network growing over its first 60 %; a machine too busy to keep the pace \
                 takes a little longer, and only a run past twice this time leaves steps out \
                 (applies from the next Reset; the training's pace applies at once)",
            );
            speed = if fast {
                Speed::Unlimited
            } else {
                Speed::Paced { seconds }
            };
        });
        self.session.set_speed(speed);
        // A mesh whose steps alone need more than the run length: say what it will take.
        if let (Speed::Paced { seconds }, Some(limit)) = (speed, self.session.steps.limit)
            && limit.is_watch_time
        {
            let needs = crate::worker::STEPS_TIME_FACTOR * limit.steps_estimate;
            if needs > 0.9 * seconds {
                ui.label(
                    RichText::new(format!(
                        "this mesh's steps after training need about {needs:.0} s: the run \
                         takes longer than {seconds:.0} s"
                    ))
                    .color(Color32::from_rgb(240, 200, 90)),
                );
            }
        }
        let mut every = self.session.checkpoint_every;
        let vertices = self.session.original().vertex_count() as u64;
        ui.horizontal(|ui| {
            let label = ui.label("checkpoint every");
            ui.add(
                egui::DragValue::new(&mut every)
                    .range(0..=1_000_000_000)
                    .speed(100.0)
                    .suffix(" signals"),
            )
            .labelled_by(label.id)
            .on_hover_text(
                "reconstruct and measure the neural mesh periodically (0: off; applies at once)",
            );
            if ui
                .small_button("|V|")
                .on_hover_text("the paper's protocol: every |V| signals")
                .clicked()
            {
                every = vertices;
            }
        });
        self.session.set_checkpoint_every(every);
    }

    /// Present λ signals (100 with automatic λ).
    pub(crate) fn step_once(&mut self) {
        let lambda = self.session.params.lambda.unwrap_or(100).max(1);
        self.session.step(u64::from(lambda));
    }
}

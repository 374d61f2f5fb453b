//! The step strip drawn with egui: one compact row of coloured chips under the viewports (build
//! rounds grouped) with a time bar, and the details window with a table of every step.

use super::text::{total_text, training_text};
use super::{
    StepGroup, StepStatus, StepStrip, TrainingClock, changed_text, format_seconds, long_name,
    status_text,
};
use crate::engine::PipelineStep;
use egui::{Color32, RichText};

impl StepGroup {
    /// Colour of the group in the strip and its time bar.
    fn color(&self) -> Color32 {
        match self.rows.first().map(|r| r.step) {
            Some(PipelineStep::Label | PipelineStep::ConnectCells) => {
                Color32::from_rgb(150, 150, 160)
            }
            Some(PipelineStep::CutSeams) => Color32::from_rgb(220, 150, 80),
            Some(PipelineStep::Decimate) => Color32::from_rgb(170, 120, 220),
            Some(PipelineStep::Relax | PipelineStep::RepairDeviations) => {
                Color32::from_rgb(70, 190, 180)
            }
            _ => {
                // Build rounds: greens, lighter each round.
                let round = self.rows.first().map_or(0, |r| r.round).min(4) as u8;
                Color32::from_rgb(80 + 25 * round, 170 + 12 * round, 90 + 20 * round)
            }
        }
    }
}

/// Colour of the training in the strip and its time bar.
const TRAINING_COLOR: Color32 = Color32::from_rgb(90, 150, 230);

/// Text colour of a status.
fn status_color(ui: &egui::Ui, status: StepStatus) -> Color32 {
    match status {
        StepStatus::Pending | StepStatus::NotRun => ui.visuals().weak_text_color(),
        StepStatus::Running => Color32::from_rgb(240, 200, 90),
        StepStatus::Done { .. } => ui.visuals().text_color(),
        StepStatus::Skipped => Color32::from_rgb(235, 140, 90),
    }
}

/// Hover text of a group: each step with its status and what it changed.
pub(super) fn group_tooltip(group: &StepGroup) -> String {
    group
        .rows
        .iter()
        .map(|r| {
            let changed = match r.status {
                StepStatus::Done { changed, .. } => format!(" — {}", changed_text(r.step, changed)),
                _ => String::new(),
            };
            format!("{}: {}{changed}", long_name(r.step), status_text(r.status))
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// A coloured square, then `text` in the status colour.
fn chip(ui: &mut egui::Ui, color: Color32, text: &str, status: StepStatus) -> egui::Response {
    let mut rich = RichText::new(text).small().color(status_color(ui, status));
    if status == StepStatus::Skipped {
        rich = rich.strikethrough();
    }
    // The text is laid out first so the chip is one unit of known width: the strip's wrapping
    // row then moves a chip that does not fit to the next line (a nested `horizontal` of unknown
    // width ran off the window's edge at 800 points).
    let galley = egui::WidgetText::from(rich).into_galley(
        ui,
        Some(egui::TextWrapMode::Extend),
        f32::INFINITY,
        egui::TextStyle::Small,
    );
    let (marker, gap) = (8.0, 3.0);
    let size = egui::vec2(marker + gap + galley.size().x, galley.size().y.max(marker));
    ui.allocate_ui_with_layout(
        size,
        egui::Layout::left_to_right(egui::Align::Center),
        |ui| {
            ui.spacing_mut().item_spacing.x = gap;
            let (rect, _) =
                ui.allocate_exact_size(egui::vec2(marker, marker), egui::Sense::hover());
            let fill = if matches!(status, StepStatus::Done { .. } | StepStatus::Running) {
                color
            } else {
                color.gamma_multiply(0.3)
            };
            ui.painter().rect_filled(rect, 1.0, fill);
            ui.add(egui::Label::new(galley))
        },
    )
    .inner
}

/// The compact strip: a row of entries (training, then each step or build round with its
/// seconds, coloured by status, details on hover) and the total against the run's limit, over a
/// thin bar with each entry's share of the run's time. `details` toggles the table
/// ([`details_window`]).
pub fn strip_ui(ui: &mut egui::Ui, strip: &StepStrip, clock: TrainingClock, details: &mut bool) {
    let groups = strip.groups();
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 10.0;
        ui.toggle_value(details, RichText::new("GNG3D steps").small())
            .on_hover_text("the table of every step of the pipeline after training");
        if strip.is_empty() {
            ui.label(RichText::new("no run yet").small().weak());
            return;
        }
        let (text, status) = training_text(strip, clock);
        let mut hover = "running wall time of the training (pauses excluded)".to_string();
        if strip.previews > 0 {
            hover += &format!(
                ", with {} checkpoint previews ({})",
                strip.previews,
                format_seconds(strip.preview_seconds)
            );
        }
        if clock.pace_seconds.is_some() && strip.limit.is_some() {
            hover += "; the signals are spread over the training's share of the run, and the \
                      time limit counts wall time from the start, pauses included";
        }
        chip(ui, TRAINING_COLOR, &text, status).on_hover_text(hover);
        for group in &groups {
            let status = group.status();
            let text = match status {
                StepStatus::Done { seconds, .. } => {
                    format!("{}: {}", group.label, format_seconds(seconds))
                }
                StepStatus::Running => format!("{} …", group.label),
                StepStatus::Pending => group.label.clone(),
                StepStatus::Skipped => format!("{} skipped", group.label),
                StepStatus::NotRun => format!("{} not run", group.label),
            };
            chip(ui, group.color(), &text, status).on_hover_text(group_tooltip(group));
        }
        let total = total_text(strip);
        if !total.is_empty() {
            let over = match (strip.total_seconds(), strip.limit) {
                (Some(total), Some(limit)) => total > 1.1 * limit.seconds,
                _ => false,
            };
            let color = if over {
                Color32::from_rgb(235, 140, 90)
            } else {
                ui.visuals().text_color()
            };
            // One unit, like the chips: it moves to the next line whole instead of breaking.
            let total = egui::WidgetText::from(RichText::new(total).small().strong().color(color))
                .into_galley(
                    ui,
                    Some(egui::TextWrapMode::Extend),
                    f32::INFINITY,
                    egui::TextStyle::Small,
                );
            ui.add(egui::Label::new(total)).on_hover_text(
                "training plus the steps after it (wall time, start to final mesh); the \
                     run's time limit is the run length unless a shorter one is set",
            );
        }
    });
    time_bar(ui, strip, clock, &groups);
}

/// A thin bar: the training and each group as a share of the run's time (the limit when it is
/// longer than what ran), with a tick at the limit.
fn time_bar(ui: &mut egui::Ui, strip: &StepStrip, clock: TrainingClock, groups: &[StepGroup]) {
    let width = ui.available_width();
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 4.0), egui::Sense::hover());
    if strip.is_empty() {
        return;
    }
    let training = strip.training_seconds.unwrap_or(clock.seconds);
    let mut segments = vec![(training, TRAINING_COLOR)];
    segments.extend(groups.iter().map(|g| (g.seconds(), g.color())));
    let used: f64 = segments.iter().map(|(s, _)| s).sum();
    let limit = strip.limit.map(|l| l.seconds);
    let expected = clock.pace_seconds.unwrap_or(0.0);
    let scale = used.max(limit.unwrap_or(0.0)).max(expected).max(1e-9);
    let painter = ui.painter();
    painter.rect_filled(rect, 1.0, ui.visuals().extreme_bg_color);
    let mut x = rect.min.x;
    for (seconds, color) in segments {
        let w = (seconds / scale) as f32 * rect.width();
        if w > 0.0 {
            let r = egui::Rect::from_min_size(egui::pos2(x, rect.min.y), egui::vec2(w, 4.0));
            painter.rect_filled(r, 0.0, color);
            x += w;
        }
    }
    if let Some(limit) = limit.filter(|&l| l < scale) {
        let lx = rect.min.x + (limit / scale) as f32 * rect.width();
        painter.vline(
            lx,
            rect.y_range().expand(2.0),
            egui::Stroke::new(1.5, ui.visuals().strong_text_color()),
        );
    }
}

/// The table of every step (a closable window over the GNG3D view): the training, each step
/// with its round, status or seconds, and what it changed, and the total.
pub fn details_window(
    ctx: &egui::Context,
    strip: &StepStrip,
    clock: TrainingClock,
    open: &mut bool,
) {
    let max_height = (ctx.content_rect().height() * 0.55).max(120.0);
    egui::Window::new("GNG3D pipeline steps")
        .open(open)
        .collapsible(true)
        .resizable(false)
        .default_pos(egui::pos2(12.0, 60.0))
        .show(ctx, |ui| {
            egui::ScrollArea::vertical()
                .max_height(max_height)
                .show(ui, |ui| details_table(ui, strip, clock));
        });
}

fn details_table(ui: &mut egui::Ui, strip: &StepStrip, clock: TrainingClock) {
    egui::Grid::new("gng3d_steps")
        .num_columns(4)
        .striped(true)
        .spacing(egui::vec2(14.0, 2.0))
        .show(ui, |ui| {
            for title in ["step", "round", "time", "changed"] {
                ui.label(RichText::new(title).small().strong());
            }
            ui.end_row();
            let (text, status) = training_text(strip, clock);
            ui.label(RichText::new("training").small());
            ui.label("");
            let time = text.trim_start_matches("training: ").to_string();
            ui.label(RichText::new(time).small().color(status_color(ui, status)));
            ui.label(
                RichText::new(if strip.previews > 0 {
                    format!(
                        "{} checkpoint previews ({})",
                        strip.previews,
                        format_seconds(strip.preview_seconds)
                    )
                } else {
                    String::new()
                })
                .small()
                .weak(),
            );
            ui.end_row();
            for row in strip.rows() {
                ui.label(RichText::new(long_name(row.step)).small());
                ui.label(RichText::new(row.round.to_string()).small().weak());
                ui.label(
                    RichText::new(status_text(row.status))
                        .small()
                        .color(status_color(ui, row.status)),
                );
                match row.status {
                    StepStatus::Done { changed, .. } => {
                        ui.label(RichText::new(changed_text(row.step, changed)).small())
                    }
                    _ => ui.label(""),
                };
                ui.end_row();
            }
            let total = total_text(strip);
            if !total.is_empty() {
                ui.label(RichText::new("total").small().strong());
                ui.label("");
                ui.label(RichText::new(total).small().strong());
                ui.label(
                    RichText::new(if strip.cut_for_time {
                        "the time limit cut steps"
                    } else {
                        ""
                    })
                    .small()
                    .weak(),
                );
                ui.end_row();
            }
        });
}

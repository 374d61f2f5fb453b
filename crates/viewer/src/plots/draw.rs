//! The figures themselves: the vertex-error, E_sur and Hausdorff plots of a [`History`], their
//! colours, titles and legends.

use super::axes::{hovered, log_hover, log_plot, log10};
use super::{History, envelope, format_count, format_value};
use egui::{Color32, Stroke};
use egui_plot::{HLine, Line, LineStyle, PlotPoints, PlotUi, Points};
/// Colour of E_avg curves.
const AVG_COLOR: Color32 = Color32::from_rgb(80, 170, 255);
/// Colour of E_max curves.
const MAX_COLOR: Color32 = Color32::from_rgb(255, 140, 60);
/// Colour of E_sur curves.
const SUR_COLOR: Color32 = Color32::from_rgb(120, 220, 120);
/// Colour of Hausdorff curves.
const HAUSDORFF_COLOR: Color32 = Color32::from_rgb(230, 110, 230);

/// One legend entry: label, colour, dashed (QEM) or solid (GNG3D).
pub type LegendEntry = (&'static str, Color32, bool);

/// A legend drawn as a row above the plot, with a short line sample per entry so solid (GNG3D)
/// and dashed (QEM) are told apart and no legend box covers data.
pub fn legend_row(ui: &mut egui::Ui, entries: &[LegendEntry]) {
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing = egui::vec2(8.0, 0.0);
        let font = egui::TextStyle::Body.resolve(ui.style());
        let row_height = ui.text_style_height(&egui::TextStyle::Body);
        for &(label, color, dashed) in entries {
            // Sample and label wrap as one unit of known width, so the row wraps between
            // entries instead of growing wider than its column (body text, 12.5 points, is
            // readable at 1280×720 but too wide for one row of a narrow column).
            let text_width = ui
                .painter()
                .layout_no_wrap(label.to_string(), font.clone(), color)
                .size()
                .x;
            let size = egui::vec2(18.0 + 4.0 + text_width + 1.0, row_height);
            ui.allocate_ui_with_layout(
                size,
                egui::Layout::left_to_right(egui::Align::Center),
                |ui| {
                    ui.spacing_mut().item_spacing.x = 4.0;
                    let (rect, _) =
                        ui.allocate_exact_size(egui::vec2(18.0, 12.0), egui::Sense::hover());
                    let (a, b) = (rect.left_center(), rect.right_center());
                    let stroke = Stroke::new(2.0, color);
                    if dashed {
                        ui.painter()
                            .extend(egui::Shape::dashed_line(&[a, b], stroke, 4.0, 3.0));
                    } else {
                        ui.painter().line_segment([a, b], stroke);
                    }
                    ui.add(egui::Label::new(label).wrap_mode(egui::TextWrapMode::Extend));
                },
            );
        }
    });
}

/// Legend of the vertex-error plot.
pub const VERTEX_LEGEND: [LegendEntry; 4] = [
    ("GNG3D E_avg", AVG_COLOR, false),
    ("GNG3D E_max", MAX_COLOR, false),
    ("QEM E_avg", AVG_COLOR, true),
    ("QEM E_max", MAX_COLOR, true),
];
/// Legend of the E_sur plot.
pub const SURFACE_LEGEND: [LegendEntry; 2] = [
    ("GNG3D |E_sur|", SUR_COLOR, false),
    ("QEM |E_sur|", SUR_COLOR, true),
];
/// Legend of the Hausdorff plot.
pub const HAUSDORFF_LEGEND: [LegendEntry; 2] = [
    ("GNG3D Hausdorff max", HAUSDORFF_COLOR, false),
    ("QEM Hausdorff max", HAUSDORFF_COLOR, true),
];

/// Titles of the three plots and the table (each says what it measures and in which unit).
pub const TITLES: [&str; 4] = [
    "E_avg, E_max (model units²)",
    "|E_sur| (model units²)",
    "Hausdorff max (model units)",
    "Table 1: latest vs QEM",
];

/// E_avg and E_max of the live network against signals (log y, squared model units), QEM as
/// dashed horizontal lines. `x_max`: the run's signal budget.
pub fn vertex_error_plot(ui: &mut egui::Ui, history: &History, height: f32, x_max: f64) {
    // One bucket per two pixels: a CPU rasterizer pays for every tiny line segment.
    let buckets = (ui.available_width() * ui.ctx().pixels_per_point() / 2.0).max(16.0) as usize;
    let series = |column: usize| -> Vec<[f64; 2]> {
        history
            .errors
            .iter()
            .map(|e| [e[0], log10(e[column])])
            .collect()
    };
    let (avg_points, max_points) = (series(1), series(2));
    let qem = history.qem.as_ref().map(|q| q.evaluation);
    let values: Vec<f64> = avg_points
        .iter()
        .chain(&max_points)
        .map(|p| p[1])
        .chain(qem.iter().flat_map(|q| [log10(q.e_avg), log10(q.e_max)]))
        .collect();
    let avg = PlotPoints::from(envelope(&avg_points, buckets));
    let max = PlotPoints::from(envelope(&max_points, buckets));
    // Markers while the series is short (a single point draws no line).
    let marks = (history.errors.len() < 40).then_some((avg_points, max_points));
    log_plot("vertex_errors", height, x_max, values)
        .label_formatter(log_hover("model units²"))
        .show(ui, move |plot| {
            if let Some((avg_marks, max_marks)) = marks {
                plot.points(
                    Points::new("GNG3D E_avg", PlotPoints::from(avg_marks))
                        .color(AVG_COLOR)
                        .radius(2.5),
                );
                plot.points(
                    Points::new("GNG3D E_max", PlotPoints::from(max_marks))
                        .color(MAX_COLOR)
                        .radius(2.5),
                );
            }
            plot.line(Line::new("GNG3D E_avg", avg).color(AVG_COLOR).width(1.5));
            plot.line(Line::new("GNG3D E_max", max).color(MAX_COLOR).width(1.5));
            if let Some(q) = qem {
                qem_line(plot, "QEM E_avg", log10(q.e_avg), AVG_COLOR);
                qem_line(plot, "QEM E_max", log10(q.e_max), MAX_COLOR);
            }
        });
}

/// The paper's |E_sur| (|Area(original) − Area(simplified)|, squared model units, log y, as
/// `gng3d reproduce` draws Figure 1) after each reconstruction, QEM dashed. The signed value
/// (positive: area lost) is in the hover text.
pub fn surface_error_plot(ui: &mut egui::Ui, history: &History, height: f32, x_max: f64) {
    let signed: Vec<(f64, f64)> = history
        .reconstructions
        .iter()
        .map(|c| (c.iteration as f64, c.evaluation.e_sur))
        .collect();
    let sur: Vec<[f64; 2]> = signed.iter().map(|&(x, e)| [x, log10(e.abs())]).collect();
    let qem = history.qem.as_ref().map(|q| q.evaluation.e_sur);
    let values: Vec<f64> = sur
        .iter()
        .map(|p| p[1])
        .chain(qem.map(|q| log10(q.abs())))
        .collect();
    log_plot("surface_error", height, x_max, values)
        .label_formatter(move |pos| {
            let (name, p) = hovered(pos);
            // The signed value of the checkpoint (or QEM) under the pointer.
            let sign = if name.starts_with("QEM") {
                qem
            } else {
                signed
                    .iter()
                    .min_by(|a, b| (a.0 - p.x).abs().total_cmp(&(b.0 - p.x).abs()))
                    .map(|s| s.1)
            };
            let signed_text = sign.map_or_else(String::new, |e| {
                format!(
                    "\nsigned E_sur {} ({})",
                    format_value(e, 3),
                    if e >= 0.0 { "area lost" } else { "area gained" }
                )
            });
            Some(format!(
                "{name}\n{} signals\n|E_sur| {} model units²{signed_text}",
                format_count(p.x),
                format_value(10f64.powf(p.y), 3)
            ))
        })
        .show(ui, move |plot| {
            checkpoint_series(plot, &SURFACE_LEGEND, sur, qem.map(|q| log10(q.abs())));
        });
}

/// Symmetric Hausdorff distance (max, model units, log y) after each reconstruction, QEM dashed.
pub fn hausdorff_plot(ui: &mut egui::Ui, history: &History, height: f32, x_max: f64) {
    let hd: Vec<[f64; 2]> = history
        .reconstructions
        .iter()
        .filter_map(|c| {
            c.evaluation
                .hausdorff
                .map(|h| [c.iteration as f64, log10(h)])
        })
        .collect();
    let qem = history.qem.as_ref().and_then(|q| q.evaluation.hausdorff);
    let values: Vec<f64> = hd.iter().map(|p| p[1]).chain(qem.map(log10)).collect();
    log_plot("hausdorff", height, x_max, values)
        .label_formatter(log_hover("model units"))
        .show(ui, move |plot| {
            checkpoint_series(plot, &HAUSDORFF_LEGEND, hd, qem.map(log10));
        });
}

/// QEM's value `y` as a dashed horizontal line.
fn qem_line(plot: &mut PlotUi<'_>, name: &'static str, y: f64, color: Color32) {
    plot.hline(
        HLine::new(name, y)
            .color(color)
            .style(LineStyle::dashed_loose()),
    );
}

/// A measure after each checkpoint as a line with markers, and QEM's value (`qem`, on the
/// plot's y scale) as a dashed horizontal line, named and coloured as in `legend` (GNG3D first).
fn checkpoint_series(
    plot: &mut PlotUi<'_>,
    legend: &[LegendEntry; 2],
    points: Vec<[f64; 2]>,
    qem: Option<f64>,
) {
    let [(gng, color, _), (qem_name, _, _)] = *legend;
    plot.line(Line::new(gng, PlotPoints::from(points.clone())).color(color));
    plot.points(
        Points::new(gng, PlotPoints::from(points))
            .color(color)
            .radius(3.0),
    );
    if let Some(y) = qem {
        qem_line(plot, qem_name, y, color);
    }
}

//! Live plots in the style of the GNG3D paper's Figure 1 (E_avg and E_max against iterations on a
//! log scale, QEM's values as horizontal lines), E_sur and Hausdorff after each reconstruction on
//! their own axes, and a checkpoint table like the paper's Table 1 with CSV export. Every plot
//! spans the run's whole signal budget on x from the start, so the curves fill in left to right.

use crate::engine::Evaluation;
use crate::error::{Result, ViewerError};
use egui::{Color32, Stroke};
use egui_plot::{GridInput, GridMark, HLine, Line, LineStyle, Plot, PlotPoints, Points};
use std::path::Path;

/// Most points kept per live series; older points are thinned beyond that.
const MAX_SERIES_POINTS: usize = 4000;

/// One row of the checkpoint table.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    /// "GNG3D" or "QEM".
    pub method: &'static str,
    /// Training signals (iterations) when taken; 0 for QEM.
    pub iteration: u64,
    /// The measurements ([`crate::engine::evaluate`]).
    pub evaluation: Evaluation,
    /// Seconds of computation (training time for GNG3D).
    pub seconds: f64,
}

/// Everything the plots show for the current session.
#[derive(Debug, Clone, Default)]
pub struct History {
    /// (iteration, E_avg, E_max) of the live network.
    pub errors: Vec<[f64; 3]>,
    /// Evaluated reconstructions, in order of iteration.
    pub reconstructions: Vec<Checkpoint>,
    /// The QEM result at the same vertex count.
    pub qem: Option<Checkpoint>,
}

impl History {
    /// Forget the GNG3D series (a new session starts); the QEM reference stays.
    pub fn clear_training(&mut self) {
        self.errors.clear();
        self.reconstructions.clear();
    }

    /// Add a live error measurement.
    pub fn push_errors(&mut self, iteration: u64, e_avg: f64, e_max: f64) {
        if self.errors.last().is_some_and(|l| l[0] >= iteration as f64) {
            return;
        }
        self.errors.push([iteration as f64, e_avg, e_max]);
        if self.errors.len() > MAX_SERIES_POINTS {
            // Keep the first point and every second one after it.
            let mut keep = 0;
            self.errors.retain(|_| {
                keep += 1;
                keep % 2 == 1
            });
        }
    }

    /// Add an evaluated reconstruction (kept sorted by iteration).
    pub fn push_reconstruction(&mut self, checkpoint: Checkpoint) {
        let at = self
            .reconstructions
            .partition_point(|c| c.iteration <= checkpoint.iteration);
        self.reconstructions.insert(at, checkpoint);
    }

    /// All table rows: GNG3D checkpoints then QEM.
    pub fn rows(&self) -> impl Iterator<Item = &Checkpoint> {
        self.reconstructions.iter().chain(self.qem.iter())
    }

    /// Write the checkpoint table as CSV.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        let fail = |message: String| ViewerError::Save {
            path: path.to_path_buf(),
            message,
        };
        let text = self.csv_string().map_err(fail)?;
        std::fs::write(path, text).map_err(|e| fail(e.to_string()))
    }

    /// The checkpoint table as CSV text.
    pub fn csv_string(&self) -> Result<String, String> {
        let mut writer = csv::Writer::from_writer(Vec::new());
        let err = |e: csv::Error| e.to_string();
        writer
            .write_record([
                "method",
                "iteration",
                "vertices",
                "faces",
                "e_avg",
                "e_max",
                "e_sur",
                "hausdorff",
                "mean_min_angle_deg",
                "share_min_angle_below_30",
                "seconds",
            ])
            .map_err(err)?;
        for row in self.rows() {
            writer
                .write_record([
                    row.method.to_string(),
                    row.iteration.to_string(),
                    row.evaluation.vertices.to_string(),
                    row.evaluation.faces.to_string(),
                    format!("{:e}", row.evaluation.e_avg),
                    format!("{:e}", row.evaluation.e_max),
                    format!("{:e}", row.evaluation.e_sur),
                    row.evaluation
                        .hausdorff
                        .map(|h| format!("{h:e}"))
                        .unwrap_or_default(),
                    format!("{:.2}", row.evaluation.median_min_angle_degrees),
                    format!("{:.4}", row.evaluation.below_20_degrees),
                    format!("{:.3}", row.seconds),
                ])
                .map_err(err)?;
        }
        let bytes = writer.into_inner().map_err(|e| e.to_string())?;
        String::from_utf8(bytes).map_err(|e| e.to_string())
    }
}

/// Colour of E_avg curves.
const AVG_COLOR: Color32 = Color32::from_rgb(80, 170, 255);
/// Colour of E_max curves.
const MAX_COLOR: Color32 = Color32::from_rgb(255, 140, 60);
/// Colour of E_sur curves.
const SUR_COLOR: Color32 = Color32::from_rgb(120, 220, 120);
/// Colour of Hausdorff curves.
const HAUSDORFF_COLOR: Color32 = Color32::from_rgb(230, 110, 230);

fn log10(v: f64) -> f64 {
    v.max(1e-30).log10()
}

/// Grid marks at decades (and 2×, 5× when zoomed in) for a log10-transformed axis.
fn decade_marks(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        return Vec::new();
    }
    let mut marks = Vec::new();
    let fine = hi - lo < 3.0;
    let (mut k, end) = (lo.floor() as i64, hi.ceil() as i64);
    if end - k > 200 {
        return Vec::new();
    }
    while k <= end {
        marks.push(GridMark {
            value: k as f64,
            step_size: 1.0,
        });
        if fine {
            for m in [2f64, 5.0] {
                marks.push(GridMark {
                    value: k as f64 + m.log10(),
                    step_size: 0.1,
                });
            }
        }
        k += 1;
    }
    // Only marks inside the shown range: egui_plot draws the labels of the others outside the
    // plot, over the neighbouring widgets.
    marks.retain(|m| m.value >= lo && m.value <= hi);
    // A curve that stays within one decade (a Hausdorff distance between 0.015 and 0.04, say)
    // would show no number at all: then the 2× and 5× marks are labelled too. There are at most
    // five of them in such a range (< 2 decades), 0.3 decades apart, so the labels do not crowd.
    if marks.iter().filter(|m| m.step_size >= 1.0).count() < 2 {
        for m in &mut marks {
            m.step_size = 1.0;
        }
    }
    // A range too narrow for any 1-2-5 mark (a nearly constant curve) gets one labelled mark
    // in its middle.
    if marks.is_empty() {
        marks.push(GridMark {
            value: 0.5 * (lo + hi),
            step_size: 1.0,
        });
    }
    marks
}

/// About three or four x grid marks at 1, 2 or 5 × 10^k signals, whatever the budget: labels never crowd
/// and never repeat one value (issue 13: "ticks 102699/102700/102701").
fn count_marks(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return Vec::new();
    }
    let raw = span / 3.0;
    let decade = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * decade)
        .max(1.0);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last)
        .map(|i| GridMark {
            value: i as f64 * step,
            step_size: step,
        })
        .collect()
}

fn format_log_tick(mark: GridMark) -> String {
    // Decades only: the 2× and 5× marks of a zoomed-in axis stay unlabelled grid lines, so
    // labels never crowd (issue 13: "1.0e-3 twice over a dense band"), unless `decade_marks`
    // promoted them because fewer than two decades are in view.
    if mark.step_size < 1.0 {
        return String::new();
    }
    // 1-2-5 marks with one significant digit (10^(log10 2 - 2) prints as 2e-2, not 1.99…e-2),
    // any other value (the middle mark of a narrow range) with two.
    let v = 10f64.powf(mark.value);
    let one = format!("{v:.0e}");
    match one.parse::<f64>() {
        Ok(r) if ((r - v) / v).abs() < 1e-6 => one,
        _ => format!("{v:.1e}"),
    }
}

/// Compact signal counts for the x axis: 0, 500, 12k, 1.5M.
pub fn format_count(v: f64) -> String {
    let a = v.abs();
    if a >= 1e6 {
        format!("{}M", trim_float(v / 1e6))
    } else if a >= 1e3 {
        format!("{}k", trim_float(v / 1e3))
    } else {
        format!("{v:.0}")
    }
}

/// `v` with at most two decimals and no trailing zeros.
fn trim_float(v: f64) -> String {
    let s = format!("{v:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A linear-axis tick with as many decimals as the tick spacing needs (scientific below 0.01).
fn format_linear_tick(mark: GridMark) -> String {
    let step = mark.step_size.abs();
    if mark.value == 0.0 {
        return "0".into();
    }
    if step < 0.01 || mark.value.abs() >= 1e5 {
        return format!("{:.1e}", mark.value);
    }
    let decimals = (-step.log10().floor()).clamp(0.0, 6.0) as usize;
    format!("{:.*}", decimals, mark.value)
}

/// The series name (empty away from data) and plot position under the pointer.
fn hovered<'a>(pos: &'a egui_plot::HoverPosition<'_>) -> (&'a str, egui_plot::PlotPoint) {
    match pos {
        egui_plot::HoverPosition::NearDataPoint {
            plot_name,
            position,
            ..
        } => (plot_name, *position),
        egui_plot::HoverPosition::Elsewhere { position } => ("", *position),
    }
}

/// Base plot: no background, sparse grid, x from 0 to the signal budget with compact labels.
fn base_plot(id: &str, height: f32, x_max: f64) -> Plot<'static> {
    Plot::new(id)
        .height(height)
        // The panel colour shows through: no second fill of the plot area.
        .show_background(false)
        // Grid lines at least 24 px apart (egui_plot's default, 8 px, draws ~3× as many faint
        // lines, each of which a CPU rasterizer pays for).
        .grid_spacing(egui::Rangef::new(24.0, 300.0))
        .include_x(0.0)
        .include_x(x_max.max(1.0))
        .x_grid_spacer(count_marks)
        .x_axis_formatter(|mark, _| format_count(mark.value))
        .x_axis_label("signals")
        .allow_scroll(false)
}

/// Base plot with a log10 y axis labelled at decades.
fn log_plot(id: &str, height: f32, x_max: f64, unit: &'static str) -> Plot<'static> {
    base_plot(id, height, x_max)
        .y_grid_spacer(decade_marks)
        .y_axis_formatter(|mark, _| format_log_tick(mark))
        .label_formatter(move |pos| {
            let (name, p) = hovered(pos);
            Some(format!(
                "{name}\n{} signals\n{:.3e} {unit}",
                format_count(p.x),
                10f64.powf(p.y)
            ))
        })
}

/// One legend entry: label, colour, dashed (QEM) or solid (GNG3D).
pub type LegendEntry = (&'static str, Color32, bool);

/// A legend drawn as a row above the plot, with a short line sample per entry so solid (GNG3D)
/// and dashed (QEM) are told apart and no legend box covers data.
pub fn legend_row(ui: &mut egui::Ui, entries: &[LegendEntry]) {
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 4.0;
        for &(label, color, dashed) in entries {
            // Sample and label wrap as one unit and the label never breaks inside (in a narrow
            // plot column, "GNG3D E_max" split over two rows, away from its line sample).
            ui.horizontal(|ui| {
                let (rect, _) =
                    ui.allocate_exact_size(egui::vec2(22.0, 12.0), egui::Sense::hover());
                let (a, b) = (rect.left_center(), rect.right_center());
                let stroke = Stroke::new(2.0, color);
                if dashed {
                    ui.painter()
                        .extend(egui::Shape::dashed_line(&[a, b], stroke, 4.0, 3.0));
                } else {
                    ui.painter().line_segment([a, b], stroke);
                }
                ui.add(
                    egui::Label::new(egui::RichText::new(label).small())
                        .wrap_mode(egui::TextWrapMode::Extend),
                );
            });
            ui.add_space(6.0);
        }
    });
}

/// At most two points (the lowest and the highest, in series order) per bucket of consecutive
/// points, `buckets` buckets in all: the line keeps its envelope with a bounded number of segments.
pub fn envelope(points: &[[f64; 2]], buckets: usize) -> Vec<[f64; 2]> {
    let buckets = buckets.max(1);
    if points.len() <= 2 * buckets {
        return points.to_vec();
    }
    let mut out = Vec::with_capacity(2 * buckets);
    for b in 0..buckets {
        let chunk = &points[b * points.len() / buckets..(b + 1) * points.len() / buckets];
        let lowest = (0..chunk.len()).min_by(|&i, &j| chunk[i][1].total_cmp(&chunk[j][1]));
        let highest = (0..chunk.len()).max_by(|&i, &j| chunk[i][1].total_cmp(&chunk[j][1]));
        if let (Some(lo), Some(hi)) = (lowest, highest) {
            out.push(chunk[lo.min(hi)]);
            if lo != hi {
                out.push(chunk[lo.max(hi)]);
            }
        }
    }
    out
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
    ("GNG3D E_sur", SUR_COLOR, false),
    ("QEM E_sur", SUR_COLOR, true),
];
/// Legend of the Hausdorff plot.
pub const HAUSDORFF_LEGEND: [LegendEntry; 2] = [
    ("GNG3D Hausdorff", HAUSDORFF_COLOR, false),
    ("QEM Hausdorff", HAUSDORFF_COLOR, true),
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
    let avg = PlotPoints::from(envelope(&avg_points, buckets));
    let max = PlotPoints::from(envelope(&max_points, buckets));
    // Markers while the series is short (a single point draws no line).
    let marks = (history.errors.len() < 40).then_some((avg_points, max_points));
    let qem = history.qem.as_ref().map(|q| q.evaluation);
    log_plot("vertex_errors", height, x_max, "model units²")
        .y_axis_label("model units²")
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
                plot.hline(
                    HLine::new("QEM E_avg", log10(q.e_avg))
                        .color(AVG_COLOR)
                        .style(LineStyle::dashed_loose()),
                );
                plot.hline(
                    HLine::new("QEM E_max", log10(q.e_max))
                        .color(MAX_COLOR)
                        .style(LineStyle::dashed_loose()),
                );
            }
        });
}

/// Signed E_sur (Area(original) − Area(simplified), squared model units, linear y) after each
/// reconstruction, QEM dashed.
pub fn surface_error_plot(ui: &mut egui::Ui, history: &History, height: f32, x_max: f64) {
    let sur: Vec<[f64; 2]> = history
        .reconstructions
        .iter()
        .map(|c| [c.iteration as f64, c.evaluation.e_sur])
        .collect();
    let qem = history.qem.as_ref().map(|q| q.evaluation.e_sur);
    let mut plot = base_plot("surface_error", height, x_max)
        .y_axis_label("model units²")
        .y_axis_formatter(|mark, _| format_linear_tick(mark))
        .label_formatter(|pos| {
            let (name, p) = hovered(pos);
            Some(format!(
                "{name}\n{} signals\nE_sur {:.3e} model units²",
                format_count(p.x),
                p.y
            ))
        });
    if sur.is_empty() && qem.is_none() {
        // Nothing yet: a sane empty axis instead of −0.02…0.02.
        plot = plot.include_y(0.0).include_y(1.0);
    }
    plot.show(ui, move |plot| {
        plot.line(Line::new("GNG3D E_sur", PlotPoints::from(sur.clone())).color(SUR_COLOR));
        plot.points(
            Points::new("GNG3D E_sur", PlotPoints::from(sur))
                .color(SUR_COLOR)
                .radius(3.0),
        );
        if let Some(q) = qem {
            plot.hline(
                HLine::new("QEM E_sur", q)
                    .color(SUR_COLOR)
                    .style(LineStyle::dashed_loose()),
            );
        }
    });
}

/// Symmetric Hausdorff distance (model units, log y) after each reconstruction, QEM dashed.
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
    let mut plot = log_plot("hausdorff", height, x_max, "model units").y_axis_label("model units");
    match (hd.is_empty(), qem) {
        (true, None) => plot = plot.include_y(-3.0).include_y(0.0),
        // QEM's line alone (before the first reconstruction): half a decade either side, so
        // the axis has labelled marks around it.
        (true, Some(h)) => plot = plot.include_y(log10(h) - 0.5).include_y(log10(h) + 0.5),
        _ => {}
    }
    plot.show(ui, move |plot| {
        plot.line(
            Line::new("GNG3D Hausdorff", PlotPoints::from(hd.clone())).color(HAUSDORFF_COLOR),
        );
        plot.points(
            Points::new("GNG3D Hausdorff", PlotPoints::from(hd))
                .color(HAUSDORFF_COLOR)
                .radius(3.0),
        );
        if let Some(h) = qem {
            plot.hline(
                HLine::new("QEM Hausdorff", log10(h))
                    .color(HAUSDORFF_COLOR)
                    .style(LineStyle::dashed_loose()),
            );
        }
    });
}

/// Column headers of the checkpoint table, with their hover explanations.
pub const TABLE_COLUMNS: [(&str, &str); 11] = [
    (
        "method",
        "GNG3D checkpoint or the QEM result at the same vertex target",
    ),
    (
        "signals",
        "training signals when the network was reconstructed",
    ),
    ("V", "vertices"),
    ("F", "faces"),
    (
        "E_avg",
        "mean squared distance from each original vertex to the nearest simplified vertex (model units²)",
    ),
    ("E_max", "largest such squared distance (model units²)"),
    (
        "E_sur",
        "Area(original) - Area(simplified), model units² (signed)",
    ),
    ("Hausdorff", "symmetric Hausdorff distance, model units"),
    (
        "min angle",
        "mean smallest triangle angle, degrees (60 = equilateral)",
    ),
    (
        "<30°",
        "share of triangles whose smallest angle is under 30°",
    ),
    (
        "time (s)",
        "training seconds (GNG3D) or simplification seconds (QEM)",
    ),
];

/// The checkpoint table (paper's Table 1 columns plus Hausdorff, triangle quality and time),
/// scrollable both ways inside whatever space it gets.
pub fn checkpoint_table(ui: &mut egui::Ui, history: &History) {
    // Solid scroll bars take their own space: floating ones would hide the last row.
    ui.spacing_mut().scroll = egui::style::ScrollStyle::solid();
    egui::ScrollArea::both()
        .id_salt("checkpoints")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            egui::Grid::new("checkpoint_grid")
                .striped(true)
                .num_columns(TABLE_COLUMNS.len())
                .spacing([8.0, 2.0])
                .show(ui, |ui| {
                    for (h, hover) in TABLE_COLUMNS {
                        ui.strong(h).on_hover_text(hover);
                    }
                    ui.end_row();
                    // Newest GNG3D checkpoint first, QEM last (always visible without scrolling
                    // far when the table is short).
                    for row in history.rows() {
                        let e = &row.evaluation;
                        ui.label(row.method);
                        ui.label(format_count(row.iteration as f64));
                        ui.label(e.vertices.to_string());
                        ui.label(e.faces.to_string());
                        ui.label(format!("{:.3e}", e.e_avg));
                        ui.label(format!("{:.3e}", e.e_max));
                        ui.label(format!("{:.3e}", e.e_sur));
                        ui.label(
                            e.hausdorff
                                .map_or_else(|| "–".into(), |h| format!("{h:.3e}")),
                        );
                        ui.label(format!("{:.1}°", e.median_min_angle_degrees));
                        ui.label(format!("{:.1} %", 100.0 * e.below_20_degrees));
                        ui.label(format!("{:.2}", row.seconds));
                        ui.end_row();
                    }
                });
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(method: &'static str, iteration: u64, e_avg: f64) -> Checkpoint {
        Checkpoint {
            method,
            iteration,
            evaluation: Evaluation {
                vertices: 10,
                faces: 16,
                e_avg,
                e_max: e_avg * 4.0,
                e_sur: -0.5,
                hausdorff: None,
                median_min_angle_degrees: 41.0,
                below_20_degrees: 0.25,
            },
            seconds: 1.0,
        }
    }

    #[test]
    fn csv_has_header_and_one_line_per_row_in_iteration_order() {
        let mut history = History::default();
        history.push_reconstruction(row("GNG3D", 2000, 1e-3));
        history.push_reconstruction(row("GNG3D", 1000, 2e-3));
        history.qem = Some(row("QEM", 0, 5e-4));
        let text = history.csv_string().unwrap();
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        let headers = reader.headers().unwrap().clone();
        assert_eq!(&headers[0], "method");
        let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(&rows[0][1], "1000");
        assert_eq!(&rows[1][1], "2000");
        assert_eq!(&rows[2][0], "QEM");
        assert_eq!(rows[0][4].parse::<f64>().unwrap(), 2e-3);
        assert_eq!(&rows[0][7], "");
        assert_eq!(rows[0][6].parse::<f64>().unwrap(), -0.5, "signed E_sur");
        assert_eq!(&rows[0][8], "41.00");
    }

    #[test]
    fn error_series_is_monotone_and_bounded() {
        let mut history = History::default();
        for i in 0..(3 * MAX_SERIES_POINTS as u64) {
            history.push_errors(i + 1, 1.0 / (i + 1) as f64, 2.0);
        }
        history.push_errors(5, 1.0, 1.0); // out of order: ignored
        assert!(history.errors.len() <= MAX_SERIES_POINTS);
        assert!(history.errors.windows(2).all(|w| w[0][0] < w[1][0]));
        assert_eq!(history.errors[0][0], 1.0);
        assert_eq!(
            history.errors.last().unwrap()[0] as u64,
            3 * MAX_SERIES_POINTS as u64
        );
    }

    #[test]
    fn decade_marks_cover_the_range() {
        let marks = decade_marks(GridInput {
            bounds: (-6.5, -2.2),
            base_step_size: 0.01,
        });
        let decades: Vec<f64> = marks
            .iter()
            .filter(|m| m.step_size == 1.0)
            .map(|m| m.value)
            .collect();
        assert_eq!(decades, vec![-6.0, -5.0, -4.0, -3.0]);
        assert!(marks.iter().all(|m| (-6.5..=-2.2).contains(&m.value)));
        let x: Vec<f64> = count_marks(GridInput {
            bounds: (0.0, 87_900.0),
            base_step_size: 1.0,
        })
        .iter()
        .map(|m| m.value)
        .collect();
        assert_eq!(x, vec![0.0, 50_000.0]);
        assert_eq!(format_count(20_000.0), "20k");
        assert_eq!(format_count(1_500_000.0), "1.5M");
        assert_eq!(
            format_log_tick(GridMark {
                value: -3.0,
                step_size: 1.0
            }),
            "1e-3"
        );
    }

    /// The non-empty tick labels of a log axis from `lo` to `hi` (values, not logs).
    fn log_labels(lo: f64, hi: f64) -> Vec<String> {
        decade_marks(GridInput {
            bounds: (lo.log10(), hi.log10()),
            base_step_size: 0.01,
        })
        .into_iter()
        .map(format_log_tick)
        .filter(|l| !l.is_empty())
        .collect()
    }

    #[test]
    fn a_range_inside_one_decade_still_gets_labelled_ticks() {
        // Hausdorff between 0.015 and 0.04: no decade inside, 2e-2 must be labelled.
        assert_eq!(log_labels(0.015, 0.04), vec!["2e-2".to_string()]);
        // One decade inside (0.08 … 0.3): 1e-1 and 2e-1 labelled.
        assert_eq!(
            log_labels(0.08, 0.3),
            vec!["1e-1".to_string(), "2e-1".to_string()]
        );
        // Two decades or more: only decades labelled.
        assert_eq!(log_labels(6.3e-4, 0.126).len(), 3);
        // A range too narrow for any 1-2-5 mark (a constant line at 2.7e-3): one mark in the
        // middle, labelled with two digits.
        let marks = decade_marks(GridInput {
            bounds: (0.0026f64.log10(), 0.0028f64.log10()),
            base_step_size: 0.001,
        });
        assert_eq!(marks.len(), 1);
        assert_eq!(format_log_tick(marks[0]), "2.7e-3");
    }

    #[test]
    fn envelope_keeps_each_bucket_extremes_in_order_and_bounds_the_count() {
        // A noisy decaying series, like E_max while training.
        let points: Vec<[f64; 2]> = (0..10_007)
            .map(|i| {
                let x = i as f64;
                [x, (-x / 3000.0).exp() + 0.1 * ((x * 0.37).sin())]
            })
            .collect();
        let buckets = 100;
        let thinned = envelope(&points, buckets);
        assert!(thinned.len() <= 2 * buckets);
        assert!(
            thinned.windows(2).all(|w| w[0][0] < w[1][0]),
            "x must increase"
        );
        // Every kept point is an input point; the global extremes survive.
        assert!(thinned.iter().all(|p| points.contains(p)));
        let extreme = |pts: &[[f64; 2]], max: bool| {
            pts.iter()
                .map(|p| p[1])
                .fold(if max { f64::MIN } else { f64::MAX }, |a, b| {
                    if max { a.max(b) } else { a.min(b) }
                })
        };
        assert_eq!(extreme(&thinned, true), extreme(&points, true));
        assert_eq!(extreme(&thinned, false), extreme(&points, false));
        // Each bucket's own minimum and maximum are kept (checked bucket by bucket).
        for b in 0..buckets {
            let chunk = &points[b * points.len() / buckets..(b + 1) * points.len() / buckets];
            for want in [extreme(chunk, true), extreme(chunk, false)] {
                assert!(
                    thinned.iter().any(|p| p[1] == want
                        && p[0] >= chunk[0][0]
                        && p[0] <= chunk[chunk.len() - 1][0]),
                    "bucket {b} lost {want}"
                );
            }
        }
        // Short series pass through unchanged.
        assert_eq!(envelope(&points[..150], buckets), points[..150].to_vec());
    }
}

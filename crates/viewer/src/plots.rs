//! Live plots in the style of the GNG3D paper's Figure 1 (E_avg and E_max against iterations on a
//! log scale, QEM's values as horizontal lines), E_sur and Hausdorff after each reconstruction on
//! their own axes, and a checkpoint table like the paper's Table 1 with CSV export. Every plot
//! spans the run's whole signal budget on x from the start, so the curves fill in left to right.

use crate::engine::{AttributeFigures, Evaluation};
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

    /// The checkpoint table as CSV text. With attributes (some row has their deviation), four
    /// more columns: the UV deviation's mean in texels and its share of samples over the
    /// threshold, the normals' mean angle in degrees and the colours' mean distance (empty
    /// where a row lacks the attribute); positions-only tables keep their columns.
    pub fn csv_string(&self) -> Result<String, String> {
        let mut writer = csv::Writer::from_writer(Vec::new());
        let err = |e: csv::Error| e.to_string();
        let with_attributes = self.rows().any(|r| r.evaluation.attributes.is_some());
        let mut header = vec![
            "method",
            "iteration",
            "vertices",
            "faces",
            "e_avg",
            "e_max",
            "e_sur",
            "hausdorff_max",
            "hausdorff_mean",
            "median_min_angle_deg",
            "share_min_angle_below_20",
            "seconds",
        ];
        if with_attributes {
            header.extend([
                "uv_texels_mean",
                "uv_share_over_threshold",
                "normal_deg_mean",
                "color_mean",
            ]);
        }
        writer.write_record(&header).map_err(err)?;
        let value = |v: Option<f64>| v.map(|v| format!("{v:e}")).unwrap_or_default();
        for row in self.rows() {
            let mut record = vec![
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
                row.evaluation
                    .hausdorff_mean
                    .map(|h| format!("{h:e}"))
                    .unwrap_or_default(),
                format!("{:.2}", row.evaluation.median_min_angle_degrees),
                format!("{:.4}", row.evaluation.below_20_degrees),
                format!("{:.3}", row.seconds),
            ];
            if with_attributes {
                let a = row.evaluation.attributes.unwrap_or_default();
                record.extend([
                    value(a.uv_texels_mean),
                    value(a.uv_over_threshold),
                    value(a.normal_degrees_mean),
                    value(a.color_mean),
                ]);
            }
            writer.write_record(&record).map_err(err)?;
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

/// Least distance between two labelled y ticks, points (a line of tick text is ~16 points).
const MIN_Y_LABEL_GAP: f32 = 26.0;
/// Least distance between two labelled x ticks, points ("1.25M" is ~40 points wide).
const MIN_X_LABEL_GAP: f32 = 64.0;

/// Points per axis unit, from what egui_plot hands a grid spacer: `base_step_size` is the
/// axis units per the plot's smallest grid spacing ([`GRID_MIN_SPACING`] points).
fn points_per_unit(input: &GridInput) -> f32 {
    if input.base_step_size > 0.0 && input.base_step_size.is_finite() {
        (f64::from(GRID_MIN_SPACING) / input.base_step_size) as f32
    } else {
        0.0
    }
}

/// Smallest spacing of the plots' grid lines, points.
const GRID_MIN_SPACING: f32 = 24.0;

/// A labelled tick. egui_plot hides or fades a tick's label when `step_size` spans fewer than
/// 20-30 points (y) or 60-80 points (x), which made the labels vanish on plots with many
/// decades or little height; the spacers here choose their labelled ticks far enough apart
/// themselves, so every labelled tick carries the whole axis span as its step size (full
/// strength), and [`is_labelled`] tells the formatters which ones they are.
fn labelled(value: f64, span: f64) -> GridMark {
    GridMark {
        value,
        step_size: span,
    }
}

/// An unlabelled grid line (a tenth of the span: a faint line).
fn unlabelled(value: f64, span: f64) -> GridMark {
    GridMark {
        value,
        step_size: 0.1 * span,
    }
}

/// Whether a mark of an axis showing `range` is one of the labelled ticks.
fn is_labelled(mark: &GridMark, range: &std::ops::RangeInclusive<f64>) -> bool {
    mark.step_size >= 0.5 * (range.end() - range.start()).abs()
}

/// Two labelled ticks near the ends of the range (a twentieth of it inside: where the data's
/// extremes sit with egui_plot's margins), for a range where no round values fit.
fn end_marks(lo: f64, hi: f64) -> Vec<GridMark> {
    let span = hi - lo;
    vec![
        labelled(lo + span / 22.0, span),
        labelled(hi - span / 22.0, span),
    ]
}

/// Grid marks of a log10-transformed axis whose labels never crowd and never vanish: decades
/// (every 1, 2, 3, 5 or 10 decades, as the plot's height allows); within less than two decades
/// the 1-2-5 values when they are far enough apart; otherwise two ticks near the ends. Every
/// axis gets at least two labelled ticks (issue 37: a plot with one tick or none).
fn log_marks(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let span = hi - lo;
    if !(lo.is_finite() && hi.is_finite()) || span <= 0.0 {
        return Vec::new();
    }
    let ppu = points_per_unit(&input).max(1e-6);
    let inside = |v: f64| v >= lo && v <= hi;
    let decades: Vec<i64> = ((lo.ceil() as i64)..=(hi.floor() as i64)).collect();
    if decades.len() > 400 {
        return end_marks(lo, hi);
    }
    let mut marks = Vec::new();
    if decades.len() >= 2 {
        let stride = [1, 2, 3, 5, 10, 20, 50, 100]
            .into_iter()
            .find(|&s| s as f32 * ppu >= MIN_Y_LABEL_GAP)
            .unwrap_or(100);
        let chosen: Vec<i64> = decades
            .iter()
            .copied()
            .filter(|d| d.rem_euclid(stride) == 0)
            .collect();
        if chosen.len() >= 2 {
            for d in decades {
                marks.push(if d.rem_euclid(stride) == 0 {
                    labelled(d as f64, span)
                } else {
                    unlabelled(d as f64, span)
                });
            }
            return marks;
        }
    }
    // Less than two decades (or too little height for two of them): 1-2-5 values, the closest
    // two of which (5 and 10) are 0.3 decades apart.
    let nice: Vec<f64> = ((lo.floor() as i64)..=(hi.ceil() as i64))
        .flat_map(|k| [1f64, 2.0, 5.0].map(|m| k as f64 + m.log10()))
        .filter(|&v| inside(v))
        .collect();
    if nice.len() >= 2 && 0.3 * ppu >= MIN_Y_LABEL_GAP {
        return nice.into_iter().map(|v| labelled(v, span)).collect();
    }
    let mut marks = end_marks(lo, hi);
    marks.extend(nice.into_iter().map(|v| unlabelled(v, span)));
    marks
}

/// Linear x marks (signals): round values (1, 2 or 5 × 10^k apart) at least
/// [`MIN_X_LABEL_GAP`] points apart from 0 up to `end` (the run's budget), and `end` itself
/// labelled when the last round value is short of it, so the axis always shows where it starts
/// and ends (issue 13: labels never repeat one value; issue 37: end values always shown).
fn count_marks(input: GridInput, end: f64) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return Vec::new();
    }
    let ppu = f64::from(points_per_unit(&input)).max(1e-12);
    let raw = (f64::from(MIN_X_LABEL_GAP) / ppu).max(span / 8.0);
    let decade = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * decade)
        .max(1.0);
    let first = (lo.max(0.0) / step).ceil() as i64;
    let last_value = if end > 0.0 && end <= hi { end } else { hi };
    let last = (last_value / step).floor() as i64;
    let mut values: Vec<f64> = (first..=last).map(|i| i as f64 * step).collect();
    if end > 0.0 && end <= hi {
        let gap = f64::from(MIN_X_LABEL_GAP) / ppu;
        // The budget's own tick replaces a round value too close to it.
        while values.last().is_some_and(|&v| end - v < gap && v != 0.0) {
            values.pop();
        }
        if values.last().is_none_or(|&v| end - v >= gap) {
            values.push(end);
        }
    }
    values.into_iter().map(|v| labelled(v, span)).collect()
}

/// A number for a tick or a table cell, with `digits` significant digits: plain between 0.001
/// and 10,000 ("0.0073", "7.3", "730"), engineering notation outside (exponent a multiple of
/// 3: "73e-6", "1.5e6"); never "7.3e0" (issue 37).
pub fn format_value(v: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let a = v.abs();
    let exponent = a.log10().floor() as i32;
    if (-3..4).contains(&exponent) {
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        let s = format!("{v:.decimals$}");
        // Rounding up can add a digit (9.96 → "10.0"): drop the extra decimal.
        return if decimals > 0 && s.contains('.') {
            let t = s.trim_end_matches('0').trim_end_matches('.');
            t.to_string()
        } else {
            s
        };
    }
    let mut eng = exponent.div_euclid(3) * 3;
    let mut mantissa = v / 10f64.powi(eng);
    let mut decimals =
        (digits as i32 - 1 - (mantissa.abs().log10().floor() as i32)).max(0) as usize;
    let mut text = format!("{mantissa:.decimals$}");
    if text
        .trim_start_matches('-')
        .parse::<f64>()
        .is_ok_and(|m| m >= 1000.0)
    {
        eng += 3;
        mantissa = v / 10f64.powi(eng);
        decimals = digits.saturating_sub(1);
        text = format!("{mantissa:.decimals$}");
    }
    if text.contains('.') {
        text = text.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    format!("{text}e{eng}")
}

/// A log-axis tick: `10^mark`, two significant digits (a round 1-2-5 value prints with one).
fn format_log_tick(mark: GridMark, range: &std::ops::RangeInclusive<f64>) -> String {
    if !is_labelled(&mark, range) {
        return String::new();
    }
    format_value(10f64.powf(mark.value), 2)
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

/// Base plot: no background, sparse grid, x from 0 to the signal budget with compact labels
/// at both ends.
fn base_plot(id: &str, height: f32, x_max: f64) -> Plot<'static> {
    let end = x_max.max(1.0);
    Plot::new(id)
        .height(height)
        // The panel colour shows through: no second fill of the plot area.
        .show_background(false)
        // Grid lines at least 24 px apart (egui_plot's default, 8 px, draws ~3× as many faint
        // lines, each of which a CPU rasterizer pays for).
        .grid_spacing(egui::Rangef::new(GRID_MIN_SPACING, 300.0))
        .include_x(0.0)
        .include_x(end)
        .x_grid_spacer(move |input| count_marks(input, end))
        .x_axis_formatter(|mark, range| {
            if is_labelled(&mark, range) {
                format_count(mark.value)
            } else {
                String::new()
            }
        })
        .x_axis_label("signals")
        .allow_scroll(false)
}

/// The log10 y range a plot of `values` (already log10) shows at least: the values, and at
/// least [`MIN_LOG_SPAN`] decades around their middle, so a single point or a flat line gets
/// a sensible axis with labelled ticks on both sides (issue 37).
pub fn log_y_range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return None;
    }
    let middle = 0.5 * (lo + hi);
    let half = (0.5 * MIN_LOG_SPAN).max(0.5 * (hi - lo));
    Some((lo.min(middle - half), hi.max(middle + half)))
}

/// Least decades a log plot spans (a lone value gets a third of a decade either side).
pub const MIN_LOG_SPAN: f64 = 0.7;

/// Base plot with a log10 y axis: its y range holds `values` (log10, see [`log_y_range`]).
fn log_plot(
    id: &str,
    height: f32,
    x_max: f64,
    values: impl IntoIterator<Item = f64>,
) -> Plot<'static> {
    let mut plot = base_plot(id, height, x_max)
        .y_grid_spacer(log_marks)
        .y_axis_formatter(format_log_tick);
    let (lo, hi) = log_y_range(values).unwrap_or((-3.0, 0.0));
    plot = plot.include_y(lo).include_y(hi);
    plot
}

/// Hover text of a log plot: series, signals, value with its unit.
fn log_hover(unit: &'static str) -> impl Fn(&egui_plot::HoverPosition<'_>) -> Option<String> {
    move |pos| {
        let (name, p) = hovered(pos);
        Some(format!(
            "{name}\n{} signals\n{} {unit}",
            format_count(p.x),
            format_value(10f64.powf(p.y), 3)
        ))
    }
}

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
            plot.line(Line::new("GNG3D |E_sur|", PlotPoints::from(sur.clone())).color(SUR_COLOR));
            plot.points(
                Points::new("GNG3D |E_sur|", PlotPoints::from(sur))
                    .color(SUR_COLOR)
                    .radius(3.0),
            );
            if let Some(q) = qem {
                plot.hline(
                    HLine::new("QEM |E_sur|", log10(q.abs()))
                        .color(SUR_COLOR)
                        .style(LineStyle::dashed_loose()),
                );
            }
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
            plot.line(
                Line::new("GNG3D Hausdorff max", PlotPoints::from(hd.clone()))
                    .color(HAUSDORFF_COLOR),
            );
            plot.points(
                Points::new("GNG3D Hausdorff max", PlotPoints::from(hd))
                    .color(HAUSDORFF_COLOR)
                    .radius(3.0),
            );
            if let Some(h) = qem {
                plot.hline(
                    HLine::new("QEM Hausdorff max", log10(h))
                        .color(HAUSDORFF_COLOR)
                        .style(LineStyle::dashed_loose()),
                );
            }
        });
}

/// Column headers of the full checkpoint table (every checkpoint, [`history_table`]), with
/// their hover explanations.
pub const TABLE_COLUMNS: [(&str, &str); 12] = [
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
        "E_avg (u²)",
        "the paper's E_avg: mean squared distance from each original vertex to the nearest \
         simplified vertex, squared model units",
    ),
    (
        "E_max (u²)",
        "the paper's E_max: largest such squared distance, squared model units",
    ),
    (
        "|E_sur| (u²)",
        "the paper's E_sur: |Area(original) - Area(simplified)|, squared model units",
    ),
    (
        "Hausdorff max (u)",
        "symmetric Hausdorff distance (the larger one-sided maximum), model units",
    ),
    (
        "Hausdorff mean (u)",
        "mean surface distance (both directions), model units",
    ),
    (
        "min angle (°)",
        "median over triangles of the smallest angle, degrees (60 = equilateral)",
    ),
    (
        "< 20° (%)",
        "share of triangles whose smallest angle is under 20°",
    ),
    (
        "time (s)",
        "training seconds (GNG3D) or simplification seconds (QEM)",
    ),
];

/// The rows of Table 1 as the viewer shows it ([`comparison_table`]): label, hover text, and
/// the cell of an evaluation. "u" is the model's unit of length.
type TableRow = (&'static str, &'static str, fn(&Evaluation) -> String);

/// Significant digits of the table's errors.
const TABLE_DIGITS: usize = 3;

/// Table 1's rows: what is measured, with max/mean and units in the label.
pub const TABLE_ROWS: [TableRow; 8] = [
    ("V / F", "vertices / faces", |e| {
        format!("{} / {}", e.vertices, e.faces)
    }),
    (
        "E_avg (u²)",
        "the paper's E_avg: mean squared distance from each original vertex to the nearest \
         simplified vertex (u = model units)",
        |e| format_value(e.e_avg, TABLE_DIGITS),
    ),
    (
        "E_max (u²)",
        "the paper's E_max: the largest such squared distance (u = model units)",
        |e| format_value(e.e_max, TABLE_DIGITS),
    ),
    (
        "|E_sur| (u²)",
        "the paper's E_sur: |Area(original) − Area(simplified)| (u = model units); hover a \
         value for its sign",
        |e| format_value(e.e_sur.abs(), TABLE_DIGITS),
    ),
    (
        "Hausdorff max (u)",
        "symmetric Hausdorff distance: the larger of the two one-sided maxima (u = model \
         units, 200k samples per direction)",
        |e| {
            e.hausdorff
                .map_or_else(|| "–".into(), |h| format_value(h, TABLE_DIGITS))
        },
    ),
    (
        "Hausdorff mean (u)",
        "mean surface distance, both directions (u = model units)",
        |e| {
            e.hausdorff_mean
                .map_or_else(|| "–".into(), |h| format_value(h, TABLE_DIGITS))
        },
    ),
    (
        "min angle, median (°)",
        "median over triangles of the smallest angle, degrees (60 = equilateral)",
        |e| format!("{:.1}", e.median_min_angle_degrees),
    ),
    (
        "angles < 20° (%)",
        "share of triangles whose smallest angle is under 20°",
        |e| format!("{:.1}", 100.0 * e.below_20_degrees),
    ),
];

/// One of Table 1's attribute rows: label (with its unit), hover text, the value where the
/// output has the attribute, and a detail for the value's hover text.
pub type AttributeRow = (
    String,
    String,
    fn(&AttributeFigures) -> Option<String>,
    fn(&AttributeFigures) -> Option<String>,
);

/// Table 1's attribute rows, shown when the loaded mesh has attributes (samples on each output
/// against the original, as `gng3d compare`): one row per attribute, so that the table stays
/// within the plots panel (the share of UV samples off by more than the threshold is the UV
/// value's hover text).
pub fn attribute_rows(figures: &AttributeFigures) -> [AttributeRow; 3] {
    let size = figures.texture_size;
    [
        (
            format!("UV mean (texels @{size})"),
            format!(
                "mean distance between the output's texture coordinates and the original's at \
                 the closest points, in texels of a {size}×{size} texture; hover a value for the \
                 share of samples off by more than {} UV",
                figures.uv_threshold
            ),
            |a| a.uv_texels_mean.map(|v| format!("{v:.2}")),
            |a| {
                a.uv_over_threshold.map(|v| {
                    format!(
                        "{:.2} % of the samples more than {} UV off",
                        100.0 * v,
                        a.uv_threshold
                    )
                })
            },
        ),
        (
            "normal dev. mean (°)".into(),
            "mean angle between the output's normals and the original's at the closest points"
                .into(),
            |a| a.normal_degrees_mean.map(|v| format!("{v:.2}")),
            |_| None,
        ),
        (
            "colour dev. mean (RGB)".into(),
            "mean distance between the output's vertex colours and the original's at the \
             closest points (linear RGB, channels 0–1)"
                .into(),
            |a| a.color_mean.map(|v| format!("{v:.3}")),
            |_| None,
        ),
    ]
}

/// Width the comparison table asks for, points (its labels and two value columns at the
/// default body font).
pub const TABLE_WIDTH: f32 = 300.0;

/// What [`comparison_table`] laid out: the rectangle it could draw in (its clip rectangle)
/// and every cell's rectangle (tests check that all of them are inside).
#[derive(Debug, Clone)]
pub struct TableLayout {
    /// The area the table may draw in.
    pub clip: egui::Rect,
    /// Every cell (header and values), row by row.
    pub cells: Vec<egui::Rect>,
}

/// Table 1 for the current comparison: the latest evaluated GNG3D checkpoint (`method`: which
/// GNG3D) next to QEM, one row per measure, so it fits a plot column without scrolling (issue
/// 37). The whole history is in [`history_table`] and the CSV export.
pub fn comparison_table(ui: &mut egui::Ui, history: &History, method: &str) -> TableLayout {
    let mut layout = TableLayout {
        clip: ui.clip_rect().intersect(ui.max_rect()),
        cells: Vec::new(),
    };
    let latest = history.reconstructions.last();
    let qem = history.qem.as_ref();
    // Rows as high as their text (not the 18-point interaction height): the nine rows fit
    // the plots panel at 1024×600 (148 points).
    ui.spacing_mut().interact_size.y = 0.0;
    ui.spacing_mut().item_spacing.y = 0.0;
    egui::Grid::new("table1")
        .striped(true)
        .num_columns(3)
        .spacing([10.0, 0.0])
        .min_row_height(0.0)
        .show(ui, |ui| {
            let mut cell = |r: egui::Response| layout.cells.push(r.rect);
            let at = latest.map_or_else(
                || "no checkpoint yet".to_string(),
                |c| format!("at {} signals", format_count(c.iteration as f64)),
            );
            let r = ui.label(egui::RichText::new("u = model unit").weak());
            cell(r);
            let r = ui.strong(method).on_hover_text(at);
            cell(r);
            let r = ui.strong("QEM");
            cell(r);
            ui.end_row();
            for (label, hover, value) in TABLE_ROWS {
                let r = ui.label(label).on_hover_text(hover);
                cell(r);
                for row in [latest, qem] {
                    let text = row.map_or_else(|| "–".into(), |c| value(&c.evaluation));
                    let r = ui.label(text);
                    let r = if label.starts_with("|E_sur|")
                        && let Some(c) = row
                    {
                        r.on_hover_text(format!(
                            "signed E_sur = Area(original) − Area(simplified) = {}",
                            format_value(c.evaluation.e_sur, TABLE_DIGITS)
                        ))
                    } else {
                        r
                    };
                    cell(r);
                }
                ui.end_row();
            }
            // The attribute deviation of both outputs, one row per attribute either has.
            let figures = [latest, qem].map(|c| c.and_then(|c| c.evaluation.attributes));
            if let Some(any) = figures.iter().flatten().next() {
                for (label, hover, value, detail) in attribute_rows(any) {
                    if figures.iter().flatten().all(|f| value(f).is_none()) {
                        continue;
                    }
                    let r = ui.label(label).on_hover_text(hover);
                    cell(r);
                    for f in figures {
                        let text = f.and_then(|f| value(&f)).unwrap_or_else(|| "–".into());
                        let r = ui.label(text);
                        let r = match f.and_then(|f| detail(&f)) {
                            Some(d) => r.on_hover_text(d),
                            None => r,
                        };
                        cell(r);
                    }
                    ui.end_row();
                }
            }
        });
    layout
}

/// The full checkpoint table (every checkpoint and QEM, as the CSV export writes it),
/// scrollable both ways inside whatever space it gets.
pub fn history_table(ui: &mut egui::Ui, history: &History) {
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
                    for row in history.rows() {
                        let e = &row.evaluation;
                        let value = |v: Option<f64>| {
                            v.map_or_else(|| "–".into(), |v| format_value(v, TABLE_DIGITS))
                        };
                        ui.label(row.method);
                        ui.label(format_count(row.iteration as f64));
                        ui.label(e.vertices.to_string());
                        ui.label(e.faces.to_string());
                        ui.label(format_value(e.e_avg, TABLE_DIGITS));
                        ui.label(format_value(e.e_max, TABLE_DIGITS));
                        ui.label(format_value(e.e_sur.abs(), TABLE_DIGITS));
                        ui.label(value(e.hausdorff));
                        ui.label(value(e.hausdorff_mean));
                        ui.label(format!("{:.1}", e.median_min_angle_degrees));
                        ui.label(format!("{:.1}", 100.0 * e.below_20_degrees));
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
                hausdorff_mean: None,
                median_min_angle_degrees: 41.0,
                below_20_degrees: 0.25,
                attributes: None,
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
        assert_eq!(&rows[0][8], "");
        assert_eq!(&rows[0][9], "41.00");
    }

    #[test]
    fn csv_has_attribute_columns_only_with_attributes() {
        let mut history = History::default();
        history.push_reconstruction(row("GNG3D", 1000, 2e-3));
        let mut qem = row("QEM", 0, 5e-4);
        qem.evaluation.attributes = Some(crate::engine::AttributeFigures {
            uv_texels_mean: Some(3.25),
            uv_over_threshold: Some(0.0004),
            texture_size: 1024,
            uv_threshold: 0.05,
            ..Default::default()
        });
        history.qem = Some(qem);
        let text = history.csv_string().unwrap();
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        let headers = reader.headers().unwrap().clone();
        assert_eq!(headers.len(), 16);
        assert_eq!(&headers[12], "uv_texels_mean");
        let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
        // GNG3D's row has no figures: empty cells, not zeros.
        assert_eq!(&rows[0][12], "");
        assert_eq!(rows[1][12].parse::<f64>().unwrap(), 3.25);
        assert_eq!(rows[1][13].parse::<f64>().unwrap(), 0.0004);
        assert_eq!(&rows[1][14], "");
        // Without attributes the columns are the twelve of before.
        history.qem = Some(row("QEM", 0, 5e-4));
        let text = history.csv_string().unwrap();
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        assert_eq!(reader.headers().unwrap().len(), 12);
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

    /// The labelled ticks of a log axis from `lo` to `hi` (values, not logs) drawn `points`
    /// high, as egui_plot asks for them, with their labels.
    fn log_labels(lo: f64, hi: f64, points: f64) -> Vec<String> {
        let (lo, hi) = (lo.log10(), hi.log10());
        let range = lo..=hi;
        log_marks(GridInput {
            bounds: (lo, hi),
            base_step_size: (hi - lo) / points * f64::from(GRID_MIN_SPACING),
        })
        .into_iter()
        .map(|m| format_log_tick(m, &range))
        .filter(|l| !l.is_empty())
        .collect()
    }

    #[test]
    fn numbers_read_plainly_or_in_engineering_notation() {
        for (v, digits, want) in [
            (7.3, 2, "7.3"),
            (7.0, 2, "7"),
            (0.0073, 2, "0.0073"),
            (730.0, 2, "730"),
            (7.3e-5, 2, "73e-6"),
            (1e-4, 1, "100e-6"),
            (1.5e6, 2, "1.5e6"),
            (12345.0, 3, "12.3e3"),
            (-0.5, 3, "-0.5"),
            (9.996, 3, "10"),
            (999_999.0, 2, "1e6"),
            (0.0, 3, "0"),
        ] {
            assert_eq!(format_value(v, digits), want, "{v} with {digits} digits");
        }
        assert_eq!(format_count(20_000.0), "20k");
        assert_eq!(format_count(1_500_000.0), "1.5M");
    }

    #[test]
    fn a_log_axis_always_has_two_readable_labels() {
        // Many decades on a tall plot: every decade.
        assert_eq!(
            log_labels(3e-7, 2e-2, 300.0),
            ["1e-6", "10e-6", "100e-6", "0.001", "0.01"]
        );
        // The same decades on a short plot (issue 37: no y numbers on a dirty scan at
        // 1280×720): every second decade or more, never none.
        let short = log_labels(3e-7, 2e-2, 60.0);
        assert!(short.len() >= 2 && short.len() <= 3, "{short:?}");
        // Inside one decade (a Hausdorff between 0.015 and 0.04): 2e-2 alone is not enough;
        // on a tall plot the 1-2-5 values, else the two ends.
        assert_eq!(log_labels(0.015, 0.04, 100.0).len(), 2);
        assert_eq!(log_labels(0.08, 0.3, 200.0), ["0.1", "0.2"]);
        // A range no round value fits (7.1 … 7.5): the two ends, two digits, never "7.3e0".
        let ends = log_labels(7.1, 7.5, 120.0);
        assert_eq!(ends.len(), 2, "{ends:?}");
        assert!(ends.iter().all(|l| !l.contains('e')), "{ends:?}");
        // Ticks are at least MIN_Y_LABEL_GAP apart on any plot height.
        for points in [40.0, 80.0, 160.0, 400.0] {
            for (lo, hi) in [(1e-9, 1.0), (0.01, 0.5), (3.0, 3.3), (1e-5, 2e-3)] {
                let (l, h) = (f64::log10(lo), f64::log10(hi));
                let marks: Vec<f64> = log_marks(GridInput {
                    bounds: (l, h),
                    base_step_size: (h - l) / points * f64::from(GRID_MIN_SPACING),
                })
                .into_iter()
                .filter(|m| is_labelled(m, &(l..=h)))
                .map(|m| m.value)
                .collect();
                assert!(marks.len() >= 2, "{lo}..{hi} at {points}: {marks:?}");
                let gap = marks
                    .windows(2)
                    .map(|w| (w[1] - w[0]) / (h - l) * points)
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    gap >= f64::from(MIN_Y_LABEL_GAP) - 1e-6 || marks.len() == 2,
                    "{lo}..{hi} at {points}: {gap} points apart"
                );
            }
        }
        // A single point gets MIN_LOG_SPAN decades around it.
        let (lo, hi) = log_y_range([0.73f64.log10()]).unwrap();
        assert!((hi - lo - MIN_LOG_SPAN).abs() < 1e-12);
    }

    #[test]
    fn the_signal_axis_shows_where_it_starts_and_ends() {
        let labels = |budget: f64, points: f64| -> Vec<String> {
            let (lo, hi) = (-0.05 * budget, 1.05 * budget);
            count_marks(
                GridInput {
                    bounds: (lo, hi),
                    base_step_size: (hi - lo) / points * f64::from(GRID_MIN_SPACING),
                },
                budget,
            )
            .into_iter()
            .map(|m| format_count(m.value))
            .collect()
        };
        assert_eq!(labels(150_000.0, 400.0), ["0", "50k", "100k", "150k"]);
        // The budget is labelled even when it is not a round value.
        assert_eq!(
            labels(190_000.0, 400.0),
            ["0", "50k", "100k", "150k", "190k"]
        );
        // A narrow plot: still both ends.
        let narrow = labels(87_900.0, 150.0);
        assert_eq!(narrow.first().unwrap(), "0");
        assert_eq!(narrow.last().unwrap(), "87.9k");
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

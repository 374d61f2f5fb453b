//! Live plots in the style of the GNG3D paper's Figure 1 (E_avg and E_max against iterations on a
//! log scale, QEM's values as horizontal lines), E_sur/Hausdorff after each reconstruction, and a
//! checkpoint table like the paper's Table 1 with CSV export.

use egui::Color32;
use egui_plot::{GridInput, GridMark, HLine, Legend, Line, LineStyle, Plot, PlotPoints, Points};
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
    /// Vertices of the mesh.
    pub vertices: usize,
    /// Faces of the mesh.
    pub faces: usize,
    /// E_avg, squared model units.
    pub e_avg: f64,
    /// E_max, squared model units.
    pub e_max: f64,
    /// E_sur = |ΔArea|, squared model units.
    pub e_sur: f64,
    /// Symmetric Hausdorff distance, model units.
    pub hausdorff: Option<f64>,
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
    pub fn write_csv(&self, path: &Path) -> Result<(), String> {
        let text = self.csv_string()?;
        std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
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
                "seconds",
            ])
            .map_err(err)?;
        for row in self.rows() {
            writer
                .write_record([
                    row.method.to_string(),
                    row.iteration.to_string(),
                    row.vertices.to_string(),
                    row.faces.to_string(),
                    format!("{:e}", row.e_avg),
                    format!("{:e}", row.e_max),
                    format!("{:e}", row.e_sur),
                    row.hausdorff.map(|h| format!("{h:e}")).unwrap_or_default(),
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
    marks
}

fn format_log_tick(mark: GridMark) -> String {
    format!("{:.0e}", 10f64.powf(mark.value))
}

fn log_plot(id: &str, height: f32) -> Plot<'static> {
    Plot::new(id)
        .height(height)
        // The panel colour shows through: no second fill of the plot area.
        .show_background(false)
        // Grid lines at least 24 px apart (egui_plot's default, 8 px, draws ~3× as many faint
        // lines, each of which a CPU rasterizer pays for).
        .grid_spacing(egui::Rangef::new(24.0, 300.0))
        .legend(
            Legend::default()
                .position(egui_plot::Corner::RightTop)
                .text_style(egui::TextStyle::Small)
                .background_alpha(0.6),
        )
        .y_grid_spacer(decade_marks)
        .y_axis_formatter(|mark, _| format_log_tick(mark))
        .x_axis_label("iteration (signals)")
        .label_formatter(|pos| {
            let (name, p) = match pos {
                egui_plot::HoverPosition::NearDataPoint {
                    plot_name,
                    position,
                    ..
                } => (*plot_name, *position),
                egui_plot::HoverPosition::Elsewhere { position } => ("", *position),
            };
            Some(format!(
                "{name}\niteration {:.0}\n{:.3e}",
                p.x,
                10f64.powf(p.y)
            ))
        })
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

/// E_avg and E_max of the live network against iterations (log y), QEM as horizontal lines.
pub fn vertex_error_plot(ui: &mut egui::Ui, history: &History, height: f32) {
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
    let qem = history.qem.clone();
    log_plot("vertex_errors", height)
        .y_axis_label("squared error")
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

/// E_sur and Hausdorff after each reconstruction (log y), QEM as horizontal lines.
pub fn surface_error_plot(ui: &mut egui::Ui, history: &History, height: f32) {
    let sur: Vec<[f64; 2]> = history
        .reconstructions
        .iter()
        .map(|c| [c.iteration as f64, log10(c.e_sur)])
        .collect();
    let hd: Vec<[f64; 2]> = history
        .reconstructions
        .iter()
        .filter_map(|c| c.hausdorff.map(|h| [c.iteration as f64, log10(h)]))
        .collect();
    let qem = history.qem.clone();
    log_plot("surface_errors", height)
        .y_axis_label("E_sur / Hausdorff")
        .show(ui, move |plot| {
            plot.line(Line::new("GNG3D E_sur", PlotPoints::from(sur.clone())).color(SUR_COLOR));
            plot.points(
                Points::new("GNG3D E_sur", PlotPoints::from(sur))
                    .color(SUR_COLOR)
                    .radius(3.0),
            );
            plot.line(
                Line::new("GNG3D Hausdorff", PlotPoints::from(hd.clone())).color(HAUSDORFF_COLOR),
            );
            plot.points(
                Points::new("GNG3D Hausdorff", PlotPoints::from(hd))
                    .color(HAUSDORFF_COLOR)
                    .radius(3.0),
            );
            if let Some(q) = qem {
                plot.hline(
                    HLine::new("QEM E_sur", log10(q.e_sur))
                        .color(SUR_COLOR)
                        .style(LineStyle::dashed_loose()),
                );
                if let Some(h) = q.hausdorff {
                    plot.hline(
                        HLine::new("QEM Hausdorff", log10(h))
                            .color(HAUSDORFF_COLOR)
                            .style(LineStyle::dashed_loose()),
                    );
                }
            }
        });
}

/// The checkpoint table (paper's Table 1 columns plus Hausdorff and time).
pub fn checkpoint_table(ui: &mut egui::Ui, history: &History) {
    // Solid scroll bars take their own space: floating ones would hide the last row.
    ui.spacing_mut().scroll = egui::style::ScrollStyle::solid();
    egui::ScrollArea::both()
        .id_salt("checkpoints")
        .auto_shrink([false, true])
        .show(ui, |ui| {
            egui::Grid::new("checkpoint_grid")
                .striped(true)
                .num_columns(9)
                .spacing([8.0, 2.0])
                .show(ui, |ui| {
                    for h in [
                        "method",
                        "iter.",
                        "V",
                        "F",
                        "E_avg",
                        "E_max",
                        "E_sur",
                        "Hausdorff",
                        "time (s)",
                    ] {
                        ui.strong(h);
                    }
                    ui.end_row();
                    for row in history.rows() {
                        ui.label(row.method);
                        ui.label(row.iteration.to_string());
                        ui.label(row.vertices.to_string());
                        ui.label(row.faces.to_string());
                        ui.label(format!("{:.3e}", row.e_avg));
                        ui.label(format!("{:.3e}", row.e_max));
                        ui.label(format!("{:.3e}", row.e_sur));
                        ui.label(
                            row.hausdorff
                                .map(|h| format!("{h:.3e}"))
                                .unwrap_or_else(|| "–".into()),
                        );
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
            vertices: 10,
            faces: 16,
            e_avg,
            e_max: e_avg * 4.0,
            e_sur: 0.5,
            hausdorff: None,
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
        assert_eq!(decades, vec![-7.0, -6.0, -5.0, -4.0, -3.0, -2.0]);
        assert_eq!(
            format_log_tick(GridMark {
                value: -3.0,
                step_size: 1.0
            }),
            "1e-3"
        );
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

//! The checkpoint tables: Table 1 (the latest GNG3D checkpoint next to QEM, one row per
//! measure) and the full history table, with their rows, columns and hover texts.

use super::{History, format_count, format_value};
use crate::engine::{AttributeFigures, Evaluation};
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

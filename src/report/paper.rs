//! Files written by `gng3d reproduce`: the paper's Table 1 (CSV, Markdown) and its plots.

use super::attributes::{AttributeColumn, attribute_columns_of};
use super::eng;
use super::plot::{Chart, Series};
use super::table::Table;
use crate::experiment::PaperRow;
use crate::experiment::reproduce::ReproduceReport;
use std::path::{Path, PathBuf};

/// The attribute-deviation columns of `report` ([`attribute_columns_of`] its meshes'
/// deviations): none for an original without attributes.
pub fn attribute_columns(report: &ReproduceReport) -> Vec<AttributeColumn> {
    attribute_columns_of(
        report
            .checkpoints
            .iter()
            .filter_map(|c| c.attributes.as_ref())
            .flat_map(|a| [&a.gng, &a.qem_equal])
            .chain(&report.qem_fixed_attributes),
    )
}

/// The 17 columns of [`checkpoint_table`] for a positions-only report: the paper's Table 1
/// (iteration, vertices, faces, E_avg, E_max, E_sur) and Hausdorff for GNG3D, then QEM at the
/// same vertex count and at the target.
pub const CHECKPOINT_COLUMNS: [&str; 17] = [
    "iteration",
    "vertices",
    "faces",
    "E_avg",
    "E_max",
    "E_sur",
    "Hausdorff",
    "QEM= vertices",
    "QEM= faces",
    "QEM= E_avg",
    "QEM= E_max",
    "QEM= E_sur",
    "QEM= Hausdorff",
    "QEM@target E_avg",
    "QEM@target E_max",
    "QEM@target E_sur",
    "QEM@target Hausdorff",
];

/// The paper's Table 1 columns (iteration, vertices, faces, E_avg, E_max, E_sur) for GNG3D,
/// followed by Hausdorff and the same measures for QEM at the same vertex count and at the
/// fixed target. For an original with attributes, the attribute-deviation columns
/// ([`attribute_columns`]) follow, for GNG3D, `QEM=` and `QEM@target` each; a positions-only
/// table has the 17 columns alone.
pub fn checkpoint_table(report: &ReproduceReport) -> Table {
    let columns = attribute_columns(report);
    let mut headers: Vec<String> = CHECKPOINT_COLUMNS.map(String::from).to_vec();
    for c in &columns {
        headers.push(c.name.clone());
        headers.push(format!("QEM= {}", c.name));
        headers.push(format!("QEM@target {}", c.name));
    }
    let mut t = Table::new(headers);
    let f = &report.qem_fixed;
    let fixed_attributes = report.qem_fixed_attributes.as_ref();
    for c in &report.checkpoints {
        let (g, q) = (&c.gng, &c.qem_equal);
        let mut row = vec![
            c.iteration.to_string(),
            g.vertices.to_string(),
            g.faces.to_string(),
        ];
        row.extend(distance_cells(g));
        row.extend([q.vertices.to_string(), q.faces.to_string()]);
        row.extend(distance_cells(q));
        row.extend(distance_cells(f));
        let a = c.attributes.as_ref();
        for column in &columns {
            row.push(column.cell(a.map(|a| &a.gng)));
            row.push(column.cell(a.map(|a| &a.qem_equal)));
            row.push(column.cell(fixed_attributes));
        }
        t.push(row);
    }
    t
}

/// E_avg, E_max, E_sur and Hausdorff of `r`, as the checkpoint table writes them.
fn distance_cells(r: &PaperRow) -> [String; 4] {
    [
        eng(r.e_avg),
        eng(r.e_max),
        eng(r.e_sur_signed),
        eng(r.hausdorff_max),
    ]
}

/// The attribute deviation at each checkpoint for the terminal (`None` for an original without
/// attributes): GNG3D and QEM at the same vertex count side by side per measure, under the
/// columns' short names, within [`TERMINAL_WIDTH`]; [`terminal_attribute_legend`] explains
/// them.
pub fn terminal_attribute_table(report: &ReproduceReport) -> Option<Table> {
    let columns = attribute_columns(report);
    if columns.is_empty() {
        return None;
    }
    let mut headers = vec!["iteration".to_string()];
    for c in &columns {
        headers.push(format!("{} GNG", c.short));
        headers.push(format!("{} QEM", c.short));
    }
    let mut t = Table::new(headers);
    for checkpoint in &report.checkpoints {
        let a = checkpoint.attributes.as_ref();
        let mut row = vec![checkpoint.iteration.to_string()];
        for c in &columns {
            row.push(c.cell(a.map(|a| &a.gng)));
            row.push(c.cell(a.map(|a| &a.qem_equal)));
        }
        t.push(row);
    }
    Some(t)
}

/// Lines printed under [`terminal_attribute_table`] (empty without attributes): what the short
/// names stand for and QEM's figures at the target, each line within [`TERMINAL_WIDTH`].
pub fn terminal_attribute_legend(report: &ReproduceReport) -> String {
    let columns = attribute_columns(report);
    if columns.is_empty() {
        return String::new();
    }
    let mut sentences: Vec<String> = vec![
        "Attribute deviation: samples on each mesh against the original at their closest points;"
            .into(),
    ];
    for c in &columns {
        sentences.push(format!("{} = {};", c.short, c.name));
    }
    sentences.push(
        "\"dropped\": the mesh lost the attribute. GNG3D takes the original's values at its \
         corners, QEM keeps them through its contractions."
            .into(),
    );
    let fixed = report.qem_fixed_attributes.as_ref();
    let at_target: Vec<String> = columns
        .iter()
        .map(|c| format!("{} {}", c.short, c.cell(fixed)))
        .collect();
    sentences.push(format!(
        "QEM at the target ({} vertices): {}.",
        report.qem_fixed.vertices,
        at_target.join(", ")
    ));
    wrap(&sentences.join(" "), TERMINAL_WIDTH)
}

/// `text` broken into lines of at most `width` characters at spaces (a longer word stands on
/// its own line), each ending in a newline.
fn wrap(text: &str, width: usize) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in text.split(' ').filter(|w| !w.is_empty()) {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            out.push_str(&line);
            out.push('\n');
            line.clear();
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// The checkpoint table for the terminal: at most [`TERMINAL_WIDTH`] characters wide, GNG3D
/// and QEM at the same vertex count side by side for E_avg, E_max and Hausdorff. The full
/// table (faces, E_sur, QEM at the target) is [`checkpoint_table`], written to table.md/csv;
/// [`terminal_legend`] explains the columns.
pub fn terminal_table(report: &ReproduceReport) -> Table {
    let mut t = Table::new([
        "iteration",
        "vertices",
        "E_avg GNG",
        "E_avg QEM",
        "E_max GNG",
        "E_max QEM",
        "Haus. GNG",
        "Haus. QEM",
    ]);
    for c in &report.checkpoints {
        let (g, q) = (&c.gng, &c.qem_equal);
        t.push([
            c.iteration.to_string(),
            g.vertices.to_string(),
            eng(g.e_avg),
            eng(q.e_avg),
            eng(g.e_max),
            eng(q.e_max),
            eng(g.hausdorff_max),
            eng(q.hausdorff_max),
        ]);
    }
    t
}

/// Width the terminal table is kept within, characters.
pub const TERMINAL_WIDTH: usize = 100;

/// Lines printed under [`terminal_table`]: what the columns are, their units, and QEM at the
/// fixed target for reference. Each line fits in [`TERMINAL_WIDTH`].
pub fn terminal_legend(report: &ReproduceReport) -> String {
    let f = &report.qem_fixed;
    format!(
        "iteration = signals so far; GNG = GNG3D at that checkpoint; QEM = QEM simplified to the\n\
         same vertex count. E_avg, E_max: squared model units; Haus. = symmetric Hausdorff, model\n\
         units (bbox diagonal {:.4}). Faces, E_sur and the full table: table.md / table.csv.\n\
         QEM at the target ({} vertices): E_avg {}, E_max {}, Hausdorff {}.\n",
        report.bbox_diagonal,
        f.vertices,
        eng(f.e_avg),
        eng(f.e_max),
        eng(f.hausdorff_max),
    )
}

fn series(label: &str, report: &ReproduceReport, y: impl Fn(usize) -> f64) -> Series {
    Series {
        label: label.into(),
        points: report
            .checkpoints
            .iter()
            .enumerate()
            .map(|(i, c)| (c.iteration as f64, y(i)))
            .collect(),
        reference: false,
    }
}

fn reference(label: &str, report: &ReproduceReport, value: f64) -> Series {
    let first = report
        .checkpoints
        .first()
        .map_or(0.0, |c| c.iteration as f64);
    let last = report
        .checkpoints
        .last()
        .map_or(1.0, |c| c.iteration as f64);
    Series {
        label: label.into(),
        points: vec![(first, value), (last, value)],
        reference: true,
    }
}

/// The report's charts: the paper's Figure 1 (E_sur vs iteration) and E_avg, E_max and
/// Hausdorff vs iteration on log scales, QEM as reference; returned with their file stems.
pub fn charts(report: &ReproduceReport, mesh_name: &str) -> Vec<(&'static str, Chart)> {
    let c = &report.checkpoints;
    let f = &report.qem_fixed;
    let metric = |name: &str,
                  title: &str,
                  log_y: bool,
                  get: &dyn Fn(&crate::experiment::PaperRow) -> f64| Chart {
        title: format!("{title} — {mesh_name}"),
        x_label: "iteration (signals)".into(),
        y_label: name.into(),
        log_y,
        series: vec![
            series("GNG3D", report, |i| get(&c[i].gng)),
            series("QEM, same vertex count", report, |i| get(&c[i].qem_equal)),
            reference(
                &format!("QEM at target ({} vertices)", f.vertices),
                report,
                get(f),
            ),
        ],
    };
    vec![
        // The paper plots E_sur linearly; here its magnitude goes on a log axis: QEM's
        // |E_sur| (~1e-3 of GNG3D's early values) would otherwise sit flat on zero, and the
        // sign (simplified area smaller or larger) is in table.md / table.csv.
        (
            "figure1_esur",
            metric(
                "|E_sur| = |original − simplified area| (squared units)",
                "Figure 1: |E_sur| vs iteration",
                true,
                &|r| r.e_sur_signed.abs(),
            ),
        ),
        (
            "e_avg",
            metric("E_avg (squared units)", "E_avg vs iteration", true, &|r| {
                r.e_avg
            }),
        ),
        (
            "e_max",
            metric("E_max (squared units)", "E_max vs iteration", true, &|r| {
                r.e_max
            }),
        ),
        (
            "hausdorff",
            metric(
                "symmetric Hausdorff (model units)",
                "Hausdorff vs iteration",
                true,
                &|r| r.hausdorff_max,
            ),
        ),
    ]
}

/// Write `table.csv`, `table.md`, `report.json` and the plots (SVG + PNG) into `dir`.
pub fn write_reproduction(
    report: &ReproduceReport,
    mesh_name: &str,
    dir: &Path,
) -> Result<Vec<PathBuf>, super::ReportError> {
    let table = checkpoint_table(report);
    let text = format!(
        "# GNG3D vs QEM on {mesh_name}\n\n{} vertices, {} faces; GNG3D target {} vertices, \
         {} signals per checkpoint. E_avg/E_max in squared model units, E_sur in squared model \
         units (original minus simplified area), Hausdorff in model units (bbox diagonal {:.4}).\n\
         `QEM=`: QEM at the GNG3D mesh's vertex count; `QEM@target`: QEM fixed at the target, \
         as in the paper.\n\n{}",
        report.original_vertices,
        report.original_faces,
        report.target_vertices,
        report.signals_per_epoch,
        report.bbox_diagonal,
        table.to_markdown()
    );
    let text = if attribute_columns(report).is_empty() {
        text
    } else {
        format!(
            "{text}\nAttribute columns (an original with texture coordinates, normals or \
             colours): each mesh's deviation, samples on it against the original at their \
             closest points; GNG3D's reconstruction takes the original's values at its corners \
             (the checkpoints are the protocol's meshes, without the seam cuts of a full \
             `gng3d simplify` run), QEM keeps them through its contractions as `gng3d simplify` \
             does. \"dropped\": the mesh lost the attribute.\n"
        )
    };
    super::write_report(
        dir,
        ("table.csv", &table),
        ("table.md", &text),
        ("report.json", report),
        charts(report, mesh_name),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::reproduce::{Checkpoint, CheckpointAttributes, Timings};

    /// Worst-case widths: negative E_sur, 7-digit iterations and vertex counts.
    fn row(vertices: usize, e: f64) -> PaperRow {
        PaperRow {
            vertices,
            faces: 2 * vertices,
            e_avg: e,
            e_max: -e * 1e3,
            e_sur_signed: -e,
            hausdorff_max: -1.234e-10,
            hausdorff_mean: e,
            hausdorff_rms: e,
            hausdorff_area_mean: e,
            median_min_angle_degrees: 45.0,
            below_20_degrees: 0.1,
        }
    }

    fn report() -> ReproduceReport {
        ReproduceReport {
            original_vertices: 2_000_000,
            original_faces: 4_000_000,
            original_area: 1.0,
            bbox_diagonal: 1.0,
            target_vertices: 1_000_000,
            signals_per_epoch: 2_000_000,
            checkpoints: (1..=30)
                .map(|i| Checkpoint {
                    iteration: i * 2_000_000,
                    nodes: 1_000_000,
                    gng: row(1_000_000, -1.5e-300),
                    qem_equal: row(1_000_000, 2.5e-7),
                    attributes: None,
                })
                .collect(),
            qem_fixed: row(1_000_000, -9.999e-100),
            qem_fixed_attributes: None,
            seconds: Timings::default(),
        }
    }

    /// Every line of a terminal table and its legend fits [`TERMINAL_WIDTH`].
    fn assert_fits(text: &str, legend: &str) {
        for line in text.lines().chain(legend.lines()) {
            let width = line.chars().count();
            assert!(
                width <= TERMINAL_WIDTH,
                "{width} > {TERMINAL_WIDTH}: {line}"
            );
        }
    }

    #[test]
    fn terminal_table_and_legend_fit_the_width() {
        let r = report();
        let text = terminal_table(&r).to_text();
        let legend = terminal_legend(&r);
        assert_eq!(text.lines().count(), 2 + r.checkpoints.len());
        assert_fits(&text, &legend);
        // Every column the legend names appears in the header.
        let header = text.lines().next().unwrap();
        for name in ["E_avg GNG", "E_avg QEM", "Haus. GNG", "Haus. QEM"] {
            assert!(header.contains(name), "{header}");
        }
        assert!(legend.contains("GNG = GNG3D") && legend.contains("QEM = QEM"));
        // The full table keeps every measure, the terminal one a subset.
        assert_eq!(checkpoint_table(&r).headers.len(), 17);
        // Positions only: no attribute columns anywhere.
        assert!(terminal_attribute_table(&r).is_none());
        assert!(terminal_attribute_legend(&r).is_empty());
    }

    /// Worst-case widths of every attribute measure: four-digit texel means, shares near
    /// 100 %, and a dropped attribute.
    fn deviation(colors_dropped: bool) -> metrics::AttributeDeviation {
        let stats = |v: f64| metrics::DistanceStats {
            max: v,
            mean: v,
            rms: v,
        };
        let uv = metrics::UvDeviation {
            uv: stats(0.9),
            texels: stats(1234.56),
            over_threshold: 0.9999,
        };
        let errors = metrics::AttributeErrors {
            samples: 100_000,
            uv0: Some(uv),
            uv1: None,
            normals: Some(metrics::AngleDeviation {
                mean_degrees: 179.99,
                max_degrees: 180.0,
            }),
            colors: (!colors_dropped).then_some(stats(1.5)),
        };
        let mut compared = vec!["normals".to_string(), "uv0".to_string()];
        let mut missing = Vec::new();
        if colors_dropped {
            missing.push("colors".to_string());
        } else {
            compared.push("colors".to_string());
        }
        metrics::AttributeDeviation {
            backward: errors,
            forward: errors,
            compared,
            missing,
            texture_size: 1024,
            uv_threshold: 0.05,
            seconds: 1.0,
        }
    }

    #[test]
    fn attribute_columns_follow_the_paper_columns() {
        let mut r = report();
        for c in &mut r.checkpoints {
            c.attributes = Some(CheckpointAttributes {
                gng: deviation(true),
                qem_equal: deviation(false),
            });
        }
        r.qem_fixed_attributes = Some(deviation(false));
        // Four measures (UV mean, UV share off, normals, colours) for three meshes each.
        let table = checkpoint_table(&r);
        assert_eq!(table.headers.len(), 17 + 4 * 3);
        assert_eq!(
            &table.headers[..17],
            &checkpoint_table(&report()).headers[..]
        );
        let col = |name: &str| {
            table
                .headers
                .iter()
                .position(|h| h == name)
                .unwrap_or_else(|| panic!("{name} not in {:?}", table.headers))
        };
        let row = &table.rows[0];
        assert_eq!(row[col("UV deviation mean (texels of 1024²)")], "1234.56");
        assert_eq!(row[col("QEM= UV samples off by > 0.05 UV")], "99.99 %");
        assert_eq!(
            row[col("QEM@target attribute normal deviation mean (degrees)")],
            "179.99°"
        );
        assert_eq!(
            row[col("colour deviation mean (linear RGB distance)")],
            "dropped"
        );
        assert_eq!(
            row[col("QEM= colour deviation mean (linear RGB distance)")],
            "1.50"
        );
        // The terminal's attribute table and its legend fit the width.
        let text = terminal_attribute_table(&r).unwrap().to_text();
        let legend = terminal_attribute_legend(&r);
        assert_eq!(text.lines().count(), 2 + r.checkpoints.len());
        assert_fits(&text, &legend);
        let header = text.lines().next().unwrap();
        let joined = legend.replace('\n', " ");
        for short in ["UV", "UV off", "normal", "RGB"] {
            assert!(
                header.contains(&format!("{short} GNG"))
                    && header.contains(&format!("{short} QEM")),
                "{header}"
            );
            assert!(joined.contains(&format!("{short} = ")), "{legend}");
        }
        assert!(
            joined.contains("QEM at the target (1000000 vertices): UV 1234.56, UV off 99.99 %"),
            "{legend}"
        );
    }
}

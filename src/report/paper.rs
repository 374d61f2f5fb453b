//! Files written by `gng3d reproduce`: the paper's Table 1 (CSV, Markdown) and its plots.

use super::eng;
use super::plot::{Chart, Series};
use super::table::Table;
use crate::experiment::reproduce::ReproduceReport;
use std::path::{Path, PathBuf};

/// The paper's Table 1 columns (iteration, vertices, faces, E_avg, E_max, E_sur) for GNG3D,
/// followed by Hausdorff and the same measures for QEM at the same vertex count and at the
/// fixed target.
pub fn checkpoint_table(report: &ReproduceReport) -> Table {
    let mut t = Table::new([
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
    ]);
    let f = &report.qem_fixed;
    for c in &report.checkpoints {
        let (g, q) = (&c.gng, &c.qem_equal);
        t.push([
            c.iteration.to_string(),
            g.vertices.to_string(),
            g.faces.to_string(),
            eng(g.e_avg),
            eng(g.e_max),
            eng(g.e_sur_signed),
            eng(g.hausdorff_max),
            q.vertices.to_string(),
            q.faces.to_string(),
            eng(q.e_avg),
            eng(q.e_max),
            eng(q.e_sur_signed),
            eng(q.hausdorff_max),
            eng(f.e_avg),
            eng(f.e_max),
            eng(f.e_sur_signed),
            eng(f.hausdorff_max),
        ]);
    }
    t
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
    std::fs::create_dir_all(dir).map_err(|source| super::ReportError::Folder {
        path: dir.to_path_buf(),
        source,
    })?;
    let table = checkpoint_table(report);
    let mut written = Vec::new();
    let csv = dir.join("table.csv");
    table.write_csv(&csv)?;
    written.push(csv);
    let md = dir.join("table.md");
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
    mesh::io::write_atomic(&md, text.as_bytes())?;
    written.push(md);
    let json = dir.join("report.json");
    mesh::io::write_atomic(&json, serde_json::to_string_pretty(report)?.as_bytes())?;
    written.push(json);
    for (stem, chart) in charts(report, mesh_name) {
        written.extend(chart.write(&dir.join(stem))?);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::PaperRow;
    use crate::experiment::reproduce::{Checkpoint, Timings};

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
                })
                .collect(),
            qem_fixed: row(1_000_000, -9.999e-100),
            seconds: Timings::default(),
        }
    }

    #[test]
    fn terminal_table_and_legend_fit_the_width() {
        let r = report();
        let text = terminal_table(&r).to_text();
        let legend = terminal_legend(&r);
        assert_eq!(text.lines().count(), 2 + r.checkpoints.len());
        for line in text.lines().chain(legend.lines()) {
            let width = line.chars().count();
            assert!(
                width <= TERMINAL_WIDTH,
                "{width} > {TERMINAL_WIDTH}: {line}"
            );
        }
        // Every column the legend names appears in the header.
        let header = text.lines().next().unwrap();
        for name in ["E_avg GNG", "E_avg QEM", "Haus. GNG", "Haus. QEM"] {
            assert!(header.contains(name), "{header}");
        }
        assert!(legend.contains("GNG = GNG3D") && legend.contains("QEM = QEM"));
        // The full table keeps every measure, the terminal one a subset.
        assert_eq!(checkpoint_table(&r).headers.len(), 17);
    }
}

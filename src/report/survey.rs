//! Files and terminal tables of `gng3d reproduce --all`: the three methods (the paper's GNG3D,
//! GNG3D-Q and QEM) on every mesh and ratio, with the verdict per metric against QEM at equal
//! vertex count.

use super::attributes::{AttributeColumn, attribute_columns_of};
use super::plot::{Chart, Series};
use super::table::Table;
use super::{ReportError, eng};
use crate::experiment::PaperRow;
use crate::experiment::survey::SurveyRow;
use metrics::AttributeDeviation;
use std::path::{Path, PathBuf};

/// A measure of the survey: its name, how to read it from a row, and which way is better.
#[derive(Debug, Clone, Copy)]
pub struct Metric {
    /// Name in the Markdown file and the CSV headers.
    pub name: &'static str,
    /// Short name for the terminal.
    pub short: &'static str,
    /// The value of a method's row.
    pub get: fn(&PaperRow) -> f64,
    /// Lower values are better (false: higher, the smallest angle).
    pub lower_is_better: bool,
}

/// The measures the survey gives a verdict on, in the order of the tables.
pub const METRICS: [Metric; 7] = [
    Metric {
        name: "E_avg (squared units)",
        short: "E_avg",
        get: |r| r.e_avg,
        lower_is_better: true,
    },
    Metric {
        name: "E_max (squared units)",
        short: "E_max",
        get: |r| r.e_max,
        lower_is_better: true,
    },
    Metric {
        name: "|E_sur| (squared units)",
        short: "|E_sur|",
        get: |r| r.e_sur_signed.abs(),
        lower_is_better: true,
    },
    Metric {
        name: "Hausdorff max (units)",
        short: "Hausdorff max",
        get: |r| r.hausdorff_max,
        lower_is_better: true,
    },
    Metric {
        name: "mean surface distance (area-weighted, units)",
        short: "mean distance",
        get: |r| r.hausdorff_area_mean,
        lower_is_better: true,
    },
    Metric {
        name: "median min angle (degrees, higher is better)",
        short: "median min angle",
        get: |r| r.median_min_angle_degrees,
        lower_is_better: false,
    },
    Metric {
        name: "share of triangles with min angle < 20°",
        short: "min angle < 20°",
        get: |r| r.below_20_degrees,
        lower_is_better: true,
    },
];

/// One of the two GNG3D variants the survey sets against QEM.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// The paper's GNG3D (node placement, no flips, the paper's budget).
    Paper,
    /// GNG3D-Q, `gng3d simplify --method gng`'s defaults.
    Q,
}

impl Variant {
    /// Both, in table order.
    pub const ALL: [Variant; 2] = [Variant::Paper, Variant::Q];

    /// The name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Paper => "GNG3D (paper)",
            Variant::Q => "GNG3D-Q",
        }
    }

    /// This variant's row and QEM's row at its output vertex count.
    pub fn rows(self, r: &SurveyRow) -> (&PaperRow, &PaperRow) {
        match self {
            Variant::Paper => (&r.gng, &r.qem),
            Variant::Q => (&r.gngq, &r.qem_at_gngq),
        }
    }
}

/// Which of `variant` and QEM is better on `metric` in one run: `variant.name()`, "QEM" or
/// "tie" (equal within 1e-9 relative).
pub fn better(metric: &Metric, variant: Variant, run: &SurveyRow) -> &'static str {
    let (g, q) = variant.rows(run);
    let (g, q) = ((metric.get)(g), (metric.get)(q));
    let (g, q) = if metric.lower_is_better {
        (g, q)
    } else {
        (-g, -q)
    };
    match super::compare::winner(q, g) {
        "GNG3D" => variant.name(),
        "QEM" => "QEM",
        _ => "tie",
    }
}

/// The verdict of one metric for one variant over all runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// Runs the variant is better in.
    pub wins: usize,
    /// Runs QEM is better in.
    pub losses: usize,
    /// Runs with equal values.
    pub ties: usize,
    /// Runs left out because the variant and QEM ended at different vertex counts (a method
    /// stopped short of its target): no verdict between unequal counts.
    pub unequal: usize,
    /// Median over the runs of the variant's value divided by QEM's (runs where QEM's is 0 left
    /// out; `None` when none is left).
    pub median_ratio: Option<f64>,
}

/// The verdict of `metric` for `variant` over `rows`.
pub fn verdict(metric: &Metric, variant: Variant, rows: &[SurveyRow]) -> Verdict {
    let mut v = Verdict {
        wins: 0,
        losses: 0,
        ties: 0,
        unequal: 0,
        median_ratio: None,
    };
    let mut ratios = Vec::new();
    for r in rows {
        let (g, q) = variant.rows(r);
        if g.vertices != q.vertices {
            v.unequal += 1;
            continue;
        }
        match better(metric, variant, r) {
            "QEM" => v.losses += 1,
            "tie" => v.ties += 1,
            _ => v.wins += 1,
        }
        let (g, q) = variant.rows(r);
        let (g, q) = ((metric.get)(g), (metric.get)(q));
        if q > 0.0 && g.is_finite() {
            ratios.push(g / q);
        }
    }
    ratios.sort_by(f64::total_cmp);
    let n = ratios.len();
    if n > 0 {
        v.median_ratio = Some(if n % 2 == 1 {
            ratios[n / 2]
        } else {
            0.5 * (ratios[n / 2 - 1] + ratios[n / 2])
        });
    }
    v
}

/// A ratio to QEM with three significant digits ("0.808", "73.1"), "-" when undefined.
fn ratio(r: Option<f64>) -> String {
    match r {
        Some(r) if r.is_finite() => {
            let digits = if r.abs() >= 100.0 {
                0
            } else if r.abs() >= 10.0 {
                1
            } else if r.abs() >= 1.0 {
                2
            } else {
                3
            };
            format!("{r:.digits$}")
        }
        _ => "-".into(),
    }
}

/// The verdict per metric for both variants against QEM at equal vertex count: wins of each
/// (out of all runs) and the median of its value over QEM's. Narrow enough for a terminal
/// (at most [`super::paper::TERMINAL_WIDTH`] characters); `short` picks the metric names.
pub fn verdict_table(rows: &[SurveyRow], short: bool) -> Table {
    let mut headers = vec!["metric".to_string()];
    for variant in Variant::ALL {
        headers.push(format!("{} wins", variant.name()));
        headers.push(format!("{} / QEM", variant.name()));
    }
    let mut t = Table::new(headers);
    let n = rows.len();
    for metric in &METRICS {
        let mut row = vec![if short { metric.short } else { metric.name }.to_string()];
        for variant in Variant::ALL {
            let v = verdict(metric, variant, rows);
            let ties = if v.ties > 0 {
                format!(", {} ties", v.ties)
            } else {
                String::new()
            };
            let equal = n - v.unequal;
            row.push(format!("{} of {equal}{ties}", v.wins));
            row.push(ratio(v.median_ratio));
        }
        t.push(row);
    }
    t
}

fn genus(g: Option<i64>) -> String {
    g.map_or("-".to_string(), |g| g.to_string())
}

fn yes_no(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

/// The attribute-deviation columns of `rows` ([`attribute_columns_of`] of GNG3D-Q's outputs);
/// none when no input has attributes, so a positions-only survey's tables are as before.
pub fn attribute_columns(rows: &[SurveyRow]) -> Vec<AttributeColumn> {
    attribute_columns_of(
        rows.iter()
            .filter_map(|r| r.attributes.as_ref().map(|a| &a.gngq)),
    )
}

/// The attribute deviations of the three methods' outputs in one run, in table order
/// (GNG3D (paper), GNG3D-Q, QEM at GNG3D-Q's count); `None` each for a run without attributes.
fn deviations(r: &SurveyRow) -> [Option<&AttributeDeviation>; 3] {
    match &r.attributes {
        Some(a) => [Some(&a.gng), Some(&a.gngq), Some(&a.qem_at_gngq)],
        None => [None; 3],
    }
}

/// Every run with every measure of the three methods and the verdict of each GNG3D variant
/// against QEM per metric (`summary.csv`). QEM is run to each variant's output vertex count;
/// the `QEM` columns are QEM at GNG3D-Q's count, the paper's verdict is against QEM at its own
/// count (the same mesh when the counts agree, as they do on closed inputs).
pub fn summary_table(rows: &[SurveyRow]) -> Table {
    let mut headers: Vec<String> = [
        "mesh",
        "ratio",
        "original vertices",
        "vertices GNG3D (paper)",
        "vertices GNG3D-Q",
        "vertices QEM",
    ]
    .into_iter()
    .map(String::from)
    .collect();
    for m in &METRICS {
        headers.push(format!("{} GNG3D (paper)", m.name));
        headers.push(format!("{} GNG3D-Q", m.name));
        headers.push(format!("{} QEM", m.name));
        headers.push(format!("{} better: GNG3D (paper) or QEM", m.name));
        headers.push(format!("{} better: GNG3D-Q or QEM", m.name));
    }
    headers.extend(
        [
            "closed manifold GNG3D (paper)",
            "closed manifold GNG3D-Q",
            "genus original/GNG3D (paper)/GNG3D-Q/QEM",
            "seconds GNG3D (paper)",
            "seconds GNG3D-Q",
            "seconds QEM",
        ]
        .map(String::from),
    );
    let columns = attribute_columns(rows);
    for c in &columns {
        for method in ["GNG3D (paper)", "GNG3D-Q", "QEM"] {
            headers.push(format!("{} {method}", c.name));
        }
    }
    let mut t = Table::new(headers);
    for r in rows {
        let mut row = vec![
            r.mesh.clone(),
            format!("{:.2}", r.ratio),
            r.original_vertices.to_string(),
            r.gng.vertices.to_string(),
            r.gngq.vertices.to_string(),
            r.qem_at_gngq.vertices.to_string(),
        ];
        for m in &METRICS {
            for p in [&r.gng, &r.gngq, &r.qem_at_gngq] {
                row.push(value(m, p));
            }
            row.push(better(m, Variant::Paper, r).to_string());
            row.push(better(m, Variant::Q, r).to_string());
        }
        row.extend([
            yes_no(r.gng_closed_manifold).to_string(),
            yes_no(r.gngq_closed_manifold).to_string(),
            format!(
                "{}/{}/{}/{}",
                genus(r.original_genus),
                genus(r.gng_genus),
                genus(r.gngq_genus),
                genus(r.qem_genus)
            ),
            format!("{:.3}", r.gng_seconds),
            format!("{:.3}", r.gngq_seconds),
            format!("{:.3}", r.qem_seconds),
        ]);
        for c in &columns {
            row.extend(deviations(r).map(|d| c.cell(d)));
        }
        t.push(row);
    }
    t
}

/// A metric's value in a table: angles in degrees, shares in percent, the rest in
/// engineering notation.
fn value(metric: &Metric, row: &PaperRow) -> String {
    let v = (metric.get)(row);
    if metric.short == "median min angle" {
        format!("{v:.1}°")
    } else if metric.short == "min angle < 20°" {
        format!("{:.2} %", 100.0 * v)
    } else {
        eng(v)
    }
}

/// The per-run table of `summary.md`: the headline measures of the three methods side by side,
/// GNG3D-Q's ratios to QEM, and the seconds.
pub fn runs_table(rows: &[SurveyRow]) -> Table {
    let columns = attribute_columns(rows);
    let mut headers: Vec<String> = [
        "mesh",
        "ratio",
        "vertices GNG3D (paper) / GNG3D-Q / QEM",
        "mean distance GNG3D (paper) / GNG3D-Q / QEM",
        "Hausdorff max GNG3D (paper) / GNG3D-Q / QEM",
        "GNG3D-Q / QEM mean",
        "GNG3D-Q / QEM Hausdorff",
        "E_avg GNG3D (paper) / GNG3D-Q / QEM",
        "median min angle GNG3D (paper) / GNG3D-Q / QEM",
        "seconds GNG3D (paper) / GNG3D-Q / QEM",
    ]
    .map(String::from)
    .to_vec();
    for c in &columns {
        headers.push(format!("{} GNG3D (paper) / GNG3D-Q / QEM", c.name));
    }
    let mut t = Table::new(headers);
    let three = |m: &Metric, r: &SurveyRow| {
        format!(
            "{} / {} / {}",
            value(m, &r.gng),
            value(m, &r.gngq),
            value(m, &r.qem_at_gngq)
        )
    };
    let over = |m: &Metric, r: &SurveyRow| {
        let q = (m.get)(&r.qem_at_gngq);
        ratio((q > 0.0).then(|| (m.get)(&r.gngq) / q))
    };
    let [e_avg, _, _, hausdorff, mean, angle, _] = &METRICS;
    for r in rows {
        let mut row = vec![
            r.mesh.clone(),
            format!("{:.2}", r.ratio),
            format!(
                "{} / {} / {}",
                r.gng.vertices, r.gngq.vertices, r.qem_at_gngq.vertices
            ),
            three(mean, r),
            three(hausdorff, r),
            over(mean, r),
            over(hausdorff, r),
            three(e_avg, r),
            three(angle, r),
            format!(
                "{:.2} / {:.2} / {:.3}",
                r.gng_seconds, r.gngq_seconds, r.qem_seconds
            ),
        ];
        for c in &columns {
            row.push(deviations(r).map(|d| c.cell(d)).join(" / "));
        }
        t.push(row);
    }
    t
}

/// One line per variant: outputs closed and manifold, vertex counts on target, total seconds.
fn totals(rows: &[SurveyRow]) -> String {
    let target = |r: &SurveyRow| ((r.original_vertices as f64 * r.ratio).round() as usize).max(4);
    let qem_seconds: f64 = rows.iter().map(|r| r.qem_seconds).sum();
    let n = rows.len();
    let mut out = String::new();
    for variant in Variant::ALL {
        let (closed, exact, seconds) = match variant {
            Variant::Paper => (
                rows.iter().filter(|r| r.gng_closed_manifold).count(),
                rows.iter().filter(|r| r.gng.vertices == target(r)).count(),
                rows.iter().map(|r| r.gng_seconds).sum::<f64>(),
            ),
            Variant::Q => (
                rows.iter().filter(|r| r.gngq_closed_manifold).count(),
                rows.iter().filter(|r| r.gngq.vertices == target(r)).count(),
                rows.iter().map(|r| r.gngq_seconds).sum::<f64>(),
            ),
        };
        let unequal = rows
            .iter()
            .filter(|r| {
                let (g, q) = variant.rows(r);
                g.vertices != q.vertices
            })
            .count();
        let unequal = if unequal > 0 {
            format!(
                ", QEM stopped at another vertex count in {unequal} of {n} (left out of the \
                 verdict)"
            )
        } else {
            String::new()
        };
        out.push_str(&format!(
            "{}: output closed and manifold in {closed} of {n} runs, vertex count on target in \
             {exact} of {n}{unequal}, {seconds:.2} s in all (QEM {qem_seconds:.2} s).\n",
            variant.name()
        ));
    }
    out
}

/// `summary.md`: the verdict per metric for both GNG3D variants, the totals, every run, and
/// the meshes left out with the reason (`skipped`: file name, reason).
pub fn summary_markdown(rows: &[SurveyRow], skipped: &[(String, String)], epochs: u64) -> String {
    let mut text = format!(
        "# Survey: GNG3D (paper), GNG3D-Q and QEM\n\n\
         {} runs. GNG3D (paper): node placement, no flips, {epochs} epochs of |V| signals; \
         GNG3D-Q: `gng3d simplify --method gng` defaults; QEM at each variant's output vertex \
         count. \"wins\": runs in which the variant is better than QEM; \"/ QEM\": median over \
         the runs of its value divided by QEM's (below 1 is better, except for the angle). \
         Distances in model units, E_avg/E_max/|E_sur| in squared model units; the mean \
         distance is the area-weighted (1/A)∫d dA, both directions averaged.\n\n\
         ## Verdict against QEM at equal vertex count\n\n{}\n{}\n\
         ## All runs\n\n{}\nEvery measure of every run, with the verdict per run: summary.csv; \
         the raw figures: summary.json.\n",
        rows.len(),
        verdict_table(rows, false).to_markdown(),
        totals(rows),
        runs_table(rows).to_markdown()
    );
    if !attribute_columns(rows).is_empty() {
        text.push_str(
            "\nAttribute columns (inputs with texture coordinates, normals or colours): every \
             method keeps the input's attributes as `gng3d simplify` does (QEM through its \
             contractions, both GNG3D variants by transfer from the original surface), and each \
             output's deviation is measured as `gng3d compare` does, samples on the output \
             against the original at their closest points; \"-\": the input does not have the \
             attribute, \"dropped\": the output lost it. The verdict does not include them.\n",
        );
    }
    if !skipped.is_empty() {
        text.push_str("\n## Skipped\n\n");
        for (name, reason) in skipped {
            text.push_str(&format!("- {name}: {reason}\n"));
        }
    }
    text
}

/// What `reproduce --all` prints: the verdict table, the totals, and where the files are.
pub fn terminal_summary(rows: &[SurveyRow]) -> String {
    format!(
        "{} runs; against QEM at equal vertex count (wins, median ratio to QEM):\n{}{}",
        rows.len(),
        verdict_table(rows, true).to_text(),
        totals(rows)
    )
}

/// The survey's charts with their file stems: for each headline measure, every run's ratio to
/// QEM for both variants, sorted (the runs left of where a curve crosses 1 are its wins).
pub fn survey_charts(rows: &[SurveyRow]) -> Vec<(&'static str, Chart)> {
    let [e_avg, _, _, hausdorff, mean, angle, _] = &METRICS;
    [
        ("survey_mean_distance", mean),
        ("survey_hausdorff", hausdorff),
        ("survey_e_avg", e_avg),
        ("survey_min_angle", angle),
    ]
    .into_iter()
    .map(|(stem, m)| {
        let mut series: Vec<Series> = Variant::ALL
            .iter()
            .map(|&variant| {
                let mut ratios: Vec<f64> = rows
                    .iter()
                    .filter_map(|r| {
                        let (g, q) = variant.rows(r);
                        let q = (m.get)(q);
                        (q > 0.0).then(|| (m.get)(g) / q)
                    })
                    .collect();
                ratios.sort_by(f64::total_cmp);
                Series {
                    label: variant.name().into(),
                    points: ratios
                        .into_iter()
                        .enumerate()
                        .map(|(i, v)| (i as f64 + 1.0, v))
                        .collect(),
                    reference: false,
                }
            })
            .collect();
        series.push(Series {
            label: "QEM (= 1)".into(),
            points: vec![(1.0, 1.0), (rows.len().max(2) as f64, 1.0)],
            reference: true,
        });
        let better = if m.lower_is_better { "below" } else { "above" };
        (
            stem,
            Chart {
                title: format!("{}: ratio to QEM per run, sorted", m.short),
                x_label: "runs, sorted by ratio".into(),
                y_label: format!("{} / QEM's ({better} 1: better than QEM)", m.short),
                log_y: true,
                series,
            },
        )
    })
    .collect()
}

/// Write `summary.csv`, `summary.md`, `summary.json` and the charts (SVG + PNG) into `dir`;
/// `skipped` (file name, reason) are listed in `summary.md`. Returns the paths written.
pub fn write_survey(
    rows: &[SurveyRow],
    skipped: &[(String, String)],
    epochs: u64,
    dir: &Path,
) -> Result<Vec<PathBuf>, ReportError> {
    let charts = if rows.is_empty() {
        Vec::new()
    } else {
        survey_charts(rows)
    };
    super::write_report(
        dir,
        ("summary.csv", &summary_table(rows)),
        ("summary.md", &summary_markdown(rows, skipped, epochs)),
        ("summary.json", rows),
        charts,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(e: f64, angle: f64) -> PaperRow {
        PaperRow {
            vertices: 100,
            faces: 196,
            e_avg: e,
            e_max: 10.0 * e,
            e_sur_signed: -e,
            hausdorff_max: 2.0 * e,
            hausdorff_mean: e,
            hausdorff_rms: e,
            hausdorff_area_mean: e,
            median_min_angle_degrees: angle,
            below_20_degrees: 0.1,
        }
    }

    /// Paper GNG3D worse than QEM on distances, GNG3D-Q better; both better on the angle.
    fn run(mesh: &str, q: f64) -> SurveyRow {
        SurveyRow {
            mesh: mesh.into(),
            ratio: 0.1,
            original_vertices: 1000,
            original_genus: Some(0),
            gng: row(3.0, 40.0),
            qem: row(1.0, 30.0),
            gng_closed_manifold: true,
            gng_genus: Some(0),
            qem_genus: Some(0),
            gng_seconds: 1.0,
            qem_seconds: 0.1,
            gngq: row(q, 40.0),
            qem_at_gngq: row(1.0, 30.0),
            gngq_closed_manifold: true,
            gngq_genus: Some(0),
            gngq_seconds: 2.0,
            attributes: None,
        }
    }

    #[test]
    fn verdicts_count_each_variant_against_its_qem() {
        let rows = vec![run("a", 0.5), run("b", 0.8), run("c", 2.0)];
        let [e_avg, .., angle, below] = &METRICS;
        let p = verdict(e_avg, Variant::Paper, &rows);
        assert_eq!((p.wins, p.losses, p.ties), (0, 3, 0));
        assert_eq!(p.median_ratio, Some(3.0));
        let q = verdict(e_avg, Variant::Q, &rows);
        assert_eq!((q.wins, q.losses, q.ties), (2, 1, 0));
        assert_eq!(q.median_ratio, Some(0.8));
        // Higher is better for the angle.
        assert_eq!(verdict(angle, Variant::Q, &rows).wins, 3);
        assert_eq!(verdict(below, Variant::Q, &rows).ties, 3);
        let t = verdict_table(&rows, true).to_text();
        assert!(t.contains("GNG3D-Q wins") && t.contains("2 of 3"), "{t}");
        for line in t.lines() {
            assert!(
                line.chars().count() <= super::super::paper::TERMINAL_WIDTH,
                "{line}"
            );
        }
    }

    #[test]
    fn summary_csv_and_markdown_have_all_three_methods() {
        let rows = vec![run("a", 0.5)];
        let t = summary_table(&rows);
        assert_eq!(t.headers.len(), 6 + 5 * METRICS.len() + 6);
        let col = |name: &str| t.headers.iter().position(|h| h == name).unwrap();
        let r = &t.rows[0];
        assert_eq!(r[col("E_avg (squared units) GNG3D-Q")], "500.0e-3");
        assert_eq!(
            r[col("E_avg (squared units) better: GNG3D-Q or QEM")],
            "GNG3D-Q"
        );
        assert_eq!(
            r[col("E_avg (squared units) better: GNG3D (paper) or QEM")],
            "QEM"
        );
        let skipped = vec![("big.ply".to_string(), "skipped: 9 faces".to_string())];
        let md = summary_markdown(&rows, &skipped, 30);
        assert!(md.contains("- big.ply: skipped: 9 faces"), "{md}");
        assert!(md.contains(" GNG3D-Q wins |"), "{md}");
        assert!(md.contains("3.000 / 500.0e-3 / 1.000 |"), "{md}");
        assert!(md.contains("| \\|E_sur\\| (squared units) "), "{md}");
    }
}

//! What the plots show: the live error series and the evaluated checkpoints of a session
//! ([`History`]), its CSV export, and the thinning of a series to what a plot can draw.

use crate::engine::Evaluation;
use crate::error::{Result, ViewerError};
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

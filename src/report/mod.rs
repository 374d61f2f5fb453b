//! Experiment reports: plots and tables written by `compare` and `reproduce`.

pub mod attributes;
pub mod compare;
pub mod paper;
pub mod plot;
pub mod survey;
pub mod table;

/// A number in engineering notation with four significant digits: the exponent a multiple of
/// three and left out when zero (`59.94e-3`, `1.380`, `14.53`, `2.500e6`); `0` for zero.
/// Parsed back by any float parser; what the terminal tables and the reports print.
pub fn eng(v: f64) -> String {
    eng_digits(v, 4)
}

/// [`eng`] with `digits` significant digits (at least 1).
pub fn eng_digits(v: f64, digits: usize) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let digits = digits.max(1) as i32;
    let mut exp = (v.abs().log10().floor() as i32).div_euclid(3) * 3;
    let mut mantissa = v / 10f64.powi(exp);
    // Decimals so the mantissa has `digits` significant digits; rounding can reach 1000.
    let decimals = |m: f64| (digits - 1 - m.abs().log10().floor() as i32).max(0) as usize;
    let mut text = format!("{mantissa:.*}", decimals(mantissa));
    if text.trim_start_matches('-').parse::<f64>().unwrap_or(0.0) >= 1000.0 {
        exp += 3;
        mantissa = text.parse::<f64>().unwrap_or(mantissa) / 1000.0;
        text = format!("{mantissa:.*}", decimals(mantissa));
    }
    if exp == 0 {
        text
    } else {
        format!("{text}e{exp}")
    }
}

#[cfg(test)]
mod eng_tests {
    use super::eng;

    #[test]
    fn engineering_notation() {
        assert_eq!(eng(0.05994), "59.94e-3");
        assert_eq!(eng(1.380), "1.380");
        assert_eq!(eng(14.53), "14.53");
        assert_eq!(eng(999.96), "1.000e3");
        assert_eq!(eng(-2.5e6), "-2.500e6");
        assert_eq!(eng(1.234e-10), "123.4e-12");
        assert_eq!(eng(0.0), "0");
        assert_eq!(eng(1.0), "1.000");
        for v in [3.1e-7, 0.5, 42.0, 7.7e9] {
            let back: f64 = eng(v).parse().unwrap();
            assert!((back - v).abs() <= 1e-3 * v, "{v}");
        }
    }
}

/// The files of one report, written into `dir` (created if missing) under the names given:
/// the table as CSV, the Markdown text, the JSON, then each chart as SVG and PNG. Returns the
/// paths written, in that order.
pub(crate) fn write_report<T: serde::Serialize + ?Sized>(
    dir: &std::path::Path,
    (csv, table): (&str, &table::Table),
    (md, text): (&str, &str),
    (json, value): (&str, &T),
    charts: Vec<(&'static str, plot::Chart)>,
) -> Result<Vec<std::path::PathBuf>, ReportError> {
    std::fs::create_dir_all(dir).map_err(|source| ReportError::Folder {
        path: dir.to_path_buf(),
        source,
    })?;
    let (csv, md, json) = (dir.join(csv), dir.join(md), dir.join(json));
    table.write_csv(&csv)?;
    mesh::io::write_atomic(&md, text.as_bytes())?;
    mesh::io::write_atomic(&json, serde_json::to_string_pretty(value)?.as_bytes())?;
    let mut written = vec![csv, md, json];
    for (stem, chart) in charts {
        written.extend(chart.write(&dir.join(stem))?);
    }
    Ok(written)
}

/// Why a report file could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Writing a file (or creating its folder) failed.
    #[error(transparent)]
    Write(#[from] mesh::error::MeshError),
    /// A folder could not be created.
    #[error("cannot create folder {path}: {source}")]
    Folder {
        /// The folder.
        path: std::path::PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Encoding a table as CSV failed.
    #[error("CSV: {0}")]
    Csv(String),
    /// Drawing or encoding a chart failed.
    #[error("plot {path}: {message}")]
    Plot {
        /// The chart file.
        path: std::path::PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Serialising a report as JSON failed.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
}

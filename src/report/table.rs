//! A small text table rendered as aligned terminal text, Markdown or CSV.

use std::path::Path;

/// A table of pre-formatted cells; the first column is left-aligned, the rest right-aligned.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    /// Column headers.
    pub headers: Vec<String>,
    /// Rows, each with one cell per header.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// An empty table with these headers.
    pub fn new<S: Into<String>>(headers: impl IntoIterator<Item = S>) -> Table {
        Table {
            headers: headers.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// Append a row (must have one cell per header).
    pub fn push<S: Into<String>>(&mut self, row: impl IntoIterator<Item = S>) {
        let row: Vec<String> = row.into_iter().map(Into::into).collect();
        debug_assert_eq!(row.len(), self.headers.len(), "row width");
        self.rows.push(row);
    }

    fn widths(&self) -> Vec<usize> {
        let mut w: Vec<usize> = self.headers.iter().map(|h| h.chars().count()).collect();
        for row in &self.rows {
            for (i, c) in row.iter().enumerate() {
                w[i] = w[i].max(c.chars().count());
            }
        }
        w
    }

    fn line(cells: &[String], widths: &[usize], sep: &str) -> String {
        cells
            .iter()
            .zip(widths)
            .enumerate()
            .map(|(i, (c, &w))| {
                if i == 0 {
                    format!("{c:<w$}")
                } else {
                    format!("{c:>w$}")
                }
            })
            .collect::<Vec<_>>()
            .join(sep)
    }

    /// Aligned plain text for the terminal.
    pub fn to_text(&self) -> String {
        let w = self.widths();
        let mut out = Table::line(&self.headers, &w, "  ");
        out.push('\n');
        out.push_str(
            &w.iter()
                .map(|&n| "-".repeat(n))
                .collect::<Vec<_>>()
                .join("  "),
        );
        out.push('\n');
        for row in &self.rows {
            out.push_str(&Table::line(row, &w, "  "));
            out.push('\n');
        }
        out
    }

    /// GitHub-flavoured Markdown; a `|` in a cell is escaped (`\|`) so it does not split it.
    pub fn to_markdown(&self) -> String {
        let escaped = Table {
            headers: self.headers.iter().map(|c| c.replace('|', "\\|")).collect(),
            rows: self
                .rows
                .iter()
                .map(|r| r.iter().map(|c| c.replace('|', "\\|")).collect())
                .collect(),
        };
        escaped.markdown()
    }

    fn markdown(&self) -> String {
        let w = self.widths();
        let mut out = format!("| {} |\n", Table::line(&self.headers, &w, " | "));
        let rule: Vec<String> = w
            .iter()
            .enumerate()
            .map(|(i, &n)| {
                if i == 0 {
                    "-".repeat(n.max(3))
                } else {
                    format!("{}:", "-".repeat(n.max(3) - 1))
                }
            })
            .collect();
        out.push_str(&format!("| {} |\n", rule.join(" | ")));
        for row in &self.rows {
            out.push_str(&format!("| {} |\n", Table::line(row, &w, " | ")));
        }
        out
    }

    /// CSV text (RFC 4180 quoting).
    pub fn to_csv(&self) -> Result<Vec<u8>, super::ReportError> {
        let csv_err = |e: csv::Error| super::ReportError::Csv(e.to_string());
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(&self.headers).map_err(csv_err)?;
        for row in &self.rows {
            w.write_record(row).map_err(csv_err)?;
        }
        w.into_inner()
            .map_err(|e| super::ReportError::Csv(e.to_string()))
    }

    /// Write as CSV (RFC 4180 quoting) to `path`, atomically (temporary file + rename).
    pub fn write_csv(&self, path: &Path) -> Result<(), super::ReportError> {
        mesh::io::write_atomic(path, &self.to_csv()?)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Table {
        let mut t = Table::new(["metric", "QEM", "GNG3D"]);
        t.push(["E_avg", "1.0e-6", "2.5e-7"]);
        t.push(["faces, total", "100", "98"]);
        t
    }

    #[test]
    fn text_columns_align() {
        let text = sample().to_text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        let widths: Vec<usize> = lines.iter().map(|l| l.chars().count()).collect();
        assert!(widths.iter().all(|&w| w == widths[0]), "{text}");
    }

    #[test]
    fn markdown_has_header_rule_and_rows() {
        let md = sample().to_markdown();
        let lines: Vec<&str> = md.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[1].starts_with("| ---") && lines[1].ends_with(": |"));
        assert!(lines.iter().all(|l| l.starts_with('|') && l.ends_with('|')));
        let mut t = Table::new(["metric", "value"]);
        t.push(["|E_sur|", "1"]);
        assert!(
            t.to_markdown().contains("| \\|E_sur\\| |"),
            "{}",
            t.to_markdown()
        );
    }

    #[test]
    fn csv_round_trips_including_commas() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        sample().write_csv(&path).unwrap();
        let mut r = csv::Reader::from_path(&path).unwrap();
        let rows: Vec<csv::StringRecord> = r.records().map(|r| r.unwrap()).collect();
        assert_eq!(rows.len(), 2);
        assert_eq!(&rows[1][0], "faces, total");
        assert_eq!(r.headers().unwrap().len(), 3);
    }
}

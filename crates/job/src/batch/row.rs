//! [`Row`]: one file's line of a batch — the JSON line `gng3d batch` prints, the dict
//! `gng3d.batch` returns and the record of the stats table — with its CSV form
//! ([`Row::cells`], [`csv_line`], [`parse_csv`]) and the run's one-line [`summary`].

use super::Item;
use serde::{Deserialize, Serialize};

/// The stats table's columns, in the order of [`Row`]'s fields.
pub const FIELDS: [&str; 13] = [
    "input",
    "output",
    "status",
    "error",
    "warnings",
    "method",
    "input_vertices",
    "input_faces",
    "vertices",
    "faces",
    "seconds",
    "hausdorff_max",
    "hausdorff_mean",
];

/// How a file's run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Simplified (and measured when asked).
    Ok,
    /// Its output was there already (resume).
    Skipped,
    /// Failed; the row's `error` says why.
    Error,
}

impl Status {
    /// `ok`, `skipped` or `error`.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Skipped => "skipped",
            Status::Error => "error",
        }
    }
}

/// One file's status row; serialised with [`FIELDS`] as its keys, in that order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The input file.
    pub input: String,
    /// Its output file.
    pub output: String,
    /// How the run ended.
    pub status: Status,
    /// Why it failed (or what could not be read back for a skipped file).
    pub error: Option<String>,
    /// The run's warnings, `; `-separated.
    pub warnings: String,
    /// The method's name (`qem`, `gng`, `paper`).
    pub method: String,
    /// Vertices of the input.
    pub input_vertices: Option<u64>,
    /// Faces of the input.
    pub input_faces: Option<u64>,
    /// Vertices of the output.
    pub vertices: Option<u64>,
    /// Faces of the output.
    pub faces: Option<u64>,
    /// Wall time of the file's run, seconds.
    pub seconds: Option<f64>,
    /// Symmetric Hausdorff distance, largest (when measured).
    pub hausdorff_max: Option<f64>,
    /// Symmetric Hausdorff distance, mean (when measured).
    pub hausdorff_mean: Option<f64>,
}

/// A measure of a run's output: its Hausdorff distance (max, mean), or why it failed.
pub type Measured = Result<(Option<f64>, Option<f64>), String>;

impl Row {
    /// Finish the row of a run that made its output: the Hausdorff figures (max, mean) when it
    /// was measured (a failed measure makes the row an error), the warnings and the seconds
    /// since `start`.
    pub fn finish(
        mut self,
        measured: Option<Measured>,
        warnings: &[String],
        start: std::time::Instant,
    ) -> Row {
        match measured {
            Some(Ok((max, mean))) => (self.hausdorff_max, self.hausdorff_mean) = (max, mean),
            Some(Err(e)) => {
                self.status = Status::Error;
                self.error = Some(format!("measuring the result: {e}"));
            }
            None => {}
        }
        self.warnings = warnings.join("; ");
        self.seconds = Some(start.elapsed().as_secs_f64());
        self
    }

    /// A row of `item` with `status` and nothing measured yet.
    pub fn new(item: &Item, method: &str, status: Status) -> Row {
        Row {
            input: item.input.display().to_string(),
            output: item.output.display().to_string(),
            status,
            error: None,
            warnings: String::new(),
            method: method.to_string(),
            input_vertices: None,
            input_faces: None,
            vertices: None,
            faces: None,
            seconds: None,
            hausdorff_max: None,
            hausdorff_mean: None,
        }
    }

    /// An error row of `item` saying `error`.
    pub fn failed(item: &Item, method: &str, error: impl Into<String>) -> Row {
        Row {
            error: Some(error.into()),
            ..Row::new(item, method, Status::Error)
        }
    }

    /// The row as CSV cells, in the order of [`FIELDS`] (`None` an empty cell).
    pub fn cells(&self) -> [String; 13] {
        let n = |v: Option<u64>| v.map_or(String::new(), |v| v.to_string());
        let x = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
        [
            self.input.clone(),
            self.output.clone(),
            self.status.name().to_string(),
            self.error.clone().unwrap_or_default(),
            self.warnings.clone(),
            self.method.clone(),
            n(self.input_vertices),
            n(self.input_faces),
            n(self.vertices),
            n(self.faces),
            x(self.seconds),
            x(self.hausdorff_max),
            x(self.hausdorff_mean),
        ]
    }

    /// A row read back from a stats table (`None` unless it has every column).
    pub fn from_cells(cells: &[String]) -> Option<Row> {
        if cells.len() != FIELDS.len() {
            return None;
        }
        let n = |s: &String| s.parse().ok();
        let x = |s: &String| s.parse().ok();
        Some(Row {
            input: cells[0].clone(),
            output: cells[1].clone(),
            status: match cells[2].as_str() {
                "ok" => Status::Ok,
                "skipped" => Status::Skipped,
                _ => Status::Error,
            },
            error: (!cells[3].is_empty()).then(|| cells[3].clone()),
            warnings: cells[4].clone(),
            method: cells[5].clone(),
            input_vertices: n(&cells[6]),
            input_faces: n(&cells[7]),
            vertices: n(&cells[8]),
            faces: n(&cells[9]),
            seconds: x(&cells[10]),
            hausdorff_max: x(&cells[11]),
            hausdorff_mean: x(&cells[12]),
        })
    }
}

/// The run's one line: how many files were ok, skipped and failed (and the wall time).
pub fn summary(statuses: &[Status], seconds: Option<f64>) -> String {
    let count = |s: Status| statuses.iter().filter(|&&t| t == s).count();
    let mut line = format!(
        "{} files: {} ok, {} skipped, {} errors",
        statuses.len(),
        count(Status::Ok),
        count(Status::Skipped),
        count(Status::Error)
    );
    if let Some(s) = seconds {
        line += &format!(" in {s:.2} s");
    }
    line
}

/// One CSV record (RFC 4180 quoting: fields with a comma, quote or line break are quoted),
/// ended by CRLF.
pub fn csv_line(cells: &[String]) -> String {
    let mut line = cells
        .iter()
        .map(|c| {
            if c.contains([',', '"', '\n', '\r']) {
                format!("\"{}\"", c.replace('"', "\"\""))
            } else {
                c.clone()
            }
        })
        .collect::<Vec<_>>()
        .join(",");
    line.push_str("\r\n");
    line
}

/// The records of a CSV text written by [`csv_line`] (or Python's csv module).
pub fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let mut records = Vec::new();
    let (mut record, mut field) = (Vec::new(), String::new());
    let (mut quoted, mut chars) = (false, text.chars().peekable());
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => record.push(std::mem::take(&mut field)),
            (false, '\r') => {}
            (false, '\n') => {
                record.push(std::mem::take(&mut field));
                records.push(std::mem::take(&mut record));
            }
            (false, c) => field.push(c),
        }
    }
    if !field.is_empty() || !record.is_empty() {
        record.push(field);
        records.push(record);
    }
    records
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trips_quotes_commas_and_line_breaks() {
        let cells = [
            "a.obj".to_string(),
            "x, \"y\"\nz".to_string(),
            String::new(),
            "3".to_string(),
        ];
        let text = csv_line(&cells) + &csv_line(&cells[..2]);
        let back = parse_csv(&text);
        assert_eq!(back, vec![cells.to_vec(), cells[..2].to_vec()]);
    }

    #[test]
    fn a_row_serialises_with_the_table_columns_in_order() {
        let item = Item {
            input: "a.obj".into(),
            output: "out/a.obj".into(),
        };
        let json = serde_json::to_string(&Row::new(&item, "qem", Status::Ok)).unwrap();
        let mut at = 0;
        for key in FIELDS {
            at += json[at..].find(&format!("\"{key}\":")).expect(key);
        }
        let row = Row::failed(&item, "gng", "x, \"y\"");
        assert_eq!(Row::from_cells(&row.cells()), Some(row));
    }
}

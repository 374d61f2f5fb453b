//! [`Table`]: the stats table, rows appended and flushed as files complete; the ok and skipped
//! rows of an earlier run give a skipped file its counts back.
//!
//! Another batch may write the same table (two processes given one output folder): the table
//! is read and its header written under an exclusive advisory lock (`flock(LOCK_EX)` on Unix),
//! and each row is appended under it, so the header is written once and rows are whole.

use super::PlanError;
use super::row::{FIELDS, Row, Status, csv_line, parse_csv};
use std::collections::HashMap;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// The stats table of a batch (or none: rows are then only completed, not written).
#[derive(Debug)]
pub struct Table {
    file: Option<Sink>,
    earlier: HashMap<String, Row>,
}

/// The table's file and its path.
#[derive(Debug)]
struct Sink {
    file: std::fs::File,
    path: PathBuf,
}

impl Sink {
    /// `f` with the file locked against other processes writing it.
    fn locked<T>(
        &mut self,
        f: impl FnOnce(&mut std::fs::File, &Path) -> Result<T, PlanError>,
    ) -> Result<T, PlanError> {
        self.file.lock().map_err(|e| {
            PlanError::Io(format!(
                "{}: cannot lock the stats table: {e}",
                self.path.display()
            ))
        })?;
        let result = f(&mut self.file, &self.path);
        self.file.unlock().ok();
        result
    }
}

impl Table {
    /// Open (or create, with its header) the table at `path`; `None`: no table.
    pub fn open(path: Option<&Path>) -> Result<Table, PlanError> {
        let Some(path) = path else {
            return Ok(Table {
                file: None,
                earlier: HashMap::new(),
            });
        };
        let io = |what: &str, e: std::io::Error| {
            PlanError::Io(format!("{}: {what} the stats table: {e}", path.display()))
        };
        let file = std::fs::OpenOptions::new()
            .read(true)
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| io("cannot open", e))?;
        let mut sink = Sink {
            file,
            path: path.to_path_buf(),
        };
        let earlier = sink.locked(|file, path| {
            let mut bytes = Vec::new();
            file.read_to_end(&mut bytes)
                .map_err(|e| io("cannot read", e))?;
            let existing = String::from_utf8_lossy(&bytes);
            let mut records = parse_csv(&existing).into_iter();
            if records.next().is_some_and(|h| h != FIELDS) {
                return Err(PlanError::Invalid(format!(
                    "{}: not a gng3d stats table (its header differs); move it or choose \
                     another --out",
                    path.display()
                )));
            }
            let earlier = records
                .filter_map(|cells| Row::from_cells(&cells))
                .filter(|r| r.status != Status::Error)
                .map(|r| (r.output.clone(), r))
                .collect();
            if existing.is_empty() {
                append(file, path, &csv_line(&FIELDS.map(String::from)))?;
            }
            Ok(earlier)
        })?;
        Ok(Table {
            file: Some(sink),
            earlier,
        })
    }

    /// Record `row` and return it as the batch reports it: a skipped file an earlier run
    /// recorded comes back with that run's row (status skipped) and is not written again; one
    /// without a row (written by a run killed before it recorded it) gets the counts read from
    /// its files and is written, so the table ends with one row per input.
    pub fn add(&mut self, row: Row) -> Result<Row, PlanError> {
        let row = match (row.status, self.earlier.get(&row.output)) {
            (Status::Skipped, Some(earlier)) => {
                return Ok(Row {
                    status: Status::Skipped,
                    ..earlier.clone()
                });
            }
            (Status::Skipped, None) => counted(row),
            _ => row,
        };
        if let Some(sink) = &mut self.file {
            let line = csv_line(&row.cells());
            sink.locked(|file, path| append(file, path, &line))?;
        }
        Ok(row)
    }
}

/// Append `line` to `file` and flush it.
fn append(file: &mut std::fs::File, path: &Path, line: &str) -> Result<(), PlanError> {
    file.write_all(line.as_bytes())
        .and_then(|()| file.flush())
        .map_err(|e| PlanError::Io(format!("{}: write failed: {e}", path.display())))
}

/// A skipped row with the counts a run gives, read from its input and output files (what
/// cannot be read is the row's error).
fn counted(mut row: Row) -> Row {
    // As a run counts them: the input welded and cleaned (`crate::load`), the output as written.
    let request = crate::Request::new(crate::Target::Ratio(1.0));
    let counts = |path: &str| {
        crate::load(Path::new(path), &request, &[]).map(|m| {
            (
                Some(m.model.mesh.vertex_count() as u64),
                Some(m.model.mesh.face_count() as u64),
            )
        })
    };
    let mut problems = Vec::new();
    match counts(&row.output) {
        Ok((v, f)) => (row.vertices, row.faces) = (v, f),
        Err(e) => problems.push(format!("reading the existing output: {e}")),
    }
    match counts(&row.input) {
        Ok((v, f)) => (row.input_vertices, row.input_faces) = (v, f),
        Err(e) => problems.push(format!("reading the input: {e}")),
    }
    row.error = (!problems.is_empty()).then(|| problems.join("; "));
    row
}

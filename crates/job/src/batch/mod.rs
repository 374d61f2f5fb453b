//! The batch engine of every front end (`gng3d batch`, Python's `gng3d.batch`): many mesh
//! files simplified into one folder, one status [`Row`] each.
//!
//! - [`Plan`]: the files ([`list_inputs`]: a folder, a manifest or one mesh), where each
//!   result goes ([`output_path`]), the checks over the whole list before anything is written
//!   (no two files to one output, a `.gltf`'s buffer `<stem>.bin` included and names that
//!   differ only in case counted as one; no result over an input), and this process's
//!   [`Shard`] of them, started largest first ([`Plan::largest_first`]).
//! - [`run_one`]: one file in this process ([`crate::simplify_file`], measured when asked),
//!   as its [`Row`]; a failure is the row's error, never a stop.
//! - [`Table`]: the stats table the rows are appended to as files complete (locked, so
//!   batches into one folder write its header once), whose earlier rows resume a killed run.
//!
//! Outputs are written atomically, so a resumed run ([`Settings::skip_existing`]) can trust
//! that an output that exists is complete.

mod check;
mod one;
mod row;
mod table;

pub use check::output_path;
pub use one::{Settings, describe, run_one};
pub use row::{FIELDS, Row, Status, csv_line, parse_csv, summary};
pub use table::Table;

use std::path::{Path, PathBuf};

/// Why a batch cannot start (or its table cannot be written).
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// The files, the output folder or the table do not make a batch.
    #[error("{0}")]
    Invalid(String),
    /// A folder, manifest or table could not be read or written.
    #[error("{0}")]
    Io(String),
    /// The output folder cannot take the stats table.
    #[error(transparent)]
    Mesh(#[from] mesh::error::MeshError),
}

/// One file of a batch and where its result goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Item {
    /// The input file.
    pub input: PathBuf,
    /// Its result.
    pub output: PathBuf,
}

/// Which files of the list this process runs: `rank`, `rank + world_size`, ...
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    rank: usize,
    world_size: usize,
}

impl Shard {
    /// Every file.
    pub const ALL: Shard = Shard {
        rank: 0,
        world_size: 1,
    };

    /// Shard `rank` of `world_size`; `None` unless `rank < world_size`.
    pub fn new(rank: usize, world_size: usize) -> Option<Shard> {
        (rank < world_size).then_some(Shard { rank, world_size })
    }

    /// The stats table's name: `stats.csv`, or `stats-R-of-W.csv` when sharded.
    pub fn stats_name(self) -> String {
        if self.world_size > 1 {
            format!("stats-{}-of-{}.csv", self.rank, self.world_size)
        } else {
            "stats.csv".to_string()
        }
    }
}

/// What a batch is given: a source to list ([`list_inputs`]) or the files themselves.
#[derive(Debug, Clone, Copy)]
pub enum Inputs<'a> {
    /// A folder, a manifest or one mesh.
    Source(&'a Path),
    /// The files, in this order.
    Files(&'a [PathBuf]),
}

/// The files of a batch, checked, and this process's share of them.
#[derive(Debug, Clone)]
pub struct Plan {
    items: Vec<Item>,
}

impl Plan {
    /// Plan `inputs` into `out_dir` (created), each result named by [`output_path`] (`format`:
    /// an extension for every output, e.g. `ply`), and keep `shard`'s files. Refused before
    /// anything but the folder is written: two files to one output file, a result over an
    /// input (or `out_dir` the source folder), an output folder that cannot take the stats
    /// table. The checks cover every file, not the shard's only (all shards write one folder).
    pub fn new(
        inputs: Inputs<'_>,
        out_dir: &Path,
        format: Option<&str>,
        shard: Shard,
    ) -> Result<Plan, PlanError> {
        if let Some(f) = format
            && !known_format(f)
        {
            return Err(PlanError::Invalid(format!(
                "--format must be obj, ply, stl, gltf or glb, got {f:?}"
            )));
        }
        let (source, all) = match inputs {
            Inputs::Source(source) => (Some(source), list_inputs(source)?),
            Inputs::Files(files) => (None, files.to_vec()),
        };
        let outputs: Vec<PathBuf> = all
            .iter()
            .map(|f| output_path(f, out_dir, format))
            .collect();
        check::check_collisions(&all, &outputs)?;
        std::fs::create_dir_all(out_dir).map_err(|e| {
            PlanError::Io(format!(
                "{}: cannot create the output folder: {e}",
                out_dir.display()
            ))
        })?;
        check::check_inputs_kept(source, out_dir, &all, &outputs)?;
        mesh::io::check_writable(&out_dir.join("stats.csv"))?;
        let items = all
            .into_iter()
            .zip(outputs)
            .skip(shard.rank)
            .step_by(shard.world_size)
            .map(|(input, output)| Item { input, output })
            .collect();
        Ok(Plan { items })
    }

    /// This shard's files, in the list's order.
    pub fn items(&self) -> &[Item] {
        &self.items
    }

    /// The order to start the items in: largest first (bytes on disk standing in for the
    /// work), so that a big file started last does not leave one job running alone at the end
    /// (longest-processing-time-first scheduling); files that cannot be read last.
    pub fn largest_first(&self) -> Vec<usize> {
        let inputs: Vec<&Path> = self.items.iter().map(|i| i.input.as_path()).collect();
        largest_first(&inputs)
    }
}

/// The order to start `files` in: largest first, ties and unreadable files in list order (the
/// unreadable last); see [`Plan::largest_first`].
pub fn largest_first(files: &[&Path]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..files.len()).collect();
    let size = |i: usize| std::fs::metadata(files[i]).ok().map(|m| m.len());
    order.sort_by_cached_key(|&i| (std::cmp::Reverse(size(i)), i));
    order
}

/// Whether `extension` (e.g. `ply`) names a format the writer knows.
pub fn known_format(extension: &str) -> bool {
    mesh::io::Format::from_path(Path::new(&format!("x.{extension}"))).is_some()
}

/// The mesh files of `source`: a folder's files in a format the loader knows
/// ([`mesh::io::Format::from_path`]) sorted by name, one mesh file, or the paths listed in a
/// manifest (one a line, relative to it; blank lines and `#` comments skipped).
pub fn list_inputs(source: &Path) -> Result<Vec<PathBuf>, PlanError> {
    let is_mesh = |p: &Path| mesh::io::Format::from_path(p).is_some();
    if source.is_dir() {
        let entries = std::fs::read_dir(source).map_err(|e| {
            PlanError::Io(format!("{}: cannot read the folder: {e}", source.display()))
        })?;
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && is_mesh(p))
            .collect();
        files.sort();
        return Ok(files);
    }
    if is_mesh(source) {
        return Ok(vec![source.to_path_buf()]);
    }
    let text = std::fs::read_to_string(source).map_err(|e| {
        PlanError::Io(format!(
            "{}: not a folder, a mesh or a readable manifest: {e}",
            source.display()
        ))
    })?;
    let base = source.parent().unwrap_or(Path::new("."));
    Ok(text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| base.join(l))
        .collect())
}

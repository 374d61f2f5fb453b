//! `gng3d batch`: simplify a folder or a manifest of mesh files, for schedulers without Dask
//! (Slurm arrays, `xargs`, one machine): static sharding by `--rank`/`--world-size`, `--jobs`
//! files at a time, one JSON line per file on stdout as it completes, the same rows as the
//! Python package's `gng3d.batch` (and its `stats.csv`), a summary line on stderr.
//!
//! Each file runs as its own `gng3d simplify` process (this executable), so a batch writes
//! byte for byte the meshes `gng3d simplify` writes with the same options, and a file that
//! exhausts memory or crashes is an error row while the others go on. Outputs are written
//! atomically, so `--skip-existing` resumes a killed run: an output that exists is complete.

use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::{Context, bail};

/// The stats table's columns (the Python package's `gng3d.batch.STATS_FIELDS`).
const FIELDS: [&str; 13] = [
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

#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  gng3d batch meshes/ --out out/ --ratio 0.1 --jobs 2
  gng3d batch list.txt --out out/ --vertices 2000 --method gng --rank 3 --world-size 8 --skip-existing
  gng3d batch meshes/ --out out/ --ratio 0.25 -- --no-relax --time-limit 2

Each file is simplified as `gng3d simplify FILE OUT/NAME` with the options given (the same bytes);
options after `--` are passed to every `gng3d simplify` unchanged. stdout gets one JSON line per
file (input, output, status ok/skipped/error, error, warnings, method, input and output counts,
seconds, and with --measure the symmetric Hausdorff max and mean); the same rows are appended to
OUT/stats.csv (stats-R-of-W.csv when sharded) as files complete. Exit status 1 when a file failed.")]
pub(crate) struct BatchArgs {
    /// A folder (its .obj, .ply, .stl, .gltf and .glb files, sorted by name) or a manifest: a text file with
    /// one mesh path per line (relative to the manifest; blank lines and # comments skipped).
    pub source: PathBuf,
    /// Output folder (created); each result keeps its input's file name.
    #[arg(long)]
    pub out: PathBuf,
    /// Method: qem (default) or gng, as for `gng3d simplify`.
    #[arg(long, default_value = "qem", value_parser = ["qem", "gng"])]
    pub method: String,
    /// Target vertex count of every output.
    #[arg(long, group = "target")]
    pub vertices: Option<u64>,
    /// Target face count of every output (QEM only).
    #[arg(long, group = "target")]
    pub faces: Option<u64>,
    /// Target as a fraction of each input, as `gng3d simplify --ratio`.
    #[arg(long, group = "target")]
    pub ratio: Option<f64>,
    /// Files simplified at a time (default: the number of cores); each run gets the cores
    /// divided among them (the meshes do not depend on the thread count).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// This process's shard: files rank, rank + world-size, rank + 2·world-size, ...
    #[arg(long, default_value_t = 0)]
    pub rank: usize,
    /// Number of shards (processes or machines sharing the list).
    #[arg(long, default_value_t = 1)]
    pub world_size: usize,
    /// Skip files whose output exists (a killed run resumes where it stopped).
    #[arg(long)]
    pub skip_existing: bool,
    /// Also measure each result (`gng3d metrics`: symmetric Hausdorff max and mean).
    #[arg(long)]
    pub measure: bool,
    /// Write outputs in this format instead of the input's (obj, ply, stl, gltf or glb).
    #[arg(long)]
    pub format: Option<String>,
    /// Further `gng3d simplify` options for every file (after `--`).
    #[arg(last = true)]
    pub simplify_options: Vec<String>,
}

/// One file's status row (the JSON line and the stats.csv row).
#[derive(Debug, Clone, Default, serde::Serialize)]
struct Row {
    input: String,
    output: String,
    status: &'static str,
    error: Option<String>,
    warnings: String,
    method: String,
    input_vertices: Option<u64>,
    input_faces: Option<u64>,
    vertices: Option<u64>,
    faces: Option<u64>,
    seconds: Option<f64>,
    hausdorff_max: Option<f64>,
    hausdorff_mean: Option<f64>,
}

impl Row {
    fn cells(&self) -> [String; 13] {
        let n = |v: Option<u64>| v.map_or(String::new(), |v| v.to_string());
        let x = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
        [
            self.input.clone(),
            self.output.clone(),
            self.status.to_string(),
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

    /// A row read back from stats.csv (`None` unless it has every column).
    fn from_cells(cells: &[String]) -> Option<Row> {
        if cells.len() != FIELDS.len() {
            return None;
        }
        let n = |s: &String| s.parse().ok();
        let x = |s: &String| s.parse().ok();
        Some(Row {
            input: cells[0].clone(),
            output: cells[1].clone(),
            status: if cells[2] == "ok" { "ok" } else { "error" },
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

pub(crate) fn run(args: BatchArgs) -> anyhow::Result<()> {
    // Options first, in one place: the shard, the job count, the format, and every
    // `gng3d simplify` option checked by the same parser `gng3d simplify` uses.
    if args.world_size == 0 || args.rank >= args.world_size {
        bail!(
            "--rank must be in [0, --world-size), got --rank {} with --world-size {}",
            args.rank,
            args.world_size
        );
    }
    if args.jobs == Some(0) {
        bail!("--jobs must be at least 1");
    }
    if args.vertices.is_none() && args.faces.is_none() && args.ratio.is_none() {
        bail!("give a target: --vertices N, --faces N or --ratio R");
    }
    if let Some(f) = &args.format
        && mesh::io::Format::from_path(Path::new(&format!("x.{f}"))).is_none()
    {
        bail!("--format must be obj, ply, stl, gltf or glb, got {f:?}");
    }
    let simplify_options = simplify_options(&args);
    let probe: Vec<String> = ["gng3d", "simplify", "in.ply", "out.ply"]
        .into_iter()
        .map(String::from)
        .chain(simplify_options.iter().cloned())
        .collect();
    if let Err(e) = <super::Cli as clap::Parser>::try_parse_from(&probe) {
        let message = e.render().to_string();
        let first = message
            .lines()
            .next()
            .unwrap_or("")
            .trim_start_matches("error: ");
        bail!("simplify option: {first}");
    }

    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create the output folder", args.out.display()))?;
    mesh::io::check_writable(&args.out.join("stats.csv"))?;
    check_values(&args, &simplify_options)?;

    let all = list_inputs(&args.source)?;
    let files: Vec<PathBuf> = all
        .into_iter()
        .skip(args.rank)
        .step_by(args.world_size)
        .collect();
    let outputs: Vec<PathBuf> = files
        .iter()
        .map(|f| output_path(f, &args.out, args.format.as_deref()))
        .collect();
    let mut seen: HashMap<&Path, &Path> = HashMap::new();
    for (f, o) in files.iter().zip(&outputs) {
        if let Some(other) = seen.insert(o, f) {
            bail!(
                "{} and {} would both be written to {}",
                other.display(),
                f.display(),
                o.display()
            );
        }
    }

    let stats_name = if args.world_size > 1 {
        format!("stats-{}-of-{}.csv", args.rank, args.world_size)
    } else {
        "stats.csv".to_string()
    };
    let stats = Stats::open(&args.out.join(stats_name))?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = args.jobs.unwrap_or(cores).clamp(1, files.len().max(1));
    let threads_per_run = (cores / jobs).max(1);
    let exe = std::env::current_exe().context("cannot find the gng3d executable")?;

    // Largest files first (bytes on disk standing in for the work): a big file started last
    // leaves one job running alone at the end (longest-processing-time-first scheduling).
    let mut order: Vec<usize> = (0..files.len()).collect();
    let size = |i: usize| std::fs::metadata(&files[i]).map_or(0, |m| m.len());
    order.sort_by_key(|&i| (std::cmp::Reverse(size(i)), i));
    let start = std::time::Instant::now();
    let next = AtomicUsize::new(0);
    let done = Mutex::new((stats, Vec::<Row>::new(), None::<anyhow::Error>));
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&i) = order.get(k) else {
                        break;
                    };
                    let row = simplify_file(
                        &exe,
                        &files[i],
                        &outputs[i],
                        &args,
                        &simplify_options,
                        threads_per_run,
                    );
                    let mut done = done.lock().unwrap_or_else(|e| e.into_inner());
                    let (stats, rows, failure) = &mut *done;
                    if failure.is_some() {
                        continue;
                    }
                    // A row is recorded and printed before the next file's is.
                    let row = match stats.add(row) {
                        Ok(row) => row,
                        Err(e) => {
                            *failure = Some(e);
                            continue;
                        }
                    };
                    let line = serde_json::to_string(&row).unwrap_or_default();
                    if let Err(e) = super::write_stdout(format_args!("{line}"), true) {
                        *failure = Some(e);
                    }
                    rows.push(row);
                }
            });
        }
    });
    let (_, rows, failure) = done.into_inner().unwrap_or_else(|e| e.into_inner());
    if let Some(e) = failure {
        return Err(e);
    }
    let count = |s: &str| rows.iter().filter(|r| r.status == s).count();
    let errors = count("error");
    eprintln!(
        "{} files: {} ok, {} skipped, {} errors in {:.2} s",
        rows.len(),
        count("ok"),
        count("skipped"),
        errors,
        start.elapsed().as_secs_f64()
    );
    if errors > 0 {
        bail!(
            "{errors} of {} files failed (their rows say why)",
            rows.len()
        );
    }
    Ok(())
}

/// The option values (ranges, combinations) checked once before any file is read, by the
/// checks `gng3d simplify` makes: one run on a small sphere written to the output folder. An
/// error that does not name that mesh's file is the options' (e.g. `--ratio must be in (0, 1]`)
/// and stops the batch now instead of giving every file the same error row; one that names it
/// depends on the mesh (a target above its vertex count) and is each file's business.
fn check_values(args: &BatchArgs, options: &[String]) -> anyhow::Result<()> {
    let probe = args.out.join(".gng3d-batch-probe.ply");
    let probe_out = args.out.join(".gng3d-batch-probe-out.ply");
    mesh::io::save(&mesh::procedural::icosphere(2), &probe)?;
    let exe = std::env::current_exe().context("cannot find the gng3d executable")?;
    let run = Command::new(exe)
        .arg("simplify")
        .arg(&probe)
        .arg(&probe_out)
        .args(options)
        .env("RAYON_NUM_THREADS", "1")
        .output();
    std::fs::remove_file(&probe).ok();
    std::fs::remove_file(&probe_out).ok();
    let o = run.context("cannot run gng3d simplify")?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    let message = stderr.lines().rev().find_map(|l| l.strip_prefix("error: "));
    match message {
        Some(m) if !o.status.success() && !m.contains(".gng3d-batch-probe") => bail!("{m}"),
        _ => Ok(()),
    }
}

/// The `gng3d simplify` options of every file: method, target, then those after `--`.
fn simplify_options(args: &BatchArgs) -> Vec<String> {
    let mut options = vec!["--method".to_string(), args.method.clone()];
    if let Some(v) = args.vertices {
        options.extend(["--vertices".to_string(), v.to_string()]);
    }
    if let Some(f) = args.faces {
        options.extend(["--faces".to_string(), f.to_string()]);
    }
    if let Some(r) = args.ratio {
        options.extend(["--ratio".to_string(), r.to_string()]);
    }
    options.extend(args.simplify_options.iter().cloned());
    options
}

/// The mesh files of `source`: a folder's files in a format the loader knows
/// ([`mesh::io::Format::from_path`]) sorted by name, or the paths
/// listed in a manifest (relative to it).
fn list_inputs(source: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let is_mesh = |p: &Path| mesh::io::Format::from_path(p).is_some();
    if source.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(source)
            .with_context(|| format!("{}: cannot read the folder", source.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && is_mesh(p))
            .collect();
        files.sort();
        return Ok(files);
    }
    if is_mesh(source) {
        return Ok(vec![source.to_path_buf()]);
    }
    let text = std::fs::read_to_string(source).with_context(|| {
        format!(
            "{}: not a folder, a mesh or a readable manifest",
            source.display()
        )
    })?;
    let base = source.parent().unwrap_or(Path::new("."));
    Ok(text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| base.join(l))
        .collect())
}

/// Where `input`'s result goes: its file name in `out` (with `format`'s extension if given).
fn output_path(input: &Path, out: &Path, format: Option<&str>) -> PathBuf {
    let name = Path::new(input.file_name().unwrap_or_default());
    match format {
        Some(f) => out.join(name.with_extension(f.to_ascii_lowercase())),
        None => out.join(name),
    }
}

/// Simplify one file with a `gng3d simplify` process (and measure it with `gng3d metrics`);
/// never fails: what goes wrong is the row's error.
fn simplify_file(
    exe: &Path,
    input: &Path,
    output: &Path,
    args: &BatchArgs,
    options: &[String],
    threads: usize,
) -> Row {
    let mut row = Row {
        input: input.display().to_string(),
        output: output.display().to_string(),
        method: args.method.clone(),
        ..Row::default()
    };
    if args.skip_existing && output.exists() {
        row.status = "skipped";
        return row;
    }
    let start = std::time::Instant::now();
    let run = |cmd: &mut Command| -> Result<(serde_json::Value, Vec<String>), String> {
        let o = cmd
            .env("RAYON_NUM_THREADS", threads.to_string())
            .output()
            .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
        let stderr = String::from_utf8_lossy(&o.stderr);
        let warnings = stderr
            .lines()
            .filter_map(|l| l.strip_prefix("warning: "))
            .map(str::to_string)
            .collect();
        if !o.status.success() {
            let message = stderr
                .lines()
                .rev()
                .find_map(|l| l.strip_prefix("error: "))
                .map(str::to_string)
                .unwrap_or_else(|| format!("gng3d ended with {} ({})", o.status, stderr.trim()));
            return Err(message);
        }
        let json = serde_json::from_slice(&o.stdout)
            .map_err(|e| format!("unreadable --json output: {e}"))?;
        Ok((json, warnings))
    };
    let simplified = run(Command::new(exe)
        .arg("simplify")
        .arg(input)
        .arg(output)
        .args(options)
        .arg("--json"));
    let (json, warnings) = match simplified {
        Ok(x) => x,
        Err(e) => {
            row.status = "error";
            row.error = Some(e);
            row.seconds = Some(start.elapsed().as_secs_f64());
            return row;
        }
    };
    let count = |keys: &[&str]| {
        keys.iter().find_map(|k| {
            json.get(k)
                .or_else(|| json.get("report").and_then(|r| r.get(k)))
                .and_then(serde_json::Value::as_u64)
        })
    };
    row.vertices = count(&["vertices"]);
    row.faces = count(&["faces"]);
    row.input_vertices = count(&["input_vertices"]);
    row.input_faces = count(&["input_faces"]);
    if args.measure {
        match run(Command::new(exe)
            .arg("metrics")
            .arg(input)
            .arg(output)
            .arg("--json"))
        {
            Ok((m, _)) => {
                row.hausdorff_max = m["hausdorff"]["max"].as_f64();
                row.hausdorff_mean = m["hausdorff"]["mean"].as_f64();
            }
            Err(e) => {
                row.status = "error";
                row.error = Some(format!("measuring the result: {e}"));
            }
        }
    }
    row.warnings = warnings.join("; ");
    if row.status.is_empty() {
        row.status = "ok";
    }
    row.seconds = Some(start.elapsed().as_secs_f64());
    row
}

/// The stats table: rows appended and flushed as files complete; the ok rows of an earlier run
/// give a skipped file its counts back.
struct Stats {
    file: std::fs::File,
    path: PathBuf,
    earlier: HashMap<String, Row>,
}

impl Stats {
    fn open(path: &Path) -> anyhow::Result<Stats> {
        let mut earlier = HashMap::new();
        let existing = std::fs::read_to_string(path).unwrap_or_default();
        let mut records = parse_csv(&existing).into_iter();
        let header_ok = records.next().is_none_or(|h| h == FIELDS);
        if !header_ok {
            bail!(
                "{}: not a gng3d stats table (its header differs); move it or choose another --out",
                path.display()
            );
        }
        for cells in records {
            if let Some(row) = Row::from_cells(&cells).filter(|r| r.status == "ok") {
                earlier.insert(row.output.clone(), row);
            }
        }
        let mut file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .with_context(|| format!("{}: cannot open the stats table", path.display()))?;
        if existing.is_empty() {
            file.write_all(csv_line(&FIELDS.map(String::from)).as_bytes())
                .with_context(|| format!("{}: write failed", path.display()))?;
        }
        Ok(Stats {
            file,
            path: path.to_path_buf(),
            earlier,
        })
    }

    /// Record `row` (a skipped file an earlier run recorded comes back with that run's counts
    /// and is not written again).
    fn add(&mut self, row: Row) -> anyhow::Result<Row> {
        if row.status == "skipped" {
            if let Some(earlier) = self.earlier.get(&row.output) {
                return Ok(Row {
                    status: "skipped",
                    ..earlier.clone()
                });
            }
            return Ok(row);
        }
        self.file
            .write_all(csv_line(&row.cells()).as_bytes())
            .and_then(|()| self.file.flush())
            .with_context(|| format!("{}: write failed", self.path.display()))?;
        Ok(row)
    }
}

/// One CSV record (RFC 4180 quoting: fields with a comma, quote or line break are quoted).
fn csv_line(cells: &[String]) -> String {
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
fn parse_csv(text: &str) -> Vec<Vec<String>> {
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
}

//! `gng3d batch`: simplify a folder or a manifest of mesh files, for schedulers without Dask
//! (Slurm arrays, `xargs`, one machine): static sharding by `--rank`/`--world-size`, `--jobs`
//! files at a time, one JSON line per file on stdout as it completes, the same rows as the
//! Python package's `gng3d.batch` (and its `stats.csv`), a summary line on stderr.
//!
//! Each file runs as its own `gng3d simplify` process (this executable), so a batch writes
//! byte for byte the meshes `gng3d simplify` writes with the same options, and a file that
//! exhausts memory or crashes is an error row while the others go on. Outputs are written
//! atomically, so `--skip-existing` resumes a killed run: an output that exists is complete.
//! A resumed run records an output that has no row yet (counts read from the files), so the
//! table ends with one row per input.
//!
//! Refused before anything is written: two files whose results would share a file (a `.gltf`'s
//! buffer `<stem>.bin` included, names that differ only in case counted as one), and a result
//! that would replace an input (`--out` the source folder). The `gng3d simplify` children die
//! with the batch (Linux), and the stats table is locked while it is written, so batches run
//! into one folder write its header once.

use std::collections::HashMap;
use std::io::{Read, Write};
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
            status: match cells[2].as_str() {
                "ok" => "ok",
                "skipped" => "skipped",
                _ => "error",
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

    // Where every file goes, checked over the whole list (all shards write into one folder)
    // before anything is written: no two files, or a `.gltf` and its buffer file, to one place
    // (or to names that differ only in case), and no result over an input.
    let all = list_inputs(&args.source)?;
    let all_outputs: Vec<PathBuf> = all
        .iter()
        .map(|f| output_path(f, &args.out, args.format.as_deref()))
        .collect();
    check_collisions(&all, &all_outputs)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create the output folder", args.out.display()))?;
    check_inputs_kept(&args.source, &args.out, &all, &all_outputs)?;
    mesh::io::check_writable(&args.out.join("stats.csv"))?;
    check_values(&args, &simplify_options)?;

    let files: Vec<PathBuf> = all
        .into_iter()
        .skip(args.rank)
        .step_by(args.world_size)
        .collect();
    let outputs: Vec<PathBuf> = all_outputs
        .into_iter()
        .skip(args.rank)
        .step_by(args.world_size)
        .collect();

    let stats_name = if args.world_size > 1 {
        format!("stats-{}-of-{}.csv", args.rank, args.world_size)
    } else {
        "stats.csv".to_string()
    };
    let stats = Stats::open(&args.out.join(stats_name))?;
    // The outputs the table already has a row for (a skipped file's row comes from there).
    let recorded: std::collections::HashSet<String> = stats.earlier.keys().cloned().collect();
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
                        recorded.contains(&outputs[i].display().to_string()),
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
    // Named for this process: another batch into the same folder probes at the same time.
    let id = std::process::id();
    let probe = args.out.join(format!(".gng3d-batch-probe-{id}.ply"));
    let probe_out = args.out.join(format!(".gng3d-batch-probe-{id}-out.ply"));
    mesh::io::save(&mesh::procedural::icosphere(2), &probe)?;
    let exe = std::env::current_exe().context("cannot find the gng3d executable")?;
    let run = gng3d_command(&exe)
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

/// A command running `exe` (this executable) as a child that dies with the batch: on Linux the
/// child asks for SIGKILL when its parent ends (`PR_SET_PDEATHSIG`), so `kill -9` of a batch
/// does not leave its `gng3d simplify` runs going on (and writing) unseen. The signal comes
/// when the *thread* that spawned the child ends, not the process: children are spawned by the
/// batch's job threads (and its main thread), which live until the batch's last file is done.
fn gng3d_command(exe: &Path) -> Command {
    let mut command = Command::new(exe);
    // The opt-in of this run reaches its children.
    if mesh::io::reference_scope() == mesh::io::ReferenceScope::Anywhere {
        command.arg("--allow-outside-references");
    }
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        let parent = std::process::id();
        // SAFETY: between fork and exec the closure only makes async-signal-safe system calls
        // (prctl, getppid) and builds an io::Error from an errno, which does not allocate.
        unsafe {
            command.pre_exec(move || {
                let signal = libc::SIGKILL as libc::c_ulong;
                if libc::prctl(libc::PR_SET_PDEATHSIG, signal) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                // The batch ended before the request was made: nothing would send the signal.
                if libc::getppid() as u32 != parent {
                    return Err(std::io::Error::from_raw_os_error(libc::ESRCH));
                }
                Ok(())
            });
        }
    }
    command
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

/// The files that writing `output` creates: itself, and for a `.gltf` its buffer `<stem>.bin`
/// next to it (as [`mesh::io::save`] names it), each with how an error message names it.
fn written_files(output: &Path) -> Vec<(PathBuf, String)> {
    let mut files = vec![(output.to_path_buf(), output.display().to_string())];
    if mesh::io::Format::from_path(output) == Some(mesh::io::Format::Gltf)
        && let Some(stem) = output.file_stem()
    {
        let mut name = stem.to_os_string();
        name.push(".bin");
        let bin = output.with_file_name(name);
        let says = format!(
            "{} (the buffer file of {})",
            bin.display(),
            output.display()
        );
        files.push((bin, says));
    }
    files
}

/// `path` with its letters in one case: the key under which two output names that differ only
/// in case (one file on a case-insensitive file system) meet.
fn fold_case(path: &Path) -> Vec<u8> {
    let bytes = path.as_os_str().as_encoded_bytes();
    std::str::from_utf8(bytes).map_or_else(
        |_| bytes.to_ascii_lowercase(),
        |s| s.to_lowercase().into_bytes(),
    )
}

/// Refuses a list in which two files would write one output file (the result, or a `.gltf`'s
/// buffer file), names that differ only in case counting as one: the later file would
/// overwrite the earlier's result, and both rows would say ok.
fn check_collisions(inputs: &[PathBuf], outputs: &[PathBuf]) -> anyhow::Result<()> {
    // Files that are one on any file system first (m.gltf and m.GLTF both write m.bin), then
    // names one on case-insensitive ones.
    let mut same: HashMap<PathBuf, &Path> = HashMap::new();
    let mut folded: HashMap<Vec<u8>, (&Path, String)> = HashMap::new();
    for (input, output) in inputs.iter().zip(outputs) {
        for (file, says) in written_files(output) {
            if let Some(other) = same.insert(file.clone(), input) {
                bail!(
                    "{} and {} would both be written to {says}",
                    other.display(),
                    input.display(),
                );
            }
            folded.entry(fold_case(&file)).or_insert((input, says));
        }
    }
    let mut seen: HashMap<Vec<u8>, &Path> = HashMap::new();
    for (input, output) in inputs.iter().zip(outputs) {
        for (file, says) in written_files(output) {
            let key = fold_case(&file);
            if let Some(other) = seen.insert(key.clone(), input) {
                let other_says = &folded[&key].1;
                bail!(
                    "{} and {} would both be written to one file, {other_says} and {says} \
                     (names that differ only in case are one file on case-insensitive file \
                     systems); rename one",
                    other.display(),
                    input.display(),
                );
            }
        }
    }
    Ok(())
}

/// The file `path` names with links followed (writes go through links): its canonical path
/// when it exists, else its folder's joined with its name (`None` when the folder is not there
/// either, so nothing can be there).
fn canonical(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(dir.canonicalize().ok()?.join(path.file_name()?))
}

/// Refuses, before any file is written, an output folder that is the source folder or a result
/// (or a `.gltf` result's buffer file) that would replace an input: `--out` the source would otherwise replace every input
/// with its simplification (and with `--skip-existing`, skip everything). A folder inside the
/// source folder is fine while no result lands on an input.
fn check_inputs_kept(
    source: &Path,
    out: &Path,
    inputs: &[PathBuf],
    outputs: &[PathBuf],
) -> anyhow::Result<()> {
    if source.is_dir()
        && let (Ok(s), Ok(o)) = (source.canonicalize(), out.canonicalize())
        && s == o
    {
        bail!(
            "{}: the output folder is the source folder {} (each result would replace its \
             input); choose another --out",
            out.display(),
            source.display()
        );
    }
    let kept: HashMap<PathBuf, &Path> = inputs
        .iter()
        .filter_map(|input| Some((input.canonicalize().ok()?, input.as_path())))
        .collect();
    for (input, output) in inputs.iter().zip(outputs) {
        for (file, _) in written_files(output) {
            if let Some(kept) = canonical(&file).and_then(|c| kept.get(&c)) {
                bail!(
                    "{}: the result of {} would be written over the input {}; choose another \
                     --out",
                    file.display(),
                    input.display(),
                    kept.display()
                );
            }
        }
    }
    Ok(())
}

/// Simplify one file with a `gng3d simplify` process (and measure it with `gng3d metrics`);
/// never fails: what goes wrong is the row's error. `recorded`: the stats table has a row for
/// `output` (a skipped file gets that row's counts; without one, its counts are read from the
/// files).
fn simplify_file(
    exe: &Path,
    input: &Path,
    output: &Path,
    args: &BatchArgs,
    options: &[String],
    threads: usize,
    recorded: bool,
) -> Row {
    let mut row = Row {
        input: input.display().to_string(),
        output: output.display().to_string(),
        method: args.method.clone(),
        ..Row::default()
    };
    if args.skip_existing && output.exists() {
        row.status = "skipped";
        if !recorded {
            // Written by a run killed before it recorded the row: the row (with the counts a
            // run gives) is made from the files, so the table has one row per input.
            let counts = |path: &Path| {
                mesh::io::load(path).map(|m| {
                    (
                        Some(m.mesh.vertex_count() as u64),
                        Some(m.mesh.face_count() as u64),
                    )
                })
            };
            let mut problems = Vec::new();
            match counts(output) {
                Ok((v, f)) => (row.vertices, row.faces) = (v, f),
                Err(e) => problems.push(format!("reading the existing output: {e}")),
            }
            match counts(input) {
                Ok((v, f)) => (row.input_vertices, row.input_faces) = (v, f),
                Err(e) => problems.push(format!("reading the input: {e}")),
            }
            row.error = (!problems.is_empty()).then(|| problems.join("; "));
        }
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
    let simplified = run(gng3d_command(exe)
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
        match run(gng3d_command(exe)
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

/// The stats table: rows appended and flushed as files complete; the ok and skipped rows of an
/// earlier run give a skipped file its counts back.
///
/// Another batch may write the same table (two processes given one `--out`): the table is read
/// and its header written under an exclusive advisory lock (`flock(LOCK_EX)` on Unix), and each
/// row is appended under it, so the header is written once and rows are whole.
struct Stats {
    file: std::fs::File,
    path: PathBuf,
    earlier: HashMap<String, Row>,
}

impl Stats {
    fn open(path: &Path) -> anyhow::Result<Stats> {
        let file = std::fs::OpenOptions::new()
            .read(true)
            .create(true)
            .append(true)
            .open(path)
            .with_context(|| format!("{}: cannot open the stats table", path.display()))?;
        let mut stats = Stats {
            file,
            path: path.to_path_buf(),
            earlier: HashMap::new(),
        };
        stats.locked(|stats| {
            let mut bytes = Vec::new();
            (&stats.file)
                .read_to_end(&mut bytes)
                .with_context(|| format!("{}: cannot read the stats table", path.display()))?;
            let existing = String::from_utf8_lossy(&bytes);
            let mut records = parse_csv(&existing).into_iter();
            let header_ok = records.next().is_none_or(|h| h == FIELDS);
            if !header_ok {
                bail!(
                    "{}: not a gng3d stats table (its header differs); move it or choose another --out",
                    path.display()
                );
            }
            for cells in records {
                if let Some(row) = Row::from_cells(&cells).filter(|r| r.status != "error") {
                    stats.earlier.insert(row.output.clone(), row);
                }
            }
            if existing.is_empty() {
                stats.append(&csv_line(&FIELDS.map(String::from)))?;
            }
            Ok(())
        })?;
        Ok(stats)
    }

    /// `f` with the table locked against other processes writing it.
    fn locked<T>(&mut self, f: impl FnOnce(&mut Stats) -> anyhow::Result<T>) -> anyhow::Result<T> {
        self.file
            .lock()
            .with_context(|| format!("{}: cannot lock the stats table", self.path.display()))?;
        let result = f(self);
        self.file.unlock().ok();
        result
    }

    /// Append `line` (the table locked) and flush it.
    fn append(&mut self, line: &str) -> anyhow::Result<()> {
        self.file
            .write_all(line.as_bytes())
            .and_then(|()| self.file.flush())
            .with_context(|| format!("{}: write failed", self.path.display()))
    }

    /// Record `row` (a skipped file an earlier run recorded comes back with that run's counts
    /// and is not written again; one without a row is written with the counts it has).
    fn add(&mut self, row: Row) -> anyhow::Result<Row> {
        if row.status == "skipped"
            && let Some(earlier) = self.earlier.get(&row.output)
        {
            return Ok(Row {
                status: "skipped",
                ..earlier.clone()
            });
        }
        self.locked(|stats| stats.append(&csv_line(&row.cells())))?;
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

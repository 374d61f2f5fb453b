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
//! The engine is `job::batch`, Python's too: the files, their outputs and the checks before
//! anything is written ([`Plan`]), the rows and the stats table ([`Table`]). What is this
//! command's own: the options (checked once by `gng3d simplify`'s parser and checks), the job
//! threads, and the `gng3d simplify` children, which die with the batch (Linux).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::{Context, bail};
use job::batch::{Inputs, Item, Plan, Row, Shard, Status, Table};

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

pub(crate) fn run(args: BatchArgs) -> anyhow::Result<()> {
    // Options first, in one place: the shard, the job count, the format, and every
    // `gng3d simplify` option checked by the same parser `gng3d simplify` uses.
    let Some(shard) = Shard::new(args.rank, args.world_size) else {
        bail!(
            "--rank must be in [0, --world-size), got --rank {} with --world-size {}",
            args.rank,
            args.world_size
        );
    };
    if args.jobs == Some(0) {
        bail!("--jobs must be at least 1");
    }
    if args.vertices.is_none() && args.faces.is_none() && args.ratio.is_none() {
        bail!("give a target: --vertices N, --faces N or --ratio R");
    }
    if let Some(f) = &args.format
        && !job::batch::known_format(f)
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
    // before anything is written.
    let plan = Plan::new(
        Inputs::Source(&args.source),
        &args.out,
        args.format.as_deref(),
        shard,
    )?;
    check_values(&args, &simplify_options)?;
    let items = plan.items();
    let stats = Table::open(Some(&args.out.join(shard.stats_name())))?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = args.jobs.unwrap_or(cores).clamp(1, items.len().max(1));
    let threads_per_run = (cores / jobs).max(1);
    let exe = std::env::current_exe().context("cannot find the gng3d executable")?;

    // Largest files first: a big file started last leaves one job running alone at the end.
    let order = plan.largest_first();
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
                    let row =
                        simplify_file(&exe, &items[i], &args, &simplify_options, threads_per_run);
                    let mut done = done.lock().unwrap_or_else(|e| e.into_inner());
                    let (stats, rows, failure) = &mut *done;
                    if failure.is_some() {
                        continue;
                    }
                    // A row is recorded and printed before the next file's is.
                    let row = match stats.add(row) {
                        Ok(row) => row,
                        Err(e) => {
                            *failure = Some(e.into());
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
    let statuses: Vec<Status> = rows.iter().map(|r| r.status).collect();
    let errors = statuses.iter().filter(|&&s| s == Status::Error).count();
    eprintln!(
        "{}",
        job::batch::summary(&statuses, Some(start.elapsed().as_secs_f64()))
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
    mesh::io::save(&mesh::procedural::icosphere(2).into(), &probe)?;
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

/// Simplify one file with a `gng3d simplify` process (and measure it with `gng3d metrics`);
/// never fails: what goes wrong is the row's error. A skipped file's row has no counts yet
/// (the stats table gives it an earlier run's or reads them from the files).
fn simplify_file(
    exe: &Path,
    item: &Item,
    args: &BatchArgs,
    options: &[String],
    threads: usize,
) -> Row {
    let (input, output) = (&item.input, &item.output);
    if args.skip_existing && output.exists() {
        return Row::new(item, &args.method, Status::Skipped);
    }
    let mut row = Row::new(item, &args.method, Status::Ok);
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
            row.status = Status::Error;
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
    let measured = args.measure.then(|| {
        run(gng3d_command(exe)
            .arg("metrics")
            .arg(input)
            .arg(output)
            .arg("--json"))
        .map(|(m, _)| {
            (
                m["hausdorff"]["max"].as_f64(),
                m["hausdorff"]["mean"].as_f64(),
            )
        })
        .map_err(|e| e.to_string())
    });
    row.finish(measured, &warnings, start)
}

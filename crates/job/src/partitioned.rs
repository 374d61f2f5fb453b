//! The partitioned run (issue 50, `--partition auto`): one mesh larger than memory simplified
//! by the `partition` crate without ever being held — QEM on positions only, the input read
//! in a streaming pass (PLY, OBJ or STL), cut into cells that fit [`PartitionOptions::memory_budget`],
//! each cell simplified, the cells stitched and finished to the exact target.
//!
//! Steps of [`simplify_file`]:
//! 1. **Inspect** the input's header (`partition::inspect`): its counts resolve the target
//!    ([`partition_target`]) and what it holds besides positions is named in a warning (kept
//!    attributes cannot follow: the run is positions-only for now).
//! 2. **Run** `partition::simplify` in a scoped thread while this thread hands the cells'
//!    progress to the observer ([`crate::Observer::cells`]).
//! 3. **Report**: the output is read back (it has the target's size) for the summary's line,
//!    and the work folder is removed unless asked to keep it.

use crate::summary::{PartitionSummary, Summary, Warning};
use crate::{AttributePolicy, FileOutcome, JobError, Observer, Opt, Outcome, Request, Target};
use std::path::{Path, PathBuf};

/// Whether a run holds the mesh in memory (the default) or streams it through the partition.
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub enum Partition {
    /// The whole mesh in memory: `off`.
    #[default]
    Off,
    /// The partitioned simplification (QEM, positions only, PLY, OBJ or STL input): `auto`.
    Auto(PartitionOptions),
}

/// The partitioned run's options.
#[derive(Debug, Clone, PartialEq)]
pub struct PartitionOptions {
    /// Bytes one cell may take while it is simplified (at least 64 KiB).
    pub memory_budget: u64,
    /// The folder of the chunk files; `None`: [`default_work_dir`] of the output. A rerun with
    /// the same folder resumes from its finished cells.
    pub work_dir: Option<PathBuf>,
    /// Keep the work folder after a successful run (otherwise removed when this run made it or
    /// it held an earlier partition).
    pub keep_work: bool,
}

impl Default for PartitionOptions {
    /// The partition's default budget (1 GiB a cell), the default folder, removed at the end.
    fn default() -> PartitionOptions {
        PartitionOptions {
            memory_budget: partition::PartitionParams::new(qem::Target::Ratio(1.0), PathBuf::new())
                .memory_budget,
            work_dir: None,
            keep_work: false,
        }
    }
}

/// The smallest budget the partition takes.
const MIN_BUDGET: u64 = 1 << 16;

/// The work folder of a run writing `output` when none is named: `<output's name>.gng3d-work`
/// beside it.
pub fn default_work_dir(output: &Path) -> PathBuf {
    let name = output
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    output.with_file_name(format!("{name}.gng3d-work"))
}

/// A size in bytes: a number with an optional unit, `kB`/`MB`/`GB`/`TB` (powers of 1000),
/// `KiB`/`MiB`/`GiB`/`TiB` (powers of 1024) or `B`, e.g. `2GB`, `512MiB`, `1.5 GB`.
pub fn parse_size(s: &str) -> Result<u64, JobError> {
    let t = s.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = (&t[..split], t[split..].trim());
    let scale: f64 = match unit.to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "k" | "kb" => 1e3,
        "m" | "mb" => 1e6,
        "g" | "gb" => 1e9,
        "t" | "tb" => 1e12,
        "kib" => 1024.0,
        "mib" => 1024.0 * 1024.0,
        "gib" => 1024.0 * 1024.0 * 1024.0,
        "tib" => 1024.0_f64.powi(4),
        _ => {
            return Err(JobError::option(
                Opt::MemoryBudget,
                format!("unknown unit {unit:?} in {s:?} (B, kB, MB, GB, TB, KiB, MiB, GiB, TiB)"),
            ));
        }
    };
    let value: f64 = number.parse().map_err(|_| {
        JobError::option(
            Opt::MemoryBudget,
            format!("expected a size such as 2GB, got {s:?}"),
        )
    })?;
    Ok((value * scale).round() as u64)
}

/// The checks of a partitioned request ([`Request::validate`] calls it): QEM with a size target
/// and none of QEM's other options, a budget the partition takes.
pub(crate) fn validate(request: &Request, options: &PartitionOptions) -> Result<(), JobError> {
    if request.method.is_gng() {
        return Err(JobError::NotForMethod {
            options: vec![Opt::Partition],
            method: request.method,
            detail: "the partitioned simplification is QEM's",
        });
    }
    let q = &request.qem;
    let refused: Vec<Opt> = [
        (q.threshold != 0.0, Opt::Threshold),
        (q.lock_border, Opt::LockBorder),
        (q.max_error.is_some(), Opt::MaxError),
        (q.attribute_weights.is_some(), Opt::AttributeWeights),
    ]
    .into_iter()
    .filter_map(|(given, opt)| given.then_some(opt))
    .collect();
    if !refused.is_empty() {
        return Err(JobError::NotWithPartition { options: refused });
    }
    if request.target == Target::MaxErrorOnly {
        return Err(JobError::NoTarget);
    }
    if options.memory_budget < MIN_BUDGET {
        return Err(JobError::option(
            Opt::MemoryBudget,
            format!(
                "must be at least 64 KiB, got {} bytes",
                options.memory_budget
            ),
        ));
    }
    Ok(())
}

/// QEM's target of `target` on an input with `vertices` vertex records: a share of the
/// vertices is rounded to a count of them (the file's records: the partition does not weld),
/// a share of the faces stays a share. An STL has no vertex records (`None`: its corners are
/// welded during the partition), so a share of its vertices is taken as the same share of its
/// faces (equal on a closed mesh, where V ≈ F/2). The one mapping of the CLI and of Python's
/// distributed driver, so both reach the same mesh.
pub fn partition_target(target: Target, vertices: Option<u64>) -> Result<qem::Target, JobError> {
    Ok(match target {
        Target::Vertices(n) => qem::Target::Vertices(n),
        Target::Faces(n) => qem::Target::Faces(n),
        Target::Ratio(r) => match vertices {
            Some(v) => qem::Target::Vertices((r * v as f64).round() as usize),
            None => qem::Target::Ratio(r),
        },
        Target::FaceRatio(r) => qem::Target::Ratio(r),
        _ => return Err(JobError::NoTarget),
    })
}

/// The warning of a positions-only run on an input holding more (`ignored`, as
/// `partition::inspect` names it), when the request keeps attributes; `None` otherwise
/// (`--attributes drop` asked for positions only).
pub fn dropped_attributes(request: &Request, ignored: &[String]) -> Option<String> {
    (request.attributes == AttributePolicy::Keep && !ignored.is_empty()).then(|| {
        format!(
            "the partitioned simplification is QEM on positions only for now: dropped {} (--attributes drop to say so)",
            ignored.join(", ")
        )
    })
}

/// Relay of the cells' progress from the worker threads to the observer's thread.
type CellsSender = std::sync::Mutex<std::sync::mpsc::Sender<(usize, usize)>>;

/// The partitioned run of `request` (whose `partition` is `options`) from `input` to `output`
/// (see the module's steps); [`crate::simplify_file`] calls it.
pub(crate) fn simplify_file(
    input: &Path,
    output: &Path,
    request: &Request,
    options: &PartitionOptions,
    observer: &mut dyn Observer,
) -> Result<FileOutcome, JobError> {
    let info = partition::inspect(input).map_err(JobError::from)?;
    let target = partition_target(request.target, info.vertices)?;
    let mut warnings: Vec<Warning> = dropped_attributes(request, &info.ignored)
        .map(|message| Warning {
            kind: "attributes_dropped",
            message,
        })
        .into_iter()
        .collect();
    let work_dir = options
        .work_dir
        .clone()
        .unwrap_or_else(|| default_work_dir(output));
    // Removed at the end only when it is the partition's: new, or an earlier run's.
    let removable = !work_dir.exists() || work_dir.join("manifest").is_file();
    let (sender, receiver) = std::sync::mpsc::channel();
    let sender: CellsSender = std::sync::Mutex::new(sender);
    let params = partition::PartitionParams {
        memory_budget: options.memory_budget,
        threads: request.threads.unwrap_or(0),
        progress: Some(std::sync::Arc::new(move |done, total| {
            if let Ok(s) = sender.lock() {
                let _ = s.send((done, total));
            }
        })),
        ..partition::PartitionParams::new(target, work_dir.clone())
    };
    let start = std::time::Instant::now();
    let report = std::thread::scope(|scope| {
        let run = scope.spawn(move || {
            let params = params;
            partition::simplify(input, output, &params)
        });
        // Ends when the run drops its parameters, and the sender with them.
        for (done, total) in receiver {
            observer.cells(done, total);
        }
        run.join()
    })
    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    .map_err(JobError::from)?;
    let seconds = start.elapsed().as_secs_f64();
    let model = mesh::Model::from(mesh::io::load(output)?);
    if let Some(shortfall) = reached(target, &report) {
        warnings.push(Warning {
            kind: "target_not_reached",
            message: shortfall,
        });
    }
    if !options.keep_work && removable {
        // The output is written: a folder left behind costs disk, not the result.
        let _ = std::fs::remove_dir_all(&work_dir);
    }
    let messages: Vec<String> = warnings.iter().map(|w| w.message.clone()).collect();
    let summary = PartitionSummary::new(&report, seconds, work_dir, warnings);
    Ok(FileOutcome {
        outcome: Outcome {
            model,
            summary: Summary::Partition(Box::new(summary)),
            warnings: messages,
            training_stop: None,
        },
        kept: mesh::io::KeptAttributes::default(),
        file_counts: (
            info.vertices.map_or(report.input_vertices, |v| v as usize),
            report.input_faces,
        ),
    })
}

/// The sentence of a target the final pass fell short of (QEM stops when no contraction is
/// left), `None` when it was reached.
fn reached(target: qem::Target, report: &partition::PartitionReport) -> Option<String> {
    let (asked, got, what) = match target {
        qem::Target::Vertices(n) => (n, report.vertices, "vertices"),
        qem::Target::Faces(n) => (n, report.faces, "faces"),
        qem::Target::Ratio(r) => (
            (report.input_faces as f64 * r).round() as usize,
            report.faces,
            "faces",
        ),
    };
    // A face target may end one face short (an interior collapse removes two).
    (got > asked + usize::from(what == "faces"))
        .then(|| format!("target of {asked} {what} not reached: {got} {what}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_with_their_units() {
        for (text, bytes) in [
            ("2GB", 2_000_000_000),
            ("512MiB", 512 << 20),
            ("1.5 kB", 1_500),
            ("65536", 65_536),
            ("1GiB", 1 << 30),
        ] {
            assert_eq!(parse_size(text).unwrap(), bytes, "{text}");
        }
        for bad in ["", "GB", "2 parsecs", "1..2GB"] {
            assert!(parse_size(bad).is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn a_share_of_the_vertices_is_rounded_to_a_count() {
        let t = partition_target(Target::Ratio(0.1), Some(10_242)).unwrap();
        assert_eq!(t, qem::Target::Vertices(1_024));
        let t = partition_target(Target::FaceRatio(0.25), Some(10_242)).unwrap();
        assert_eq!(t, qem::Target::Ratio(0.25));
        // STL: no vertex records, a share of the faces.
        let t = partition_target(Target::Ratio(0.1), None).unwrap();
        assert_eq!(t, qem::Target::Ratio(0.1));
    }
}

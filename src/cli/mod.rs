//! Command-line definitions (clap) and dispatch to one module per subcommand.

mod compare;
mod info;
mod metrics;
mod reproduce;
mod simplify;

use clap::{Parser, Subcommand};

/// Simplify triangle meshes with GNG3D and QEM, and measure the results.
#[derive(Debug, Parser)]
#[command(name = "gng3d", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print vertex/face counts, topology, area and size of a mesh.
    Info(info::InfoArgs),
    /// Simplify a mesh with QEM or GNG3D and write the result.
    Simplify(simplify::SimplifyArgs),
    /// Compare an original and a simplified mesh: paper errors and Hausdorff distance.
    Metrics(metrics::MetricsArgs),
    /// Simplify with QEM and GNG3D to the same vertex count and measure both.
    Compare(compare::CompareArgs),
    /// Run the paper's checkpoint protocol on a mesh, or survey a folder of meshes.
    Reproduce(reproduce::ReproduceArgs),
}

/// Run the parsed command.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Info(args) => info::run(args),
        Command::Simplify(args) => simplify::run(args),
        Command::Metrics(args) => metrics::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Reproduce(args) => reproduce::run(args),
    }
}

/// Print `value` as pretty JSON on stdout; a closed stdout (e.g. `| head`) is not an error.
pub(crate) fn print_json<T: serde::Serialize>(value: &T) -> anyhow::Result<()> {
    use std::io::Write;
    let text = serde_json::to_string_pretty(value)?;
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}").and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

/// Load a mesh for the algorithms: welded, without degenerate/duplicate faces or unreferenced
/// vertices unless `raw`; loader warnings and what cleaning removed go to stderr.
pub(crate) fn load_prepared(path: &std::path::Path, raw: bool) -> anyhow::Result<mesh::TriMesh> {
    use anyhow::Context;
    let loaded = mesh::io::load(path).with_context(|| format!("loading {}", path.display()))?;
    for w in &loaded.warnings {
        eprintln!("warning: {}: {w}", path.display());
    }
    if raw {
        return Ok(loaded.mesh);
    }
    let (prepared, _report) = mesh::clean::prepare(&loaded.mesh);
    Ok(prepared)
}

/// Write `bytes` to `path` through a temporary file in the same folder and a rename, so a
/// failure never leaves a partial file.
pub(crate) fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> anyhow::Result<()> {
    use anyhow::Context;
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    let name = path
        .file_name()
        .map_or_else(Default::default, |n| n.to_os_string());
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(&name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = dir.join(tmp_name);
    std::fs::write(&tmp, bytes).with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        anyhow::anyhow!("renaming {} to {}: {e}", tmp.display(), path.display())
    })
}

//! Command-line definitions (clap) and dispatch to one module per subcommand.

mod info;
mod metrics;
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
}

/// Run the parsed command.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Info(args) => info::run(args),
        Command::Simplify(args) => simplify::run(args),
        Command::Metrics(args) => metrics::run(args),
    }
}

/// Print `value` as pretty JSON on stdout.
pub(crate) fn print_json<T: serde::Serialize>(value: &T) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}

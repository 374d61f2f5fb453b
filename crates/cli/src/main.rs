//! The `gng3d` command-line tool: inspect, simplify, measure and compare meshes.

use clap::Parser;
use std::process::ExitCode;

/// Out of memory is an error message and exit status 1, not an abort.
#[global_allocator]
static ALLOCATOR: gng3d_cli::process::ReportingAllocator = gng3d_cli::process::ReportingAllocator;

fn main() -> ExitCode {
    // Die quietly on a closed pipe (`gng3d info x.obj | head`), like other Unix tools.
    #[cfg(unix)]
    // SAFETY: restoring the default SIGPIPE disposition before any other thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Signals and file-size limits remove the temporary file of a write in progress.
    gng3d_cli::process::install_exit_handlers();
    let args = gng3d_cli::Cli::parse();
    match gng3d_cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}

//! The `gng3d` command-line tool as a library: argument definitions (clap) and one module per
//! subcommand. The binary (`src/main.rs`) only parses `std::env::args` and calls [`run`];
//! tests and the in-process fuzz driver call [`run_args`] with the same code path.
//!
//! Every subcommand checks its options and output paths before any work, validates them through
//! the library's one owner of each mapping (`gng3d_core::GngOptions`, `qem::QemParams`,
//! `metrics::HausdorffParams::validate`), and never writes an empty or unloadable mesh.

/// `println!` for the commands' text output: an error writing stdout (a full disk, a closed
/// file) is the command's error, as `--json`'s is, instead of a panic; a closed pipe is not (the
/// reader has what it wanted). Usable where the function returns `anyhow::Result`.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::cli::write_stdout(format_args!($($arg)*), true)?
    };
}

/// `print!` with [`outln!`]'s error handling.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cli::write_stdout(format_args!($($arg)*), false)?
    };
}

mod cli;
pub mod process;

pub use cli::{Cli, run};

use clap::Parser;
use std::ffi::OsString;

/// Parse `args` (the first item is the program name, as in `std::env::args_os`) and run the
/// command. A `--help`/`--version` request or a usage error comes back as the clap error (its
/// text is what the binary prints); everything else as the command's error.
pub fn run_args<I, T>(args: I) -> anyhow::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = Cli::try_parse_from(args)?;
    run(cli)
}

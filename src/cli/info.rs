//! `gng3d info`: counts, topology, area and size of one mesh.

use clap::Args;
use std::path::PathBuf;

/// Arguments of `gng3d info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Mesh file (.obj, .ply, .stl).
    pub mesh: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Run `gng3d info`.
pub fn run(_args: InfoArgs) -> anyhow::Result<()> {
    anyhow::bail!("`info` is being implemented")
}

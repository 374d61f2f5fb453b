//! `gng3d metrics`: paper errors and symmetric surface distance between two meshes.

use clap::Args;
use std::path::PathBuf;

/// Arguments of `gng3d metrics`.
#[derive(Debug, Args)]
pub struct MetricsArgs {
    /// The original mesh.
    pub original: PathBuf,
    /// The simplified mesh.
    pub simplified: PathBuf,
    /// Number of surface samples per direction for the Hausdorff distance.
    #[arg(long)]
    pub samples: Option<usize>,
    /// Seed of the surface sampler.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Run `gng3d metrics`.
pub fn run(_args: MetricsArgs) -> anyhow::Result<()> {
    anyhow::bail!("`metrics` is being implemented")
}

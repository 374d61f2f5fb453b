//! `gng3d simplify --method gng`.

use super::SimplifyArgs;

/// Simplify with GNG3D.
pub fn run(_args: &SimplifyArgs) -> anyhow::Result<()> {
    anyhow::bail!("GNG3D simplification is being implemented")
}

//! `gng3d simplify --method qem`.

use super::SimplifyArgs;

/// Simplify with QEM.
pub fn run(_args: &SimplifyArgs) -> anyhow::Result<()> {
    anyhow::bail!("QEM simplification is being implemented")
}

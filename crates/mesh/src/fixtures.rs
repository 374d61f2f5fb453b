//! Locating the shared real meshes (`GNG3D_MESHES`) for tests and benchmarks, with the project's
//! rule: without them a test skips with a message, except under `CI`, where it fails.

use std::path::PathBuf;

/// Name of the environment variable that points at the shared meshes folder.
pub const MESHES_ENV: &str = "GNG3D_MESHES";

/// The folder named by `GNG3D_MESHES`, provided it holds the file `probe` (e.g. `"README.md"`,
/// or the mesh a test needs). Otherwise `None` after a message on stderr, or a panic when the
/// environment variable `CI` is set: tests that need the meshes must fail, not skip, in CI.
pub fn shared_meshes_dir(probe: &str) -> Option<PathBuf> {
    let dir = std::env::var_os(MESHES_ENV).map(PathBuf::from);
    if let Some(d) = dir.as_ref().filter(|d| d.join(probe).is_file()) {
        return Some(d.clone());
    }
    let problem = format!("{MESHES_ENV} ({dir:?}) does not hold {probe}");
    assert!(std::env::var_os("CI").is_none(), "CI is set but {problem}");
    eprintln!("{problem}: set {MESHES_ENV} to the shared meshes folder to use the real meshes");
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_probe_is_none_outside_ci_and_a_panic_in_ci() {
        // The probe name cannot exist in any folder, so the outcome depends only on `CI`.
        let probe = "no such file \u{1}.obj";
        let result = std::panic::catch_unwind(|| shared_meshes_dir(probe));
        match std::env::var_os("CI") {
            Some(_) => assert!(result.is_err(), "must panic under CI"),
            None => assert_eq!(result.ok(), Some(None)),
        }
    }
}

//! [`run_one`]: one file of a batch in this process — [`crate::simplify_file`], measured when
//! asked — as its [`Row`]; never fails (what goes wrong is the row's error).

use super::Item;
use super::row::{Row, Status};
use crate::{JobError, Request, Spelling};
use std::path::Path;

/// What a batch does with each file besides simplifying it.
#[derive(Debug, Clone, Copy, Default)]
pub struct Settings {
    /// A file whose output exists is skipped (a killed run resumes where it stopped).
    pub skip_existing: bool,
    /// Measure each result against its input (symmetric Hausdorff max and mean, as
    /// `gng3d metrics` on the two files), with these parameters.
    pub measure: Option<metrics::HausdorffParams>,
}

/// Simplify `item` with `request` (and measure it by `settings`): its row. A skipped file's
/// row has no counts yet ([`super::Table::add`] completes it). A failed run's error is
/// `describe(error)`, or with [`describe`] the command line's wording.
pub fn run_one(
    item: &Item,
    request: &Request,
    settings: &Settings,
    describe: &dyn Fn(&Item, &Request, JobError) -> String,
) -> Row {
    let method = request.method.name();
    if settings.skip_existing && item.output.exists() {
        return Row::new(item, method, Status::Skipped);
    }
    let start = std::time::Instant::now();
    let mut row = Row::new(item, method, Status::Ok);
    let mut warnings = Vec::new();
    let done = crate::simplify_file(
        &item.input,
        &item.output,
        request,
        |loaded| {
            let input = item.input.display();
            warnings.extend(loaded.iter().map(|w| format!("{input}: {w}")));
        },
        &mut (),
    );
    let done = match done {
        Ok(done) => done,
        Err(e) => {
            row.status = Status::Error;
            row.error = Some(describe(item, request, e));
            row.seconds = Some(start.elapsed().as_secs_f64());
            return row;
        }
    };
    let output = item.output.display();
    warnings.extend(done.kept.dropped.iter().map(|w| format!("{output}: {w}")));
    warnings.extend(done.outcome.warnings.iter().cloned());
    let count = |n: usize| Some(n as u64);
    // The mesh the run was given (welded and cleaned), as `gng3d simplify --json` counts it:
    // the count a ratio is a share of.
    let (input_vertices, input_faces) = done.outcome.summary.input_counts();
    (row.input_vertices, row.input_faces) = (count(input_vertices), count(input_faces));
    let (vertices, faces) = done.outcome.summary.counts();
    (row.vertices, row.faces) = (count(vertices), count(faces));
    let measured = settings.measure.as_ref().map(|params| {
        measure(&item.input, &item.output, params)
            .map(|(max, mean)| (Some(max), Some(mean)))
            .map_err(|e| e.to_string())
    });
    row.finish(measured, &warnings, start)
}

/// The command line's wording of a failed run: "METHOD on INPUT: what" (options spelt as
/// flags), as `gng3d simplify` says it.
pub fn describe(item: &Item, request: &Request, error: JobError) -> String {
    format!(
        "{} on {}: {}",
        request.method.label(),
        item.input.display(),
        error.message(Spelling::Flags)
    )
}

/// The symmetric Hausdorff distance (max, mean) between the files `input` and `output`, as
/// they are (not welded), as `gng3d metrics` measures them.
fn measure(
    input: &Path,
    output: &Path,
    params: &metrics::HausdorffParams,
) -> Result<(f64, f64), String> {
    let (a, b) = rayon::join(|| mesh::io::load(input), || mesh::io::load(output));
    let (a, b) = (a.map_err(|e| e.to_string())?, b.map_err(|e| e.to_string())?);
    let params = metrics::MetricsParams { hausdorff: *params };
    let report = metrics::evaluate(&a.mesh, &b.mesh, &params).map_err(|e| e.to_string())?;
    Ok((report.hausdorff.max, report.hausdorff.mean))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Target;

    #[test]
    fn a_file_is_a_row_and_a_broken_one_an_error_row() {
        let dir = std::env::temp_dir().join(format!("job-batch-one-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = Item {
            input: dir.join("sphere.ply"),
            output: dir.join("out.ply"),
        };
        mesh::io::save(&mesh::procedural::icosphere(3).into(), &good.input).unwrap();
        let request = Request::new(Target::Ratio(0.25));
        let row = run_one(&good, &request, &Settings::default(), &describe);
        assert_eq!(row.status, Status::Ok, "{row:?}");
        assert_eq!((row.input_vertices, row.vertices), (Some(642), Some(161)));
        let skip = Settings {
            skip_existing: true,
            ..Settings::default()
        };
        let row = run_one(&good, &request, &skip, &describe);
        assert_eq!((row.status, row.vertices), (Status::Skipped, None));
        let broken = Item {
            input: dir.join("broken.ply"),
            output: dir.join("broken-out.ply"),
        };
        std::fs::write(&broken.input, "ply\nformat ascii 1.0\nelement vertex 3\n").unwrap();
        let row = run_one(&broken, &request, &Settings::default(), &describe);
        let error = row.error.unwrap_or_default();
        assert_eq!(row.status, Status::Error);
        assert!(
            error.starts_with("QEM on ") && error.contains("broken.ply"),
            "{error}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}

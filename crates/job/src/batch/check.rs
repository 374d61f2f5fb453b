//! Where each file's result goes, and the checks over the whole list before anything is
//! written: no two files to one output file (a `.gltf`'s buffer `<stem>.bin` included, names
//! that differ only in case counted as one) and no result over an input.

use super::PlanError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Where `input`'s result goes: its file name in `out` (with `format`'s extension if given).
pub fn output_path(input: &Path, out: &Path, format: Option<&str>) -> PathBuf {
    let name = Path::new(input.file_name().unwrap_or_default());
    match format {
        Some(f) => out.join(name.with_extension(f.to_ascii_lowercase())),
        None => out.join(name),
    }
}

/// The files that writing `output` creates: itself, and for a `.gltf` its buffer `<stem>.bin`
/// next to it (as [`mesh::io::save`] names it), each with how an error message names it.
fn written_files(output: &Path) -> Vec<(PathBuf, String)> {
    let mut files = vec![(output.to_path_buf(), output.display().to_string())];
    if mesh::io::Format::from_path(output) == Some(mesh::io::Format::Gltf)
        && let Some(stem) = output.file_stem()
    {
        let mut name = stem.to_os_string();
        name.push(".bin");
        let bin = output.with_file_name(name);
        let says = format!(
            "{} (the buffer file of {})",
            bin.display(),
            output.display()
        );
        files.push((bin, says));
    }
    files
}

/// `path` with its letters in one case: the key under which two output names that differ only
/// in case (one file on a case-insensitive file system) meet.
fn fold_case(path: &Path) -> Vec<u8> {
    let bytes = path.as_os_str().as_encoded_bytes();
    std::str::from_utf8(bytes).map_or_else(
        |_| bytes.to_ascii_lowercase(),
        |s| s.to_lowercase().into_bytes(),
    )
}

/// Refuses a list in which two files would write one output file (the result, or a `.gltf`'s
/// buffer file), names that differ only in case counting as one: the later file would
/// overwrite the earlier's result, and both rows would say ok.
pub(super) fn check_collisions(inputs: &[PathBuf], outputs: &[PathBuf]) -> Result<(), PlanError> {
    // Files that are one on any file system first (m.gltf and m.GLTF both write m.bin), then
    // names one on case-insensitive ones.
    let mut same: HashMap<PathBuf, &Path> = HashMap::new();
    let mut folded: HashMap<Vec<u8>, (&Path, String)> = HashMap::new();
    for (input, output) in inputs.iter().zip(outputs) {
        for (file, says) in written_files(output) {
            if let Some(other) = same.insert(file.clone(), input) {
                return Err(PlanError::Invalid(format!(
                    "{} and {} would both be written to {says}",
                    other.display(),
                    input.display(),
                )));
            }
            folded.entry(fold_case(&file)).or_insert((input, says));
        }
    }
    let mut seen: HashMap<Vec<u8>, &Path> = HashMap::new();
    for (input, output) in inputs.iter().zip(outputs) {
        for (file, says) in written_files(output) {
            let key = fold_case(&file);
            if let Some(other) = seen.insert(key.clone(), input) {
                let other_says = &folded[&key].1;
                return Err(PlanError::Invalid(format!(
                    "{} and {} would both be written to one file, {other_says} and {says} \
                     (names that differ only in case are one file on case-insensitive file \
                     systems); rename one",
                    other.display(),
                    input.display(),
                )));
            }
        }
    }
    Ok(())
}

/// The file `path` names with links followed (writes go through links): its canonical path
/// when it exists, else its folder's joined with its name (`None` when the folder is not there
/// either, so nothing can be there).
fn canonical(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(dir.canonicalize().ok()?.join(path.file_name()?))
}

/// Refuses, before any file is written, an output folder that is the source folder or a result
/// (or a `.gltf` result's buffer file) that would replace an input: writing into the source
/// folder would replace every input with its simplification (and a resumed run would skip
/// everything). A folder inside the source folder is fine while no result lands on an input.
pub(super) fn check_inputs_kept(
    source: Option<&Path>,
    out: &Path,
    inputs: &[PathBuf],
    outputs: &[PathBuf],
) -> Result<(), PlanError> {
    if let Some(source) = source
        && source.is_dir()
        && let (Ok(s), Ok(o)) = (source.canonicalize(), out.canonicalize())
        && s == o
    {
        return Err(PlanError::Invalid(format!(
            "{}: the output folder is the source folder {} (each result would replace its \
             input); choose another --out",
            out.display(),
            source.display()
        )));
    }
    let kept: HashMap<PathBuf, &Path> = inputs
        .iter()
        .filter_map(|input| Some((input.canonicalize().ok()?, input.as_path())))
        .collect();
    for (input, output) in inputs.iter().zip(outputs) {
        for (file, _) in written_files(output) {
            if let Some(kept) = canonical(&file).and_then(|c| kept.get(&c)) {
                return Err(PlanError::Invalid(format!(
                    "{}: the result of {} would be written over the input {}; choose another \
                     --out",
                    file.display(),
                    input.display(),
                    kept.display()
                )));
            }
        }
    }
    Ok(())
}

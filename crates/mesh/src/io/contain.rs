//! The one containment rule for the files a model names and the files written beside an
//! output, used by every reader and writer of this module (and through them by every front
//! end). Models come from strangers (upload forms, batch pipelines), so what a file *points at*
//! is as hostile as its bytes:
//!
//! - **Reading**: a model reads only *regular* files (no FIFO, device, socket or folder: a FIFO
//!   blocks forever, `/dev/zero` never ends) *inside its own folder*: the reference is
//!   percent-decoded by the caller, must be relative, is normalised (`a/../b` is `b`) and may
//!   not leave the folder by `..`, and after following symbolic links it must still lie inside
//!   the folder. It reads at most the bytes it declares ([`read_prefix`]: a glTF buffer's
//!   `byteLength`) or a fixed cap ([`LIBRARY_LIMIT`], [`IMAGE_LIMIT`]). What falls outside is
//!   refused with a [`Refused`] reason that the caller turns into a warning; nothing of it is
//!   read.
//! - **Writing**: files beside an output (material libraries, textures, images, a `.gltf`'s
//!   `.bin`) go inside the output's folder only ([`side_file`]): a relative name of plain
//!   components (no `..`, no root, no hidden names, no control characters), a folder that after
//!   links is still inside the output's folder, and never through a symbolic link. Generated
//!   names take their extension from a fixed list ([`image_extension`]), never from the file.
//! - **Names inside text formats** (OBJ `usemtl`, MTL `newmtl`) are written through
//!   [`one_line_name`], so a material name cannot add lines to the file.

use std::io::Read;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Where the files a model names may be read from ([`set_reference_scope`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ReferenceScope {
    /// Only inside the model's own folder (the default: models from strangers are safe).
    #[default]
    ModelFolder,
    /// Anywhere on this machine, relative paths with `..` and absolute paths included: for
    /// trusted models whose textures or buffers live beside their folder (`../textures/`). Still
    /// regular files only, within the same size caps, and never URLs; files written beside an
    /// output stay inside the output's folder either way.
    Anywhere,
}

/// Whether [`ReferenceScope::Anywhere`] is in effect (process-wide: a command line run or a
/// program decides it once).
static ANYWHERE: AtomicBool = AtomicBool::new(false);

/// Sets where the files that models name may be read from, for this process (the command
/// line's `--allow-outside-references`, Python's `gng3d.allow_outside_references`). The default
/// is [`ReferenceScope::ModelFolder`].
pub fn set_reference_scope(scope: ReferenceScope) {
    ANYWHERE.store(scope == ReferenceScope::Anywhere, Ordering::Relaxed);
}

/// The scope set by [`set_reference_scope`].
pub fn reference_scope() -> ReferenceScope {
    if ANYWHERE.load(Ordering::Relaxed) {
        ReferenceScope::Anywhere
    } else {
        ReferenceScope::ModelFolder
    }
}

/// The most bytes read from one material library (MTL): real libraries are kilobytes.
pub(crate) const LIBRARY_LIMIT: u64 = 64 << 20;
/// The most bytes read from one texture image a model names.
pub(crate) const IMAGE_LIMIT: u64 = 1 << 30;

/// Why a file a model names was not read, or a side file not written.
#[derive(Debug)]
pub(crate) enum Refused {
    /// A URI with a scheme other than `data:` (`http:`, `file:`): only local files are read.
    Remote,
    /// An absolute path.
    Absolute,
    /// A relative path that leaves the folder by `..`.
    Escapes,
    /// A symbolic link (or a folder on the way) that leads outside the folder.
    LinkOutside,
    /// Not a regular file (a FIFO, a device, a socket, a folder).
    NotRegular,
    /// Larger than the cap.
    TooLarge(u64),
    /// A generated or copied name that is not a plain relative file name.
    BadName,
    /// The operating system's error.
    Io(std::io::Error),
}

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refused::Remote => write!(f, "only files next to the model are read, not URLs"),
            Refused::Absolute => write!(
                f,
                "it is an absolute path; a model may only name files inside its own folder"
            ),
            Refused::Escapes => write!(f, "it leaves the model's folder (`..`)"),
            Refused::LinkOutside => write!(f, "it is a link to a place outside the folder"),
            Refused::NotRegular => write!(
                f,
                "it is not a regular file (a FIFO, device, socket or folder)"
            ),
            Refused::TooLarge(limit) => write!(f, "it is larger than the {limit} bytes allowed"),
            Refused::BadName => write!(
                f,
                "its name is not a plain file name inside the output's folder"
            ),
            Refused::Io(e) => write!(f, "{e}"),
        }
    }
}

impl From<std::io::Error> for Refused {
    fn from(e: std::io::Error) -> Self {
        Refused::Io(e)
    }
}

/// The folder of `file` (`.` for a bare name).
pub(crate) fn folder_of(file: &Path) -> &Path {
    match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// `reference` (a relative path as the model writes it, percent-decoded; `\` taken for `/`)
/// resolved against `base` (a folder inside `root`, e.g. a material library's) and checked to
/// lie inside `root` (the model's folder) before and after following links. Returns the
/// canonical path of an existing file or folder.
pub(crate) fn resolve(root: &Path, base: &Path, reference: &str) -> Result<PathBuf, Refused> {
    let reference = reference.replace('\\', "/");
    // `file:`, `http:` and the like; a one-letter scheme is a drive letter.
    if let Some((scheme, _)) = reference.split_once(':')
        && !scheme.contains('/')
    {
        return Err(if scheme.len() == 1 {
            Refused::Absolute
        } else {
            Refused::Remote
        });
    }
    let relative = Path::new(&reference);
    if reference_scope() == ReferenceScope::Anywhere {
        // Opted in: wherever it points, as long as it exists (regular files and the caps are
        // checked by the readers).
        return Ok(base.join(relative).canonicalize()?);
    }
    if relative.has_root()
        || relative
            .components()
            .any(|c| matches!(c, Component::Prefix(_) | Component::RootDir))
    {
        return Err(Refused::Absolute);
    }
    let root = root.canonicalize()?;
    let base = base.canonicalize()?;
    if !base.starts_with(&root) {
        return Err(Refused::Escapes);
    }
    // Lexical normalisation inside the root: `..` may climb only as far as the root.
    let mut parts: Vec<std::ffi::OsString> = base
        .strip_prefix(&root)
        .map_err(|_| Refused::Escapes)?
        .components()
        .map(|c| c.as_os_str().to_os_string())
        .collect();
    for c in relative.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if parts.pop().is_none() {
                    return Err(Refused::Escapes);
                }
            }
            Component::Normal(name) => parts.push(name.to_os_string()),
            Component::Prefix(_) | Component::RootDir => return Err(Refused::Absolute),
        }
    }
    let mut joined = root.clone();
    joined.extend(&parts);
    let canonical = joined.canonicalize()?;
    if !canonical.starts_with(&root) {
        return Err(Refused::LinkOutside);
    }
    Ok(canonical)
}

/// The bytes of the regular file `path`, at most `limit` of them: more is [`Refused::TooLarge`].
pub(crate) fn read_limited(path: &Path, limit: u64) -> Result<Vec<u8>, Refused> {
    let (bytes, more) = read_regular(path, limit)?;
    if more {
        return Err(Refused::TooLarge(limit));
    }
    Ok(bytes)
}

/// The first `count` bytes of the regular file `path` (fewer when the file is shorter), never
/// more: what a glTF buffer declares.
pub(crate) fn read_prefix(path: &Path, count: u64) -> Result<Vec<u8>, Refused> {
    read_regular(path, count).map(|(bytes, _)| bytes)
}

/// The file `reference` names inside `root` (see [`resolve`]), read with [`read_limited`]:
/// its canonical path and bytes.
pub(crate) fn read_contained(
    root: &Path,
    base: &Path,
    reference: &str,
    limit: u64,
) -> Result<(PathBuf, Vec<u8>), Refused> {
    let path = resolve(root, base, reference)?;
    let bytes = read_limited(&path, limit)?;
    Ok((path, bytes))
}

/// Reads at most `limit` bytes of `path` when it is a regular file (checked before opening, so
/// a FIFO is never opened, and again on the open handle, so a swap in between is caught), and
/// whether the file holds more.
fn read_regular(path: &Path, limit: u64) -> Result<(Vec<u8>, bool), Refused> {
    if !std::fs::metadata(path)?.is_file() {
        return Err(Refused::NotRegular);
    }
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // A FIFO put in the file's place after the check must not block the open.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(Refused::NotRegular);
    }
    let capacity = meta.len().min(limit).min(1 << 30) as usize;
    let mut bytes = Vec::with_capacity(capacity);
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    let more = bytes.len() as u64 > limit;
    bytes.truncate(limit.min(bytes.len() as u64) as usize);
    Ok((bytes, more))
}

/// Where a side file named `name` (relative, `/`-separated, from the tool or carried from the
/// input) is written beside an output in `out_dir`: inside `out_dir` after links, its folders
/// created, never through a symbolic link. Refused: empty names, absolute names, `..`, hidden
/// components (`.name`), control characters and `\`.
pub(crate) fn side_file(out_dir: &Path, name: &Path) -> Result<PathBuf, Refused> {
    let mut parts = Vec::new();
    for c in name.components() {
        match c {
            Component::Normal(part) => {
                let text = part.to_str().ok_or(Refused::BadName)?;
                if text.starts_with('.')
                    || text.chars().any(|ch| ch.is_control() || ch == '\\')
                    || text.len() > 255
                {
                    return Err(Refused::BadName);
                }
                parts.push(part);
            }
            Component::CurDir => {}
            _ => return Err(Refused::BadName),
        }
    }
    let Some((file, folders)) = parts.split_last() else {
        return Err(Refused::BadName);
    };
    let root = out_dir.canonicalize()?;
    let mut dir = root.clone();
    for folder in folders {
        dir.push(folder);
        match std::fs::symlink_metadata(&dir) {
            Ok(m) if m.is_dir() => {}
            Ok(_) => return Err(Refused::LinkOutside),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => std::fs::create_dir(&dir)?,
            Err(e) => return Err(Refused::Io(e)),
        }
    }
    let target = dir.join(file);
    if std::fs::symlink_metadata(&target).is_ok_and(|m| m.file_type().is_symlink()) {
        return Err(Refused::LinkOutside);
    }
    Ok(target)
}

/// Writes `bytes` as the side file `name` of an output in `out_dir` ([`side_file`]'s rule),
/// atomically, replacing a file of that name: for a file whose name the tool chose for this
/// output (its material library, the images it embeds). A file copied from the input goes
/// through [`copy_beside`].
pub(crate) fn write_beside(out_dir: &Path, name: &Path, bytes: &[u8]) -> Result<(), Refused> {
    let target = side_file(out_dir, name)?;
    super::write_atomic(&target, bytes)
        .map_err(|e| Refused::Io(std::io::Error::other(e.to_string())))
}

/// What stands at a side file's place beside an output ([`beside`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Beside {
    /// Nothing.
    Absent,
    /// A regular file holding exactly the bytes to be written.
    Same,
    /// Anything else (another file, a folder, a FIFO): never read, never replaced.
    Other,
}

/// What stands at `target` compared with `bytes`: a file is read only when it is a regular file
/// of the same length (a FIFO or a large unrelated file is never opened).
pub(crate) fn beside(target: &Path, bytes: &[u8]) -> std::io::Result<Beside> {
    match std::fs::symlink_metadata(target) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Beside::Absent),
        Err(e) => Err(e),
        Ok(m)
            if m.is_file()
                && m.len() == bytes.len() as u64
                && std::fs::read(target).is_ok_and(|b| b == bytes) =>
        {
            Ok(Beside::Same)
        }
        Ok(_) => Ok(Beside::Other),
    }
}

/// Copies `bytes` (a file the input names, e.g. a texture) beside an output in `out_dir` under
/// `name`, or, when a file of that name is already there with other bytes, under a new name in
/// the same folder, `<stem>-<file name>` (then `<stem>-2-<file name>`, ...): an output never
/// points at someone else's file, and a file already there is never replaced. A file with the
/// same bytes is left as it is (an earlier run's copy). Returns the name the output must use.
pub(crate) fn copy_beside(
    out_dir: &Path,
    name: &Path,
    bytes: &[u8],
    stem: &str,
) -> Result<PathBuf, Refused> {
    let file = name.file_name().ok_or(Refused::BadName)?.to_string_lossy();
    for k in 0..100u32 {
        let candidate = match k {
            0 => name.to_path_buf(),
            1 => name.with_file_name(format!("{stem}-{file}")),
            _ => name.with_file_name(format!("{stem}-{k}-{file}")),
        };
        let target = side_file(out_dir, &candidate)?;
        match beside(&target, bytes)? {
            Beside::Absent => {
                super::write_atomic(&target, bytes)
                    .map_err(|e| Refused::Io(std::io::Error::other(e.to_string())))?;
                return Ok(candidate);
            }
            Beside::Same => return Ok(candidate),
            Beside::Other => {}
        }
    }
    Err(Refused::Io(std::io::Error::other(format!(
        "100 files named like {} with other contents are already beside the output",
        name.display()
    ))))
}

/// The file extension for an image of media type `mime`, from a fixed list (`bin` for anything
/// else): a generated name never takes characters from the file.
pub(crate) fn image_extension(mime: &str) -> &'static str {
    match mime.to_ascii_lowercase().as_str() {
        "image/png" => "png",
        "image/jpeg" | "image/jpg" => "jpg",
        "image/webp" => "webp",
        "image/ktx2" => "ktx2",
        "image/vnd-ms.dds" | "image/vnd.ms-dds" => "dds",
        "image/gif" => "gif",
        "image/bmp" => "bmp",
        _ => "bin",
    }
}

/// `name` as one line of a text format (OBJ `usemtl`, MTL `newmtl`): control characters
/// (line breaks among them) become `_`, and an empty name `unnamed`.
pub(crate) fn one_line_name(name: &str) -> std::borrow::Cow<'_, str> {
    if name.trim().is_empty() {
        return "unnamed".into();
    }
    if name.chars().any(char::is_control) {
        return name
            .chars()
            .map(|c| if c.is_control() { '_' } else { c })
            .collect::<String>()
            .into();
    }
    name.into()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree() -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let model = dir.path().join("model");
        std::fs::create_dir_all(model.join("tex")).unwrap();
        std::fs::write(model.join("tex/a.png"), b"inside").unwrap();
        std::fs::write(dir.path().join("secret.txt"), b"CANARY").unwrap();
        (dir, model)
    }

    #[test]
    fn resolves_inside_and_refuses_escapes() {
        let (dir, model) = tree();
        let read = |r: &str| read_contained(&model, &model, r, 100).map(|(_, b)| b);
        assert_eq!(read("tex/a.png").unwrap(), b"inside");
        assert_eq!(read("tex/../tex/./a.png").unwrap(), b"inside");
        assert_eq!(read("tex\\a.png").unwrap(), b"inside");
        assert!(matches!(read("../secret.txt"), Err(Refused::Escapes)));
        assert!(matches!(
            read("tex/../../secret.txt"),
            Err(Refused::Escapes)
        ));
        let absolute = dir.path().join("secret.txt");
        assert!(matches!(
            read(absolute.to_str().unwrap()),
            Err(Refused::Absolute)
        ));
        assert!(matches!(read("/etc/passwd"), Err(Refused::Absolute)));
        assert!(matches!(read("file:///etc/passwd"), Err(Refused::Remote)));
        // From a library's folder inside the model's folder, `..` back to the model is fine.
        let (_, b) = read_contained(&model, &model.join("tex"), "../tex/a.png", 100).unwrap();
        assert_eq!(b, b"inside");
    }

    #[cfg(unix)]
    #[test]
    fn refuses_links_out_fifos_devices_and_oversize() {
        let (dir, model) = tree();
        std::os::unix::fs::symlink(dir.path().join("secret.txt"), model.join("link.png")).unwrap();
        std::os::unix::fs::symlink(dir.path(), model.join("up")).unwrap();
        let read = |r: &str| read_contained(&model, &model, r, 100).map(|(_, b)| b);
        assert!(matches!(read("link.png"), Err(Refused::LinkOutside)));
        assert!(matches!(read("up/secret.txt"), Err(Refused::LinkOutside)));
        assert!(matches!(
            read_limited(Path::new("/dev/zero"), 100),
            Err(Refused::NotRegular)
        ));
        let fifo = model.join("fifo");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        assert!(matches!(read("fifo"), Err(Refused::NotRegular)));
        assert!(matches!(read("tex"), Err(Refused::NotRegular)));
        assert!(matches!(
            read_contained(&model, &model, "tex/a.png", 3),
            Err(Refused::TooLarge(3))
        ));
        assert_eq!(read_prefix(&model.join("tex/a.png"), 3).unwrap(), b"ins");
    }

    #[test]
    fn side_files_stay_in_the_output_folder() {
        let (dir, model) = tree();
        let ok = side_file(&model, Path::new("sub/x.png")).unwrap();
        assert!(ok.starts_with(model.canonicalize().unwrap()));
        assert!(model.join("sub").is_dir());
        for bad in [
            "../x.png",
            "/etc/x",
            "a/../../x",
            ".bashrc",
            "a\nb.png",
            "",
            "x/.hidden/y",
        ] {
            assert!(
                matches!(side_file(&model, Path::new(bad)), Err(Refused::BadName)),
                "{bad:?} accepted"
            );
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(dir.path(), model.join("out")).unwrap();
            assert!(matches!(
                side_file(&model, Path::new("out/secret.txt")),
                Err(Refused::LinkOutside)
            ));
            std::os::unix::fs::symlink(dir.path().join("secret.txt"), model.join("l.png")).unwrap();
            assert!(matches!(
                side_file(&model, Path::new("l.png")),
                Err(Refused::LinkOutside)
            ));
        }
    }

    #[test]
    fn names_and_extensions() {
        assert_eq!(image_extension("image/x/../../etc"), "bin");
        assert_eq!(image_extension("IMAGE/PNG"), "png");
        assert_eq!(
            one_line_name("evil\nmtllib /etc/passwd"),
            "evil_mtllib /etc/passwd"
        );
        assert_eq!(one_line_name("  "), "unnamed");
        assert_eq!(one_line_name("wood"), "wood");
    }
}

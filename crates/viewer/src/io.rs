//! File handling off the UI thread: file dialogs (native through rfd, or the in-app `egui_file`
//! picker where no native dialog exists), background mesh loading, mesh export and PNG
//! screenshots.

use crate::engine;
use crate::error::{Result, ViewerError};
use crate::jobs::Job;
use mesh::TriMesh;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What a file dialog was opened for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DialogPurpose {
    /// Open a mesh.
    OpenMesh,
    /// Save the GNG3D reconstruction.
    ExportGng,
    /// Save the QEM result.
    ExportQem,
    /// Save the checkpoint table.
    ExportCsv,
    /// Save a PNG screenshot of the window.
    Screenshot,
}

/// A native dialog that answers "nothing chosen" faster than this never showed a window: rfd's
/// portal and zenity backends both failed (no xdg-desktop-portal, no zenity). A person cannot
/// cancel a dialog that quickly.
const NATIVE_DIALOG_MIN_SECONDS: f64 = 0.4;

/// Environment variable that forces the in-app picker (`VIEWER_FILE_DIALOG=builtin`).
pub const FILE_DIALOG_ENV: &str = "VIEWER_FILE_DIALOG";

/// File extensions a dialog for `purpose` offers.
fn extensions(purpose: DialogPurpose) -> &'static [&'static str] {
    match purpose {
        DialogPurpose::OpenMesh | DialogPurpose::ExportGng | DialogPurpose::ExportQem => {
            &["obj", "ply", "stl", "gltf", "glb"]
        }
        DialogPurpose::ExportCsv => &["csv"],
        DialogPurpose::Screenshot => &["png"],
    }
}

/// At most one file dialog at a time: native ones run on their own thread so frames keep
/// coming; without a native dialog the in-app picker takes over (and says so once).
pub struct Dialogs {
    native: Option<(
        DialogPurpose,
        String,
        std::time::Instant,
        Job<Option<PathBuf>>,
    )>,
    builtin: Option<(DialogPurpose, egui_file::FileDialog)>,
    native_unavailable: bool,
    notice: Option<String>,
}

impl Default for Dialogs {
    fn default() -> Self {
        Dialogs {
            native: None,
            builtin: None,
            native_unavailable: std::env::var(FILE_DIALOG_ENV).is_ok_and(|v| v == "builtin"),
            notice: None,
        }
    }
}

impl Dialogs {
    /// Whether a dialog is open.
    pub fn is_open(&self) -> bool {
        self.native.is_some() || self.builtin.is_some()
    }

    /// Whether the in-app picker is open.
    pub fn builtin_open(&self) -> bool {
        self.builtin.is_some()
    }

    /// Open a dialog for `purpose` (ignored while another one is open).
    pub fn open(&mut self, purpose: DialogPurpose, suggested_name: &str) {
        if self.is_open() {
            return;
        }
        if self.native_unavailable {
            self.open_builtin(purpose, suggested_name);
            return;
        }
        let name = suggested_name.to_string();
        let job_name = name.clone();
        let job = Job::spawn("file-dialog", None, move || {
            let dialog = rfd::FileDialog::new();
            match purpose {
                DialogPurpose::OpenMesh => {
                    dialog.add_filter("meshes", extensions(purpose)).pick_file()
                }
                DialogPurpose::ExportGng | DialogPurpose::ExportQem => dialog
                    .add_filter("OBJ", &["obj"])
                    .add_filter("PLY", &["ply"])
                    .add_filter("STL", &["stl"])
                    .set_file_name(job_name)
                    .save_file(),
                DialogPurpose::ExportCsv => dialog
                    .add_filter("CSV", &["csv"])
                    .set_file_name(job_name)
                    .save_file(),
                DialogPurpose::Screenshot => dialog
                    .add_filter("PNG", &["png"])
                    .set_file_name(job_name)
                    .save_file(),
            }
        });
        self.native = Some((purpose, name, std::time::Instant::now(), job));
    }

    fn open_builtin(&mut self, purpose: DialogPurpose, suggested_name: &str) {
        let wanted = extensions(purpose);
        let filter: egui_file::Filter<PathBuf> = Box::new(move |path: &Path| {
            path.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| wanted.iter().any(|w| w.eq_ignore_ascii_case(e)))
        });
        let mut dialog = match purpose {
            DialogPurpose::OpenMesh => egui_file::FileDialog::open_file(),
            _ => egui_file::FileDialog::save_file().default_filename(suggested_name),
        }
        .show_files_filter(filter)
        .default_size([520.0, 360.0]);
        dialog.open();
        self.builtin = Some((purpose, dialog));
    }

    /// A one-off message for the status line (e.g. that the in-app picker replaced a missing
    /// native dialog).
    pub fn take_notice(&mut self) -> Option<String> {
        self.notice.take()
    }

    /// Draw the in-app picker, if open.
    pub fn show_fallback(&mut self, ctx: &egui::Context) {
        if let Some((_, dialog)) = self.builtin.as_mut() {
            dialog.show(ctx);
        }
    }

    /// The dialog's answer once it is closed: `Some((purpose, None))` when cancelled.
    pub fn poll(&mut self) -> Option<(DialogPurpose, Option<PathBuf>)> {
        if let Some((purpose, dialog)) = &self.builtin {
            let purpose = *purpose;
            return match dialog.state() {
                egui_file::State::Open => None,
                egui_file::State::Selected => {
                    let path = dialog.path().map(Path::to_path_buf);
                    self.builtin = None;
                    Some((purpose, path))
                }
                egui_file::State::Closed | egui_file::State::Cancelled => {
                    self.builtin = None;
                    Some((purpose, None))
                }
            };
        }
        let (purpose, name, started, job) = self.native.as_ref()?;
        let answer = job.poll()?.ok().flatten();
        let (purpose, name, quick) = (
            *purpose,
            name.clone(),
            started.elapsed().as_secs_f64() < NATIVE_DIALOG_MIN_SECONDS,
        );
        self.native = None;
        if answer.is_none() && quick {
            self.native_unavailable = true;
            self.notice = Some(
                "no native file dialog (it needs xdg-desktop-portal or zenity): using the \
                 built-in file picker"
                    .into(),
            );
            self.open_builtin(purpose, &name);
            return None;
        }
        Some((purpose, answer))
    }
}

/// A mesh loaded in the background.
pub struct LoadedModel {
    /// Display name (file name).
    pub name: String,
    /// Where it came from.
    pub path: PathBuf,
    /// The cleaned mesh the algorithms work on.
    pub mesh: Arc<TriMesh>,
    /// Loader and cleaning warnings.
    pub warnings: Vec<String>,
    /// The mesh's normals, texture coordinates and colours (`None` without any).
    pub attributes: Option<Arc<mesh::attributes::Attributes>>,
    /// Its materials and origin ([`engine::Loaded::place`]).
    pub place: Arc<mesh::Model>,
    /// Its base-colour texture, decoded ([`engine::Loaded::texture`]).
    pub texture: Option<Arc<metrics::Texture>>,
}

/// Load and clean `path` on a new thread.
pub fn spawn_load(path: PathBuf, ctx: Option<egui::Context>) -> Job<Result<LoadedModel>> {
    Job::spawn("load-mesh", ctx, move || {
        engine::load_mesh(&path).map(|loaded| LoadedModel {
            name: path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| path.display().to_string()),
            path: path.clone(),
            mesh: Arc::new(loaded.mesh),
            warnings: loaded.warnings,
            attributes: loaded.attributes.map(Arc::new),
            place: Arc::new(loaded.place),
            texture: loaded.texture.map(Arc::new),
        })
    })
}

/// Write an egui screenshot as PNG.
pub fn save_png(image: &egui::ColorImage, path: &Path) -> Result<()> {
    let fail = |message: String| ViewerError::Save {
        path: path.to_path_buf(),
        message,
    };
    let [w, h] = image.size;
    let mut bytes = Vec::with_capacity(w * h * 4);
    for c in &image.pixels {
        bytes.extend_from_slice(&c.to_srgba_unmultiplied());
    }
    let buffer = image::RgbaImage::from_raw(w as u32, h as u32, bytes)
        .ok_or_else(|| fail("screenshot has an inconsistent size".into()))?;
    buffer
        .save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| fail(e.to_string()))
}

/// Fraction of pixels in `image` that differ from its most common colour (0 for a blank image).
pub fn non_background_fraction(image: &image::RgbaImage) -> f64 {
    let mut counts = std::collections::HashMap::new();
    for p in image.pixels() {
        *counts.entry(p.0).or_insert(0usize) += 1;
    }
    let total = image.width() as usize * image.height() as usize;
    let most = counts.values().copied().max().unwrap_or(0);
    if total == 0 {
        0.0
    } else {
        (total - most) as f64 / total as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_round_trip_keeps_pixels() {
        let dir = std::env::temp_dir().join(format!("viewer-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("shot.png");
        let mut image = egui::ColorImage::filled([4, 3], egui::Color32::from_rgb(10, 20, 30));
        image.pixels[5] = egui::Color32::from_rgb(200, 100, 50);
        save_png(&image, &path).unwrap();
        let back = image::open(&path).unwrap().to_rgba8();
        assert_eq!((back.width(), back.height()), (4, 3));
        assert_eq!(back.get_pixel(1, 1).0, [200, 100, 50, 255]);
        assert_eq!(back.get_pixel(0, 0).0, [10, 20, 30, 255]);
        assert!((non_background_fraction(&back) - 1.0 / 12.0).abs() < 1e-12);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_screenshot_path_is_an_error_not_a_panic() {
        let image = egui::ColorImage::filled([2, 2], egui::Color32::WHITE);
        let err = save_png(&image, Path::new("/nonexistent-dir/x/shot.png"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("/nonexistent-dir/x/shot.png"), "{err}");
    }

    /// The in-app picker (egui_file 0.29) labels its title, buttons and entries with these
    /// characters; each must have a glyph in the fonts the viewer bundles, not the missing-glyph
    /// box (issue 37).
    #[test]
    fn the_fallback_pickers_icons_have_glyphs() {
        let ctx = egui::Context::default();
        let mut output = ctx.run_ui(egui::RawInput::default(), |_| {});
        output.textures_delta.clear();
        let missing: Vec<char> = "📁📂💾⬆⟲🗀🗋"
            .chars()
            .filter(|&c| {
                !ctx.fonts_mut(|fonts| fonts.has_glyph(&egui::FontId::proportional(14.0), c))
            })
            .collect();
        assert!(missing.is_empty(), "no glyph for {missing:?}");
    }
}

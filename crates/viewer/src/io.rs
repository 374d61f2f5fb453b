//! File handling off the UI thread: native file dialogs (rfd), background mesh loading, mesh
//! export and PNG screenshots.

use crate::engine;
use mesh::TriMesh;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::mpsc::{self, Receiver, TryRecvError};

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

/// At most one native dialog at a time, run on its own thread so frames keep coming.
#[derive(Default)]
pub struct Dialogs {
    pending: Option<(DialogPurpose, Receiver<Option<PathBuf>>)>,
}

impl Dialogs {
    /// Whether a dialog is open.
    pub fn is_open(&self) -> bool {
        self.pending.is_some()
    }

    /// Open a dialog for `purpose` (ignored while another one is open).
    pub fn open(&mut self, purpose: DialogPurpose, suggested_name: &str) {
        if self.pending.is_some() {
            return;
        }
        let (tx, rx) = mpsc::channel();
        let name = suggested_name.to_string();
        let spawned = std::thread::Builder::new()
            .name("file-dialog".into())
            .spawn(move || {
                let dialog = rfd::FileDialog::new();
                let path = match purpose {
                    DialogPurpose::OpenMesh => dialog
                        .add_filter("meshes", &["obj", "ply", "stl"])
                        .pick_file(),
                    DialogPurpose::ExportGng | DialogPurpose::ExportQem => dialog
                        .add_filter("OBJ", &["obj"])
                        .add_filter("PLY", &["ply"])
                        .add_filter("STL", &["stl"])
                        .set_file_name(name)
                        .save_file(),
                    DialogPurpose::ExportCsv => dialog
                        .add_filter("CSV", &["csv"])
                        .set_file_name(name)
                        .save_file(),
                    DialogPurpose::Screenshot => dialog
                        .add_filter("PNG", &["png"])
                        .set_file_name(name)
                        .save_file(),
                };
                let _ = tx.send(path);
            });
        if spawned.is_ok() {
            self.pending = Some((purpose, rx));
        }
    }

    /// The dialog's answer once it is closed: `Some((purpose, None))` when cancelled.
    pub fn poll(&mut self) -> Option<(DialogPurpose, Option<PathBuf>)> {
        let (purpose, rx) = self.pending.as_ref()?;
        match rx.try_recv() {
            Ok(path) => {
                let purpose = *purpose;
                self.pending = None;
                Some((purpose, path))
            }
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                let purpose = *purpose;
                self.pending = None;
                Some((purpose, None))
            }
        }
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
}

/// Load and clean `path` on a new thread; poll the receiver.
pub fn spawn_load(
    path: PathBuf,
    ctx: Option<egui::Context>,
) -> Receiver<Result<LoadedModel, String>> {
    let (tx, rx) = mpsc::channel();
    let _ = std::thread::Builder::new()
        .name("load-mesh".into())
        .spawn(move || {
            let result = engine::load_mesh(&path).map(|loaded| LoadedModel {
                name: path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|| path.display().to_string()),
                path: path.clone(),
                mesh: Arc::new(loaded.mesh),
                warnings: loaded.warnings,
            });
            let _ = tx.send(result);
            if let Some(ctx) = ctx {
                ctx.request_repaint();
            }
        });
    rx
}

/// Save `mesh` to `path` (format by extension).
pub fn export_mesh(mesh: &TriMesh, path: &Path) -> Result<(), String> {
    engine::save_mesh(mesh, path)
}

/// Write an egui screenshot as PNG.
pub fn save_png(image: &egui::ColorImage, path: &Path) -> Result<(), String> {
    let [w, h] = image.size;
    let mut bytes = Vec::with_capacity(w * h * 4);
    for c in &image.pixels {
        bytes.extend_from_slice(&c.to_srgba_unmultiplied());
    }
    let buffer = image::RgbaImage::from_raw(w as u32, h as u32, bytes)
        .ok_or_else(|| format!("{}: screenshot has an inconsistent size", path.display()))?;
    buffer
        .save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| format!("{}: {e}", path.display()))
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
        let err = save_png(&image, Path::new("/nonexistent-dir/x/shot.png")).unwrap_err();
        assert!(err.contains("/nonexistent-dir/x/shot.png"), "{err}");
    }
}

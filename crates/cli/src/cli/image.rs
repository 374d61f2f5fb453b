//! The image-space error's options and output, one implementation for `gng3d metrics` and
//! `gng3d compare`: the flags ([`ImageErrorArgs`], flattened into both), their validation
//! (`metrics::ImageErrorParams::validate`, errors naming the flag), the base-colour texture of
//! a mesh's materials, the PNGs of `--image-out` and the text lines.

use anyhow::Context;
use clap::Args;
use mesh::attributes::Materials;
use metrics::{ImageError, ImageErrorParams, Texture, ViewImages};
use std::path::Path;
use std::path::PathBuf;

/// The `--image-*` flags.
#[derive(Debug, Args)]
pub struct ImageErrorArgs {
    /// Also measure the image-space error: the original and the simplified mesh (`compare`:
    /// each method's output) rendered headlessly (CPU) from 14 fixed views (6 axes, 8 diagonals) framing the original, with
    /// the materials' base-colour texture at UV0 (PNG; the original's for a simplified mesh
    /// without one), else a checker on UV0 (squares of 1/8 UV), else the vertex colours, else
    /// white, lit by a headlight; RMSE and mean absolute error of RGB (0-1), PSNR (dB), the
    /// share of pixels off and of silhouette mismatch, over the pixels covered in either image.
    #[arg(long)]
    pub image_error: bool,
    /// Side of the rendered square images, pixels (16 to 4096; default 256).
    #[arg(long, requires = "image_error", value_parser = image_size)]
    pub image_size: Option<u32>,
    /// A pixel counts as off when its largest RGB channel (0-1) differs by more than this
    /// (0 to 1; default 0.1, about 26 of 255 levels).
    #[arg(long, requires = "image_error")]
    pub image_threshold: Option<f64>,
    /// Light meshes without normals with their face normals (faceted) instead of smooth
    /// area-weighted vertex normals.
    #[arg(long, requires = "image_error")]
    pub image_flat: bool,
    /// Folder (created if missing) for one PNG per view: original, simplified, and their
    /// difference (red: covered in one image only; grey: largest channel's difference × 4).
    /// `compare` writes each method's in qem/ and gng/ under it.
    #[arg(long, requires = "image_error")]
    pub image_out: Option<PathBuf>,
}

/// `--image-size` as a number of pixels; a value that is not one (e.g. `-1`) is refused with
/// the range (`ImageErrorParams::validate` checks it), not clap's range of `u32`.
fn image_size(s: &str) -> Result<u32, String> {
    s.trim().parse().map_err(|_| {
        format!(
            "{s} is not a side in pixels in 16 to {}",
            metrics::MAX_IMAGE_SIZE
        )
    })
}

/// The flag of an `ImageErrorParams` field, for errors (`None`: a field without a flag).
fn flag(field: &str) -> Option<&'static str> {
    match field {
        "size" => Some("--image-size"),
        "threshold" => Some("--image-threshold"),
        _ => None,
    }
}

impl ImageErrorArgs {
    /// The parameters with `--image-error` (checked by `ImageErrorParams::validate`, an error
    /// naming the flag), `None` without it.
    pub fn params(&self) -> anyhow::Result<Option<ImageErrorParams>> {
        if !self.image_error {
            return Ok(None);
        }
        let defaults = ImageErrorParams::default();
        let params = ImageErrorParams {
            size: self.image_size.unwrap_or(defaults.size),
            threshold: self.image_threshold.unwrap_or(defaults.threshold),
            flat_shading: self.image_flat,
            ..defaults
        };
        params.validate().map_err(|e| match &e {
            metrics::MetricsError::Parameter { name, message } if flag(name).is_some() => {
                anyhow::anyhow!("{}: {message}", flag(name).unwrap_or_default())
            }
            _ => e.into(),
        })?;
        Ok(Some(params))
    }

    /// Creates the `--image-out` folder and, under it, `subfolders` (for `compare`), and checks
    /// that they take files, before any long work.
    pub fn prepare_out(&self, subfolders: &[&str]) -> anyhow::Result<()> {
        if let Some(dir) = &self.image_out {
            super::prepare_output_folder(dir)?;
            for sub in subfolders {
                super::prepare_output_folder(&dir.join(sub))?;
            }
        }
        Ok(())
    }
}

/// The base-colour texture of the first material of `materials` that has one, decoded
/// ([`Texture::load`]; `None` without one); a texture that cannot be read or decoded is an
/// error naming its file and material.
pub fn texture(materials: Option<&Materials>) -> anyhow::Result<Option<Texture>> {
    let Some(found) = materials.and_then(mesh::io::base_color_texture) else {
        return Ok(None);
    };
    let texture = Texture::load(&found)
        .with_context(|| format!("the texture of material {}", found.material))?;
    Ok(Some(texture))
}

/// Writes one PNG per view into `dir` (`view<name>.png`: original, simplified, difference).
pub fn write_views(dir: &Path, views: &[ViewImages]) -> anyhow::Result<()> {
    for view in views {
        super::write_atomic(&dir.join(format!("view{}.png", view.view)), &view.png()?)?;
    }
    Ok(())
}

/// A PSNR for text: infinite for identical images.
fn psnr(db: f64) -> String {
    if db.is_finite() {
        format!("{db:.1} dB")
    } else {
        "∞ (identical)".to_string()
    }
}

/// How the images were made, in words: views, size, field of view, shading, normals, time.
pub fn setup_in_words(r: &ImageError) -> String {
    let shading = match (&r.texture, r.shading) {
        (Some(file), _) => format!("texture {file}"),
        (None, metrics::Shading::Checker) => "checker on UV0".to_string(),
        (None, metrics::Shading::Colors) => "vertex colours".to_string(),
        (None, _) => "white".to_string(),
    };
    format!(
        "{} views of {}² px, {:.0}° field of view, shading: {shading}, {}",
        r.views.len(),
        r.size,
        r.fov_degrees,
        if r.flat_shading {
            "face normals where a mesh has none"
        } else {
            "vertex normals where a mesh has none"
        },
    )
}

/// The image-space error's lines of `gng3d metrics`.
pub fn print(r: &ImageError, out: Option<&Path>) -> anyhow::Result<()> {
    outln!(
        "image error           {} ({:.3} s)",
        setup_in_words(r),
        r.seconds
    );
    let o = &r.overall;
    outln!(
        "  all views           RMSE {:.4}  mean abs {:.4}  (RGB 0-1)  PSNR {}  {:.2} % of pixels off by > {}  silhouette mismatch {:.2} %  ({} pixels covered in either)",
        o.rmse,
        o.mean_abs,
        psnr(o.psnr_db),
        100.0 * o.over_threshold,
        r.threshold,
        100.0 * o.coverage_mismatch,
        o.pixels
    );
    if let Some(worst) = r
        .views
        .iter()
        .max_by(|a, b| a.stats.rmse.total_cmp(&b.stats.rmse))
    {
        outln!(
            "  worst view          {}: RMSE {:.4}  PSNR {}  silhouette mismatch {:.2} %",
            worst.view,
            worst.stats.rmse,
            psnr(worst.stats.psnr_db),
            100.0 * worst.stats.coverage_mismatch
        );
    }
    if let Some(dir) = out {
        outln!(
            "  images              {}/view*.png (original | simplified | difference)",
            dir.display()
        );
    }
    Ok(())
}

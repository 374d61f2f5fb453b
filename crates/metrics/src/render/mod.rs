//! Image-space error ([`image_error`]): both meshes rendered from the same fixed views with a
//! small deterministic CPU rasterizer, and the pictures compared pixel by pixel — what a
//! player would see of the simplification, texture and silhouette included.
//!
//! **Views**: [`VIEWS`], the 6 axis directions and the 8 cube diagonals, each looking at the
//! centre of the original's bounding box from a perspective camera (vertical and horizontal
//! field of view [`ImageErrorParams::fov_degrees`], square images of
//! [`ImageErrorParams::size`] pixels) at the distance where the sphere around that box (radius
//! half its diagonal) just fills the image. The cameras depend on the original only, so both
//! meshes are seen through identical ones.
//!
//! **Rasterizer**: one sample at each pixel centre, a z-buffer on 1/w, triangles clipped
//! against a near plane, both sides of every triangle drawn (meshes need not be consistently
//! oriented), perspective-correct interpolation of the corners' wedge values.
//!
//! **Shading**, chosen once from the original ([`Shading`]): the texture, sampled bilinearly at
//! UV0 with wrapping, when the original has one and UV0 (each mesh its own texture, the
//! simplified mesh the original's when it has none); else a procedural checker on
//! UV0 ([`CHECKER_SQUARE`]); else the vertex colours (linear, shown as sRGB); else white. A mesh
//! without the attribute the shading needs is drawn white. The colour is lit by a Lambert term
//! with a headlight plus [`AMBIENT`], on the mesh's interpolated normals when it has them, else
//! on its area-weighted vertex normals (or its face normals with
//! [`ImageErrorParams::flat_shading`]). Background pixels are black. One texture covers the
//! whole mesh (a mesh with several textured materials is drawn with the one given), and colour
//! factors (OBJ `Kd`, glTF `baseColorFactor`) and alpha are not applied: both meshes share their
//! material, so these would scale both pictures alike.
//!
//! **Error**: per view and over all views, on the pixels covered in either image (a pixel
//! covered in one image only is an error, a silhouette change): RMSE and mean absolute error of
//! RGB (0-1), PSNR in dB, the share of pixels whose largest channel differs by more than
//! [`ImageErrorParams::threshold`], and the share covered in one image only.
//!
//! This module holds the parameters, the report and the comparison of the pictures; the
//! views are drawn in [`raster`], coloured from [`texture`]'s inputs.

mod raster;
mod texture;

use raster::{Camera, Rendering, Scene};
pub use texture::{Shading, Texture};

use crate::MetricsError;
use glam::Vec3;
use mesh::TriMesh;
use mesh::attributes::Attributes;
use mesh::cancel::Cancel;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Side of one square of the procedural checker, UV units: 8 × 8 squares on the unit UV square,
/// so the pattern repeats every 2 squares (a period of 1/4 UV). Fine enough to show a UV error
/// of a few percent of the texture, coarse enough not to alias at 256 pixels on a whole model.
pub const CHECKER_SQUARE: f32 = 1.0 / 8.0;
/// The checker's light and dark values (grey levels, 0-1): far enough apart that swapped
/// squares are an obvious error, neither black (the background) nor white (the untextured
/// fallback).
pub const CHECKER_VALUES: [f32; 2] = [0.9, 0.3];
/// Share of the light that does not depend on the normal: faces seen edge-on stay visible
/// (black is the background's colour).
pub const AMBIENT: f32 = 0.25;
/// Gain of the grey difference panel of [`ViewImages::png`]: a difference of 0.25 in the
/// largest channel is white, so small texture differences are visible.
pub const DIFFERENCE_GAIN: f32 = 4.0;

/// The fixed views: a name and the direction from the centre of the original's bounding box to
/// the camera (not normalised). The 6 axis views see each side of a CAD-like part head-on; the
/// 8 diagonals see the edges and corners between them, where silhouettes change most.
pub const VIEWS: [(&str, [f32; 3]); 14] = [
    ("+x", [1.0, 0.0, 0.0]),
    ("-x", [-1.0, 0.0, 0.0]),
    ("+y", [0.0, 1.0, 0.0]),
    ("-y", [0.0, -1.0, 0.0]),
    ("+z", [0.0, 0.0, 1.0]),
    ("-z", [0.0, 0.0, -1.0]),
    ("+x+y+z", [1.0, 1.0, 1.0]),
    ("+x+y-z", [1.0, 1.0, -1.0]),
    ("+x-y+z", [1.0, -1.0, 1.0]),
    ("+x-y-z", [1.0, -1.0, -1.0]),
    ("-x+y+z", [-1.0, 1.0, 1.0]),
    ("-x+y-z", [-1.0, 1.0, -1.0]),
    ("-x-y+z", [-1.0, -1.0, 1.0]),
    ("-x-y-z", [-1.0, -1.0, -1.0]),
];

/// Largest accepted [`ImageErrorParams::size`]: 14 views of 4096² pixels already hold about
/// 2 GB of buffers while they are rendered in parallel.
pub const MAX_IMAGE_SIZE: u32 = 4096;

/// Parameters of [`image_error`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImageErrorParams {
    /// Side of the square images, pixels. 16 to [`MAX_IMAGE_SIZE`]; default 256.
    pub size: u32,
    /// Field of view of the cameras (vertical = horizontal), degrees. Above 0 and at most 120;
    /// default 30 (a telephoto-like view: little perspective distortion, as a model is usually
    /// seen in a game).
    pub fov_degrees: f64,
    /// A pixel whose largest RGB channel differs by more than this (0-1) counts in
    /// [`ImageStats::over_threshold`]. 0 to 1; default 0.1 (about 26 of 255 levels: a visible
    /// change, above the texture's bilinear blur across a few pixels).
    pub threshold: f64,
    /// Light a mesh without normals with its face normals (faceted) instead of its
    /// area-weighted vertex normals. Default false: a renderer given a mesh without normals
    /// usually computes smooth ones, and with face normals the facets' lighting outweighs
    /// everything else at low vertex counts (docs/notes/attributes.md, "Image-space error").
    #[serde(default)]
    pub flat_shading: bool,
}

impl Default for ImageErrorParams {
    fn default() -> Self {
        ImageErrorParams {
            size: 256,
            fov_degrees: 30.0,
            threshold: 0.1,
            flat_shading: false,
        }
    }
}

impl ImageErrorParams {
    /// Checks the parameters (see the fields for the accepted ranges).
    pub fn validate(&self) -> Result<(), MetricsError> {
        if !(16..=MAX_IMAGE_SIZE).contains(&self.size) {
            return Err(MetricsError::Parameter {
                name: "size",
                message: format!(
                    "{} pixels is not in 16 to {MAX_IMAGE_SIZE} pixels",
                    self.size
                ),
            });
        }
        if !(self.fov_degrees > 0.0 && self.fov_degrees <= 120.0) {
            return Err(MetricsError::Parameter {
                name: "fov_degrees",
                message: format!(
                    "{} is not a field of view above 0 and at most 120 degrees",
                    self.fov_degrees
                ),
            });
        }
        if !(0.0..=1.0).contains(&self.threshold) {
            return Err(MetricsError::Parameter {
                name: "threshold",
                message: format!("{} is not a colour difference in 0 to 1", self.threshold),
            });
        }
        Ok(())
    }
}

/// Error statistics over a set of pixels (one view, or all views).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImageStats {
    /// Pixels compared: those covered in either image.
    pub pixels: usize,
    /// Pixels covered by the original.
    pub covered_original: usize,
    /// Pixels covered by the simplified mesh.
    pub covered_simplified: usize,
    /// Root mean square difference of the R, G and B values (0-1) over the pixels compared.
    pub rmse: f64,
    /// Mean absolute difference of the R, G and B values (0-1).
    pub mean_abs: f64,
    /// Peak signal-to-noise ratio, dB: 20 log10(1 / rmse); infinite (`null` in JSON) for
    /// identical images.
    #[serde(with = "psnr_json")]
    pub psnr_db: f64,
    /// Share (0-1) of the pixels compared whose largest channel differs by more than the
    /// threshold.
    pub over_threshold: f64,
    /// Share (0-1) of the pixels compared that are covered in one image only (a silhouette
    /// change).
    pub coverage_mismatch: f64,
}

/// JSON has no infinity: an infinite PSNR is written as `null` and read back as infinity.
mod psnr_json {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        if v.is_finite() {
            s.serialize_some(v)
        } else {
            s.serialize_none()
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}

/// One view's error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ViewError {
    /// The view's name in [`VIEWS`].
    pub view: String,
    /// Its statistics.
    pub stats: ImageStats,
}

/// The image-space error of a simplification (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImageError {
    /// Side of the images, pixels.
    pub size: u32,
    /// Field of view of the cameras, degrees.
    pub fov_degrees: f64,
    /// The threshold of [`ImageStats::over_threshold`] (0-1).
    pub threshold: f64,
    /// Whether meshes without normals were lit with face normals (else vertex normals).
    #[serde(default)]
    pub flat_shading: bool,
    /// What the colour was taken from.
    pub shading: Shading,
    /// The original's texture's source when the shading is [`Shading::Texture`].
    pub texture: Option<String>,
    /// All views' pixels together.
    pub overall: ImageStats,
    /// Each view, in the order of [`VIEWS`].
    pub views: Vec<ViewError>,
    /// Wall-clock time of rendering and comparing, seconds.
    pub seconds: f64,
}

/// One view's two renderings, for [`ViewImages::png`].
#[derive(Debug, Clone, PartialEq)]
pub struct ViewImages {
    /// The view's name in [`VIEWS`].
    pub view: String,
    /// Side of the images, pixels.
    pub size: u32,
    /// The original's colours (0-1), row by row from the top.
    pub original: Vec<[f32; 3]>,
    /// The simplified mesh's colours.
    pub simplified: Vec<[f32; 3]>,
    /// Which pixels the original covers.
    pub covered_original: Vec<bool>,
    /// Which pixels the simplified mesh covers.
    pub covered_simplified: Vec<bool>,
}

impl ViewImages {
    /// A PNG of the original, the simplified mesh and their difference side by side: in the
    /// difference, pixels covered in one image only are red, the others grey with the largest
    /// channel's difference × [`DIFFERENCE_GAIN`].
    pub fn png(&self) -> Result<Vec<u8>, MetricsError> {
        let n = self.size as usize;
        let mut buf = vec![0u8; 3 * n * 3 * n];
        let byte = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
        for y in 0..n {
            for x in 0..n {
                let i = y * n + x;
                let diff = if self.covered_original[i] != self.covered_simplified[i] {
                    [1.0, 0.0, 0.0]
                } else {
                    let d = max_channel_difference(self.original[i], self.simplified[i]);
                    [d * DIFFERENCE_GAIN; 3]
                };
                for (panel, c) in [self.original[i], self.simplified[i], diff]
                    .iter()
                    .enumerate()
                {
                    let at = 3 * (y * 3 * n + panel * n + x);
                    for k in 0..3 {
                        buf[at + k] = byte(c[k]);
                    }
                }
            }
        }
        let mut out = Vec::new();
        image::ImageEncoder::write_image(
            image::codecs::png::PngEncoder::new(&mut out),
            &buf,
            3 * self.size,
            self.size,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| MetricsError::Texture {
            file: format!("the images of view {}", self.view),
            problem: format!("cannot encode them as PNG ({e})"),
        })?;
        Ok(out)
    }
}

fn max_channel_difference(a: [f32; 3], b: [f32; 3]) -> f32 {
    (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f32::max)
}

/// One side of an [`image_error`]: a mesh, its attributes (`None`: positions only) and its
/// base-colour texture.
#[derive(Debug, Clone, Copy)]
pub struct Surface<'a> {
    /// The mesh.
    pub mesh: &'a TriMesh,
    /// Its attributes, which must fit it.
    pub attributes: Option<&'a Attributes>,
    /// Its base-colour texture, sampled at UV0 (its texture coordinates follow the texture's
    /// `v_down`). A simplified mesh without one is drawn with the original's: its materials
    /// are the original's.
    pub texture: Option<&'a Texture>,
    /// A flag that stops the [`image_error`] it is given to (on either side) with
    /// [`MetricsError::Cancelled`]: looked at per view and every 65,536 triangles and pixels
    /// of a rendering.
    pub cancel: Option<&'a Cancel>,
}

impl<'a> Surface<'a> {
    /// A mesh without attributes or texture.
    pub fn new(mesh: &'a TriMesh) -> Surface<'a> {
        Surface {
            mesh,
            attributes: None,
            texture: None,
            cancel: None,
        }
    }

    /// With attributes.
    pub fn with_attributes(self, attributes: Option<&'a Attributes>) -> Surface<'a> {
        Surface { attributes, ..self }
    }

    /// With a texture.
    pub fn with_texture(self, texture: Option<&'a Texture>) -> Surface<'a> {
        Surface { texture, ..self }
    }

    /// With a cancel flag (see [`Surface::cancel`]).
    pub fn with_cancel(self, cancel: &'a Cancel) -> Surface<'a> {
        Surface {
            cancel: Some(cancel),
            ..self
        }
    }
}

/// Image-space error of `simplified` against `original` (see the module docs).
pub fn image_error(
    original: &Surface<'_>,
    simplified: &Surface<'_>,
    params: &ImageErrorParams,
) -> Result<ImageError, MetricsError> {
    image_error_with_images(original, simplified, params, false).map(|(report, _)| report)
}

/// [`image_error`], also returning each view's renderings when `keep_images` (else an empty
/// list).
pub fn image_error_with_images(
    original: &Surface<'_>,
    simplified: &Surface<'_>,
    params: &ImageErrorParams,
    keep_images: bool,
) -> Result<(ImageError, Vec<ViewImages>), MetricsError> {
    params.validate()?;
    let start = Instant::now();
    let cancel = original.cancel.or(simplified.cancel);
    crate::check_cancel(cancel)?;
    crate::validate_mesh(original.mesh, "original")?;
    crate::validate_mesh(simplified.mesh, "simplified")?;
    if original.mesh.triangles.is_empty() {
        return Err(MetricsError::NoTriangles { mesh: "original" });
    }
    for (surface, which) in [(original, "original"), (simplified, "simplified")] {
        if let Some(a) = surface.attributes {
            a.validate(surface.mesh)
                .map_err(|problem| MetricsError::Attributes {
                    mesh: which,
                    problem,
                })?;
        }
    }
    let shading = Shading::of(original.attributes, original.texture);
    let bounds = original.mesh.referenced_bounding_box();
    let centre = bounds.center();
    // A point-like original still gets a frame (of unit radius) rather than a division by 0.
    let radius = match (bounds.diagonal() / 2.0) as f32 {
        r if r > 0.0 && r.is_finite() => r,
        _ => 1.0,
    };
    let scenes = [
        Scene::new(original, original.texture, shading, centre, params),
        Scene::new(
            simplified,
            simplified.texture.or(original.texture),
            shading,
            centre,
            params,
        ),
    ];
    crate::check_cancel(cancel)?;
    let results: Vec<(Sums, Option<ViewImages>)> = VIEWS
        .par_iter()
        .map(|&(name, direction)| {
            if cancel.is_some_and(Cancel::is_cancelled) {
                // Discarded below.
                return (Sums::default(), None);
            }
            let camera = Camera::new(Vec3::from(direction), radius, params);
            let a = scenes[0].render(&camera, cancel);
            let b = scenes[1].render(&camera, cancel);
            let sums = compare(&a, &b, params.threshold);
            let images = keep_images.then(|| ViewImages {
                view: name.to_string(),
                size: params.size,
                original: a.colour,
                simplified: b.colour,
                covered_original: a.covered,
                covered_simplified: b.covered,
            });
            (sums, images)
        })
        .collect();
    crate::check_cancel(cancel)?;
    // Pooled in the order of the views: the same sums whatever the thread count.
    let mut overall = Sums::default();
    let mut views = Vec::with_capacity(VIEWS.len());
    let mut images = Vec::new();
    for ((name, _), (sums, image)) in VIEWS.iter().zip(results) {
        overall.add(&sums);
        views.push(ViewError {
            view: name.to_string(),
            stats: sums.stats(),
        });
        images.extend(image);
    }
    let report = ImageError {
        size: params.size,
        fov_degrees: params.fov_degrees,
        threshold: params.threshold,
        flat_shading: params.flat_shading,
        shading,
        texture: (shading == Shading::Texture)
            .then(|| original.texture.map(|t| t.source.clone()))
            .flatten(),
        overall: overall.stats(),
        views,
        seconds: start.elapsed().as_secs_f64(),
    };
    Ok((report, images))
}

/// Sums over pixels, from which [`ImageStats`] follow (pooled exactly over views).
#[derive(Default)]
struct Sums {
    pixels: usize,
    covered: [usize; 2],
    squared: f64,
    absolute: f64,
    over: usize,
    mismatch: usize,
}

impl Sums {
    fn stats(&self) -> ImageStats {
        let n = self.pixels.max(1) as f64;
        let rmse = (self.squared / (3.0 * n)).sqrt();
        ImageStats {
            pixels: self.pixels,
            covered_original: self.covered[0],
            covered_simplified: self.covered[1],
            rmse,
            mean_abs: self.absolute / (3.0 * n),
            psnr_db: if rmse > 0.0 {
                -20.0 * rmse.log10()
            } else {
                f64::INFINITY
            },
            over_threshold: self.over as f64 / n,
            coverage_mismatch: self.mismatch as f64 / n,
        }
    }

    fn add(&mut self, other: &Sums) {
        self.pixels += other.pixels;
        self.covered[0] += other.covered[0];
        self.covered[1] += other.covered[1];
        self.squared += other.squared;
        self.absolute += other.absolute;
        self.over += other.over;
        self.mismatch += other.mismatch;
    }
}

/// Pixel-by-pixel comparison of two renderings of one view.
fn compare(a: &Rendering, b: &Rendering, threshold: f64) -> Sums {
    let mut sums = Sums::default();
    for i in 0..a.covered.len() {
        let (ca, cb) = (a.covered[i], b.covered[i]);
        if !(ca || cb) {
            continue;
        }
        sums.pixels += 1;
        sums.covered[0] += usize::from(ca);
        sums.covered[1] += usize::from(cb);
        sums.mismatch += usize::from(ca != cb);
        let mut largest = 0.0f64;
        for k in 0..3 {
            let d = f64::from(a.colour[i][k]) - f64::from(b.colour[i][k]);
            sums.squared += d * d;
            sums.absolute += d.abs();
            largest = largest.max(d.abs());
        }
        sums.over += usize::from(largest > threshold);
    }
    sums
}

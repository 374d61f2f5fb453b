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

use crate::MetricsError;
use glam::{Vec2, Vec3};
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

/// A decoded base-colour texture: RGB texels (0-1, as the image stores them; alpha is not
/// used), row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    width: u32,
    height: u32,
    texels: Vec<[f32; 3]>,
    v_down: bool,
    source: String,
}

impl Texture {
    /// A texture from RGB texels (0-1), row by row from the top. `v_down`: texture coordinate
    /// v = 0 is the top row (glTF) rather than the bottom row (OBJ). `source` names it in the
    /// report.
    pub fn from_rgb(
        width: u32,
        height: u32,
        texels: Vec<[f32; 3]>,
        v_down: bool,
        source: &str,
    ) -> Result<Texture, MetricsError> {
        if width == 0 || height == 0 || texels.len() != width as usize * height as usize {
            return Err(MetricsError::Texture {
                file: source.to_string(),
                problem: format!(
                    "{} texels do not make a {width} × {height} image",
                    texels.len()
                ),
            });
        }
        Ok(Texture {
            width,
            height,
            texels,
            v_down,
            source: source.to_string(),
        })
    }

    /// Decodes a PNG image (`source` names it in errors and the report; see [`Texture::from_rgb`]
    /// for `v_down`).
    pub fn decode(bytes: &[u8], source: &str, v_down: bool) -> Result<Texture, MetricsError> {
        let image = image::load_from_memory(bytes).map_err(|e| MetricsError::Texture {
            file: source.to_string(),
            problem: format!("cannot decode it as a PNG image ({e})"),
        })?;
        let rgb = image.to_rgb8();
        let texels = rgb
            .pixels()
            .map(|p| p.0.map(|c| f32::from(c) / 255.0))
            .collect();
        Texture::from_rgb(rgb.width(), rgb.height(), texels, v_down, source)
    }

    /// Where the texture came from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Bilinear sample at `uv`, wrapping (glTF's default sampler, and what OBJ viewers do).
    fn sample(&self, uv: Vec2) -> [f32; 3] {
        let (w, h) = (self.width as f32, self.height as f32);
        // Texel centres at half-integers; v = 0 at the bottom row for OBJ.
        let x = uv.x.rem_euclid(1.0) * w - 0.5;
        let v = uv.y.rem_euclid(1.0);
        let y = if self.v_down { v } else { 1.0 - v } * h - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let wrap = |i: f32, n: u32| (i as i64).rem_euclid(i64::from(n)) as usize;
        let (xa, xb) = (wrap(x0, self.width), wrap(x0 + 1.0, self.width));
        let (ya, yb) = (wrap(y0, self.height), wrap(y0 + 1.0, self.height));
        let row = self.width as usize;
        let t = |x: usize, y: usize| self.texels[y * row + x];
        let (a, b, c, d) = (t(xa, ya), t(xb, ya), t(xa, yb), t(xb, yb));
        std::array::from_fn(|k| {
            let top = a[k] + (b[k] - a[k]) * fx;
            let bottom = c[k] + (d[k] - c[k]) * fx;
            top + (bottom - top) * fy
        })
    }
}

/// What the surface colour is taken from (chosen from the original, see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Shading {
    /// The texture at UV0.
    Texture,
    /// The procedural checker at UV0 ([`CHECKER_SQUARE`]).
    Checker,
    /// The vertex colours.
    Colors,
    /// White.
    White,
}

impl Shading {
    fn of(original: Option<&Attributes>, texture: Option<&Texture>) -> Shading {
        match original {
            Some(a) if a.uv0.is_some() && texture.is_some() => Shading::Texture,
            Some(a) if a.uv0.is_some() => Shading::Checker,
            Some(a) if a.colors.is_some() => Shading::Colors,
            _ => Shading::White,
        }
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

/// A perspective camera looking at the centre of the original's bounding box (the origin of
/// the centred coordinates the scenes use).
struct Camera {
    eye: Vec3,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    /// 1 / tan(fov / 2).
    focal: f32,
    /// Camera-space depth below which triangles are clipped.
    near: f32,
    size: usize,
}

impl Camera {
    fn new(direction: Vec3, radius: f32, params: &ImageErrorParams) -> Camera {
        let dir = direction.normalize();
        let half = (params.fov_degrees.to_radians() / 2.0) as f32;
        // The bounding sphere touches the view cone: it fills the image whatever the direction.
        let distance = radius / half.sin();
        let forward = -dir;
        // World up is +y, except when looking along y, where +z takes its place.
        let world_up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let right = forward.cross(world_up).normalize();
        let up = right.cross(forward);
        Camera {
            eye: dir * distance,
            right,
            up,
            forward,
            focal: 1.0 / half.tan(),
            // Far in front of the eye for the original (whose sphere starts at distance −
            // radius); only a simplified mesh reaching behind the camera is clipped.
            near: distance * 1e-3,
            size: params.size as usize,
        }
    }

    /// Camera-space coordinates (x right, y up, depth along the view) of a centred point.
    fn view(&self, p: Vec3) -> Vec3 {
        let q = p - self.eye;
        Vec3::new(q.dot(self.right), q.dot(self.up), q.dot(self.forward))
    }

    /// Pixel coordinates (x right, y down, pixel centres at half-integers) of a camera-space
    /// point in front of the camera.
    fn screen(&self, v: Vec3) -> Vec2 {
        let half = self.size as f32 / 2.0;
        Vec2::new(
            half * (1.0 + self.focal * v.x / v.z),
            half * (1.0 - self.focal * v.y / v.z),
        )
    }
}

/// One mesh ready to render: centred positions, face normals, its shading inputs.
struct Scene<'a> {
    positions: Vec<Vec3>,
    triangles: &'a [[u32; 3]],
    face_normals: Vec<Vec3>,
    /// Area-weighted vertex normals, for a mesh without normals unless flat shading is asked.
    vertex_normals: Option<Vec<Vec3>>,
    attributes: Option<&'a Attributes>,
    texture: Option<&'a Texture>,
    shading: Shading,
}

/// A rendered image: colours (0-1) and coverage, row by row from the top.
struct Rendering {
    colour: Vec<[f32; 3]>,
    covered: Vec<bool>,
}

/// No triangle at this pixel.
const EMPTY: u32 = u32::MAX;

/// A corner of a (clipped) triangle: camera-space position and barycentric coordinates in the
/// mesh triangle it came from.
#[derive(Clone, Copy)]
struct Corner {
    view: Vec3,
    bary: Vec3,
}

impl<'a> Scene<'a> {
    fn new(
        surface: &Surface<'a>,
        texture: Option<&'a Texture>,
        shading: Shading,
        centre: Vec3,
        params: &ImageErrorParams,
    ) -> Scene<'a> {
        let (mesh, attributes) = (surface.mesh, surface.attributes);
        let has_normals = attributes.is_some_and(|a| a.normals.is_some());
        let vertex_normals = (!has_normals && !params.flat_shading).then(|| mesh.vertex_normals());
        // Centred before the camera transform: f32 keeps its precision for models far from
        // the origin.
        let positions: Vec<Vec3> = mesh.positions.iter().map(|&p| p - centre).collect();
        let face_normals = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| positions[v as usize]);
                (b - a).cross(c - a).normalize_or_zero()
            })
            .collect();
        Scene {
            positions,
            triangles: &mesh.triangles,
            face_normals,
            vertex_normals,
            attributes,
            texture,
            shading,
        }
    }

    /// Renders the scene through `camera`: visibility first (z-buffer of 1/w, the nearest
    /// triangle and its barycentric coordinates per pixel), then one shading per pixel.
    /// The image from `camera`; once `cancel` is set, an incomplete one (for the caller to
    /// discard).
    fn render(&self, camera: &Camera, cancel: Option<&Cancel>) -> Rendering {
        let n = camera.size * camera.size;
        let mut depth = vec![0.0f32; n];
        let mut face = vec![EMPTY; n];
        let mut bary = vec![Vec2::ZERO; n];
        let view: Vec<Vec3> = self.positions.iter().map(|&p| camera.view(p)).collect();
        let identity = [Vec3::X, Vec3::Y, Vec3::Z];
        let mut polygon = [Corner {
            view: Vec3::ZERO,
            bary: Vec3::ZERO,
        }; 4];
        for (f, t) in self.triangles.iter().enumerate() {
            if f.is_multiple_of(1 << 16) && cancel.is_some_and(Cancel::is_cancelled) {
                break;
            }
            let corners: [Corner; 3] = std::array::from_fn(|k| Corner {
                view: view[t[k] as usize],
                bary: identity[k],
            });
            let count = clip_near(&corners, camera.near, &mut polygon);
            for k in 1..count.saturating_sub(1) {
                let triangle = [polygon[0], polygon[k], polygon[k + 1]];
                rasterize(
                    camera, &triangle, f as u32, &mut depth, &mut face, &mut bary,
                );
            }
        }
        let mut colour = vec![[0.0f32; 3]; n];
        let mut covered = vec![false; n];
        for i in 0..n {
            if i.is_multiple_of(1 << 16) && cancel.is_some_and(Cancel::is_cancelled) {
                break;
            }
            if face[i] != EMPTY {
                covered[i] = true;
                colour[i] = self.shade(face[i] as usize, bary[i], camera.forward);
            }
        }
        Rendering { colour, covered }
    }

    /// The lit colour at barycentric coordinates (1 − b.x − b.y, b.x, b.y) of face `f`.
    fn shade(&self, f: usize, b: Vec2, forward: Vec3) -> [f32; 3] {
        let w = Vec3::new(1.0 - b.x - b.y, b.x, b.y);
        let wedges = self.attributes.map(|a| a.corners[f]);
        let normal = match (self.attributes.and_then(|a| a.normals.as_ref()), wedges) {
            (Some(normals), Some(c)) => {
                let n = w.x * normals[c[0] as usize]
                    + w.y * normals[c[1] as usize]
                    + w.z * normals[c[2] as usize];
                n.try_normalize().unwrap_or(self.face_normals[f])
            }
            _ => match &self.vertex_normals {
                Some(normals) => {
                    let t = self.triangles[f];
                    let n = w.x * normals[t[0] as usize]
                        + w.y * normals[t[1] as usize]
                        + w.z * normals[t[2] as usize];
                    n.try_normalize().unwrap_or(self.face_normals[f])
                }
                None => self.face_normals[f],
            },
        };
        // A headlight at infinity (light along the view direction, not from the eye): a flat
        // face is lit evenly, so a texture difference is not mixed with a lighting gradient.
        // Two-sided (|n·l|), as the rasterizer draws both sides.
        let light = AMBIENT + (1.0 - AMBIENT) * normal.dot(forward).abs();
        let uv = |a: &Attributes, c: [u32; 3]| {
            a.uv0.as_ref().map(|uv| {
                w.x * uv[c[0] as usize] + w.y * uv[c[1] as usize] + w.z * uv[c[2] as usize]
            })
        };
        let albedo = match (self.shading, self.attributes, wedges) {
            (Shading::Texture, Some(a), Some(c)) => match (uv(a, c), self.texture) {
                (Some(uv), Some(t)) => t.sample(uv),
                _ => [1.0; 3],
            },
            (Shading::Checker, Some(a), Some(c)) => uv(a, c).map_or([1.0; 3], checker),
            (Shading::Colors, Some(a), Some(c)) => a.colors.as_ref().map_or([1.0; 3], |col| {
                let v =
                    w.x * col[c[0] as usize] + w.y * col[c[1] as usize] + w.z * col[c[2] as usize];
                [v.x, v.y, v.z].map(linear_to_srgb)
            }),
            _ => [1.0; 3],
        };
        albedo.map(|c| (c * light).clamp(0.0, 1.0))
    }
}

/// The procedural checker at `uv` ([`CHECKER_SQUARE`], [`CHECKER_VALUES`]), grey.
fn checker(uv: Vec2) -> [f32; 3] {
    let i = (uv.x / CHECKER_SQUARE).floor() as i64 + (uv.y / CHECKER_SQUARE).floor() as i64;
    [CHECKER_VALUES[i.rem_euclid(2) as usize]; 3]
}

/// A linear colour channel (the mesh's vertex colours) as sRGB, what a screen shows.
fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Clips a triangle to depth ≥ `near` (Sutherland–Hodgman against one plane), writing the
/// polygon (0, 3 or 4 corners) to `out` and returning its corner count.
fn clip_near(corners: &[Corner; 3], near: f32, out: &mut [Corner; 4]) -> usize {
    if corners.iter().all(|c| c.view.z >= near) {
        out[..3].copy_from_slice(corners);
        return 3;
    }
    let mut count = 0;
    for k in 0..3 {
        let (a, b) = (corners[k], corners[(k + 1) % 3]);
        let (ina, inb) = (a.view.z >= near, b.view.z >= near);
        if ina {
            out[count] = a;
            count += 1;
        }
        if ina != inb {
            let s = (near - a.view.z) / (b.view.z - a.view.z);
            out[count] = Corner {
                view: a.view.lerp(b.view, s),
                bary: a.bary.lerp(b.bary, s),
            };
            count += 1;
        }
    }
    count
}

/// Draws one triangle in front of the near plane into the visibility buffers: every pixel whose
/// centre is inside (edges included) and nearer than what is there takes face `f` and the
/// perspective-correct barycentric coordinates of its mesh triangle.
fn rasterize(
    camera: &Camera,
    t: &[Corner; 3],
    f: u32,
    depth: &mut [f32],
    face: &mut [u32],
    bary: &mut [Vec2],
) {
    let s = t.map(|c| camera.screen(c.view));
    let inv_w = t.map(|c| 1.0 / c.view.z);
    let edge = |a: Vec2, b: Vec2, p: Vec2| (b - a).perp_dot(p - a);
    let area = edge(s[0], s[1], s[2]);
    // Edge-on (or degenerate): covers no pixel centre in a stable way.
    if area.abs() < 1e-12 || !area.is_finite() {
        return;
    }
    let size = camera.size as f32;
    let lo = s[0].min(s[1]).min(s[2]);
    let hi = s[0].max(s[1]).max(s[2]);
    // Pixel x covers [x, x + 1) with its centre at x + 0.5.
    let x0 = (lo.x - 0.5).ceil().max(0.0);
    let y0 = (lo.y - 0.5).ceil().max(0.0);
    let x1 = (hi.x - 0.5).floor().min(size - 1.0);
    let y1 = (hi.y - 0.5).floor().min(size - 1.0);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let inv_area = 1.0 / area;
    let row = camera.size;
    for y in y0 as usize..=y1 as usize {
        for x in x0 as usize..=x1 as usize {
            let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let l = Vec3::new(
                edge(s[1], s[2], p),
                edge(s[2], s[0], p),
                edge(s[0], s[1], p),
            ) * inv_area;
            if l.x < 0.0 || l.y < 0.0 || l.z < 0.0 {
                continue;
            }
            // 1/w is affine in screen space: the z-buffer's value, and the perspective
            // correction of the barycentric coordinates.
            let w = l * Vec3::from(inv_w);
            let inv = w.x + w.y + w.z;
            let i = y * row + x;
            if inv <= depth[i] {
                continue;
            }
            depth[i] = inv;
            face[i] = f;
            let b = (w.x * t[0].bary + w.y * t[1].bary + w.z * t[2].bary) / inv;
            bary[i] = Vec2::new(b.y, b.z);
        }
    }
}

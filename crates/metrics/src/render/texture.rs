//! The surface colour's inputs: a decoded base-colour [`Texture`] and its bilinear sampling, and
//! the [`Shading`] chosen from the original.

use crate::MetricsError;
use glam::Vec2;
use mesh::attributes::Attributes;
use mesh::io::BaseColorTexture;
use serde::{Deserialize, Serialize};

/// A decoded base-colour texture: RGB texels (0-1, as the image stores them; alpha is not
/// used), row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    width: u32,
    height: u32,
    texels: Vec<[f32; 3]>,
    v_down: bool,
    pub(super) source: String,
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

    /// Reads and decodes a material's base-colour texture as [`mesh::io::base_color_texture`]
    /// found it: the one loader of every front end (the CLI's image-space error, the viewer's
    /// display). An image that could not be read or decoded is an error naming its file.
    pub fn load(found: &BaseColorTexture) -> Result<Texture, MetricsError> {
        let bytes = found.bytes.as_ref().map_err(|e| MetricsError::Texture {
            file: found.source.clone(),
            problem: format!("cannot read it ({e})"),
        })?;
        Texture::decode(bytes, &found.source, found.v_down)
    }

    /// Where the texture came from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Width and height in texels.
    pub fn size(&self) -> [u32; 2] {
        [self.width, self.height]
    }

    /// Whether texture coordinate v = 0 is the top row (glTF) rather than the bottom row (OBJ).
    pub fn v_down(&self) -> bool {
        self.v_down
    }

    /// The texels as 8-bit RGBA rows from the top (alpha 255), the bytes the image stored.
    pub fn rgba8(&self) -> Vec<u8> {
        let byte = |c: f32| (c * 255.0).round().clamp(0.0, 255.0) as u8;
        self.texels
            .iter()
            .flat_map(|t| [byte(t[0]), byte(t[1]), byte(t[2]), 255])
            .collect()
    }

    /// Bilinear sample at `uv`, wrapping (glTF's default sampler, and what OBJ viewers do).
    pub(super) fn sample(&self, uv: Vec2) -> [f32; 3] {
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
    /// The procedural checker at UV0 ([`CHECKER_SQUARE`](super::CHECKER_SQUARE)).
    Checker,
    /// The vertex colours.
    Colors,
    /// White.
    White,
}

impl Shading {
    pub(super) fn of(original: Option<&Attributes>, texture: Option<&Texture>) -> Shading {
        match original {
            Some(a) if a.uv0.is_some() && texture.is_some() => Shading::Texture,
            Some(a) if a.uv0.is_some() => Shading::Checker,
            Some(a) if a.colors.is_some() => Shading::Colors,
            _ => Shading::White,
        }
    }
}

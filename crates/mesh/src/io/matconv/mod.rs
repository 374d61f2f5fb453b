//! Materials across OBJ and glTF: an OBJ input's material libraries (MTL) become glTF
//! metallic-roughness materials in a glTF output ([`obj_to_gltf`]), and a glTF input's materials
//! become a material library next to an OBJ output ([`gltf_to_mtl`]), each with its base colour
//! texture, so that the output shows the same colours and texture. What one side has and the
//! other cannot express is named in one warning per output, never dropped silently.
//!
//! | MTL                        | glTF                                                      |
//! |----------------------------|-----------------------------------------------------------|
//! | `Kd r g b`                 | `baseColorFactor` rgb                                     |
//! | `d a` (or `Tr t`: a = 1−t) | `baseColorFactor` alpha; `alphaMode` `BLEND` when a < 1   |
//! | `map_Kd file`              | `baseColorTexture` (PNG or JPEG image)                    |
//! | `Pr r`, else `Ns n`        | `roughnessFactor` r, or √(2 / (n + 2)); 1 without either  |
//! | `Pm m`                     | `metallicFactor` m; 0 without it                          |
//! | `Ke r g b`                 | `emissiveFactor`                                          |
//!
//! The way back writes `Kd`, `d` (when `alphaMode` is not `OPAQUE` and alpha < 1), `Ns` from
//! the roughness (2 / r² − 2, at most 1000), `Pr`, `Pm`, `Ke` (when not black) and `map_Kd`.
//! Texture coordinates are flipped (`v → 1 − v`) when a texture crosses, as the two formats put
//! the image's origin at opposite edges.
//!
//! The parts: the MTL reader ([`mtl`]), OBJ to glTF ([`to_gltf`]), glTF to MTL ([`to_mtl`]),
//! and the base-colour texture of either kind of material ([`base_color`]).

mod base_color;
mod mtl;
mod to_gltf;
mod to_mtl;

pub use base_color::{BaseColorTexture, base_color_texture};
pub(crate) use mtl::{MtlMaterial, parse_mtl};
pub(crate) use to_gltf::obj_to_gltf;
pub(crate) use to_mtl::{ImageSource, gltf_to_mtl, write_mtl};

/// Roughness for an MTL specular exponent (the Blinn-Phong to microfacet rule of thumb
/// √(2 / (Ns + 2)), in [0, 1]).
fn roughness_of_ns(ns: f32) -> f32 {
    (2.0 / (ns.max(0.0) + 2.0)).sqrt().clamp(0.0, 1.0)
}

/// The specular exponent for a roughness (the inverse of [`roughness_of_ns`], at most 1000).
fn ns_of_roughness(r: f32) -> f32 {
    let r = r.clamp(0.0, 1.0);
    if r < 0.0447 {
        1000.0
    } else {
        (2.0 / (r * r) - 2.0).clamp(0.0, 1000.0)
    }
}

/// The MIME type of image bytes, told by their first bytes (glTF takes PNG and JPEG).
pub(crate) fn image_mime(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some("image/jpeg")
    } else {
        None
    }
}

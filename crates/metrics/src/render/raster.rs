//! Rendering one view: the perspective [`Camera`], a mesh made ready to draw ([`Scene`]: centred
//! positions, normals, shading inputs) and the rasterizer (near-plane clipping, a z-buffer on
//! 1/w, perspective-correct barycentrics, the shading of each covered pixel).

use super::{AMBIENT, CHECKER_SQUARE, CHECKER_VALUES, ImageErrorParams, Shading, Surface, Texture};
use glam::{Vec2, Vec3};
use mesh::attributes::Attributes;
use mesh::cancel::Cancel;

/// A perspective camera looking at the centre of the original's bounding box (the origin of
/// the centred coordinates the scenes use).
pub(super) struct Camera {
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
    pub(super) fn new(direction: Vec3, radius: f32, params: &ImageErrorParams) -> Camera {
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
pub(super) struct Scene<'a> {
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
pub(super) struct Rendering {
    pub(super) colour: Vec<[f32; 3]>,
    pub(super) covered: Vec<bool>,
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
    pub(super) fn new(
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
    pub(super) fn render(&self, camera: &Camera, cancel: Option<&Cancel>) -> Rendering {
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

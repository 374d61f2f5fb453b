//! The orbit camera shared by both viewports: yaw/pitch around a target point, with the view and
//! projection matrices the renderer needs. Pure math, no GPU: unit-testable anywhere.

use glam::{Mat4, Vec3};
use mesh::Aabb;

/// Orbit camera shared by both viewports: yaw/pitch around a target point at a distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    /// Point orbited around, in model units.
    pub target: Vec3,
    /// Distance from target to eye, in model units.
    pub distance: f32,
    /// Rotation about the vertical axis, radians.
    pub yaw: f32,
    /// Elevation, radians, clamped to just under ±π/2.
    pub pitch: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Radius of the framed model, for near/far planes and pan speed.
    pub scene_radius: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        OrbitCamera {
            target: Vec3::ZERO,
            distance: 3.0,
            yaw: 0.6,
            pitch: 0.35,
            fov_y: 40f32.to_radians(),
            scene_radius: 1.0,
        }
    }
}

impl OrbitCamera {
    /// A camera that frames `bounds` from the default direction.
    pub fn framing(bounds: &Aabb) -> OrbitCamera {
        let mut camera = OrbitCamera::default();
        if !bounds.is_empty() {
            let radius = (bounds.diagonal() as f32 * 0.5).max(1e-6);
            camera.target = bounds.center();
            camera.scene_radius = radius;
            camera.distance = radius / (camera.fov_y * 0.5).sin() * 1.05;
        }
        camera
    }

    /// Eye position in model units.
    pub fn eye(&self) -> Vec3 {
        let dir = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        self.target + dir * self.distance
    }

    /// Combined projection × view matrix for a target of the given aspect ratio (width/height).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let near = (self.distance - self.scene_radius * 2.0).max(self.distance * 1e-3);
        let far = self.distance + self.scene_radius * 2.0;
        perspective(self.fov_y, aspect.max(1e-3), near, far) * look_at(self.eye(), self.target)
    }

    /// Rotate by a mouse drag of `dx`, `dy` points.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.008).clamp(-1.55, 1.55);
    }

    /// Move the target by a drag of `dx`, `dy` points in a viewport `height` points tall.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let eye = self.eye();
        let forward = (self.target - eye).normalize_or_zero();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let up = right.cross(forward);
        let units_per_point = 2.0 * self.distance * (self.fov_y * 0.5).tan() / height.max(1.0);
        self.target += (-right * dx + up * dy) * units_per_point;
    }

    /// Zoom by `factor` (> 1 moves closer).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance =
                (self.distance / factor).clamp(self.scene_radius * 0.05, self.scene_radius * 50.0);
        }
    }
}

/// Right-handed perspective projection with wgpu's 0..1 depth range.
fn perspective(fov_y: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let f = 1.0 / (fov_y * 0.5).tan();
    let r = far / (near - far);
    Mat4::from_cols_array(&[
        f / aspect,
        0.0,
        0.0,
        0.0, //
        0.0,
        f,
        0.0,
        0.0, //
        0.0,
        0.0,
        r,
        -1.0, //
        0.0,
        0.0,
        r * near,
        0.0,
    ])
}

/// Right-handed view matrix looking from `eye` at `center` with +Y up.
fn look_at(eye: Vec3, center: Vec3) -> Mat4 {
    let f = (center - eye).normalize_or_zero();
    let s = f.cross(Vec3::Y).normalize_or(Vec3::X);
    let u = s.cross(f);
    Mat4::from_cols_array(&[
        s.x,
        u.x,
        -f.x,
        0.0, //
        s.y,
        u.y,
        -f.y,
        0.0, //
        s.z,
        u.z,
        -f.z,
        0.0, //
        -s.dot(eye),
        -u.dot(eye),
        f.dot(eye),
        1.0,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn framing_camera_sees_whole_box_and_projects_center_to_origin() {
        let bounds = Aabb {
            min: Vec3::new(-1.0, 2.0, 0.0),
            max: Vec3::new(3.0, 4.0, 1.0),
        };
        let camera = OrbitCamera::framing(&bounds);
        let vp = camera.view_proj(1.0);
        let c = vp.project_point3(bounds.center());
        assert!(c.x.abs() < 1e-4 && c.y.abs() < 1e-4, "{c:?}");
        for corner in 0..8 {
            let p = Vec3::new(
                if corner & 1 == 0 {
                    bounds.min.x
                } else {
                    bounds.max.x
                },
                if corner & 2 == 0 {
                    bounds.min.y
                } else {
                    bounds.max.y
                },
                if corner & 4 == 0 {
                    bounds.min.z
                } else {
                    bounds.max.z
                },
            );
            let q = vp.project_point3(p);
            assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0, "corner {p} -> {q}");
            assert!((0.0..=1.0).contains(&q.z), "depth {q}");
        }
    }

    #[test]
    fn zoom_and_orbit_stay_in_range() {
        let mut camera = OrbitCamera::default();
        camera.zoom(1e9);
        assert!(camera.distance >= camera.scene_radius * 0.05 - 1e-6);
        camera.orbit(0.0, 1e6);
        assert!(camera.pitch <= 1.55);
        let before = camera.target;
        camera.pan(10.0, 0.0, 100.0);
        assert!(camera.target.distance(before) > 0.0);
    }
}

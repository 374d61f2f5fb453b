//! What the two viewports show: the GPU copies of the meshes, of the model's base-colour texture
//! and of the live network, kept in step with the [`Session`] by pointer identity, and the draw
//! lists of each side (GNG3D on the left, QEM on the right) rendered into their offscreen
//! targets. A mesh with texture coordinates is drawn with the texture when the model has one
//! and the display's toggle is on.

use crate::camera::OrbitCamera;
use crate::engine::NetworkSnapshot;
use crate::layout::Display;
use crate::render::{
    CopyMode, DrawItem, GpuMesh, GpuNetwork, GpuTexture, SceneRenderer, Uvs, ViewTarget,
};
use crate::session::Session;
use egui_wgpu::RenderState;
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::sync::Arc;

/// A GPU mesh and the CPU mesh it was uploaded from (to notice when the session replaced it),
/// and whether texture coordinates were asked for.
struct Uploaded {
    source: Arc<TriMesh>,
    with_uvs: bool,
    mesh: GpuMesh,
}

impl Uploaded {
    /// The GPU mesh and the texture to draw on it: `texture` when the mesh has texture
    /// coordinates.
    fn with<'a>(
        &'a self,
        texture: Option<&'a GpuTexture>,
    ) -> (&'a GpuMesh, Option<&'a GpuTexture>) {
        (&self.mesh, texture.filter(|_| self.mesh.has_uvs))
    }
}

/// A lit surface of `color` (or `texture`), with its edges drawn over it in wireframe mode.
fn surface<'a>(
    (mesh, texture): (&'a GpuMesh, Option<&'a GpuTexture>),
    color: [f32; 3],
    display: &Display,
) -> impl Iterator<Item = DrawItem<'a>> {
    let shading = display.shading;
    let wire = display.wireframe.then_some(DrawItem::Wireframe {
        mesh,
        color: [0.02, 0.02, 0.03, 0.55],
    });
    std::iter::once(DrawItem::Surface {
        mesh,
        color,
        shading,
        texture,
    })
    .chain(wire)
}

/// Upload `source` into `slot` unless the slot already holds exactly that mesh; with
/// `attributes` when the model has a texture (`v_down` its convention) to draw with them.
fn sync(
    device: &wgpu::Device,
    slot: &mut Option<Uploaded>,
    source: Option<&Arc<TriMesh>>,
    attributes: Option<&Attributes>,
    v_down: Option<bool>,
) {
    let uvs = v_down
        .zip(attributes)
        .map(|(v_down, attributes)| Uvs { attributes, v_down });
    match source {
        None => *slot = None,
        Some(s)
            if slot
                .as_ref()
                .is_some_and(|u| Arc::ptr_eq(&u.source, s) && u.with_uvs == uvs.is_some()) => {}
        Some(s) => {
            *slot = Some(Uploaded {
                source: Arc::clone(s),
                with_uvs: uvs.is_some(),
                mesh: GpuMesh::new(device, s, uvs),
            })
        }
    }
}

/// GPU resources of the viewports (absent when no wgpu render state is available).
pub struct Scene {
    render_state: RenderState,
    renderer: SceneRenderer,
    targets: [ViewTarget; 2],
    original: Option<Uploaded>,
    gng_mesh: Option<Uploaded>,
    qem_mesh: Option<Uploaded>,
    /// The model's base-colour texture and its upload.
    texture: Option<(Arc<metrics::Texture>, GpuTexture)>,
    network: GpuNetwork,
    network_source: Option<Arc<NetworkSnapshot>>,
    /// How the viewports are copied into egui's target (chosen from the adapter).
    pub copy_mode: CopyMode,
}

impl Scene {
    /// Pipelines and targets for `render_state`; the copy into egui's target follows the
    /// adapter's capabilities (no reinterpreting views on OpenGL ES).
    pub fn new(render_state: RenderState) -> Scene {
        let copy_mode = CopyMode::choose(
            render_state.target_format,
            &render_state.adapter.get_downlevel_capabilities(),
        );
        let device = &render_state.device;
        let renderer = SceneRenderer::new(
            device,
            &render_state.queue,
            render_state.target_format,
            copy_mode,
        );
        let targets = [
            renderer.create_target(device, [64, 64]),
            renderer.create_target(device, [64, 64]),
        ];
        let network = GpuNetwork::new(device);
        Scene {
            renderer,
            targets,
            original: None,
            gng_mesh: None,
            qem_mesh: None,
            texture: None,
            network,
            network_source: None,
            copy_mode,
            render_state,
        }
    }

    /// The graphics backend in use (Vulkan, Gl, …), for the run summary.
    pub fn backend(&self) -> wgpu::Backend {
        self.render_state.adapter.get_info().backend
    }

    /// The offscreen colour texture of viewport `index` (0: GNG3D, 1: QEM), for tests.
    pub fn color_texture(&self, index: usize) -> &wgpu::Texture {
        self.targets[index].color_texture()
    }

    /// The size in texels of the base-colour texture uploaded for the model (`None` without
    /// one), for tests.
    pub fn texture_size(&self) -> Option<[u32; 2]> {
        self.texture.as_ref().map(|(_, t)| t.size)
    }

    /// A paint callback copying viewport `index` into egui's pass at `rect`.
    pub fn paint_callback(&self, index: usize, rect: egui::Rect) -> egui::PaintCallback {
        self.renderer.paint_callback(&self.targets[index], rect)
    }

    /// Bring the GPU copies up to date with `session`, then redraw each viewport whose content
    /// changed, at `sizes` pixels. Returns which viewports were redrawn.
    pub fn render(
        &mut self,
        session: &Session,
        camera: &OrbitCamera,
        display: &Display,
        sizes: [[u32; 2]; 2],
    ) -> [bool; 2] {
        let device = &self.render_state.device;
        let queue = &self.render_state.queue;
        match (session.texture(), &self.texture) {
            (None, _) => self.texture = None,
            (Some(t), Some((source, _))) if Arc::ptr_eq(t, source) => {}
            (Some(t), _) => {
                let gpu = self.renderer.upload_texture(device, queue, t);
                self.texture = Some((Arc::clone(t), gpu));
            }
        }
        let v_down = self.texture.as_ref().map(|(t, _)| t.v_down());
        sync(
            device,
            &mut self.original,
            Some(session.original()),
            session.attributes().map(|a| &**a),
            v_down,
        );
        sync(
            device,
            &mut self.gng_mesh,
            session.reconstruction(),
            session.reconstruction_attributes(),
            v_down,
        );
        sync(
            device,
            &mut self.qem_mesh,
            session.qem_mesh(),
            session.qem_attributes(),
            v_down,
        );
        let texture = self
            .texture
            .as_ref()
            .filter(|_| display.texture)
            .map(|(_, t)| t);
        // Upload the network when the worker published a new snapshot.
        let snapshot = &session.live().snapshot;
        if self
            .network_source
            .as_ref()
            .is_none_or(|s| !Arc::ptr_eq(s, snapshot))
        {
            self.network
                .update(device, queue, &snapshot.positions, &snapshot.edges);
            self.network_source = Some(Arc::clone(snapshot));
        }
        for (target, size) in self.targets.iter_mut().zip(sizes) {
            self.renderer.resize_target(device, target, size);
        }
        let overlay = [0.45, 0.45, 0.50, 0.28];
        let mut left: Vec<DrawItem<'_>> = Vec::new();
        let gng_mesh = self.gng_mesh.as_ref().map(|u| u.with(texture));
        let gng_mesh_shown = display.show_gng_mesh && gng_mesh.is_some();
        if let (true, Some(mesh)) = (display.show_gng_mesh, gng_mesh) {
            left.extend(surface(mesh, [0.85, 0.42, 0.16], display));
        }
        if display.show_network && !(gng_mesh_shown && session.live().finished) {
            left.push(DrawItem::Network {
                network: &self.network,
                node_color: [1.0, 0.55, 0.12],
                edge_color: [0.35, 0.65, 1.0, 0.9],
                point_px: display.point_px,
            });
        }
        let mut right: Vec<DrawItem<'_>> = Vec::new();
        if let Some(mesh) = self.qem_mesh.as_ref().map(|u| u.with(texture)) {
            right.extend(surface(mesh, [0.20, 0.45, 0.85], display));
        }
        if let Some((original, texture)) = self.original.as_ref().map(|u| u.with(texture)) {
            if display.show_original {
                for side in [&mut left, &mut right] {
                    side.push(DrawItem::Overlay {
                        mesh: original,
                        color: overlay,
                        texture,
                    });
                }
            } else if self.qem_mesh.is_none() {
                // The original stands in on the right while QEM computes (or failed): the
                // label says which.
                right.push(DrawItem::Surface {
                    mesh: original,
                    color: [0.5, 0.5, 0.55],
                    shading: display.shading,
                    texture,
                });
            }
        }
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("viewports"),
        });
        let [left_target, right_target] = &mut self.targets;
        let drew_left = self
            .renderer
            .render(queue, &mut encoder, left_target, camera, &left);
        let drew_right = self
            .renderer
            .render(queue, &mut encoder, right_target, camera, &right);
        if drew_left || drew_right {
            queue.submit(std::iter::once(encoder.finish()));
        }
        [drew_left, drew_right]
    }
}

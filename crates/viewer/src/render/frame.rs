//! Per-frame drawing: a viewport's passes (the cached layer without the live network, then the
//! network over it), skipped when its fingerprint says the target already shows that frame, and
//! the paint callback that copies the target into egui's render pass.

use super::*;

impl SceneRenderer {
    /// A paint callback that copies `target` into egui's render pass at `rect` (points).
    pub fn paint_callback(&self, target: &ViewTarget, rect: egui::Rect) -> egui::PaintCallback {
        egui_wgpu::Callback::new_paint_callback(
            rect,
            ViewportCallback {
                pipeline: self.blit.clone(),
                bind_group: target.blit_group.clone(),
            },
        )
    }

    /// Record the drawing of `items` into `target` seen through `camera`, unless the target
    /// already shows exactly that (same camera, size and items): on a CPU rasterizer an unchanged
    /// viewport costs only its copy into the window. Returns whether it drew.
    pub fn render(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &mut ViewTarget,
        camera: &OrbitCamera,
        items: &[DrawItem<'_>],
    ) -> bool {
        let content = fingerprint(camera, target.size, items);
        if target.content == Some(content) {
            return false;
        }
        target.content = Some(content);
        let [w, h] = target.size;
        let view_proj = camera.view_proj(w as f32 / h as f32);
        let eye = camera.eye();
        // Key light from above-left of the camera, so shading follows the view.
        let forward = (camera.target - eye).normalize_or_zero();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let light = (-forward + Vec3::Y * 0.8 - right * 0.5).normalize_or_zero();
        let uniform = |color: [f32; 4], params: [f32; 4]| DrawUniform {
            view_proj: view_proj.to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
            light: light.extend(0.0).to_array(),
            color,
            params,
            viewport: [w as f32, h as f32, 0.0, 0.0],
        };
        // One uniform slot per item; networks take a second slot for their edges.
        let mut slots: Vec<DrawUniform> = Vec::with_capacity(items.len() + 1);
        let mut slot_of: Vec<(usize, Option<usize>)> = Vec::with_capacity(items.len());
        for item in items {
            let needed = if matches!(item, DrawItem::Network { .. }) {
                2
            } else {
                1
            };
            if slots.len() + needed > MAX_DRAWS as usize {
                break;
            }
            let main = slots.len();
            let mut extra = None;
            match item {
                DrawItem::Surface { color, shading, .. } => slots.push(uniform(
                    [color[0], color[1], color[2], 1.0],
                    [f32::from(*shading == Shading::Smooth), 0.0, 0.0, 0.0],
                )),
                DrawItem::Wireframe { color, .. } => {
                    slots.push(uniform(*color, [0.0, 2e-4, 0.0, 0.0]));
                }
                DrawItem::Overlay { color, .. } => {
                    slots.push(uniform(*color, [1.0, 0.0, 0.0, 0.0]));
                }
                DrawItem::Network {
                    node_color,
                    edge_color,
                    point_px,
                    ..
                } => {
                    slots.push(uniform(
                        [node_color[0], node_color[1], node_color[2], 1.0],
                        [0.0, 1e-4, *point_px, 0.0],
                    ));
                    slots.push(uniform(*edge_color, [0.0, 5e-5, 0.0, 0.0]));
                    extra = Some(main + 1);
                }
            }
            slot_of.push((main, extra));
        }
        let mut bytes = vec![0u8; (UNIFORM_STRIDE * MAX_DRAWS) as usize];
        for (i, slot) in slots.iter().enumerate() {
            let offset = i * UNIFORM_STRIDE as usize;
            bytes[offset..offset + size_of::<DrawUniform>()]
                .copy_from_slice(bytemuck::bytes_of(slot));
        }
        queue.write_buffer(&target.uniforms, 0, &bytes);

        // Surfaces, wireframes and overlays change only with a checkpoint or the camera; the
        // live network changes every frame. With a network on screen the rest is drawn once
        // into the target's layer (colour and depth) and each frame starts from a copy of it,
        // drawing only the network on top, tested against the layer's depth without writing
        // it. On lavapipe this saves the surface of the neural mesh (~12 ms a frame at
        // 1280×720 under a 10k-node network).
        let drawn = &items[..slot_of.len()];
        let is_network = |it: &DrawItem<'_>| matches!(it, DrawItem::Network { .. });
        let statics: Vec<usize> = (0..drawn.len())
            .filter(|&i| !is_network(&drawn[i]))
            .collect();
        let networks: Vec<usize> = (0..drawn.len())
            .filter(|&i| is_network(&drawn[i]))
            .collect();
        let [r, g, b] = CLEAR_COLOR;
        let clear = wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a: 1.0 });
        if networks.is_empty() {
            let mut pass = begin_pass(encoder, &target.color_view, &target.depth_view, clear, true);
            self.draw(&mut pass, target, drawn, &slot_of, &statics);
            return true;
        }
        let layer_content = fingerprint(camera, target.size, statics.iter().map(|&i| &drawn[i]));
        if target.layer_content != Some(layer_content) {
            target.layer_content = Some(layer_content);
            let mut pass = begin_pass(encoder, &target.layer_view, &target.depth_view, clear, true);
            self.draw(&mut pass, target, drawn, &slot_of, &statics);
        }
        let extent = wgpu::Extent3d {
            width: target.size[0].max(1),
            height: target.size[1].max(1),
            depth_or_array_layers: 1,
        };
        encoder.copy_texture_to_texture(
            target.layer.as_image_copy(),
            target.color.as_image_copy(),
            extent,
        );
        let mut pass = begin_pass(
            encoder,
            &target.color_view,
            &target.depth_view,
            wgpu::LoadOp::Load,
            false,
        );
        self.draw(&mut pass, target, drawn, &slot_of, &networks);
        true
    }

    /// Draw `items[indices]` (opaque first, overlays last so they blend over finished depth)
    /// with the uniform slots of `slot_of`.
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        target: &ViewTarget,
        items: &[DrawItem<'_>],
        slot_of: &[(usize, Option<usize>)],
        indices: &[usize],
    ) {
        let overlay = |i: &usize| matches!(items[*i], DrawItem::Overlay { .. });
        let order = indices
            .iter()
            .filter(|i| !overlay(i))
            .chain(indices.iter().filter(|i| overlay(i)));
        // Every pipeline's layout has the texture's group: untextured draws bind the blank one.
        pass.set_bind_group(1, &self.blank.bind_group, &[]);
        for &i in order {
            let item = &items[i];
            let (main_slot, edge_slot) = slot_of[i];
            let offset = (main_slot as u64 * UNIFORM_STRIDE) as u32;
            pass.set_bind_group(0, &target.bind_group, &[offset]);
            match item {
                DrawItem::Surface { mesh, texture, .. }
                | DrawItem::Overlay { mesh, texture, .. } => {
                    if mesh.triangle_index_count == 0 {
                        continue;
                    }
                    let overlay = matches!(item, DrawItem::Overlay { .. });
                    let pipeline = match (overlay, texture) {
                        (false, None) => &self.surface,
                        (true, None) => &self.overlay,
                        (false, Some(_)) => &self.surface_textured,
                        (true, Some(_)) => &self.overlay_textured,
                    };
                    let texture = texture.unwrap_or(&self.blank);
                    pass.set_bind_group(1, &texture.bind_group, &[]);
                    pass.set_pipeline(pipeline);
                    pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                    pass.set_index_buffer(mesh.triangles.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..mesh.triangle_index_count, 0, 0..1);
                }
                DrawItem::Wireframe { mesh, .. } => {
                    if mesh.edge_index_count == 0 {
                        continue;
                    }
                    pass.set_pipeline(&self.mesh_lines);
                    pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                    pass.set_index_buffer(mesh.edges.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..mesh.edge_index_count, 0, 0..1);
                }
                DrawItem::Network {
                    network, point_px, ..
                } => {
                    if network.node_count == 0 {
                        continue;
                    }
                    // The network writes no depth (see `render`): edges first, then the node
                    // markers over them.
                    let node_bytes = network.node_count as u64 * 12;
                    if let (Some(slot), true) = (edge_slot, network.edge_index_count > 0) {
                        let edge_offset = (slot as u64 * UNIFORM_STRIDE) as u32;
                        pass.set_bind_group(0, &target.bind_group, &[edge_offset]);
                        pass.set_pipeline(&self.network_lines);
                        pass.set_vertex_buffer(0, network.positions.slice(..node_bytes));
                        pass.set_index_buffer(
                            network.edges.slice(..network.edge_index_count as u64 * 4),
                            wgpu::IndexFormat::Uint32,
                        );
                        pass.draw_indexed(0..network.edge_index_count, 0, 0..1);
                    }
                    if node_markers_visible(network.node_count, *point_px, target.size) {
                        pass.set_bind_group(0, &target.bind_group, &[offset]);
                        pass.set_pipeline(&self.points);
                        pass.set_vertex_buffer(0, network.positions.slice(..node_bytes));
                        pass.draw(0..3, 0..network.node_count);
                    }
                }
            }
        }
    }
}

/// A viewport pass into `color` and `depth`: colour loaded by `load`, depth cleared (and kept
/// for later passes) when `clear_depth`, else loaded.
fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    color: &wgpu::TextureView,
    depth: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
    clear_depth: bool,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("viewport"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: color,
            resolve_target: None,
            ops: wgpu::Operations {
                load,
                store: wgpu::StoreOp::Store,
            },
            depth_slice: None,
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations {
                load: if clear_depth {
                    wgpu::LoadOp::Clear(1.0)
                } else {
                    wgpu::LoadOp::Load
                },
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        ..Default::default()
    })
}

/// Node markers would cover at least this share of the viewport when drawn side by side: the
/// network is then too dense for them to be told apart (its edges already show every node), so
/// only the edges are drawn. On lavapipe the 10,000 marker triangles of a 10k-node network cost
/// ~11 ms a frame at 1280×720 (21 → 27-28 fps without them); 1,000 nodes keep their markers.
pub const DENSE_MARKER_COVERAGE: f64 = 0.5;

/// Whether `nodes` markers of `point_px` pixels are drawn in a viewport of `size` pixels.
pub fn node_markers_visible(nodes: u32, point_px: f32, size: [u32; 2]) -> bool {
    let covered = f64::from(nodes) * f64::from(point_px) * f64::from(point_px);
    covered < DENSE_MARKER_COVERAGE * f64::from(size[0]) * f64::from(size[1])
}

/// A hash of everything that determines a viewport's image.
fn fingerprint<'i, 'a: 'i>(
    camera: &OrbitCamera,
    size: [u32; 2],
    items: impl IntoIterator<Item = &'i DrawItem<'a>>,
) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    let floats = |h: &mut std::collections::hash_map::DefaultHasher, values: &[f32]| {
        for v in values {
            v.to_bits().hash(h);
        }
    };
    floats(
        &mut h,
        &[
            camera.target.x,
            camera.target.y,
            camera.target.z,
            camera.distance,
            camera.yaw,
            camera.pitch,
            camera.fov_y,
            camera.scene_radius,
        ],
    );
    size.hash(&mut h);
    for item in items {
        match item {
            DrawItem::Surface {
                mesh,
                color,
                shading,
                texture,
            } => {
                (0u8, mesh.id, *shading == Shading::Smooth).hash(&mut h);
                texture.map(|t| t.id).hash(&mut h);
                floats(&mut h, color);
            }
            DrawItem::Wireframe { mesh, color } => {
                (1u8, mesh.id).hash(&mut h);
                floats(&mut h, color);
            }
            DrawItem::Overlay {
                mesh,
                color,
                texture,
            } => {
                (2u8, mesh.id, texture.map(|t| t.id)).hash(&mut h);
                floats(&mut h, color);
            }
            DrawItem::Network {
                network,
                node_color,
                edge_color,
                point_px,
            } => {
                (3u8, network.id).hash(&mut h);
                floats(&mut h, node_color);
                floats(&mut h, edge_color);
                floats(&mut h, &[*point_px]);
            }
        }
    }
    h.finish()
}

/// Copies one viewport's colour texture into egui's render pass (see [`SceneRenderer::paint_callback`]).
pub struct ViewportCallback {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
}

impl egui_wgpu::CallbackTrait for ViewportCallback {
    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        render_pass: &mut wgpu::RenderPass<'static>,
        _resources: &egui_wgpu::CallbackResources,
    ) {
        // egui has set the viewport to the callback's rectangle: one triangle covers it.
        render_pass.set_pipeline(&self.pipeline);
        render_pass.set_bind_group(0, &self.bind_group, &[]);
        render_pass.draw(0..3, 0..1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_markers_are_dropped_only_when_they_would_cover_half_the_view() {
        // 463×471 px, the GNG viewport at 1280×720; 4 px markers.
        let size = [463, 471];
        assert!(node_markers_visible(1_000, 4.0, size));
        assert!(node_markers_visible(6_000, 4.0, size));
        assert!(!node_markers_visible(10_000, 4.0, size));
        // Smaller markers or a bigger view bring them back.
        assert!(node_markers_visible(10_000, 2.0, size));
        assert!(node_markers_visible(10_000, 4.0, [1200, 900]));
    }
}

//! wgpu rendering of the 3D viewports: GPU copies of meshes and of the live
//! network, and pipelines that draw them with depth into an offscreen colour+depth target per
//! viewport. Each target is copied into egui's render pass by a paint callback
//! ([`ViewportCallback`]): one texel load per pixel, which on a CPU rasterizer (lavapipe) costs a
//! fraction of egui's own textured-quad shader.
//!
//! (Over ~700 lines on purpose: five pipelines, their vertex layouts and the targets share one
//! bind-group layout and uniform stride; splitting them would spread one GPU contract over files.)

pub use crate::camera::OrbitCamera;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use mesh::TriMesh;
use std::hash::{Hash, Hasher};
use std::sync::atomic::{AtomicU64, Ordering};
use wgpu::util::DeviceExt;

/// Colour format of the offscreen targets: the bytes are shown on screen as they are.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The same bytes read as sRGB, for copying them unchanged into an sRGB render target.
const COLOR_FORMAT_SRGB: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// How a viewport's bytes (already display-encoded, see [`COLOR_FORMAT`]) reach egui's render
/// target unchanged. Chosen from the output format and the adapter's capabilities: OpenGL ES
/// (Mesa llvmpipe via EGL, `WGPU_BACKEND=gl`) has no `DownlevelFlags::VIEW_FORMATS`, and asking
/// for an sRGB view there is a validation error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CopyMode {
    /// The output is not sRGB: read the bytes as they are.
    Direct,
    /// sRGB output, reinterpreting views supported: read through an sRGB view of the texture,
    /// so the hardware decode and the output's encode cancel exactly.
    SrgbView,
    /// sRGB output without reinterpreting views: decode sRGB in the copy shader (a WGSL
    /// `override` constant, so the other modes pay nothing for it).
    DecodeInShader,
}

impl CopyMode {
    /// The mode for copying into `output_format` on a device with `downlevel` capabilities.
    pub fn choose(
        output_format: wgpu::TextureFormat,
        downlevel: &wgpu::DownlevelCapabilities,
    ) -> CopyMode {
        if !output_format.is_srgb() {
            CopyMode::Direct
        } else if downlevel.flags.contains(wgpu::DownlevelFlags::VIEW_FORMATS) {
            CopyMode::SrgbView
        } else {
            CopyMode::DecodeInShader
        }
    }

    /// Format of the view the copy shader reads.
    fn view_format(self) -> wgpu::TextureFormat {
        match self {
            CopyMode::SrgbView => COLOR_FORMAT_SRGB,
            CopyMode::Direct | CopyMode::DecodeInShader => COLOR_FORMAT,
        }
    }

    /// Extra view formats the colour texture must be created with (none unless reinterpreted).
    fn texture_view_formats(self) -> &'static [wgpu::TextureFormat] {
        match self {
            CopyMode::SrgbView => &[COLOR_FORMAT_SRGB],
            CopyMode::Direct | CopyMode::DecodeInShader => &[],
        }
    }
}
/// Depth format of the offscreen targets.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Clear colour of the viewports (RGB as shown on screen, 0–1).
pub const CLEAR_COLOR: [f64; 3] = [0.010, 0.012, 0.018];
/// Distance between per-draw uniform slots in bytes (wgpu's minimum dynamic offset alignment).
const UNIFORM_STRIDE: u64 = 256;
/// Draw calls one viewport can issue per frame.
const MAX_DRAWS: u64 = 8;

/// Per-draw uniforms, laid out like `Draw` in shader.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct DrawUniform {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light: [f32; 4],
    color: [f32; 4],
    params: [f32; 4],
    viewport: [f32; 4],
}

/// Vertex of a surface: position and smooth normal.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SurfaceVertex {
    position: [f32; 3],
    normal: [f32; 3],
}

/// A triangle mesh uploaded to the GPU: vertices with smooth normals, triangle indices and the
/// unique edges for wireframe.
pub struct GpuMesh {
    /// Unique per upload (part of a viewport's content fingerprint).
    id: u64,
    vertices: wgpu::Buffer,
    triangles: wgpu::Buffer,
    triangle_index_count: u32,
    edges: wgpu::Buffer,
    edge_index_count: u32,
    /// Vertex count of the source mesh.
    pub vertex_count: usize,
    /// Face count of the source mesh.
    pub face_count: usize,
}

impl GpuMesh {
    /// Upload `mesh` (vertex normals are computed here).
    pub fn new(device: &wgpu::Device, mesh: &TriMesh) -> GpuMesh {
        let normals = mesh.vertex_normals();
        let vertices: Vec<SurfaceVertex> = mesh
            .positions
            .iter()
            .zip(&normals)
            .map(|(p, n)| SurfaceVertex {
                position: p.to_array(),
                normal: n.to_array(),
            })
            .collect();
        let triangle_indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        // Wireframe: the unique edges from the mesh crate's one edge builder.
        let edges = mesh::topology::EdgeTable::new(mesh).edges;
        let edge_indices: Vec<u32> = edges.into_iter().flatten().collect();
        GpuMesh {
            id: NEXT_UPLOAD_ID.fetch_add(1, Ordering::Relaxed),
            vertices: buffer_init(
                device,
                "mesh vertices",
                &vertices,
                wgpu::BufferUsages::VERTEX,
            ),
            triangles: buffer_init(
                device,
                "mesh triangles",
                &triangle_indices,
                wgpu::BufferUsages::INDEX,
            ),
            triangle_index_count: triangle_indices.len() as u32,
            edges: buffer_init(
                device,
                "mesh edges",
                &edge_indices,
                wgpu::BufferUsages::INDEX,
            ),
            edge_index_count: edge_indices.len() as u32,
            vertex_count: mesh.vertex_count(),
            face_count: mesh.face_count(),
        }
    }
}

/// Source of [`GpuMesh`] and [`GpuNetwork`] content ids.
static NEXT_UPLOAD_ID: AtomicU64 = AtomicU64::new(1);

/// Create a buffer holding `data` (at least 16 bytes so empty data stays valid).
fn buffer_init<T: Pod>(
    device: &wgpu::Device,
    label: &str,
    data: &[T],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let bytes: &[u8] = bytemuck::cast_slice(data);
    if bytes.is_empty() {
        return device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: 16,
            usage,
            mapped_at_creation: false,
        });
    }
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage,
    })
}

/// The live GNG network on the GPU: node positions (instanced points, line vertices) and edges.
pub struct GpuNetwork {
    positions: wgpu::Buffer,
    position_capacity: u64,
    edges: wgpu::Buffer,
    edge_capacity: u64,
    node_count: u32,
    edge_index_count: u32,
    /// Unique per update (part of a viewport's content fingerprint).
    id: u64,
}

impl GpuNetwork {
    /// An empty network.
    pub fn new(device: &wgpu::Device) -> GpuNetwork {
        GpuNetwork {
            positions: growable(device, "network nodes", 4096, wgpu::BufferUsages::VERTEX),
            position_capacity: 4096,
            edges: growable(device, "network edges", 4096, wgpu::BufferUsages::INDEX),
            edge_capacity: 4096,
            node_count: 0,
            edge_index_count: 0,
            id: NEXT_UPLOAD_ID.fetch_add(1, Ordering::Relaxed),
        }
    }

    /// Replace the network with `positions` and `edges` (buffers grow geometrically).
    pub fn update(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        positions: &[Vec3],
        edges: &[[u32; 2]],
    ) {
        let position_bytes: &[u8] = bytemuck::cast_slice(positions);
        let edge_bytes: &[u8] = bytemuck::cast_slice(edges);
        if position_bytes.len() as u64 > self.position_capacity {
            self.position_capacity = (position_bytes.len() as u64).next_power_of_two();
            self.positions = growable(
                device,
                "network nodes",
                self.position_capacity,
                wgpu::BufferUsages::VERTEX,
            );
        }
        if edge_bytes.len() as u64 > self.edge_capacity {
            self.edge_capacity = (edge_bytes.len() as u64).next_power_of_two();
            self.edges = growable(
                device,
                "network edges",
                self.edge_capacity,
                wgpu::BufferUsages::INDEX,
            );
        }
        if !position_bytes.is_empty() {
            queue.write_buffer(&self.positions, 0, position_bytes);
        }
        if !edge_bytes.is_empty() {
            queue.write_buffer(&self.edges, 0, edge_bytes);
        }
        self.node_count = positions.len() as u32;
        // Only edges whose endpoints exist are drawn; the worker guarantees that.
        self.edge_index_count = (edges.len() * 2) as u32;
        self.id = NEXT_UPLOAD_ID.fetch_add(1, Ordering::Relaxed);
    }

    /// Number of nodes currently uploaded.
    pub fn node_count(&self) -> u32 {
        self.node_count
    }
}

fn growable(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16).next_multiple_of(4),
        usage: usage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// How surfaces are shaded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shading {
    /// One normal per triangle (from screen-space derivatives).
    Flat,
    /// Interpolated area-weighted vertex normals.
    Smooth,
}

/// One thing to draw into a viewport.
pub enum DrawItem<'a> {
    /// An opaque lit surface.
    Surface {
        /// The mesh.
        mesh: &'a GpuMesh,
        /// RGB base colour (as shown on screen, 0–1).
        color: [f32; 3],
        /// Flat or smooth.
        shading: Shading,
    },
    /// The mesh's edges as lines.
    Wireframe {
        /// The mesh.
        mesh: &'a GpuMesh,
        /// RGBA line colour.
        color: [f32; 4],
    },
    /// A translucent lit surface drawn over everything else (the "original" overlay).
    Overlay {
        /// The mesh.
        mesh: &'a GpuMesh,
        /// RGB colour and opacity.
        color: [f32; 4],
    },
    /// GNG nodes as round points and GNG edges as lines.
    Network {
        /// The network.
        network: &'a GpuNetwork,
        /// RGB node colour.
        node_color: [f32; 3],
        /// RGBA edge colour.
        edge_color: [f32; 4],
        /// Node diameter in pixels.
        point_px: f32,
    },
}

/// An offscreen colour+depth target registered with egui as a texture.
pub struct ViewTarget {
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    /// Everything but the live network, drawn when it or the camera changes (see `render`).
    layer: wgpu::Texture,
    layer_view: wgpu::TextureView,
    /// Fingerprint of what `layer` shows.
    layer_content: Option<u64>,
    depth_view: wgpu::TextureView,
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// Binds the colour texture to the copy pipeline.
    blit_group: wgpu::BindGroup,
    /// Fingerprint of what the colour texture shows (camera, size, items); `None`: nothing yet.
    content: Option<u64>,
    /// Size in pixels.
    pub size: [u32; 2],
}

impl ViewTarget {
    /// The colour texture (for read-back in tests and screenshots).
    pub fn color_texture(&self) -> &wgpu::Texture {
        &self.color
    }
}

/// Pipelines shared by all viewports.
pub struct SceneRenderer {
    layout: wgpu::BindGroupLayout,
    blit_layout: wgpu::BindGroupLayout,
    blit: wgpu::RenderPipeline,
    /// How the copy pipeline reads the colour textures (matches the output's encoding).
    copy_mode: CopyMode,
    surface: wgpu::RenderPipeline,
    overlay: wgpu::RenderPipeline,
    mesh_lines: wgpu::RenderPipeline,
    network_lines: wgpu::RenderPipeline,
    points: wgpu::RenderPipeline,
}

impl SceneRenderer {
    /// Compile the shaders and build the pipelines; `output_format` is the format of egui's
    /// render target (`RenderState::target_format`), into which the viewports are copied, and
    /// `copy_mode` how (see [`CopyMode::choose`]).
    pub fn new(
        device: &wgpu::Device,
        output_format: wgpu::TextureFormat,
        copy_mode: CopyMode,
    ) -> SceneRenderer {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("viewer shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("viewer draw uniforms"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(size_of::<DrawUniform>() as u64),
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("viewer pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let surface_vertex = wgpu::VertexBufferLayout {
            array_stride: size_of::<SurfaceVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
        };
        let surface_position_only = wgpu::VertexBufferLayout {
            array_stride: size_of::<SurfaceVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
        };
        let node_vertex = wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
        };
        let node_instance = wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
        };
        let premultiplied = Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING);
        let make = |label: &str,
                    vs: &str,
                    fs: &str,
                    buffer: wgpu::VertexBufferLayout<'_>,
                    topology: wgpu::PrimitiveTopology,
                    depth_write: bool,
                    blend: Option<wgpu::BlendState>| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vs),
                    buffers: &[Some(buffer)],
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(wgpu::CompareFunction::LessEqual),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: COLOR_FORMAT,
                        blend,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let tri = wgpu::PrimitiveTopology::TriangleList;
        let lines = wgpu::PrimitiveTopology::LineList;
        let (blit_layout, blit) = blit_pipeline(device, output_format, copy_mode);
        SceneRenderer {
            blit_layout,
            blit,
            copy_mode,
            surface: make(
                "surface",
                "vs_surface",
                "fs_surface",
                surface_vertex.clone(),
                tri,
                true,
                None,
            ),
            overlay: make(
                "overlay",
                "vs_surface",
                "fs_surface",
                surface_vertex,
                tri,
                false,
                premultiplied,
            ),
            mesh_lines: make(
                "mesh lines",
                "vs_line",
                "fs_line",
                surface_position_only,
                lines,
                true,
                premultiplied,
            ),
            network_lines: make(
                "network lines",
                "vs_line",
                "fs_line",
                node_vertex,
                lines,
                false,
                premultiplied,
            ),
            points: make(
                "points",
                "vs_point",
                "fs_point",
                node_instance,
                tri,
                false,
                None,
            ),
            layout,
        }
    }

    /// A new viewport target of `size` pixels.
    pub fn create_target(&self, device: &wgpu::Device, size: [u32; 2]) -> ViewTarget {
        let size = clamp_target_size(size);
        let (color, color_view, depth_view) =
            make_textures(device, size, self.copy_mode.texture_view_formats());
        let layer = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("viewport layer"),
            size: color.size(),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let layer_view = layer.create_view(&wgpu::TextureViewDescriptor::default());
        let blit_group = self.blit_group(device, &color);
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("viewport uniforms"),
            size: UNIFORM_STRIDE * MAX_DRAWS,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewport bind group"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &uniforms,
                    offset: 0,
                    size: wgpu::BufferSize::new(size_of::<DrawUniform>() as u64),
                }),
            }],
        });
        ViewTarget {
            color,
            color_view,
            layer,
            layer_view,
            layer_content: None,
            depth_view,
            uniforms,
            bind_group,
            blit_group,
            content: None,
            size,
        }
    }

    /// Resize `target` to `size` pixels (no-op when unchanged): a new target replaces it.
    pub fn resize_target(&self, device: &wgpu::Device, target: &mut ViewTarget, size: [u32; 2]) {
        if target.size != clamp_target_size(size) {
            *target = self.create_target(device, size);
        }
    }

    /// The bind group through which the copy pipeline reads `color`.
    fn blit_group(&self, device: &wgpu::Device, color: &wgpu::Texture) -> wgpu::BindGroup {
        let view = color.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.copy_mode.view_format()),
            ..Default::default()
        });
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewport copy bind group"),
            layout: &self.blit_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&view),
            }],
        })
    }

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
        for &i in order {
            let item = &items[i];
            let (main_slot, edge_slot) = slot_of[i];
            let offset = (main_slot as u64 * UNIFORM_STRIDE) as u32;
            pass.set_bind_group(0, &target.bind_group, &[offset]);
            match item {
                DrawItem::Surface { mesh, .. } | DrawItem::Overlay { mesh, .. } => {
                    if mesh.triangle_index_count == 0 {
                        continue;
                    }
                    let pipeline = if matches!(item, DrawItem::Overlay { .. }) {
                        &self.overlay
                    } else {
                        &self.surface
                    };
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
            } => {
                (0u8, mesh.id, *shading == Shading::Smooth).hash(&mut h);
                floats(&mut h, color);
            }
            DrawItem::Wireframe { mesh, color } => {
                (1u8, mesh.id).hash(&mut h);
                floats(&mut h, color);
            }
            DrawItem::Overlay { mesh, color } => {
                (2u8, mesh.id).hash(&mut h);
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

/// A target size in pixels limited to 1..=8192 per side.
fn clamp_target_size(size: [u32; 2]) -> [u32; 2] {
    size.map(|s| s.clamp(1, 8192))
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

/// The pipeline that copies a viewport texture into a target of `output_format`, and its layout.
fn blit_pipeline(
    device: &wgpu::Device,
    output_format: wgpu::TextureFormat,
    copy_mode: CopyMode,
) -> (wgpu::BindGroupLayout, wgpu::RenderPipeline) {
    let decode = f64::from(u8::from(copy_mode == CopyMode::DecodeInShader));
    let constants = [("decode_srgb", decode)];
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("viewport copy shader"),
        source: wgpu::ShaderSource::Wgsl(include_str!("blit.wgsl").into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("viewport copy layout"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        }],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("viewport copy pipeline layout"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("viewport copy"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_blit"),
            buffers: &[],
            compilation_options: wgpu::PipelineCompilationOptions::default(),
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_blit"),
            targets: &[Some(wgpu::ColorTargetState {
                format: output_format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            },
        }),
        multiview_mask: None,
        cache: None,
    });
    (layout, pipeline)
}

fn make_textures(
    device: &wgpu::Device,
    size: [u32; 2],
    view_formats: &[wgpu::TextureFormat],
) -> (wgpu::Texture, wgpu::TextureView, wgpu::TextureView) {
    let extent = wgpu::Extent3d {
        width: size[0].max(1),
        height: size[1].max(1),
        depth_or_array_layers: 1,
    };
    let color = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("viewport colour"),
        size: extent,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: COLOR_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats,
    });
    let depth = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("viewport depth"),
        size: extent,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let color_view = color.create_view(&wgpu::TextureViewDescriptor::default());
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor::default());
    (color, color_view, depth_view)
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

//! wgpu rendering of the 3D viewports: GPU copies of meshes and of the live
//! network, and pipelines that draw them with depth into an offscreen colour+depth target per
//! viewport. Each target is copied into egui's render pass by a paint callback
//! ([`ViewportCallback`]): one texel load per pixel, which on a CPU rasterizer (lavapipe) costs a
//! fraction of egui's own textured-quad shader.
//!
//! This file holds the formats, the GPU copies and the types the viewports share; `setup`
//! builds the pipelines and targets, `frame` records each frame's drawing, `texture` uploads a
//! model's base-colour texture, and the WGSL shaders sit beside them (`shader.wgsl` for the
//! scene, `blit.wgsl` for the copy).

mod frame;
mod setup;
mod texture;

pub use crate::camera::OrbitCamera;
use bytemuck::{Pod, Zeroable};
pub use frame::*;
use glam::{Vec2, Vec3};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use std::hash::{Hash, Hasher};
use std::sync::atomic::{AtomicU64, Ordering};
use wgpu::BufferUsages;
use wgpu::util::DeviceExt;

pub use texture::GpuTexture;

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

/// Vertex of a surface: position, smooth normal and texture coordinates (zero without any; v
/// pointing down the image, as the GPU samples it).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SurfaceVertex {
    position: [f32; 3],
    normal: [f32; 3],
    uv: [f32; 2],
}

/// Texture coordinates to draw a mesh with: its attributes' UV0 and the image's convention
/// ([`metrics::Texture::v_down`]).
#[derive(Clone, Copy)]
pub struct Uvs<'a> {
    /// The mesh's attributes (used when they have UV0).
    pub attributes: &'a Attributes,
    /// Whether v = 0 is the image's top row (glTF) rather than its bottom row (OBJ).
    pub v_down: bool,
}

/// A triangle mesh uploaded to the GPU: vertices with smooth normals (and texture coordinates
/// when it has them), triangle indices and the unique edges for wireframe.
pub struct GpuMesh {
    /// Unique per upload (part of a viewport's content fingerprint).
    id: u64,
    vertices: wgpu::Buffer,
    triangles: wgpu::Buffer,
    triangle_index_count: u32,
    edges: wgpu::Buffer,
    edge_index_count: u32,
    /// Whether the vertices carry texture coordinates (a texture can be drawn on it).
    pub has_uvs: bool,
    /// Vertex count of the source mesh.
    pub vertex_count: usize,
    /// Face count of the source mesh.
    pub face_count: usize,
}

impl GpuMesh {
    /// Upload `mesh` (vertex normals are computed here). With `uvs` whose attributes have UV0
    /// (and fit the mesh) one GPU vertex is drawn per wedge, so the texture coordinates split
    /// at their seams while positions and normals stay the vertex's: the same surface, shaded
    /// the same.
    pub fn new(device: &wgpu::Device, mesh: &TriMesh, uvs: Option<Uvs<'_>>) -> GpuMesh {
        let normals = mesh.vertex_normals();
        let vertex = |v: usize, uv: Vec2| SurfaceVertex {
            position: mesh.positions[v].to_array(),
            normal: normals[v].to_array(),
            uv: uv.to_array(),
        };
        // Wireframe: the unique edges from the mesh crate's one edge builder.
        let edges = mesh::topology::EdgeTable::new(mesh).edges;
        let wedges = uvs.and_then(|u| {
            let uv0 = u.attributes.uv0.as_ref()?;
            u.attributes.validate(mesh).ok()?;
            let v_down = u.v_down;
            let flip = move |t: Vec2| if v_down { t } else { Vec2::new(t.x, 1.0 - t.y) };
            Some((u.attributes, uv0, flip))
        });
        let (vertices, triangle_indices, edge_indices): (Vec<_>, Vec<u32>, Vec<u32>) = match wedges
        {
            Some((attributes, uv0, flip)) => {
                // Each position vertex's first wedge carries its edges.
                let mut wedge_of = vec![0u32; mesh.vertex_count()];
                for (w, &v) in attributes.wedge_vertex.iter().enumerate().rev() {
                    wedge_of[v as usize] = w as u32;
                }
                (
                    attributes
                        .wedge_vertex
                        .iter()
                        .zip(uv0)
                        .map(|(&v, &t)| vertex(v as usize, flip(t)))
                        .collect(),
                    attributes.corners.iter().flatten().copied().collect(),
                    edges
                        .iter()
                        .flatten()
                        .map(|&v| wedge_of[v as usize])
                        .collect(),
                )
            }
            None => (
                (0..mesh.vertex_count())
                    .map(|v| vertex(v, Vec2::ZERO))
                    .collect(),
                mesh.triangles.iter().flatten().copied().collect(),
                edges.into_iter().flatten().collect(),
            ),
        };
        GpuMesh {
            id: NEXT_UPLOAD_ID.fetch_add(1, Ordering::Relaxed),
            vertices: buffer_init(device, "mesh vertices", &vertices, BufferUsages::VERTEX),
            triangles: buffer_init(
                device,
                "mesh triangles",
                &triangle_indices,
                BufferUsages::INDEX,
            ),
            triangle_index_count: triangle_indices.len() as u32,
            edges: buffer_init(device, "mesh edges", &edge_indices, BufferUsages::INDEX),
            edge_index_count: edge_indices.len() as u32,
            has_uvs: wedges.is_some(),
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
    usage: BufferUsages,
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
            positions: growable(device, "network nodes", 4096, BufferUsages::VERTEX),
            position_capacity: 4096,
            edges: growable(device, "network edges", 4096, BufferUsages::INDEX),
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
        write_growing(
            device,
            queue,
            &mut self.positions,
            &mut self.position_capacity,
            bytemuck::cast_slice(positions),
            "network nodes",
            BufferUsages::VERTEX,
        );
        write_growing(
            device,
            queue,
            &mut self.edges,
            &mut self.edge_capacity,
            bytemuck::cast_slice(edges),
            "network edges",
            BufferUsages::INDEX,
        );
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

/// Write `bytes` at the start of a growable `buffer` of `capacity` bytes, first replacing it
/// with one of the next power of two (`label`, `usage`) when `bytes` do not fit.
fn write_growing(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &mut wgpu::Buffer,
    capacity: &mut u64,
    bytes: &[u8],
    label: &str,
    usage: BufferUsages,
) {
    if bytes.len() as u64 > *capacity {
        *capacity = (bytes.len() as u64).next_power_of_two();
        *buffer = growable(device, label, *capacity, usage);
    }
    if !bytes.is_empty() {
        queue.write_buffer(buffer, 0, bytes);
    }
}

/// A buffer of at least `size` bytes that can be written to (`usage` plus `COPY_DST`).
fn growable(device: &wgpu::Device, label: &str, size: u64, usage: BufferUsages) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16).next_multiple_of(4),
        usage: usage | BufferUsages::COPY_DST,
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
        /// The base-colour texture drawn instead of `color` (the mesh has texture coordinates).
        texture: Option<&'a GpuTexture>,
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
        /// The base-colour texture drawn instead of the colour's RGB (the mesh has texture
        /// coordinates).
        texture: Option<&'a GpuTexture>,
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
    /// Layout of the base-colour texture's group (1).
    texture_layout: wgpu::BindGroupLayout,
    /// Bound as group 1 for untextured draws.
    blank: GpuTexture,
    blit_layout: wgpu::BindGroupLayout,
    blit: wgpu::RenderPipeline,
    /// How the copy pipeline reads the colour textures (matches the output's encoding).
    copy_mode: CopyMode,
    surface: wgpu::RenderPipeline,
    overlay: wgpu::RenderPipeline,
    /// `surface` and `overlay` coloured by the base-colour texture.
    surface_textured: wgpu::RenderPipeline,
    overlay_textured: wgpu::RenderPipeline,
    mesh_lines: wgpu::RenderPipeline,
    network_lines: wgpu::RenderPipeline,
    points: wgpu::RenderPipeline,
}

/// A target size in pixels limited to 1..=8192 per side.
fn clamp_target_size(size: [u32; 2]) -> [u32; 2] {
    size.map(|s| s.clamp(1, 8192))
}

//! The base-colour texture on the GPU: a model's decoded image ([`metrics::Texture`]) uploaded
//! once as an sRGB texture with a linear, repeating sampler, bound as the surface shader's group 1
//! ([`GpuTexture`]), and the 1×1 white stand-in bound for untextured draws.

use super::{NEXT_UPLOAD_ID, SceneRenderer};
use std::sync::atomic::Ordering;

/// A base-colour texture uploaded and bound for the surface shader.
pub struct GpuTexture {
    /// Unique per upload (part of a viewport's content fingerprint).
    pub(super) id: u64,
    pub(super) bind_group: wgpu::BindGroup,
    /// Width and height in texels.
    pub size: [u32; 2],
}

/// The layout of the surface shader's group 1: the base-colour texture and its sampler.
pub(super) fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty,
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("base colour layout"),
        entries: &[
            entry(
                0,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
            ),
            entry(
                1,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            ),
        ],
    })
}

impl GpuTexture {
    /// Upload `rgba` (8-bit sRGB RGBA rows from the top, `size` texels) bound through `layout`
    /// ([`layout`]).
    pub(super) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layout: &wgpu::BindGroupLayout,
        size: [u32; 2],
        rgba: &[u8],
    ) -> GpuTexture {
        let extent = wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        };
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("base colour"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        queue.write_texture(
            texture.as_image_copy(),
            rgba,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * size[0]),
                rows_per_image: Some(size[1]),
            },
            extent,
        );
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("base colour sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("base colour bind group"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
            ],
        });
        GpuTexture {
            id: NEXT_UPLOAD_ID.fetch_add(1, Ordering::Relaxed),
            bind_group,
            size,
        }
    }

    /// The 1×1 white texture bound for untextured draws (the shader does not use it there).
    pub(super) fn blank(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layout: &wgpu::BindGroupLayout,
    ) -> GpuTexture {
        GpuTexture::new(device, queue, layout, [1, 1], &[255; 4])
    }
}

impl SceneRenderer {
    /// `texture` uploaded for drawing on meshes with texture coordinates
    /// ([`super::DrawItem::Surface`]'s `texture`).
    pub fn upload_texture(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        texture: &metrics::Texture,
    ) -> GpuTexture {
        GpuTexture::new(
            device,
            queue,
            &self.texture_layout,
            texture.size(),
            &texture.rgba8(),
        )
    }
}

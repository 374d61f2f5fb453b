//! Pipeline setup: the scene's seven pipelines and the copy pipeline compiled from the WGSL
//! shaders beside this file, and the offscreen targets (colour, layer, depth, uniforms) they
//! draw into. The scene's pipelines share one layout: the per-draw uniforms (group 0) and the
//! base-colour texture (group 1, see `texture`).

use super::*;

impl SceneRenderer {
    /// Compile the shaders and build the pipelines; `output_format` is the format of egui's
    /// render target (`RenderState::target_format`), into which the viewports are copied, and
    /// `copy_mode` how (see [`CopyMode::choose`]); `queue` uploads the blank texture of
    /// untextured draws.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        output_format: wgpu::TextureFormat,
        copy_mode: CopyMode,
    ) -> SceneRenderer {
        let texture_layout = texture::layout(device);
        let (module, layout, pipeline_layout) = shader_and_layout(
            device,
            "viewer",
            include_str!("shader.wgsl"),
            wgpu::ShaderStages::VERTEX_FRAGMENT,
            wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(size_of::<DrawUniform>() as u64),
            },
            &[&texture_layout],
        );
        let surface_vertex = wgpu::VertexBufferLayout {
            array_stride: size_of::<SurfaceVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2],
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
            blank: GpuTexture::blank(device, queue, &texture_layout),
            texture_layout,
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
                surface_vertex.clone(),
                tri,
                false,
                premultiplied,
            ),
            surface_textured: make(
                "textured surface",
                "vs_surface",
                "fs_surface_textured",
                surface_vertex.clone(),
                tri,
                true,
                None,
            ),
            overlay_textured: make(
                "textured overlay",
                "vs_surface",
                "fs_surface_textured",
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
            usage: BufferUsages::UNIFORM | BufferUsages::COPY_DST,
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
}

/// The WGSL `source` compiled, a bind group layout of one `binding` at 0 seen by `visibility`,
/// and the pipeline layout of that group followed by the `later` groups; `name` starts their
/// labels.
fn shader_and_layout(
    device: &wgpu::Device,
    name: &str,
    source: &str,
    visibility: wgpu::ShaderStages,
    binding: wgpu::BindingType,
    later: &[&wgpu::BindGroupLayout],
) -> (
    wgpu::ShaderModule,
    wgpu::BindGroupLayout,
    wgpu::PipelineLayout,
) {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(&format!("{name} shader")),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(&format!("{name} layout")),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility,
            ty: binding,
            count: None,
        }],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("{name} pipeline layout")),
        bind_group_layouts: &std::iter::once(Some(&layout))
            .chain(later.iter().map(|l| Some(*l)))
            .collect::<Vec<_>>(),
        immediate_size: 0,
    });
    (module, layout, pipeline_layout)
}

/// The pipeline that copies a viewport texture into a target of `output_format`, and its layout.
fn blit_pipeline(
    device: &wgpu::Device,
    output_format: wgpu::TextureFormat,
    copy_mode: CopyMode,
) -> (wgpu::BindGroupLayout, wgpu::RenderPipeline) {
    let decode = f64::from(u8::from(copy_mode == CopyMode::DecodeInShader));
    let constants = [("decode_srgb", decode)];
    let (module, layout, pipeline_layout) = shader_and_layout(
        device,
        "viewport copy",
        include_str!("blit.wgsl"),
        wgpu::ShaderStages::FRAGMENT,
        wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        &[],
    );
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

// Copies a viewport's offscreen colour texture into egui's render pass, one texel per pixel.
// egui sets the viewport to the destination rectangle; the texture has (about) its pixel size.

@group(0) @binding(0) var source: texture_2d<f32>;

// True when the output is sRGB but the texture cannot be read through an sRGB view (OpenGL ES
// without VIEW_FORMATS): decode here so the output's encode restores the same bytes.
override decode_srgb: bool = false;

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

struct BlitOut {
    @builtin(position) clip: vec4<f32>,
    // 0..1 across the viewport (the triangle overshoots to 2)
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_blit(@builtin(vertex_index) index: u32) -> BlitOut {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var o: BlitOut;
    o.clip = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    o.uv = uv;
    return o;
}

@fragment
fn fs_blit(i: BlitOut) -> @location(0) vec4<f32> {
    let size = textureDimensions(source);
    let texel = min(vec2<u32>(i.uv * vec2<f32>(size)), size - vec2<u32>(1u, 1u));
    let c = textureLoad(source, texel, 0);
    if decode_srgb {
        return vec4<f32>(srgb_to_linear(c.rgb), c.a);
    }
    return c;
}

// Viewer shaders: lit surfaces (flat via screen-space derivatives or smooth via vertex normals;
// coloured by the draw's colour or the base-colour texture), unlit lines (GNG edges, wireframe)
// and round screen-space points (GNG nodes).

struct Draw {
    view_proj: mat4x4<f32>,
    // xyz: camera position (model units)
    eye: vec4<f32>,
    // xyz: direction towards the key light
    light: vec4<f32>,
    // RGB as shown on screen (the target stores bytes unconverted), alpha (premultiplied on output)
    color: vec4<f32>,
    // x: 0 flat / 1 smooth shading, y: depth pull towards the camera (NDC), z: point diameter (px)
    params: vec4<f32>,
    // xy: target size in pixels
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Draw;
// The base-colour texture of fs_surface_textured (sRGB: sampled and filtered in linear light).
@group(1) @binding(0) var base_map: texture_2d<f32>;
@group(1) @binding(1) var base_sampler: sampler;

struct SurfaceOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

// Linear light back to the sRGB values shown on screen (the target stores them unconverted).
fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

@vertex
fn vs_surface(
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
) -> SurfaceOut {
    var o: SurfaceOut;
    var clip = u.view_proj * vec4<f32>(pos, 1.0);
    clip.z = clip.z - u.params.y * clip.w;
    o.clip = clip;
    o.world = pos;
    o.normal = normal;
    o.uv = uv;
    return o;
}

// A surface of the draw's colour.
@fragment
fn fs_surface(i: SurfaceOut) -> @location(0) vec4<f32> {
    return lit(i, u.color.rgb);
}

// A surface of the base-colour texture (the draw's alpha).
@fragment
fn fs_surface_textured(i: SurfaceOut) -> @location(0) vec4<f32> {
    return lit(i, srgb_encode(textureSample(base_map, base_sampler, i.uv).rgb));
}

// `base` (as shown on screen) lit by the key light and a fill light from the camera, with the
// draw's alpha premultiplied.
fn lit(i: SurfaceOut, base: vec3<f32>) -> vec4<f32> {
    let face = cross(dpdx(i.world), dpdy(i.world));
    var n = normalize(face);
    if (u.params.x > 0.5 && dot(i.normal, i.normal) > 1e-12) {
        n = normalize(i.normal);
    }
    let v = normalize(u.eye.xyz - i.world);
    if (dot(n, v) < 0.0) {
        n = -n;
    }
    let l = normalize(u.light.xyz);
    let diffuse = max(dot(n, l), 0.0);
    let fill = max(dot(n, v), 0.0);
    let h = normalize(l + v);
    let specular = pow(max(dot(n, h), 0.0), 48.0) * 0.2;
    let rgb = base * (0.10 + 0.65 * diffuse + 0.30 * fill) + vec3<f32>(specular);
    return vec4<f32>(rgb * u.color.a, u.color.a);
}

@vertex
fn vs_line(@location(0) pos: vec3<f32>) -> @builtin(position) vec4<f32> {
    var clip = u.view_proj * vec4<f32>(pos, 1.0);
    clip.z = clip.z - u.params.y * clip.w;
    return clip;
}

@fragment
fn fs_line() -> @location(0) vec4<f32> {
    return vec4<f32>(u.color.rgb * u.color.a, u.color.a);
}

struct PointOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) corner: vec2<f32>,
};

@vertex
fn vs_point(@builtin(vertex_index) vi: u32, @location(0) pos: vec3<f32>) -> PointOut {
    // One equilateral triangle circumscribing the unit disc (the fragment shader cuts the disc
    // out): a software rasterizer pays per primitive, so one triangle per node, not two.
    var corners = array<vec2<f32>, 3>(
        vec2<f32>(0.0, 2.0), vec2<f32>(-1.7320508, -1.0), vec2<f32>(1.7320508, -1.0),
    );
    let c = corners[vi % 3u];
    var clip = u.view_proj * vec4<f32>(pos, 1.0);
    clip.x = clip.x + c.x * u.params.z / u.viewport.x * clip.w;
    clip.y = clip.y + c.y * u.params.z / u.viewport.y * clip.w;
    clip.z = clip.z - u.params.y * clip.w;
    var o: PointOut;
    o.clip = clip;
    o.corner = c;
    return o;
}

@fragment
fn fs_point(i: PointOut) -> @location(0) vec4<f32> {
    let r2 = dot(i.corner, i.corner);
    if (r2 > 1.0) {
        discard;
    }
    let shade = 1.0 - 0.45 * r2;
    return vec4<f32>(u.color.rgb * shade, 1.0);
}

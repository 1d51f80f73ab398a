// The environment behind the mesh (shaders/README.md): a full-screen
// triangle at the far plane whose view ray d looks up the equirect map
// (BACKGROUND_MAP, bilinear, in the map's own frame env_from_world d:
// theta = acos(d.y), phi = atan2(d.z, d.x), u = phi / 2pi + 1/2, v = theta / pi)
// or evaluates the windowed SH reconstruction sum_l w_l sum_m L_lm Y_lm(d)
// (BACKGROUND_SH, what lmax keeps).

@group(0) @binding(2) var environment: texture_2d<f32>;

struct BackgroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn vs_background(@builtin(vertex_index) v: u32) -> BackgroundOut {
    // (-1,-1), (3,-1), (-1,3): one triangle covering the screen.
    let xy = vec2<f32>(f32((v << 1u) & 2u), f32(v & 2u)) * 2.0 - vec2<f32>(1.0);
    var out: BackgroundOut;
    out.clip = vec4<f32>(xy, 1.0, 1.0);
    out.ndc = xy;
    return out;
}

fn view_ray(ndc: vec2<f32>) -> vec3<f32> {
    let near = frame.inv_view_proj * vec4<f32>(ndc, 0.0, 1.0);
    let far = frame.inv_view_proj * vec4<f32>(ndc, 1.0, 1.0);
    return normalize(far.xyz / far.w - near.xyz / near.w);
}

fn map_texel(x: i32, y: i32) -> vec3<f32> {
    return textureLoad(environment, vec2<i32>(x, y), 0).rgb;
}

// Bilinear between the four nearest texel centres; columns wrap around,
// rows clamp at the poles.
fn map_radiance(d_world: vec3<f32>) -> vec3<f32> {
    let d = normalize((frame.env_from_world * vec4<f32>(d_world, 0.0)).xyz);
    let size = vec2<i32>(textureDimensions(environment));
    let theta = acos(clamp(d.y, -1.0, 1.0));
    let phi = atan2(d.z, d.x);
    let fx = (phi / (2.0 * SH_PI) + 0.5) * f32(size.x) - 0.5;
    let fy = theta / SH_PI * f32(size.y) - 0.5;
    let x0f = floor(fx);
    let y0f = floor(fy);
    let t = vec2<f32>(fx - x0f, fy - y0f);
    let xa = ((i32(x0f) % size.x) + size.x) % size.x;
    let xb = (xa + 1) % size.x;
    let ya = clamp(i32(y0f), 0, size.y - 1);
    let yb = clamp(i32(y0f) + 1, 0, size.y - 1);
    let top = mix(map_texel(xa, ya), map_texel(xb, ya), t.x);
    let bottom = mix(map_texel(xa, yb), map_texel(xb, yb), t.x);
    return mix(top, bottom, t.y);
}

@fragment
fn fs_background(in: BackgroundOut) -> @location(0) vec4<f32> {
    let d = view_ray(in.ndc);
    if frame.background == BACKGROUND_SH {
        return finish(sh_reconstruct(d, frame.radiance_band));
    }
    return finish(map_radiance(d));
}

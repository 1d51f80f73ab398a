// A glTF scene's surfaces (shaders/README.md): each unique primitive drawn
// once per instance, its material in bind group 1. What the surface passes
// share: the vertex and instance layout, the placing vertex stage, and the
// diffuse albedo at a fragment (shlight-mesh's Material::surface):
//
//   base   = baseColorFactor x baseColorTexture(uv) x COLOR_0
//   albedo = base.rgb x (1 - metallicFactor x metallicRoughnessTexture(uv).b)
//
// the base colour texture an sRGB texture (decoded by the GPU before
// filtering), mip-mapped; UVs are the texture's own set with its
// KHR_texture_transform already applied per vertex by the CPU (the
// transform is affine, so interpolating transformed UVs is transforming
// the interpolated UV). Alpha cuts the surface out: MASK discards
// fragments with base.a < alphaCutoff; BLEND discards by an ordered 4x4
// dither, keeping the fraction base.a of the fragments (coverage, as the
// bakes read BLEND; no sorting, no blending, the depth buffer stays
// right). Single-sided materials are drawn without their back faces (a
// pipeline with back-face culling, front faces clockwise for an instance
// that mirrors); double-sided ones with both, the normal flipped toward the
// viewer on the back.

struct Material {
    // baseColorFactor, linear RGBA.
    base_color: vec4<f32>,
    // metallicFactor.
    metallic: f32,
    // alphaCutoff (ALPHA_MASK).
    cutoff: f32,
    // ALPHA_* below.
    alpha_mode: u32,
}

const ALPHA_OPAQUE: u32 = 0u;
const ALPHA_MASK: u32 = 1u;
const ALPHA_BLEND: u32 = 2u;

@group(1) @binding(0) var<uniform> material: Material;
// White where the material has no such texture.
@group(1) @binding(1) var base_color_texture: texture_2d<f32>;
@group(1) @binding(2) var base_color_sampler: sampler;
@group(1) @binding(3) var metal_texture: texture_2d<f32>;
@group(1) @binding(4) var metal_sampler: sampler;

struct SurfaceVertexIn {
    // Per vertex, in the primitive's own space.
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The base colour texture's UV, and the metallic-roughness texture's.
    @location(2) uv: vec2<f32>,
    @location(3) uv_metal: vec2<f32>,
    // COLOR_0, linear RGBA (white without one).
    @location(4) color: vec4<f32>,
    // Emitted radiance (the volume pass adds it).
    @location(5) emission: vec3<f32>,
    // Per instance: world from the primitive's space (columns), and its
    // inverse transpose for normals (xyz of three columns).
    @location(6) model_0: vec4<f32>,
    @location(7) model_1: vec4<f32>,
    @location(8) model_2: vec4<f32>,
    @location(9) model_3: vec4<f32>,
    @location(10) normal_0: vec4<f32>,
    @location(11) normal_1: vec4<f32>,
    @location(12) normal_2: vec4<f32>,
    // TEXCOORD_1 (0 without one), and per instance its node's lightmap
    // scaleOffset (su, sv, ou, ov): all 0 where the node has no lightmap.
    @location(13) uv_lightmap: vec2<f32>,
    @location(14) lightmap_scale_offset: vec4<f32>,
}

struct SurfaceVertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) uv_metal: vec2<f32>,
    @location(4) color: vec4<f32>,
    @location(5) emission: vec3<f32>,
    // PRT: the vertex's transferred radiance per unit albedo, and its
    // static exit radiance (surface.wgsl).
    @location(6) prt: vec3<f32>,
    @location(7) prt_static: vec3<f32>,
    // The lightmap atlas UV, and 1 where the instance's node is baked.
    @location(8) lightmap_uv: vec2<f32>,
    @location(9) @interpolate(flat) lightmap_baked: u32,
}

// The vertex placed by its instance.
fn surface_vertex(in: SurfaceVertexIn) -> SurfaceVertexOut {
    var out: SurfaceVertexOut;
    let model = mat4x4<f32>(in.model_0, in.model_1, in.model_2, in.model_3);
    let normals = mat3x3<f32>(in.normal_0.xyz, in.normal_1.xyz, in.normal_2.xyz);
    let world = model * vec4<f32>(in.position, 1.0);
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = normals * in.normal;
    out.uv = in.uv;
    out.uv_metal = in.uv_metal;
    out.color = in.color;
    out.emission = in.emission;
    out.prt = vec3<f32>(0.0);
    out.prt_static = vec3<f32>(0.0);
    let so = in.lightmap_scale_offset;
    out.lightmap_uv = in.uv_lightmap * so.xy + so.zw;
    out.lightmap_baked = select(0u, 1u, any(so.xy != vec2<f32>(0.0)));
    return out;
}

// The threshold of a 4x4 ordered (Bayer) dither at a pixel, in (0, 1):
// (B + 1/2) / 16 with B the Bayer index
//    0  8  2 10
//   12  4 14  6
//    3 11  1  9
//   15  7 13  5
// (x across, y down), the bits of x ^ y and y interleaved and reversed.
fn dither_threshold(pixel: vec2<f32>) -> f32 {
    let p = vec2<u32>(pixel) % vec2<u32>(4u);
    let c = p.x ^ p.y;
    let b = ((c & 1u) << 3u) | ((p.y & 1u) << 2u) | (c & 2u) | ((p.y >> 1u) & 1u);
    return (f32(b) + 0.5) / 16.0;
}

// The diffuse albedo at a fragment; the fragment is discarded where the
// material cuts it out.
fn surface_albedo(in: SurfaceVertexOut) -> vec3<f32> {
    let base = material.base_color * in.color
        * textureSample(base_color_texture, base_color_sampler, in.uv);
    let metal = material.metallic * textureSample(metal_texture, metal_sampler, in.uv_metal).b;
    let mask = material.alpha_mode == ALPHA_MASK && base.a < material.cutoff;
    let blend = material.alpha_mode == ALPHA_BLEND && base.a < dither_threshold(in.clip.xy);
    if mask || blend {
        discard;
    }
    return base.rgb * (1.0 - clamp(metal, 0.0, 1.0));
}

// The unit normal on the side seen: flipped on a back face (drawn only
// for double-sided materials).
fn surface_normal(normal: vec3<f32>, front: bool) -> vec3<f32> {
    let n = normalize(normal);
    return select(-n, n, front);
}

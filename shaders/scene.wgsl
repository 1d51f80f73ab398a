// What the mesh and background passes share (shaders/README.md): the frame
// uniform, the light's SH coefficients, exposure and the named tone maps.

// Per-frame settings, written by shlight-gpu's `FrameUniform`.
struct Frame {
    // Clip from world.
    view_proj: mat4x4<f32>,
    // World from clip (background rays).
    inv_view_proj: mat4x4<f32>,
    // The environment map's own y-up frame from world: map frame, mirror and
    // the inverse of the environment's rotation (background lookups).
    env_from_world: mat4x4<f32>,
    // The unturned light's frame from world: R^T for a light turned by R
    // (MODE_ENCODED evaluates the unturned encoding at R^T n).
    light_from_world: mat4x4<f32>,
    // Per band l (element l/4, lane l%4): A_l w_l, irradiance from radiance
    // with the window w_l (A_l: Ramamoorthi & Hanrahan's clamped cosine).
    irradiance_band: array<vec4<f32>, 3>,
    // Per band: w_l, the windowed radiance reconstruction (background).
    radiance_band: array<vec4<f32>, 3>,
    // Lambertian albedo (rgb); outgoing radiance rho / pi E(n).
    albedo: vec4<f32>,
    // Linear scale 2^EV applied before the tone map.
    exposure: f32,
    // Highest degree of the light used (the PRT sum; the SH passes have it
    // built into their pipeline's sh_reconstruct).
    lmax: u32,
    // MODE_* below.
    mode: u32,
    // TONE_* below.
    tone_map: u32,
    // PRT transfer: highest degree and channels (1 or 3) per vertex.
    prt_lmax: u32,
    prt_channels: u32,
    // BACKGROUND_* below.
    background: u32,
    // 1: encode sRGB in the shader (the target is not an sRGB format).
    encode_srgb: u32,
    // The camera's position (xyz): glossy shading's view direction.
    eye: vec4<f32>,
    // Per band l (element l/4, lane l%4): the glossy lobe's Lambda_l.
    glossy_band: array<vec4<f32>, 3>,
    // Glossy transfer: basis vectors per cluster K (0 uncompressed), and
    // the first f32 of the parts in the transfer buffer (mesh.wgsl).
    glossy_vectors: u32,
    glossy_parts: u32,
    // A tabulated glossy lobe (GGX): the first f32 of its direction
    // weights in the transfer buffer, and their rows (0: a zonal lobe).
    ggx_table: u32,
    ggx_rows: u32,
    // Diffuse transfer with a static term (a glTF scene's lights and
    // emission, docs/shprt.md "Format version 3"): the first f32 of the
    // per-vertex RGB static exit radiance in the transfer buffer, after the
    // transfer (mesh.wgsl); 0 without one.
    prt_static: u32,
    // A lightmapped scene's texel format (LIGHTMAP_* of lightmap.wgsl; 0:
    // none) and its engine's units' scale (E = light / scale).
    lightmap: u32,
    lightmap_scale: f32,
}

const MODE_SH: u32 = 0u;
const MODE_PRT: u32 = 1u;
const MODE_NORMALS: u32 = 2u;
const MODE_ENCODED: u32 = 3u;
// MODE_PRT with glossy transfer (set by the renderer).
const MODE_GLOSSY: u32 = 4u;

const TONE_LINEAR: u32 = 0u;
const TONE_CLAMP: u32 = 1u;
const TONE_REINHARD: u32 = 2u;
const TONE_ACES: u32 = 3u;

const BACKGROUND_NONE: u32 = 0u;
const BACKGROUND_MAP: u32 = 1u;
const BACKGROUND_SH: u32 = 2u;

@group(0) @binding(0) var<uniform> frame: Frame;
// Radiance coefficients L_i (rgb), i < (lmax+1)^2, in shlight's basis. A
// uniform block: sh_reconstruct reads it at constant indices, which CPU
// rasterisers (llvmpipe) serve as one load for all lanes, where a storage
// buffer costs a bounds-checked load per lane.
@group(0) @binding(1) var<uniform> light: array<vec4<f32>, SH_MAX_COUNT>;

// sh_reconstruct(d: vec3<f32>, factors: array<vec4<f32>, 3>) -> vec3<f32>
// returns sum_l factors_l sum_m L_lm Y_lm(d) over the light's coefficients,
// factors_l = factors[l / 4][l % 4] (irradiance_band or radiance_band). It is
// written out as straight-line code for the pipeline's lmax and appended to
// the module (crates/shlight-gpu/src/sh_expansion.rs): no loops, no local
// arrays, every recurrence factor a literal.

// The curves of shlight-io's ToneMap, channel by channel; negatives and NaN give 0.
fn tone_map(x_in: vec3<f32>, curve: u32) -> vec3<f32> {
    let x = max(x_in, vec3<f32>(0.0));
    switch curve {
        case TONE_CLAMP: {
            return clamp(x, vec3<f32>(0.0), vec3<f32>(1.0));
        }
        case TONE_REINHARD: {
            return x / (vec3<f32>(1.0) + x);
        }
        case TONE_ACES: {
            let y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
            return clamp(y, vec3<f32>(0.0), vec3<f32>(1.0));
        }
        default: {
            return x_in;
        }
    }
}

fn srgb_encode(x: vec3<f32>) -> vec3<f32> {
    let lo = 12.92 * x;
    let hi = 1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, x <= vec3<f32>(0.0031308));
}

// Linear radiance to what the target stores: exposure, tone map, sRGB if asked.
fn finish(radiance: vec3<f32>) -> vec4<f32> {
    if frame.tone_map == TONE_LINEAR {
        return vec4<f32>(radiance * frame.exposure, 1.0);
    }
    var c = tone_map(radiance * frame.exposure, frame.tone_map);
    if frame.encode_srgb == 1u {
        c = srgb_encode(c);
    }
    return vec4<f32>(c, 1.0);
}

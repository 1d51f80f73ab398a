// A lightmapped scene's baked light (shaders/README.md), read as shlight
// sample reads it (shlight-pipeline's lightmap_irradiance): the pages are
// the layers of one rgba16float array texture (the half floats of the
// file's KTX2 pages, unchanged), read with a linear, clamp-to-edge sampler
// (bilinear between texel centres) at the fragment's atlas UV (TEXCOORD_1
// through its node's scaleOffset, per vertex: the map is affine), and the
// texel turned into light by the port of the engine's shader
// (shlight-lightmap's TexelFormat::reconstruct), divided by the engine's
// units (frame.lightmap_scale) to give E in W/m2.
//
// frame.lightmap (scene.wgsl) names the texel format, LIGHTMAP_* below; 0:
// no lightmap.

const LIGHTMAP_NONE: u32 = 0u;
// One layer: the texel's RGB.
const LIGHTMAP_IRRADIANCE: u32 = 1u;
// shlight's layout (three.js): l0, l1x, l1y, l1z as floats; linear, or
// Geomerics' non-linear reconstruction per channel.
const LIGHTMAP_SH_L1: u32 = 2u;
const LIGHTMAP_SH_L1_NON_LINEAR: u32 = 3u;
// Godot's directional lightmaps: l0, then l1y, l1z, l1x packed as
// L1 / (8 L0) + 1/2.
const LIGHTMAP_GODOT: u32 = 4u;
// Bakery's SH (l0, rnm0..2: L1 = (t * 2 - 1) * L0 * 2) and MonoSH (l0,
// one direction shared by the channels), linear or non-linear.
const LIGHTMAP_BAKERY_SH: u32 = 5u;
const LIGHTMAP_BAKERY_SH_NON_LINEAR: u32 = 6u;
const LIGHTMAP_MONOSH: u32 = 7u;
const LIGHTMAP_MONOSH_NON_LINEAR: u32 = 8u;

@group(0) @binding(3) var lightmap_pages: texture_2d_array<f32>;
@group(0) @binding(4) var lightmap_sampler: sampler;

// Page k at the atlas UV uv, filtered bilinearly.
fn lightmap_page(uv: vec2<f32>, k: i32) -> vec3<f32> {
    return textureSampleLevel(lightmap_pages, lightmap_sampler, uv, k, 0.0).rgb;
}

// Geomerics' non-linear reconstruction of one channel (shlight-lightmap's
// geomerics_l1, as Bakery's shEvaluateDiffuseL1Geomerics writes it).
fn lightmap_geomerics(l0: f32, l1: vec3<f32>, n: vec3<f32>) -> f32 {
    if l0 <= 0.0 {
        return 0.0;
    }
    let r1 = 0.5 * l1;
    let len_r1 = length(r1);
    var q = 0.5;
    if len_r1 > 0.0 {
        q = dot(r1 / len_r1, n) * 0.5 + 0.5;
    }
    q = clamp(q, 0.0, 1.0);
    let p = 1.0 + 2.0 * len_r1 / l0;
    let a = (1.0 - len_r1 / l0) / (1.0 + len_r1 / l0);
    return l0 * (a + (1.0 - a) * (p + 1.0) * pow(q, p));
}

// Bakery's decode once the L1 vectors are known (BakerySH_float,
// BakeryMonoSH_float and their linear branch).
fn lightmap_bakery(
    l0: vec3<f32>,
    l1x: vec3<f32>,
    l1y: vec3<f32>,
    l1z: vec3<f32>,
    n: vec3<f32>,
    non_linear: bool,
) -> vec3<f32> {
    var sh = l0 + n.x * l1x + n.y * l1y + n.z * l1z;
    if !non_linear {
        return sh;
    }
    let one = vec3<f32>(1.0);
    let luma_l1 = vec3<f32>(dot(l1x, one), dot(l1y, one), dot(l1z, one));
    let luma_sh = lightmap_geomerics(dot(l0, one), luma_l1, n);
    let regular = dot(sh, one);
    let w = clamp(regular * 16.0, 0.0, 1.0);
    if w > 0.0 {
        sh = sh * (1.0 + w * (luma_sh / regular - 1.0));
    }
    return max(sh, vec3<f32>(0.0));
}

// The irradiance E (W/m2) the lightmap holds at the atlas UV uv for the
// unit normal n (world axes).
fn lightmap_irradiance(uv: vec2<f32>, n: vec3<f32>) -> vec3<f32> {
    let format = frame.lightmap;
    let l0 = lightmap_page(uv, 0);
    var light = l0;
    switch format {
        case LIGHTMAP_SH_L1, LIGHTMAP_SH_L1_NON_LINEAR: {
            let bx = lightmap_page(uv, 1);
            let by = lightmap_page(uv, 2);
            let bz = lightmap_page(uv, 3);
            if format == LIGHTMAP_SH_L1 {
                light = l0 + bx * n.x + by * n.y + bz * n.z;
            } else {
                light = vec3<f32>(
                    lightmap_geomerics(l0.x, vec3<f32>(bx.x, by.x, bz.x), n),
                    lightmap_geomerics(l0.y, vec3<f32>(bx.y, by.y, bz.y), n),
                    lightmap_geomerics(l0.z, vec3<f32>(bx.z, by.z, bz.z), n),
                );
            }
        }
        case LIGHTMAP_GODOT: {
            let l1n1 = (lightmap_page(uv, 1) - vec3<f32>(0.5)) * 2.0;
            let l1_0 = (lightmap_page(uv, 2) - vec3<f32>(0.5)) * 2.0;
            let l1p1 = (lightmap_page(uv, 3) - vec3<f32>(0.5)) * 2.0;
            let m = normalize(n);
            light = l0 + l1n1 * m.y * (l0 * 4.0) + l1_0 * m.z * (l0 * 4.0)
                + l1p1 * m.x * (l0 * 4.0);
        }
        case LIGHTMAP_BAKERY_SH, LIGHTMAP_BAKERY_SH_NON_LINEAR: {
            let x = lightmap_page(uv, 1) * 2.0 - 1.0;
            let y = lightmap_page(uv, 2) * 2.0 - 1.0;
            let z = lightmap_page(uv, 3) * 2.0 - 1.0;
            light = lightmap_bakery(
                l0, x * l0 * 2.0, y * l0 * 2.0, z * l0 * 2.0, n,
                format == LIGHTMAP_BAKERY_SH_NON_LINEAR,
            );
        }
        case LIGHTMAP_MONOSH, LIGHTMAP_MONOSH_NON_LINEAR: {
            let d = lightmap_page(uv, 1) * 2.0 - 1.0;
            light = lightmap_bakery(
                l0, d.x * l0 * 2.0, d.y * l0 * 2.0, d.z * l0 * 2.0, n,
                format == LIGHTMAP_MONOSH_NON_LINEAR,
            );
        }
        default: {}
    }
    return light / frame.lightmap_scale;
}

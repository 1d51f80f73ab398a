// Irradiance-volume shading (shaders/README.md, docs/shvol.md "Shading"):
// meshes lit per fragment by trilinear interpolation of an irradiance
// volume's valid probes (Greger et al. 1998), any lmax up to 4, each probe
// also weighted by its visibility of the point where the volume holds
// distance maps (volume_visibility.wgsl, a module of its own).
//
// At a point p with unit normal n, over the eight probes k around p with
// trilinear weights w_k and validity v_k (0 or 1):
//
//   E(p, n) = sum_k w_k v_k E_k(n) / sum_k w_k v_k,
//   E_k(n)  = sum_l A_l w_l sum_m L_k,lm Y_lm(n)
//
// (the invalid probes' weights dropped and the rest renormalised; when all
// eight are invalid E = 0: the point is inside geometry). A Lambertian
// surface of albedo rho leaves rho/pi E(p, n) plus its own emission. A
// probe sphere (drawn by the fs_probe pipeline, below) shows its own
// probe's E_k(n), or 0 when the probe is invalid.
//
// The probes are a 3D texture of premultiplied texels: per probe the floats
// (v, v L_i, ...) (v the validity, L_i the rgb radiance of coefficient i,
// for every i to lmax_v but those of degree 3: A_3 = 0, so they add nothing
// to E), four to a texel, so a probe's T = ceil((3 c + 1) / 4) texels (c
// the coefficients kept: T = 7 at lmax 2, 14 at lmax 4) hold its float f
// at texel f / 4, lane f % 4. Texel j of
// every probe lies in block j of the texture, the grid itself (probe
// (x, y, z) at texel (x, y, z) of the block) with one layer more on each
// side in y and z that repeats the edge; the blocks tile the texture's y and
// z. Interpolating the texels with the trilinear weights gives
// (sum_k w_k v_k, sum_k w_k v_k L_k,i) at once, so
//
//   E(p, n) = sum_i y_i (sum_k w_k v_k L_k,i) / sum_k w_k v_k
//
// with y_i = A_l w_l Y_i(n): the coefficients are interpolated first and
// dotted with the basis once. Three ways to weigh, one module each:
//
// - filtered (the adapter filters Rgba32Float): one trilinear sample per
//   texel, the point clamped to the grid's first and last probe centres on
//   every axis (clamp-to-edge within the block; probes sit at cell centres,
//   which are texel centres);
// - loads: eight textureLoads per texel, weighted in the shader exactly as
//   shlight-baked's ProbeGrid::trilinear weighs them;
// - visibility (a volume with probe distance maps): the same eight loads,
//   each probe's trilinear weight multiplied by its visibility of the
//   point (volume_visibility.wgsl, appended to this file in that module
//   only), the lookup of shlight-baked's visibility.rs. The weights then
//   differ per probe, so the sampler's filter cannot apply them; a volume
//   without maps keeps one of the two above, with no trace of this one.
//
// ShBasis / sh_basis, volume_sum and probe_sum (the texel dot products) are
// written out per lmax and variant and appended
// (crates/shlight-gpu/src/volume_expansion.rs).
//
// Two fragment entry points, one pipeline each: fs_volume for meshes lit by
// interpolation, fs_probe for the probe spheres. One shader that chose
// between the two per instance would cost every fragment both on a CPU
// rasteriser: llvmpipe runs both sides of a branch, masked, whatever the
// condition (shaders/README.md).

// Texels per probe at lmax 4: ceil((3 * 18 + 1) / 4) (degree 3 left out).
const VOLUME_MAX_TEXELS: u32 = 14u;

// The grid and the texture's layout, written by shlight-gpu's
// `VolumeUniform`. Probes sit at cell centres, numbered x fastest: probe
// (x, y, z) is x + nx (y + ny z).
struct Volume {
    // The grid box's lower corner (xyz).
    min: vec4<f32>,
    // Cells per unit length along each axis: resolution / (max - min).
    inv_cell: vec4<f32>,
    // Probes along x, y, z; w: texels per probe T.
    resolution: vec4<u32>,
    // 1 / the texture's width, height and depth (in texels).
    inv_size: vec4<f32>,
    // Per texel j < T, where block j starts: x, y its first probe layer in
    // y and z as normalised texture coordinates; z, w the same in texels.
    blocks: array<vec4<f32>, VOLUME_MAX_TEXELS>,
    // The visibility variant's constants (volume_visibility.wgsl; 0 in the
    // others): x the normal bias b, y the least Chebyshev factor, z the
    // weight below which weights are crushed, w its square (each the f32
    // value shlight-baked's visibility.rs computes with).
    visibility: vec4<f32>,
    // x texels per side of a probe's distance map, y texels per map.
    map: vec4<u32>,
}

@group(0) @binding(2) var probe_texels: texture_3d<f32>;
@group(0) @binding(3) var<uniform> volume: Volume;
// Linear filtering, clamp to edge (the filtered variant only).
@group(0) @binding(6) var probe_sampler: sampler;

struct VolumeVertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    @location(3) emission: vec3<f32>,
    // Per instance: world = position * scale + offset (xyz offset, w scale).
    @location(4) offset_scale: vec4<f32>,
    // Per instance: the probe a probe sphere shows (read by fs_probe only;
    // fs_volume's instances carry a filler value).
    @location(5) probe: u32,
}

struct VolumeVertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    @location(3) emission: vec3<f32>,
    @location(4) @interpolate(flat) probe: u32,
}

// Filtered: the point in texture coordinates of block 0, clamped on each
// axis to the first and last probe centres (texel centres 0.5 and n - 0.5):
// the clamp of Grid::trilinear, where an axis of one probe has weight 1 on
// it. Block j adds its offset in y and z; the layers beyond a block's edge
// repeat it, so rounding at a clamped coordinate reads the same values.
fn volume_filtered_at(p: vec3<f32>) -> vec3<f32> {
    let n = vec3<f32>(volume.resolution.xyz);
    let u = (p - volume.min.xyz) * volume.inv_cell.xyz;
    return clamp(u, vec3<f32>(0.5), n - vec3<f32>(0.5)) * volume.inv_size.xyz;
}

// Texel j of the eight probes around the point at, filtered.
fn volume_filtered(at: vec3<f32>, j: u32) -> vec4<f32> {
    let b = volume.blocks[j];
    let c = vec3<f32>(at.x, at.y + b.x, at.z + b.y);
    return textureSampleLevel(probe_texels, probe_sampler, c, 0.0);
}

// Loads: the trilinear cell of p, clamped to the grid as shlight-volume's
// Grid::trilinear is: its lower and upper corners per axis (the same on an
// axis of one probe) and the weights of its eight corners, corner k the
// upper one along x, y, z where bit 0, 1, 2 of k is set (w03: corners 0..3,
// w47: 4..7).
struct VolumeCell {
    lower: vec3<u32>,
    upper: vec3<u32>,
    w03: vec4<f32>,
    w47: vec4<f32>,
}

fn volume_loads_at(p: vec3<f32>) -> VolumeCell {
    let n = vec3<f32>(volume.resolution.xyz);
    let u = (p - volume.min.xyz) * volume.inv_cell.xyz - vec3<f32>(0.5);
    let f = clamp(u, vec3<f32>(0.0), max(n - vec3<f32>(1.0), vec3<f32>(0.0)));
    let i = min(floor(f), max(n - vec3<f32>(2.0), vec3<f32>(0.0)));
    let t = f - i;
    let s = vec3<f32>(1.0) - t;
    let lower = vec3<u32>(i);
    let upper = min(lower + vec3<u32>(1u), volume.resolution.xyz - vec3<u32>(1u));
    let xy = vec4<f32>(s.x * s.y, t.x * s.y, s.x * t.y, t.x * t.y);
    return VolumeCell(lower, upper, xy * s.z, xy * t.z);
}

// Texel j of the eight probes around the cell c, weighted.
fn volume_loads(c: VolumeCell, j: u32) -> vec4<f32> {
    let b = volume.blocks[j];
    let o = vec3<u32>(0u, u32(b.z), u32(b.w));
    let lo = c.lower + o;
    let hi = c.upper + o;
    return c.w03.x * textureLoad(probe_texels, lo, 0)
        + c.w03.y * textureLoad(probe_texels, vec3<u32>(hi.x, lo.y, lo.z), 0)
        + c.w03.z * textureLoad(probe_texels, vec3<u32>(lo.x, hi.y, lo.z), 0)
        + c.w03.w * textureLoad(probe_texels, vec3<u32>(hi.x, hi.y, lo.z), 0)
        + c.w47.x * textureLoad(probe_texels, vec3<u32>(lo.x, lo.y, hi.z), 0)
        + c.w47.y * textureLoad(probe_texels, vec3<u32>(hi.x, lo.y, hi.z), 0)
        + c.w47.z * textureLoad(probe_texels, vec3<u32>(lo.x, hi.y, hi.z), 0)
        + c.w47.w * textureLoad(probe_texels, hi, 0);
}

// Probe k's texel coordinates in block 0.
fn probe_at(k: u32) -> vec3<u32> {
    let r = volume.resolution;
    return vec3<u32>(k % r.x, (k / r.x) % r.y, k / (r.x * r.y));
}

// Texel j of the probe at a.
fn probe_load(a: vec3<u32>, j: u32) -> vec4<f32> {
    let b = volume.blocks[j];
    return textureLoad(probe_texels, a + vec3<u32>(0u, u32(b.z), u32(b.w)), 0);
}

// sum_k w_k v_k E_k(n) / sum_k w_k v_k in rgb, sum_k w_k v_k in a (rgb 0
// when the sum is 0). volume_sum(p, n, y) returns
// (sum_i y_i sum_k w_k v_k L_k,i, sum_k w_k v_k); w_k is the trilinear
// weight, times the probe's visibility of p in the visibility variant
// (volume_visibility.wgsl), which alone reads n.
fn volume_irradiance(p: vec3<f32>, n: vec3<f32>) -> vec4<f32> {
    let s = volume_sum(p, n, sh_basis(n, frame.irradiance_band));
    if s.w > 0.0 {
        return vec4<f32>(s.xyz / s.w, s.w);
    }
    return vec4<f32>(0.0);
}

// E_k(n) of one probe, 0 when it is invalid (its texels are 0).
fn probe_irradiance(k: u32, n: vec3<f32>) -> vec3<f32> {
    return probe_sum(probe_at(k), sh_basis(n, frame.irradiance_band));
}

@vertex
fn vs_volume(in: VolumeVertexIn) -> VolumeVertexOut {
    var out: VolumeVertexOut;
    let world = in.position * in.offset_scale.w + in.offset_scale.xyz;
    out.clip = frame.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = in.normal;
    out.albedo = in.albedo;
    out.emission = in.emission;
    out.probe = in.probe;
    return out;
}

// Meshes lit by interpolation (the scene and the object).
@fragment
fn fs_volume(in: VolumeVertexOut) -> @location(0) vec4<f32> {
    let e = volume_irradiance(in.world, normalize(in.normal)).rgb;
    return finish(in.albedo / SH_PI * e + in.emission);
}

// Probe spheres: each lit by its own probe in.probe alone.
@fragment
fn fs_probe(in: VolumeVertexOut) -> @location(0) vec4<f32> {
    let e = probe_irradiance(in.probe, normalize(in.normal));
    return finish(in.albedo / SH_PI * e + in.emission);
}

// The interpolation itself, for checks against the CPU: query j is the
// point queries[2j].xyz with the unit normal queries[2j+1].xyz; answers[j]
// is volume_irradiance there.
@group(0) @binding(4) var<storage, read> queries: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> answers: array<vec4<f32>>;

@compute @workgroup_size(64)
fn cs_volume(@builtin(global_invocation_id) id: vec3<u32>) {
    let j = id.x;
    if j >= arrayLength(&answers) {
        return;
    }
    answers[j] = volume_irradiance(queries[2u * j].xyz, queries[2u * j + 1u].xyz);
}

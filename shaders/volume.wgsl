// Irradiance-volume shading (shaders/README.md, docs/shvol.md "Shading"):
// meshes lit per fragment by trilinear interpolation of an irradiance
// volume's valid probes (Greger et al. 1998), any lmax up to 4.
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
// probe sphere (instance with a probe number) shows its own probe's E_k(n),
// or 0 when the probe is invalid.
//
// The weighted basis ShBasis / sh_basis and probe_dot are written out per
// lmax and appended (crates/shlight-gpu/src/volume_expansion.rs).

// The grid, written by shlight-gpu's `VolumeUniform`. Probes sit at cell
// centres, numbered x fastest: probe (x, y, z) is x + nx (y + ny z).
struct Volume {
    // The grid box's lower corner (xyz).
    min: vec4<f32>,
    // Cells per unit length along each axis: resolution / (max - min).
    inv_cell: vec4<f32>,
    // Probes along x, y, z; w: vec4 slots per probe, (lmax_v + 1)^2 with
    // lmax_v the uploaded lmax (at most 4).
    resolution: vec4<u32>,
}

// Probe-major: probe k's coefficient i (i < (lmax_v+1)^2) at
// probes[k * resolution.w + i], radiance L_k,i in rgb; the w of slot 0 is
// 1 for a valid probe and 0 for an invalid one (every other w is 0).
@group(0) @binding(2) var<storage, read> probes: array<vec4<f32>>;
@group(0) @binding(3) var<uniform> volume: Volume;

// No probe: the instance is lit by interpolation.
const NO_PROBE: u32 = 0xffffffffu;

struct VolumeVertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    @location(3) emission: vec3<f32>,
    // Per instance: world = position * scale + offset (xyz offset, w scale).
    @location(4) offset_scale: vec4<f32>,
    // Per instance: the probe a probe sphere shows, or NO_PROBE.
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

// The trilinear cell of p, clamped to the grid as shlight-volume's
// Grid::trilinear is: lower corner per axis and the fraction t towards the
// upper one (t = 0 on an axis of one probe, so its upper corners weigh 0).
struct Cell {
    lower: vec3<u32>,
    t: vec3<f32>,
}

fn volume_cell(p: vec3<f32>) -> Cell {
    let n = vec3<f32>(volume.resolution.xyz);
    let u = (p - volume.min.xyz) * volume.inv_cell.xyz - vec3<f32>(0.5);
    let f = clamp(u, vec3<f32>(0.0), max(n - vec3<f32>(1.0), vec3<f32>(0.0)));
    let i = min(floor(f), max(n - vec3<f32>(2.0), vec3<f32>(0.0)));
    return Cell(vec3<u32>(i), f - i);
}

// sum_k w_k v_k E_k(n) / sum_k w_k v_k in rgb, sum_k w_k v_k in a (rgb 0
// when the sum is 0).
fn volume_irradiance(p: vec3<f32>, n: vec3<f32>) -> vec4<f32> {
    let y = sh_basis(n, frame.irradiance_band);
    let cell = volume_cell(p);
    let res = volume.resolution;
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var k = 0u; k < 8u; k = k + 1u) {
        let up = vec3<u32>(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
        let wv = select(vec3<f32>(1.0) - cell.t, cell.t, up == vec3<u32>(1u));
        let w = wv.x * wv.y * wv.z;
        let c = cell.lower + up;
        let b = (c.x + res.x * (c.y + res.y * c.z)) * res.w;
        if w > 0.0 && probes[b].w > 0.5 {
            sum = sum + w * probe_dot(b, y);
            total = total + w;
        }
    }
    if total > 0.0 {
        return vec4<f32>(sum / total, total);
    }
    return vec4<f32>(0.0);
}

// E_k(n) of one probe, 0 when it is invalid.
fn probe_irradiance(k: u32, n: vec3<f32>) -> vec3<f32> {
    let b = k * volume.resolution.w;
    if probes[b].w < 0.5 {
        return vec3<f32>(0.0);
    }
    return probe_dot(b, sh_basis(n, frame.irradiance_band));
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

@fragment
fn fs_volume(in: VolumeVertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    var e: vec3<f32>;
    if in.probe == NO_PROBE {
        e = volume_irradiance(in.world, n).rgb;
    } else {
        e = probe_irradiance(in.probe, n);
    }
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

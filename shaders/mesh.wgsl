// Band-limited shading of a triangle mesh (shaders/README.md).
//
// MODE_SH: per fragment, irradiance E(n) = sum_l A_l w_l sum_m L_lm Y_lm(n)
// at the interpolated unit normal, outgoing radiance rho/pi E(n).
// MODE_PRT: per vertex, radiance sum_i T_vi L_i + S_v (the transfer T from a
// storage buffer, one or three channels; S the static term a glTF scene's
// lights and emission leave, zero without one), interpolated.
// MODE_GLOSSY: per vertex, glossy PRT (docs/shprt.md, "Glossy transfer"):
// a diffuse base of albedo rho under the glossy layer,
//   L_o = sum_lm (rho/pi A_l Y_lm(n) + Lambda_l Y_lm(R)) T_lm,
// R the mirror of the direction to the eye about the normal, T the vertex's
// transferred radiance M L, interpolated; for a tabulated lobe (GGX,
// frame.ggx_rows > 0) Lambda_l is 0 and ggx_layer adds the glossy layer.
// MODE_NORMALS: the world-space unit normal as the colour, untouched by
// exposure and tone map.

// PRT transfer. Diffuse: vertex-major, vertex v, channel c, coefficient i at
// (v * channels + c) * (prt_lmax + 1)^2 + i. Glossy: first a record per
// vertex of K + 1 values, at v (K + 1): its group (a cluster, or the vertex
// itself uncompressed) as u32 bits, then its K weights; from
// frame.glossy_parts the parts, group-major, K + 1 parts of (prt_lmax + 1)^2
// RGB coefficients each (part 0 the cluster mean's M L, part k the k-th
// basis vector's), written by the renderer whenever the light changes.
// Diffuse with a static term: after the transfer, from frame.prt_static,
// each vertex's static exit radiance S_v as R, G, B at prt_static + 3 v.
@group(0) @binding(2) var<storage, read> transfer: array<f32>;

// The vertex's record and the first f32 of its group's parts (glossy).
var<private> glossy_record: u32;
var<private> glossy_part: u32;

// The vertex's transferred radiance T_i: part 0 plus each weight times its
// part (glossy; glossy_record and glossy_part set).
fn glossy_t(i: u32) -> vec3<f32> {
    let stride = 3u * sh_count(frame.prt_lmax);
    var at = glossy_part + 3u * i;
    var t = vec3<f32>(transfer[at], transfer[at + 1u], transfer[at + 2u]);
    for (var k = 0u; k < frame.glossy_vectors; k = k + 1u) {
        at = at + stride;
        let w = transfer[glossy_record + 1u + k];
        t = t + w * vec3<f32>(transfer[at], transfer[at + 1u], transfer[at + 2u]);
    }
    return t;
}

// The vertex's transferred radiance T_i, for the GGX layer's band sums.
var<private> ggx_t: array<vec3<f32>, 81>;

// The glossy layer of a tabulated lobe (GGX; docs/shprt.md, "Shading glossy
// files"): at the unit normal n seen from the unit direction w,
//   sum_l sum_k w_lk(theta_o) T_l(d_k),  d_k = x sin(psi_k) + n cos(psi_k),
// psi_k = pi (k + 1/2) / K, K = prt_lmax + 1, x the unit tangent toward w,
// T_l(d) band l of T at d (ggx_band_sums), w_lk the direction weights at rows
// k..k+3 of the table at frame.ggx_table (rows of (prt_lmax+1) bands of K),
// Catmull-Rom in t = 2/pi asin(2 theta_o / pi) (shlight-prt's GgxLobe).
// 0 for a view from below.
fn ggx_layer(n: vec3<f32>, w: vec3<f32>) -> vec3<f32> {
    let mu = dot(n, w);
    if mu <= 0.0 {
        return vec3<f32>(0.0);
    }
    let lmax = min(frame.prt_lmax, GGX_LMAX);
    for (var i = 0u; i < sh_count(lmax); i = i + 1u) {
        ggx_t[i] = glossy_t(i);
    }
    var tangent = w - mu * n;
    // |w - mu n| = sin theta_o: theta_o by atan2, accurate near the normal
    // where acos of an f32 is not.
    let sin_o = length(tangent);
    let half_pi = 0.5 * SH_PI;
    let elevations = frame.ggx_rows - 2u;
    // t = asin(y) / (pi/2), y = theta_o / (pi/2), as atan2(y, sqrt((1 - y)
    // (1 + y))) with 1 - y from the complement of theta_o: accurate near
    // grazing, where asin's slope is steep and the table's rows dense.
    let y = atan2(sin_o, mu) / half_pi;
    let one_minus_y = atan2(mu, sin_o) / half_pi;
    let x = atan2(y, sqrt(one_minus_y * (1.0 + y))) / half_pi * f32(elevations - 1u);
    let k = min(u32(floor(x)), elevations - 2u);
    let t = x - f32(k);
    let t2 = t * t;
    let t3 = t2 * t;
    let cw = array<f32, 4>(
        0.5 * (-t3 + 2.0 * t2 - t),
        0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
        0.5 * (-3.0 * t3 + 4.0 * t2 + t),
        0.5 * (t3 - t2),
    );
    if sin_o > 1e-6 {
        tangent = tangent / sin_o;
    } else {
        // Looking along the normal: the lobe is symmetric about it.
        let a = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n.x) > 0.9);
        tangent = normalize(cross(n, a));
    }
    let dirs = frame.prt_lmax + 1u;
    let row = (frame.prt_lmax + 1u) * dirs;
    var sum = vec3<f32>(0.0);
    for (var d = 0u; d < dirs; d = d + 1u) {
        let psi = SH_PI * (f32(d) + 0.5) / f32(dirs);
        let bands = ggx_band_sums(tangent * sin(psi) + n * cos(psi));
        for (var l = 0u; l <= lmax; l = l + 1u) {
            let at = frame.ggx_table + k * row + l * dirs + d;
            let weight = cw[0] * transfer[at] + cw[1] * transfer[at + row]
                + cw[2] * transfer[at + 2u * row] + cw[3] * transfer[at + 3u * row];
            sum = sum + weight * bands[l];
        }
    }
    return sum;
}

// glossy_radiance(n: vec3<f32>, r: vec3<f32>) -> vec3<f32> returns
// sum_i (frame.albedo.rgb / pi A_l Y_i(n) + Lambda_l Y_i(r)) glossy_t(i) to
// prt_lmax: written out per lmax and appended to the module
// (crates/shlight-gpu/src/glossy_expansion.rs).

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) prt: vec3<f32>,
}

// sum_i T_vi L_i for vertex v, to the lower of the two degrees.
fn prt_radiance(v: u32) -> vec3<f32> {
    let n = sh_count(frame.prt_lmax);
    let count = sh_count(min(frame.prt_lmax, frame.lmax));
    var sum = vec3<f32>(0.0);
    if frame.prt_channels == 3u {
        let base = v * 3u * n;
        for (var i = 0u; i < count; i = i + 1u) {
            let t = vec3<f32>(transfer[base + i], transfer[base + n + i], transfer[base + 2u * n + i]);
            sum = sum + t * light[i].rgb;
        }
    } else {
        let base = v * n;
        for (var i = 0u; i < count; i = i + 1u) {
            sum = sum + transfer[base + i] * light[i].rgb;
        }
    }
    return sum;
}

// The static exit radiance S_v of vertex v (docs/shprt.md, "Format version
// 3"), to add to the transfer's radiance where frame.prt_static is not 0
// (radiance without a static term stays as it was, bit for bit).
fn static_radiance(v: u32) -> vec3<f32> {
    let at = frame.prt_static + 3u * v;
    return vec3<f32>(transfer[at], transfer[at + 1u], transfer[at + 2u]);
}

@vertex
fn vs_mesh(in: VertexIn, @builtin(vertex_index) v: u32) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(in.position, 1.0);
    out.normal = in.normal;
    out.prt = vec3<f32>(0.0);
    if frame.mode == MODE_PRT {
        out.prt = prt_radiance(v);
        if frame.prt_static != 0u {
            out.prt = out.prt + static_radiance(v);
        }
    }
    if frame.mode == MODE_GLOSSY {
        let n = normalize(in.normal);
        let w = normalize(frame.eye.xyz - in.position);
        let r = 2.0 * dot(n, w) * n - w;
        let parts = frame.glossy_vectors + 1u;
        glossy_record = v * parts;
        let group = bitcast<u32>(transfer[glossy_record]);
        glossy_part = frame.glossy_parts + group * parts * 3u * sh_count(frame.prt_lmax);
        out.prt = glossy_radiance(n, normalize(r));
        if frame.ggx_rows > 0u {
            out.prt = out.prt + ggx_layer(n, w);
        }
    }
    return out;
}

@fragment
fn fs_mesh(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    switch frame.mode {
        case MODE_NORMALS: {
            return vec4<f32>(n, 1.0);
        }
        case MODE_PRT, MODE_GLOSSY: {
            return finish(in.prt);
        }
        default: {
            let e = sh_reconstruct(n, frame.irradiance_band);
            return finish(frame.albedo.rgb / SH_PI * e);
        }
    }
}

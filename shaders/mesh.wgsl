// Band-limited shading of a triangle mesh (shaders/README.md).
//
// MODE_SH: per fragment, irradiance E(n) = sum_l A_l w_l sum_m L_lm Y_lm(n)
// at the interpolated unit normal, outgoing radiance rho/pi E(n).
// MODE_PRT: per vertex, radiance sum_i T_vi L_i (the transfer T from a
// storage buffer, one or three channels), interpolated.
// MODE_NORMALS: the world-space unit normal as the colour, untouched by
// exposure and tone map.

// PRT transfer, vertex-major: vertex v, channel c, coefficient i at
// (v * channels + c) * (prt_lmax + 1)^2 + i.
@group(0) @binding(2) var<storage, read> transfer: array<f32>;

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

@vertex
fn vs_mesh(in: VertexIn, @builtin(vertex_index) v: u32) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(in.position, 1.0);
    out.normal = in.normal;
    out.prt = vec3<f32>(0.0);
    if frame.mode == MODE_PRT {
        out.prt = prt_radiance(v);
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
        case MODE_PRT: {
            return finish(in.prt);
        }
        default: {
            let e = sh_reconstruct(n, frame.irradiance_band);
            return finish(frame.albedo.rgb / SH_PI * e);
        }
    }
}

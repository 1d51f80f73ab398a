// Projection of an equirect map to SH by exact texel-solid-angle quadrature
// (shaders/README.md), the GPU twin of shlight-core's `project_equirect`,
// by the same ring transform, about the map's own pole (z-up):
//
//   C_m(j) + i S_m(j) = sum_x f(x, j) e^{i m psi_x},
//   L_l^0 = sum_j w_l^0(j) C_0(j),
//   L_l^m = sum_j w_l^m(j) C_m(j),  L_l^-m = sum_j w_l^m(j) S_m(j)   (m > 0),
//   w_l^m(j) = Omega_j Pbar_l^m(cos theta_j) (times sqrt2 for m > 0),
//   Omega_j = (2 pi / W)(cos(j pi / H) - cos((j + 1) pi / H)).
//
// Pass 1 (`project_rows`): one workgroup per row computes the row's ring
// sums (`ring_sums`, written out per lmax by crates/shlight-gpu/src/
// ring_sums.rs and appended to this file with ROW_THREADS, RING_SLOTS,
// RING_SCALARS, LEGENDRE_COUNT and the workgroup memory it uses). Pass 2
// (`legendre_sums`): one workgroup per coefficient sums w times the ring
// sum over the rows. The tables (psi per column, w per row) come from the
// CPU in f64 rounded to f32; the CPU turns the result from the map's pole
// to its frame (y-up) in f64, as `project_equirect` does.

struct ProjectParams {
    // Quads (4 texels) per row: rows are padded with zero texels to a
    // multiple of 4.
    quads: u32,
    height: u32,
    // First row of the rows now in `texels` (large maps go in chunks).
    row_offset: u32,
    pad: u32,
}

@group(0) @binding(0) var<uniform> params: ProjectParams;
// This chunk's texels, row-major, packed RGB: a quad of 4 texels in 3 vec4.
@group(0) @binding(1) var<storage, read> texels: array<vec4<f32>>;
// Per pair of columns: cos psi, sin psi of each (psi the azimuth about the
// map's pole).
@group(0) @binding(2) var<storage, read> columns: array<vec4<f32>>;
// Ring sums: row j, slot k, channel c at j * RING_SCALARS + 3 k + c.
@group(0) @binding(3) var<storage, read_write> rings: array<f32>;
// Per row j: w_l^m(j) at j * LEGENDRE_COUNT + l (l + 1) / 2 + m.
@group(0) @binding(4) var<storage, read> weights: array<f32>;
// The coefficients about the map's pole (pass 2).
@group(0) @binding(5) var<storage, read_write> result: array<vec4<f32>>;

const REDUCE_THREADS: u32 = 64u;

var<workgroup> reduce_scratch: array<vec3<f32>, 64>;

@compute @workgroup_size(ROW_THREADS)
fn project_rows(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    ring_sums(group.x, params.row_offset + group.x, t);
}

@compute @workgroup_size(REDUCE_THREADS)
fn legendre_sums(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let i = group.x;
    let l = sh_band(i);
    let centre = l * (l + 1u);
    // |m| and the ring slot: C_0, C_m at 2m - 1, S_m at 2m.
    var m = 0u;
    var slot = 0u;
    if i > centre {
        m = i - centre;
        slot = 2u * m - 1u;
    } else if i < centre {
        m = centre - i;
        slot = 2u * m;
    }
    let p = centre / 2u + m;
    var sum = vec3<f32>(0.0);
    for (var j = t; j < params.height; j = j + REDUCE_THREADS) {
        let k = j * RING_SCALARS + 3u * slot;
        sum = sum + weights[j * LEGENDRE_COUNT + p] * vec3<f32>(rings[k], rings[k + 1u], rings[k + 2u]);
    }
    reduce_scratch[t] = sum;
    workgroupBarrier();
    for (var s = REDUCE_THREADS / 2u; s > 0u; s = s >> 1u) {
        if t < s {
            reduce_scratch[t] = reduce_scratch[t] + reduce_scratch[t + s];
        }
        workgroupBarrier();
    }
    if t == 0u {
        result[i] = vec4<f32>(reduce_scratch[0], 0.0);
    }
}

// Projection of an equirect map to SH by exact texel-solid-angle quadrature
// (shaders/README.md), the GPU twin of shlight-core's `project_equirect`:
//
//   L_i = sum_rows Omega_j sum_x f(x, j) Y_i(d(x, j)),
//   Omega_j = (2 pi / W)(cos(j pi / H) - cos((j + 1) pi / H)).
//
// Pass 1 (`project_rows`): one workgroup per row; each invocation sums
// f Y_i over every 64th texel of the row, the workgroup reduces the 64
// partial sums per coefficient in shared memory, and writes Omega_j times
// the row sum. Pass 2 (`reduce_rows`): one workgroup per coefficient sums
// the rows. The per-row (cos theta, sin theta, Omega) and per-column
// (cos phi, sin phi) tables come from the CPU in f64 rounded to f32.

struct ProjectParams {
    // World from the map's own y-up frame (frame and mirror).
    world_from_map: mat4x4<f32>,
    width: u32,
    height: u32,
    // First row of the rows now in `texels` (large maps go in chunks).
    row_offset: u32,
    lmax: u32,
}

@group(0) @binding(0) var<uniform> params: ProjectParams;
// This chunk's texels, row-major, packed RGB.
@group(0) @binding(1) var<storage, read> texels: array<f32>;
// Per row of the whole map: cos theta, sin theta, Omega, 0.
@group(0) @binding(2) var<storage, read> rows: array<vec4<f32>>;
// Per column: cos phi, sin phi.
@group(0) @binding(3) var<storage, read> columns: array<vec2<f32>>;
// Row sums, row-major: row j, coefficient i at j * (lmax+1)^2 + i.
@group(0) @binding(4) var<storage, read_write> partials: array<vec4<f32>>;
// The coefficients (pass 2).
@group(0) @binding(5) var<storage, read_write> result: array<vec4<f32>>;

const ROW_THREADS: u32 = 64u;
const REDUCE_THREADS: u32 = 256u;

var<workgroup> row_scratch: array<vec3<f32>, 64>;
var<workgroup> reduce_scratch: array<vec3<f32>, 256>;

@compute @workgroup_size(64)
fn project_rows(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let local_row = group.x;
    let row = params.row_offset + local_row;
    let count = sh_count(params.lmax);
    let ring = rows[row];
    var acc: array<vec3<f32>, 81>;
    for (var i = 0u; i < count; i = i + 1u) {
        acc[i] = vec3<f32>(0.0);
    }
    var y: array<f32, 81>;
    for (var x = t; x < params.width; x = x + ROW_THREADS) {
        let col = columns[x];
        let d_map = vec3<f32>(ring.y * col.x, ring.x, ring.y * col.y);
        let d = (params.world_from_map * vec4<f32>(d_map, 0.0)).xyz;
        sh_basis(d, params.lmax, &y);
        let k = 3u * (local_row * params.width + x);
        let f = vec3<f32>(texels[k], texels[k + 1u], texels[k + 2u]);
        for (var i = 0u; i < count; i = i + 1u) {
            acc[i] = acc[i] + f * y[i];
        }
    }
    for (var i = 0u; i < count; i = i + 1u) {
        row_scratch[t] = acc[i];
        workgroupBarrier();
        for (var s = ROW_THREADS / 2u; s > 0u; s = s >> 1u) {
            if t < s {
                row_scratch[t] = row_scratch[t] + row_scratch[t + s];
            }
            workgroupBarrier();
        }
        if t == 0u {
            partials[row * count + i] = vec4<f32>(ring.z * row_scratch[0], 0.0);
        }
        workgroupBarrier();
    }
}

@compute @workgroup_size(256)
fn reduce_rows(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) t: u32) {
    let i = group.x;
    let count = sh_count(params.lmax);
    var sum = vec3<f32>(0.0);
    for (var j = t; j < params.height; j = j + REDUCE_THREADS) {
        sum = sum + partials[j * count + i].xyz;
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

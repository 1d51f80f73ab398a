// The visibility-weighted lookup of a volume that holds probe distance
// maps (DDGI: Majercik et al. 2019), the volume module's third variant
// (shaders/README.md; docs/shvol.md, "Shading on the GPU"). The one
// definition is shlight-baked's visibility.rs (visibility_weights,
// Visibility::moments_at) and octahedral.rs (oct_encode, wrap, bilinear);
// this file repeats its arithmetic in the same f32 operations, in the same
// order, and shlight-volume's irradiance_at (Lookup::Shlight) is what
// tests/volume_gpu.rs checks it against.
//
// Of the eight probes k around p (volume_loads_at: trilinear weights t_k
// from the cell centres, clamped to the grid), each at its position q_k
// (its cell centre plus its offset), with p' = p + b n (b the normal bias,
// a quarter of the smallest cell side):
//
//   d     = |p' - q_k|,  (mean, mean_sq) = k's map at (p' - q_k) / d, bilinear
//   cheb  = 1 where d <= mean (or d = 0), else (v / (v + (d - mean)^2))^3,
//           v = |mean_sq - mean^2|
//   w     = max(floor, cheb); w = w (w^2 / crush^2) where w < crush
//   w_k   = w t_k
//
// and the eight loads of volume_loads weigh texel j of probe k by w_k
// instead of t_k. The texels are premultiplied by the validity v_k, so an
// invalid probe adds nothing to either sum (the CPU leaves it out), and
// E = sum_i y_i (sum_k w_k v_k L_k,i) / sum_k w_k v_k renormalises as the
// CPU does. Every probe's weight is computed, valid or not, with no branch:
// llvmpipe would run both sides anyway (shaders/README.md).

// Per probe its position (xyz: the cell centre plus the bake's offset,
// computed on the CPU as VolumeView::position does; w 0).
@group(0) @binding(7) var<storage, read> probe_positions: array<vec4<f32>>;
// Per probe its map of size x size texels of (mean, mean_sq) in pairs of
// horizontal neighbours, across the folded edges (written by shlight-gpu's
// `pair_texels` with octahedral.rs's wrap): for a in 0..=size (column
// fastest) and b in 0..=size+1, entry (a, b) holds texels (a - 1, b - 1)
// and (a, b - 1) of the map, each wrapped into it, as one vec4. A
// bilinear lookup whose lower left texel is (i0, j0) (each -1..size-1)
// reads entries (i0 + 1, j0 + 1) and (i0 + 1, j0 + 2): two loads, the
// edges folded already. Values as stored, (size + 1)(size + 2) entries per
// probe (volume.map.y).
@group(0) @binding(8) var<storage, read> probe_moments: array<vec4<f32>>;

// The point of [-1, 1]^2 of the direction d (octahedral.rs's oct_encode):
// (x, y) / (|x| + |y| + |z|), folded for z < 0 with the sign 1 at zero.
fn oct_encode(d: vec3<f32>) -> vec2<f32> {
    let l1 = abs(d.x) + abs(d.y) + abs(d.z);
    let p = vec2<f32>(d.x / l1, d.y / l1);
    let s = select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
    let folded = (vec2<f32>(1.0) - abs(p.yx)) * s;
    return select(p, folded, vec2<bool>(d.z < 0.0));
}

// The bilinear (mean, mean_sq) of probe k's map along the unit direction
// dir (Visibility::moments_at, octahedral.rs's bilinear): the four texels
// around its point, texel centres at (k + 1/2) / size of the square,
// summed in bilinear's order. The lower left texel (i0, j0) lies within
// -1..size-1 on each axis (e within [-1, 1]); the clamp only keeps a
// lookup inside its probe's entries whatever the rounding.
fn probe_moments_at(k: u32, dir: vec3<f32>) -> vec2<f32> {
    let size = volume.map.x;
    let e = oct_encode(dir);
    let s = (e + vec2<f32>(1.0)) * 0.5 * f32(size) - vec2<f32>(0.5);
    let base = floor(s);
    let f = s - base;
    let g = vec2<f32>(1.0) - f;
    let a = u32(clamp(i32(base.x) + 1, 0, i32(size)));
    let b = u32(clamp(i32(base.y) + 1, 0, i32(size)));
    let row = size + 1u;
    let at = k * volume.map.y + b * row + a;
    let lower = probe_moments[at];
    let upper = probe_moments[at + row];
    return g.x * g.y * lower.xy + f.x * g.y * lower.zw + g.x * f.y * upper.xy
        + f.x * f.y * upper.zw;
}

// The factor w of probe k for the biased point (before its trilinear
// weight): Chebyshev's visibility, floored, small values crushed.
fn probe_visibility(k: u32, biased: vec3<f32>) -> f32 {
    let v = biased - probe_positions[k].xyz;
    let d = length(v);
    let seen = d > 0.0;
    let dir = select(vec3<f32>(0.0, 0.0, 1.0), v / d, seen);
    let m = probe_moments_at(k, dir);
    let variance = abs(m.y - m.x * m.x);
    let x = d - m.x;
    let c = variance / (variance + x * x);
    let cheb = select(1.0, c * c * c, seen && d > m.x);
    let w = max(cheb, volume.visibility.y);
    return select(w, w * (w * w / volume.visibility.w), w < volume.visibility.z);
}

// The cell of p (volume_loads_at) with each corner's trilinear weight
// multiplied by its probe's visibility of p moved along n.
fn volume_visibility_at(p: vec3<f32>, n: vec3<f32>) -> VolumeCell {
    let c = volume_loads_at(p);
    let biased = p + n * volume.visibility.x;
    let r = volume.resolution;
    let lo = c.lower;
    let hi = c.upper;
    // Probe (x, y, z) is x + nx (y + ny z).
    let z0 = r.y * lo.z;
    let z1 = r.y * hi.z;
    let r00 = r.x * (lo.y + z0);
    let r10 = r.x * (hi.y + z0);
    let r01 = r.x * (lo.y + z1);
    let r11 = r.x * (hi.y + z1);
    let w03 = vec4<f32>(
        probe_visibility(lo.x + r00, biased),
        probe_visibility(hi.x + r00, biased),
        probe_visibility(lo.x + r10, biased),
        probe_visibility(hi.x + r10, biased),
    );
    let w47 = vec4<f32>(
        probe_visibility(lo.x + r01, biased),
        probe_visibility(hi.x + r01, biased),
        probe_visibility(lo.x + r11, biased),
        probe_visibility(hi.x + r11, biased),
    );
    return VolumeCell(lo, hi, c.w03 * w03, c.w47 * w47);
}

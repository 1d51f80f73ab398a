// The visibility-weighted lookup of a volume that holds probe distance
// maps (DDGI: Majercik et al. 2019), the volume module's third variant
// (shaders/README.md; docs/shvol.md, "Shading on the GPU"). The one
// definition is shlight-baked's visibility.rs (visibility_weights,
// Visibility::moments_at) and octahedral.rs (oct_encode, wrap, bilinear);
// its arithmetic, in the same f32 operations in the same order, is the
// function shlight_volume_visibility(k, q, biased) that shlight-shader
// writes and the module appends (crates/shlight-gpu/src/volume_expansion.rs:
// the same lookup as the volume snippets of `shlight convert`, reading
// these buffers). shlight-volume's PreparedLookup (Lookup::Shlight) is what
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
// CPU does. Every probe's weight is computed, valid or not (llvmpipe runs
// both sides of a branch anyway: shaders/README.md).

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

// The factor w of probe k for the biased point (before its trilinear
// weight), the probe at its position.
fn probe_visibility(k: u32, biased: vec3<f32>) -> f32 {
    return shlight_volume_visibility(k, probe_positions[k].xyz, biased);
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

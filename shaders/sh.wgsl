// Real orthonormal spherical harmonics on the GPU (shaders/README.md): the
// constants and index helpers every module shares. The basis itself is
// written out per lmax in Rust (crates/shlight-gpu/src/sh_expansion.rs:
// `sh_reconstruct`; the projection needs only Pbar_l^m per row, from
// shlight-core on the CPU, and e^{i m psi} per texel, ring_sums.rs).
//
// shlight's basis (docs/conventions.md): Condon-Shortley phase included,
// flat index i = l(l+1) + m, polar axis world +z. With z = cos(theta) and
// x + i y = sin(theta) e^{i phi}, write Y_l^m through
//
//   Q_l^m = Pbar_l^m(z) / sin(theta)^m,   C_m + i S_m = (x + i y)^m,
//   Y_l^m = sqrt2 Q_l^m C_m (m > 0),  Y_l^0 = Q_l^0,  Y_l^-m = sqrt2 Q_l^m S_m,
//
// where Q obeys the same recurrences as the SH-normalised Pbar with the
// sin(theta) factor dropped (so nothing divides by sin(theta) at the poles):
//
//   Q_0^0 = 1/sqrt(4 pi),  Q_m^m = -sqrt((2m+1)/(2m)) Q_{m-1}^{m-1},
//   Q_{m+1}^m = sqrt(2m+3) z Q_m^m,
//   Q_l^m = a (z Q_{l-1}^m - b Q_{l-2}^m),
//   a = sqrt((4l^2-1)/(l^2-m^2)),  b = sqrt(((l-1)^2-m^2)/(4(l-1)^2-1)).
//
// Any lmax up to SH_MAX_LMAX; nothing is hard-wired to 9 coefficients.
// (A loop to a run-time lmax filling a local array<f32, 81> is what the
// first version did here; llvmpipe keeps such an array in memory lane by
// lane: README, GPU speed.)

// Highest degree the shaders evaluate.
const SH_MAX_LMAX: u32 = 8u;
// (SH_MAX_LMAX + 1)^2.
const SH_MAX_COUNT: u32 = 81u;
const SH_PI: f32 = 3.14159265358979;
const SH_SQRT2: f32 = 1.41421356237310;

// Coefficient count (lmax + 1)^2.
fn sh_count(lmax: u32) -> u32 {
    return (lmax + 1u) * (lmax + 1u);
}

// Band of coefficient index i: the l with l^2 <= i < (l+1)^2.
fn sh_band(i: u32) -> u32 {
    var l = u32(sqrt(f32(i)));
    if (l + 1u) * (l + 1u) <= i {
        l = l + 1u;
    }
    if l * l > i {
        l = l - 1u;
    }
    return l;
}

//! The ring transform's inner loops, each in code compiled for AVX and FMA
//! (chosen at run time, [`crate::cpu_features`]) and in portable code that
//! also finishes the vector code's tails: for the row pass, texels into
//! channels ([`deinterleave`]), rows folded onto a quarter ([`fold_row`])
//! and the sums against the trigonometric table ([`dots`]); for the column
//! pass, the plain recurrence over a tile of degrees ([`run_plain`]) and
//! the sums of one step ([`add`], [`add_scaled`] for lanes in extended
//! exponent).

#[cfg(target_arch = "x86_64")]
use crate::cpu_features::avx_fma;
use crate::map::projection::ring_transform::blocks::{BlockWeights, LANES, Partial};
use crate::sh::real::Real;

/// Linear RGB texels into three `f64` channel buffers (from index 0).
pub(crate) fn deinterleave(texels: &[[f32; 3]], channels: &mut [Vec<f64>; 3]) {
    #[cfg(target_arch = "x86_64")]
    if avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        unsafe { deinterleave_avx(texels, channels) };
        return;
    }
    deinterleave_scalar(texels, channels, 0);
}

/// [`deinterleave`] of `texels[start..]`, one texel at a time.
#[inline(always)]
fn deinterleave_scalar(texels: &[[f32; 3]], channels: &mut [Vec<f64>; 3], start: usize) {
    let [r, g, b] = channels;
    for (i, t) in texels.iter().enumerate().skip(start) {
        r[i] = f64::from(t[0]);
        g[i] = f64::from(t[1]);
        b[i] = f64::from(t[2]);
    }
}

/// [`deinterleave`] four texels at a time ([`rgb4`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn deinterleave_avx(texels: &[[f32; 3]], channels: &mut [Vec<f64>; 3]) {
    use core::arch::x86_64::*;
    let n = texels.len();
    let body = n / 4 * 4;
    let [r, g, b] = channels;
    assert!(r.len() >= n && g.len() >= n && b.len() >= n);
    let flat = texels.as_ptr().cast::<f32>();
    // SAFETY: texel i occupies floats 3i..3i+3; chunk i (i + 3 < body <= n)
    // reads floats 3i..3i+12, inside the slice; stores write 4 lanes at
    // i + 3 < n <= channel lengths (asserted).
    unsafe {
        let mut i = 0;
        while i < body {
            let [rv, gv, bv] = rgb4(flat.add(3 * i));
            _mm256_storeu_pd(r.as_mut_ptr().add(i), rv);
            _mm256_storeu_pd(g.as_mut_ptr().add(i), gv);
            _mm256_storeu_pd(b.as_mut_ptr().add(i), bv);
            i += 4;
        }
    }
    deinterleave_scalar(texels, channels, body);
}

/// `[sum p_r cos, sum p_g cos, sum p_b cos, sum q_r sin, sum q_g sin,
/// sum q_b sin]` over `cos.len()` entries, all three channels in one pass,
/// four entries per vector lane group (`p = q` = the texels of a row, or
/// the folded quarters of [`fold_row`]).
#[inline]
pub(crate) fn dots(p: &[Vec<f64>; 3], q: &[Vec<f64>; 3], cos: &[f64], sin: &[f64]) -> [f64; 6] {
    #[cfg(target_arch = "x86_64")]
    if avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        return unsafe { dots_avx(p, q, cos, sin) };
    }
    dots_from(p, q, cos, sin, 0, [0.0; 6])
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn dots_avx(p: &[Vec<f64>; 3], q: &[Vec<f64>; 3], cos: &[f64], sin: &[f64]) -> [f64; 6] {
    use core::arch::x86_64::*;
    let n = cos.len();
    let (r, g, b) = (&p[0][..n], &p[1][..n], &p[2][..n]);
    let (u, v, t) = (&q[0][..n], &q[1][..n], &q[2][..n]);
    let sin = &sin[..n];
    let body = n / 4 * 4;
    let mut out = [0.0; 6];
    // SAFETY: every load reads 4 lanes at i + 3 < body <= n of slices of
    // length n; the CPU has AVX and FMA (checked by the caller).
    unsafe {
        let mut acc = [_mm256_setzero_pd(); 6];
        let mut i = 0;
        while i < body {
            let c = _mm256_loadu_pd(cos.as_ptr().add(i));
            let s = _mm256_loadu_pd(sin.as_ptr().add(i));
            let lanes = |x: &[f64]| _mm256_loadu_pd(x.as_ptr().add(i));
            acc[0] = _mm256_fmadd_pd(lanes(r), c, acc[0]);
            acc[1] = _mm256_fmadd_pd(lanes(g), c, acc[1]);
            acc[2] = _mm256_fmadd_pd(lanes(b), c, acc[2]);
            acc[3] = _mm256_fmadd_pd(lanes(u), s, acc[3]);
            acc[4] = _mm256_fmadd_pd(lanes(v), s, acc[4]);
            acc[5] = _mm256_fmadd_pd(lanes(t), s, acc[5]);
            i += 4;
        }
        for c in 0..6 {
            let mut lanes = [0.0; 4];
            _mm256_storeu_pd(lanes.as_mut_ptr(), acc[c]);
            out[c] = (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
        }
    }
    dots_from(p, q, cos, sin, body, out)
}

/// [`dots`] of texels `start..` added to `out`, one texel at a time (the
/// portable code, and the tail of the vector code).
#[inline(always)]
fn dots_from(
    p: &[Vec<f64>; 3],
    q: &[Vec<f64>; 3],
    cos: &[f64],
    sin: &[f64],
    start: usize,
    mut out: [f64; 6],
) -> [f64; 6] {
    for i in start..cos.len() {
        let (c, s) = (cos[i], sin[i]);
        for k in 0..3 {
            out[k] += p[k][i] * c;
            out[k + 3] += q[k][i] * s;
        }
    }
    out
}

/// Quarter entries per chunk of a folded row ([`fold_row`]).
pub(crate) const FOLD_CHUNK: usize = 128;

/// Folds entries `start..start + n` of the first quarter of a row of
/// `W = 4Q` RGB texels, `n = min(FOLD_CHUNK, Q - start)`, so the direct sums
/// over `m` run on `Q` entries instead of `W`.
///
/// Texel azimuths are `ψ_i = ±(2π (i + 1/2)/W - π)`, so the texels
/// `a = i`, `b = W-1-i`, `c = W/2+i`, `d = W/2-1-i` (`i < Q`) sit at
/// `ψ`, `-ψ`, `ψ + π` and `-ψ - π`, and
///
/// ```text
/// sum_i f_i cos(m ψ_i) = sum_{i<Q} cos(m ψ_i) [(a + b) ± (c + d)]   (P)
/// sum_i f_i sin(m ψ_i) = sum_{i<Q} sin(m ψ_i) [(a - b) ± (c - d)]   (Q)
/// ```
///
/// with `+` for even `m` and `-` for odd. `out` receives
/// `[P_even, P_odd, Q_even, Q_odd][channel][i - start]` in `f64`.
pub(crate) fn fold_row(texels: &[[f32; 3]], start: usize, out: &mut [[Vec<f64>; 3]; 4]) {
    #[cfg(target_arch = "x86_64")]
    if avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        unsafe { fold_row_avx(texels, start, out) };
        return;
    }
    fold_row_from(texels, start, 0, out);
}

/// [`fold_row`] with AVX: four entries at a time from four runs of four
/// texels (two of them read backwards).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn fold_row_avx(texels: &[[f32; 3]], start: usize, out: &mut [[Vec<f64>; 3]; 4]) {
    use core::arch::x86_64::*;
    let q = texels.len() / 4;
    let n = FOLD_CHUNK.min(q - start);
    let body = n / 4 * 4;
    let (half, w) = (2 * q, 4 * q);
    let flat = texels.as_ptr().cast::<f32>();
    assert!(out.iter().flatten().all(|v| v.len() >= n));
    let [p_even, p_odd, q_even, q_odd] = &mut *out;
    // SAFETY: for k + 3 < body <= n, i = start + k < q: the runs read are
    // texels i..i+4, half+i..half+i+4, w-4-i..w-i and half-4-i..half-i, all
    // inside the row of w texels; stores write lanes k..k+4 < n of buffers
    // of length >= n (asserted).
    unsafe {
        let reversed = |v: __m256d| _mm256_permute_pd::<0b0101>(_mm256_permute2f128_pd::<1>(v, v));
        let mut k = 0;
        while k < body {
            let i = start + k;
            let a = rgb4(flat.add(3 * i));
            let c = rgb4(flat.add(3 * (half + i)));
            let b = rgb4(flat.add(3 * (w - 4 - i))).map(reversed);
            let d = rgb4(flat.add(3 * (half - 4 - i))).map(reversed);
            for ch in 0..3 {
                let (s1, s2) = (_mm256_add_pd(a[ch], b[ch]), _mm256_add_pd(c[ch], d[ch]));
                let (d1, d2) = (_mm256_sub_pd(a[ch], b[ch]), _mm256_sub_pd(c[ch], d[ch]));
                _mm256_storeu_pd(p_even[ch].as_mut_ptr().add(k), _mm256_add_pd(s1, s2));
                _mm256_storeu_pd(p_odd[ch].as_mut_ptr().add(k), _mm256_sub_pd(s1, s2));
                _mm256_storeu_pd(q_even[ch].as_mut_ptr().add(k), _mm256_add_pd(d1, d2));
                _mm256_storeu_pd(q_odd[ch].as_mut_ptr().add(k), _mm256_sub_pd(d1, d2));
            }
            k += 4;
        }
    }
    fold_row_from(texels, start, body, out);
}

/// Four RGB texels at `flat` (12 floats) as three `f64` vectors `r, g, b`:
/// three loads of `[f32; 4]` (`r0 g0 b0 r1 | g1 b1 r2 g2 | b2 r3 g3 b3`),
/// shuffles to planar, conversion to `f64`.
///
/// # Safety
/// `flat..flat + 12` must be readable; the CPU must have AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
#[inline]
unsafe fn rgb4(flat: *const f32) -> [core::arch::x86_64::__m256d; 3] {
    use core::arch::x86_64::*;
    // SAFETY: the caller guarantees 12 readable floats.
    let (x0, x1, x2) = unsafe {
        (
            _mm_loadu_ps(flat),
            _mm_loadu_ps(flat.add(4)),
            _mm_loadu_ps(flat.add(8)),
        )
    };
    // r = [x0.0, x0.3, x1.2, x2.1]
    let r = _mm_blend_ps::<0b1000>(
        _mm_shuffle_ps::<0b00_10_11_00>(x0, x1),
        _mm_shuffle_ps::<0b01_00_00_00>(x2, x2),
    );
    // g = [x0.1, x1.0, x1.3, x2.2]
    let u = _mm_shuffle_ps::<0b11_00_01_01>(x0, x1);
    let g = _mm_blend_ps::<0b1000>(
        _mm_shuffle_ps::<0b11_11_10_00>(u, u),
        _mm_shuffle_ps::<0b10_00_00_00>(x2, x2),
    );
    // b = [x0.2, x1.1, x2.0, x2.3]
    let v = _mm_shuffle_ps::<0b01_01_10_10>(x0, x1);
    let b = _mm_shuffle_ps::<0b11_00_10_00>(v, x2);
    [_mm256_cvtps_pd(r), _mm256_cvtps_pd(g), _mm256_cvtps_pd(b)]
}

/// [`fold_row`] of chunk entries `from..`, one at a time (the portable
/// code, and the tail of the vector code).
#[inline(always)]
fn fold_row_from(texels: &[[f32; 3]], start: usize, from: usize, out: &mut [[Vec<f64>; 3]; 4]) {
    let q = texels.len() / 4;
    let n = FOLD_CHUNK.min(q - start);
    let (half, w) = (2 * q, 4 * q);
    let [p_even, p_odd, q_even, q_odd] = out;
    for k in from..n {
        let i = start + k;
        let [a, b, c, d] = [i, w - 1 - i, half + i, half - 1 - i].map(|t| texels[t]);
        for ch in 0..3 {
            let [a, b, c, d] = [a[ch], b[ch], c[ch], d[ch]].map(f64::from);
            let (s1, s2, d1, d2) = (a + b, c + d, a - b, c - d);
            p_even[ch][k] = s1 + s2;
            p_odd[ch][k] = s1 - s2;
            q_even[ch][k] = d1 + d2;
            q_odd[ch][k] = d1 - d2;
        }
    }
}

/// A lane at `k = -1` whose mantissa is under this is worth less than
/// `2^-200` and is left out of the sums (lanes at `k <= -2` always are).
const NEGLIGIBLE_MANTISSA: f64 = 2.582_249_878_086_908_6e120; // 2^400

/// The recurrence from `(Q_{l-2}, Q_{l-1}) = (p1, p2)` on for every
/// `alpha` (all lanes at `k = 0`), each new `Q_l` added to `acc` (one entry
/// per step) against the weights of its parity, `w[parity]` first; `p1`
/// and `p2` are left at the last two values.
#[inline(always)]
pub(crate) fn run_plain<const FMA: bool>(
    x: &[f64; LANES],
    p1: &mut [f64; LANES],
    p2: &mut [f64; LANES],
    alpha: &[f64],
    acc: &mut [Partial],
    w: &BlockWeights,
    parity: usize,
) {
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: FMA is only set in functions compiled for AVX and FMA,
        // which run after the runtime feature check.
        unsafe { run_plain_avx(x, p1, p2, alpha, acc, w, parity) };
        return;
    }
    for (i, (&a, acc)) in alpha.iter().zip(acc).enumerate() {
        let mut p3 = [0.0; LANES];
        for j in 0..LANES {
            p3[j] = a * x[j] * p2[j] - p1[j];
        }
        *p1 = *p2;
        *p2 = p3;
        add::<false>(acc, p2, &w[(parity + i) % 2]);
    }
}

/// [`run_plain`] in AVX and FMA registers: the lanes' `x`, `Q_{l-2}` and
/// `Q_{l-1}` stay in twelve registers, two steps per pass so that no
/// register is copied.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn run_plain_avx(
    x: &[f64; LANES],
    p1: &mut [f64; LANES],
    p2: &mut [f64; LANES],
    alpha: &[f64],
    acc: &mut [Partial],
    w: &BlockWeights,
    parity: usize,
) {
    use core::arch::x86_64::*;
    assert!(acc.len() >= alpha.len());
    // One step: `q_old <- alpha x q_new - q_old`, then its sums.
    #[inline(always)]
    unsafe fn step(
        a: f64,
        xv: &[__m256d; 4],
        q_new: &[__m256d; 4],
        q_old: &mut [__m256d; 4],
        acc: *mut f64,
        w: *const f64,
    ) {
        // SAFETY: the caller passes 24 sums at `acc` and a parity's 96
        // weights at `w`.
        unsafe {
            let av = _mm256_set1_pd(a);
            for g in 0..4 {
                let t = _mm256_mul_pd(av, xv[g]);
                q_old[g] = _mm256_fmsub_pd(t, q_new[g], q_old[g]);
            }
            for c in 0..6 {
                let pa = acc.add(4 * c);
                let wc = w.add(LANES * c);
                let mut v = _mm256_loadu_pd(pa);
                v = _mm256_fmadd_pd(q_old[0], _mm256_loadu_pd(wc), v);
                v = _mm256_fmadd_pd(q_old[1], _mm256_loadu_pd(wc.add(4)), v);
                v = _mm256_fmadd_pd(q_old[2], _mm256_loadu_pd(wc.add(8)), v);
                v = _mm256_fmadd_pd(q_old[3], _mm256_loadu_pd(wc.add(12)), v);
                _mm256_storeu_pd(pa, v);
            }
        }
    }
    // SAFETY: the loads and stores of the lanes are within the fixed-size
    // arrays, `acc` has an entry (24 values) per `alpha`, and `k + 1 < n`
    // is checked before the second step of a pass.
    unsafe {
        let load4 = |p: *const f64| {
            [
                _mm256_loadu_pd(p),
                _mm256_loadu_pd(p.add(4)),
                _mm256_loadu_pd(p.add(8)),
                _mm256_loadu_pd(p.add(12)),
            ]
        };
        let store4 = |p: *mut f64, v: &[__m256d; 4]| {
            for (g, v) in v.iter().enumerate() {
                _mm256_storeu_pd(p.add(4 * g), *v);
            }
        };
        let xv = load4(x.as_ptr());
        let mut q1 = load4(p1.as_ptr());
        let mut q2 = load4(p2.as_ptr());
        let (w_a, w_b) = (
            w[parity % 2].as_ptr().cast::<f64>(),
            w[(parity + 1) % 2].as_ptr().cast::<f64>(),
        );
        let n = alpha.len();
        let acc = acc.as_mut_ptr().cast::<f64>();
        let mut k = 0;
        while k + 1 < n {
            step(alpha[k], &xv, &q2, &mut q1, acc.add(24 * k), w_a);
            step(alpha[k + 1], &xv, &q1, &mut q2, acc.add(24 * (k + 1)), w_b);
            k += 2;
        }
        if k < n {
            // One step left: the newest value lands in q1.
            step(alpha[k], &xv, &q2, &mut q1, acc.add(24 * k), w_a);
            store4(p1.as_mut_ptr(), &q2);
            store4(p2.as_mut_ptr(), &q1);
        } else {
            store4(p1.as_mut_ptr(), &q1);
            store4(p2.as_mut_ptr(), &q2);
        }
    }
}

/// [`add`] of the true values of extended-exponent lanes (see
/// [`crate::sh::Legendre`]); nothing when every lane is negligible.
#[inline(always)]
pub(crate) fn add_scaled<const FMA: bool>(
    acc: &mut Partial,
    p: &[f64; LANES],
    k: &[f64; LANES],
    scaled: bool,
    w: &[[f64; LANES]; 6],
) {
    if !scaled {
        add::<FMA>(acc, p, w);
        return;
    }
    let mut out = [0.0; LANES];
    let mut any = false;
    for j in 0..LANES {
        out[j] = if k[j] == 0.0 {
            p[j]
        } else if k[j] == -1.0 && p[j].abs() >= NEGLIGIBLE_MANTISSA {
            p[j] * f64::SMALL
        } else {
            0.0
        };
        any |= out[j] != 0.0;
    }
    if any {
        add::<FMA>(acc, &out, w);
    }
}

/// `acc[c][q] += sum_g p[4g + q] w[c][4g + q]`: four lanes per vector,
/// one vector of partial sums per channel.
///
/// `FMA` is true only in code compiled for AVX and FMA (`column_avx`).
#[inline(always)]
fn add<const FMA: bool>(acc: &mut Partial, p: &[f64; LANES], w: &[[f64; LANES]; 6]) {
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: FMA is only set in functions compiled for AVX and FMA,
        // which run after the runtime feature check.
        unsafe { add_avx(acc, p, w) };
        return;
    }
    for c in 0..6 {
        for g in (0..LANES).step_by(4) {
            for q in 0..4 {
                acc[c][q] += p[g + q] * w[c][g + q];
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
#[inline]
unsafe fn add_avx(acc: &mut Partial, p: &[f64; LANES], w: &[[f64; LANES]; 6]) {
    use core::arch::x86_64::*;
    // SAFETY: all loads and stores are within the fixed-size arrays.
    unsafe {
        let pv = [0, 4, 8, 12].map(|g| _mm256_loadu_pd(p.as_ptr().add(g)));
        for c in 0..6 {
            let a = acc[c].as_mut_ptr();
            let wc = w[c].as_ptr();
            let mut v = _mm256_loadu_pd(a);
            for (g, pg) in pv.iter().enumerate() {
                v = _mm256_fmadd_pd(*pg, _mm256_loadu_pd(wc.add(4 * g)), v);
            }
            _mm256_storeu_pd(a, v);
        }
    }
}

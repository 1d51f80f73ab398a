//! The ring transform behind equirect projection: azimuthal sums per row,
//! then Legendre sums per column `m`, with the map's pole as the basis's
//! polar axis (z-up).
//!
//! For rows `j` (colatitude `θ_j`, texel solid angle `Ω_j`) and texel
//! azimuths `ψ_i` about the pole,
//!
//! ```text
//! L_l^m    = sqrt2 sum_j Ω_j Pbar_l^m(cos θ_j) C_m(j),  C_m(j) = sum_i f_ji cos(m ψ_i)
//! L_l^-m   = sqrt2 sum_j Ω_j Pbar_l^m(cos θ_j) S_m(j),  S_m(j) = sum_i f_ji sin(m ψ_i)
//! ```
//!
//! (no `sqrt2` at `m = 0`). Two phases:
//!
//! 1. **Azimuthal sums**, row by row: direct sums against a table of
//!    `cos(m ψ_i)`, `sin(m ψ_i)` for small lmax, a real FFT of each row for
//!    large lmax (`O(W log W)` instead of `O(W lmax)`). With
//!    `ψ_i = ∓φ_i`, `φ_i = 2π i/W + c`, `c = π/W - π`:
//!    `sum_i f_i e^{-i m φ_i} = e^{-i m c} X_m`, `X` the DFT of the row
//!    (`X_m` for `m >= W` wraps around, as the sum does).
//! 2. **Legendre sums**, column `m` by column: rows `j` and `H-1-j` sit at
//!    `±cos θ` with the same `Ω`, and `Pbar_l^m(-x) = (-1)^(l+m) Pbar_l^m(x)`,
//!    so each pair enters through `Ω (C(j) ± C(H-1-j))` and the recurrence
//!    runs once per pair, on 16 pairs at a time (vector lanes), with the
//!    extended exponent of [`crate::legendre`] near the poles.
//!
//! Columns are independent, so phase 2 runs in parallel over `m`; phase 1
//! in parallel over row pairs. All sums are in `f64`. On x86-64 CPUs with
//! AVX and FMA both phases run in code compiled for them (runtime check).

use core::f64::consts::PI;

use glam::DVec3;
use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

use crate::legendre::Legendre;
use crate::projection::{EquirectView, equirect_row_solid_angle};
use crate::{Real, ShCoeffs, sh_index};

/// Tests set this to run the portable code on CPUs that have AVX and FMA.
#[cfg(test)]
pub(crate) static FORCE_PORTABLE: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Whether the AVX + FMA kernels can run (and are not switched off by a test).
#[cfg(target_arch = "x86_64")]
#[inline]
fn avx_fma() -> bool {
    #[cfg(test)]
    if FORCE_PORTABLE.load(std::sync::atomic::Ordering::Relaxed) {
        return false;
    }
    std::arch::is_x86_feature_detected!("avx") && std::arch::is_x86_feature_detected!("fma")
}

/// Lanes (row pairs) per recurrence pass in phase 2.
const LANES: usize = 16;

/// From this lmax on, rows are transformed by FFT instead of direct sums.
/// Chosen by operation count on 2048-wide rows: direct sums cost
/// `6 W (lmax + 1)` multiply-adds per row, three real FFTs about
/// `3 · 2.5 W log2 W`, equal near lmax 20 (the crossover was not measured).
pub(crate) const FFT_FROM_LMAX: usize = 24;

/// Per row pair and column `m`: `Ω f_m (A ± B)` for the even / odd parity of
/// `l + m`, as `[C_r, C_g, C_b, S_r, S_g, S_b, 0, 0]` (8 wide for vector lanes).
type Weights = [f64; 8];

/// Radiance coefficients of an equirect map about its own pole (z-up), the
/// azimuth of texel column `i` being `sign * φ_i`.
pub(crate) fn project_rings(map: EquirectView<'_>, lmax: usize, sign: f64) -> ShCoeffs<DVec3> {
    let (w, h) = (map.width, map.height);
    let pairs = h.div_ceil(2);
    let cols = lmax + 1;
    let leg = Legendre::<f64>::new(lmax);
    let azimuth = Azimuth::new(w, lmax, sign);

    // Phase 1: weights [pair][m][parity] and sectoral start values [pair][m].
    let mut weights = vec![[0.0; 8]; pairs * cols * 2];
    let mut sectoral = vec![[0.0; 2]; pairs * cols];
    let mut xs = vec![0.0; pairs];
    let phase1 =
        |p: usize, wts: &mut [Weights], sect: &mut [[f64; 2]], x: &mut f64, s: &mut Scratch| {
            let j2 = h - 1 - p;
            azimuth.row(&map.pixels[p * w..(p + 1) * w], &mut s.ring_a, &mut s.bufs);
            if j2 != p {
                azimuth.row(
                    &map.pixels[j2 * w..(j2 + 1) * w],
                    &mut s.ring_b,
                    &mut s.bufs,
                );
            } else {
                s.ring_b.iter_mut().for_each(|r| *r = [0.0; 6]);
            }
            let omega = equirect_row_solid_angle(p, w, h);
            for m in 0..cols {
                let f = omega * if m == 0 { 1.0 } else { 2f64.sqrt() };
                let (a, b) = (s.ring_a[m], s.ring_b[m]);
                for c in 0..6 {
                    wts[2 * m][c] = f * (a[c] + b[c]);
                    wts[2 * m + 1][c] = f * (a[c] - b[c]);
                }
            }
            let theta = PI * (p as f64 + 0.5) / h as f64;
            *x = theta.cos();
            sectoral_values(&leg, theta.sin(), sect);
        };
    let new_scratch = || Scratch::new(w, lmax, &azimuth);
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        weights
            .par_chunks_mut(cols * 2)
            .zip(sectoral.par_chunks_mut(cols))
            .zip(xs.par_iter_mut())
            .enumerate()
            .for_each_init(new_scratch, |s, (p, ((wts, sect), x))| {
                phase1(p, wts, sect, x, s)
            });
    }
    #[cfg(not(feature = "rayon"))]
    {
        let mut s = new_scratch();
        for (p, ((wts, sect), x)) in weights
            .chunks_mut(cols * 2)
            .zip(sectoral.chunks_mut(cols))
            .zip(xs.iter_mut())
            .enumerate()
        {
            phase1(p, wts, sect, x, &mut s);
        }
    }

    // Phase 2: one column m at a time.
    let input = ColumnInput {
        leg: &leg,
        lmax,
        pairs,
        xs: &xs,
        weights: &weights,
        sectoral: &sectoral,
    };
    // Long columns (small m) and short ones interleaved for load balance.
    let order = |i: usize| {
        if i.is_multiple_of(2) {
            i / 2
        } else {
            lmax - i / 2
        }
    };
    #[cfg(feature = "rayon")]
    let sums: Vec<(usize, Vec<Weights>)> = {
        use rayon::prelude::*;
        (0..cols)
            .into_par_iter()
            .with_max_len(1)
            .map(|i| (order(i), column(&input, order(i))))
            .collect()
    };
    #[cfg(not(feature = "rayon"))]
    let sums: Vec<(usize, Vec<Weights>)> = (0..cols)
        .map(|i| (order(i), column(&input, order(i))))
        .collect();

    let mut out = ShCoeffs::<DVec3>::zeros(lmax);
    for (m, col) in sums {
        for (i, v) in col.iter().enumerate() {
            let l = m + i;
            out[sh_index(l, m as isize)] = DVec3::new(v[0], v[1], v[2]);
            if m > 0 {
                out[sh_index(l, -(m as isize))] = DVec3::new(v[3], v[4], v[5]);
            }
        }
    }
    out
}

/// `Pbar_m^m(sin θ)` for every `m`, as `(mantissa, exponent count k <= 0)`
/// with the true value `mantissa * SMALL^(-k)` ([`crate::legendre`]).
fn sectoral_values(leg: &Legendre<f64>, s: f64, out: &mut [[f64; 2]]) {
    let (big, small) = (f64::BIG, f64::SMALL);
    let mut p = 0.5 / PI.sqrt();
    let mut k = 0.0;
    for (m, o) in out.iter_mut().enumerate() {
        if m > 0 {
            p *= leg.sectoral_factor(m) * s;
            if p.abs() < small {
                p *= big;
                k -= 1.0;
            }
        }
        *o = [p, k];
    }
}

/// Row transform: the table of `cos(m ψ_i)`, `sin(m ψ_i)` or an FFT plan.
struct Azimuth {
    w: usize,
    lmax: usize,
    sign: f64,
    /// `[m][i]` cosines and sines for the direct sums (empty with FFT).
    cos: Vec<f64>,
    sin: Vec<f64>,
    fft: Option<std::sync::Arc<dyn RealToComplex<f64>>>,
    /// `e^{-i m c}`, `c = π/W - π`, per `m` (FFT path).
    phase: Vec<Complex<f64>>,
}

/// Per-thread buffers of phase 1.
struct Scratch {
    ring_a: Vec<[f64; 6]>,
    ring_b: Vec<[f64; 6]>,
    bufs: RowBuffers,
}

/// Buffers for [`Azimuth::row`].
struct RowBuffers {
    channels: [Vec<f64>; 3],
    spectrum: Vec<Complex<f64>>,
    fft_scratch: Vec<Complex<f64>>,
}

impl Scratch {
    fn new(w: usize, lmax: usize, az: &Azimuth) -> Self {
        let (spectrum, fft_scratch) = match &az.fft {
            Some(f) => (f.make_output_vec(), f.make_scratch_vec()),
            None => (Vec::new(), Vec::new()),
        };
        Self {
            ring_a: vec![[0.0; 6]; lmax + 1],
            ring_b: vec![[0.0; 6]; lmax + 1],
            bufs: RowBuffers {
                channels: [vec![0.0; w], vec![0.0; w], vec![0.0; w]],
                spectrum,
                fft_scratch,
            },
        }
    }
}

impl Azimuth {
    fn new(w: usize, lmax: usize, sign: f64) -> Self {
        let angle = |i: usize| 2.0 * PI * ((i as f64 + 0.5) / w as f64 - 0.5);
        if lmax >= FFT_FROM_LMAX && w > 1 {
            let fft = RealFftPlanner::<f64>::new().plan_fft_forward(w);
            let c = PI / w as f64 - PI;
            let phase = (0..=lmax)
                .map(|m| {
                    let (s, co) = (-(m as f64) * c).sin_cos();
                    Complex::new(co, s)
                })
                .collect();
            return Self {
                w,
                lmax,
                sign,
                cos: Vec::new(),
                sin: Vec::new(),
                fft: Some(fft),
                phase,
            };
        }
        let mut cos = vec![0.0; (lmax + 1) * w];
        let mut sin = vec![0.0; (lmax + 1) * w];
        for m in 0..=lmax {
            for i in 0..w {
                let (s, c) = (m as f64 * sign * angle(i)).sin_cos();
                cos[m * w + i] = c;
                sin[m * w + i] = s;
            }
        }
        Self {
            w,
            lmax,
            sign,
            cos,
            sin,
            fft: None,
            phase: Vec::new(),
        }
    }

    /// `ring[m] = [C_r, C_g, C_b, S_r, S_g, S_b]` of one row of texels.
    fn row(&self, texels: &[[f32; 3]], ring: &mut [[f64; 6]], s: &mut RowBuffers) {
        match &self.fft {
            None => {
                // Blocks of texels small enough that the channels and the
                // trig rows they meet stay in the L1 cache.
                ring.iter_mut().for_each(|r| *r = [0.0; 6]);
                for start in (0..self.w).step_by(DIRECT_BLOCK) {
                    let end = (start + DIRECT_BLOCK).min(self.w);
                    deinterleave(&texels[start..end], &mut s.channels);
                    for (m, out) in ring.iter_mut().enumerate() {
                        let cos = &self.cos[m * self.w + start..m * self.w + end];
                        let sin = &self.sin[m * self.w + start..m * self.w + end];
                        let d = dots(&s.channels, cos, sin);
                        for c in 0..6 {
                            out[c] += d[c];
                        }
                    }
                }
            }
            Some(fft) => {
                deinterleave(texels, &mut s.channels);
                let half = self.w / 2;
                for c in 0..3 {
                    // The transform reuses the input as scratch; the channel
                    // buffer is refilled for every row anyway.
                    fft.process_with_scratch(
                        &mut s.channels[c],
                        &mut s.spectrum,
                        &mut s.fft_scratch,
                    )
                    .expect("buffer sizes come from the plan");
                    for m in 0..=self.lmax {
                        let k = m % self.w;
                        let x = if k <= half {
                            s.spectrum[k]
                        } else {
                            s.spectrum[self.w - k].conj()
                        };
                        let mut z = self.phase[m] * x;
                        if self.sign > 0.0 {
                            z = z.conj();
                        }
                        ring[m][c] = z.re;
                        ring[m][c + 3] = z.im;
                    }
                }
            }
        }
    }
}

/// Texels per block of the direct sums.
const DIRECT_BLOCK: usize = 512;

/// Linear RGB texels into three `f64` channel buffers (from index 0).
fn deinterleave(texels: &[[f32; 3]], channels: &mut [Vec<f64>; 3]) {
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

/// [`deinterleave`] four texels at a time: three loads of `[f32; 4]`
/// (`r0 g0 b0 r1 | g1 b1 r2 g2 | b2 r3 g3 b3`), shuffles to planar, and
/// conversion to `f64`.
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
            let x0 = _mm_loadu_ps(flat.add(3 * i));
            let x1 = _mm_loadu_ps(flat.add(3 * i + 4));
            let x2 = _mm_loadu_ps(flat.add(3 * i + 8));
            // r = [x0.0, x0.3, x1.2, x2.1]
            let rv = _mm_blend_ps::<0b1000>(
                _mm_shuffle_ps::<0b00_10_11_00>(x0, x1),
                _mm_shuffle_ps::<0b01_00_00_00>(x2, x2),
            );
            // g = [x0.1, x1.0, x1.3, x2.2]
            let u = _mm_shuffle_ps::<0b11_00_01_01>(x0, x1);
            let gv = _mm_blend_ps::<0b1000>(
                _mm_shuffle_ps::<0b11_11_10_00>(u, u),
                _mm_shuffle_ps::<0b10_00_00_00>(x2, x2),
            );
            // b = [x0.2, x1.1, x2.0, x2.3]
            let v = _mm_shuffle_ps::<0b01_01_10_10>(x0, x1);
            let bv = _mm_shuffle_ps::<0b11_00_10_00>(v, x2);
            _mm256_storeu_pd(r.as_mut_ptr().add(i), _mm256_cvtps_pd(rv));
            _mm256_storeu_pd(g.as_mut_ptr().add(i), _mm256_cvtps_pd(gv));
            _mm256_storeu_pd(b.as_mut_ptr().add(i), _mm256_cvtps_pd(bv));
            i += 4;
        }
    }
    deinterleave_scalar(texels, channels, body);
}

/// `[sum r cos, sum g cos, sum b cos, sum r sin, sum g sin, sum b sin]` over
/// one row, all three channels in one pass, four texels per vector lane
/// group.
#[inline]
fn dots(ch: &[Vec<f64>; 3], cos: &[f64], sin: &[f64]) -> [f64; 6] {
    #[cfg(target_arch = "x86_64")]
    if avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        return unsafe { dots_avx(ch, cos, sin) };
    }
    dots_from(ch, cos, sin, 0, [0.0; 6])
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn dots_avx(ch: &[Vec<f64>; 3], cos: &[f64], sin: &[f64]) -> [f64; 6] {
    use core::arch::x86_64::*;
    let n = cos.len();
    let (r, g, b) = (&ch[0][..n], &ch[1][..n], &ch[2][..n]);
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
            let x = _mm256_loadu_pd(r.as_ptr().add(i));
            let y = _mm256_loadu_pd(g.as_ptr().add(i));
            let z = _mm256_loadu_pd(b.as_ptr().add(i));
            acc[0] = _mm256_fmadd_pd(x, c, acc[0]);
            acc[1] = _mm256_fmadd_pd(y, c, acc[1]);
            acc[2] = _mm256_fmadd_pd(z, c, acc[2]);
            acc[3] = _mm256_fmadd_pd(x, s, acc[3]);
            acc[4] = _mm256_fmadd_pd(y, s, acc[4]);
            acc[5] = _mm256_fmadd_pd(z, s, acc[5]);
            i += 4;
        }
        for c in 0..6 {
            let mut lanes = [0.0; 4];
            _mm256_storeu_pd(lanes.as_mut_ptr(), acc[c]);
            out[c] = (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
        }
    }
    dots_from(ch, cos, sin, body, out)
}

/// `a * b + c`, fused when the code is compiled for FMA.
#[inline(always)]
fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

/// [`dots`] of texels `start..` added to `out`, one texel at a time (the
/// portable code, and the tail of the vector code).
#[inline(always)]
fn dots_from(
    ch: &[Vec<f64>; 3],
    cos: &[f64],
    sin: &[f64],
    start: usize,
    mut out: [f64; 6],
) -> [f64; 6] {
    let n = cos.len();
    let (r, g, b) = (&ch[0][..n], &ch[1][..n], &ch[2][..n]);
    for i in start..n {
        let (c, s) = (cos[i], sin[i]);
        out[0] += r[i] * c;
        out[1] += g[i] * c;
        out[2] += b[i] * c;
        out[3] += r[i] * s;
        out[4] += g[i] * s;
        out[5] += b[i] * s;
    }
    out
}

/// Everything phase 2 reads.
struct ColumnInput<'a> {
    leg: &'a Legendre<f64>,
    lmax: usize,
    pairs: usize,
    xs: &'a [f64],
    weights: &'a [Weights],
    sectoral: &'a [[f64; 2]],
}

/// The sums of column `m`: entry `l - m` for `l = m..=lmax`.
fn column(input: &ColumnInput<'_>, m: usize) -> Vec<Weights> {
    #[cfg(target_arch = "x86_64")]
    if avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        return unsafe { column_avx(input, m) };
    }
    column_body::<false>(input, m)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn column_avx(input: &ColumnInput<'_>, m: usize) -> Vec<Weights> {
    column_body::<true>(input, m)
}

#[inline(always)]
fn column_body<const FMA: bool>(input: &ColumnInput<'_>, m: usize) -> Vec<Weights> {
    let lmax = input.lmax;
    let cols = lmax + 1;
    let mut out = vec![[0.0; 8]; lmax - m + 1];
    let (big, small) = (f64::BIG, f64::SMALL);
    let diag = input.leg.diagonal_factor(m);
    let factors = input.leg.column_factors(m);
    let mut start = 0;
    while start < input.pairs {
        let n = LANES.min(input.pairs - start);
        let mut x = [0.0; LANES];
        let mut p1 = [0.0; LANES];
        let mut k = [0.0; LANES];
        let mut we = [[0.0; 8]; LANES];
        let mut wo = [[0.0; 8]; LANES];
        for j in 0..n {
            let p = start + j;
            x[j] = input.xs[p];
            let [v, e] = input.sectoral[p * cols + m];
            p1[j] = v;
            k[j] = e;
            we[j] = input.weights[(p * cols + m) * 2];
            wo[j] = input.weights[(p * cols + m) * 2 + 1];
        }
        start += n;
        let scaled = k.iter().any(|&e| e != 0.0);
        accumulate::<FMA>(&mut out[0], &unscale(&p1, &k, scaled), &we);
        if m == lmax {
            continue;
        }
        let mut p2 = [0.0; LANES];
        for j in 0..LANES {
            p2[j] = diag * x[j] * p1[j];
        }
        accumulate::<FMA>(&mut out[1], &unscale(&p2, &k, scaled), &wo);
        for (i, &[a, ab]) in factors.iter().enumerate() {
            let mut p3 = [0.0; LANES];
            if scaled {
                for j in 0..LANES {
                    let v = a * x[j] * p2[j] - ab * p1[j];
                    let grow = k[j] < 0.0 && v.abs() > big;
                    p3[j] = if grow { v * small } else { v };
                    p2[j] = if grow { p2[j] * small } else { p2[j] };
                    k[j] = if grow { k[j] + 1.0 } else { k[j] };
                }
            } else {
                for j in 0..LANES {
                    p3[j] = madd::<FMA>(a * x[j], p2[j], -ab * p1[j]);
                }
            }
            p1 = p2;
            p2 = p3;
            let w = if i % 2 == 0 { &we } else { &wo };
            accumulate::<FMA>(&mut out[i + 2], &unscale(&p2, &k, scaled), w);
        }
    }
    out
}

/// `acc += sum_j p[j] w[j]`, in four independent partial sums.
///
/// `FMA` is true only in code compiled for AVX and FMA (`column_avx`).
#[inline(always)]
fn accumulate<const FMA: bool>(acc: &mut Weights, p: &[f64; LANES], w: &[Weights; LANES]) {
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: FMA is only set in functions compiled for AVX and FMA,
        // which run after the runtime feature check.
        unsafe { accumulate_avx(acc, p, w) };
        return;
    }
    let mut t = [[0.0; 8]; 4];
    for j in (0..LANES).step_by(4) {
        for q in 0..4 {
            for c in 0..8 {
                t[q][c] += p[j + q] * w[j + q][c];
            }
        }
    }
    for c in 0..8 {
        acc[c] += (t[0][c] + t[1][c]) + (t[2][c] + t[3][c]);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
#[inline]
unsafe fn accumulate_avx(acc: &mut Weights, p: &[f64; LANES], w: &[Weights; LANES]) {
    use core::arch::x86_64::*;
    // SAFETY: all loads and stores are within the fixed-size arrays.
    unsafe {
        let mut lo = [_mm256_setzero_pd(); 4];
        let mut hi = [_mm256_setzero_pd(); 4];
        for j in (0..LANES).step_by(4) {
            for q in 0..4 {
                let pj = _mm256_set1_pd(p[j + q]);
                let wp = w[j + q].as_ptr();
                lo[q] = _mm256_fmadd_pd(pj, _mm256_loadu_pd(wp), lo[q]);
                hi[q] = _mm256_fmadd_pd(pj, _mm256_loadu_pd(wp.add(4)), hi[q]);
            }
        }
        let l = _mm256_add_pd(_mm256_add_pd(lo[0], lo[1]), _mm256_add_pd(lo[2], lo[3]));
        let h = _mm256_add_pd(_mm256_add_pd(hi[0], hi[1]), _mm256_add_pd(hi[2], hi[3]));
        let a = acc.as_mut_ptr();
        _mm256_storeu_pd(a, _mm256_add_pd(_mm256_loadu_pd(a), l));
        _mm256_storeu_pd(a.add(4), _mm256_add_pd(_mm256_loadu_pd(a.add(4)), h));
    }
}

/// True values of extended-exponent lanes (see [`crate::legendre`]).
#[inline(always)]
fn unscale(p: &[f64; LANES], k: &[f64; LANES], scaled: bool) -> [f64; LANES] {
    if !scaled {
        return *p;
    }
    let mut out = [0.0; LANES];
    for j in 0..LANES {
        out[j] = if k[j] == 0.0 {
            p[j]
        } else if k[j] == -1.0 {
            p[j] * f64::SMALL
        } else {
            0.0
        };
    }
    out
}

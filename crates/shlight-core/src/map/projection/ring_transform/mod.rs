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
//! 1. **Azimuthal sums**, row by row: for small lmax, direct sums against a
//!    table of `cos(m ψ_i)`, `sin(m ψ_i)` over the row folded onto its first
//!    quarter by the symmetries `ψ -> -ψ` and `ψ -> ψ + π` (`fold_row`;
//!    `W/4` multiply-adds per `m` instead of `W`); for large lmax, a real FFT
//!    of each row (`O(W log W)` instead of `O(W lmax)`). With
//!    `ψ_i = ∓φ_i`, `φ_i = 2π i/W + c`, `c = π/W - π`:
//!    `sum_i f_i e^{-i m φ_i} = e^{-i m c} X_m`, `X` the DFT of the row
//!    (`X_m` for `m >= W` wraps around, as the sum does).
//! 2. **Legendre sums**, column `m` by column: rows `j` and `H-1-j` sit at
//!    `±cos θ` with the same `Ω`, and `Pbar_l^m(-x) = (-1)^(l+m) Pbar_l^m(x)`,
//!    so each pair enters through `Ω (C(j) ± C(H-1-j))` and the recurrence
//!    runs once per pair, on 16 pairs at a time (vector lanes), with the
//!    extended exponent of [`crate::sh`] near the poles; lanes worth
//!    less than `2^-200` are left out, and a block whose lanes are all such
//!    skips its sums. The recurrence is taken in the form with a unit
//!    coefficient on `l - 2` ([`UnitRecurrence`]: two operations per lane
//!    and degree), its state held in registers, and the degrees are run in
//!    tiles of [`TILE`], every block of a column through one tile before
//!    the next, so that the tile's sums stay in the L1 cache.
//!
//! Columns are independent, so phase 2 runs in parallel over `m`; phase 1
//! in parallel over row pairs. All sums are in `f64`. On x86-64 CPUs with
//! AVX and FMA both phases run in code compiled for them (runtime check).

use core::f64::consts::PI;

use glam::DVec3;
use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

use crate::map::equirect::equirect_row_solid_angle;
use crate::map::texel_source::{TexelSource, read_row};
use crate::sh::index::sh_index;
use crate::sh::legendre::Legendre;
use crate::sh::real::Real;
use crate::sh::sh_coeffs::ShCoeffs;

#[cfg(target_arch = "x86_64")]
use crate::cpu_features::avx_fma;

/// Lanes (row pairs) per recurrence pass in phase 2.
const LANES: usize = 16;

/// From this lmax on, rows are transformed by FFT instead of direct sums.
/// Chosen by instruction counts (callgrind) of a 2048x1024 projection: the
/// folded direct sums ([`fold_row`]) cost 73 M instructions at lmax 24,
/// 110 M at 40 and 169 M at 63; the FFT path 137 M, 142 M and 150 M.
pub(crate) const FFT_FROM_LMAX: usize = 48;

/// One block of [`LANES`] row pairs for one column `m`: both parities'
/// weights `Ω f_m (A ± B)` (even / odd `l + m`), channel-major as
/// `[parity][C_r, C_g, C_b, S_r, S_g, S_b][lane]`, ready for vector lanes.
type BlockWeights = [[[f64; LANES]; 6]; 2];

/// One block's per-pair data for one column `m`: the sectoral start value
/// `Pbar_m^m(sin θ)` as mantissa and exponent count per lane.
#[derive(Clone, Copy)]
struct BlockStart {
    value: [f64; LANES],
    exponent: [f64; LANES],
}

/// Radiance coefficients of an equirect map about its own pole (z-up), the
/// azimuth of texel column `i` being `sign * φ_i`. Rows are read through
/// [`read_row`]: straight from the source when it stores them contiguously.
pub(crate) fn project_rings<S: TexelSource + ?Sized>(
    map: &S,
    lmax: usize,
    sign: f64,
) -> ShCoeffs<DVec3> {
    let (w, h) = map.size();
    let pairs = h.div_ceil(2);
    let blocks = pairs.div_ceil(LANES);
    let cols = lmax + 1;
    let leg = Legendre::<f64>::new(lmax);
    let azimuth = Azimuth::new(w, lmax, sign);

    // Phase 1, per block of row pairs: weights and sectoral start values
    // `[block][m]`, and `cos θ` per lane. Lanes past the last pair stay zero.
    let zero_start = BlockStart {
        value: [0.0; LANES],
        exponent: [0.0; LANES],
    };
    let mut weights = vec![[[[0.0; LANES]; 6]; 2]; blocks * cols];
    let mut starts = vec![zero_start; blocks * cols];
    let mut xs = vec![[0.0; LANES]; blocks];
    let phase1 = |b: usize,
                  wts: &mut [BlockWeights],
                  st: &mut [BlockStart],
                  x: &mut [f64; LANES],
                  s: &mut Scratch| {
        for lane in 0..LANES.min(pairs - b * LANES) {
            let p = b * LANES + lane;
            let j2 = h - 1 - p;
            let row = read_row(map, p, &mut s.texels);
            azimuth.row(row, &mut s.ring_a, &mut s.bufs);
            if j2 != p {
                let row = read_row(map, j2, &mut s.texels);
                azimuth.row(row, &mut s.ring_b, &mut s.bufs);
            } else {
                s.ring_b.iter_mut().for_each(|r| *r = [0.0; 6]);
            }
            let omega = equirect_row_solid_angle(p, w, h);
            let theta = PI * (p as f64 + 0.5) / h as f64;
            x[lane] = theta.cos();
            sectoral_values(&leg, theta.sin(), &mut s.sectoral);
            for m in 0..cols {
                let f = omega * if m == 0 { 1.0 } else { 2f64.sqrt() };
                let (a, b) = (s.ring_a[m], s.ring_b[m]);
                for c in 0..6 {
                    wts[m][0][c][lane] = f * (a[c] + b[c]);
                    wts[m][1][c][lane] = f * (a[c] - b[c]);
                }
                [st[m].value[lane], st[m].exponent[lane]] = s.sectoral[m];
            }
        }
    };
    let new_scratch = || Scratch::new(w, lmax, &azimuth);
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        weights
            .par_chunks_mut(cols)
            .zip(starts.par_chunks_mut(cols))
            .zip(xs.par_iter_mut())
            .enumerate()
            .for_each_init(new_scratch, |s, (b, ((wts, st), x))| {
                phase1(b, wts, st, x, s)
            });
    }
    #[cfg(not(feature = "rayon"))]
    {
        let mut s = new_scratch();
        for (b, ((wts, st), x)) in weights
            .chunks_mut(cols)
            .zip(starts.chunks_mut(cols))
            .zip(xs.iter_mut())
            .enumerate()
        {
            phase1(b, wts, st, x, &mut s);
        }
    }

    // Phase 2: one column m at a time.
    let input = ColumnInput {
        leg: &leg,
        lmax,
        xs: &xs,
        weights: &weights,
        starts: &starts,
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
    let sums: Vec<(usize, Vec<[f64; 6]>)> = {
        use rayon::prelude::*;
        (0..cols)
            .into_par_iter()
            .with_max_len(1)
            .map(|i| (order(i), column(&input, order(i))))
            .collect()
    };
    #[cfg(not(feature = "rayon"))]
    let sums: Vec<(usize, Vec<[f64; 6]>)> = (0..cols)
        .map(|i| (order(i), column(&input, order(i))))
        .collect();

    // The phases' buffers (tens of MB at high lmax) go back before the
    // coefficients are allocated, which can then reuse their memory.
    drop((weights, starts, xs));
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
/// with the true value `mantissa * SMALL^(-k)` ([`crate::sh`]).
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
    /// `[m][i]` cosines and sines for the direct sums (empty with FFT), of
    /// the first quarter of the row when it is folded.
    cos: Vec<f64>,
    sin: Vec<f64>,
    /// Whether rows are folded into quarters before the direct sums
    /// ([`fold_row`]; needs `W` a multiple of 4).
    folded: bool,
    fft: Option<std::sync::Arc<dyn RealToComplex<f64>>>,
    /// `e^{-i m c}`, `c = π/W - π`, per `m` (FFT path).
    phase: Vec<Complex<f64>>,
}

/// Per-thread buffers of phase 1.
struct Scratch {
    ring_a: Vec<[f64; 6]>,
    ring_b: Vec<[f64; 6]>,
    sectoral: Vec<[f64; 2]>,
    /// A row read texel by texel from a source that does not store it
    /// contiguously.
    texels: Vec<[f32; 3]>,
    bufs: RowBuffers,
}

/// Buffers for [`Azimuth::row`].
struct RowBuffers {
    channels: [Vec<f64>; 3],
    /// Folded rows `[P_even, P_odd, Q_even, Q_odd][channel]` ([`fold_row`]).
    quarters: [[Vec<f64>; 3]; 4],
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
            sectoral: vec![[0.0; 2]; lmax + 1],
            texels: Vec::new(),
            bufs: RowBuffers {
                channels: [vec![0.0; w], vec![0.0; w], vec![0.0; w]],
                quarters: core::array::from_fn(|_| {
                    core::array::from_fn(|_| vec![0.0; FOLD_CHUNK.min(w / 4)])
                }),
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
                folded: false,
                fft: Some(fft),
                phase,
            };
        }
        let folded = w.is_multiple_of(4);
        let n = if folded { w / 4 } else { w };
        let mut cos = vec![0.0; (lmax + 1) * n];
        let mut sin = vec![0.0; (lmax + 1) * n];
        for m in 0..=lmax {
            for i in 0..n {
                let (s, c) = (m as f64 * sign * angle(i)).sin_cos();
                cos[m * n + i] = c;
                sin[m * n + i] = s;
            }
        }
        Self {
            w,
            lmax,
            sign,
            cos,
            sin,
            folded,
            fft: None,
            phase: Vec::new(),
        }
    }

    /// `ring[m] = [C_r, C_g, C_b, S_r, S_g, S_b]` of one row of texels.
    fn row(&self, texels: &[[f32; 3]], ring: &mut [[f64; 6]], s: &mut RowBuffers) {
        match &self.fft {
            None if self.folded => {
                // Chunks of the quarter small enough that the folded values
                // and the trig rows they meet stay in the L1 cache.
                ring.iter_mut().for_each(|r| *r = [0.0; 6]);
                let q = self.w / 4;
                for start in (0..q).step_by(FOLD_CHUNK) {
                    let n = FOLD_CHUNK.min(q - start);
                    fold_row(texels, start, &mut s.quarters);
                    let [p_even, p_odd, q_even, q_odd] = &s.quarters;
                    for (m, out) in ring.iter_mut().enumerate() {
                        let (p, q_) = if m % 2 == 0 {
                            (p_even, q_even)
                        } else {
                            (p_odd, q_odd)
                        };
                        let trig = m * q + start..m * q + start + n;
                        let d = dots(p, q_, &self.cos[trig.clone()], &self.sin[trig]);
                        for c in 0..6 {
                            out[c] += d[c];
                        }
                    }
                }
            }
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
                        let d = dots(&s.channels, &s.channels, cos, sin);
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
                    // k = m mod W, stepped (a division per m cost more
                    // than the rest of this loop).
                    let mut k = 0;
                    for m in 0..=self.lmax {
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
                        k = if k + 1 == self.w { 0 } else { k + 1 };
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
fn dots(p: &[Vec<f64>; 3], q: &[Vec<f64>; 3], cos: &[f64], sin: &[f64]) -> [f64; 6] {
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
const FOLD_CHUNK: usize = 128;

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
fn fold_row(texels: &[[f32; 3]], start: usize, out: &mut [[Vec<f64>; 3]; 4]) {
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

/// Everything phase 2 reads, `[block][m]` (and `xs` per block).
struct ColumnInput<'a> {
    leg: &'a Legendre<f64>,
    lmax: usize,
    xs: &'a [[f64; LANES]],
    weights: &'a [BlockWeights],
    starts: &'a [BlockStart],
}

/// The sums of column `m`: entry `l - m` for `l = m..=lmax`.
fn column(input: &ColumnInput<'_>, m: usize) -> Vec<[f64; 6]> {
    #[cfg(target_arch = "x86_64")]
    if avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        return unsafe { column_avx(input, m) };
    }
    column_body::<false>(input, m)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn column_avx(input: &ColumnInput<'_>, m: usize) -> Vec<[f64; 6]> {
    column_body::<true>(input, m)
}

/// Per-degree partial sums while a column runs: `[channel][lane mod 4]`,
/// added across lanes only at the end.
type Partial = [[f64; 4]; 6];

/// The column sums leave out a block of rings for the orders `m` beyond
/// every lane's turning point `m = lmax sin θ` by more than
/// [`turning_margin`]: there `Pbar_l^m(cos θ)` decays faster than
/// exponentially for every `l <= lmax` (the associated Legendre functions
/// are evanescent past `m = l sin θ`), so those rings add nothing above
/// rounding, while their recurrence, mostly in extended exponent near the
/// poles, is the dearest part of the column. The same cut-off as libsharp's
/// and ducc0's `get_mlim` (Reinecke & Seljebotn 2013), checked against the
/// direct sums up to lmax 2100 in the tests.
///
/// The margin past the turning point: `max(100, lmax / 100)` orders
/// (libsharp's `sharp_get_mlim` for spin 0).
#[inline(always)]
fn turning_margin(lmax: usize) -> f64 {
    (lmax as f64 * 0.01).max(100.0)
}

/// The largest `sin θ` of a block's lanes (`x = cos θ`; padding lanes have
/// `x = 0`, hence `sin θ = 1`, and never let a block be left out).
#[inline(always)]
fn block_sin_max(x: &[f64; LANES]) -> f64 {
    x.iter()
        .map(|c| (1.0 - c * c).max(0.0).sqrt())
        .fold(0.0, f64::max)
}

/// A lane at `k = -1` whose mantissa is under this is worth less than
/// `2^-200` and is left out of the sums (lanes at `k <= -2` always are).
const NEGLIGIBLE_MANTISSA: f64 = 2.582_249_878_086_908_6e120; // 2^400

/// The column's recurrence with a unit coefficient on `l - 2`.
///
/// [`Legendre`] steps `P_l = A_l x P_{l-1} - B_l P_{l-2}` (`B_l > 0`). With
/// `P_l = c_l Q_l`, `c_m = c_{m+1} = 1` and `c_l = B_l c_{l-2}`, the same
/// functions come from
///
/// ```text
/// Q_l = alpha_l x Q_{l-1} - Q_{l-2},   alpha_l = A_l c_{l-1} / c_l,
/// ```
///
/// a multiply and a fused multiply-subtract per lane instead of three
/// operations (libsharp's and ducc0's form). The sums are taken of `Q_l`
/// and scaled by `c_l` once per degree at the end. `c_l` stays within
/// `[0.16, 1.13]` for every `m <= l <= 4096`, so nothing overflows or
/// underflows, and the extended exponent of the start values works on `Q`
/// as on `P`.
struct UnitRecurrence {
    /// `alpha_l` for `l = m+2..=lmax` (index `l - m - 2`).
    alpha: Vec<f64>,
    /// `c_l` for `l = m..=lmax` (index `l - m`).
    scale: Vec<f64>,
}

impl UnitRecurrence {
    fn new(factors: &[[f64; 2]]) -> Self {
        let mut scale = Vec::with_capacity(factors.len() + 2);
        scale.extend([1.0, 1.0]);
        let mut alpha = Vec::with_capacity(factors.len());
        for (i, &[a, ab]) in factors.iter().enumerate() {
            let c = ab * scale[i];
            alpha.push(a * scale[i + 1] / c);
            scale.push(c);
        }
        Self { alpha, scale }
    }
}

/// Degrees per tile of a column's plain recurrence: the sums of a tile
/// (`TILE x 192` bytes) stay in the L1 cache while every block of rings
/// runs through it, instead of streaming the whole column's sums through
/// the cache once per block.
const TILE: usize = 48;

/// A block of rings whose lanes are all at `k = 0` from step `from` on,
/// with `(Q_{l-2}, Q_{l-1})` for the step `from` is about to take.
struct PlainRun {
    block: usize,
    from: usize,
    p1: [f64; LANES],
    p2: [f64; LANES],
}

#[inline(always)]
fn column_body<const FMA: bool>(input: &ColumnInput<'_>, m: usize) -> Vec<[f64; 6]> {
    let lmax = input.lmax;
    let cols = lmax + 1;
    let mut acc: Vec<Partial> = vec![[[0.0; 4]; 6]; lmax - m + 1];
    let (big, small) = (f64::BIG, f64::SMALL);
    let diag = input.leg.diagonal_factor(m);
    let rec = UnitRecurrence::new(input.leg.column_factors(m));
    let n = rec.alpha.len();
    let margin = turning_margin(lmax);
    let mut runs = Vec::with_capacity(input.xs.len());
    for (b, x) in input.xs.iter().enumerate() {
        if m as f64 > lmax as f64 * block_sin_max(x) + margin {
            continue;
        }
        let w = &input.weights[b * cols + m];
        let BlockStart {
            value: mut p1,
            exponent: mut k,
        } = input.starts[b * cols + m];
        // Blocks near the poles start far below f64's range (extended
        // exponent); once every lane is back at `k = 0` the plain
        // recurrence takes over.
        let mut scaled = k.iter().any(|&e| e != 0.0);
        add_scaled::<FMA>(&mut acc[0], &p1, &k, scaled, &w[0]);
        if m == lmax {
            continue;
        }
        let mut p2 = [0.0; LANES];
        for j in 0..LANES {
            p2[j] = diag * x[j] * p1[j];
        }
        add_scaled::<FMA>(&mut acc[1], &p2, &k, scaled, &w[1]);
        let mut i = 0;
        while scaled && i < n {
            let a = rec.alpha[i];
            let mut p3 = [0.0; LANES];
            for j in 0..LANES {
                let v = a * x[j] * p2[j] - p1[j];
                let grow = k[j] < 0.0 && v.abs() > big;
                p3[j] = if grow { v * small } else { v };
                p2[j] = if grow { p2[j] * small } else { p2[j] };
                k[j] = if grow { k[j] + 1.0 } else { k[j] };
            }
            scaled = k.iter().any(|&e| e != 0.0);
            p1 = p2;
            p2 = p3;
            add_scaled::<FMA>(&mut acc[i + 2], &p2, &k, scaled, &w[i % 2]);
            i += 1;
        }
        if i < n {
            runs.push(PlainRun {
                block: b,
                from: i,
                p1,
                p2,
            });
        }
    }
    // The plain steps tile by tile, every block through each tile.
    for t0 in (0..n).step_by(TILE) {
        let t1 = (t0 + TILE).min(n);
        for run in &mut runs {
            let from = run.from.max(t0);
            if from >= t1 {
                continue;
            }
            run_plain::<FMA>(
                &input.xs[run.block],
                &mut run.p1,
                &mut run.p2,
                &rec.alpha[from..t1],
                &mut acc[from + 2..t1 + 2],
                &input.weights[run.block * cols + m],
                from % 2,
            );
        }
    }
    acc.iter()
        .zip(&rec.scale)
        .map(|(a, &c)| a.map(|v| ((v[0] + v[1]) + (v[2] + v[3])) * c))
        .collect()
}

/// The recurrence from `(Q_{l-2}, Q_{l-1}) = (p1, p2)` on for every
/// `alpha` (all lanes at `k = 0`), each new `Q_l` added to `acc` (one entry
/// per step) against the weights of its parity, `w[parity]` first; `p1`
/// and `p2` are left at the last two values.
#[inline(always)]
fn run_plain<const FMA: bool>(
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
/// [`crate::sh`]); nothing when every lane is negligible.
#[inline(always)]
fn add_scaled<const FMA: bool>(
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit recurrence's scales `c_l` stay within the range its docs
    /// give, `[0.16, 1.13]`, for every column to degree 4096.
    #[test]
    fn unit_recurrence_scales_stay_in_range() {
        let lmax = 4096;
        let leg = Legendre::<f64>::new(lmax);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for m in 0..=lmax {
            for &c in &UnitRecurrence::new(leg.column_factors(m)).scale {
                lo = lo.min(c);
                hi = hi.max(c);
            }
        }
        assert!(lo >= 0.16 && hi <= 1.13, "c_l in [{lo}, {hi}]");
    }
}

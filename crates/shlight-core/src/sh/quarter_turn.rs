//! Quarter turns of SH coefficients from Wigner's `d(π/2)`, in
//! `O(lmax^3)` with a small constant: the fast route between the y-up and
//! z-up frames, which differ by a quarter turn about X.

use core::f64::consts::SQRT_2;

use crate::sh::real::Real;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// The rows of `d^l(π/2)` from `m = l` down to `0`, by the recurrence (see
/// [`quarter_turn_x`]), columns `m' = 0..=m` only, split by the parity of `m'`
/// (index `k` of part `p` is column `m' = 2k + p`).
struct HalfPiRows {
    l: usize,
    /// `2 m'` per column of each part.
    twice_mprime: [Vec<f64>; 2],
    /// Row `m`, exact for `m' <= m`.
    cur: [Vec<f64>; 2],
    /// Row `m + 1`.
    prev: [Vec<f64>; 2],
    /// The row `cur` holds; `None` before the first.
    m: Option<usize>,
}

/// The number of columns `m' = 0..=l` of each parity: even, odd.
fn parts(l: usize) -> [usize; 2] {
    // m' = 0, 2, .. <= l and m' = 1, 3, .. <= l.
    [l / 2 + 1, l.div_ceil(2)]
}

impl HalfPiRows {
    fn new(l: usize) -> Self {
        // |d_{l 0}| = 2^-l sqrt(C(2l, l)) = sqrt(prod_k (2k-1)/(2k)); then
        // outwards by the ratio of binomials, so nothing underflows early;
        // signs (-1)^(l-m').
        let centre = (1..=l)
            .map(|k| (2 * k - 1) as f64 / (2 * k) as f64)
            .product::<f64>()
            .sqrt();
        let mut edge = vec![0.0; l + 1];
        edge[0] = parity_sign(l) * centre;
        for mp in 0..l {
            // C(2l, l+m'+1) / C(2l, l+m') = (l-m') / (l+m'+1).
            let ratio = ((l - mp) as f64 / (l + mp + 1) as f64).sqrt();
            edge[mp + 1] = -edge[mp] * ratio;
        }
        let split = |v: &[f64], p: usize| v.iter().skip(p).step_by(2).copied().collect::<Vec<_>>();
        let columns: Vec<f64> = (0..=l).map(|mp| 2.0 * mp as f64).collect();
        Self {
            l,
            twice_mprime: [split(&columns, 0), split(&columns, 1)],
            cur: [split(&edge, 0), split(&edge, 1)],
            prev: parts(l).map(|n| vec![0.0; n]),
            m: None,
        }
    }

    /// The next row `m` and its entries `d_{m m'}`, `m' = 0..=m`, as the
    /// even-`m'` part (`m / 2 + 1` entries) and the odd-`m'` part
    /// (`(m + 1) / 2` entries).
    #[inline(always)]
    fn next_row<const FMA: bool>(&mut self) -> Option<(usize, [&[f64]; 2])> {
        let l = self.l;
        let m = match self.m {
            None => l,
            Some(0) => return None,
            Some(m) => {
                // Row m - 1 from rows m and m + 1, columns m' <= m - 1.
                let (mf, lf) = (m as f64, l as f64);
                let up = ((lf - mf) * (lf + mf + 1.0)).sqrt();
                let inv = 1.0 / ((lf + mf) * (lf - mf + 1.0)).sqrt();
                for (p, n) in [(0, m.div_ceil(2)), (1, m / 2)] {
                    let prev = &mut self.prev[p][..n];
                    let cur = &self.cur[p][..n];
                    let k = &self.twice_mprime[p][..n];
                    for ((p, &c), &k) in prev.iter_mut().zip(cur).zip(k) {
                        *p = mul_add::<FMA>(k, c, -up * *p) * inv;
                    }
                }
                core::mem::swap(&mut self.prev, &mut self.cur);
                m - 1
            }
        };
        self.m = Some(m);
        Some((
            m,
            [&self.cur[0][..m / 2 + 1], &self.cur[1][..m.div_ceil(2)]],
        ))
    }
}

/// `a b + c`, fused when the kernel is compiled for FMA.
#[inline(always)]
fn mul_add<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

/// `(-1)^n`.
#[inline(always)]
fn parity_sign(n: usize) -> f64 {
    if n.is_multiple_of(2) { 1.0 } else { -1.0 }
}

/// Band-`l` values of three channels (unused ones zero), split by the
/// parity of `|m|`: `v[c][p][k]` is the value at `|m| = 2k + p`.
type Split = [[Vec<f64>; 2]; 3];

/// Applies the band-`l` block of the quarter turn about Y, `Ry(π/2)`, to
/// `x` (the `2l + 1` coefficients of band `l`) into `out`.
fn turn_y_band<C: ShValue>(l: usize, x: &[C], out: &mut [C]) {
    #[cfg(target_arch = "x86_64")]
    if crate::cpu_features::avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        unsafe { turn_y_band_avx(l, x, out) };
        return;
    }
    turn_y_band_body::<C, false>(l, x, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn turn_y_band_avx<C: ShValue>(l: usize, x: &[C], out: &mut [C]) {
    turn_y_band_body::<C, true>(l, x, out);
}

/// The band's product with the even block `E = S D S` and the odd block
/// `O = 2 D` ([`quarter_turn_x`]; `D` the checkerboard part of `d`, `S` the
/// `s_b`): inputs are scaled by `S` on the way in, outputs by `S` (even)
/// or 2 (odd) on the way out.
#[inline(always)]
fn turn_y_band_body<C: ShValue, const FMA: bool>(l: usize, x: &[C], out: &mut [C]) {
    debug_assert!(C::CHANNELS <= 3);
    let scale = |b: usize| if b == 0 { 1.0 } else { SQRT_2 };
    let channel = |c: usize, i: usize| {
        if c < C::CHANNELS {
            x[i].channel(c).to_f64()
        } else {
            0.0
        }
    };
    let n = parts(l);
    // Even inputs S x_{+b}; odd inputs x_{-b} (0 at b = 0, which has none).
    let even_in: Split = core::array::from_fn(|c| {
        core::array::from_fn(|p| {
            (0..n[p])
                .map(|k| 2 * k + p)
                .map(|b| scale(b) * channel(c, l + b))
                .collect()
        })
    });
    let odd_in: Split = core::array::from_fn(|c| {
        core::array::from_fn(|p| {
            (0..n[p])
                .map(|k| 2 * k + p)
                .map(|b| if b == 0 { 0.0 } else { channel(c, l - b) })
                .collect()
        })
    });
    let mut even_out: Split = core::array::from_fn(|_| n.map(|len| vec![0.0; len]));
    let mut odd_out: Split = core::array::from_fn(|_| n.map(|len| vec![0.0; len]));
    let sign_even = parity_sign(l);
    let mut rows = HalfPiRows::new(l);
    while let Some((a, d)) = rows.next_row::<FMA>() {
        // Non-zero columns of the even block's row a: b = a + l (mod 2);
        // the odd block's: the other parity (its b = 0 entry meets x = 0).
        let q = (a + l) % 2;
        block_row::<FMA>(d[q], a, q, &even_in, &mut even_out, sign_even);
        if a > 0 {
            block_row::<FMA>(d[1 - q], a, 1 - q, &odd_in, &mut odd_out, -sign_even);
        }
    }
    for c in 0..C::CHANNELS {
        for b in 0..=l {
            let (p, k) = (b % 2, b / 2);
            out[l + b].set_channel(c, C::Scalar::from_f64(scale(b) * even_out[c][p][k]));
            if b > 0 {
                out[l - b].set_channel(c, C::Scalar::from_f64(2.0 * odd_out[c][p][k]));
            }
        }
    }
}

/// Row `a` of a signed-symmetric checkerboard block, given up to its
/// diagonal by `row[k]` (the entry at column `b = 2k + p`), for three
/// channels: `y_a += sum_b row_b x_b` over `b <= a`, and `y_b += sign x_a
/// row_b` for `b < a` (the transposed entries).
#[inline(always)]
fn block_row<const FMA: bool>(
    row: &[f64],
    a: usize,
    p: usize,
    x: &Split,
    y: &mut Split,
    sign: f64,
) {
    let (pa, ka) = (a % 2, a / 2);
    // The diagonal b = a lies in this parity exactly when a = p (mod 2).
    let diagonal = pa == p;
    let n = row.len() - usize::from(diagonal);
    let xa = [x[0][pa][ka], x[1][pa][ka], x[2][pa][ka]];
    let alpha = xa.map(|v| sign * v);
    let r = &row[..n];
    let [x0, x1, x2] = [&x[0][p][..n], &x[1][p][..n], &x[2][p][..n]];
    let dot = {
        let [y0, y1, y2] = y;
        let ys = [&mut y0[p][..n], &mut y1[p][..n], &mut y2[p][..n]];
        row_kernel::<FMA>(r, [x0, x1, x2], ys, alpha)
    };
    for c in 0..3 {
        let mut sum = dot[c];
        if diagonal {
            sum = mul_add::<FMA>(row[n], xa[c], sum);
        }
        y[c][pa][ka] += sum;
    }
}

/// For three channels `c`: returns `sum_i r_i x_c[i]` and adds
/// `alpha_c r_i` to `y_c[i]`; all slices of one length.
#[inline(always)]
fn row_kernel<const FMA: bool>(
    r: &[f64],
    x: [&[f64]; 3],
    y: [&mut [f64]; 3],
    alpha: [f64; 3],
) -> [f64; 3] {
    let n = r.len();
    assert!(x.iter().all(|v| v.len() == n) && y.iter().all(|v| v.len() == n));
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: FMA kernels run only from `turn_y_band_avx`, after the
        // CPU was found to have AVX and FMA; the lengths are checked above.
        return unsafe { row_kernel_avx(r, x, y, alpha) };
    }
    let [x0, x1, x2] = x;
    let [y0, y1, y2] = y;
    let mut dot = [0.0; 3];
    for i in 0..n {
        let ri = r[i];
        dot[0] = mul_add::<FMA>(ri, x0[i], dot[0]);
        dot[1] = mul_add::<FMA>(ri, x1[i], dot[1]);
        dot[2] = mul_add::<FMA>(ri, x2[i], dot[2]);
        y0[i] = mul_add::<FMA>(alpha[0], ri, y0[i]);
        y1[i] = mul_add::<FMA>(alpha[1], ri, y1[i]);
        y2[i] = mul_add::<FMA>(alpha[2], ri, y2[i]);
    }
    dot
}

/// [`row_kernel`] in 256-bit AVX registers with fused multiply-adds, four
/// entries at a time (the compiler does not vectorise the portable loop's
/// three dot products and three updates by itself).
///
/// # Safety
/// The CPU must have AVX and FMA; every slice must be as long as `r`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn row_kernel_avx(
    r: &[f64],
    x: [&[f64]; 3],
    y: [&mut [f64]; 3],
    alpha: [f64; 3],
) -> [f64; 3] {
    use core::arch::x86_64::{
        __m256d, _mm_add_pd, _mm_cvtsd_f64, _mm_unpackhi_pd, _mm256_castpd256_pd128,
        _mm256_extractf128_pd, _mm256_fmadd_pd, _mm256_loadu_pd, _mm256_set1_pd, _mm256_setzero_pd,
        _mm256_storeu_pd,
    };
    let n = r.len();
    let [x0, x1, x2] = x;
    let [y0, y1, y2] = y;
    let (a0, a1, a2) = (
        _mm256_set1_pd(alpha[0]),
        _mm256_set1_pd(alpha[1]),
        _mm256_set1_pd(alpha[2]),
    );
    let (mut d0, mut d1, mut d2) = (
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
        _mm256_setzero_pd(),
    );
    let mut i = 0;
    while i + 4 <= n {
        // SAFETY: i + 4 <= n, the length of every slice.
        unsafe {
            let rv = _mm256_loadu_pd(r.as_ptr().add(i));
            d0 = _mm256_fmadd_pd(rv, _mm256_loadu_pd(x0.as_ptr().add(i)), d0);
            d1 = _mm256_fmadd_pd(rv, _mm256_loadu_pd(x1.as_ptr().add(i)), d1);
            d2 = _mm256_fmadd_pd(rv, _mm256_loadu_pd(x2.as_ptr().add(i)), d2);
            let p0 = y0.as_mut_ptr().add(i);
            _mm256_storeu_pd(p0, _mm256_fmadd_pd(a0, rv, _mm256_loadu_pd(p0)));
            let p1 = y1.as_mut_ptr().add(i);
            _mm256_storeu_pd(p1, _mm256_fmadd_pd(a1, rv, _mm256_loadu_pd(p1)));
            let p2 = y2.as_mut_ptr().add(i);
            _mm256_storeu_pd(p2, _mm256_fmadd_pd(a2, rv, _mm256_loadu_pd(p2)));
        }
        i += 4;
    }
    let sum = |v: __m256d| {
        let pair = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd::<1>(v));
        _mm_cvtsd_f64(_mm_add_pd(pair, _mm_unpackhi_pd(pair, pair)))
    };
    let mut dot = [sum(d0), sum(d1), sum(d2)];
    for i in i..n {
        let ri = r[i];
        dot[0] = ri.mul_add(x0[i], dot[0]);
        dot[1] = ri.mul_add(x1[i], dot[1]);
        dot[2] = ri.mul_add(x2[i], dot[2]);
        y0[i] = alpha[0].mul_add(ri, y0[i]);
        y1[i] = alpha[1].mul_add(ri, y1[i]);
        y2[i] = alpha[2].mul_add(ri, y2[i]);
    }
    dot
}

/// Rotates band `l` about Z by `turns` quarter turns, exactly:
/// `g^m = c f^m - s f^-m`, `g^-m = c f^-m + s f^m` with
/// `(c, s) = (cos, sin)(m turns π/2)`, each 0 or ±1 (see
/// [`crate::sh::rotate_z`]).
fn quarter_turn_z_band<C: ShValue>(l: usize, band: &mut [C], turns: i32) {
    for m in 1..=l {
        let (ip, im) = (l + m, l - m);
        let (fp, fm) = (band[ip], band[im]);
        let (gp, gm) = match (m as i64 * i64::from(turns)).rem_euclid(4) {
            0 => (fp, fm),
            1 => (-fm, fp),
            2 => (-fp, -fm),
            _ => (fm, -fp),
        };
        band[ip] = gp;
        band[im] = gm;
    }
}

/// Rotates coefficients by a quarter turn about X: `turns = 1` for
/// `Rx(+π/2)` (`(x, y, z) -> (x, -z, y)`), `turns = -1` for `Rx(-π/2)`;
/// `g(d) = f(R^-1 d)`, the same convention as [`crate::sh::ShRotation`].
///
/// Band by band, `g_l = Rz(∓π/2) Ry(π/2) Rz(±π/2) f_l`: the `Rz` are exact
/// signed swaps of `f_l^m` and `f_l^-m`, and `Ry(π/2)` is the checkerboard
/// block of Wigner's `d^l(π/2)` below. Equals
/// `rotate_once(f, R)` to rounding, at a fraction of the cost: about
/// `(l+1)^2` multiply-adds per band and channel, and no rotation blocks built
/// by recurrence. Bands run in parallel with the `rayon` feature.
///
/// `C` is any value type (`f32`, `f64`, `Vec3`, `DVec3`). The arithmetic is
/// in `f64` whatever the scalar: `f32` channels are widened (exactly), turned
/// by the same `f64` kernels (AVX/FMA when the CPU has them) and each result
/// is rounded once to `f32`, so an `f32` result is the `f64` turn of the same
/// input to within half an `f32` ulp. `f64` channels go through no
/// conversion.
///
/// # Panics
/// If `turns` is not `1` or `-1`.
///
/// # The blocks
///
/// A rotation about Y by `π/2` keeps functions even in `y` (`m >= 0`,
/// `cos mφ`) apart from odd ones (`m < 0`, `sin mφ`). In shlight's real basis
/// its band-`l` block is, with `d = d^l(π/2)` (Wigner's small d,
/// `d_{m m'}(β) = <l m| e^{-iβJ_y} |l m'>`) and `a, b > 0`,
///
/// ```text
/// even:  M_{a b}   = d_{a b} + (-1)^b d_{a,-b}     M_{a 0} = sqrt2 d_{a 0}
///        M_{0 b}   = sqrt2 d_{0 b}                 M_{0 0} = d_{0 0}
/// odd:   M_{-a,-b} = d_{a b} - (-1)^b d_{a,-b}
/// ```
///
/// (`conj(U) d U^T` for the unitary `U` from complex to real SH, whose
/// mixed even-odd entries vanish). At `β = π/2` the reflection
/// `d_{m m'}(π - β) = (-1)^(l+m) d_{m,-m'}(β)` (Varshalovich, Moskalev &
/// Khersonskii, *Quantum Theory of Angular Momentum*, 4.4) gives
/// `d_{a,-b} = (-1)^(l+a) d_{a b}`, so
///
/// ```text
/// even:  M_{a b}   = s_a s_b d_{a b}   when a + b + l is even, else 0
/// odd:   M_{-a,-b} = 2 d_{a b}         when a + b + l is odd,  else 0
/// ```
///
/// with `s_0 = 1`, `s_{b>0} = sqrt2`: each block is a checkerboard, and only
/// the columns `m' >= 0` of `d` are needed. Both blocks are signed-symmetric
/// (`d_{m m'} = (-1)^(m-m') d_{m' m}`), with the one sign `(-1)^l` (even) or
/// `(-1)^(l+1)` (odd) on their non-zero entries, so each row of `d` is used
/// up to the diagonal only, as it leaves the recurrence; no matrix is stored.
/// Per band and channel that is about `(l+1)^2 / 2` multiply-adds for the
/// rows and as many for their transposes.
///
/// `d(π/2)` comes from the three-term recurrence in the row index at
/// `cos β = 0`,
///
/// ```text
/// sqrt((l+m)(l-m+1)) d_{m-1,m'} = 2 m' d_{m m'} - sqrt((l-m)(l+m+1)) d_{m+1,m'},
/// ```
///
/// run from the edge `d_{l m'} = (-1)^(l-m') 2^-l sqrt(C(2l, l+m'))` down to
/// `m = m'`, the direction in which the values grow (stable); each column
/// runs on its own, so columns of one parity of `m'` sit side by side in
/// vector lanes, matching the checkerboard.
/// A quarter turn about X is `Rz(-π/2) Ry(π/2) Rz(π/2)`, and the `Rz` are
/// exact signed swaps within each `(m, -m)` pair, done per band.
///
/// Coefficients of any value type (`f32`, `f64`, `Vec3`, `DVec3`) are turned
/// in `f64`; `f32` ones are widened on the way in and rounded once on the
/// way out.
#[must_use]
pub fn quarter_turn_x<C: ShValue>(f: &ShCoeffs<C>, turns: i32) -> ShCoeffs<C> {
    assert!(
        turns == 1 || turns == -1,
        "quarter_turn_x takes turns = 1 or -1"
    );
    // Rx(±π/2) = Rz(∓π/2) Ry(π/2) Rz(±π/2): Rz(∓π/2) takes +Y to ±X, and
    // rotating coefficients composes the same way (rightmost first).
    let band = |l: usize, x: &[C], out: &mut [C]| {
        let mut y = x.to_vec();
        quarter_turn_z_band(l, &mut y, turns);
        turn_y_band(l, &y, out);
        quarter_turn_z_band(l, out, -turns);
    };
    let mut out = ShCoeffs::<C>::zeros(f.lmax());
    // Bands as disjoint slices, largest first (for load balance).
    let mut bands: Vec<(usize, &mut [C])> = Vec::with_capacity(f.lmax() + 1);
    let mut rest = out.as_mut_slice();
    for l in 0..=f.lmax() {
        let (head, tail) = rest.split_at_mut(2 * l + 1);
        bands.push((l, head));
        rest = tail;
    }
    bands.reverse();
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        bands
            .into_par_iter()
            .with_max_len(1)
            .for_each(|(l, o)| band(l, f.band(l), o));
    }
    #[cfg(not(feature = "rayon"))]
    for (l, o) in bands {
        band(l, f.band(l), o);
    }
    out
}

#[cfg(test)]
mod tests {
    use core::f64::consts::FRAC_PI_2;

    use glam::{DMat3, DVec3};

    use super::*;
    use crate::sh::rotation::{rotate_once, rotate_z};
    use crate::test_util::{U32, max_diff, numbers};

    /// Rounding of the quarter turn against other routes: a few hundred
    /// multiply-adds per coefficient at the lmax tested, each within an
    /// ulp of values of order 1.
    const TOL: f64 = 1e-12;

    fn random(lmax: usize, seed: u64) -> ShCoeffs<DVec3> {
        let mut next = numbers(seed);
        let n = (lmax + 1) * (lmax + 1);
        ShCoeffs::from_vec((0..n).map(|_| DVec3::new(next(), next(), next())).collect()).unwrap()
    }

    /// The whole of `d^l(π/2)`, `(2l+1)^2` entries (row `l + m`, column
    /// `l + m'`), from the recurrence run over every column `-l..=l`
    /// (rows `m >= |m'|`) and the symmetries `d_{m m'} = (-1)^(m-m') d_{m' m}
    /// = d_{-m',-m}` for the rest: no use of the reflection in `β` that the
    /// fast route relies on.
    fn dense_d(l: usize) -> Vec<Vec<f64>> {
        let li = l as i64;
        let n = 2 * l + 1;
        let centre = (1..=l)
            .map(|k| (2 * k - 1) as f64 / (2 * k) as f64)
            .product::<f64>()
            .sqrt();
        // Row l over all columns.
        let mut row = vec![0.0; n];
        row[l] = parity_sign(l) * centre;
        for mp in 0..l {
            let ratio = ((l - mp) as f64 / (l + mp + 1) as f64).sqrt();
            row[l + mp + 1] = -row[l + mp] * ratio;
            row[l - mp - 1] = -row[l - mp] * ratio;
        }
        let mut table = vec![vec![0.0; n]; n]; // valid for m >= |m'|
        table[n - 1] = row.clone();
        let mut prev = vec![0.0; n];
        let mut cur = row;
        for m in (1..=l).rev() {
            let (mf, lf) = (m as f64, l as f64);
            let up = ((lf - mf) * (lf + mf + 1.0)).sqrt();
            let down = ((lf + mf) * (lf - mf + 1.0)).sqrt();
            let next: Vec<f64> = (0..n)
                .map(|j| (2.0 * (j as f64 - lf) * cur[j] - up * prev[j]) / down)
                .collect();
            prev = cur;
            cur = next;
            table[l + m - 1] = cur.clone();
        }
        let t = |m: i64, mp: i64| table[(li + m) as usize][(li + mp) as usize];
        let sign = |k: i64| if k.rem_euclid(2) == 0 { 1.0 } else { -1.0 };
        let get = |m: i64, mp: i64| {
            if m >= mp.abs() {
                t(m, mp)
            } else if -m >= mp.abs() {
                sign(m - mp) * t(-m, -mp)
            } else if mp >= m.abs() {
                sign(m - mp) * t(mp, m)
            } else {
                t(-mp, -m)
            }
        };
        (-li..=li)
            .map(|m| (-li..=li).map(|mp| get(m, mp)).collect())
            .collect()
    }

    /// `Ry(π/2)` on band `l` by the first formula of [`quarter_turn_x`]'s docs, from the
    /// dense `d`: every entry of both blocks, no checkerboard, no symmetry.
    fn dense_turn_y(l: usize, x: &[DVec3]) -> Vec<DVec3> {
        let d = dense_d(l);
        let at = |m: usize, mp: isize| d[l + m][(l as isize + mp) as usize];
        let r2 = SQRT_2;
        let mut y = vec![DVec3::ZERO; 2 * l + 1];
        for a in 0..=l {
            for b in 0..=l {
                let e = match (a, b) {
                    (0, 0) => at(0, 0),
                    (_, 0) => r2 * at(a, 0),
                    (0, _) => r2 * at(0, b as isize),
                    _ => at(a, b as isize) + parity_sign(b) * at(a, -(b as isize)),
                };
                y[l + a] += x[l + b] * e;
                if a > 0 && b > 0 {
                    let o = at(a, b as isize) - parity_sign(b) * at(a, -(b as isize));
                    y[l - a] += x[l - b] * o;
                }
            }
        }
        y
    }

    #[test]
    fn band_one_of_d_half_pi_is_the_textbook_matrix() {
        // d^1(β): d_11 = (1+c)/2, d_10 = -s/sqrt2, d_00 = c (columns m' >= 0).
        let r = 0.5f64.sqrt();
        let mut rows = HalfPiRows::new(1);
        let (m, [even, odd]) = rows.next_row::<false>().unwrap();
        assert_eq!(m, 1);
        assert!((even[0] + r).abs() < 1e-15 && (odd[0] - 0.5).abs() < 1e-15);
        let (m, [even, odd]) = rows.next_row::<false>().unwrap();
        assert_eq!((m, even.len(), odd.len()), (0, 1, 0));
        assert!(even[0].abs() < 1e-15);
        assert!(rows.next_row::<false>().is_none());
    }

    #[test]
    fn the_dense_reference_is_orthogonal_and_reflects_at_half_pi() {
        // Checks the reference itself: d d^T = I, and the reflection
        // d_{m,-m'} = (-1)^(l+m) d_{m m'} the fast route relies on.
        for l in [1, 2, 7, 20] {
            let d = dense_d(l);
            let n = 2 * l + 1;
            for i in 0..n {
                for j in 0..n {
                    let dot: f64 = (0..n).map(|k| d[i][k] * d[j][k]).sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((dot - want).abs() < TOL, "l {l}: (d d^T)_{i}{j} = {dot}");
                    let reflected = parity_sign(l + i + l) * d[i][j]; // m = i - l
                    assert!((d[i][n - 1 - j] - reflected).abs() < TOL, "l {l}");
                }
            }
        }
    }

    #[test]
    fn fast_band_turn_matches_the_dense_blocks() {
        for l in [0, 1, 2, 3, 4, 5, 8, 13, 32, 61] {
            let f = random(l, 3 + l as u64);
            let x = f.band(l);
            let want = dense_turn_y(l, x);
            let mut got = vec![DVec3::ZERO; 2 * l + 1];
            turn_y_band(l, x, &mut got);
            let d = max_diff(&got, &want);
            assert!(d < TOL, "band {l}: {d:e}");
        }
    }

    #[test]
    fn portable_and_vector_kernels_agree() {
        for l in [0, 1, 6, 33, 200] {
            let f = random(l, 11 + l as u64);
            let mut a = vec![DVec3::ZERO; 2 * l + 1];
            let mut b = vec![DVec3::ZERO; 2 * l + 1];
            turn_y_band(l, f.band(l), &mut a);
            turn_y_band_body::<DVec3, false>(l, f.band(l), &mut b);
            let d = max_diff(&a, &b);
            assert!(d < TOL, "band {l}: {d:e}");
        }
    }

    #[test]
    fn quarter_turns_match_the_recurrence_rotation() {
        let rx = DMat3::from_cols(DVec3::X, DVec3::Z, DVec3::NEG_Y); // (x,y,z)->(x,-z,y)
        for lmax in [0, 1, 2, 5, 16, 40] {
            let f = random(lmax, 7 + lmax as u64);
            let d = max_diff(
                quarter_turn_x(&f, 1).as_slice(),
                rotate_once(&f, rx).as_slice(),
            );
            assert!(d < TOL, "lmax {lmax} +: {d:e}");
            let d = max_diff(
                quarter_turn_x(&f, -1).as_slice(),
                rotate_once(&f, rx.transpose()).as_slice(),
            );
            assert!(d < TOL, "lmax {lmax} -: {d:e}");
        }
    }

    #[test]
    fn quarter_turns_match_rotation_by_reprojection() {
        // g(d) = f(R^-1 d) projected by a product rule exact to degree
        // 2 lmax: an independent route from the Wigner blocks.
        let lmax = 12;
        let f = random(lmax, 5);
        for turns in [1, -1] {
            let g = ShCoeffs::<DVec3>::project_fn(lmax, 2 * lmax, |d| {
                let (x, y, z) = (d.x, d.y, d.z);
                // Rx(+π/2)^-1 (x, y, z) = (x, z, -y); Rx(-π/2)^-1 = (x, -z, y).
                let back = if turns == 1 {
                    DVec3::new(x, z, -y)
                } else {
                    DVec3::new(x, -z, y)
                };
                f.eval(back)
            });
            let d = max_diff(quarter_turn_x(&f, turns).as_slice(), g.as_slice());
            assert!(d < TOL, "turns {turns}: {d:e}");
        }
    }

    #[test]
    fn z_quarter_turns_are_rotate_z() {
        let f = random(9, 2);
        for turns in [1, -1, 2, 3] {
            let mut got = f.clone();
            for l in 0..=9 {
                quarter_turn_z_band(l, got.band_mut(l), turns);
            }
            let want = rotate_z(&f, f64::from(turns) * FRAC_PI_2);
            let d = max_diff(got.as_slice(), want.as_slice());
            assert!(d < TOL, "turns {turns}: {d:e}");
        }
    }

    #[test]
    fn quarter_turns_stay_orthogonal_at_high_degree() {
        // Four quarter turns about Y are the identity and norms are kept,
        // past degree 1074 where the edge value 2^-l of the recurrence
        // leaves f64's range.
        for l in [40, 300, 1100, 1500] {
            let x = random(l, l as u64);
            let x = x.band(l);
            let mut y = x.to_vec();
            let mut z = vec![DVec3::ZERO; 2 * l + 1];
            for turn in 0..4 {
                turn_y_band(l, &y, &mut z);
                if turn == 0 {
                    let n = |v: &[DVec3]| v.iter().map(|c| c.length_squared()).sum::<f64>();
                    assert!((n(&z) / n(x) - 1.0).abs() < 1e-11, "band {l}: norm");
                }
                std::mem::swap(&mut y, &mut z);
            }
            let d = max_diff(x, &y);
            assert!(d < 1e-10, "band {l}: {d:e}");
        }
    }

    /// `f32` quarter turn against the `f64` one, per output channel, in
    /// units of `U32 |f_l|` (`|f_l|` the band's 2-norm in that channel):
    /// rounding the input to `f32` moves each coefficient by at most
    /// `U32 |f_l^m|`, which the orthogonal band block carries to any output
    /// with at most its 2-norm, `U32 |f_l|`; the output is rounded once
    /// more, by at most `U32 |g_l^m| <= U32 |f_l|`. So 2, plus the `f64`
    /// route's own rounding ([`TOL`], absolute).
    const F32_VS_F64_ULPS: f64 = 2.0;

    /// `f32` quarter turn against `rotate_once` in `f32` on the same `f32`
    /// coefficients, in units of `U32 |f_l|` for band `l`: `rotate_once`
    /// rounds each block entry to `f32` (`U32 |f_l|` in all, the block rows
    /// being unit vectors) and sums `2l + 1` products in `f32` (at most
    /// `(2l + 1) U32` times `sum_j |M_ij f_j| <= |f_l|`); the quarter turn
    /// rounds its `f64` result once (`U32 |f_l|`). So `2l + 3`, plus [`TOL`].
    fn f32_vs_rotate_once_ulps(l: usize) -> f64 {
        (2 * l + 3) as f64
    }

    /// The largest `|a - b|` per band and channel over `U32 |x_l|` (the
    /// band's norm in that channel of the input `x`), after subtracting the
    /// absolute `TOL`; asserts it is at most `ulps(l)`.
    fn check_band_ulps(
        x: &ShCoeffs<DVec3>,
        a: &ShCoeffs<DVec3>,
        b: &ShCoeffs<DVec3>,
        ulps: impl Fn(usize) -> f64,
        what: &str,
    ) -> f64 {
        let mut worst = 0.0f64;
        for l in 0..=x.lmax() {
            let norm = x.band(l).iter().fold(DVec3::ZERO, |s, v| s + *v * *v);
            for (p, q) in a.band(l).iter().zip(b.band(l)) {
                for c in 0..3 {
                    let err = ((p[c] - q[c]).abs() - TOL).max(0.0);
                    let units = err / (U32 * norm[c].sqrt());
                    assert!(
                        units <= ulps(l),
                        "{what}: band {l} channel {c}: {units} ulps"
                    );
                    worst = worst.max(units);
                }
            }
        }
        worst
    }

    #[test]
    fn f32_quarter_turns_are_the_f64_ones_to_f32_rounding() {
        let mut worst = 0.0f64;
        for lmax in [0, 1, 2, 5, 16, 40] {
            let f = random(lmax, 31 + lmax as u64);
            let f32_rgb = f.to_f32();
            let f32_scalar = f32_rgb.map(|v| v.y);
            for turns in [1, -1] {
                let want = quarter_turn_x(&f, turns);
                let got = quarter_turn_x(&f32_rgb, turns).to_f64();
                let what = format!("lmax {lmax} turns {turns} rgb");
                worst = worst.max(check_band_ulps(&f, &got, &want, |_| F32_VS_F64_ULPS, &what));
                // One channel on its own turns like the RGB's green.
                let got = quarter_turn_x(&f32_scalar, turns).map(|v| DVec3::splat(f64::from(v)));
                let want = want.map(|v| DVec3::splat(v.y));
                let x = f.map(|v| DVec3::splat(v.y));
                let what = format!("lmax {lmax} turns {turns} scalar");
                worst = worst.max(check_band_ulps(&x, &got, &want, |_| F32_VS_F64_ULPS, &what));
            }
        }
        eprintln!("f32 vs f64 quarter turn: worst {worst:.3} U32 |f_l|");
    }

    #[test]
    fn f32_quarter_turns_match_f32_rotate_once() {
        let rx = DMat3::from_cols(DVec3::X, DVec3::Z, DVec3::NEG_Y); // (x,y,z)->(x,-z,y)
        let mut worst = 0.0f64;
        for lmax in [1, 2, 5, 16, 40] {
            let f = random(lmax, 17 + lmax as u64).to_f32();
            let x = f.to_f64();
            for (turns, r) in [(1, rx), (-1, rx.transpose())] {
                let got = quarter_turn_x(&f, turns).to_f64();
                let want = rotate_once(&f, r).to_f64();
                let what = format!("lmax {lmax} turns {turns}");
                worst = worst.max(check_band_ulps(
                    &x,
                    &got,
                    &want,
                    f32_vs_rotate_once_ulps,
                    &what,
                ));
            }
        }
        eprintln!("f32 quarter turn vs f32 rotate_once: worst {worst:.3} U32 |f_l|");
    }

    #[test]
    fn scalar_coefficients_turn_like_each_rgb_channel() {
        let f = random(20, 9);
        let g = quarter_turn_x(&f, 1);
        for c in 0..3 {
            let got = quarter_turn_x(&f.channel(c), 1);
            let want = g.channel(c);
            let d = got
                .as_slice()
                .iter()
                .zip(want.as_slice())
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(d < TOL, "channel {c}: {d:e}");
        }
    }
}

//! Quarter turns of SH coefficients from Wigner's `d(π/2)`, in
//! `O(lmax^3)` with a small constant: the fast route between the y-up and
//! z-up frames, which differ by a quarter turn about X.
//!
//! A rotation about Y by `π/2` keeps functions even in `y` (`m >= 0`,
//! `cos mφ`) apart from odd ones (`m < 0`, `sin mφ`). In shlight's real basis
//! its band-`l` block is, with `d = d^l(π/2)` (Wigner's small d,
//! `d_{m m'}(β) = <l m| e^{-iβJ_y} |l m'>`) and `a, b > 0`,
//!
//! ```text
//! even:  M_{a b}   = d_{a b} + (-1)^b d_{a,-b}     M_{a 0} = sqrt2 d_{a 0}
//!        M_{0 b}   = sqrt2 d_{0 b}                 M_{0 0} = d_{0 0}
//! odd:   M_{-a,-b} = d_{a b} - (-1)^b d_{a,-b}
//! ```
//!
//! (`conj(U) d U^T` for the unitary `U` from complex to real SH, whose
//! mixed even-odd entries vanish). `d(π/2)` comes from the three-term
//! recurrence in the row index at `cos β = 0`,
//!
//! ```text
//! sqrt((l+m)(l-m+1)) d_{m-1,m'} = 2 m' d_{m m'} - sqrt((l-m)(l+m+1)) d_{m+1,m'},
//! ```
//!
//! run from the edge `d_{l m'} = (-1)^(l-m') 2^-l sqrt(C(2l, l+m'))` down to
//! `m = |m'|`, the direction in which the values grow (stable); the other
//! entries follow from `d_{m m'} = (-1)^(m-m') d_{m' m} = d_{-m',-m}`.
//! A quarter turn about X is `Rz(-π/2) Ry(π/2) Rz(π/2)`, and the `Rz` are
//! signed swaps within each `(m, -m)` pair.

use core::f64::consts::FRAC_PI_2;

use crate::rotation::rotate_z;
use crate::{ShCoeffs, ShValue};

/// The rows of `d^l(π/2)` from `m = l` down to `0`, by the recurrence (see
/// the module docs), all columns `m'` of a row at once (vector lanes).
struct HalfPiRows {
    l: usize,
    /// `2 m'` per column, `m' = -l..=l`.
    twice_mprime: Vec<f64>,
    /// Row `m`, exact for `|m'| <= m` (column `l + m'`).
    cur: Vec<f64>,
    /// Row `m + 1`.
    prev: Vec<f64>,
    /// The row `cur` holds; `None` before the first.
    m: Option<usize>,
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
        let mut edge = vec![0.0; 2 * l + 1];
        edge[l] = if l.is_multiple_of(2) { centre } else { -centre };
        for mp in 0..l {
            // C(2l, l+m'+1) / C(2l, l+m') = (l-m') / (l+m'+1).
            let ratio = ((l - mp) as f64 / (l + mp + 1) as f64).sqrt();
            edge[l + mp + 1] = -edge[l + mp] * ratio;
            edge[l - mp - 1] = -edge[l - mp] * ratio;
        }
        Self {
            l,
            twice_mprime: (0..=2 * l).map(|i| 2.0 * (i as f64 - l as f64)).collect(),
            cur: edge,
            prev: vec![0.0; 2 * l + 1],
            m: None,
        }
    }

    /// The next row `m` and its entries `d_{m m'}` for `m' = -m..=m`.
    fn next_row(&mut self) -> Option<(usize, &[f64])> {
        let l = self.l;
        let m = match self.m {
            None => l,
            Some(0) => return None,
            Some(m) => {
                // Row m - 1 from rows m and m + 1, columns |m'| <= m - 1.
                let (mf, lf) = (m as f64, l as f64);
                let up = ((lf - mf) * (lf + mf + 1.0)).sqrt();
                let inv = 1.0 / ((lf + mf) * (lf - mf + 1.0)).sqrt();
                let cols = l + 1 - m..l + m;
                let prev = &mut self.prev[cols.clone()];
                let cur = &self.cur[cols.clone()];
                for ((p, &c), &k) in prev.iter_mut().zip(cur).zip(&self.twice_mprime[cols]) {
                    *p = (k * c - up * *p) * inv;
                }
                core::mem::swap(&mut self.prev, &mut self.cur);
                m - 1
            }
        };
        self.m = Some(m);
        Some((m, &self.cur[l - m..=l + m]))
    }
}

/// `(-1)^n`.
#[inline(always)]
fn parity_sign(n: usize) -> f64 {
    if n.is_multiple_of(2) { 1.0 } else { -1.0 }
}

/// Applies the band-`l` block of the quarter turn about Y, `Ry(π/2)`, to
/// `x` (the `2l + 1` coefficients of band `l`) into `out`.
///
/// Row `a` of `d` gives row `a` of the even block `E` and row `-a` of the
/// odd block `O` (module docs) as each row leaves the recurrence, so no
/// matrix is stored. Both blocks are signed-symmetric,
/// `E_{b a} = (-1)^(a+b) E_{a b}` (from `d_{m m'} = (-1)^(m-m') d_{m' m}`
/// and `d_{a,-b} = d_{b,-a}`), so row `a` is needed only up to the diagonal:
/// it adds `E_{a b} x_b` to `y_a` and `(-1)^(a+b) E_{a b} x_a` to `y_b`.
fn turn_y_band<C: ShValue<Scalar = f64>>(l: usize, x: &[C], out: &mut [C]) {
    #[cfg(target_arch = "x86_64")]
    if crate::cpu_features::avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        unsafe { turn_y_band_avx(l, x, out) };
        return;
    }
    turn_y_band_body(l, x, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn turn_y_band_avx<C: ShValue<Scalar = f64>>(l: usize, x: &[C], out: &mut [C]) {
    turn_y_band_body(l, x, out);
}

#[inline(always)]
fn turn_y_band_body<C: ShValue<Scalar = f64>>(l: usize, x: &[C], out: &mut [C]) {
    debug_assert!(C::CHANNELS <= 3);
    let sqrt2 = 2f64.sqrt();
    let signs: Vec<f64> = (0..=l).map(parity_sign).collect();
    // Per channel (three, unused ones zero): even inputs x_{+b} (b = 0..=l)
    // and odd inputs x_{-b} (b = 1..=l at index b - 1), and their sums.
    let channel = |c: usize, i: usize| {
        if c < C::CHANNELS {
            x[i].channel(c)
        } else {
            0.0
        }
    };
    let even_in: [Vec<f64>; 3] =
        core::array::from_fn(|c| (0..=l).map(|b| channel(c, l + b)).collect());
    let odd_in: [Vec<f64>; 3] =
        core::array::from_fn(|c| (1..=l).map(|b| channel(c, l - b)).collect());
    let mut even_out: [Vec<f64>; 3] = core::array::from_fn(|_| vec![0.0; l + 1]);
    let mut odd_out: [Vec<f64>; 3] = core::array::from_fn(|_| vec![0.0; l]);
    // Row a of E (b = 0..=a) and of O (b = 1..=a at index b - 1), and the
    // same times (-1)^b.
    let (mut e, mut e_signed) = (vec![0.0; l + 1], vec![0.0; l + 1]);
    let (mut o, mut o_signed) = (vec![0.0; l], vec![0.0; l]);
    let mut rows = HalfPiRows::new(l);
    while let Some((a, d)) = rows.next_row() {
        // d[a + b] = d_{a b}, d[a - b] = d_{a,-b}.
        if a == 0 {
            e[0] = d[0];
            symmetric_rows(&e[..1], &[], &even_in, &mut even_out, 0, 1.0);
            continue;
        }
        e[0] = sqrt2 * d[a];
        let plus = &d[a + 1..=2 * a];
        let minus = d[..a].iter().rev();
        for ((((eb, ob), &p), &n), &s) in e[1..=a]
            .iter_mut()
            .zip(&mut o[..a])
            .zip(plus)
            .zip(minus)
            .zip(&signs[1..=a])
        {
            let n = s * n;
            *eb = p + n;
            *ob = p - n;
        }
        for ((es, &ev), &s) in e_signed[..a].iter_mut().zip(&e[..a]).zip(&signs) {
            *es = s * ev;
        }
        for ((os, &ov), &s) in o_signed[..a - 1]
            .iter_mut()
            .zip(&o[..a - 1])
            .zip(&signs[1..])
        {
            *os = s * ov;
        }
        let sa = signs[a];
        symmetric_rows(&e[..=a], &e_signed[..a], &even_in, &mut even_out, a, sa);
        symmetric_rows(
            &o[..a],
            &o_signed[..a - 1],
            &odd_in,
            &mut odd_out,
            a - 1,
            sa,
        );
    }
    for c in 0..C::CHANNELS {
        for b in 0..=l {
            out[l + b].set_channel(c, even_out[c][b]);
            if b > 0 {
                out[l - b].set_channel(c, odd_out[c][b - 1]);
            }
        }
    }
}

/// Row `a` of a signed-symmetric block given up to its diagonal (`row[b]`,
/// `b = 0..=a`; `signed[b]` = `row[b]` times the block's `(-1)^b`, `b < a`),
/// for three channels: `y_a += sum_b row[b] x_b` and
/// `y_b += sign_a x_a signed[b]` for `b < a`.
#[inline(always)]
fn symmetric_rows(
    row: &[f64],
    signed: &[f64],
    x: &[Vec<f64>; 3],
    y: &mut [Vec<f64>; 3],
    a: usize,
    sign_a: f64,
) {
    let xs = x.each_ref().map(|v| &v[..=a]);
    let mut acc = [[0.0; 4]; 3];
    let body = row.len() / 4 * 4;
    for (i, r) in row[..body].chunks_exact(4).enumerate() {
        for (c, xc) in xs.iter().enumerate() {
            let xv = &xc[4 * i..4 * i + 4];
            for k in 0..4 {
                acc[c][k] += r[k] * xv[k];
            }
        }
    }
    for (c, xc) in xs.iter().enumerate() {
        let mut dot = (acc[c][0] + acc[c][1]) + (acc[c][2] + acc[c][3]);
        for b in body..row.len() {
            dot += row[b] * xc[b];
        }
        y[c][a] += dot;
    }
    let alpha = xs.map(|xc| sign_a * xc[a]);
    let [y0, y1, y2] = y;
    for (((y0b, y1b), y2b), &s) in y0[..a]
        .iter_mut()
        .zip(&mut y1[..a])
        .zip(&mut y2[..a])
        .zip(signed)
    {
        *y0b += alpha[0] * s;
        *y1b += alpha[1] * s;
        *y2b += alpha[2] * s;
    }
}

/// Rotates coefficients by a quarter turn about Y, `Ry(π/2)`:
/// `g(d) = f(Ry(π/2)^-1 d)`, bands in parallel with the `rayon` feature.
fn turn_y<C: ShValue<Scalar = f64>>(f: &ShCoeffs<C>) -> ShCoeffs<C> {
    let lmax = f.lmax();
    let band = |l: usize| {
        let mut out = vec![C::ZERO; 2 * l + 1];
        turn_y_band(l, f.band(l), &mut out);
        out
    };
    #[cfg(feature = "rayon")]
    let bands: Vec<Vec<C>> = {
        use rayon::prelude::*;
        // Largest bands first for load balance.
        let mut b: Vec<Vec<C>> = (0..lmax + 1)
            .into_par_iter()
            .with_max_len(1)
            .map(|i| band(lmax - i))
            .collect();
        b.reverse();
        b
    };
    #[cfg(not(feature = "rayon"))]
    let bands: Vec<Vec<C>> = (0..=lmax).map(band).collect();
    let mut out = f.clone();
    for (l, b) in bands.into_iter().enumerate() {
        out.band_mut(l).copy_from_slice(&b);
    }
    out
}

/// Rotates coefficients by a quarter turn about X: `turns = 1` for
/// `Rx(+π/2)` (`(x, y, z) -> (x, -z, y)`), `turns = -1` for `Rx(-π/2)`;
/// `g(d) = f(R^-1 d)`, the same convention as [`crate::rotation::ShRotation`].
///
/// Equals `rotate_once(f, R)` to rounding, at a fraction of the cost:
/// `(l+1)^2 + l^2` multiply-adds per band and channel, and no rotation
/// blocks built by recurrence.
///
/// # Panics
/// If `turns` is not `1` or `-1`.
#[must_use]
pub fn quarter_turn_x<C: ShValue<Scalar = f64>>(f: &ShCoeffs<C>, turns: i32) -> ShCoeffs<C> {
    assert!(
        turns == 1 || turns == -1,
        "quarter_turn_x takes turns = 1 or -1"
    );
    // Rx(±π/2) = Rz(∓π/2) Ry(π/2) Rz(±π/2): Rz(∓π/2) takes +Y to ±X, and
    // rotating coefficients composes the same way (rightmost first).
    let s = f64::from(turns);
    rotate_z(&turn_y(&rotate_z(f, s * FRAC_PI_2)), -s * FRAC_PI_2)
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3};

    use super::*;
    use crate::rotation::rotate_once;

    fn random(lmax: usize, seed: u64) -> ShCoeffs<DVec3> {
        let mut s = seed;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let n = (lmax + 1) * (lmax + 1);
        ShCoeffs::from_vec((0..n).map(|_| DVec3::new(next(), next(), next())).collect()).unwrap()
    }

    fn max_diff(a: &ShCoeffs<DVec3>, b: &ShCoeffs<DVec3>) -> f64 {
        a.as_slice()
            .iter()
            .zip(b.as_slice())
            .map(|(x, y)| (*x - *y).abs().max_element())
            .fold(0.0, f64::max)
    }

    #[test]
    fn band_one_of_d_half_pi_is_the_textbook_matrix() {
        // d^1(β): d_11 = (1+c)/2, d_10 = -s/sqrt2, d_1-1 = (1-c)/2, d_00 = c.
        let r = 0.5f64.sqrt();
        let mut rows = HalfPiRows::new(1);
        let (m, d) = rows.next_row().unwrap();
        assert_eq!(m, 1);
        for (got, want) in d.iter().zip([0.5, -r, 0.5]) {
            assert!((got - want).abs() < 1e-15, "{d:?}");
        }
        let (m, d) = rows.next_row().unwrap();
        assert_eq!((m, d.len()), (0, 1));
        assert!(d[0].abs() < 1e-15);
        assert!(rows.next_row().is_none());
    }

    #[test]
    fn quarter_turns_match_the_recurrence_rotation() {
        let rx = DMat3::from_cols(DVec3::X, DVec3::Z, DVec3::NEG_Y); // (x,y,z)->(x,-z,y)
        for lmax in [0, 1, 2, 5, 16, 40] {
            let f = random(lmax, 7 + lmax as u64);
            let d = max_diff(&quarter_turn_x(&f, 1), &rotate_once(&f, rx));
            assert!(d < 1e-12, "lmax {lmax} +: {d:e}");
            let d = max_diff(&quarter_turn_x(&f, -1), &rotate_once(&f, rx.transpose()));
            assert!(d < 1e-12, "lmax {lmax} -: {d:e}");
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
            let d = x
                .iter()
                .zip(&y)
                .map(|(a, b)| (*a - *b).abs().max_element())
                .fold(0.0, f64::max);
            assert!(d < 1e-10, "band {l}: {d:e}");
        }
    }
}

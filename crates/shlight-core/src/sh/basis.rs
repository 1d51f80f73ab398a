//! Evaluation of the real SH basis at unit directions, one at a time or in batches.

use glam::DVec3;

use crate::sh::index::sh_count;
use crate::sh::legendre::Legendre;
use crate::sh::low_degree::{Lanes, QuadraticForm, eval_low_degree, eval_low_degree_with};
use crate::sh::real::Real;

/// Lanes the batch evaluator processes together (a multiple of every SIMD width).
const LANES: usize = 16;

/// Evaluates every real SH `Y_l^m`, `l <= lmax`, at unit directions.
///
/// Holds the recurrence tables, so build it once per `lmax` and reuse it.
///
/// ```
/// use shlight_core::sh::ShBasis;
/// let basis = ShBasis::<f64>::new(2);
/// let mut y = [0.0; 9];
/// basis.eval(glam::DVec3::Z, &mut y);
/// assert!((y[2] - 0.4886025119029199).abs() < 1e-15); // Y_1^0 at +Z
/// ```
///
/// # The basis
///
/// The real orthonormal SH used throughout shlight (Condon-Shortley phase
/// included; see the crate's conventions) are, with `x = cos t` and
/// `Pbar_l^m` from [`Legendre`]:
///
/// ```text
/// Y_l^m    = sqrt(2) Pbar_l^m(cos t) cos(m phi)    m > 0
/// Y_l^0    =         Pbar_l^0(cos t)
/// Y_l^{-m} = sqrt(2) Pbar_l^m(cos t) sin(m phi)    m > 0
/// ```
///
/// on the world direction `d = (sin t cos phi, sin t sin phi, cos t)`.
/// No trigonometric function is called: `cos(m phi)` and `sin(m phi)` come
/// from the complex recurrence `(c_m + i s_m) = (c_{m-1} + i s_{m-1})(x + i y)/s`
/// on the unit azimuth vector (Sloan 2008, appendix A1, kept unit-length so
/// nothing underflows at high `m`), and the polar part from the normalised
/// Legendre recurrences. For `lmax <= 4` the hard-coded Cartesian
/// polynomials of each function are used instead.
#[derive(Clone, Debug)]
pub struct ShBasis<T> {
    lmax: usize,
    legendre: Legendre<T>,
}

impl<T: Real> ShBasis<T> {
    /// Prepares evaluation up to degree `lmax`.
    #[must_use]
    pub fn new(lmax: usize) -> Self {
        Self {
            lmax,
            legendre: Legendre::new(if lmax <= 4 { 0 } else { lmax }),
        }
    }

    /// The highest degree evaluated.
    #[must_use]
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// Number of values per direction, `(lmax+1)^2`.
    #[must_use]
    pub fn count(&self) -> usize {
        sh_count(self.lmax)
    }

    /// Writes `Y_l^m(d)` to `out[l*(l+1)+m]` for every `l <= lmax`.
    ///
    /// Precondition: `d` (a `glam::Vec3` for `f32`, `DVec3` for `f64`) has
    /// unit length. Panics if `out` is shorter than [`ShBasis::count`].
    pub fn eval(&self, d: T::Vec3, out: &mut [T]) {
        let d: [T; 3] = d.into();
        if self.lmax <= 4 {
            eval_low_degree(self.lmax, d[0], d[1], d[2], out);
        } else {
            let out = &mut out[..self.count()];
            self.general::<1>(&[d[0]], &[d[1]], &[d[2]], |i, v| out[i] = v[0]);
        }
    }

    /// Evaluates the basis at `n` directions given as structure of arrays.
    ///
    /// `out` is coefficient-major: `out[i * n + k] = Y_i(x[k], y[k], z[k])`, so
    /// each basis function's values over the batch are contiguous (what a
    /// projection or a shader upload wants). The loops run over lanes of 16
    /// directions and auto-vectorise.
    ///
    /// Panics if `y`, `z` differ in length from `x`, or `out.len() != count * n`.
    pub fn eval_batch(&self, x: &[T], y: &[T], z: &[T], out: &mut [T]) {
        let n = x.len();
        assert!(y.len() == n && z.len() == n, "x, y, z lengths differ");
        let count = self.count();
        assert_eq!(out.len(), count * n, "output must hold count * n values");
        let mut start = 0;
        while start < n {
            let len = LANES.min(n - start);
            let (xs, ys, zs) = load_lanes(x, y, z, start);
            self.lanes(
                &xs,
                &ys,
                &zs,
                #[inline(always)]
                |i, v| store_lanes(&mut out[i * n + start..i * n + start + len], v),
            );
            start += len;
        }
    }

    /// Reconstructs `f(d_k) = sum_i coeffs[i] Y_i(d_k)` at `n` directions
    /// given as structure of arrays, writing `out[k]`.
    ///
    /// `coeffs` holds `count()` values in flat-index order. Same lane
    /// structure as [`ShBasis::eval_batch`], without storing the basis.
    ///
    /// Panics if the lengths disagree.
    pub fn eval_sum_batch(&self, coeffs: &[T], x: &[T], y: &[T], z: &[T], out: &mut [T]) {
        let n = x.len();
        assert!(
            y.len() == n && z.len() == n && out.len() == n,
            "x, y, z, out lengths differ"
        );
        let count = self.count();
        assert_eq!(coeffs.len(), count, "coeffs must hold (lmax+1)^2 values");
        let form = (self.lmax <= 2).then(|| QuadraticForm::from_coeffs(coeffs));
        let mut start = 0;
        while start < n {
            let len = LANES.min(n - start);
            let (xs, ys, zs) = load_lanes(x, y, z, start);
            if let Some(form) = &form {
                let v: Lanes<T, LANES> = form.eval(Lanes(xs), Lanes(ys), Lanes(zs));
                store_lanes(&mut out[start..start + len], &v.0);
                start += len;
                continue;
            }
            let mut acc = [T::ZERO; LANES];
            self.lanes(
                &xs,
                &ys,
                &zs,
                #[inline(always)]
                |i, v| {
                    let c = coeffs[i];
                    for j in 0..LANES {
                        acc[j] += c * v[j];
                    }
                },
            );
            out[start..start + len].copy_from_slice(&acc[..len]);
            start += len;
        }
    }

    /// Hands `(i, Y_i)` over one block of lanes to `emit`: the hard-coded
    /// polynomials for `lmax <= 4`, the recurrences above.
    #[inline(always)]
    fn lanes(
        &self,
        x: &[T; LANES],
        y: &[T; LANES],
        z: &[T; LANES],
        mut emit: impl FnMut(usize, &[T; LANES]),
    ) {
        if self.lmax <= 4 {
            eval_low_degree_with(
                self.lmax,
                Lanes(*x),
                Lanes(*y),
                Lanes(*z),
                #[inline(always)]
                |i, v: Lanes<T, LANES>| emit(i, &v.0),
            );
        } else {
            self.general::<LANES>(x, y, z, emit);
        }
    }

    /// The general path: Legendre columns times the azimuth recurrence.
    #[inline(always)]
    fn general<const N: usize>(
        &self,
        x: &[T; N],
        y: &[T; N],
        z: &[T; N],
        mut emit: impl FnMut(usize, &[T; N]),
    ) {
        let sqrt2 = T::from_f64(core::f64::consts::SQRT_2);
        // Polar sine and the unit azimuth vector (1, 0) at the poles.
        let mut s = [T::ZERO; N];
        let mut ca = [T::ONE; N];
        let mut sa = [T::ZERO; N];
        for j in 0..N {
            let r2 = x[j] * x[j] + y[j] * y[j];
            s[j] = r2.sqrt();
            if s[j] > T::ZERO {
                let inv = T::ONE / s[j];
                ca[j] = x[j] * inv;
                sa[j] = y[j] * inv;
            }
        }
        // sqrt(2) cos(m phi), sqrt(2) sin(m phi) for the current column.
        let mut cm = [T::ONE; N];
        let mut sm = [T::ZERO; N];
        let mut cur_m = 0;
        let mut row_c = [T::ZERO; N];
        let mut row_s = [T::ZERO; N];
        self.legendre.columns::<N>(
            z,
            &s,
            #[inline(always)]
            |l, m, p| {
                if m != cur_m {
                    // Advance the azimuth recurrence to m (columns arrive in order).
                    for j in 0..N {
                        let c = cm[j] * ca[j] - sm[j] * sa[j];
                        let sn = sm[j] * ca[j] + cm[j] * sa[j];
                        cm[j] = c;
                        sm[j] = sn;
                    }
                    cur_m = m;
                }
                let base = l * (l + 1);
                if m == 0 {
                    emit(base, p);
                } else {
                    for j in 0..N {
                        row_c[j] = sqrt2 * p[j] * cm[j];
                        row_s[j] = sqrt2 * p[j] * sm[j];
                    }
                    emit(base + m, &row_c);
                    emit(base - m, &row_s);
                }
            },
        );
    }
}

/// Copies the first `dst.len()` lanes of `v` to `dst`, as one fixed-size
/// copy when the chunk is full.
#[inline(always)]
fn store_lanes<T: Real>(dst: &mut [T], v: &[T; LANES]) {
    if let Ok(full) = <&mut [T; LANES]>::try_from(&mut *dst) {
        *full = *v;
    } else {
        let len = dst.len();
        dst.copy_from_slice(&v[..len]);
    }
}

/// Lanes `start..start+LANES` of the three coordinate arrays; past the end,
/// lanes hold the direction +Z.
#[inline(always)]
fn load_lanes<T: Real>(
    x: &[T],
    y: &[T],
    z: &[T],
    start: usize,
) -> ([T; LANES], [T; LANES], [T; LANES]) {
    let end = start + LANES;
    if end <= x.len() {
        // Fixed-size copies: no memcpy call.
        let f = |v: &[T]| -> [T; LANES] { v[start..end].try_into().expect("length checked") };
        return (f(x), f(y), f(z));
    }
    let len = x.len() - start;
    let mut xs = [T::ZERO; LANES];
    let mut ys = [T::ZERO; LANES];
    let mut zs = [T::ONE; LANES];
    xs[..len].copy_from_slice(&x[start..]);
    ys[..len].copy_from_slice(&y[start..]);
    zs[..len].copy_from_slice(&z[start..]);
    (xs, ys, zs)
}

/// `Y_l^m(d)` for every `l <= lmax` at one unit direction, in `f64`.
///
/// Convenience for one-off use; build an [`ShBasis`] to evaluate many
/// directions.
///
/// ```
/// let y = shlight_core::sh::sh_eval(1, glam::DVec3::X);
/// assert!((y[3] + 0.4886025119029199).abs() < 1e-15); // Y_1^1 = -sqrt(3/4pi) x
/// ```
#[must_use]
pub fn sh_eval(lmax: usize, d: DVec3) -> Vec<f64> {
    let mut out = vec![0.0; sh_count(lmax)];
    ShBasis::new(lmax).eval(d, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dirs() -> Vec<[f64; 3]> {
        let mut v = vec![
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
        ];
        for i in 0..40 {
            let t = 0.3 + i as f64 * 0.071;
            let p = i as f64 * 0.9 - 2.0;
            v.push([t.sin() * p.cos(), t.sin() * p.sin(), t.cos()]);
        }
        v
    }

    #[test]
    fn sum_batch_equals_dot_of_scalar_evaluations() {
        let d = dirs();
        for lmax in [0, 2, 4, 6] {
            let basis = ShBasis::<f64>::new(lmax);
            let coeffs: Vec<f64> = (0..basis.count())
                .map(|i| (i as f64 * 0.37).sin())
                .collect();
            let x: Vec<f64> = d.iter().map(|v| v[0]).collect();
            let y: Vec<f64> = d.iter().map(|v| v[1]).collect();
            let z: Vec<f64> = d.iter().map(|v| v[2]).collect();
            let mut out = vec![0.0; d.len()];
            basis.eval_sum_batch(&coeffs, &x, &y, &z, &mut out);
            let mut one = vec![0.0; basis.count()];
            for (k, v) in d.iter().enumerate() {
                basis.eval(glam::DVec3::from(*v), &mut one);
                let want: f64 = one.iter().zip(&coeffs).map(|(a, b)| a * b).sum();
                assert!((out[k] - want).abs() < 1e-14, "lmax {lmax} k {k}");
            }
        }
    }

    #[test]
    fn batch_equals_scalar() {
        let d = dirs();
        for lmax in [0, 2, 4, 5, 9] {
            let basis = ShBasis::<f64>::new(lmax);
            let n = d.len();
            let (x, y, z): (Vec<_>, Vec<_>, Vec<_>) = (
                d.iter().map(|v| v[0]).collect(),
                d.iter().map(|v| v[1]).collect(),
                d.iter().map(|v| v[2]).collect(),
            );
            let mut out = vec![0.0; basis.count() * n];
            basis.eval_batch(&x, &y, &z, &mut out);
            let mut one = vec![0.0; basis.count()];
            for k in 0..n {
                basis.eval(glam::DVec3::from(d[k]), &mut one);
                for i in 0..basis.count() {
                    assert_eq!(out[i * n + k], one[i], "lmax {lmax} i {i} k {k}");
                }
            }
        }
    }
}

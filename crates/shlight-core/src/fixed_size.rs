//! What the fixed-size SH types ([`crate::ShL1`], [`crate::ShL2`],
//! [`crate::ShL1Rgb`], [`crate::ShL2Rgb`]) share: their evaluation (the
//! basis constants of [`crate::hardcoded`] folded into the coefficients,
//! then one dot product with the monomials of the direction), the
//! clamped-cosine eigenvalues of degrees 0 to 2, rotation by
//! [`crate::ShRotationL2`], and their methods and per-coefficient
//! arithmetic (the macros `impl_fixed_sh` and `impl_fixed_arith`).

use core::f64::consts::PI;

use crate::hardcoded::{K00, K1, K2_2, K20, K22, eval_hardcoded};
use crate::{GlamReal, ShRotationL2};

/// `A_l` for `l = 0, 1, 2`: `pi, 2 pi / 3, pi / 4`, the Funk-Hecke
/// eigenvalues of the clamped cosine (Ramamoorthi & Hanrahan 2001, eq. 8;
/// [`crate::zonal::clamped_cosine_eigenvalue`] for every `l`).
pub(crate) const A_L: [f64; 3] = [PI, 2.0 * PI / 3.0, PI / 4.0];

/// `sum_i a_i b_i`, in index order (a fixed chain the compiler keeps in registers).
#[inline(always)]
pub(crate) fn dot<T: crate::Real, const N: usize>(a: &[T; N], b: &[T; N]) -> T {
    let mut acc = a[0] * b[0];
    for i in 1..N {
        acc += a[i] * b[i];
    }
    acc
}

/// The degree of flat index `i < 9`.
const BAND: [usize; 9] = [0, 1, 1, 1, 2, 2, 2, 2, 2];

/// The highest degree held by `n = 4` or `9` coefficients.
pub(crate) const fn lmax_of(n: usize) -> usize {
    if n == 4 { 1 } else { 2 }
}

/// `Y_i(d)`, `i < N` (`N = 4` or `9`), from [`crate::hardcoded`]'s polynomials.
#[inline(always)]
pub(crate) fn basis<T: GlamReal, const N: usize>(d: T::Vec3) -> [T; N] {
    let [x, y, z] = T::vec3_to_array(d);
    let mut out = [<T as crate::Real>::ZERO; N];
    eval_hardcoded(lmax_of(N), x, y, z, &mut out);
    out
}

/// The weights `w` with `f(d) = sum_i w_i p_i(d)` for the monomials
/// `p = [1, y, z, x, xy, yz, z^2, xz, x^2 - y^2]` of [`monomials`]: the
/// basis constants and signs of [`crate::hardcoded`] folded into the
/// coefficients, and `Y_2^0 = K20 (3 z^2 - 1)` split between `z^2` and the
/// constant. Evaluation then costs one product per coefficient and the
/// basis constants are applied once per expansion, not once per direction
/// (inside a loop the compiler lifts this out).
#[inline(always)]
pub(crate) fn monomial_weights<T: GlamReal, const N: usize>(c: &[T; N]) -> [T; N] {
    let k = T::from_f64;
    let mut w = [<T as crate::Real>::ZERO; N];
    w[0] = c[0] * k(K00);
    w[1] = -c[1] * k(K1);
    w[2] = c[2] * k(K1);
    w[3] = -c[3] * k(K1);
    if N == 9 {
        let c: [T; 9] = core::array::from_fn(|i| c[i]);
        let tail = [
            c[4] * k(K2_2),
            -c[5] * k(K2_2),
            c[6] * k(3.0 * K20),
            -c[7] * k(K2_2),
            c[8] * k(K22),
        ];
        w[0] -= c[6] * k(K20);
        w[4..9].copy_from_slice(&tail);
    }
    w
}

/// `[1, y, z, x]` or `[1, y, z, x, xy, yz, z^2, xz, x^2 - y^2]` at `d`.
#[inline(always)]
pub(crate) fn monomials<T: GlamReal, const N: usize>(d: T::Vec3) -> [T; N] {
    let [x, y, z] = T::vec3_to_array(d);
    let mut p = [T::ONE; N];
    p[1] = y;
    p[2] = z;
    p[3] = x;
    if N == 9 {
        let tail = [x * y, y * z, z * z, x * z, x * x - y * y];
        p[4..9].copy_from_slice(&tail);
    }
    p
}

/// `E_i = A_l L_i`, `l` the degree of `i`.
#[inline(always)]
pub(crate) fn irradiance<T: GlamReal, const N: usize>(c: &[T; N]) -> [T; N] {
    core::array::from_fn(|i| c[i] * T::from_f64(A_L[BAND[i]]))
}

/// `c` with degree 1 rotated by `M^1` and, when `N = 9`, degree 2 by `M^2`.
#[inline]
pub(crate) fn rotated<T: GlamReal, const N: usize>(c: &[T; N], rot: &ShRotationL2<T>) -> [T; N] {
    let mut out = *c;
    let b1 = rot.apply_band1(&core::array::from_fn(|k| c[1 + k]));
    out[1..4].copy_from_slice(&b1);
    if N == 9 {
        let b2 = rot.apply_band2(&core::array::from_fn(|k| c[4 + k]));
        out[4..9].copy_from_slice(&b2);
    }
    out
}

/// The first `N` coefficients of `s`, channel `ch`, zero past its end.
pub(crate) fn take<C: crate::ShValue, const N: usize>(s: &[C], ch: usize) -> [C::Scalar; N] {
    core::array::from_fn(|i| {
        s.get(i)
            .map_or(<C::Scalar as crate::Real>::ZERO, |v| v.channel(ch))
    })
}

/// Per-coefficient arithmetic for a fixed-size type `$ty<T>` whose
/// coefficient arrays are the fields `$f`: `+`, `-`, unary `-`, `* s`,
/// `s *` (for `f32` and `f64`), the assigning forms, `ZERO`, `Default`
/// (zero) and `lerp`.
macro_rules! impl_fixed_arith {
    ($ty:ident, $($f:ident),+) => {
        impl<T: $crate::GlamReal> $ty<T> {
            /// All coefficients zero: the function that is zero everywhere.
            pub const ZERO: Self = Self { $($f: [<T as $crate::Real>::ZERO; _]),+ };

            /// Linear interpolation `self (1 - t) + other t`, coefficient by
            /// coefficient (the SH of the interpolated functions); `t = 0`
            /// gives `self`, `t = 1` gives `other` exactly.
            #[inline]
            #[must_use]
            pub fn lerp(&self, other: &Self, t: T) -> Self {
                let s = T::ONE - t;
                let mut out = *self;
                $(
                    for (o, b) in out.$f.iter_mut().zip(&other.$f) {
                        *o = *o * s + *b * t;
                    }
                )+
                out
            }
        }

        impl<T: $crate::GlamReal> Default for $ty<T> {
            /// [`Self::ZERO`].
            #[inline]
            fn default() -> Self {
                Self::ZERO
            }
        }

        impl<T: $crate::GlamReal> core::ops::Add for $ty<T> {
            type Output = Self;
            /// The sum of the two functions.
            #[inline]
            fn add(mut self, rhs: Self) -> Self {
                self += rhs;
                self
            }
        }

        impl<T: $crate::GlamReal> core::ops::AddAssign for $ty<T> {
            #[inline]
            fn add_assign(&mut self, rhs: Self) {
                $(
                    for (a, b) in self.$f.iter_mut().zip(rhs.$f) {
                        *a += b;
                    }
                )+
            }
        }

        impl<T: $crate::GlamReal> core::ops::Sub for $ty<T> {
            type Output = Self;
            /// The difference of the two functions.
            #[inline]
            fn sub(mut self, rhs: Self) -> Self {
                self -= rhs;
                self
            }
        }

        impl<T: $crate::GlamReal> core::ops::SubAssign for $ty<T> {
            #[inline]
            fn sub_assign(&mut self, rhs: Self) {
                $(
                    for (a, b) in self.$f.iter_mut().zip(rhs.$f) {
                        *a -= b;
                    }
                )+
            }
        }

        impl<T: $crate::GlamReal> core::ops::Neg for $ty<T> {
            type Output = Self;
            #[inline]
            fn neg(mut self) -> Self {
                $(
                    for a in &mut self.$f {
                        *a = -*a;
                    }
                )+
                self
            }
        }

        impl<T: $crate::GlamReal> core::ops::Mul<T> for $ty<T> {
            type Output = Self;
            /// Every coefficient times `s`: the function scaled by `s`.
            #[inline]
            fn mul(mut self, s: T) -> Self {
                self *= s;
                self
            }
        }

        impl<T: $crate::GlamReal> core::ops::MulAssign<T> for $ty<T> {
            #[inline]
            fn mul_assign(&mut self, s: T) {
                $(
                    for a in &mut self.$f {
                        *a *= s;
                    }
                )+
            }
        }

        impl core::ops::Mul<$ty<f32>> for f32 {
            type Output = $ty<f32>;
            #[inline]
            fn mul(self, sh: $ty<f32>) -> $ty<f32> {
                sh * self
            }
        }

        impl core::ops::Mul<$ty<f64>> for f64 {
            type Output = $ty<f64>;
            #[inline]
            fn mul(self, sh: $ty<f64>) -> $ty<f64> {
                sh * self
            }
        }
    };
}
pub(crate) use impl_fixed_arith;

/// The methods of a scalar fixed-size type `$sc<T> { coeffs: [T; $n] }` and
/// its RGB form `$rgb<T> { r, g, b: [T; $n] }`: construction, the basis,
/// evaluation, irradiance, rotation, conversion to and from [`crate::ShCoeffs`],
/// and the arithmetic of [`impl_fixed_arith`].
macro_rules! impl_fixed_sh {
    ($sc:ident, $rgb:ident, $n:literal) => {
        impl<T: $crate::GlamReal> $sc<T> {
            /// The highest degree held.
            pub const LMAX: usize = $crate::fixed_size::lmax_of($n);

            /// From the coefficients in flat-index order `l*(l+1)+m`.
            #[inline]
            #[must_use]
            pub const fn new(coeffs: [T; $n]) -> Self {
                Self { coeffs }
            }

            /// The basis at the unit direction `d`, `Y_l^m(d)`: also the
            /// coefficients of a directional light from `d` whose irradiance
            /// facing it is 1 (a delta distribution, truncated).
            #[inline]
            #[must_use]
            pub fn basis(d: T::Vec3) -> Self {
                Self {
                    coeffs: $crate::fixed_size::basis(d),
                }
            }

            /// The function at the unit direction `d`: `sum_i f_i Y_i(d)`
            /// (radiance, when the coefficients are radiance).
            #[inline]
            #[must_use]
            pub fn eval(&self, d: T::Vec3) -> T {
                let w = $crate::fixed_size::monomial_weights(&self.coeffs);
                $crate::fixed_size::dot(&w, &$crate::fixed_size::monomials(d))
            }

            /// Irradiance coefficients from radiance ones: `E_l^m = A_l L_l^m`
            /// with `A_0 = pi`, `A_1 = 2 pi / 3`, `A_2 = pi / 4`
            /// (Ramamoorthi & Hanrahan 2001, eq. 8; [`crate::irradiance`]).
            #[inline]
            #[must_use]
            pub fn irradiance(&self) -> Self {
                Self {
                    coeffs: $crate::fixed_size::irradiance(&self.coeffs),
                }
            }

            /// Irradiance at the unit normal `n` of radiance held in `self`,
            /// `E(n) = sum A_l L_l^m Y_l^m(n)`, the truncation of
            /// `int L(w) max(n . w, 0) dw`: [`Self::irradiance`] then
            /// [`Self::eval`]. Inside a loop the compiler lifts the
            /// conversion out; convert once yourself to be sure.
            #[inline]
            #[must_use]
            pub fn eval_irradiance(&self, n: T::Vec3) -> T {
                self.irradiance().eval(n)
            }

            /// The function rotated by the rotation matrix `r` (column
            /// vectors, `d -> r d`): `g(d) = f(r^T d)`, so a light from `a`
            /// comes from `r a`. Precondition: `r` is a rotation
            /// (`debug_assert!` only); see [`crate::ShRotationL2`].
            #[must_use]
            pub fn rotated(&self, r: T::Mat3) -> Self {
                self.rotated_by(&$crate::ShRotationL2::from_mat3_to(Self::LMAX, r))
            }

            /// The function rotated by the rotation `d -> q d q*` (`q`
            /// normalised first): `g(d) = f(R(q)^T d)`.
            #[must_use]
            pub fn rotated_quat(&self, q: T::Quat) -> Self {
                self.rotated_by(&$crate::ShRotationL2::from_quat_to(Self::LMAX, q))
            }

            /// The function rotated by prepared blocks (degree 2 unused at lmax 1).
            #[inline]
            #[must_use]
            pub fn rotated_by(&self, rot: &$crate::ShRotationL2<T>) -> Self {
                Self {
                    coeffs: $crate::fixed_size::rotated(&self.coeffs, rot),
                }
            }

            /// From an expansion of any lmax: a longer one is **truncated**
            /// (degrees above `LMAX` dropped, the least-squares fit of what
            /// is kept), a shorter one **zero-padded**; the same rule as
            /// [`crate::ShCoeffs::resized`].
            #[must_use]
            pub fn from_coeffs(sh: &$crate::ShCoeffs<T>) -> Self {
                Self {
                    coeffs: $crate::fixed_size::take(sh.as_slice(), 0),
                }
            }

            /// The same coefficients as an [`crate::ShCoeffs`] of lmax `LMAX`.
            #[must_use]
            pub fn to_coeffs(&self) -> $crate::ShCoeffs<T> {
                $crate::ShCoeffs::from_fn(Self::LMAX, |l, m| self.coeffs[$crate::sh_index(l, m)])
            }
        }

        impl<T: $crate::GlamReal> From<$sc<T>> for $crate::ShCoeffs<T> {
            /// The same coefficients as an expansion of lmax `LMAX` (lossless).
            fn from(sh: $sc<T>) -> Self {
                sh.to_coeffs()
            }
        }

        impl<T: $crate::GlamReal> $rgb<T> {
            /// The highest degree held.
            pub const LMAX: usize = $crate::fixed_size::lmax_of($n);

            /// From the three channels' coefficients, each in flat-index order.
            #[inline]
            #[must_use]
            pub const fn new(r: [T; $n], g: [T; $n], b: [T; $n]) -> Self {
                Self { r, g, b }
            }

            /// From three scalar expansions (red, green, blue).
            #[inline]
            #[must_use]
            pub const fn from_channels(r: $sc<T>, g: $sc<T>, b: $sc<T>) -> Self {
                Self {
                    r: r.coeffs,
                    g: g.coeffs,
                    b: b.coeffs,
                }
            }

            /// The scalar expansions of red, green and blue.
            #[inline]
            #[must_use]
            pub const fn channels(&self) -> [$sc<T>; 3] {
                [$sc::new(self.r), $sc::new(self.g), $sc::new(self.b)]
            }

            /// A scalar expansion times an RGB colour: channel `c` is
            /// `f * colour[c]` (e.g. a scalar `basis(d)` times a light's colour).
            #[inline]
            #[must_use]
            pub fn from_scalar(f: &$sc<T>, colour: T::Vec3) -> Self {
                let [r, g, b] = T::vec3_to_array(colour);
                Self::from_channels(*f * r, *f * g, *f * b)
            }

            /// The function at the unit direction `d` (RGB in `x, y, z`):
            /// the basis once, then one dot product per channel. (The basis
            /// constants are folded into the coefficients first, so "the
            /// basis" is its monomials `1, y, z, x, xy, yz, z^2, xz, x^2 - y^2`;
            /// in a loop that folding is lifted out.)
            #[inline]
            #[must_use]
            pub fn eval(&self, d: T::Vec3) -> T::Vec3 {
                use $crate::fixed_size::{dot, monomial_weights};
                let p = $crate::fixed_size::monomials(d);
                T::vec3_from_array([
                    dot(&monomial_weights(&self.r), &p),
                    dot(&monomial_weights(&self.g), &p),
                    dot(&monomial_weights(&self.b), &p),
                ])
            }

            /// Irradiance coefficients from radiance ones, per channel:
            /// `E_l^m = A_l L_l^m` with `A_0 = pi`, `A_1 = 2 pi / 3`, `A_2 = pi / 4`.
            #[inline]
            #[must_use]
            pub fn irradiance(&self) -> Self {
                Self {
                    r: $crate::fixed_size::irradiance(&self.r),
                    g: $crate::fixed_size::irradiance(&self.g),
                    b: $crate::fixed_size::irradiance(&self.b),
                }
            }

            /// Irradiance at the unit normal `n` of radiance held in `self`,
            /// `E(n) = sum A_l L_l^m Y_l^m(n)` per channel: [`Self::irradiance`]
            /// then [`Self::eval`] (the compiler lifts the conversion out of loops).
            #[inline]
            #[must_use]
            pub fn eval_irradiance(&self, n: T::Vec3) -> T::Vec3 {
                self.irradiance().eval(n)
            }

            /// Every channel rotated by the rotation matrix `r`:
            /// `g(d) = f(r^T d)` so a light from `a` comes from `r a`.
            #[must_use]
            pub fn rotated(&self, r: T::Mat3) -> Self {
                self.rotated_by(&$crate::ShRotationL2::from_mat3_to(Self::LMAX, r))
            }

            /// Every channel rotated by the rotation `d -> q d q*`.
            #[must_use]
            pub fn rotated_quat(&self, q: T::Quat) -> Self {
                self.rotated_by(&$crate::ShRotationL2::from_quat_to(Self::LMAX, q))
            }

            /// Every channel rotated by prepared blocks.
            #[inline]
            #[must_use]
            pub fn rotated_by(&self, rot: &$crate::ShRotationL2<T>) -> Self {
                Self {
                    r: $crate::fixed_size::rotated(&self.r, rot),
                    g: $crate::fixed_size::rotated(&self.g, rot),
                    b: $crate::fixed_size::rotated(&self.b, rot),
                }
            }

            /// From an RGB expansion of any lmax: truncated if longer,
            /// zero-padded if shorter (the rule of [`crate::ShCoeffs::resized`]).
            #[must_use]
            pub fn from_coeffs(sh: &$crate::ShCoeffs<T::Vec3>) -> Self {
                let s = sh.as_slice();
                Self {
                    r: $crate::fixed_size::take(s, 0),
                    g: $crate::fixed_size::take(s, 1),
                    b: $crate::fixed_size::take(s, 2),
                }
            }

            /// The same coefficients as an RGB [`crate::ShCoeffs`] of lmax `LMAX`.
            #[must_use]
            pub fn to_coeffs(&self) -> $crate::ShCoeffs<T::Vec3> {
                $crate::ShCoeffs::from_fn(Self::LMAX, |l, m| {
                    let i = $crate::sh_index(l, m);
                    T::vec3_from_array([self.r[i], self.g[i], self.b[i]])
                })
            }
        }

        impl<T: $crate::GlamReal> From<$rgb<T>> for $crate::ShCoeffs<T::Vec3> {
            /// The same coefficients as an RGB expansion of lmax `LMAX` (lossless).
            fn from(sh: $rgb<T>) -> Self {
                sh.to_coeffs()
            }
        }

        $crate::fixed_size::impl_fixed_arith!($sc, coeffs);
        $crate::fixed_size::impl_fixed_arith!($rgb, r, g, b);
    };
}
pub(crate) use impl_fixed_sh;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::zonal::clamped_cosine_eigenvalue;

    #[test]
    fn eigenvalues_match_the_general_formula() {
        for (l, a) in A_L.iter().enumerate() {
            assert!((a - clamped_cosine_eigenvalue(l)).abs() < 1e-15, "l = {l}");
        }
    }

    #[test]
    fn dot_sums_every_product() {
        let a = [1.0f64, 2.0, 3.0, 4.0];
        let b = [0.5, -1.0, 2.0, 0.25];
        assert_eq!(dot(&a, &b), 0.5 - 2.0 + 6.0 + 1.0);
    }
}

//! The methods and arithmetic of the fixed-size SH types, written once for
//! all four by macros: `impl_fixed_sh` (construction, the basis,
//! evaluation, irradiance, rotation, conversion to and from
//! [`crate::sh::ShCoeffs`]) and `impl_fixed_arith` (per-coefficient `+ - *`,
//! `ZERO`, `Default`, `lerp`).

/// Per-coefficient arithmetic for a fixed-size type `$ty<T>` whose
/// coefficient arrays are the fields `$f`: `+`, `-`, unary `-`, `* s`,
/// `s *` (for `f32` and `f64`), the assigning forms, `ZERO`, `Default`
/// (zero) and `lerp`.
macro_rules! impl_fixed_arith {
    ($ty:ident, $($f:ident),+) => {
        impl<T: $crate::sh::glam_real::GlamReal> $ty<T> {
            /// All coefficients zero: the function that is zero everywhere.
            pub const ZERO: Self = Self { $($f: [<T as $crate::sh::real::Real>::ZERO; _]),+ };

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

        impl<T: $crate::sh::glam_real::GlamReal> Default for $ty<T> {
            /// [`Self::ZERO`].
            #[inline]
            fn default() -> Self {
                Self::ZERO
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> core::ops::Add for $ty<T> {
            type Output = Self;
            /// The sum of the two functions.
            #[inline]
            fn add(mut self, rhs: Self) -> Self {
                self += rhs;
                self
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> core::ops::AddAssign for $ty<T> {
            #[inline]
            fn add_assign(&mut self, rhs: Self) {
                $(
                    for (a, b) in self.$f.iter_mut().zip(rhs.$f) {
                        *a += b;
                    }
                )+
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> core::ops::Sub for $ty<T> {
            type Output = Self;
            /// The difference of the two functions.
            #[inline]
            fn sub(mut self, rhs: Self) -> Self {
                self -= rhs;
                self
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> core::ops::SubAssign for $ty<T> {
            #[inline]
            fn sub_assign(&mut self, rhs: Self) {
                $(
                    for (a, b) in self.$f.iter_mut().zip(rhs.$f) {
                        *a -= b;
                    }
                )+
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> core::ops::Neg for $ty<T> {
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

        impl<T: $crate::sh::glam_real::GlamReal> core::ops::Mul<T> for $ty<T> {
            type Output = Self;
            /// Every coefficient times `s`: the function scaled by `s`.
            #[inline]
            fn mul(mut self, s: T) -> Self {
                self *= s;
                self
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> core::ops::MulAssign<T> for $ty<T> {
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
/// evaluation, irradiance, rotation, conversion to and from [`crate::sh::ShCoeffs`],
/// and the arithmetic of [`impl_fixed_arith`].
macro_rules! impl_fixed_sh {
    ($sc:ident, $rgb:ident, $n:literal) => {
        impl<T: $crate::sh::glam_real::GlamReal> $sc<T> {
            /// The highest degree held.
            pub const LMAX: usize = $crate::sh::fixed_size::array_eval::lmax_of($n);

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
                    coeffs: $crate::sh::fixed_size::array_eval::basis(d),
                }
            }

            /// The function at the unit direction `d`: `sum_i f_i Y_i(d)`
            /// (radiance, when the coefficients are radiance).
            #[inline]
            #[must_use]
            pub fn eval(&self, d: T::Vec3) -> T {
                let w = $crate::sh::fixed_size::array_eval::monomial_weights(&self.coeffs);
                $crate::sh::fixed_size::array_eval::dot(
                    &w,
                    &$crate::sh::fixed_size::array_eval::monomials(d),
                )
            }

            /// Irradiance coefficients from radiance ones: `E_l^m = A_l L_l^m`
            /// with `A_0 = pi`, `A_1 = 2 pi / 3`, `A_2 = pi / 4`
            /// (Ramamoorthi & Hanrahan 2001, eq. 8; [`crate::sh::irradiance`]).
            #[inline]
            #[must_use]
            pub fn irradiance(&self) -> Self {
                Self {
                    coeffs: $crate::sh::fixed_size::array_eval::irradiance(&self.coeffs),
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
            /// (`debug_assert!` only); see [`crate::sh::ShRotationL2`].
            #[must_use]
            pub fn rotated(&self, r: T::Mat3) -> Self {
                self.rotated_by(
                    &$crate::sh::fixed_size::rotation_l2::ShRotationL2::from_mat3_to(Self::LMAX, r),
                )
            }

            /// The function rotated by the rotation `d -> q d q*` (`q`
            /// normalised first): `g(d) = f(R(q)^T d)`.
            #[must_use]
            pub fn rotated_quat(&self, q: T::Quat) -> Self {
                self.rotated_by(
                    &$crate::sh::fixed_size::rotation_l2::ShRotationL2::from_quat_to(Self::LMAX, q),
                )
            }

            /// The function rotated by prepared blocks (degree 2 unused at lmax 1).
            #[inline]
            #[must_use]
            pub fn rotated_by(
                &self,
                rot: &$crate::sh::fixed_size::rotation_l2::ShRotationL2<T>,
            ) -> Self {
                Self {
                    coeffs: $crate::sh::fixed_size::rotation_l2::rotated(&self.coeffs, rot),
                }
            }

            /// From an expansion of any lmax: a longer one is **truncated**
            /// (degrees above `LMAX` dropped, the least-squares fit of what
            /// is kept), a shorter one **zero-padded**; the same rule as
            /// [`crate::sh::ShCoeffs::resized`].
            #[must_use]
            pub fn from_coeffs(sh: &$crate::sh::sh_coeffs::ShCoeffs<T>) -> Self {
                Self {
                    coeffs: $crate::sh::fixed_size::array_eval::take(sh.as_slice(), 0),
                }
            }

            /// The same coefficients as an [`crate::sh::ShCoeffs`] of lmax `LMAX`.
            #[must_use]
            pub fn to_coeffs(&self) -> $crate::sh::sh_coeffs::ShCoeffs<T> {
                $crate::sh::sh_coeffs::ShCoeffs::from_fn(Self::LMAX, |l, m| {
                    self.coeffs[$crate::sh::index::sh_index(l, m)]
                })
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> From<$sc<T>>
            for $crate::sh::sh_coeffs::ShCoeffs<T>
        {
            /// The same coefficients as an expansion of lmax `LMAX` (lossless).
            fn from(sh: $sc<T>) -> Self {
                sh.to_coeffs()
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> $rgb<T> {
            /// The highest degree held.
            pub const LMAX: usize = $crate::sh::fixed_size::array_eval::lmax_of($n);

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
                use $crate::sh::fixed_size::array_eval::{dot, monomial_weights};
                let p = $crate::sh::fixed_size::array_eval::monomials(d);
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
                    r: $crate::sh::fixed_size::array_eval::irradiance(&self.r),
                    g: $crate::sh::fixed_size::array_eval::irradiance(&self.g),
                    b: $crate::sh::fixed_size::array_eval::irradiance(&self.b),
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
                self.rotated_by(
                    &$crate::sh::fixed_size::rotation_l2::ShRotationL2::from_mat3_to(Self::LMAX, r),
                )
            }

            /// Every channel rotated by the rotation `d -> q d q*`.
            #[must_use]
            pub fn rotated_quat(&self, q: T::Quat) -> Self {
                self.rotated_by(
                    &$crate::sh::fixed_size::rotation_l2::ShRotationL2::from_quat_to(Self::LMAX, q),
                )
            }

            /// Every channel rotated by prepared blocks.
            #[inline]
            #[must_use]
            pub fn rotated_by(
                &self,
                rot: &$crate::sh::fixed_size::rotation_l2::ShRotationL2<T>,
            ) -> Self {
                Self {
                    r: $crate::sh::fixed_size::rotation_l2::rotated(&self.r, rot),
                    g: $crate::sh::fixed_size::rotation_l2::rotated(&self.g, rot),
                    b: $crate::sh::fixed_size::rotation_l2::rotated(&self.b, rot),
                }
            }

            /// From an RGB expansion of any lmax: truncated if longer,
            /// zero-padded if shorter (the rule of [`crate::sh::ShCoeffs::resized`]).
            #[must_use]
            pub fn from_coeffs(sh: &$crate::sh::sh_coeffs::ShCoeffs<T::Vec3>) -> Self {
                let s = sh.as_slice();
                Self {
                    r: $crate::sh::fixed_size::array_eval::take(s, 0),
                    g: $crate::sh::fixed_size::array_eval::take(s, 1),
                    b: $crate::sh::fixed_size::array_eval::take(s, 2),
                }
            }

            /// The same coefficients as an RGB [`crate::sh::ShCoeffs`] of lmax `LMAX`.
            #[must_use]
            pub fn to_coeffs(&self) -> $crate::sh::sh_coeffs::ShCoeffs<T::Vec3> {
                $crate::sh::sh_coeffs::ShCoeffs::from_fn(Self::LMAX, |l, m| {
                    let i = $crate::sh::index::sh_index(l, m);
                    T::vec3_from_array([self.r[i], self.g[i], self.b[i]])
                })
            }
        }

        impl<T: $crate::sh::glam_real::GlamReal> From<$rgb<T>>
            for $crate::sh::sh_coeffs::ShCoeffs<T::Vec3>
        {
            /// The same coefficients as an RGB expansion of lmax `LMAX` (lossless).
            fn from(sh: $rgb<T>) -> Self {
                sh.to_coeffs()
            }
        }

        $crate::sh::fixed_size::impl_macros::impl_fixed_arith!($sc, coeffs);
        $crate::sh::fixed_size::impl_macros::impl_fixed_arith!($rgb, r, g, b);
    };
}
pub(crate) use impl_fixed_sh;

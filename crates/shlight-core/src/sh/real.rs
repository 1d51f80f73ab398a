//! The floating-point scalars the basis is evaluated in (`f32`, `f64`), and
//! their directions (`Real::Vec3`) to and from `DVec3`.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use glam::DVec3;

/// A real scalar type in which SH can be evaluated: implemented for `f32` and `f64`.
///
/// Besides arithmetic it carries the two constants of the extended-exponent
/// Legendre recurrence ([`Real::BIG`], [`Real::SMALL`]): values that would
/// underflow are kept as `mantissa * SMALL^k` with an integer `k`, which is
/// what keeps `f64` evaluation accurate far past lmax 1000
/// ([`crate::sh::Legendre`]).
pub trait Real:
    Copy
    + PartialOrd
    + Default
    + Debug
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// The rescaling factor of the extended-exponent recurrence:
    /// `2^600` for `f64`, `2^60` for `f32`.
    const BIG: Self;
    /// `1 / BIG`.
    const SMALL: Self;
    /// Machine epsilon, the gap between 1 and the next value: `2^-52` for
    /// `f64`, `2^-23` for `f32` (twice the unit roundoff).
    const EPSILON: Self;
    /// The glam vector of three of these: `glam::Vec3` for `f32`,
    /// `glam::DVec3` for `f64`, the type of directions in the public API.
    type Vec3: Copy + Debug + PartialEq + Send + Sync + From<[Self; 3]> + Into<[Self; 3]>;
    /// Converts from `f64` (rounding for `f32`).
    fn from_f64(x: f64) -> Self;
    /// Converts to `f64` (exact).
    fn to_f64(self) -> f64;
    /// Square root.
    #[must_use]
    fn sqrt(self) -> Self;
    /// Absolute value.
    #[must_use]
    fn abs(self) -> Self;
}

macro_rules! impl_real {
    ($t:ty, $v:ty, $big:expr, $small:expr) => {
        impl Real for $t {
            type Vec3 = $v;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const BIG: Self = $big;
            const SMALL: Self = $small;
            const EPSILON: Self = <$t>::EPSILON;
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
        }
    };
}

// 2^600 and 2^-600; 2^60 and 2^-60.
impl_real!(
    f64,
    glam::DVec3,
    f64::from_bits(((1023 + 600) as u64) << 52),
    f64::from_bits(((1023 - 600) as u64) << 52)
);
impl_real!(
    f32,
    glam::Vec3,
    f32::from_bits(((127 + 60) as u32) << 23),
    f32::from_bits(((127 - 60) as u32) << 23)
);

/// A direction of the public API (`Vec3` or `DVec3`) as `DVec3`.
pub(crate) fn dir_f64<R: Real>(d: R::Vec3) -> DVec3 {
    let a: [R; 3] = d.into();
    DVec3::new(a[0].to_f64(), a[1].to_f64(), a[2].to_f64())
}

/// `d` as a direction of the public API (`Vec3` or `DVec3`), each
/// component rounded once for `f32`; the inverse of [`dir_f64`].
pub(crate) fn dir_from_f64<R: Real>(d: DVec3) -> R::Vec3 {
    R::Vec3::from(d.to_array().map(R::from_f64))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_constants_are_exact_powers_of_two() {
        assert_eq!(<f64 as Real>::BIG, 2f64.powi(600));
        assert_eq!(<f64 as Real>::SMALL, 2f64.powi(-600));
        assert_eq!(<f32 as Real>::BIG, 2f32.powi(60));
        assert_eq!(<f32 as Real>::SMALL, 2f32.powi(-60));
        assert_eq!(<f64 as Real>::EPSILON, 2f64.powi(-52));
        assert_eq!(<f32 as Real>::EPSILON, 2f32.powi(-23));
    }
}

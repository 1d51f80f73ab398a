//! What a coefficient can be: a scalar (`f32`, `f64`) or linear RGB (`Vec3`, `DVec3`).

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Neg, Sub};
use glam::{DVec3, Vec3};

use crate::sh::real::Real;

/// A coefficient value: one channel (`f32`, `f64`) or three linear RGB
/// channels (`glam::Vec3`, `glam::DVec3`). Arithmetic is per channel.
pub trait ShValue:
    Copy
    + Default
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + AddAssign
    + Neg<Output = Self>
{
    /// The scalar type of each channel.
    type Scalar: Real;
    /// Number of channels (1 or 3).
    const CHANNELS: usize;
    /// All channels zero.
    const ZERO: Self;
    /// Every channel multiplied by `s`.
    #[must_use]
    fn scale(self, s: Self::Scalar) -> Self;
    /// Per-channel product.
    #[must_use]
    fn mul_elem(self, other: Self) -> Self;
    /// Every channel set to `s`.
    #[must_use]
    fn splat(s: Self::Scalar) -> Self;
    /// Channel `c` (`c < CHANNELS`).
    #[must_use]
    fn channel(self, c: usize) -> Self::Scalar;
    /// Sets channel `c`.
    fn set_channel(&mut self, c: usize, v: Self::Scalar);
}

macro_rules! impl_scalar_value {
    ($t:ty) => {
        impl ShValue for $t {
            type Scalar = $t;
            const CHANNELS: usize = 1;
            const ZERO: Self = 0.0;
            #[inline(always)]
            fn scale(self, s: $t) -> Self {
                self * s
            }
            #[inline(always)]
            fn mul_elem(self, other: Self) -> Self {
                self * other
            }
            #[inline(always)]
            fn splat(s: $t) -> Self {
                s
            }
            #[inline(always)]
            fn channel(self, _c: usize) -> $t {
                self
            }
            #[inline(always)]
            fn set_channel(&mut self, _c: usize, v: $t) {
                *self = v;
            }
        }
    };
}
impl_scalar_value!(f32);
impl_scalar_value!(f64);

macro_rules! impl_rgb_value {
    ($t:ty, $s:ty) => {
        impl ShValue for $t {
            type Scalar = $s;
            const CHANNELS: usize = 3;
            const ZERO: Self = <$t>::ZERO;
            #[inline(always)]
            fn scale(self, s: $s) -> Self {
                self * s
            }
            #[inline(always)]
            fn mul_elem(self, other: Self) -> Self {
                self * other
            }
            #[inline(always)]
            fn splat(s: $s) -> Self {
                <$t>::splat(s)
            }
            #[inline(always)]
            fn channel(self, c: usize) -> $s {
                self[c]
            }
            #[inline(always)]
            fn set_channel(&mut self, c: usize, v: $s) {
                self[c] = v;
            }
        }
    };
}
impl_rgb_value!(Vec3, f32);
impl_rgb_value!(DVec3, f64);

//! [`ShL2`] and [`ShL2Rgb`]: SH to lmax 2 (9 coefficients) as small `Copy`
//! values, scalar and RGB (like Unity's `SphericalHarmonicsL2`), for the
//! runtime hot path of engines.

use crate::sh::fixed_size::impl_macros::impl_fixed_sh;
use crate::sh::fixed_size::sh_l1::{ShL1, ShL1Rgb};
use crate::sh::glam_real::GlamReal;

/// A scalar function on the sphere expanded to lmax 2: 9 coefficients in a
/// fixed-size `Copy` value, in `f32` or `f64`.
///
/// # Basis
///
/// `f(d) = sum_i f_i Y_i(d)` at a unit direction `d = (x, y, z)`, index
/// `i = l*(l+1) + m`, in shlight's real orthonormal basis, **Condon-Shortley
/// phase included** (as [`crate::sh::ShCoeffs`]):
///
/// ```text
/// i = 0:  Y_0^0  =  1 / (2 sqrt(pi))            =  0.282095
/// i = 1:  Y_1^-1 = -sqrt(3/(4 pi)) y            = -0.488603 y
/// i = 2:  Y_1^0  =  sqrt(3/(4 pi)) z            =  0.488603 z
/// i = 3:  Y_1^1  = -sqrt(3/(4 pi)) x            = -0.488603 x
/// i = 4:  Y_2^-2 =  sqrt(15/pi)/2 x y           =  1.092548 x y
/// i = 5:  Y_2^-1 = -sqrt(15/pi)/2 y z           = -1.092548 y z
/// i = 6:  Y_2^0  =  sqrt(5/pi)/4 (3 z^2 - 1)    =  0.315392 (3 z^2 - 1)
/// i = 7:  Y_2^1  = -sqrt(15/pi)/2 x z           = -1.092548 x z
/// i = 8:  Y_2^2  =  sqrt(15/pi)/4 (x^2 - y^2)   =  0.546274 (x^2 - y^2)
/// ```
///
/// The constants are computed from these formulas (the crate's hard-coded low-degree basis),
/// not typed as decimals. Tables without the phase (Ramamoorthi-Hanrahan,
/// three.js) have the opposite sign on the odd-`m` coefficients 1, 3, 5, 7.
///
/// # Irradiance and rotation
///
/// Radiance `L` held here gives the 9-term irradiance
/// `E(n) = sum_{l <= 2} A_l sum_m L_l^m Y_l^m(n)`, `A = (pi, 2 pi / 3, pi / 4)`
/// (Ramamoorthi & Hanrahan 2001), the truncation of
/// `int L(w) max(n . w, 0) dw` (within 9% of it for any non-negative `L`):
/// [`ShL2::irradiance`] converts to irradiance coefficients,
/// [`ShL2::eval_irradiance`] evaluates directly. [`ShL2::rotated`] turns
/// `f(d)` into `f(R^T d)` (a light from `a` comes from `R a`) with the 3x3
/// block on degree 1 and the 5x5 block on degree 2, derived from the
/// quadratic forms of the degree-2 functions ([`crate::sh::ShRotationL2`]).
///
/// Arithmetic (`+`, `-`, `* s`, [`ShL2::lerp`]) is per coefficient.
/// [`ShL2::from_coeffs`] truncates a longer [`crate::sh::ShCoeffs`] and
/// zero-pads a shorter one; `From<ShL1>` zero-pads.
///
/// ```
/// use glam::DVec3;
/// use shlight_core::sh::ShL2;
/// // A directional light from +Z of unit irradiance, kept to lmax 2:
/// let light = ShL2::<f64>::basis(DVec3::Z);
/// // Ramamoorthi-Hanrahan's 9-term irradiance: 17/16 facing it, 3/32 at 90 degrees.
/// assert!((light.eval_irradiance(DVec3::Z) - 17.0 / 16.0).abs() < 1e-15);
/// assert!((light.eval_irradiance(DVec3::Y) - 3.0 / 32.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShL2<T> {
    /// `f_i`, flat index `i = l*(l+1) + m`: `f_0^0, f_1^-1, f_1^0, f_1^1, f_2^-2, ..., f_2^2`.
    pub coeffs: [T; 9],
}

/// Linear RGB on the sphere expanded to lmax 2 (27 numbers, like Unity's
/// `SphericalHarmonicsL2`), stored channel by channel (planar), so
/// evaluation computes the 9 basis values once and takes three dot products.
///
/// The basis, irradiance and rotation are those of [`ShL2`], per channel;
/// directions are `glam::Vec3` / `DVec3` and colours come back as the same
/// vector type (red, green, blue in `x`, `y`, `z`). Conversions go to and
/// from [`crate::sh::ShCoeffs`]`<Vec3>` / `<DVec3>` (truncating or zero-padding).
/// The coefficients are shlight's (Condon-Shortley phase included, no
/// basis constants folded in), not Unity's shader-ready form.
///
/// ```
/// use glam::{Mat3, Vec3};
/// use shlight_core::sh::{ShL2, ShL2Rgb};
/// // A white light from +X, turned a quarter about +Z, now lights +Y.
/// let light = ShL2Rgb::from_scalar(&ShL2::<f32>::basis(Vec3::X), Vec3::ONE);
/// let turned = light.rotated(Mat3::from_rotation_z(std::f32::consts::FRAC_PI_2));
/// let e = turned.eval_irradiance(Vec3::Y);
/// assert!((e - Vec3::splat(17.0 / 16.0)).abs().max_element() < 1e-5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShL2Rgb<T> {
    /// Red coefficients, flat index `l*(l+1) + m`.
    pub r: [T; 9],
    /// Green coefficients.
    pub g: [T; 9],
    /// Blue coefficients.
    pub b: [T; 9],
}

impl_fixed_sh!(ShL2, ShL2Rgb, 9);

/// Zero-padded `[f_0 .. f_3, 0, 0, 0, 0, 0]`.
fn pad<T: GlamReal>(c: &[T; 4]) -> [T; 9] {
    core::array::from_fn(|i| {
        if i < 4 {
            c[i]
        } else {
            <T as crate::sh::real::Real>::ZERO
        }
    })
}

fn cut<T: GlamReal>(c: &[T; 9]) -> [T; 4] {
    core::array::from_fn(|i| c[i])
}

impl<T: GlamReal> ShL2<T> {
    /// Truncated to lmax 1 (degree 2 dropped).
    #[must_use]
    pub fn to_l1(&self) -> ShL1<T> {
        ShL1::new(cut(&self.coeffs))
    }
}

impl<T: GlamReal> ShL2Rgb<T> {
    /// Truncated to lmax 1 (degree 2 dropped).
    #[must_use]
    pub fn to_l1(&self) -> ShL1Rgb<T> {
        ShL1Rgb::new(cut(&self.r), cut(&self.g), cut(&self.b))
    }
}

impl<T: GlamReal> From<ShL1<T>> for ShL2<T> {
    /// Zero-padded: degree 2 is zero.
    fn from(f: ShL1<T>) -> Self {
        Self::new(pad(&f.coeffs))
    }
}

impl<T: GlamReal> From<ShL1Rgb<T>> for ShL2Rgb<T> {
    /// Zero-padded: degree 2 is zero.
    fn from(f: ShL1Rgb<T>) -> Self {
        Self::new(pad(&f.r), pad(&f.g), pad(&f.b))
    }
}

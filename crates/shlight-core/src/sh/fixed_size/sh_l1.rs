//! [`ShL1`] and [`ShL1Rgb`]: SH to lmax 1 (4 coefficients) as small `Copy`
//! values, scalar and RGB, for the runtime hot path of engines.

use crate::sh::fixed_size::impl_macros::impl_fixed_sh;

/// A scalar function on the sphere expanded to lmax 1: 4 coefficients in a
/// fixed-size `Copy` value (an ambient probe's one channel, a visibility
/// term), in `f32` or `f64`.
///
/// # Basis
///
/// `f(d) = sum_i f_i Y_i(d)` at a unit direction `d = (x, y, z)`, index
/// `i = l*(l+1) + m`, in shlight's real orthonormal basis, **Condon-Shortley
/// phase included** (as [`crate::sh::ShCoeffs`]):
///
/// ```text
/// i = 0:  Y_0^0  =  1 / (2 sqrt(pi))   =  0.282095
/// i = 1:  Y_1^-1 = -sqrt(3/(4 pi)) y   = -0.488603 y
/// i = 2:  Y_1^0  =  sqrt(3/(4 pi)) z   =  0.488603 z
/// i = 3:  Y_1^1  = -sqrt(3/(4 pi)) x   = -0.488603 x
/// ```
///
/// The constants are computed from these formulas (the crate's hard-coded low-degree basis),
/// not typed as decimals. Tables without the phase (Ramamoorthi-Hanrahan,
/// three.js) have the opposite sign on `f_1` and `f_3`.
///
/// # Irradiance and rotation
///
/// Radiance `L` held here gives irradiance `E(n) = int L(w) max(n . w, 0) dw`
/// truncated to `E(n) = A_0 L_0 Y_0 + A_1 sum_m L_1^m Y_1^m(n)`, `A_0 = pi`,
/// `A_1 = 2 pi / 3` (Ramamoorthi & Hanrahan 2001): [`ShL1::irradiance`]
/// converts to irradiance coefficients, [`ShL1::eval_irradiance`] evaluates
/// directly. [`ShL1::rotated`] turns `f(d)` into `f(R^T d)` (a light from
/// `a` comes from `R a`) with the 3x3 block `M^1 = P R P^T` on degree 1
/// ([`crate::sh::ShRotationL2`]).
///
/// Arithmetic (`+`, `-`, `* s`, [`ShL1::lerp`]) is per coefficient: the SH
/// of sums, differences and blends of functions. [`ShL1::from_coeffs`]
/// truncates a longer [`crate::sh::ShCoeffs`] and zero-pads a shorter one.
///
/// ```
/// use glam::DVec3;
/// use shlight_core::sh::ShL1;
/// // A directional light from +Z of unit irradiance, kept to lmax 1:
/// let light = ShL1::<f64>::basis(DVec3::Z);
/// // Its truncated irradiance is 1/4 + cos(t)/2 (3/4 facing the light).
/// assert!((light.eval_irradiance(DVec3::Z) - 0.75).abs() < 1e-15);
/// assert!((light.eval_irradiance(DVec3::X) - 0.25).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShL1<T> {
    /// `f_i`, flat index `i = l*(l+1) + m`: `[f_0^0, f_1^-1, f_1^0, f_1^1]`.
    pub coeffs: [T; 4],
}

/// Linear RGB on the sphere expanded to lmax 1: three channels of 4
/// coefficients, stored channel by channel (planar), so evaluation computes
/// the 4 basis values once and takes three dot products.
///
/// The basis, irradiance and rotation are those of [`ShL1`], per channel;
/// directions are `glam::Vec3` / `DVec3` and colours come back as the same
/// vector type (red, green, blue in `x`, `y`, `z`). Conversions go to and
/// from [`crate::sh::ShCoeffs`]`<Vec3>` / `<DVec3>` (truncating or zero-padding).
///
/// ```
/// use glam::Vec3;
/// use shlight_core::sh::{ShL1, ShL1Rgb};
/// // A reddish light from +X.
/// let sky = ShL1Rgb::from_scalar(&ShL1::<f32>::basis(Vec3::X), Vec3::new(1.0, 0.5, 0.25));
/// let e = sky.eval_irradiance(Vec3::X);
/// assert!((e - Vec3::new(0.75, 0.375, 0.1875)).abs().max_element() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShL1Rgb<T> {
    /// Red coefficients, flat index `l*(l+1) + m`.
    pub r: [T; 4],
    /// Green coefficients.
    pub g: [T; 4],
    /// Blue coefficients.
    pub b: [T; 4],
}

impl_fixed_sh!(ShL1, ShL1Rgb, 4);

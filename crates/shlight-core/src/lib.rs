//! Real spherical harmonics for lighting: the core of shlight.
//!
//! One job: the mathematics of SH lighting, with no I/O, image or GPU
//! dependency (only `glam`, `rand`, and `rayon` behind the default feature),
//! so it cannot fail for I/O reasons and builds anywhere. Image files, PRT
//! baking, the GPU renderer and the command line sit on top of it.
//!
//! # Main types
//! - [`ShBasis`]: evaluates every `Y_l^m`, `l <= lmax`, at unit directions,
//!   one at a time or in vectorised batches (any lmax; stable past 2800).
//! - [`ShCoeffs`]: an expansion of scalars or linear RGB (`glam::Vec3`,
//!   `DVec3`) with arithmetic, evaluation, band power and phase conversion.
//! - [`ZonalKernel`] and [`irradiance`]: Funk-Hecke convolution, the
//!   clamped-cosine `A_l` for every `l`, normalised Phong lobes.
//! - [`ShRotation`]: block-diagonal rotation matrices for any lmax, built
//!   once and applied many times; [`rotation::Frame`] switches y-up / z-up.
//! - [`ShL1`], [`ShL2`] (scalar) and [`ShL1Rgb`], [`ShL2Rgb`] (RGB, stored
//!   channel-planar, like Unity's `SphericalHarmonicsL2`): fixed-size `Copy`
//!   expansions to lmax 1 and 2 for the runtime hot path, in `f32` or `f64`
//!   ([`GlamReal`] pairs each with glam's `Vec3`/`Mat3`/`Quat`). Radiance at
//!   a glam direction, irradiance `E_l^m = A_l L_l^m` as coefficients or
//!   directly, rotation by a matrix or quaternion ([`ShRotationL2`]: the
//!   3x3 and 5x5 blocks), `+ - *` and `lerp`, and conversion to and from
//!   [`ShCoeffs`] (truncating a longer expansion, zero-padding a shorter one).
//! - [`Window`] and [`auto_window()`]: ringing suppression, and the weakest
//!   window that makes a function or its irradiance non-negative;
//!   [`sphere_minimum()`]: the global minimum of an expansion.
//! - [`layout`] and [`equirect`]: the geometry of environment maps of every
//!   layout (equirect, cube cross, strip, angular map, mirror ball): texel
//!   directions, exact texel solid angles, lookups; [`TexelGrid`]: the same
//!   without pixels, for drawing maps; [`MapOrientation`]: how a map's
//!   frame meets world directions.
//! - Drawing lights into maps: [`texel_means()`] (each texel a function's
//!   mean over equal-area points of it in equirect, its centre elsewhere),
//!   [`AnalyticLight`] (constant, cap, gradient: radiance and closed-form
//!   coefficients) and [`directional_texels()`] (a delta as one texel, or a
//!   cap of exact power).
//! - [`projection`]: environment maps to SH by exact texel-solid-angle
//!   quadrature, one entry point ([`projection::project`]) over any
//!   [`TexelSource`] (a contiguous image, a [`StridedImage`], six
//!   [`CubeFaces`], a user's own type); equirect maps by a fast ring
//!   transform (FFT rows, vectorised Legendre sums) to any lmax.
//! - [`montecarlo`]: the Monte Carlo estimator (uniform, stratified, Sobol,
//!   luminance importance sampling) with standard errors.
//! - [`irradiance_map`]: brute-force irradiance of a map (every texel,
//!   cosine-weighted), the ground truth for SH irradiance.
//! - Encodings beyond plain SH, each against the exact irradiance:
//!   [`dominant_lights`] (bright compact sources taken out as [`CapLight`]s
//!   with Snyder's exact irradiance, the rest left as SH) and
//!   [`sloan_light`] (Sloan 2008's light from coefficients alone),
//!   [`zh3`] (Roughton et al. 2024, stored and hallucinated),
//!   [`l1_nonlinear`] (the Geomerics reconstruction), [`ambient_cube`]
//!   (Valve 2006, Bevy's irradiance volumes).
//! - [`analytic`]: closed-form projections of lights (directional, cosine
//!   lobe, cap, constant, linear gradient), the test oracles.
//!
//! # Conventions
//! Stated once here and in `docs/conventions.md`; everything else links here.
//!
//! - **Basis**: real orthonormal SH, `int Y_i Y_j = delta_ij` over the unit
//!   sphere, **Condon-Shortley phase included** (as Green 2003, Sloan 2008,
//!   google/spherical-harmonics, Filament, pbrt):
//!   `Y_1^-1 = -sqrt(3/4pi) y`, `Y_1^0 = sqrt(3/4pi) z`, `Y_1^1 = -sqrt(3/4pi) x`.
//!   Tools without the phase (three.js, the Ramamoorthi-Hanrahan tables)
//!   differ in the sign of every odd-`|m|` coefficient
//!   ([`ShCoeffs::toggled_cs_phase`]).
//! - **Index**: flat `i = l*(l+1) + m` ([`sh_index`]); an expansion to
//!   degree `lmax` holds `(lmax+1)^2` coefficients. shlight always says
//!   `lmax` (the highest degree): "lmax 2" is 9 coefficients, what others
//!   call 3 bands or order 3.
//! - **Axes**: SH are functions of the world direction `(x, y, z)`; the
//!   basis's polar axis is `+z` (`theta` from `+z`, `phi` from `+x` toward
//!   `+y`). How an image maps to world directions (y-up or z-up) is the
//!   I/O layer's business and is stated in `docs/conventions.md`.
//! - **Quantities**: radiance `L` (W sr^-1 m^-2 or any linear unit) and
//!   irradiance `E(n) = int L(w) max(n.w, 0) dw = sum A_l L_l^m Y_l^m(n)`;
//!   exit radiance of a Lambertian surface is `albedo / pi * E`.
//! - **Precision**: accumulate in `f64`; `f32` paths exist for speed.
//!
//! # Example
//! ```
//! use shlight_core::sh::{ShCoeffs, closed_form, irradiance};
//! // A directional light from +Z of unit irradiance, kept to lmax 2:
//! let light: ShCoeffs<f64> = closed_form::directional(2, glam::DVec3::new(0.0, 0.0, 1.0), 1.0);
//! let e = irradiance(&light);
//! // Ramamoorthi-Hanrahan's 9-term irradiance facing the light is 17/16.
//! assert!((e.eval(glam::DVec3::new(0.0, 0.0, 1.0)) - 17.0 / 16.0).abs() < 1e-14);
//! ```
//!
//! # References
//! 1. R. Green, *Spherical Harmonic Lighting: The Gritty Details*, 2003 —
//!    basis and phase ([`basis`]).
//! 2. P.-P. Sloan, *Stupid Spherical Harmonics (SH) Tricks*, 2008 —
//!    trig-free recurrences ([`basis`]), windows ([`window`]).
//! 3. R. Ramamoorthi, P. Hanrahan, *An Efficient Representation for
//!    Irradiance Environment Maps*, SIGGRAPH 2001 — `A_l` ([`zonal`]).
//! 4. J. Ivanic, K. Ruedenberg, *Rotation Matrices for Real Spherical
//!    Harmonics*, J. Phys. Chem. 1996, and the 1998 erratum ([`rotation`]).
//! 5. S. A. Holmes, W. E. Featherstone 2002; N. Schaeffer (SHTns) 2013 —
//!    normalised recurrences with an extended exponent ([`legendre`]).

#![deny(missing_docs)]

pub mod encoding;
pub mod map;
pub mod sh;

mod cpu_features;
#[cfg(test)]
mod test_util;

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

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
//! - [`Window`] and [`window::auto_window`]: ringing suppression, and the
//!   weakest window that makes a function or its irradiance non-negative.
//! - [`projection`] and [`layout`]: environment maps of every layout
//!   (equirect, cube cross, strip, angular map, mirror ball) to SH by exact
//!   texel-solid-angle quadrature; equirect maps by a fast ring transform
//!   (FFT rows, vectorised Legendre sums) to any lmax.
//! - [`montecarlo`]: the Monte Carlo estimator (uniform, stratified, Sobol,
//!   luminance importance sampling) with standard errors.
//! - [`irradiance_map`]: brute-force irradiance of a map (every texel,
//!   cosine-weighted), the ground truth for SH irradiance.
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
//! use shlight_core::{ShCoeffs, analytic, irradiance};
//! // A directional light from +Z of unit irradiance, kept to lmax 2:
//! let light: ShCoeffs<f64> = analytic::directional(2, [0.0, 0.0, 1.0], 1.0);
//! let e = irradiance(&light);
//! // Ramamoorthi-Hanrahan's 9-term irradiance facing the light is 17/16.
//! assert!((e.eval([0.0, 0.0, 1.0]) - 17.0 / 16.0).abs() < 1e-14);
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

pub mod analytic;
pub mod basis;
pub mod channel_windows;
pub mod coeffs;
mod cpu_features;
pub mod hardcoded;
pub mod index;
pub mod irradiance_map;
pub mod layout;
pub mod legendre;
pub mod montecarlo;
pub mod projection;
pub mod quadrature;
pub mod quarter_turn;
mod real;
mod ring_transform;
pub mod rotation;
pub mod std_error_rotation;
mod value;
pub mod window;
pub mod zonal;

pub use basis::{ShBasis, sh_eval};
pub use coeffs::ShCoeffs;
pub use index::{lm_from_index, lmax_from_count, sh_count, sh_index};
pub use real::Real;
pub use rotation::ShRotation;
pub use value::ShValue;
pub use window::Window;
pub use zonal::{ZonalKernel, irradiance};

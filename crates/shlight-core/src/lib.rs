//! Real spherical harmonics for lighting: the core of shlight.
//!
//! One job: the mathematics of SH lighting, with no I/O, image or GPU
//! dependency (only `glam`, `rand`, `realfft`, and `rayon` behind the
//! default feature), so it cannot fail for I/O reasons and builds anywhere.
//! Image files, PRT baking, the GPU renderer and the command line sit on top
//! of it.
//!
//! # Wings
//!
//! Three modules, each with the maths it rests on and its references in its
//! own documentation; they depend one way, [`encoding`] on [`map`] on
//! [`sh`], and every public item has exactly one path.
//!
//! - [`sh`]: the basis and everything done on coefficients.
//!   [`sh::ShBasis`] evaluates every `Y_l^m`, `l <= lmax`, at unit
//!   directions, one at a time or in vectorised batches (any lmax; stable
//!   past 2800); [`sh::ShCoeffs`] holds an expansion of scalars or linear
//!   RGB (`glam::Vec3`, `DVec3`) with arithmetic, evaluation, band power and
//!   phase conversion; [`sh::ZonalKernel`] and [`sh::irradiance`] convolve
//!   (Funk-Hecke, the clamped-cosine `A_l` for every `l`, Phong lobes);
//!   [`sh::ShRotation`] rotates to any lmax and [`sh::Frame`] names the
//!   y-up and z-up frames; [`sh::Window`] and [`sh::auto_window()`] damp
//!   ringing, the latter with the weakest window that keeps a function or
//!   its irradiance non-negative; [`sh::closed_form`] holds the exact
//!   coefficients of simple lights (directional, cosine lobe, cap, constant,
//!   linear gradient); [`sh::ShL1`], [`sh::ShL2`], [`sh::ShL1Rgb`],
//!   [`sh::ShL2Rgb`] are fixed-size `Copy` expansions for engines' hot path.
//! - [`map`]: environment maps. [`map::Layout`], [`map::EnvMap`] and
//!   [`map::TexelGrid`] give the geometry of every layout (equirect, cube
//!   crosses and strip, angular map, mirror ball: texel directions, exact
//!   solid angles, lookups), read in a [`map::MapOrientation`];
//!   [`map::project`] projects any [`map::TexelSource`] (a contiguous map,
//!   a [`map::StridedImage`], six [`map::CubeFaces`], a type of the
//!   caller's) to SH, equirect maps by a fast ring transform to any lmax;
//!   [`map::montecarlo`] is the Monte Carlo estimator with standard errors;
//!   [`map::texel_means()`], [`map::AnalyticLight`] and
//!   [`map::directional_texels()`] draw lights into maps;
//!   [`map::irradiance_brute_force`] is a map's exact irradiance, the
//!   ground truth for SH irradiance; [`map::render_coefficients`] renders
//!   an expansion back into a map, and [`map::render_lobe`] draws a scalar
//!   one as its lobe ([`map::LobeSurface`], [`map::LobeCamera`]).
//! - [`encoding`]: encodings beyond plain SH, each against the exact
//!   irradiance. [`encoding::Encoding`] names them and
//!   [`encoding::encode_map`] builds one; [`encoding::DominantLights`]
//!   takes bright compact sources out as [`encoding::CapLight`]s with
//!   Snyder's exact irradiance, the rest left as SH;
//!   [`encoding::sloan_directional`] finds Sloan's light from coefficients
//!   alone; [`encoding::Zh3`] (stored and hallucinated),
//!   [`encoding::L1NonLinear`] (the Geomerics reconstruction) and
//!   [`encoding::AmbientCube`] (Valve's, as Bevy's irradiance volumes store
//!   it).
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
//!   ([`sh::ShCoeffs::toggled_cs_phase`]).
//! - **Index**: flat `i = l*(l+1) + m` ([`sh::sh_index`]); an expansion to
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
//! Each wing lists the sources of its maths: [`sh`] the basis, its phase,
//! `A_l`, the rotation recurrence and the extended-exponent Legendre
//! recurrences; [`map`] the solid angles and the ring transform; [`encoding`]
//! the papers of each encoding.

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

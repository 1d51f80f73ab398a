//! How close shlight's irradiance is to the truth, with numbers and
//! pictures.
//!
//! One job: measure the error of SH irradiance (projection, then
//! `E_l^m = A_l L_l^m`) against analytic lights whose irradiance is known in
//! closed form, separating the truncation error at `lmax` from the
//! projection error, and draw it. The `shlight accuracy` command and the
//! accuracy tests run the same [`suite`].
//!
//! # Main items
//! - [`oracle::Oracle`]: uniform sphere, hemisphere, spherical caps,
//!   polygons (Lambert's formula, clipped to the horizon), a directional
//!   light and a sky gradient, each with its radiance, exact irradiance,
//!   and SH irradiance truncated at any `lmax`.
//! - [`suite::run`]: every oracle by truncation, equirect and cube-cross
//!   quadrature at several resolutions, and Monte Carlo with each sampler
//!   at several sample counts, as [`suite::Row`]s with bounds and fitted
//!   convergence rates; [`report_table::report_table`] prints them.
//! - [`compare`]: every encoding of a map (dominant lights + SH, ZH3,
//!   non-linear L1, the ambient cube, plain SH) against its exact
//!   irradiance: a table, JSON and a plot of error against floats stored.
//! - [`map_irradiance`]: a map's brute-force irradiance on a grid of
//!   normals and an encoding's pointwise and peak-relative errors against
//!   it (`shlight irradiance`).
//! - [`error`]: the relative error (to the peak irradiance, as Ramamoorthi
//!   & Hanrahan 2001) and log-log slopes.
//! - [`legendre_study`]: Legendre polynomials by Rodrigues' formula
//!   against the recurrence, to lmax 2800 (`shlight accuracy --legendre`).
//! - [`plot`]: error-vs-samples and error-vs-lmax plots (SVG) and error
//!   maps over the sphere (equirect PNG with a colour scale).
//!
//! The oracles are written independently of the code they check: closed
//! forms from `sh-reference.md` §4, Legendre series of their own, and tests
//! that check the core's zonal coefficients they use against numerical
//! integration.
//!
//! # Example
//! ```
//! use glam::DVec3;
//! use shlight_accuracy::oracle::{Oracle, Shape};
//! let sun = Oracle::new("sun", Shape::Directional { dir: DVec3::Z }, 1.0);
//! // Ramamoorthi & Hanrahan: the 9-term irradiance is 3/32 at 90 degrees.
//! let e2 = sun.truncated(2).eval(DVec3::X);
//! assert!((e2 - 3.0 / 32.0).abs() < 1e-14);
//! ```
//!
//! **Architecture invariant:** the mathematics under test lives in
//! `shlight-core`; this crate only drives it and compares.

#![deny(missing_docs)]

pub mod compare;
pub mod error;
pub mod lambert;
pub mod legendre_study;
pub mod map_irradiance;
pub mod oracle;
pub mod plot;
pub mod render;
pub mod report_table;
pub mod suite;

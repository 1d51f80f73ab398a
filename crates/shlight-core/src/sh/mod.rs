//! The SH wing: the basis and everything done on coefficients. Evaluation
//! of the basis, the coefficient container, zonal convolution and
//! irradiance, quadrature rules, rotation, windowing, the closed-form
//! coefficients of simple lights, and fixed-size lmax-1 and lmax-2 types for
//! engines. Nothing here knows of images: directions are glam vectors,
//! functions are closures or coefficients. The map and encoding wings build
//! on this one; it uses neither.
//!
//! # The basis
//!
//! Real orthonormal SH with the Condon-Shortley phase (the crate's
//! conventions), flat index `i = l (l+1) + m` ([`sh_index`], [`sh_count`],
//! [`lm_from_index`], [`lmax_from_count`]). At
//! `d = (sin t cos φ, sin t sin φ, cos t)`
//!
//! ```text
//! Y_l^0 = Pbar_l^0(cos t),   Y_l^{±m} = sqrt2 Pbar_l^m(cos t) {cos, sin}(m φ)   (m > 0)
//! ```
//!
//! with `Pbar_l^m` the SH-normalised associated Legendre functions, which
//! [`Legendre`] computes by recurrences on normalised values with an
//! extended exponent, so that nothing underflows near the poles at any
//! degree. [`ShBasis`] evaluates every `Y_l^m` at one direction or a batch
//! of them, without trigonometric calls (the azimuth by a complex
//! recurrence on the unit vector), below lmax 5 by hard-coded Cartesian
//! polynomials; [`sh_eval`] is the one-shot form. Scalars are [`Real`]
//! (`f32`, `f64`), coefficients [`ShValue`]s (a scalar, or linear RGB as
//! `glam::Vec3` / `DVec3`).
//!
//! # Coefficients
//!
//! [`ShCoeffs`]: an expansion to some lmax, with arithmetic, evaluation,
//! band power, resizing, the Condon-Shortley phase toggle, and projection
//! of a function by a product rule ([`ShCoeffs::project_fn`]).
//!
//! # Zonal functions and irradiance
//!
//! A zonal function `h(d · a)` has only `m = 0` coefficients `h_l` about its
//! axis. Turned to axis `a`, `f_l^m = sqrt(4π/(2l+1)) h_l Y_l^m(a)`
//! ([`zonal_to_sh`]), and convolution with it is diagonal (Funk-Hecke):
//!
//! ```text
//! (h * f)_l^m = Λ_l f_l^m,   Λ_l = sqrt(4π/(2l+1)) h_l = 2π ∫_{-1}^{1} h(t) P_l(t) dt
//! ```
//!
//! ([`ZonalKernel`], [`zonal_factor`], [`legendre_polynomials`]). The
//! clamped cosine `max(t, 0)` has `Λ_l = A_l` ([`clamped_cosine_eigenvalue`];
//! `π, 2π/3, π/4, 0, -π/24, ...`), so irradiance is `E_l^m = A_l L_l^m`
//! ([`irradiance`]). [`cap_zonal`] and [`clamped_cosine_zonal`] are the
//! zonal coefficients of a cap's indicator and of the clamped cosine.
//!
//! # Quadrature
//!
//! [`gauss_legendre`] nodes and weights on `[-1, 1]`; [`SphereQuadrature`],
//! Gauss-Legendre in `cos t` times the uniform rule in `φ`, exact for
//! spherical polynomials to a chosen degree; [`fibonacci_sphere`] point
//! sets.
//!
//! # Rotation
//!
//! Rotating `f` by `R` gives `g(d) = f(R^T d)`: a light from `a` then comes
//! from `R a`. On the coefficients it is block diagonal, one orthogonal
//! `(2l+1) x (2l+1)` block `M^l(R)` per degree. [`ShRotation`] builds the
//! blocks to any lmax by the Ivanic-Ruedenberg recurrence, applied on both
//! sides so that rounding does not grow with `l`; [`rotate_once`] applies a
//! rotation without storing them; [`rotate_z`] turns about +Z in
//! `O(lmax²)`; [`quarter_turn_x`] turns a quarter about X from Wigner's
//! `d(π/2)`, the fast way between the y-up and z-up [`Frame`]s in which an
//! equirect map is read; [`rotate_std_error`] carries Monte Carlo standard
//! errors through a rotation. [`ORTHONORMAL_TOLERANCE`] is how far from a
//! rotation a matrix may be.
//!
//! # Windows
//!
//! [`Window`]: per-degree factors `w_l` that damp the ringing of a
//! truncated expansion (Hanning, Lanczos, a Laplacian penalty), each of
//! them a one-parameter [`WindowFamily`]. [`auto_window()`] finds the
//! weakest window of a family that keeps the reconstruction, or its
//! irradiance ([`WindowTarget`]), non-negative on the whole sphere, resting
//! on [`sphere_minimum()`] (a dense search over [`dense_point_count`]
//! points, then Newton steps on the sphere); [`auto_windows`] and
//! [`apply_channel_windows`] do it per colour channel.
//!
//! # Closed-form lights
//!
//! [`closed_form`]: the exact coefficients, to any lmax, of a constant, a
//! directional light (a delta), a cosine lobe, a cap and a linear gradient:
//! the oracles projections are tested against.
//!
//! # Fixed-size lmax 1 and 2
//!
//! [`ShL1`], [`ShL2`] (scalar) and [`ShL1Rgb`], [`ShL2Rgb`] (RGB, stored
//! channel-planar like Unity's `SphericalHarmonicsL2`): `Copy` expansions
//! for engines' hot path, in `f32` or `f64` ([`GlamReal`] pairs each with
//! glam's `Vec3`, `Mat3`, `Quat`). Evaluation is one dot product with the
//! monomials of the direction (the basis constants folded into the
//! coefficients once); irradiance `E_l^m = A_l L_l^m`; rotation by
//! [`ShRotationL2`], whose 3x3 degree-1 block is read off `R` and whose 5x5
//! degree-2 block comes from the quadratic forms `Y_2^m(d) = d^T S_m d`,
//! independently of the Ivanic-Ruedenberg recurrence; `+ - *` and `lerp`;
//! conversion to and from [`ShCoeffs`] truncates or zero-pads.
//!
//! # References
//!
//! 1. R. Green, *Spherical Harmonic Lighting: The Gritty Details*, 2003 —
//!    the basis and its phase.
//! 2. P.-P. Sloan, *Stupid Spherical Harmonics (SH) Tricks*, GDC 2008 —
//!    trigonometry-free recurrences (appendix A1), windows.
//! 3. R. Ramamoorthi, P. Hanrahan, *An Efficient Representation for
//!    Irradiance Environment Maps*, SIGGRAPH 2001 — `A_l`.
//! 4. J. Ivanic, K. Ruedenberg, *Rotation Matrices for Real Spherical
//!    Harmonics. Direct Determination by Recursion*, J. Phys. Chem. 100
//!    (1996) 6342, and the erratum, J. Phys. Chem. A 102 (1998) 9099 —
//!    [`ShRotation`].
//! 5. D. A. Varshalovich, A. N. Moskalev, V. K. Khersonskii, *Quantum Theory
//!    of Angular Momentum*, 1988, 4.4 — Wigner's `d(π/2)` of
//!    [`quarter_turn_x`].
//! 6. S. A. Holmes, W. E. Featherstone, J. Geodesy 76 (2002); N. Schaeffer,
//!    SHTns, G-cubed 14 (2013) — normalised recurrences with an extended
//!    exponent ([`Legendre`]).

pub mod closed_form;

pub(crate) mod auto_window;
pub(crate) mod basis;
pub(crate) mod channel_windows;
pub(crate) mod fixed_size;
pub(crate) mod frame;
pub(crate) mod glam_real;
pub(crate) mod index;
pub(crate) mod legendre;
pub(crate) mod low_degree;
pub(crate) mod quadrature;
pub(crate) mod quarter_turn;
pub(crate) mod real;
pub(crate) mod rotation;
pub(crate) mod sh_coeffs;
pub(crate) mod sh_value;
pub(crate) mod sphere_minimum;
pub(crate) mod std_error_rotation;
pub(crate) mod window;
pub(crate) mod zonal;

pub use auto_window::{AUTO_WINDOW_MARGIN, AutoWindow, AutoWindowError, WindowTarget, auto_window};
pub use basis::{ShBasis, sh_eval};
pub use channel_windows::{apply_channel_windows, auto_windows};
pub use fixed_size::rotation_l2::ShRotationL2;
pub use fixed_size::sh_l1::{ShL1, ShL1Rgb};
pub use fixed_size::sh_l2::{ShL2, ShL2Rgb};
pub use frame::{Frame, ParseFrameError};
pub use glam_real::GlamReal;
pub use index::{lm_from_index, lmax_from_count, sh_count, sh_index};
pub use legendre::{Legendre, legendre_count, legendre_index};
pub use quadrature::{SphereQuadrature, fibonacci_sphere, gauss_legendre};
pub use quarter_turn::quarter_turn_x;
pub use real::Real;
pub use rotation::{ORTHONORMAL_TOLERANCE, ShRotation, rotate_once, rotate_z};
pub use sh_coeffs::ShCoeffs;
pub use sh_value::ShValue;
pub use sphere_minimum::{dense_point_count, sphere_minimum};
pub use std_error_rotation::rotate_std_error;
pub use window::{ParseWindowError, ParseWindowErrorKind, Window, WindowFamily};
pub use zonal::{
    ZonalKernel, cap_zonal, clamped_cosine_eigenvalue, clamped_cosine_zonal, irradiance,
    legendre_polynomials, zonal_factor, zonal_to_sh,
};

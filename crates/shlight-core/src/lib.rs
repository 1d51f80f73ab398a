//! Real spherical harmonics for lighting: the core of shlight.
//!
//! (Crate documentation is completed below.)

pub mod basis;
pub mod coeffs;
pub mod hardcoded;
pub mod index;
pub mod legendre;
pub mod quadrature;
mod real;
mod value;
pub mod zonal;

pub use basis::{ShBasis, sh_eval};
pub use coeffs::ShCoeffs;
pub use index::{lm_from_index, lmax_from_count, sh_count, sh_index};
pub use real::Real;
pub use value::ShValue;
pub use zonal::{ZonalKernel, irradiance};

//! The SH wing (placeholder doc).

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

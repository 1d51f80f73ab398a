//! [`GlamReal`]: a scalar (`f32`, `f64`) together with glam's vector,
//! matrix and quaternion of that precision, so the fixed-size SH types
//! ([`crate::sh::ShL1`], [`crate::sh::ShL2`] and their RGB forms) can take and
//! return glam values while staying generic over the precision.

use core::fmt::Debug;

use glam::{DMat3, DQuat, DVec3, Mat3, Quat, Vec3};

use crate::sh::real::Real;
use crate::sh::sh_value::ShValue;

/// A [`Real`] scalar paired with glam's types of the same precision:
/// `f32` with `Vec3`, `Mat3`, `Quat`; `f64` with `DVec3`, `DMat3`, `DQuat`.
///
/// Directions are `Self::Vec3` (unit length), rotations `Self::Mat3`
/// (column vectors, `d -> R d`) or `Self::Quat` (`d -> q d q*`), and an RGB
/// value is a `Self::Vec3` (red, green, blue in `x`, `y`, `z`).
///
/// The 3-vector is [`Real::Vec3`] (`Vec3`, `DVec3`), also an RGB value.
pub trait GlamReal: Real<Vec3: ShValue<Scalar = Self>> + ShValue<Scalar = Self> {
    /// The 3x3 matrix of this precision (`Mat3`, `DMat3`).
    type Mat3: Copy + Debug + PartialEq;
    /// The quaternion of this precision (`Quat`, `DQuat`).
    type Quat: Copy + Debug + PartialEq;
    /// The vector `(a[0], a[1], a[2])`.
    fn vec3_from_array(a: [Self; 3]) -> Self::Vec3;
    /// The components `[x, y, z]`.
    fn vec3_to_array(v: Self::Vec3) -> [Self; 3];
    /// The entries row by row: `rows[i][j] = R_ij`, so that `(R d)_i = sum_j R_ij d_j`.
    fn mat3_to_rows(m: Self::Mat3) -> [[Self; 3]; 3];
    /// The rotation matrix of `q` after normalising it (`q` and `-q` give
    /// the same matrix). Precondition: `q` is non-zero and finite.
    fn quat_to_mat3(q: Self::Quat) -> Self::Mat3;
}

macro_rules! impl_glam_real {
    ($t:ty, $v:ty, $m:ty, $q:ty) => {
        impl GlamReal for $t {
            type Mat3 = $m;
            type Quat = $q;
            #[inline(always)]
            fn vec3_from_array(a: [$t; 3]) -> $v {
                <$v>::from_array(a)
            }
            #[inline(always)]
            fn vec3_to_array(v: $v) -> [$t; 3] {
                v.to_array()
            }
            #[inline(always)]
            fn mat3_to_rows(m: $m) -> [[$t; 3]; 3] {
                m.transpose().to_cols_array_2d()
            }
            #[inline]
            fn quat_to_mat3(q: $q) -> $m {
                <$m>::from_quat(q.normalize())
            }
        }
    };
}
impl_glam_real!(f32, Vec3, Mat3, Quat);
impl_glam_real!(f64, DVec3, DMat3, DQuat);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_rows_of_the_column_vector_convention() {
        // Rz(90 deg) takes +X to +Y: R_10 = 1, R_01 = -1.
        let r =
            <f64 as GlamReal>::mat3_to_rows(DMat3::from_rotation_z(core::f64::consts::FRAC_PI_2));
        assert!((r[1][0] - 1.0).abs() < 1e-15 && (r[0][1] + 1.0).abs() < 1e-15);
        let q = <f32 as GlamReal>::quat_to_mat3(Quat::from_xyzw(0.0, 0.0, 2.0, 2.0));
        assert!((q * Vec3::X - Vec3::Y).length() < 1e-6);
    }
}

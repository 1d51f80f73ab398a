//! [`ShRotationL2`]: the rotation of SH coefficients to lmax 2 as two small
//! dense blocks (3x3 for degree 1, 5x5 for degree 2), built straight from
//! the rotation matrix for the fixed-size types ([`crate::sh::ShL1`],
//! [`crate::sh::ShL2`] and their RGB forms).

use core::f64::consts::PI;

use crate::sh::glam_real::GlamReal;
use crate::sh::low_degree::{K2_2, K20, K22};
use crate::sh::rotation::ORTHONORMAL_TOLERANCE;

/// The rotation of SH coefficients of degrees 1 and 2 by a rotation `R`:
/// the blocks `M^1(R)` (3x3) and `M^2(R)` (5x5); degree 0 is unchanged.
///
/// Applied to the coefficients of `f` it gives those of `g(d) = f(R^T d)`:
/// a light from `a` comes from `R a` afterwards (the convention of
/// [`crate::sh::ShRotation`]). Build it once and rotate many probes with
/// [`crate::sh::ShL2::rotated_by`] and friends; the blocks are derived
/// below.
///
/// ```
/// use glam::{Mat3, Vec3};
/// use shlight_core::sh::{ShL2, ShRotationL2};
/// // A quarter turn about +Z takes a light at +X to +Y.
/// let rot = ShRotationL2::<f32>::from_mat3(Mat3::from_rotation_z(std::f32::consts::FRAC_PI_2));
/// let at_x = ShL2::<f32>::basis(Vec3::X);
/// let moved = at_x.rotated_by(&rot);
/// let want = ShL2::<f32>::basis(Vec3::Y);
/// assert!(moved.coeffs.iter().zip(&want.coeffs).all(|(a, b)| (a - b).abs() < 1e-6));
/// ```
///
/// # Convention
///
/// As for [`crate::sh::ShRotation`]: rotating the coefficients of `f` by `R`
/// gives those of `g(d) = f(R^T d)`, so a light from `a` comes from `R a`
/// afterwards. The blocks `M^l` are defined by
/// `Y_l^m(R d) = sum_n M^l_{mn} Y_l^n(d)` and act as `g_l^m = sum_n M^l_{mn} f_l^n`.
///
/// # Derivation (independent of the Ivanic-Ruedenberg recurrence)
///
/// Degree 1: `(Y_1^{-1}, Y_1^0, Y_1^1) = sqrt(3/(4 pi)) (-y, z, -x)`, so
/// `M^1_{ij} = s_i s_j R[a_i][a_j]` with axes `a = (y, z, x)` and signs
/// `s = (-1, +1, -1)`.
///
/// Degree 2: on the unit sphere every degree-2 function is a quadratic form
/// `d^T S d` with a traceless symmetric `S`. With `k = sqrt(15/pi)/4`
/// (half of the basis constant `sqrt(15/pi)/2` of `xy`, `yz`, `xz`) and
/// `k_0 = sqrt(5/(16 pi))`:
///
/// ```text
/// Y_2^-2 = d^T S_-2 d,  S_-2 =  k (E_xy + E_yx)
/// Y_2^-1 = d^T S_-1 d,  S_-1 = -k (E_yz + E_zy)
/// Y_2^0  = d^T S_0 d,   S_0  =  k_0 diag(-1, -1, 2)     (3 z^2 - 1 = 2 z^2 - x^2 - y^2)
/// Y_2^1  = d^T S_1 d,   S_1  = -k (E_xz + E_zx)
/// Y_2^2  = d^T S_2 d,   S_2  =  k diag(1, -1, 0)
/// ```
///
/// These five are orthogonal in the Frobenius product and all have
/// `|S_m|_F^2 = 15/(8 pi)`. Then `Y_2^m(R d) = d^T (R^T S_m R) d`, and
/// `R^T S_m R` is again traceless symmetric, so
///
/// ```text
/// M^2_{mn} = <S_n, R^T S_m R>_F / (15/(8 pi)).
/// ```
///
/// The blocks are built in `f64` whatever `T` is, then rounded to `T`.
/// Building costs about 500 multiply-adds; applying costs 9 + 25 per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShRotationL2<T> {
    band1: [[T; 3]; 3],
    band2: [[T; 5]; 5],
}

impl<T: GlamReal> ShRotationL2<T> {
    /// The identity: both blocks are identity matrices.
    #[must_use]
    pub fn identity() -> Self {
        Self {
            band1: core::array::from_fn(|i| core::array::from_fn(|j| identity_entry(i, j))),
            band2: core::array::from_fn(|i| core::array::from_fn(|j| identity_entry(i, j))),
        }
    }

    /// The blocks of the rotation matrix `r` (column vectors, `d -> r d`).
    ///
    /// Precondition: `r` is orthonormal with `det r = +1`, to
    /// [`ORTHONORMAL_TOLERANCE`]; checked by `debug_assert!` only (the
    /// blocks are orthogonal only as far as `r` is). Use
    /// [`ShRotationL2::try_from_mat3`] for matrices of unknown origin.
    #[must_use]
    pub fn from_mat3(r: T::Mat3) -> Self {
        Self::from_mat3_to(2, r)
    }

    /// [`ShRotationL2::from_mat3`], or `None` when `r` is not a rotation:
    /// a non-finite entry, `max |r^T r - I| > ORTHONORMAL_TOLERANCE`, or
    /// `|det r - 1| > ORTHONORMAL_TOLERANCE` (reflections have `det = -1`).
    #[must_use]
    pub fn try_from_mat3(r: T::Mat3) -> Option<Self> {
        let rows = rows_f64::<T>(r);
        is_rotation(&rows).then(|| Self::from_rows_to(2, &rows))
    }

    /// The blocks of the rotation `d -> q d q*`; `q` is normalised first,
    /// so any non-zero finite quaternion is accepted (`q` and `-q` agree).
    #[must_use]
    pub fn from_quat(q: T::Quat) -> Self {
        Self::from_quat_to(2, q)
    }

    /// The degree-1 block, and the degree-2 block only when `lmax >= 2`
    /// (the identity otherwise): what a lmax-1 rotation needs, without the
    /// cost of degree 2. Same precondition as [`ShRotationL2::from_mat3`].
    pub(crate) fn from_mat3_to(lmax: usize, r: T::Mat3) -> Self {
        let rows = rows_f64::<T>(r);
        debug_assert!(
            is_rotation(&rows),
            "rotation of SH: {r:?} is not a rotation (orthonormal, det +1)"
        );
        Self::from_rows_to(lmax, &rows)
    }

    /// [`ShRotationL2::from_quat`] to `lmax` as in [`ShRotationL2::from_mat3_to`].
    pub(crate) fn from_quat_to(lmax: usize, q: T::Quat) -> Self {
        Self::from_rows_to(lmax, &rows_f64::<T>(T::quat_to_mat3(q)))
    }

    fn from_rows_to(lmax: usize, r: &[[f64; 3]; 3]) -> Self {
        let mut out = Self::identity();
        out.band1 = band1_block(r).map(|row| row.map(T::from_f64));
        if lmax >= 2 {
            out.band2 = band2_block(r).map(|row| row.map(T::from_f64));
        }
        out
    }

    /// `M^1`, row-major: `band1()[m + 1][n + 1] = M^1_{mn}`, `m, n = -1..=1`.
    #[must_use]
    pub fn band1(&self) -> &[[T; 3]; 3] {
        &self.band1
    }

    /// `M^2`, row-major: `band2()[m + 2][n + 2] = M^2_{mn}`, `m, n = -2..=2`.
    #[must_use]
    pub fn band2(&self) -> &[[T; 5]; 5] {
        &self.band2
    }

    /// `g_1^m = sum_n M^1_{mn} f_1^n` for the three degree-1 coefficients.
    #[inline]
    #[must_use]
    pub fn apply_band1(&self, f: &[T; 3]) -> [T; 3] {
        self.band1
            .map(|row| crate::sh::fixed_size::array_eval::dot(&row, f))
    }

    /// `g_2^m = sum_n M^2_{mn} f_2^n` for the five degree-2 coefficients.
    #[inline]
    #[must_use]
    pub fn apply_band2(&self, f: &[T; 5]) -> [T; 5] {
        self.band2
            .map(|row| crate::sh::fixed_size::array_eval::dot(&row, f))
    }
}

impl<T: GlamReal> Default for ShRotationL2<T> {
    /// [`ShRotationL2::identity`].
    fn default() -> Self {
        Self::identity()
    }
}

fn identity_entry<T: GlamReal>(i: usize, j: usize) -> T {
    if i == j {
        T::ONE
    } else {
        <T as crate::sh::real::Real>::ZERO
    }
}

fn rows_f64<T: GlamReal>(r: T::Mat3) -> [[f64; 3]; 3] {
    T::mat3_to_rows(r).map(|row| row.map(T::to_f64))
}

/// Finite, `max |r^T r - I| <= tol` and `|det r - 1| <= tol`.
fn is_rotation(r: &[[f64; 3]; 3]) -> bool {
    if r.iter().flatten().any(|v| !v.is_finite()) {
        return false;
    }
    let mut worst = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            let g: f64 = (0..3).map(|k| r[k][i] * r[k][j]).sum();
            worst = worst.max((g - if i == j { 1.0 } else { 0.0 }).abs());
        }
    }
    let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
        - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
        + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    worst <= ORTHONORMAL_TOLERANCE && (det - 1.0).abs() <= ORTHONORMAL_TOLERANCE
}

/// `M^1_{ij} = s_i s_j R[a_i][a_j]`, `a = (y, z, x)`, `s = (-1, +1, -1)`.
pub(crate) fn band1_block(r: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    const AXIS: [usize; 3] = [1, 2, 0];
    const SIGN: [f64; 3] = [-1.0, 1.0, -1.0];
    core::array::from_fn(|i| core::array::from_fn(|j| SIGN[i] * SIGN[j] * r[AXIS[i]][AXIS[j]]))
}

/// The five traceless symmetric `S_m`, `m = -2..=2`, with `Y_2^m(d) = d^T S_m d`.
fn band2_forms() -> [[[f64; 3]; 3]; 5] {
    let k = 0.5 * K2_2;
    let z = 0.0;
    [
        [[z, k, z], [k, z, z], [z, z, z]],
        [[z, z, z], [z, z, -k], [z, -k, z]],
        [[-K20, z, z], [z, -K20, z], [z, z, 2.0 * K20]],
        [[z, z, -k], [z, z, z], [-k, z, z]],
        [[K22, z, z], [z, -K22, z], [z, z, z]],
    ]
}

/// `M^2_{mn} = <S_n, R^T S_m R>_F / (15/(8 pi))`.
fn band2_block(r: &[[f64; 3]; 3]) -> [[f64; 5]; 5] {
    let s = band2_forms();
    let norm = 15.0 / (8.0 * PI);
    core::array::from_fn(|m| {
        // R^T S_m R, entry (i, j) = sum_ab R_ai S_ab R_bj.
        let t: [[f64; 3]; 3] = core::array::from_fn(|i| {
            core::array::from_fn(|j| {
                let mut acc = 0.0;
                for a in 0..3 {
                    for b in 0..3 {
                        acc += r[a][i] * s[m][a][b] * r[b][j];
                    }
                }
                acc
            })
        });
        core::array::from_fn(|n| {
            let mut acc = 0.0;
            for i in 0..3 {
                for j in 0..3 {
                    acc += s[n][i][j] * t[i][j];
                }
            }
            acc / norm
        })
    })
}

/// `c` with degree 1 rotated by `M^1` and, when `N = 9`, degree 2 by `M^2`.
#[inline]
pub(crate) fn rotated<T: GlamReal, const N: usize>(c: &[T; N], rot: &ShRotationL2<T>) -> [T; N] {
    let mut out = *c;
    let b1 = rot.apply_band1(&core::array::from_fn(|k| c[1 + k]));
    out[1..4].copy_from_slice(&b1);
    if N == 9 {
        let b2 = rot.apply_band2(&core::array::from_fn(|k| c[4 + k]));
        out[4..9].copy_from_slice(&b2);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::low_degree::eval_low_degree;

    #[test]
    fn forms_reproduce_the_degree_two_basis() {
        let s = band2_forms();
        for d in [[0.6, 0.0, 0.8], [0.48, -0.6, 0.64], [0.0, 1.0, 0.0]] {
            let mut y = [0.0; 9];
            eval_low_degree(2, d[0], d[1], d[2], &mut y);
            for m in 0..5 {
                let mut q = 0.0;
                for i in 0..3 {
                    for j in 0..3 {
                        q += d[i] * s[m][i][j] * d[j];
                    }
                }
                assert!((q - y[4 + m]).abs() < 1e-15, "m = {m}");
            }
        }
    }

    #[test]
    fn forms_are_orthogonal_with_the_stated_norm() {
        let s = band2_forms();
        for m in 0..5 {
            for n in 0..5 {
                let p: f64 = (0..9)
                    .map(|k| s[m][k / 3][k % 3] * s[n][k / 3][k % 3])
                    .sum();
                let want = if m == n { 15.0 / (8.0 * PI) } else { 0.0 };
                assert!((p - want).abs() < 1e-15, "m = {m}, n = {n}");
            }
        }
    }

    #[test]
    fn non_rotations_are_refused() {
        let scale = glam::DMat3::from_diagonal(glam::DVec3::new(1.0, 1.0, 1.01));
        assert!(ShRotationL2::<f64>::try_from_mat3(scale).is_none());
        let mirror = glam::DMat3::from_diagonal(glam::DVec3::new(1.0, 1.0, -1.0));
        assert!(ShRotationL2::<f64>::try_from_mat3(mirror).is_none());
        let nan = glam::DMat3::from_diagonal(glam::DVec3::new(f64::NAN, 1.0, 1.0));
        assert!(ShRotationL2::<f64>::try_from_mat3(nan).is_none());
        assert!(ShRotationL2::<f64>::try_from_mat3(glam::DMat3::IDENTITY).is_some());
    }
}

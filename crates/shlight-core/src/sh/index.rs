//! The flat coefficient index `i = l*(l+1) + m` and coefficient counts.
//!
//! Coefficients of degree `l` and order `m` (`-l <= m <= l`) are stored band by
//! band, `m` ascending within a band: `(0,0), (1,-1), (1,0), (1,1), (2,-2), ...`.
//! An expansion up to degree `lmax` holds `(lmax+1)^2` coefficients.

/// Flat index of the coefficient of degree `l`, order `m`: `l*(l+1) + m`.
///
/// Precondition: `|m| <= l` (checked in debug builds).
///
/// ```
/// use shlight_core::sh::sh_index;
/// assert_eq!(sh_index(0, 0), 0);
/// assert_eq!(sh_index(1, -1), 1);
/// assert_eq!(sh_index(2, 2), 8);
/// ```
#[inline]
#[must_use]
pub const fn sh_index(l: usize, m: isize) -> usize {
    debug_assert!(m.unsigned_abs() <= l);
    (l * (l + 1)).wrapping_add_signed(m)
}

/// Number of coefficients of an expansion up to degree `lmax`: `(lmax+1)^2`.
///
/// ```
/// assert_eq!(shlight_core::sh::sh_count(2), 9);
/// ```
#[inline]
#[must_use]
pub const fn sh_count(lmax: usize) -> usize {
    (lmax + 1) * (lmax + 1)
}

/// Degree and order `(l, m)` of flat index `i` (inverse of [`sh_index`]).
///
/// ```
/// use shlight_core::sh::{lm_from_index, sh_index};
/// assert_eq!(lm_from_index(sh_index(7, -3)), (7, -3));
/// ```
#[inline]
#[must_use]
pub fn lm_from_index(i: usize) -> (usize, isize) {
    let mut l = (i as f64).sqrt() as usize;
    // Guard against rounding of the square root for very large i.
    while l * l > i {
        l -= 1;
    }
    while (l + 1) * (l + 1) <= i {
        l += 1;
    }
    (l, i as isize - (l * (l + 1)) as isize)
}

/// The `lmax` of an expansion with `count` coefficients, if `count` is a perfect square.
///
/// ```
/// assert_eq!(shlight_core::sh::lmax_from_count(25), Some(4));
/// assert_eq!(shlight_core::sh::lmax_from_count(24), None);
/// ```
#[must_use]
pub fn lmax_from_count(count: usize) -> Option<usize> {
    if count == 0 {
        return None;
    }
    let (l, m) = lm_from_index(count - 1);
    (m == l as isize).then_some(l)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_round_trips_for_every_coefficient_to_lmax_300() {
        let mut i = 0;
        for l in 0..=300usize {
            for m in -(l as isize)..=(l as isize) {
                assert_eq!(sh_index(l, m), i);
                assert_eq!(lm_from_index(i), (l, m));
                i += 1;
            }
            assert_eq!(i, sh_count(l));
        }
    }

    #[test]
    fn lmax_from_count_accepts_only_squares() {
        for lmax in 0..100 {
            assert_eq!(lmax_from_count(sh_count(lmax)), Some(lmax));
            assert_eq!(lmax_from_count(sh_count(lmax) + 1), None);
        }
        assert_eq!(lmax_from_count(0), None);
    }
}

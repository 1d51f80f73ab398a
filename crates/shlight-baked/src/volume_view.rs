//! [`VolumeView`]: an irradiance volume's probes borrowed, as the renderer
//! and every reader of a bake take them, and the lmax limits of volumes.

use crate::{ProbeGrid, ShapeError};

/// Highest lmax a volume's probes hold (a `.shvol` file, a bake).
pub const MAX_LMAX: usize = 8;

/// Highest lmax the GPU's volume pass shades: a volume of higher lmax is
/// clipped to it (`ceil((3 c + 1) / 4)` texels are interpolated per
/// fragment, `c` the coefficients of the degrees whose `A_l` is not 0: 7
/// at lmax 2, 14 at lmax 4, where degree 3's 7 coefficients are left out).
/// Here, not in the GPU crate, so that builds without a GPU refuse the
/// same `--lmax`.
pub const SHADED_MAX_LMAX: usize = 4;

/// A volume's probes (the fields of a `.shvol` file: docs/shvol.md),
/// borrowed.
#[derive(Clone, Copy, Debug)]
pub struct VolumeView<'a> {
    /// The probes' box and resolution.
    pub grid: ProbeGrid,
    /// Highest SH degree of `radiance`.
    pub lmax: usize,
    /// Per probe: whether interpolation may use it.
    pub valid: &'a [bool],
    /// Per probe `(lmax+1)^2` rows of `[r, g, b]` radiance coefficients,
    /// probes x fastest, then y, then z.
    pub radiance: &'a [f32],
}

impl VolumeView<'_> {
    /// Number of probes.
    #[must_use]
    pub fn probe_count(&self) -> usize {
        self.grid.probe_count()
    }

    /// Checks that the view's parts fit together: counts of at least 1,
    /// `min < max` on every axis, `probes` validity flags and
    /// `probes * (lmax+1)^2 * 3` values.
    ///
    /// # Errors
    /// [`ShapeError`] naming the part that does not fit.
    pub fn check(&self) -> Result<(), ShapeError> {
        let g = &self.grid;
        let n = g
            .resolution
            .iter()
            .try_fold(1usize, |a, &r| a.checked_mul(r));
        let Some(n) = n.filter(|_| !g.resolution.contains(&0)) else {
            return Err(ShapeError(format!(
                "volume resolution {:?}: each count must be at least 1",
                g.resolution
            )));
        };
        if !(g.min.is_finite() && g.max.is_finite()) || g.min.cmpge(g.max).any() {
            return Err(ShapeError(format!(
                "volume bounds {}:{}: min must be below max on every axis",
                g.min, g.max
            )));
        }
        let nc = (self.lmax + 1) * (self.lmax + 1);
        let values = n.checked_mul(nc * 3);
        if self.valid.len() != n || values != Some(self.radiance.len()) {
            return Err(ShapeError(format!(
                "a volume of {n} probes at lmax {} needs {n} validity flags and {} values, not {} and {}",
                self.lmax,
                values.map_or_else(|| "too many".to_string(), |v| v.to_string()),
                self.valid.len(),
                self.radiance.len()
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn parts_must_fit() {
        let grid = ProbeGrid::new([2, 1, 1], Vec3::ZERO, Vec3::ONE).unwrap();
        let valid = [true, false];
        let radiance = vec![0.0f32; 2 * 9 * 3];
        let v = VolumeView {
            grid,
            lmax: 2,
            valid: &valid,
            radiance: &radiance,
        };
        assert!(v.check().is_ok());
        assert_eq!(v.probe_count(), 2);
        let short = VolumeView {
            radiance: &radiance[1..],
            ..v
        };
        assert_eq!(
            short.check().unwrap_err().0,
            "a volume of 2 probes at lmax 2 needs 2 validity flags and 54 values, not 2 and 53"
        );
        let flat = VolumeView {
            grid: ProbeGrid {
                max: Vec3::new(1.0, 0.0, 1.0),
                ..grid
            },
            ..v
        };
        assert!(
            flat.check()
                .unwrap_err()
                .0
                .contains("min must be below max")
        );
        let empty = VolumeView {
            grid: ProbeGrid {
                resolution: [2, 0, 1],
                ..grid
            },
            ..v
        };
        assert!(empty.check().unwrap_err().0.contains("at least 1"));
    }
}

//! [`VolumeView`]: an irradiance volume's probes borrowed, as the renderer
//! and every reader of a bake take them, and the lmax limits of volumes.

use glam::Vec3;

use crate::probe_grid::ProbeGrid;
use crate::shape_error::ShapeError;
use crate::visibility::Visibility;

/// Highest lmax a volume's probes hold (a `.shvol` file, a bake).
pub const MAX_LMAX: usize = 8;

/// Highest lmax the GPU's volume pass shades: a volume of higher lmax is
/// clipped to it (`ceil((3 c + 1) / 4)` texels are interpolated per
/// fragment, `c` the coefficients of the degrees whose `A_l` is not 0: 7
/// at lmax 2, 14 at lmax 4, where degree 3's 7 coefficients are left out).
/// Here, not in the GPU crate, so that builds without a GPU refuse the
/// same `--lmax`.
pub const SHADED_MAX_LMAX: usize = 4;

/// A volume's lit probes (the fields of a `.shvol` file: docs/shvol.md),
/// borrowed: what every lookup of a volume and the GPU's volume pass
/// read.
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
    /// Per probe `[dx, dy, dz]`: where the bake moved it from its cell's
    /// centre out of geometry (`None`: every probe at its centre).
    pub offsets: Option<&'a [f32]>,
    /// The probes' distance maps, for the visibility-weighted lookup
    /// (`None`: a volume baked without them, or a version 1 file).
    pub visibility: Option<Visibility<'a>>,
}

/// The probes a bake moved (a non-zero offset in `offsets`, per probe
/// `[dx, dy, dz]`), in probe order.
#[must_use]
pub fn moved_probes(offsets: &[f32]) -> Vec<usize> {
    offsets
        .chunks_exact(3)
        .enumerate()
        .filter(|(_, d)| d.iter().any(|&x| x != 0.0))
        .map(|(k, _)| k)
        .collect()
}

/// The farthest any probe was moved along an axis, as a fraction of that
/// axis's cell side (relocation keeps it at most 0.45).
#[must_use]
pub fn largest_move(grid: &ProbeGrid, offsets: &[f32]) -> f32 {
    let cell = grid.cell();
    offsets
        .chunks_exact(3)
        .map(|d| (Vec3::from_slice(d) / cell).abs().max_element())
        .fold(0.0, f32::max)
}

impl VolumeView<'_> {
    /// Number of probes.
    #[must_use]
    pub fn probe_count(&self) -> usize {
        self.grid.probe_count()
    }

    /// Where probe `k` is: its cell's centre plus its offset.
    #[must_use]
    pub fn position(&self, k: usize) -> Vec3 {
        let c = self.grid.centre(self.grid.grid_index(k));
        match self.offsets {
            Some(o) => c + Vec3::from_slice(&o[3 * k..3 * k + 3]),
            None => c,
        }
    }

    /// Checks that the view's parts fit together: counts of at least 1,
    /// `min < max` on every axis, `probes` validity flags,
    /// `probes * (lmax+1)^2 * 3` values, `3 probes` finite offsets and
    /// distance maps of the right shape.
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
        if let Some(o) = self.offsets {
            if o.len() != 3 * n {
                return Err(ShapeError(format!(
                    "a volume of {n} probes needs {} offset values, not {}",
                    3 * n,
                    o.len()
                )));
            }
            if o.iter().any(|x| !x.is_finite()) {
                return Err(ShapeError("a probe offset is not finite".into()));
            }
        }
        if let Some(v) = &self.visibility {
            v.check(n)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            offsets: None,
            visibility: None,
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
        let offsets = [0.0, 0.5, 0.0, 0.0, 0.0, -0.25];
        let moved = VolumeView {
            offsets: Some(&offsets),
            ..v
        };
        assert!(moved.check().is_ok());
        assert_eq!(moved.position(0), Vec3::new(0.25, 1.0, 0.5));
        assert_eq!(moved.position(1), Vec3::new(0.75, 0.5, 0.25));
        // Both probes moved; the farthest is 0.5 of the unit y side
        // (cells are 0.5 x 1 x 1: 0.25 along z is a quarter).
        assert_eq!(moved_probes(&offsets), vec![0, 1]);
        assert_eq!(moved_probes(&[0.0; 6]), Vec::<usize>::new());
        assert_eq!(largest_move(&grid, &offsets), 0.5);
        assert_eq!(largest_move(&grid, &[0.0, 0.0, 0.0, 0.2, 0.0, 0.0]), 0.4);
        assert_eq!(v.position(1), Vec3::new(0.75, 0.5, 0.5));
        let short = VolumeView {
            offsets: Some(&offsets[1..]),
            ..v
        };
        assert!(
            short
                .check()
                .unwrap_err()
                .0
                .contains("6 offset values, not 5")
        );
        let maps = vec![1.0f32; 2 * 2 * 4 * 4];
        let seen = VolumeView {
            visibility: Some(Visibility {
                size: 4,
                max_distance: 1.0,
                moments: &maps,
            }),
            ..v
        };
        assert!(seen.check().is_ok());
        let short = VolumeView {
            visibility: Some(Visibility {
                size: 4,
                max_distance: 1.0,
                moments: &maps[1..],
            }),
            ..v
        };
        assert!(
            short
                .check()
                .unwrap_err()
                .0
                .contains("need 64 values, not 63")
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

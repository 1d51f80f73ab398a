//! [`ProbeGrid`]: a box cut into cells, one probe at each cell's centre.

use glam::Vec3;

use crate::ShapeError;

/// Most probes a grid holds (`2^24`): a `.shvol` file, a bake and the GPU's
/// volume texture all stay within it.
pub const MAX_PROBES: usize = 1 << 24;

/// A grid of probes: `resolution` cells along x, y and z of the box
/// `min..max`, a probe at the centre of each cell (as Bevy's and three.js's
/// irradiance volumes place them), numbered x fastest, then y, then z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeGrid {
    /// Probes along x, y and z (each at least 1).
    pub resolution: [usize; 3],
    /// The box's lower corner.
    pub min: Vec3,
    /// The box's upper corner (above `min` on every axis).
    pub max: Vec3,
}

/// How much [`ProbeGrid::around`] grows a scene's bounding box on each side, as
/// a fraction of its diagonal: probes sit inside the scene's walls, not on
/// them, and a flat scene still gets a box of some height.
pub const PADDING: f32 = 0.02;

impl ProbeGrid {
    /// A grid over `min..max`.
    ///
    /// # Errors
    /// A zero count, more than [`MAX_PROBES`] probes,
    /// or bounds that are not finite with `min < max` on every axis.
    pub fn new(resolution: [usize; 3], min: Vec3, max: Vec3) -> Result<Self, ShapeError> {
        let probes = resolution
            .iter()
            .try_fold(1usize, |acc, &n| acc.checked_mul(n))
            .unwrap_or(usize::MAX);
        if resolution.contains(&0) || probes > MAX_PROBES {
            return Err(ShapeError(format!(
                "resolution {}x{}x{}: each count must be at least 1 and the grid at most {} probes",
                resolution[0], resolution[1], resolution[2], MAX_PROBES
            )));
        }
        if !(min.is_finite() && max.is_finite()) || min.cmpge(max).any() {
            return Err(ShapeError(format!(
                "bounds {min}:{max}: min must be below max on every axis"
            )));
        }
        Ok(Self {
            resolution,
            min,
            max,
        })
    }

    /// A grid over a scene's bounding box `lo..hi`, grown by [`PADDING`]
    /// times its diagonal on every side.
    ///
    /// # Errors
    /// As [`ProbeGrid::new`].
    pub fn around(resolution: [usize; 3], (lo, hi): (Vec3, Vec3)) -> Result<Self, ShapeError> {
        let pad = PADDING * (hi - lo).length().max(f32::MIN_POSITIVE.sqrt());
        Self::new(resolution, lo - Vec3::splat(pad), hi + Vec3::splat(pad))
    }

    /// Number of probes.
    #[must_use]
    pub fn probe_count(&self) -> usize {
        self.resolution.iter().product()
    }

    /// The size of one cell.
    #[must_use]
    pub fn cell(&self) -> Vec3 {
        (self.max - self.min) / Vec3::from_array(self.resolution.map(|n| n as f32))
    }

    /// The probe number of grid index `(x, y, z)`: `x + nx (y + ny z)`.
    #[must_use]
    pub fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        x + self.resolution[0] * (y + self.resolution[1] * z)
    }

    /// The grid index `(x, y, z)` of probe number `k` (the inverse of
    /// [`ProbeGrid::index`]).
    #[must_use]
    pub fn grid_index(&self, k: usize) -> [usize; 3] {
        let [nx, ny, _] = self.resolution;
        [k % nx, k / nx % ny, k / (nx * ny)]
    }

    /// The centre of cell `(x, y, z)`, where its probe sits:
    /// `min + (i + 1/2) cell` per axis, with `cell = (max - min) / n`. The
    /// one formula of a probe's place: the bake casts from it, the files
    /// record it, the GPU interpolates between it.
    #[must_use]
    pub fn centre(&self, index: [usize; 3]) -> Vec3 {
        self.min + (Vec3::from_array(index.map(|i| i as f32)) + 0.5) * self.cell()
    }

    /// Every probe's centre, in probe order.
    #[must_use]
    pub fn centres(&self) -> Vec<Vec3> {
        let [nx, ny, nz] = self.resolution;
        let mut out = Vec::with_capacity(self.probe_count());
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    out.push(self.centre([x, y, z]));
                }
            }
        }
        out
    }

    /// The up to eight probes around `p` with their trilinear weights
    /// (`(probe, weight)`, weights summing to 1), clamped to the grid: a
    /// point outside the probes' hull takes the nearest face's, edge's or
    /// corner's probes.
    #[must_use]
    pub fn trilinear(&self, p: Vec3) -> Vec<(usize, f32)> {
        let u = (p - self.min) / self.cell() - 0.5;
        let mut lo = [0usize; 3];
        let mut t = [0.0f32; 3];
        for a in 0..3 {
            let n = self.resolution[a];
            if n == 1 {
                continue;
            }
            let f = u[a].clamp(0.0, (n - 1) as f32);
            let i = (f.floor() as usize).min(n - 2);
            lo[a] = i;
            t[a] = f - i as f32;
        }
        let mut out = Vec::with_capacity(8);
        for corner in 0..8usize {
            let mut index = lo;
            let mut w = 1.0;
            for a in 0..3 {
                let up = corner >> a & 1 == 1;
                if self.resolution[a] == 1 {
                    if up {
                        w = 0.0;
                    }
                    continue;
                }
                index[a] += usize::from(up);
                w *= if up { t[a] } else { 1.0 - t[a] };
            }
            if w > 0.0 {
                out.push((self.index(index), w));
            }
        }
        out
    }

    /// Parses `NXxNYxNZ`, e.g. `16x8x16`.
    ///
    /// # Errors
    /// Anything else, or a zero count.
    pub fn parse_resolution(text: &str) -> Result<[usize; 3], ShapeError> {
        let bad = || {
            ShapeError(format!(
                "resolution \"{text}\" is not NXxNYxNZ with whole numbers of at least 1 (e.g. 16x8x16)"
            ))
        };
        let parts: Vec<usize> = text
            .split(['x', 'X'])
            .map(|s| s.trim().parse::<usize>().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        let r: [usize; 3] = parts.try_into().map_err(|_| bad())?;
        if r.contains(&0) {
            return Err(bad());
        }
        Ok(r)
    }

    /// Parses `X0,Y0,Z0:X1,Y1,Z1` into `(min, max)`.
    ///
    /// # Errors
    /// Anything else, or `min` not below `max` on every axis.
    pub fn parse_bounds(text: &str) -> Result<(Vec3, Vec3), ShapeError> {
        let bad = || {
            ShapeError(format!(
                "bounds \"{text}\" are not X0,Y0,Z0:X1,Y1,Z1 with finite numbers and X0 < X1, Y0 < Y1, Z0 < Z1"
            ))
        };
        let corner = |s: &str| -> Result<Vec3, ShapeError> {
            let v: Vec<f32> = s
                .split(',')
                .map(|x| x.trim().parse::<f32>().map_err(|_| bad()))
                .collect::<Result<_, _>>()?;
            let v: [f32; 3] = v.try_into().map_err(|_| bad())?;
            Ok(Vec3::from_array(v))
        };
        let (a, b) = text.split_once(':').ok_or_else(bad)?;
        let (min, max) = (corner(a)?, corner(b)?);
        if !(min.is_finite() && max.is_finite()) || min.cmpge(max).any() {
            return Err(bad());
        }
        Ok((min, max))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probes_sit_at_cell_centres_x_fastest() {
        let g = ProbeGrid::new([2, 3, 4], Vec3::ZERO, Vec3::new(2.0, 3.0, 4.0)).unwrap();
        let p = g.centres();
        assert_eq!(p.len(), 24);
        assert_eq!(p[0], Vec3::splat(0.5));
        assert_eq!(p[1], Vec3::new(1.5, 0.5, 0.5));
        assert_eq!(p[2], Vec3::new(0.5, 1.5, 0.5));
        assert_eq!(p[6], Vec3::new(0.5, 0.5, 1.5));
        assert_eq!(g.index([1, 2, 3]), 23);
        assert_eq!(p[g.index([1, 2, 3])], Vec3::new(1.5, 2.5, 3.5));
        for k in 0..24 {
            assert_eq!(g.index(g.grid_index(k)), k);
        }
    }

    #[test]
    fn trilinear_weights_reproduce_linear_functions() {
        // Interpolating the probes' own positions must give the point back
        // anywhere inside the probes' hull (trilinear interpolation is exact
        // for linear functions), and the weights sum to 1.
        let g = ProbeGrid::new(
            [3, 2, 4],
            Vec3::new(-1.0, 0.0, 2.0),
            Vec3::new(2.0, 1.0, 6.0),
        )
        .unwrap();
        let positions = g.centres();
        for p in [
            Vec3::new(0.1, 0.4, 3.3),
            Vec3::new(-0.5, 0.25, 2.5),
            Vec3::new(1.49, 0.74, 5.49),
            Vec3::new(0.5, 0.5, 4.0),
        ] {
            let w = g.trilinear(p);
            let sum: f32 = w.iter().map(|x| x.1).sum();
            assert!((sum - 1.0).abs() < 1e-5);
            let back: Vec3 = w.iter().map(|&(i, x)| positions[i] * x).sum();
            assert!(back.distance(p) < 1e-4, "{p} -> {back}");
        }
        // Outside: clamped to the nearest probe.
        let w = g.trilinear(Vec3::new(-10.0, -10.0, -10.0));
        assert_eq!(w, vec![(0, 1.0)]);
        // A flat grid (one probe along y) interpolates in x and z only.
        let flat = ProbeGrid::new([2, 1, 2], Vec3::ZERO, Vec3::ONE).unwrap();
        let w = flat.trilinear(Vec3::new(0.5, 0.9, 0.5));
        assert_eq!(w.len(), 4);
        assert!(w.iter().all(|&(_, x)| (x - 0.25).abs() < 1e-6));
    }

    #[test]
    fn parses_and_refuses() {
        assert_eq!(ProbeGrid::parse_resolution("16x8x16").unwrap(), [16, 8, 16]);
        for bad in ["16x8", "0x1x1", "ax1x1", "1x1x1x1", ""] {
            let e = ProbeGrid::parse_resolution(bad).unwrap_err().to_string();
            assert!(e.contains(&format!("\"{bad}\"")), "{e}");
        }
        let (lo, hi) = ProbeGrid::parse_bounds("-1,0,-2.5:1,2,2.5").unwrap();
        assert_eq!(
            (lo, hi),
            (Vec3::new(-1.0, 0.0, -2.5), Vec3::new(1.0, 2.0, 2.5))
        );
        for bad in ["1,1,1:0,2,2", "0,0:1,1", "0,0,0", "0,0,0:1,1,nan"] {
            assert!(ProbeGrid::parse_bounds(bad).is_err(), "{bad}");
        }
        assert!(ProbeGrid::new([1, 1, 0], Vec3::ZERO, Vec3::ONE).is_err());
        assert!(ProbeGrid::new([1, 1, 1], Vec3::ONE, Vec3::ONE).is_err());
        assert!(ProbeGrid::new([4096, 4096, 4096], Vec3::ZERO, Vec3::ONE).is_err());
        let g = ProbeGrid::around([1, 1, 1], (Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0))).unwrap();
        assert!(g.min.y < 0.0 && g.max.y > 0.0);
    }
}

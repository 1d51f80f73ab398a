//! [`ImportanceGrid`]: a piecewise-constant pdf over the cells of an
//! equirect grid of the sphere, proportional to luminance, for importance
//! sampling.

use core::f64::consts::PI;

use glam::DVec3;

use crate::map::equirect::{equirect_direction, equirect_row_solid_angle};
use crate::map::orientation::MapOrientation;
use crate::map::radiance_map::{RadianceMap, luminance};

/// Share of the probability spread uniformly over the sphere (the
/// "defensive" mixture): `P(cell) = (1 - α) w/Σw + α Ω/(4π)`, `α = 0.1`.
///
/// It keeps the pdf at least `α / (4π)` everywhere, so the estimator stays
/// unbiased where the grid says dark but the map is not (between texel
/// centres, under bilinear lookups, for negative values), and bounds the
/// weight `f/p` by `4π |f| / α`.
pub const DEFENSIVE_FRACTION: f64 = 0.1;

/// The whole of a row's conditional CDF in the grid's fixed point:
/// `2^32` units ([`ImportanceGrid`]'s `col_cdf`).
const COL_ONE: u64 = 1 << 32;

/// A piecewise-constant probability density on the sphere whose cells are
/// the texels of a `width x height` equirect grid in a [`MapOrientation`].
///
/// Cell `(i, j)` (column `i`, row `j` from the top) covers
/// `θ ∈ [jπ/H, (j+1)π/H]`, `φ ∈ [2π(i/W - 1/2), 2π((i+1)/W - 1/2)]` in the
/// map's frame (docs/conventions.md), solid angle
/// `Ω_j = (2π/W)(cos(jπ/H) - cos((j+1)π/H))`
/// ([`equirect_row_solid_angle`]). With `lum_ij` the cell's luminance as
/// each constructor defines it (an upper estimate over the cell for
/// [`ImportanceGrid::from_fn`] and [`ImportanceGrid::from_equirect`], the
/// given value for [`ImportanceGrid::from_cell_luminance`]) and weights
/// `w_ij = max(lum_ij, 0) Ω_j`, its probability is
///
/// ```text
/// P_ij = (1 - α) w_ij / Σ w + α Ω_j / (4π)          (α = DEFENSIVE_FRACTION)
/// ```
///
/// (only the uniform part when `Σ w = 0`), and inside a cell directions are
/// uniform in `(cos θ, φ)`, i.e. uniform in solid angle, so the density is
/// exactly `p(ω) = P_ij / Ω_j` on cell `(i, j)`.
///
/// Sampling inverts the 2-D CDF: a row from the marginal CDF of the row
/// masses, then a column from that row's conditional CDF (binary searches),
/// then `(cos θ, φ)` uniformly inside the cell.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportanceGrid {
    width: usize,
    height: usize,
    orientation: MapOrientation,
    /// `R_j`, `j = 0..=H`: marginal CDF of the rows, `R_0 = 0`, `R_H = 1`.
    row_cdf: Vec<f64>,
    /// Row `j` holds the conditional CDF of the columns in units of
    /// `2^-32`: `Q_j(i)` for `i = 1..W-1` (`Q_j(0) = 0` and
    /// `Q_j(W) = 2^32` are implied; [`ImportanceGrid::col_cdf`]), rounded
    /// from the `f64` sums and kept strictly increasing, so every cell
    /// keeps a share. `P_ij` is not stored: it is the CDF differences that
    /// sampling realises, `(R_{j+1} - R_j)(Q_j(i+1) - Q_j(i)) 2^-32`,
    /// computed where needed (4 bytes a cell in all, besides the map).
    col_cdf: Vec<u32>,
    /// `Ω_j`, solid angle of one cell of row `j`.
    row_omega: Vec<f64>,
    /// `1 - cos(jπ/H)`, `j = 0..=H`, without cancellation.
    row_omz: Vec<f64>,
}

impl ImportanceGrid {
    /// A grid whose cell luminance is the largest value of `f` at the
    /// cell's centre ([`equirect_direction`]) and its four corners
    /// (`θ = jπ/H`, `φ = 2π(i/W - 1/2)` in the grid's frame).
    ///
    /// Taking the largest rather than the centre's value makes the density
    /// follow an upper bound of the map across each cell, so a bright
    /// feature that covers part of a cell without its centre still gets its
    /// share and the weight `f/p` stays bounded there; features smaller than
    /// a cell may be missed and are covered by the defensive floor.
    ///
    /// Panics if `width` or `height` is 0.
    #[must_use]
    pub fn from_fn(
        width: usize,
        height: usize,
        orientation: MapOrientation,
        f: impl Fn(DVec3) -> f64,
    ) -> Self {
        let (w, h) = (width, height);
        assert!(w > 0 && h > 0, "grid must have cells");
        let g = |v: f64| if v.is_nan() { f64::NEG_INFINITY } else { v };
        let corners: Vec<f64> = (0..=h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| {
                let t = PI * j as f64 / h as f64;
                let p = 2.0 * PI * (i as f64 / w as f64 - 0.5);
                let p = if orientation.mirror { -p } else { p };
                g(f(orientation.frame.direction(t, p)))
            })
            .collect();
        let mut lum = Vec::with_capacity(w * h);
        for j in 0..h {
            for i in 0..w {
                let i1 = (i + 1) % w;
                let c = g(f(equirect_direction(i, j, w, h, orientation)))
                    .max(corners[j * w + i])
                    .max(corners[j * w + i1])
                    .max(corners[(j + 1) * w + i])
                    .max(corners[(j + 1) * w + i1]);
                lum.push(c);
            }
        }
        Self::from_cell_luminance(w, h, orientation, &lum)
    }

    /// A grid over the texels of an equirect map: cell `(i, j)` is texel
    /// `(i, j)` and its luminance is the largest Rec.709 luminance
    /// `Y = 0.2126 R + 0.7152 G + 0.0722 B` ([`luminance`]) of the texels
    /// `(i±1, j±1)` around it (columns wrap around, rows stop at the poles).
    /// Any nearest or bilinear lookup inside the cell reads only those
    /// texels, so the density follows an upper bound of the map and `f/p`
    /// stays bounded next to a small bright source. For weights from the
    /// texels alone use [`ImportanceGrid::from_cell_luminance`].
    ///
    /// `pixels` is row-major from the top-left corner, linear RGB;
    /// non-finite values count as 0.
    ///
    /// Panics if `pixels.len() != width * height` or either size is 0.
    #[must_use]
    pub fn from_equirect(
        width: usize,
        height: usize,
        pixels: &[[f32; 3]],
        orientation: MapOrientation,
    ) -> Self {
        let (w, h) = (width, height);
        assert!(w > 0 && h > 0, "grid must have cells");
        assert_eq!(pixels.len(), w * h, "pixel count must be width * height");
        // The 3x3 maximum row by row, from three rows of the luminance's
        // maximum along rows: no table the size of the map.
        let mut window = MaxWindow::new(w);
        Self::from_rows(w, h, orientation, |j, out| {
            window.cell_row(pixels, h, j, out);
        })
    }

    /// A grid from the luminance of `map` ([`ImportanceGrid::from_fn`] with
    /// `|d| luminance(map.radiance(d))`: the largest over each cell's centre
    /// and corners).
    #[must_use]
    pub fn from_map(
        map: &impl RadianceMap,
        width: usize,
        height: usize,
        orientation: MapOrientation,
    ) -> Self {
        Self::from_fn(width, height, orientation, |d| luminance(map.radiance(d)))
    }

    /// A grid from one luminance value per cell, row-major from the top-left
    /// corner: cell weight `w_ij = max(lum_ij, 0) Ω_j`, non-finite values
    /// counting as 0, then `P_ij` as in the type's docs.
    ///
    /// Panics if `lum.len() != width * height` or either size is 0.
    #[must_use]
    pub fn from_cell_luminance(
        width: usize,
        height: usize,
        orientation: MapOrientation,
        lum: &[f64],
    ) -> Self {
        assert!(width > 0 && height > 0, "grid must have cells");
        assert_eq!(lum.len(), width * height, "one luminance per cell");
        Self::from_rows(width, height, orientation, |j, out| {
            out.copy_from_slice(&lum[j * width..(j + 1) * width]);
        })
    }

    /// [`ImportanceGrid::from_cell_luminance`] with the luminance of row
    /// `j` written by `cell_row(j, row)`, called for every row in order,
    /// twice (once for the total weight, once for the CDFs), so that no
    /// table of luminance the size of the grid is kept.
    fn from_rows(
        width: usize,
        height: usize,
        orientation: MapOrientation,
        mut cell_row: impl FnMut(usize, &mut [f64]),
    ) -> Self {
        let (w, h) = (width, height);
        let row_omega: Vec<f64> = (0..h).map(|j| equirect_row_solid_angle(j, w, h)).collect();
        let clean = |v: f64| if v.is_finite() && v > 0.0 { v } else { 0.0 };
        let mut lum = vec![0.0; w];
        let total: f64 = (0..h)
            .map(|j| {
                cell_row(j, &mut lum);
                row_omega[j] * lum.iter().map(|&v| clean(v)).sum::<f64>()
            })
            .sum();
        let (a, b) = if total > 0.0 && total.is_finite() {
            (
                (1.0 - DEFENSIVE_FRACTION) / total,
                DEFENSIVE_FRACTION / (4.0 * PI),
            )
        } else {
            (0.0, 1.0 / (4.0 * PI))
        };
        // Unnormalised cell masses, then the two CDFs.
        let mut col_cdf = vec![0u32; h * (w - 1)];
        let mut row_mass = vec![0.0; h];
        let mut sums = vec![0.0; w];
        for j in 0..h {
            cell_row(j, &mut lum);
            let mut acc = 0.0;
            for i in 0..w {
                acc += row_omega[j] * (a * clean(lum[i]) + b);
                sums[i] = acc;
            }
            row_mass[j] = acc;
            // Q(i) = round(2^32 C(i)), at least one more than Q(i - 1) and
            // room left for one unit a cell to the end (every cell has
            // the uniform share `b`, so none should have none).
            let c = &mut col_cdf[j * (w - 1)..(j + 1) * (w - 1)];
            let mut last = 0u64;
            for i in 1..w {
                let q = (sums[i - 1] / acc * COL_ONE as f64).round() as u64;
                let q = q.max(last + 1).min(COL_ONE - (w - i) as u64);
                c[i - 1] = q as u32;
                last = q;
            }
        }
        let mut row_cdf = vec![0.0; h + 1];
        let mut acc = 0.0;
        for j in 0..h {
            acc += row_mass[j];
            row_cdf[j + 1] = acc;
        }
        for v in &mut row_cdf {
            *v /= acc;
        }
        row_cdf[h] = 1.0;
        let row_omz = (0..=h)
            .map(|j| {
                let s = (PI * j as f64 / h as f64 / 2.0).sin();
                2.0 * s * s
            })
            .collect();
        Self {
            width,
            height,
            orientation,
            row_cdf,
            col_cdf,
            row_omega,
            row_omz,
        }
    }

    /// Columns of the grid.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows of the grid.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// How the grid's cells meet world directions.
    #[must_use]
    pub fn orientation(&self) -> MapOrientation {
        self.orientation
    }

    /// Probability `P_ij` of cell `(i, j)` (column, row); they sum to 1.
    #[must_use]
    pub fn cell_probability(&self, i: usize, j: usize) -> f64 {
        let share = (self.col_cdf(j, i + 1) - self.col_cdf(j, i)) as f64 / COL_ONE as f64;
        (self.row_cdf[j + 1] - self.row_cdf[j]) * share
    }

    /// `Q_j(i)`, `i = 0..=W`: row `j`'s conditional CDF of the columns at
    /// column `i`, in units of `2^-32` (`Q_j(0) = 0`, `Q_j(W) = 2^32`).
    fn col_cdf(&self, j: usize, i: usize) -> u64 {
        let w = self.width;
        match i {
            0 => 0,
            i if i >= w => COL_ONE,
            i => u64::from(self.col_cdf[j * (w - 1) + i - 1]),
        }
    }

    /// Maps four uniforms in `[0, 1)` to a direction and its density:
    /// row `j` with `R_j <= u0 < R_{j+1}`, column `i` with
    /// `Q_j(i) <= floor(2^32 u1) < Q_j(i+1)`, then `cos θ = cos θ_j - u2 (cos θ_j - cos θ_{j+1})`
    /// and `φ = 2π((i + u3)/W - 1/2)` in the grid's frame. Returns
    /// `(ω, p(ω))` with `p(ω) = P_ij / Ω_j`.
    #[must_use]
    pub fn sample(&self, u: [f64; 4]) -> (DVec3, f64) {
        let (w, h) = (self.width, self.height);
        let j = self.row_cdf.partition_point(|&c| c <= u[0]).clamp(1, h) - 1;
        // Columns 1..W-1 stored: the count of those at or below the
        // draw is the column.
        let x = ((u[1] * COL_ONE as f64) as u64).min(COL_ONE - 1);
        let c = &self.col_cdf[j * (w - 1)..(j + 1) * (w - 1)];
        let i = c.partition_point(|&v| u64::from(v) <= x);
        // 1 - z and 1 + z inside the row, without cancellation near the poles.
        let dz = self.row_omz[j + 1] - self.row_omz[j];
        let omz = self.row_omz[j] + u[2] * dz;
        let opz = 2.0 - omz;
        let z = 1.0 - omz;
        let s = (omz * opz).max(0.0).sqrt();
        let phi = 2.0 * PI * ((i as f64 + u[3]) / w as f64 - 0.5);
        let d = self.direction(z, s, phi);
        (d, self.cell_probability(i, j) / self.row_omega[j])
    }

    /// World direction of `(cos θ, sin θ, φ)` in the grid's frame: the y-up
    /// direction `(sin θ cos φ, cos θ, sin θ sin φ)` taken to the world by
    /// [`MapOrientation::world_from_map`], exactly as [`equirect_direction`]
    /// places texels.
    fn direction(&self, z: f64, s: f64, phi: f64) -> DVec3 {
        let (sp, cp) = phi.sin_cos();
        self.orientation
            .world_from_map(DVec3::new(s * cp, z, s * sp))
    }

    /// The density `p(ω) = P_ij / Ω_j` of the cell holding the unit
    /// direction `d` (for MIS weights or checks). Integrates to 1 over the sphere.
    #[must_use]
    pub fn pdf(&self, d: DVec3) -> f64 {
        let (i, j) = self.cell_of(d);
        self.cell_probability(i, j) / self.row_omega[j]
    }

    /// The cell `(column, row)` holding the unit direction `d`.
    fn cell_of(&self, d: DVec3) -> (usize, usize) {
        let (w, h) = (self.width, self.height);
        let y = self.orientation.map_from_world(d);
        let theta = (y.x.hypot(y.z)).atan2(y.y);
        let phi = y.z.atan2(y.x);
        let u = phi / (2.0 * PI) + 0.5;
        let i = ((u * w as f64) as usize).min(w - 1);
        let j = ((theta / PI * h as f64) as usize).min(h - 1);
        (i, j)
    }
}

/// The 3x3 maximum of an equirect map's luminance, row by row
/// ([`ImportanceGrid::from_equirect`]): the maximum along each row
/// (columns wrapping) of the rows `j - 1`, `j`, `j + 1`, kept as they slide
/// down the map, then their maximum (rows stopping at the poles).
struct MaxWindow {
    w: usize,
    /// Maxima along rows `j - 1`, `j`, `j + 1` (those that exist) of the
    /// last row `j` asked for, row `r` in slot `r mod 3`.
    rows: [Vec<f64>; 3],
    /// The last row asked for, `None` before any.
    last: Option<usize>,
    lum: Vec<f64>,
}

impl MaxWindow {
    fn new(w: usize) -> Self {
        Self {
            w,
            rows: core::array::from_fn(|_| vec![0.0; w]),
            last: None,
            lum: vec![0.0; w],
        }
    }

    /// The maximum along row `j` of `pixels`' luminance (NaN as `-inf`)
    /// into slot `k`.
    fn row_max(&mut self, pixels: &[[f32; 3]], j: usize, k: usize) {
        let w = self.w;
        for (l, p) in self.lum.iter_mut().zip(&pixels[j * w..(j + 1) * w]) {
            let y = luminance(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
            *l = if y.is_nan() { f64::NEG_INFINITY } else { y };
        }
        let r = &self.lum;
        for (i, o) in self.rows[k].iter_mut().enumerate() {
            *o = r[(i + w - 1) % w].max(r[i]).max(r[(i + 1) % w]);
        }
    }

    /// Row `j` of the 3x3 maximum into `out`; rows must come in order
    /// (from 0 again to start over).
    fn cell_row(&mut self, pixels: &[[f32; 3]], h: usize, j: usize, out: &mut [f64]) {
        // Row r sits in slot r mod 3. One row down from the last call,
        // row j + 1 is the only new one.
        if j > 0 && self.last == Some(j - 1) {
            if j + 1 < h {
                self.row_max(pixels, j + 1, (j + 1) % 3);
            }
        } else {
            for r in j.saturating_sub(1)..(j + 2).min(h) {
                self.row_max(pixels, r, r % 3);
            }
        }
        self.last = Some(j);
        let mid = &self.rows[j % 3];
        out.copy_from_slice(mid);
        if j > 0 {
            let up = &self.rows[(j - 1) % 3];
            for (o, &u) in out.iter_mut().zip(up) {
                *o = o.max(u);
            }
        }
        if j + 1 < h {
            let down = &self.rows[(j + 1) % 3];
            for (o, &d) in out.iter_mut().zip(down) {
                *o = o.max(d);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::frame::Frame;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    #[test]
    fn cell_centres_match_equirect_directions_and_pdf_lookup() {
        let (w, h) = (12, 7);
        for o in MapOrientation::ALL {
            let g = ImportanceGrid::from_fn(w, h, o, |d| 1.0 + d.x * 3.0 + d.y * d.y);
            for j in 0..h {
                for i in 0..w {
                    // The cell's centre in (θ, φ): u2 with cos θ at θ_centre.
                    let t0 = PI * j as f64 / h as f64;
                    let t1 = PI * (j + 1) as f64 / h as f64;
                    let tc = 0.5 * (t0 + t1);
                    let u2 = (t0.cos() - tc.cos()) / (t0.cos() - t1.cos());
                    let u0 = 0.5 * (g.row_cdf[j] + g.row_cdf[j + 1]);
                    let u1 = 0.5 * (g.col_cdf(j, i) + g.col_cdf(j, i + 1)) as f64 / COL_ONE as f64;
                    let (d, p) = g.sample([u0, u1, u2, 0.5]);
                    let want = equirect_direction(i, j, w, h, o);
                    assert!((d - want).length() < 1e-12, "{o:?} {i} {j}: {d} {want}");
                    let expect = g.cell_probability(i, j) / equirect_row_solid_angle(j, w, h);
                    assert!((p - expect).abs() <= 1e-15 * expect);
                    assert_eq!(g.pdf(d), p);
                }
            }
        }
    }

    #[test]
    fn probabilities_sum_to_one_and_follow_luminance_with_the_defensive_floor() {
        let (w, h) = (16, 8);
        let o = MapOrientation::default();
        let lum: Vec<f64> = (0..w * h).map(|k| if k < w { 5.0 } else { 0.0 }).collect();
        let g = ImportanceGrid::from_cell_luminance(w, h, o, &lum);
        let total: f64 = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| g.cell_probability(i, j))
            .sum();
        assert!((total - 1.0).abs() < 1e-14);
        // Dark cells get exactly the uniform share α Ω / 4π.
        let j = h - 1;
        let want = DEFENSIVE_FRACTION * equirect_row_solid_angle(j, w, h) / (4.0 * PI);
        assert!((g.cell_probability(3, j) - want).abs() < 1e-15);
        // Row 0 (the bright cells) holds the remaining 90% and its uniform share.
        let row0: f64 = (0..w).map(|i| g.cell_probability(i, 0)).sum();
        let floor0 = DEFENSIVE_FRACTION * w as f64 * equirect_row_solid_angle(0, w, h) / (4.0 * PI);
        assert!((row0 - (1.0 - DEFENSIVE_FRACTION) - floor0).abs() < 1e-14);
        // from_fn takes the largest value over centre and corners: a light
        // reaching just past row 1's top edge (θ = π/8) lights all of rows
        // 0 and 1, though row 1's centres are dark.
        for (reach, lit) in [(1e-3, true), (-1e-3, false)] {
            let c = (PI / 8.0 + reach).cos();
            let g = ImportanceGrid::from_fn(w, h, o, |d| if d.y > c { 5.0 } else { 0.0 });
            let p0 = g.cell_probability(5, 0) / equirect_row_solid_angle(0, w, h);
            let p1 = g.cell_probability(5, 1) / equirect_row_solid_angle(1, w, h);
            let p2 = g.cell_probability(5, 2) / equirect_row_solid_angle(2, w, h);
            // Equal cells agree to the column CDF's steps of 2^-32 of
            // their row (1e-8 of a cell here).
            let omega0 = equirect_row_solid_angle(0, w, h);
            assert!((g.cell_probability(2, 0) / p0 - omega0).abs() < 1e-8 * omega0);
            assert_eq!((p1 - p0).abs() < 1e-8 * p0, lit, "reach {reach}");
            assert!(p2 < 0.05 * p0);
        }
        // from_equirect dilates by one texel, wrapping around in φ.
        let mut px = vec![[0.0f32; 3]; w * h];
        px[3 * w] = [1.0, 1.0, 1.0];
        let g = ImportanceGrid::from_equirect(w, h, &px, o);
        let bright = g.cell_probability(0, 3);
        for (i, j) in [
            (w - 1, 2),
            (0, 2),
            (1, 2),
            (w - 1, 3),
            (1, 3),
            (w - 1, 4),
            (0, 4),
            (1, 4),
        ] {
            let p = g.cell_probability(i, j) / equirect_row_solid_angle(j, w, h);
            let pb = bright / equirect_row_solid_angle(3, w, h);
            assert!((p - pb).abs() < 1e-8 * pb, "{i} {j}");
        }
        assert!(g.cell_probability(2, 3) < 0.2 * bright);
        assert!(g.cell_probability(0, 5) < 0.2 * bright);
        // An all-dark grid is uniform.
        let u = ImportanceGrid::from_fn(w, h, o, |_| f64::NAN);
        assert!((u.pdf(DVec3::X) - 1.0 / (4.0 * PI)).abs() < 1e-15);
    }

    #[test]
    fn sampled_directions_have_the_stated_density() {
        // Histogram of samples per cell against P_ij.
        let (w, h) = (6, 4);
        for o in MapOrientation::ALL {
            let g = ImportanceGrid::from_fn(w, h, o, |d| (d.x + 2.0 * d.z).max(0.0));
            let mut rng = StdRng::seed_from_u64(7);
            let n = 200_000;
            let mut hits = vec![0usize; w * h];
            for _ in 0..n {
                let u: [f64; 4] = core::array::from_fn(|_| rng.random());
                let (d, p) = g.sample(u);
                assert!((d.length() - 1.0).abs() < 1e-14);
                assert_eq!(g.pdf(d), p);
                // Locate the cell from the conventions table, independently of `pdf`.
                let (t, mut ph) = match o.frame {
                    Frame::YUp => (d.y.clamp(-1.0, 1.0).acos(), d.z.atan2(d.x)),
                    Frame::ZUp => (d.z.clamp(-1.0, 1.0).acos(), (-d.y).atan2(d.x)),
                };
                if o.mirror {
                    ph = -ph;
                }
                let i = ((ph / (2.0 * PI) + 0.5) * w as f64) as usize;
                let j = (t / PI * h as f64) as usize;
                hits[j.min(h - 1) * w + i.min(w - 1)] += 1;
            }
            for k in 0..w * h {
                let p = g.cell_probability(k % w, k / w);
                let sd = (n as f64 * p * (1.0 - p)).sqrt();
                assert!(
                    (hits[k] as f64 - n as f64 * p).abs() < 5.0 * sd + 1.0,
                    "{o:?} cell {k}"
                );
            }
        }
    }

    /// The grid over a map's texels, built row by row, equals the grid of
    /// the 3x3 maximum computed over the whole map at once (the brute-force
    /// route: a table of luminance, the maximum of each texel's nine
    /// neighbours, columns wrapping, rows stopping at the poles), table for
    /// table, with NaN, infinite and negative texels, on every size from
    /// one row and one column up.
    #[test]
    fn the_rolling_maximum_gives_the_whole_table_grid() {
        for (w, h) in [(1, 1), (3, 1), (1, 4), (2, 2), (7, 5), (16, 9)] {
            let mut pixels: Vec<[f32; 3]> = (0..w * h)
                .map(|k| [((k * 37) % 11) as f32, ((k * 13) % 7) as f32 * 0.5, 1.0])
                .collect();
            if w * h > 5 {
                pixels[2] = [f32::NAN, 1.0, 1.0];
                pixels[w * h - 1] = [f32::INFINITY, 0.0, 0.0];
                pixels[w * h / 2] = [-40.0, 0.0, 0.0];
            }
            let lum: Vec<f64> = pixels
                .iter()
                .map(|p| {
                    let y = luminance(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
                    if y.is_nan() { f64::NEG_INFINITY } else { y }
                })
                .collect();
            let mut max = vec![f64::NEG_INFINITY; w * h];
            for j in 0..h {
                for i in 0..w {
                    for dj in [-1_isize, 0, 1] {
                        let jj = j as isize + dj;
                        if jj < 0 || jj >= h as isize {
                            continue;
                        }
                        for di in [w - 1, 0, 1] {
                            let v = lum[jj as usize * w + (i + di) % w];
                            max[j * w + i] = max[j * w + i].max(v);
                        }
                    }
                }
            }
            let o = MapOrientation::default();
            assert_eq!(
                ImportanceGrid::from_equirect(w, h, &pixels, o),
                ImportanceGrid::from_cell_luminance(w, h, o, &max),
                "{w}x{h}"
            );
        }
    }
}

//! Equirectangular (latitude-longitude) geometry: the borrowed image
//! [`EquirectView`], texel centre angles and directions, and the exact solid
//! angle of a texel of each row.
//!
//! A `W x H` map has texel `(x, y)` centred at `u = (x+.5)/W`,
//! `v = (y+.5)/H`, `θ = π v`, `φ = 2π (u - .5)`; in the map's own y-up frame
//! its direction is `(sin θ cos φ, cos θ, sin θ sin φ)` (docs/conventions.md),
//! taken to the world by a [`MapOrientation`]. Every texel of row `j` covers
//! `Ω_j = (2π/W)(cos(jπ/H) - cos((j+1)π/H))`, and the rows sum to exactly `4π`.

use core::f64::consts::PI;

use glam::DVec3;

use crate::map::orientation::MapOrientation;

/// A borrowed equirectangular map: `width x height` texels, row-major from
/// the top-left corner, linear RGB.
#[derive(Clone, Copy, Debug)]
pub struct EquirectView<'a> {
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` linear RGB texels.
    pub pixels: &'a [[f32; 3]],
}

/// Texel centre angles `(θ, φ)` of equirect texel `(x, y)` in a `w x h` map:
/// `u = (x+.5)/w`, `v = (y+.5)/h`, `θ = π v`, `φ = 2π (u - .5)`.
#[inline]
#[must_use]
pub fn equirect_angles(x: usize, y: usize, w: usize, h: usize) -> (f64, f64) {
    let u = (x as f64 + 0.5) / w as f64;
    let v = (y as f64 + 0.5) / h as f64;
    (PI * v, 2.0 * PI * (u - 0.5))
}

/// World direction of the centre of equirect texel `(x, y)`.
#[must_use]
pub fn equirect_direction(x: usize, y: usize, w: usize, h: usize, o: MapOrientation) -> DVec3 {
    let (t, p) = equirect_angles(x, y, w, h);
    o.frame.direction(t, if o.mirror { -p } else { p })
}

/// Exact solid angle of one texel in row `j` of a `w x h` equirect map:
/// `(2π/w)(cos(jπ/h) - cos((j+1)π/h))`.
#[must_use]
pub fn equirect_row_solid_angle(j: usize, w: usize, h: usize) -> f64 {
    let t0 = PI * j as f64 / h as f64;
    let t1 = PI * (j + 1) as f64 / h as f64;
    // cos a - cos b = 2 sin((a+b)/2) sin((b-a)/2), without cancellation.
    2.0 * PI / w as f64 * 2.0 * ((t0 + t1) / 2.0).sin() * ((t1 - t0) / 2.0).sin()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_solid_angles_sum_to_four_pi() {
        for (w, h) in [(8, 4), (64, 32), (2048, 1024)] {
            let total: f64 = (0..h)
                .map(|j| w as f64 * equirect_row_solid_angle(j, w, h))
                .sum();
            assert!((total - 4.0 * PI).abs() < 1e-12, "{w}x{h}");
        }
    }
}

//! [`equirect_texel_means`]: an equirect map whose every texel holds a
//! function's **mean over the texel** (not its value at the centre), the
//! form in which a light with edges (a sun, a lamp) is drawn so that its
//! power in the map is its exact power up to the sub-sampling.
//!
//! Texel `(x, y)` of a `W x H` map covers `φ ∈ 2π [x/W - 1/2, (x+1)/W - 1/2]`
//! and `cos θ ∈ [cos(yπ/H), cos((y+1)π/H)]`; `n x n` points at the centres
//! of an `n x n` grid **uniform in `φ` and `cos θ`** split it into equal
//! solid angles, so their plain average is the texel mean to the midpoint
//! rule's accuracy (the same sub-sampling as `shlight synth`).

use core::f64::consts::PI;

use glam::DVec3;

use crate::orientation::MapOrientation;

/// A `width x height` equirect map (read in `orientation`) of the means of
/// `f` over each texel, from `n x n` equal-area points per texel (module
/// docs). `n = 0` is taken as 1.
#[must_use]
pub fn equirect_texel_means(
    width: usize,
    height: usize,
    orientation: MapOrientation,
    n: usize,
    f: impl Fn(DVec3) -> DVec3 + Sync,
) -> Vec<[f32; 3]> {
    let n = n.max(1);
    let mut pixels = vec![[0.0f32; 3]; width * height];
    let row = |(y, out): (usize, &mut [[f32; 3]])| {
        let z0 = (PI * y as f64 / height as f64).cos();
        let z1 = (PI * (y + 1) as f64 / height as f64).cos();
        for (x, px) in out.iter_mut().enumerate() {
            let mut sum = DVec3::ZERO;
            for i in 0..n {
                let s = (i as f64 + 0.5) / n as f64;
                let phi = 2.0 * PI * ((x as f64 + s) / width as f64 - 0.5);
                let phi = if orientation.mirror { -phi } else { phi };
                for j in 0..n {
                    let t = (j as f64 + 0.5) / n as f64;
                    let theta = (z0 + (z1 - z0) * t).clamp(-1.0, 1.0).acos();
                    sum += f(orientation.frame.direction(theta, phi));
                }
            }
            *px = (sum / (n * n) as f64).as_vec3().to_array();
        }
    };
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        pixels.par_chunks_mut(width).enumerate().for_each(row);
    }
    #[cfg(not(feature = "rayon"))]
    pixels.chunks_mut(width).enumerate().for_each(row);
    pixels
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::equirect::equirect_row_solid_angle;

    #[test]
    fn a_caps_power_converges_to_its_exact_power() {
        // Power Σ mean Ω of a unit cap of half-angle 2° against 2π(1 - cos a).
        let axis = DVec3::new(0.3, 0.7, -0.2).normalize();
        let a = 2f64.to_radians();
        let exact = 4.0 * PI * (a / 2.0).sin().powi(2);
        let (w, h) = (512, 256);
        let mut errors = Vec::new();
        for n in [2, 8, 32] {
            let px = equirect_texel_means(w, h, MapOrientation::default(), n, |d| {
                DVec3::splat(if d.dot(axis) >= a.cos() { 1.0 } else { 0.0 })
            });
            let power: f64 = px
                .iter()
                .enumerate()
                .map(|(k, p)| f64::from(p[0]) * equirect_row_solid_angle(k / w, w, h))
                .sum();
            errors.push((power / exact - 1.0).abs());
        }
        // Measured: the error falls with n (edge texels resolved finer).
        assert!(errors[2] < 2e-3 && errors[2] < errors[0], "{errors:?}");
    }
}

//! A picture of a volume's probes: each probe drawn as a diffuse white ball
//! lit by its light, the grid laid out one z layer after another, and the
//! exposure to show it at ([`probe_sheet_exposure`]).

use glam::{DVec3, Vec3};
use shlight_core::sh::{ShCoeffs, irradiance, sh_count};

use shlight_baked::VolumeView;

/// Shaded colour of invalid probes (a flat mid grey).
pub(crate) const INVALID: [f32; 3] = [0.18, 0.18, 0.18];

/// The exposure in stops for a [`probe_sheet`]'s pixels: the mean
/// luminance of the pixels that are not black (the balls, not the
/// background) at 0.25, as the PRT preview
/// ([`shlight_prt::vertex_exposure`]).
#[must_use]
pub fn probe_sheet_exposure(pixels: &[[f32; 3]]) -> f32 {
    let lit: Vec<Vec3> = pixels
        .iter()
        .map(|p| Vec3::from_array(*p))
        .filter(|p| *p != Vec3::ZERO)
        .collect();
    shlight_prt::vertex_exposure(&lit)
}

/// The lit probes of `view` as an image of `(width, height, pixels)`,
/// row-major from the top.
///
/// Each probe is a disc of `ball` pixels across: the ball of a white
/// Lambertian surface seen from +Z (x to the right, y up), each pixel the
/// exit radiance `E(n) / pi` for its normal `n`, `E` the probe's SH
/// irradiance (R&H). The z layers are side by side from left to right
/// (z = 0 first), each layer's probes at x across and y up, with a gap of a
/// quarter ball. Invalid probes are flat mid-grey discs (0.18). Background
/// black.
#[must_use]
pub fn probe_sheet(view: &VolumeView<'_>, ball: usize) -> (usize, usize, Vec<[f32; 3]>) {
    let VolumeView {
        grid,
        lmax,
        valid,
        radiance,
        ..
    } = *view;
    let ball = ball.max(3);
    let gap = (ball / 4).max(1);
    let cell = ball + gap;
    let [nx, ny, nz] = grid.resolution;
    let layer_width = nx * cell + gap;
    let (width, height) = (nz * layer_width + gap, ny * cell + gap);
    let mut pixels = vec![[0.0f32; 3]; width * height];
    let nc = sh_count(lmax);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let i = grid.index([x, y, z]);
                let e = irradiance(
                    &ShCoeffs::from_vec(
                        radiance[i * 3 * nc..][..3 * nc]
                            .chunks_exact(3)
                            .map(|c| Vec3::from_slice(c).as_dvec3())
                            .collect(),
                    )
                    .expect("(lmax+1)^2 rows"),
                );
                let (left, top) = (z * layer_width + gap + x * cell, gap + (ny - 1 - y) * cell);
                let r = ball as f64 / 2.0;
                for py in 0..ball {
                    for px in 0..ball {
                        let u = (px as f64 + 0.5 - r) / r;
                        let v = (r - py as f64 - 0.5) / r;
                        let rr = u * u + v * v;
                        if rr > 1.0 {
                            continue;
                        }
                        let colour = if valid[i] {
                            let n = DVec3::new(u, v, (1.0 - rr).sqrt());
                            (e.eval(n) / std::f64::consts::PI)
                                .max(DVec3::ZERO)
                                .as_vec3()
                                .to_array()
                        } else {
                            INVALID
                        };
                        pixels[(top + py) * width + left + px] = colour;
                    }
                }
            }
        }
    }
    (width, height, pixels)
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_baked::ProbeGrid;
    use shlight_core::sh::closed_form;

    /// `grid`'s probes with `radiance`, every probe at its centre.
    fn view<'a>(
        grid: ProbeGrid,
        valid: &'a [bool],
        radiance: &'a [f32],
        lmax: usize,
    ) -> VolumeView<'a> {
        VolumeView {
            grid,
            lmax,
            valid,
            radiance,
            offsets: None,
            visibility: None,
        }
    }

    /// The background does not darken the picture: a sheet of balls of
    /// luminance 1 on black is shown at 0.25 whatever the black around.
    #[test]
    fn the_exposure_ignores_the_background() {
        let ball = [1.0f32; 3];
        let few = [ball, [0.0; 3], [0.0; 3], [0.0; 3]];
        assert_eq!(probe_sheet_exposure(&few), -2.0);
        assert_eq!(probe_sheet_exposure(&[ball; 2]), -2.0);
        assert_eq!(probe_sheet_exposure(&[[0.0; 3]; 4]), 0.0);
    }

    #[test]
    fn each_ball_shows_its_probes_light_where_the_layout_says() {
        let grid = ProbeGrid::new([2, 2, 2], Vec3::ZERO, Vec3::ONE).unwrap();
        let lmax = 2;
        // Probe i lit by constant radiance i + 1: E = pi (i + 1) everywhere,
        // so its ball shows i + 1 at every pixel.
        let mut radiance = Vec::new();
        for i in 0..8 {
            for c in closed_form::constant(lmax, DVec3::splat(i as f64 + 1.0)).as_slice() {
                radiance.extend(c.as_vec3().to_array());
            }
        }
        let mut valid = vec![true; 8];
        valid[5] = false;
        let ball = 16;
        let (w, h, pixels) = probe_sheet(&view(grid, &valid, &radiance, lmax), ball);
        let (gap, cell) = (4, 20);
        assert_eq!((w, h), (2 * (2 * cell + gap) + gap, 2 * cell + gap));
        for z in 0..2 {
            for y in 0..2 {
                for x in 0..2 {
                    let i = grid.index([x, y, z]);
                    let cx = z * (2 * cell + gap) + gap + x * cell + ball / 2;
                    let cy = gap + (1 - y) * cell + ball / 2;
                    let want = if valid[i] {
                        [i as f32 + 1.0; 3]
                    } else {
                        INVALID
                    };
                    let got = pixels[cy * w + cx];
                    assert!(
                        (0..3).all(|c| (got[c] - want[c]).abs() < 1e-4),
                        "probe {i}: {got:?}"
                    );
                }
            }
        }
        assert_eq!(pixels[0], [0.0; 3], "background");
    }

    #[test]
    fn a_ball_under_a_light_from_above_is_brighter_at_its_top() {
        let grid = ProbeGrid::new([1, 1, 1], Vec3::ZERO, Vec3::ONE).unwrap();
        let lmax = 2;
        let light = closed_form::cosine_lobe(lmax, DVec3::Y, DVec3::ONE);
        let radiance: Vec<f32> = light
            .as_slice()
            .iter()
            .flat_map(|c| c.as_vec3().to_array())
            .collect();
        let (w, _, pixels) = probe_sheet(&view(grid, &[true], &radiance, lmax), 32);
        let (top, bottom) = (pixels[(8 + 3) * w + 8 + 16], pixels[(8 + 29) * w + 8 + 16]);
        let e = irradiance(&light);
        assert!(top[0] > 2.0 * bottom[0]);
        // The top pixel's normal, from its place on the disc.
        let v = (16.0 - 3.5) / 16.0;
        let n = DVec3::new(
            0.5 / 16.0,
            v,
            (1.0f64 - v * v - (0.5f64 / 16.0).powi(2)).sqrt(),
        );
        assert!((f64::from(top[0]) - e.eval(n).x / std::f64::consts::PI).abs() < 1e-4);
    }
}

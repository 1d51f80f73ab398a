//! [`directional_texels`]: a directional light (a delta) drawn into a map.

use core::f64::consts::{FRAC_PI_2, PI};

use glam::DVec3;

use crate::map::analytic_light::AnalyticLight;
use crate::map::layout::texel_grid::TexelGrid;
use crate::map::texel_means::texel_means;
use crate::sh::zonal::cap_solid_angle;

/// How [`directional_texels`] drew the light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DirectionalDrawing {
    /// A cap of the half-angle asked for, normalised to its exact power.
    Cap,
    /// All of it in texel `(x, y)`.
    Texel {
        /// Column.
        x: usize,
        /// Row.
        y: usize,
        /// The direction of the texel's centre, where a projection puts
        /// the delta.
        centre: DVec3,
        /// The angle (radians) between `centre` and the direction asked for.
        offset: f64,
        /// A cap was asked for but it is smaller than the texels can
        /// resolve (it covered no point).
        unresolved_cap: bool,
    },
}

/// A map of a directional light: its texels and how it was drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalTexels {
    /// `width * height` texels, row-major.
    pub pixels: Vec<[f32; 3]>,
    /// One texel or a cap.
    pub drawing: DirectionalDrawing,
}

/// A directional light from unit `axis` of irradiance `irradiance` (facing
/// it) drawn into `grid`: in one texel when `half_angle` (radians) is 0, or
/// as a cap normalised to its exact power (below) with `n x n`
/// points per texel (at least 8). `on_rows` is called with the number of
/// rows finished (a progress bar), `grid.height()` rows in all.
///
/// # Panics
/// If `half_angle` is not within `0..=π/2`.
///
/// # Drawing a delta
///
/// A delta cannot be stored in texels. It is approximated in one of two
/// ways, both keeping its irradiance `E` facing it:
///
/// - half-angle `0`: all of it in the single texel `k` that the direction
///   falls in ([`TexelGrid::texel_of`]), with radiance `E / Ω_k`. A
///   projection at texel centres then gives exactly the delta at that
///   texel's centre, `E Y_l^m(d_k)`; the centre is at most half a texel
///   from the direction asked for ([`DirectionalDrawing::Texel`] says
///   where).
/// - half-angle `0 < α <= π/2`: a uniform cap of half-angle `α` whose
///   radiance `L = E / (π sin² α)` gives irradiance `E` facing it (past
///   `π/2` the cap covers the whole hemisphere facing it, whose irradiance
///   is `π L` whatever `L` is spread beyond it, so larger caps are refused); its coefficients
///   are [`crate::sh::closed_form::cap`]'s and differ from the delta's by about
///   `l(l+1) α² / 4` relatively in degree `l`. The cap is drawn as texel
///   means ([`crate::map::texel_means()`], at least `8 x 8` points per equirect
///   texel) and then scaled so that its power `Σ L_k Ω_k` is the cap's
///   exact `2π(1 - cos α) L = 4π sin²(α/2) L`. A cap that misses every
///   point falls back to one texel.
#[must_use]
pub fn directional_texels(
    grid: &TexelGrid,
    axis: DVec3,
    irradiance: DVec3,
    half_angle: f64,
    n: usize,
    on_rows: &(dyn Fn(usize) + Sync),
) -> DirectionalTexels {
    assert!(
        (0.0..=FRAC_PI_2).contains(&half_angle),
        "a directional light's half-angle must be within 0..=π/2, not {half_angle}"
    );
    let (w, h) = (grid.width(), grid.height());
    let mut unresolved_cap = false;
    if half_angle > 0.0 {
        let sin2 = half_angle.sin().powi(2);
        let radiance = irradiance / (PI * sin2);
        let cap = AnalyticLight::Cap {
            axis,
            cos_half: half_angle.cos(),
            radiance: DVec3::ONE,
        };
        let coverage = texel_means(grid, n.max(8), |d| cap.radiance(d), on_rows);
        let power: f64 = coverage
            .iter()
            .zip(grid.solid_angles())
            .map(|(c, omega)| f64::from(c[0]) * omega)
            .sum();
        if power > 0.0 {
            let scale = cap_solid_angle(half_angle) / power;
            let pixels = coverage
                .into_iter()
                .map(|px| {
                    let c = f64::from(px[0]) * scale;
                    (radiance * c).as_vec3().to_array()
                })
                .collect();
            return DirectionalTexels {
                pixels,
                drawing: DirectionalDrawing::Cap,
            };
        }
        unresolved_cap = true;
    }
    let (x, y) = grid.texel_of(axis);
    let centre = grid.direction(x, y).unwrap_or(axis);
    let radiance = irradiance / grid.solid_angle(x, y);
    let mut pixels = vec![[0.0f32; 3]; w * h];
    pixels[y * w + x] = radiance.as_vec3().to_array();
    if !unresolved_cap {
        // The cap's texel means have already counted every row.
        on_rows(h);
    }
    DirectionalTexels {
        pixels,
        drawing: DirectionalDrawing::Texel {
            x,
            y,
            centre,
            offset: centre.angle_between(axis),
            unresolved_cap,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::layout::env_map::EnvMap;
    use crate::map::layout::kind::Layout;
    use crate::map::orientation::MapOrientation;
    use crate::map::projection::project_map;
    use crate::sh::closed_form;
    use crate::sh::frame::Frame;
    use crate::test_util::max_diff;

    /// On a texel centre the one-texel light projects to exactly the
    /// delta's coefficients `E Y_l^m(d)` (but for the f32 texel), in every
    /// layout; off a centre it says which texel and how far.
    #[test]
    fn one_texel_is_the_delta_at_its_centre() {
        let e = DVec3::new(5.0, 4.5, 4.0);
        for layout in [Layout::Equirect, Layout::CrossHorizontal, Layout::Angular] {
            let o = MapOrientation {
                frame: Frame::ZUp,
                mirror: true,
            };
            let (w, h) = layout.dimensions(16);
            let grid = TexelGrid::new(layout, (w, h), o).unwrap();
            let d = grid.direction(w / 2 + 1, h / 2 - 1).unwrap();
            let drawn = directional_texels(&grid, d, e, 0.0, 4, &|_| {});
            let DirectionalDrawing::Texel {
                x,
                y,
                offset,
                unresolved_cap,
                ..
            } = drawn.drawing
            else {
                panic!("{layout:?}: {:?}", drawn.drawing);
            };
            assert_eq!((x, y), (w / 2 + 1, h / 2 - 1));
            assert!(offset < 1e-9 && !unresolved_cap);
            assert_eq!(drawn.pixels.iter().filter(|p| **p != [0.0; 3]).count(), 1);
            let map = EnvMap::new(layout, o, w, h, &drawn.pixels).unwrap();
            let got = project_map(&map, 4);
            let err = max_diff(got.as_slice(), closed_form::directional(4, d, e).as_slice());
            assert!(err < 1e-6 * 5.0, "{layout:?}: {err}");
        }
        let grid = TexelGrid::new(Layout::Equirect, (32, 16), MapOrientation::default()).unwrap();
        let axis = DVec3::new(0.3, 0.4, 0.5).normalize();
        let drawn = directional_texels(&grid, axis, DVec3::ONE, 0.0, 4, &|_| {});
        let DirectionalDrawing::Texel {
            x,
            y,
            centre,
            offset,
            ..
        } = drawn.drawing
        else {
            panic!("{:?}", drawn.drawing);
        };
        assert_eq!(grid.texel_of(axis), (x, y));
        assert_eq!(grid.direction(x, y), Some(centre));
        // Within a texel's half-diagonal (π/16 rows, 2π/32 columns here).
        assert!(offset > 1e-9 && offset < 0.2, "{offset}");
    }

    /// A cap's power `Σ L Ω` is its exact `2π(1 - cos α) L`, with
    /// `L = E / (π sin² α)`, and its projection is near the closed-form cap
    /// of that radiance.
    #[test]
    fn a_cap_keeps_its_exact_power() {
        let (w, h) = (256, 128);
        let o = MapOrientation::default();
        let grid = TexelGrid::new(Layout::Equirect, (w, h), o).unwrap();
        let axis = DVec3::new(0.2, 0.9, -0.3).normalize();
        let e = DVec3::new(2.0, 1.0, 0.5);
        let a = 4f64.to_radians();
        let drawn = directional_texels(&grid, axis, e, a, 4, &|_| {});
        assert_eq!(drawn.drawing, DirectionalDrawing::Cap);
        let radiance = e / (PI * a.sin().powi(2));
        let power: DVec3 = (0..w * h)
            .map(|k| DVec3::from(drawn.pixels[k].map(f64::from)) * grid.solid_angle(k % w, k / w))
            .sum();
        let exact = radiance * 2.0 * PI * (1.0 - a.cos());
        assert!(
            ((power - exact) / exact).abs().max_element() < 1e-6,
            "{power} {exact}"
        );
        let map = EnvMap::new(Layout::Equirect, o, w, h, &drawn.pixels).unwrap();
        let got = project_map(&map, 2);
        let err = max_diff(
            got.as_slice(),
            closed_form::cap(2, axis, a, radiance).as_slice(),
        );
        // Measured 2e-4 of coefficients near 0.5 (edge texels only).
        assert!(err < 2e-3, "{err}");
    }

    /// A cap far smaller than a texel between the sample points falls back
    /// to one texel and says so.
    #[test]
    fn an_unresolved_cap_is_one_texel() {
        let grid = TexelGrid::new(Layout::Equirect, (16, 8), MapOrientation::default()).unwrap();
        let axis = grid.sample(3, 2, 0.03, 0.03).unwrap();
        let drawn = directional_texels(&grid, axis, DVec3::ONE, 1e-4, 1, &|_| {});
        assert!(matches!(
            drawn.drawing,
            DirectionalDrawing::Texel {
                x: 3,
                y: 2,
                unresolved_cap: true,
                ..
            }
        ));
    }

    /// Each row is reported once, whichever way the light is drawn.
    #[test]
    fn progress_counts_every_row_once() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let grid = TexelGrid::new(Layout::Equirect, (16, 8), MapOrientation::default()).unwrap();
        let axis = grid.sample(3, 2, 0.03, 0.03).unwrap();
        // One texel, a resolved cap, a cap too small to resolve.
        for half_angle in [0.0, 0.5, 1e-4] {
            let rows = AtomicUsize::new(0);
            let _ = directional_texels(&grid, axis, DVec3::ONE, half_angle, 1, &|n| {
                rows.fetch_add(n, Ordering::Relaxed);
            });
            assert_eq!(rows.into_inner(), 8, "half-angle {half_angle}");
        }
    }
}

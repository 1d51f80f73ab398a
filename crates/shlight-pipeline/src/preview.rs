//! [`write_preview`]: the picture `shlight project --preview` judges a
//! projection by.
//!
//! Three equirect panels of the same size, side by side, left to right, in
//! the input's frame and under one exposure and tone map:
//!
//! 1. the input map: an equirect map box-filtered to the panel size
//!    ([`Image::resample`]); another layout looked up bilinearly
//!    ([`shlight_core::map::EnvMap::radiance_bilinear`]) at each panel texel's centre;
//! 2. the SH reconstruction of its radiance, `Σ L_l^m Y_l^m(d)` at each
//!    texel centre ([`render_map`]): ringing and lost detail show here;
//! 3. the SH irradiance divided by π, `Σ A_l L_l^m Y_l^m(n) / π`: the
//!    radiance of a white Lambertian surface facing each direction.
//!
//! The default exposure ([`preview_exposure`]) puts the map's mean
//! radiance, `L_0^0 / (2 sqrt π)` (luminance-weighted), at 0.18, so panel 3
//! of a uniform light is mid grey.

use std::f64::consts::PI;
use std::path::Path;

use glam::DVec3;
use shlight_core::map::{Layout, MapOrientation, luminance, render_map as draw};
use shlight_core::sh::{ShCoeffs, irradiance};
use shlight_io::{Image, ToneMap, WriteOptions, auto_exposure, write_image};

use crate::load::env_map;
use crate::output_grid::output_grid;
use crate::render::render_map;
use crate::{PipelineError, Result};

/// How the preview is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreviewOptions {
    /// Size of each of the three panels (2:1).
    pub panel: (usize, usize),
    /// Exposure in stops; `None`: [`preview_exposure`].
    pub exposure: Option<f32>,
    /// Tone map for PNG.
    pub tone_map: ToneMap,
}

/// The stops that bring the mean radiance's luminance,
/// `luminance(L_0^0 / (2 sqrt π))`, to 0.18 (0 for a dark map).
#[must_use]
pub fn preview_exposure(radiance: &ShCoeffs<DVec3>) -> f32 {
    let mean = radiance[0] / (2.0 * PI.sqrt());
    auto_exposure(luminance(mean), 0.18)
}

/// The three panels (module docs) of `input`, a map of `layout` read in
/// `orientation`, and its radiance coefficients, each `panel` in size:
/// one `3 pw x ph` image.
///
/// # Errors
/// A panel that is not 2:1, or an input whose size does not fit `layout`.
pub fn preview_image(
    input: &Image,
    layout: Layout,
    radiance: &ShCoeffs<DVec3>,
    orientation: MapOrientation,
    panel: (usize, usize),
) -> Result<Image> {
    output_grid(Layout::Equirect, panel, orientation)?;
    let (pw, ph) = panel;
    let shown = match layout {
        Layout::Equirect => input.resample(pw, ph),
        other => {
            let size = (input.width(), input.height());
            let map = env_map(other, orientation, size, input.pixels())?;
            let pixels = draw(Layout::Equirect, orientation, pw, ph, |d| {
                map.radiance_bilinear(d)
            })
            .map_err(|e| PipelineError::new(e.to_string()))?;
            Image::new(pw, ph, pixels).map_err(|e| PipelineError::new(e.to_string()))?
        }
    };
    let lambert = irradiance(radiance).scaled(1.0 / PI);
    let panels = [
        shown,
        render_map(radiance, Layout::Equirect, panel, orientation, &|| {})?,
        render_map(&lambert, Layout::Equirect, panel, orientation, &|| {})?,
    ];
    Ok(Image::from_fn(3 * pw, ph, |x, y| {
        panels[x / pw].get(x % pw, y)
    }))
}

/// Writes [`preview_image`] to `path` (any format shlight writes) under
/// `options`' exposure (default [`preview_exposure`]) and tone map.
///
/// # Errors
/// As [`preview_image`], and the file cannot be written.
pub fn write_preview(
    path: &Path,
    input: &Image,
    layout: Layout,
    radiance: &ShCoeffs<DVec3>,
    orientation: MapOrientation,
    options: &PreviewOptions,
) -> Result<()> {
    let image = preview_image(input, layout, radiance, orientation, options.panel)?;
    let exposure = options
        .exposure
        .unwrap_or_else(|| preview_exposure(radiance));
    write_image(
        path,
        &image,
        &WriteOptions {
            exposure_ev: exposure,
            tone_map: options.tone_map,
            ..WriteOptions::default()
        },
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_core::sh::closed_form;

    /// A uniform light: every panel of a `(8, 4)` preview is the radiance
    /// (input and reconstruction) or the irradiance over π, which for a
    /// uniform light is the radiance again; the exposure puts it at 0.18.
    #[test]
    fn a_uniform_light_is_the_same_in_every_panel() {
        let c = [0.5f32, 0.25, 1.0];
        let o = MapOrientation::default();
        let radiance = closed_form::constant(2, DVec3::from(c.map(f64::from)));
        for (layout, size) in [
            (Layout::Equirect, (16, 8)),
            (Layout::CrossHorizontal, (16, 12)),
        ] {
            let input = Image::from_fn(size.0, size.1, |_, _| c);
            let image = preview_image(&input, layout, &radiance, o, (8, 4)).unwrap();
            assert_eq!((image.width(), image.height()), (24, 4));
            for y in 0..4 {
                for x in 0..24 {
                    let got = image.get(x, y);
                    for k in 0..3 {
                        assert!((got[k] - c[k]).abs() < 1e-5, "{layout:?} {x} {y}: {got:?}");
                    }
                }
            }
        }
        let lum = 0.2126 * 0.5 + 0.7152 * 0.25 + 0.0722;
        let ev = preview_exposure(&radiance);
        assert!((f64::from(ev).exp2() * lum - 0.18).abs() < 1e-6, "{ev}");
        assert_eq!(preview_exposure(&ShCoeffs::zeros(2)), 0.0);
        let e = preview_image(
            &Image::from_fn(16, 8, |_, _| c),
            Layout::Equirect,
            &radiance,
            o,
            (8, 8),
        )
        .unwrap_err();
        assert!(e.message().contains("twice its height"), "{e}");
    }

    /// The middle panel is the render of the coefficients, the right one
    /// the irradiance's over π (a directional light: `A_l Y(d) / π`).
    #[test]
    fn the_panels_are_the_radiance_and_the_lambertian_radiance() {
        let o = MapOrientation::default();
        let d = DVec3::new(0.3, 0.8, 0.2).normalize();
        let radiance = closed_form::directional(3, d, DVec3::new(1.0, 2.0, 3.0));
        let input = Image::from_fn(32, 16, |_, _| [0.0; 3]);
        let image = preview_image(&input, Layout::Equirect, &radiance, o, (32, 16)).unwrap();
        let grid = output_grid(Layout::Equirect, (32, 16), o).unwrap();
        let lambert = irradiance(&radiance).scaled(1.0 / PI);
        for y in 0..16 {
            for x in 0..32 {
                let n = grid.direction(x, y).unwrap();
                let sh = DVec3::from(image.get(32 + x, y).map(f64::from));
                let e = DVec3::from(image.get(64 + x, y).map(f64::from));
                assert!((sh - radiance.eval(n)).abs().max_element() < 1e-5);
                assert!((e - lambert.eval(n)).abs().max_element() < 1e-5);
                assert_eq!(image.get(x, y), [0.0; 3]);
            }
        }
    }
}

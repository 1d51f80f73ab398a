//! `shlight project --preview FILE.png`: a picture to judge a projection by.
//!
//! Three equirect panels of the same size, side by side, left to right, in
//! the input's frame and under one exposure and tone map:
//!
//! 1. the input map (box-filtered to the panel size),
//! 2. the SH reconstruction of its radiance (after the window, before
//!    `--rotate`): ringing and lost detail show here,
//! 3. the SH irradiance divided by π: the radiance of a white Lambertian
//!    surface facing each direction.
//!
//! The default exposure puts the map's mean radiance (`L_0^0 / (2 sqrt π)`,
//! luminance-weighted) at 0.18, so panel 3 of a uniform light is mid grey.

use std::path::Path;

use anyhow::{Result, anyhow};
use glam::DVec3;
use indicatif::ProgressBar;
use shlight_core::layout::{EnvMap, Layout};
use shlight_core::projection::MapOrientation;
use shlight_core::{ShCoeffs, irradiance};
use shlight_io::{Image, ToneMap, WriteOptions, write_image};

use crate::render::render;
use crate::texels::{LayoutArg, TexelGrid};

/// How the preview is drawn.
#[derive(Clone, Copy, Debug)]
pub struct PreviewOptions {
    /// Size of each of the three panels.
    pub panel: (usize, usize),
    /// Exposure in stops; `None`: the mean radiance at 0.18.
    pub exposure: Option<f32>,
    /// Tone map for PNG.
    pub tone_map: ToneMap,
}

/// Writes the three-panel preview of `input` (an equirect map read with
/// `orientation`) and its radiance coefficients to `path`.
pub fn write_preview(
    path: &Path,
    input: &Image,
    radiance: &ShCoeffs<DVec3>,
    orientation: MapOrientation,
    options: &PreviewOptions,
) -> Result<()> {
    let grid = TexelGrid::new(LayoutArg::Equirect, options.panel, orientation)?;
    let (pw, ph) = options.panel;
    let panels = [
        resample(input, pw, ph),
        render(radiance, &grid, &ProgressBar::hidden()),
        {
            let lambert = irradiance(radiance).scaled(1.0 / std::f64::consts::PI);
            render(&lambert, &grid, &ProgressBar::hidden())
        },
    ];
    let image = Image::from_fn(3 * pw, ph, |x, y| panels[x / pw].get(x % pw, y));
    let exposure = options.exposure.unwrap_or_else(|| auto_exposure(radiance));
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

/// An equirect panel of `panel` size showing a map in another layout,
/// looked up bilinearly at each texel centre, for `--preview`.
pub fn equirect_panel(
    image: &Image,
    layout: Layout,
    orientation: MapOrientation,
    panel: (usize, usize),
) -> Result<Image> {
    let map = EnvMap::new(
        layout,
        orientation,
        image.width(),
        image.height(),
        image.pixels(),
    )
    .map_err(|e| anyhow!("{e}"))?;
    let grid = TexelGrid::new(LayoutArg::Equirect, panel, orientation)?;
    Ok(Image::from_fn(grid.width, grid.height, |x, y| {
        let d = grid.direction(x, y).unwrap_or(DVec3::Y);
        map.radiance_bilinear(d).as_vec3().to_array()
    }))
}

/// Stops that bring the mean radiance's luminance to 0.18 (0 for a dark map).
pub fn auto_exposure(radiance: &ShCoeffs<DVec3>) -> f32 {
    let mean = radiance[0] / (2.0 * std::f64::consts::PI.sqrt());
    let luminance = mean.dot(DVec3::new(0.2126, 0.7152, 0.0722));
    if luminance > 0.0 && luminance.is_finite() {
        (0.18 / luminance).log2() as f32
    } else {
        0.0
    }
}

/// `image` brought to `w x h`: each output texel the mean of the input
/// texels whose block it covers (at least one; nearest when enlarging).
fn resample(image: &Image, w: usize, h: usize) -> Image {
    let (iw, ih) = (image.width(), image.height());
    let span = |o: usize, n: usize, total: usize| {
        let a = o * total / n;
        let b = ((o + 1) * total / n).max(a + 1).min(total);
        a..b
    };
    Image::from_fn(w, h, |x, y| {
        let mut sum = [0.0f64; 3];
        let mut count = 0.0;
        for yy in span(y, h, ih) {
            for px in &image.row(yy)[span(x, w, iw)] {
                for c in 0..3 {
                    sum[c] += f64::from(px[c]);
                }
                count += 1.0;
            }
        }
        sum.map(|s| (s / count) as f32)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_averages_blocks_and_repeats_when_enlarging() {
        let img = Image::from_fn(4, 2, |x, y| [(x + 4 * y) as f32; 3]);
        let small = resample(&img, 2, 1);
        assert_eq!(small.get(0, 0)[0], (0.0 + 1.0 + 4.0 + 5.0) / 4.0);
        let big = resample(&img, 8, 4);
        assert_eq!(big.get(7, 3)[0], 7.0);
        assert_eq!(big.get(0, 0)[0], 0.0);
    }
}

//! `synth`: analytic environment maps, the test inputs whose SH
//! coefficients are known in closed form
//! (`shlight_core::sh::closed_form`): each texel the light's mean over the
//! texel ([`texel_means`]), a directional light one texel or a cap of
//! exact power ([`directional_texels`]) ([`SynthRequest`] → [`SynthPlan`]
//! → [`synth`]).

use std::path::Path;

use glam::DVec3;
use shlight_core::map::{
    AnalyticLight, DirectionalDrawing, Layout, MapOrientation, TexelGrid, directional_texels,
    texel_means,
};
use shlight_io::{Image, ToneMap, WriteOptions, write_image};

use crate::hooks::{Hooks, StageCounter};
use crate::job::by_name::by_name;
use crate::output_grid::{default_output_size, output_grid};
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// The lights `synth` draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SynthKind {
    /// Radiance `value * color` in every direction.
    Constant,
    /// Radiance `value * color` over the hemisphere about the direction
    /// (default: the frame's up axis), 0 below.
    Hemisphere,
    /// Radiance `value * color` inside a cap of the half-angle about the
    /// direction (default up), 0 outside.
    Cap,
    /// Sky gradient `(value + slope (d . direction)) * color`, direction
    /// defaulting to up.
    Gradient,
    /// A sun: irradiance `value * color` facing the direction (default
    /// up); one texel, or a cap of the half-angle.
    Directional,
}

impl SynthKind {
    /// Every light, in the order of the command line's help.
    pub const ALL: [SynthKind; 5] = [
        SynthKind::Constant,
        SynthKind::Hemisphere,
        SynthKind::Cap,
        SynthKind::Gradient,
        SynthKind::Directional,
    ];

    /// The name both front ends take.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SynthKind::Constant => "constant",
            SynthKind::Hemisphere => "hemisphere",
            SynthKind::Cap => "cap",
            SynthKind::Gradient => "gradient",
            SynthKind::Directional => "directional",
        }
    }
}

impl std::str::FromStr for SynthKind {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        by_name(&SynthKind::ALL, SynthKind::name, s, "light")
    }
}

/// An analytic map as a front end asks for it, before
/// [`SynthRequest::check`].
#[derive(Clone, Copy, Debug)]
pub struct SynthRequest {
    /// Which light.
    pub kind: SynthKind,
    /// The whole image [default: [`default_output_size`] from 512].
    pub size: Option<(usize, usize)>,
    /// The map's layout.
    pub layout: Layout,
    /// How the map's texels meet world directions.
    pub orientation: MapOrientation,
    /// Linear Rec.709 colour multiplying the light.
    pub color: DVec3,
    /// Strength: radiance (constant, hemisphere, cap; the gradient's mean)
    /// or, for directional, the irradiance facing the light.
    pub value: f64,
    /// The gradient's `b` in `a + b (d . direction)`.
    pub slope: f64,
    /// The light's axis in world coordinates [default: the frame's up].
    pub direction: Option<DVec3>,
    /// Half-angle in degrees [default: 30 for a cap, 0 (one texel) for a
    /// directional light].
    pub half_angle: Option<f64>,
    /// Points per texel side of the texel means, 1 to 64.
    pub supersample: u32,
    /// Exposure in stops of the written image.
    pub exposure: f32,
    /// Tone map of a written PNG.
    pub tone_map: ToneMap,
}

/// A checked [`SynthRequest`].
#[derive(Debug)]
pub struct SynthPlan {
    kind: SynthKind,
    grid: TexelGrid,
    axis: DVec3,
    colour: DVec3,
    gradient: DVec3,
    alpha: f64,
    supersample: usize,
    write: (f32, ToneMap),
}

impl SynthRequest {
    /// The plan, after the checks every front end makes: a size that fits
    /// the layout, a direction of non-zero length, a half-angle from 0 to
    /// 180 degrees (90 for a directional light), 1 to 64 points a side.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<SynthPlan> {
        let size = self
            .size
            .unwrap_or_else(|| default_output_size(self.layout, 512));
        let grid = output_grid(self.layout, size, self.orientation)
            .map_err(|e| e.context(spelling.option("size")))?;
        let axis = match self.direction {
            None => grid.up(),
            Some(d) if d.length() > 0.0 => d.normalize(),
            Some(_) => {
                return Err(PipelineError::new(format!(
                    "{} has no direction",
                    spelling.option_number("direction", "0,0,0", "(0, 0, 0)")
                )));
            }
        };
        let half_angle = self.half_angle.unwrap_or(if self.kind == SynthKind::Cap {
            30.0
        } else {
            0.0
        });
        let half = spelling.option_number("half_angle", half_angle, half_angle);
        if !(0.0..=180.0).contains(&half_angle) {
            return Err(PipelineError::new(format!(
                "{half}: must be between 0 and 180 degrees"
            )));
        }
        if self.kind == SynthKind::Directional && half_angle > 90.0 {
            return Err(PipelineError::new(format!(
                "{half}: a directional light's cap must be at most 90 degrees \
                 (a wider cap cannot give the light's irradiance facing it)"
            )));
        }
        if !(1..=64).contains(&self.supersample) {
            return Err(PipelineError::new(format!(
                "{}: from 1 to 64 points a side",
                spelling.option_number("supersample", self.supersample, self.supersample)
            )));
        }
        Ok(SynthPlan {
            kind: self.kind,
            grid,
            axis,
            colour: self.color * self.value,
            gradient: self.color * self.slope,
            alpha: half_angle.to_radians(),
            supersample: self.supersample as usize,
            write: (self.exposure, self.tone_map),
        })
    }
}

/// The map of `plan` (progress: its rows, stage `"synthesising"`); where a
/// one-texel sun landed away from the direction asked for is a note, and a
/// cap too small for the texels a warning.
///
/// # Errors
/// None in practice (the plan's grid sizes the image).
pub fn synth_map(plan: &SynthPlan, hooks: &dyn Hooks) -> Result<Image> {
    let grid = &plan.grid;
    let rows = StageCounter::new(hooks, "synthesising", grid.height());
    let on_rows = |n: usize| rows.add(n);
    let means =
        |light: AnalyticLight, n: usize| texel_means(grid, n, |d| light.radiance(d), &on_rows);
    let (axis, colour, n) = (plan.axis, plan.colour, plan.supersample);
    let pixels = match plan.kind {
        SynthKind::Constant => means(AnalyticLight::Constant(colour), 1),
        SynthKind::Hemisphere => means(
            AnalyticLight::Cap {
                axis,
                cos_half: 0.0,
                radiance: colour,
            },
            n,
        ),
        SynthKind::Cap => means(
            AnalyticLight::Cap {
                axis,
                cos_half: plan.alpha.cos(),
                radiance: colour,
            },
            n,
        ),
        SynthKind::Gradient => means(
            AnalyticLight::Gradient {
                axis,
                a: colour,
                b: plan.gradient,
            },
            n,
        ),
        SynthKind::Directional => {
            let drawn = directional_texels(grid, axis, colour, plan.alpha, n, &on_rows);
            report_sun(&drawn.drawing, plan.alpha, hooks);
            drawn.pixels
        }
    };
    Image::new(grid.width(), grid.height(), pixels).map_err(|e| PipelineError::new(e.to_string()))
}

/// Where a one-texel sun landed, as a note, and a cap too small for the
/// texels, as a warning.
fn report_sun(drawing: &DirectionalDrawing, alpha: f64, hooks: &dyn Hooks) {
    let DirectionalDrawing::Texel {
        x,
        y,
        centre,
        offset,
        unresolved_cap,
    } = *drawing
    else {
        return;
    };
    if unresolved_cap {
        hooks.warn(&format!(
            "a cap of half-angle {}° is smaller than the texels can resolve; drawn as one texel",
            alpha.to_degrees()
        ));
    }
    if offset > 1e-9 {
        hooks.note(&format!(
            "the light lands in texel x={x}, y={y}, centred at direction {:.6},{:.6},{:.6} ({:.3}° from the one asked for)",
            centre.x,
            centre.y,
            centre.z,
            offset.to_degrees()
        ));
    }
}

/// `shlight synth`: draws the map ([`synth_map`]) and writes it to
/// `output` at the plan's exposure and tone map, atomically; negative
/// values (a gradient steeper than its mean) are a warning.
///
/// # Errors
/// The image cannot be written.
pub fn synth(output: &Path, plan: &SynthPlan, hooks: &dyn Hooks) -> Result<Image> {
    let image = synth_map(plan, hooks)?;
    let stats = image.stats();
    if stats.negative > 0 {
        hooks.warn(&format!(
            "{}: {} negative values (minimum {}); radiance cannot be negative",
            output.display(),
            stats.negative,
            stats.min_value
        ));
    }
    let (exposure_ev, tone_map) = plan.write;
    write_image(
        output,
        &image,
        &WriteOptions {
            exposure_ev,
            tone_map,
            ..WriteOptions::default()
        },
    )?;
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(kind: SynthKind) -> SynthRequest {
        SynthRequest {
            kind,
            size: Some((16, 8)),
            layout: Layout::Equirect,
            orientation: MapOrientation::default(),
            color: DVec3::ONE,
            value: 1.0,
            slope: 0.5,
            direction: None,
            half_angle: None,
            supersample: 2,
            exposure: 0.0,
            tone_map: ToneMap::Clamp,
        }
    }

    #[test]
    fn kinds_parse_by_name() {
        for k in SynthKind::ALL {
            assert_eq!(k.name().parse::<SynthKind>(), Ok(k));
        }
        assert!("sun".parse::<SynthKind>().is_err());
    }

    #[test]
    fn refusals_name_the_settings_of_each_front_end() {
        let wide = SynthRequest {
            half_angle: Some(120.0),
            ..request(SynthKind::Directional)
        };
        let e = wide.check(Spelling::CommandLine).unwrap_err();
        assert!(e.message().starts_with("--half-angle 120: "), "{e}");
        let e = wide.check(Spelling::Python).unwrap_err();
        assert!(e.message().starts_with("half_angle=120: "), "{e}");
        assert!(
            SynthRequest {
                half_angle: Some(120.0),
                ..request(SynthKind::Cap)
            }
            .check(Spelling::Python)
            .is_ok()
        );
        let zero = SynthRequest {
            direction: Some(DVec3::ZERO),
            ..request(SynthKind::Cap)
        };
        assert!(
            zero.check(Spelling::Python)
                .unwrap_err()
                .message()
                .contains("has no direction")
        );
        let dense = SynthRequest {
            supersample: 65,
            ..request(SynthKind::Cap)
        };
        assert!(dense.check(Spelling::Python).is_err());
    }

    /// A constant light is its value in every texel, whatever the layout.
    #[test]
    fn a_constant_map_holds_its_value() {
        let plan = SynthRequest {
            value: 2.0,
            color: DVec3::new(1.0, 0.5, 0.25),
            ..request(SynthKind::Constant)
        }
        .check(Spelling::Python)
        .unwrap();
        let image = synth_map(&plan, &crate::Silent).unwrap();
        assert!(image.pixels().iter().all(|p| *p == [2.0, 1.0, 0.5]));
    }
}

//! `render`: a coefficient file drawn back as a map in any layout, or as
//! the lobe of its luminance ([`RenderRequest`] → [`RenderPlan`] →
//! [`render`]).

use std::path::Path;

use glam::DVec3;
use shlight_core::map::{Layout, MapOrientation, default_lobe_view, luminance};
use shlight_core::sh::irradiance;
use shlight_format::{CoeffFile, FileEncoding, Quantity};
use shlight_io::{Image, ReadOptions, ToneMap, WriteOptions, write_image};

use crate::hooks::{Hooks, StageCounter};
use crate::job::by_name::by_name;
use crate::lobe::render_lobe;
use crate::output_grid::{default_output_size, output_grid};
use crate::output_path::refuse_overwriting;
use crate::render::render_map;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// What `render` draws: a map in one of the layouts of the maps shlight
/// writes, or the function's lobe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderLayout {
    /// The function on a map of this layout.
    Map(Layout),
    /// The luminance's lobe, the surface `r(w) = |f(w)|`
    /// ([`crate::render_lobe`]).
    Lobe,
}

impl RenderLayout {
    /// Every layout: the map layouts in [`Layout::ALL`]'s order, then the
    /// lobe.
    pub const ALL: [RenderLayout; Layout::ALL.len() + 1] = {
        let mut all = [RenderLayout::Lobe; Layout::ALL.len() + 1];
        let mut i = 0;
        while i < Layout::ALL.len() {
            all[i] = RenderLayout::Map(Layout::ALL[i]);
            i += 1;
        }
        all
    };

    /// The name both front ends take: a [`Layout`]'s, or `lobe`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            RenderLayout::Map(l) => l.name(),
            RenderLayout::Lobe => "lobe",
        }
    }
}

impl std::str::FromStr for RenderLayout {
    type Err = String;

    /// A [`Layout`]'s name or `lobe`, ASCII case-insensitive.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        by_name(&RenderLayout::ALL, RenderLayout::name, s, "layout")
    }
}

/// A render as a front end asks for it, before [`RenderRequest::check`].
#[derive(Clone, Copy, Debug)]
pub struct RenderRequest {
    /// Draw irradiance `E = A_l L_lm` of a radiance file.
    pub irradiance: bool,
    /// The whole image, width x height [default: a map's
    /// [`default_output_size`] from 256, or 256x256 for a lobe].
    pub size: Option<(usize, usize)>,
    /// A map layout, or the lobe.
    pub layout: RenderLayout,
    /// Where the lobe is seen from [default: [`default_lobe_view`]].
    pub view: Option<DVec3>,
    /// Exposure in stops of the written image.
    pub exposure: f32,
    /// Tone map of a written PNG.
    pub tone_map: ToneMap,
}

impl Default for RenderRequest {
    /// An equirect map of radiance, at its default size.
    fn default() -> Self {
        Self {
            irradiance: false,
            size: None,
            layout: RenderLayout::Map(Layout::Equirect),
            view: None,
            exposure: 0.0,
            tone_map: ToneMap::Clamp,
        }
    }
}

/// A checked [`RenderRequest`]: what [`render`] and [`render_light`] do.
#[derive(Clone, Copy, Debug)]
pub struct RenderPlan {
    irradiance: bool,
    shape: Shape,
    write: (f32, ToneMap),
}

#[derive(Clone, Copy, Debug)]
enum Shape {
    Map {
        layout: Layout,
        size: (usize, usize),
    },
    Lobe {
        size: (usize, usize),
        view: Option<DVec3>,
    },
}

impl RenderRequest {
    /// The plan of the render, after the checks every front end makes:
    /// a view only for the lobe, and not of zero length; a size of at most
    /// the reader's pixel limit that fits the layout.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<RenderPlan> {
        let size_name = |(w, h): (usize, usize)| {
            spelling.option_number("size", format!("{w}x{h}"), format!("({w}, {h})"))
        };
        if let Some(size) = self.size
            && size
                .0
                .checked_mul(size.1)
                .is_none_or(|n| n == 0 || n > ReadOptions::DEFAULT_MAX_PIXELS)
        {
            return Err(PipelineError::new(format!(
                "{}: not from 1 to {} pixels",
                size_name(size),
                ReadOptions::DEFAULT_MAX_PIXELS
            )));
        }
        let shape = match self.layout {
            RenderLayout::Map(layout) => {
                if self.view.is_some() {
                    return Err(PipelineError::new(format!(
                        "{} is where {} is seen from; a map ({}) shows every direction",
                        spelling.option("view"),
                        spelling.option_value("layout", "lobe"),
                        spelling.option_value("layout", layout.name())
                    )));
                }
                let size = self
                    .size
                    .unwrap_or_else(|| default_output_size(layout, 256));
                output_grid(layout, size, MapOrientation::default())
                    .map_err(|e| e.context(spelling.option("size")))?;
                Shape::Map { layout, size }
            }
            RenderLayout::Lobe => {
                if self.view.is_some_and(|v| v.length_squared() == 0.0) {
                    return Err(PipelineError::new(format!(
                        "{} has no direction: give the direction from the lobe toward the eye (e.g. 2,1,1)",
                        spelling.option_number("view", "0,0,0", "(0, 0, 0)")
                    )));
                }
                Shape::Lobe {
                    size: self.size.unwrap_or((256, 256)),
                    view: self.view,
                }
            }
        };
        Ok(RenderPlan {
            irradiance: self.irradiance,
            shape,
            write: (self.exposure, self.tone_map),
        })
    }
}

impl RenderPlan {
    /// The image's width and height.
    #[must_use]
    pub fn size(&self) -> (usize, usize) {
        match self.shape {
            Shape::Map { size, .. } | Shape::Lobe { size, .. } => size,
        }
    }
}

/// `file` drawn as `plan` says, named `name` in messages: radiance, or its
/// irradiance with `irradiance` (a file of irradiance is drawn as it is,
/// with a note), as a map in the file's frame and mirroring, or as the
/// lobe of its luminance. Progress: the rows drawn.
///
/// # Errors
/// The file holds an encoding other than plain SH (its coefficients are not
/// the whole light); its lobe cannot be drawn (zero everywhere).
pub fn render_light(
    file: &CoeffFile,
    name: &str,
    plan: &RenderPlan,
    hooks: &dyn Hooks,
) -> Result<Image> {
    if file.encoding != FileEncoding::Sh {
        return Err(PipelineError::new(format!(
            "{name}: holds the {} encoding, whose coefficients are not the whole light; render draws plain SH (irradiance with an encoding draws an encoding's irradiance)",
            file.encoding.encoding()
        )));
    }
    let coeffs = match (file.quantity, plan.irradiance) {
        (Quantity::Radiance, true) => irradiance(&file.coeffs),
        (Quantity::Irradiance, false) => {
            hooks.note(&format!(
                "{name} holds irradiance; rendering irradiance (radiance cannot be recovered from it)"
            ));
            file.coeffs.clone()
        }
        _ => file.coeffs.clone(),
    };
    match plan.shape {
        Shape::Map { layout, size } => {
            let orientation = MapOrientation {
                frame: file.frame,
                mirror: file.mirror,
            };
            let rows = StageCounter::new(hooks, "rendering", size.1);
            render_map(&coeffs, layout, size, orientation, &|| rows.add(1))
        }
        Shape::Lobe { size, view } => {
            let view = view.unwrap_or_else(|| default_lobe_view(file.frame));
            let rows = StageCounter::new(hooks, "drawing the lobe", size.1);
            render_lobe(&coeffs.map(luminance), file.frame, view, size, &|| {
                rows.add(1);
            })
            .map_err(|e| e.context(format!("{name}: lobe")))
        }
    }
}

/// `shlight render`: reads the coefficient file `input`, draws it
/// ([`render_light`]) and writes the image `output` (its format by
/// extension, at the plan's exposure and tone map), atomically.
///
/// # Errors
/// `output` is `input`; the file cannot be read; [`render_light`]'s; the
/// image cannot be written.
pub fn render(input: &Path, output: &Path, plan: &RenderPlan, hooks: &dyn Hooks) -> Result<()> {
    refuse_overwriting(output, &[input])?;
    let file = CoeffFile::read(input)?;
    let image = render_light(&file, &input.display().to_string(), plan, hooks)?;
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
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_parse_by_name() {
        for l in RenderLayout::ALL {
            assert_eq!(l.name().parse::<RenderLayout>(), Ok(l));
        }
        assert!(
            "bogus"
                .parse::<RenderLayout>()
                .unwrap_err()
                .contains("lobe")
        );
    }

    #[test]
    fn checks_name_the_settings_of_each_front_end() {
        let lobe_view = RenderRequest {
            view: Some(DVec3::ONE),
            ..RenderRequest::default()
        };
        let e = lobe_view.check(Spelling::CommandLine).unwrap_err();
        assert_eq!(
            e.message(),
            "--view is where --layout lobe is seen from; a map (--layout equirect) shows every direction"
        );
        let e = lobe_view.check(Spelling::Python).unwrap_err();
        assert_eq!(
            e.message(),
            "view is where layout=\"lobe\" is seen from; a map (layout=\"equirect\") shows every direction"
        );
        let square = RenderRequest {
            size: Some((64, 64)),
            ..RenderRequest::default()
        };
        let e = square.check(Spelling::Python).unwrap_err();
        assert!(e.message().starts_with("size: "), "{e}");
        assert!(e.message().contains("twice its height"), "{e}");
        let zero = RenderRequest {
            layout: RenderLayout::Lobe,
            view: Some(DVec3::ZERO),
            ..RenderRequest::default()
        };
        assert!(
            zero.check(Spelling::CommandLine)
                .unwrap_err()
                .message()
                .starts_with("--view 0,0,0 has no direction")
        );
        let plan = RenderRequest {
            layout: RenderLayout::Map(Layout::CrossHorizontal),
            ..RenderRequest::default()
        }
        .check(Spelling::Python)
        .unwrap();
        assert_eq!(
            plan.size(),
            default_output_size(Layout::CrossHorizontal, 256)
        );
    }
}

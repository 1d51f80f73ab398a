//! `prefilter`: an environment map GGX-prefiltered into cube mips for an
//! engine's specular lighting, written as cmgen's `--ibl-ld` faces, a KTX
//! 1.1 cube or a KTX2 cube ([`PrefilterRequest`] → [`PrefilterPlan`] →
//! [`prefilter`]).

use std::path::{Path, PathBuf};

use shlight_core::map::MapOrientation;
use shlight_specular::{PrefilterSettings, Prefiltered};

use crate::hooks::{Hooks, StageCounter};
use crate::output_path::{names_dir, refuse_overwriting};
use crate::read_settings::ReadSettings;
use crate::specular::{
    prefilter_map, write_prefiltered_faces, write_prefiltered_ktx1, write_prefiltered_ktx2,
};
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// How a prefiltered cube is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrefilterOutput {
    /// A directory of one float OpenEXR per mip and face, named as cmgen's
    /// `--ibl-ld` names them.
    Faces,
    /// Filament's KTX 1.1 cube (`R11F_G11F_B10F`), as `cmgen --format=ktx`.
    Ktx1,
    /// A KTX2 cube with its mips (`RGBA16F`), Bevy's specular map.
    Ktx2,
}

impl PrefilterOutput {
    /// The form `path` names: `.ktx`, `.ktx2`, or a directory (an existing
    /// one, a path ending in a separator, or a name without an extension);
    /// none for a file of another kind (`out.exr`).
    #[must_use]
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("ktx") => Some(Self::Ktx1),
            Some("ktx2") => Some(Self::Ktx2),
            None => Some(Self::Faces),
            _ if names_dir(path) => Some(Self::Faces),
            _ => None,
        }
    }
}

/// A prefilter as a front end asks for it, before
/// [`PrefilterRequest::check`].
#[derive(Clone, Debug)]
pub struct PrefilterRequest<'a> {
    /// The map.
    pub input: &'a Path,
    /// Where the cube goes ([`PrefilterOutput::of`]).
    pub output: &'a Path,
    /// How the map is read.
    pub read: ReadSettings,
    /// How its texels meet world directions.
    pub orientation: MapOrientation,
    /// The cube, its mips, samples and engine.
    pub settings: PrefilterSettings,
}

/// A checked [`PrefilterRequest`].
#[derive(Clone, Debug)]
pub struct PrefilterPlan {
    input: PathBuf,
    output: PathBuf,
    form: PrefilterOutput,
    read: ReadSettings,
    orientation: MapOrientation,
    settings: PrefilterSettings,
}

impl PrefilterRequest<'_> {
    /// The plan, after the checks every front end makes: an output that
    /// names a directory, a `.ktx` or a `.ktx2` file and is not the input;
    /// shlight-specular's limits on the settings
    /// ([`PrefilterSettings::check`]).
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<PrefilterPlan> {
        let Some(form) = PrefilterOutput::of(self.output) else {
            return Err(PipelineError::new(format!(
                "{}: {} names a directory for the faces (end it with /, e.g. ld/), a .ktx or a .ktx2 file",
                self.output.display(),
                spelling.pick("-o", "output")
            )));
        };
        refuse_overwriting(self.output, &[self.input])?;
        self.settings
            .check()
            .map_err(|e| PipelineError::new(format!("{}: {e}", spelling.option(e.setting()))))?;
        Ok(PrefilterPlan {
            input: self.input.to_path_buf(),
            output: self.output.to_path_buf(),
            form,
            read: self.read.clone(),
            orientation: self.orientation,
            settings: self.settings,
        })
    }
}

/// `shlight prefilter`: reads the map, prefilters it (progress: the rows
/// of every face of every mip, stage `"prefilter"`) and writes the cube;
/// notes each mip's size, roughness and samples. Returns the cube and the
/// files written (the faces, or the one KTX file).
///
/// # Errors
/// The loader's, or a file that cannot be written, naming it.
pub fn prefilter(plan: &PrefilterPlan, hooks: &dyn Hooks) -> Result<(Prefiltered, Vec<PathBuf>)> {
    let rows = StageCounter::new(hooks, "prefilter", plan.settings.rows());
    let cube = prefilter_map(
        &plan.input,
        &plan.read,
        plan.orientation,
        &plan.settings,
        &|w| hooks.warn(w),
        &|n| rows.add(n),
    )?;
    let written = match plan.form {
        PrefilterOutput::Ktx1 => {
            write_prefiltered_ktx1(&cube, &plan.output)?;
            vec![plan.output.clone()]
        }
        PrefilterOutput::Ktx2 => {
            write_prefiltered_ktx2(&cube, &plan.output)?;
            vec![plan.output.clone()]
        }
        PrefilterOutput::Faces => write_prefiltered_faces(&cube, &plan.output)?,
    };
    for (k, level) in cube.levels.iter().enumerate() {
        hooks.note(&format!(
            "mip {k}: {0}x{0}, roughness {1:.4} (perceptual {2:.4}), {3} samples",
            level.cube.size(),
            level.alpha,
            level.alpha.sqrt(),
            level.samples
        ));
    }
    Ok((cube, written))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_are_named_by_extension_or_a_directory() {
        assert_eq!(
            PrefilterOutput::of(Path::new("a.KTX")),
            Some(PrefilterOutput::Ktx1)
        );
        assert_eq!(
            PrefilterOutput::of(Path::new("a.ktx2")),
            Some(PrefilterOutput::Ktx2)
        );
        assert_eq!(
            PrefilterOutput::of(Path::new("ld/")),
            Some(PrefilterOutput::Faces)
        );
        assert_eq!(
            PrefilterOutput::of(Path::new("ld")),
            Some(PrefilterOutput::Faces)
        );
        assert_eq!(
            PrefilterOutput::of(Path::new("ld.d/")),
            Some(PrefilterOutput::Faces)
        );
        assert_eq!(PrefilterOutput::of(Path::new("ld.exr")), None);
    }

    #[test]
    fn refusals_name_the_settings_of_each_front_end() {
        let request = PrefilterRequest {
            input: Path::new("map.exr"),
            output: Path::new("out.exr"),
            read: ReadSettings::default(),
            orientation: MapOrientation::default(),
            settings: PrefilterSettings::new(shlight_specular::TargetEngine::Filament),
        };
        let e = request.check(Spelling::Python).unwrap_err();
        assert!(e.message().contains("output names a directory"), "{e}");
        let e = request.check(Spelling::CommandLine).unwrap_err();
        assert!(e.message().contains("-o names a directory"), "{e}");
        let odd = PrefilterRequest {
            output: Path::new("out.ktx2"),
            settings: PrefilterSettings {
                size: 48,
                ..request.settings
            },
            ..request.clone()
        };
        let e = odd.check(Spelling::CommandLine).unwrap_err();
        assert!(e.message().starts_with("--size: "), "{e}");
        assert!(e.message().contains("power of two"), "{e}");
        let e = odd.check(Spelling::Python).unwrap_err();
        assert!(e.message().starts_with("size: "), "{e}");
    }
}

//! `convert`: coefficient files to engine formats and back, a light added
//! to a glTF asset, and irradiance volumes to three.js's grid or to a
//! shader snippet of their lookup with its textures ([`ConvertRequest`] →
//! [`ConvertPlan`] → [`convert`]).

use std::path::{Path, PathBuf};

use shlight_format::threejs_volume::Precision;
use shlight_format::{
    ExportFormat, ExportInput, FileEncoding, ShaderLanguage, ShvolFile, VolumeFormat, export,
    export_gltf, gltf, read_coefficients, write_volume_shader,
};

use crate::hooks::Hooks;
use crate::job::project::{Dest, write_text};
use crate::output_path::refuse_overwriting;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// A conversion as a front end asks for it, before
/// [`ConvertRequest::check`].
#[derive(Clone, Copy, Debug)]
pub struct ConvertRequest<'a> {
    /// A coefficient file or an engine file that keeps its coefficients
    /// ([`read_coefficients`]), or an irradiance volume (`.shvol`).
    pub input: &'a Path,
    /// The output (none: standard output).
    pub output: Option<&'a Path>,
    /// The output format [default: from the output's extension, where one
    /// format writes it].
    pub format: Option<ExportFormat>,
    /// A glTF asset to add the light to, in place.
    pub into: Option<&'a Path>,
    /// The numbers of a volume's three.js atlas.
    pub precision: Precision,
    /// A glTF light from the coefficients alone, without its specular
    /// images.
    pub irradiance_only: bool,
}

/// A checked [`ConvertRequest`].
#[derive(Clone, Debug)]
pub struct ConvertPlan {
    input: PathBuf,
    action: Action,
}

#[derive(Clone, Debug)]
enum Action {
    /// Coefficients to `format`, to a file or standard output.
    Coefficients {
        format: ExportFormat,
        dest: Dest,
        irradiance_only: bool,
    },
    /// The light added to a glTF asset.
    Into { scene: PathBuf },
    /// A volume to three.js's grid.
    VolumeGrid {
        output: PathBuf,
        precision: Precision,
    },
    /// A volume to a shader snippet and its textures.
    VolumeShader {
        output: PathBuf,
        language: ShaderLanguage,
    },
}

impl ConvertRequest<'_> {
    /// The plan, after the checks every front end makes: a volume goes to
    /// a file, as three.js's grid or a WGSL or GLSL snippet, never into a
    /// glTF asset; a light goes into a glTF asset only from its
    /// coefficients alone (`irradiance_only`); standard output needs a
    /// format; nothing is written over the input.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<ConvertPlan> {
        let is_volume = self
            .input
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("shvol"));
        let action = if is_volume {
            self.volume_action(spelling)?
        } else if let Some(scene) = self.into {
            if !self.irradiance_only {
                return Err(PipelineError::new(format!(
                    "{}: {}",
                    self.input.display(),
                    gltf::MISSING_SPECULAR
                )));
            }
            refuse_overwriting(scene, &[self.input])?;
            Action::Into {
                scene: scene.to_path_buf(),
            }
        } else {
            let format = match (self.format, self.output) {
                (Some(f), _) => f,
                (None, Some(path)) => ExportFormat::from_path(path).map_err(|e| {
                    PipelineError::from(e).context_after(format!(
                        "name the format with {}",
                        spelling.option("format")
                    ))
                })?,
                (None, None) => {
                    return Err(PipelineError::new(format!(
                        "writing to stdout needs {} (or give {})",
                        spelling.option("format"),
                        spelling.pick("-o FILE", "output")
                    )));
                }
            };
            let dest = match self.output {
                Some(path) => {
                    refuse_overwriting(path, &[self.input])?;
                    Dest::File(path.to_path_buf())
                }
                None => Dest::Stdout,
            };
            Action::Coefficients {
                format,
                dest,
                irradiance_only: self.irradiance_only,
            }
        };
        Ok(ConvertPlan {
            input: self.input.to_path_buf(),
            action,
        })
    }

    fn volume_action(&self, spelling: Spelling) -> Result<Action> {
        let input = self.input.display();
        let threejs = spelling.option_value("format", "threejs");
        if self.into.is_some() {
            return Err(PipelineError::new(format!(
                "{input}: {} adds a light to a glTF asset; a volume is not one light",
                spelling.option("into")
            )));
        }
        let output_name = spelling.pick("-o", "output");
        let Some(output) = self.output else {
            return Err(PipelineError::new(format!(
                "{input}: converting a volume needs {output_name} (FILE.json with {threejs}, or FILE.wgsl / FILE.glsl)"
            )));
        };
        let format = match self.format {
            Some(f) => f,
            None => match ExportFormat::from_path(output) {
                Ok(f @ (ExportFormat::Wgsl | ExportFormat::Glsl)) => f,
                _ => {
                    return Err(PipelineError::new(format!(
                        "{input}: converting a volume needs {threejs}, or {output_name} FILE.wgsl|glsl"
                    )));
                }
            },
        };
        refuse_overwriting(output, &[self.input])?;
        let output = output.to_path_buf();
        Ok(match format {
            ExportFormat::Threejs => Action::VolumeGrid {
                output,
                precision: self.precision,
            },
            ExportFormat::Wgsl => Action::VolumeShader {
                output,
                language: ShaderLanguage::Wgsl,
            },
            ExportFormat::Glsl => Action::VolumeShader {
                output,
                language: ShaderLanguage::Glsl,
            },
            f => {
                return Err(PipelineError::new(format!(
                    "{input}: a volume converts to {threejs} (three.js's LightProbeGrid), wgsl or \
                     glsl (a shader snippet and its textures), not {}",
                    f.name()
                )));
            }
        })
    }
}

/// What [`convert`] wrote.
#[derive(Clone, Debug, Default)]
pub struct Converted {
    /// The text for standard output, where the plan writes there.
    pub stdout: Option<String>,
    /// The files a volume's shader snippet wrote (the snippet and its
    /// textures).
    pub written: Vec<PathBuf>,
}

/// `shlight convert`: reads the input and writes what the plan says, the
/// exporters' notes to `hooks`.
///
/// # Errors
/// An input that cannot be read; an exporter's refusal (the format cannot
/// hold the light, an encoded light into glTF), naming the input; an
/// output that cannot be written.
pub fn convert(plan: &ConvertPlan, hooks: &dyn Hooks) -> Result<Converted> {
    let input = plan.input.display();
    match &plan.action {
        Action::Coefficients {
            format,
            dest,
            irradiance_only,
        } => {
            let file = read_coefficients(&plan.input)?;
            // Without `irradiance_only`, export refuses a glTF light (after
            // the checks every format shares).
            let out = if *format == ExportFormat::Gltf && *irradiance_only {
                export_gltf(&file, None)
            } else {
                export(&file, *format)
            }
            .map_err(|e| PipelineError::from(e).context(format!("{input}: converting")))?;
            out.notes.iter().for_each(|n| hooks.note(n));
            match dest {
                Dest::Stdout => Ok(Converted {
                    stdout: Some(out.text),
                    ..Converted::default()
                }),
                Dest::File(path) => {
                    write_text(path, &out.text)?;
                    Ok(Converted::default())
                }
            }
        }
        Action::Into { scene } => {
            let file = read_coefficients(&plan.input)?;
            if file.encoding != FileEncoding::Sh {
                return Err(PipelineError::new(format!(
                    "{input}: holds the {} encoding, whose coefficients are not the whole light; \
                     a glTF light keeps plain SH only",
                    file.encoding.encoding()
                )));
            }
            let light = ExportInput {
                coeffs: &file.coeffs,
                quantity: file.quantity,
                frame: file.frame,
            };
            for note in gltf::add_light_to_file(&light, scene)? {
                hooks.note(&note);
            }
            Ok(Converted::default())
        }
        Action::VolumeGrid { output, precision } => {
            let file = ShvolFile::read(&plan.input)?;
            for note in file.write_as(output, VolumeFormat::Threejs, *precision)? {
                hooks.note(&note);
            }
            Ok(Converted::default())
        }
        Action::VolumeShader { output, language } => {
            let file = ShvolFile::read(&plan.input)?;
            let written = write_volume_shader(&file, *language, output)
                .map_err(|e| PipelineError::from(e).context(format!("{input}: converting")))?;
            for note in &written.notes {
                hooks.note(note);
            }
            Ok(Converted {
                stdout: None,
                written: written.paths,
            })
        }
    }
}

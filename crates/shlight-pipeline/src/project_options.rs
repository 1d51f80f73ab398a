//! [`ProjectOptions`]: a projection's options as a front end was given
//! them, and [`ProjectOptions::check`], which makes the [`Settings`] of
//! [`crate::project`] with the same defaults and refusals for every front
//! end, each message naming the option as that front end spells it
//! ([`Spelling`]).

use shlight_baked::LIGHT_MAX_LMAX;
use shlight_core::encoding::Encoding;
use shlight_core::map::MapOrientation;
use shlight_core::map::montecarlo::{DEFAULT_SEED, McOptions, SamplerKind};
use shlight_core::sh::Window;
use shlight_format::{ExportFormat, Quantity, RotationRecord};

use crate::read_settings::ReadSettings;
use crate::rotation_spec::parse_rotation;
use crate::settings::{DEFAULT_SAMPLES, Method, ProjectSettings, Settings};
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// A projection's options as a front end was given them, its own values
/// already parsed, before [`ProjectOptions::check`] resolves and checks
/// them together.
#[derive(Clone, Debug)]
pub struct ProjectOptions<'a> {
    /// How input files are read.
    pub read: ReadSettings,
    /// Highest SH degree kept.
    pub lmax: usize,
    /// How the map's texels meet world directions.
    pub orientation: MapOrientation,
    /// `method` is Monte Carlo (else quadrature).
    pub monte_carlo: bool,
    /// Monte Carlo directions, if given (default [`DEFAULT_SAMPLES`]).
    pub samples: Option<usize>,
    /// Monte Carlo sampler, if given (default [`SamplerKind::default`]).
    pub sampler: Option<SamplerKind>,
    /// Monte Carlo seed, if given (default [`DEFAULT_SEED`]).
    pub seed: Option<u64>,
    /// The window as given: `none`, `auto`, or a [`Window`] spec.
    pub window: &'a str,
    /// The rotation spec, if given ([`parse_rotation`]).
    pub rotate: Option<&'a str>,
    /// What the coefficients hold.
    pub quantity: Quantity,
    /// The light kept: plain SH or an encoding of the map.
    pub encoding: Encoding,
    /// The projection runs on the GPU (the command line's `--gpu`).
    pub gpu: bool,
    /// The output format, where the front end writes one.
    pub format: Option<ExportFormat>,
}

impl ProjectOptions<'_> {
    /// The settings of [`crate::project`] (no preview), after the checks
    /// every front end makes, in this order:
    ///
    /// 1. an encoding other than plain SH keeps radiance projected by
    ///    quadrature in shlight's JSON file (or a code snippet): no
    ///    irradiance, rotation, GPU, Monte Carlo, window, or other format;
    /// 2. the window spec parses (`auto`: one per channel, chosen later);
    /// 3. the rotation spec parses;
    /// 4. Monte Carlo takes at least one sample; its options are refused
    ///    with quadrature;
    /// 5. the GPU computes the quadrature, to [`LIGHT_MAX_LMAX`] at most.
    ///
    /// # Errors
    /// The first check that fails, naming the options as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<Settings> {
        if self.encoding != Encoding::Sh {
            self.check_encoding(spelling)?;
        }
        let window = match self.window.trim() {
            "auto" => None,
            spec => Some(spec.parse::<Window>().map_err(|e| {
                PipelineError::new(format!("{}: {e}", spelling.option_value("window", spec)))
            })?),
        };
        let rotation = match self.rotate {
            None => None,
            Some(spec) => {
                let matrix = parse_rotation(spec, self.orientation.frame, spelling)?;
                let record = RotationRecord {
                    spec: spec.trim().to_string(),
                    matrix: matrix.transpose().to_cols_array_2d(),
                };
                Some((record, matrix))
            }
        };
        let method = self.method(spelling)?;
        if self.gpu {
            self.check_gpu(&method, spelling)?;
        }
        Ok(Settings {
            read: self.read.clone(),
            project: ProjectSettings {
                lmax: self.lmax,
                orientation: self.orientation,
                method,
                window,
                rotation,
                quantity: self.quantity,
            },
            encoding: self.encoding,
            preview: None,
        })
    }

    /// Step 1 of [`ProjectOptions::check`].
    fn check_encoding(&self, spelling: Spelling) -> Result<()> {
        let format = format!(
            "{} other than json, wgsl, glsl, hlsl or c",
            spelling.option("format")
        );
        let clash = [
            (
                self.quantity != Quantity::Radiance,
                spelling.option_value("quantity", Quantity::Irradiance.name()),
            ),
            (self.rotate.is_some(), spelling.option("rotate")),
            (self.gpu, spelling.option("gpu")),
            (
                self.monte_carlo,
                spelling.option_value("method", "montecarlo"),
            ),
            (self.window.trim() != "none", spelling.option("window")),
            (self.format.is_some_and(|f| !f.takes_encodings()), format),
        ];
        match clash.into_iter().find(|(c, _)| *c) {
            Some((_, what)) => Err(PipelineError::new(format!(
                "{} keeps radiance projected by quadrature in shlight's JSON file; it cannot be combined with {what}",
                spelling.option_value("encoding", self.encoding.name())
            ))),
            None => Ok(()),
        }
    }

    /// Step 5 of [`ProjectOptions::check`].
    fn check_gpu(&self, method: &Method, spelling: Spelling) -> Result<()> {
        if *method != Method::Quadrature {
            return Err(PipelineError::new(format!(
                "{} computes the quadrature; it does not apply to {}",
                spelling.option("gpu"),
                spelling.option_value("method", "montecarlo")
            )));
        }
        if self.lmax > LIGHT_MAX_LMAX {
            return Err(PipelineError::new(format!(
                "{} projects to lmax {LIGHT_MAX_LMAX} at most (asked: {})",
                spelling.option("gpu"),
                self.lmax
            )));
        }
        Ok(())
    }

    /// Step 4 of [`ProjectOptions::check`]: the method with its options.
    fn method(&self, spelling: Spelling) -> Result<Method> {
        if self.monte_carlo {
            let samples = self.samples.unwrap_or(DEFAULT_SAMPLES);
            if samples == 0 {
                return Err(PipelineError::new("the sample count must be at least 1"));
            }
            return Ok(Method::MonteCarlo {
                options: McOptions {
                    lmax: self.lmax,
                    samples,
                    seed: self.seed.unwrap_or(DEFAULT_SEED),
                    ..McOptions::default()
                },
                sampler: self.sampler.unwrap_or_default(),
            });
        }
        let given: Vec<String> = [
            ("samples", self.samples.is_some()),
            ("sampler", self.sampler.is_some()),
            ("seed", self.seed.is_some()),
        ]
        .into_iter()
        .filter(|(_, given)| *given)
        .map(|(name, _)| spelling.option(name))
        .collect();
        if !given.is_empty() {
            return Err(PipelineError::new(format!(
                "{} only apply to {} (the method is quadrature)",
                given.join(", "),
                spelling.option_value("method", "montecarlo")
            )));
        }
        Ok(Method::Quadrature)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options() -> ProjectOptions<'static> {
        ProjectOptions {
            read: ReadSettings::default(),
            lmax: 3,
            orientation: MapOrientation::default(),
            monte_carlo: false,
            samples: None,
            sampler: None,
            seed: None,
            window: "none",
            rotate: None,
            quantity: Quantity::Radiance,
            encoding: Encoding::Sh,
            gpu: false,
            format: None,
        }
    }

    fn message(o: &ProjectOptions<'_>, spelling: Spelling) -> String {
        o.check(spelling).unwrap_err().message().to_string()
    }

    /// The defaults: quadrature, no window, no rotation; `auto` leaves the
    /// window to be chosen; Monte Carlo takes the default samples and seed.
    #[test]
    fn defaults_and_the_methods_options() {
        let s = options().check(Spelling::CommandLine).unwrap();
        assert_eq!(s.project.method, Method::Quadrature);
        assert_eq!(s.project.window, Some(Window::None));
        assert!(s.project.rotation.is_none() && s.preview.is_none());
        let auto = ProjectOptions {
            window: " auto ",
            rotate: Some(" yaw:30 "),
            ..options()
        };
        let s = auto.check(Spelling::Python).unwrap();
        assert_eq!(s.project.window, None);
        assert_eq!(s.project.rotation.unwrap().0.spec, "yaw:30");
        let mc = ProjectOptions {
            monte_carlo: true,
            seed: Some(7),
            ..options()
        };
        let Method::MonteCarlo { options, sampler } =
            mc.check(Spelling::Python).unwrap().project.method
        else {
            panic!("Monte Carlo");
        };
        assert_eq!(
            (options.lmax, options.samples, options.seed),
            (3, DEFAULT_SAMPLES, 7)
        );
        assert_eq!(sampler, SamplerKind::default());
    }

    /// Each refusal names the options as the front end spells them.
    #[test]
    fn refusals_are_spelled_for_each_front_end() {
        use Spelling::{CommandLine, Python};
        let quadrature = ProjectOptions {
            samples: Some(10),
            seed: Some(3),
            ..options()
        };
        assert_eq!(
            message(&quadrature, CommandLine),
            "--samples, --seed only apply to --method montecarlo (the method is quadrature)"
        );
        assert_eq!(
            message(&quadrature, Python),
            "samples, seed only apply to method=\"montecarlo\" (the method is quadrature)"
        );
        let zero = ProjectOptions {
            monte_carlo: true,
            samples: Some(0),
            ..options()
        };
        assert_eq!(
            message(&zero, Python),
            "the sample count must be at least 1"
        );
        let window = ProjectOptions {
            window: "gauss:2",
            ..options()
        };
        assert!(message(&window, Python).starts_with("window=\"gauss:2\": "));
        assert!(message(&window, CommandLine).starts_with("--window gauss:2: "));
        let head = "keeps radiance projected by quadrature in shlight's JSON file; it cannot be combined with";
        for (o, cli, python) in [
            (
                ProjectOptions {
                    quantity: Quantity::Irradiance,
                    ..options()
                },
                "--quantity irradiance",
                "quantity=\"irradiance\"",
            ),
            (
                ProjectOptions {
                    rotate: Some("bogus"),
                    ..options()
                },
                "--rotate",
                "rotate",
            ),
            (
                ProjectOptions {
                    gpu: true,
                    ..options()
                },
                "--gpu",
                "gpu",
            ),
            (
                ProjectOptions {
                    monte_carlo: true,
                    samples: Some(0),
                    ..options()
                },
                "--method montecarlo",
                "method=\"montecarlo\"",
            ),
            (
                ProjectOptions {
                    window: "bogus",
                    ..options()
                },
                "--window",
                "window",
            ),
            (
                ProjectOptions {
                    format: Some(ExportFormat::Threejs),
                    ..options()
                },
                "--format other than json, wgsl, glsl, hlsl or c",
                "format other than json, wgsl, glsl, hlsl or c",
            ),
        ] {
            let o = ProjectOptions {
                encoding: Encoding::Zh3,
                ..o
            };
            assert_eq!(
                message(&o, CommandLine),
                format!("--encoding zh3 {head} {cli}")
            );
            assert_eq!(
                message(&o, Python),
                format!("encoding=\"zh3\" {head} {python}")
            );
        }
        let fine = ProjectOptions {
            encoding: Encoding::Zh3,
            format: Some(ExportFormat::Wgsl),
            ..options()
        };
        assert_eq!(fine.check(CommandLine).unwrap().encoding, Encoding::Zh3);
    }
}

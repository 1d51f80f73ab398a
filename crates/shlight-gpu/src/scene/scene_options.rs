//! [`SceneOptions`]: what a front end was asked to shade (`render-mesh`
//! and `view` alike), and [`SceneOptions::check`], which refuses settings
//! that do not go together before any file is read, with the same message
//! for every front end, each naming the settings as that front end spells
//! them ([`Spelling`]).

use std::path::PathBuf;

use glam::{DMat3, Vec3};
use shlight_baked::{LIGHT_MAX_LMAX, SHADED_MAX_LMAX};
use shlight_core::encoding::Encoding;
use shlight_core::sh::Frame;
use shlight_pipeline::{Spelling, parse_rotation};

use super::SceneError;
use crate::{Background, Mode};

/// A scene's settings as a front end was given them, each value already
/// parsed, before [`SceneOptions::check`] checks them together.
#[derive(Clone, Debug)]
pub struct SceneOptions {
    /// The mesh (OBJ, PLY, OFF), or a glTF/GLB scene drawn with its
    /// materials and instances; `None`: the built-in mesh
    /// ([`crate::BuiltIn`]).
    pub mesh: Option<PathBuf>,
    /// PRT transfer baked for the mesh (`.shprt`).
    pub prt: Option<PathBuf>,
    /// The light: an equirect map or a radiance coefficient file
    /// (`.json`); `None`: the built-in map.
    pub env: Option<PathBuf>,
    /// Which world axis a map's top row faces.
    pub up: Frame,
    /// What the mesh shows [default: [`Mode::Prt`] with a transfer, else
    /// [`Mode::Sh`]; [`Mode::Encoded`] is chosen by `encoding`].
    pub mode: Option<Mode>,
    /// Highest SH degree shaded [default: the volume's, at most
    /// [`SHADED_MAX_LMAX`]; in PRT mode the transfer's, at most
    /// [`LIGHT_MAX_LMAX`]; else 2].
    pub lmax: Option<usize>,
    /// The light's encoding (plain SH, or one shaded by its irradiance).
    pub encoding: Encoding,
    /// Lambertian albedo, linear RGB [default: 0.8 each; in PRT mode with
    /// a glossy file, none: the glossy layer alone].
    pub albedo: Option<[f32; 3]>,
    /// Behind the mesh [default: the map where the light is one, else its
    /// SH].
    pub background: Option<Background>,
    /// The light's turn ([`parse_rotation`]'s specs).
    pub rotate: Option<String>,
    /// An irradiance volume baked through the mesh (`.shvol`), lighting
    /// it and an object moved through it.
    pub volume: Option<PathBuf>,
    /// The object moved through the volume [default: the built-in mesh].
    pub object: Option<PathBuf>,
    /// Where the object's bounding-box centre goes [default: the volume's
    /// centre].
    pub at: Option<Vec3>,
    /// The object's bounding-box diagonal [default: a third of the volume
    /// box's shortest side].
    pub object_size: Option<f32>,
    /// Draw a lightmapped scene (a GLB `shlight lightmap` wrote) by its
    /// lightmap even with a light given (which then lights the nodes the
    /// lightmap skipped). Without it the lightmap is used when no light is
    /// given ([`SceneOptions::env`] `None`), no transfer or volume either,
    /// in SH mode.
    pub lightmap: bool,
}

impl Default for SceneOptions {
    /// The built-in mesh under the built-in map, y up, every other setting
    /// left to its default.
    fn default() -> Self {
        Self {
            mesh: None,
            prt: None,
            env: None,
            up: Frame::YUp,
            mode: None,
            lmax: None,
            encoding: Encoding::Sh,
            albedo: None,
            background: None,
            rotate: None,
            volume: None,
            object: None,
            at: None,
            object_size: None,
            lightmap: false,
        }
    }
}

/// A scene's settings checked together ([`SceneOptions::check`]), for
/// [`crate::Scene::read`].
#[derive(Clone, Debug)]
pub struct SceneSettings {
    /// The settings as given.
    pub options: SceneOptions,
    /// How the front end names them, for the refusals that need the files.
    pub spelling: Spelling,
    /// What the mesh shows: [`Mode::Sh`], [`Mode::Prt`] or
    /// [`Mode::Normals`].
    pub mode: Mode,
    /// The light's turn (identity without one): a light from `a` then
    /// comes from `R a`.
    pub rotation: DMat3,
}

impl SceneOptions {
    /// The settings of [`crate::Scene::read`], after the checks every
    /// front end makes before reading a file, in this order:
    ///
    /// 1. the volume's: the object's settings need a volume; a volume is a
    ///    `.shvol` file, shaded to lmax [`SHADED_MAX_LMAX`] at most, of a
    ///    scene named (not the built-in mesh), by its SH alone (no
    ///    transfer, mode or encoding); the object's size is positive and
    ///    its place finite;
    /// 2. lmax at most [`LIGHT_MAX_LMAX`];
    /// 3. the mode: PRT needs a transfer; an encoding other than plain SH
    ///    shades by the irradiance (SH mode);
    /// 4. the rotation spec parses.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<SceneSettings, SceneError> {
        self.check_volume(spelling)?;
        self.check_lightmap(spelling)?;
        if let Some(lmax) = self.lmax.filter(|&l| l > LIGHT_MAX_LMAX) {
            return refuse(format!(
                "{}: the GPU shades to lmax {LIGHT_MAX_LMAX}",
                spelling.option_number("lmax", lmax, lmax)
            ));
        }
        let mode = self.mode(spelling)?;
        let rotation = match &self.rotate {
            Some(spec) => parse_rotation(spec, self.up, spelling)?,
            None => DMat3::IDENTITY,
        };
        Ok(SceneSettings {
            options: self.clone(),
            spelling,
            mode,
            rotation,
        })
    }

    /// Step 1 of [`SceneOptions::check`].
    fn check_volume(&self, spelling: Spelling) -> Result<(), SceneError> {
        let needs_volume = spelling.option_value("volume", "FILE.shvol");
        let Some(path) = &self.volume else {
            for (given, name) in [
                (self.object.is_some(), "object"),
                (self.at.is_some(), "at"),
                (self.object_size.is_some(), "object-size"),
            ] {
                if given {
                    return refuse(format!(
                        "{} places an object in an irradiance volume: it needs {needs_volume}",
                        spelling.option(name)
                    ));
                }
            }
            return Ok(());
        };
        let volume = spelling.option("volume");
        if !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("shvol"))
        {
            let hint = match spelling {
                Spelling::CommandLine => {
                    " (bake one with shlight volume SCENE --env LIGHT -o FILE.shvol)"
                }
                Spelling::Python => "",
            };
            return refuse(format!(
                "{}: {volume} takes a .shvol file{hint}",
                path.display()
            ));
        }
        if let Some(l) = self.lmax.filter(|&l| l > SHADED_MAX_LMAX) {
            return refuse(format!(
                "{}: volumes are shaded to lmax {SHADED_MAX_LMAX} at most",
                spelling.option_number("lmax", l, l)
            ));
        }
        if let Some(s) = self.object_size
            && !(s.is_finite() && s > 0.0)
        {
            return refuse(format!(
                "{}: expected a positive length",
                spelling.option_number("object-size", s, s)
            ));
        }
        if let Some(at) = self.at.filter(|at| !at.is_finite()) {
            return refuse(format!(
                "{}: expected finite coordinates",
                spelling.option_value("at", at)
            ));
        }
        if self.mesh.is_none() {
            let mesh = spelling.pick("MESH", "mesh");
            return refuse(format!(
                "{volume} lights the scene it was baked in: give that scene as {mesh}"
            ));
        }
        let by_sh = format!("{volume} shades by the volume's SH");
        if self.prt.is_some() {
            return refuse(format!("{by_sh}: it takes no {}", spelling.option("prt")));
        }
        if let Some(mode) = self.mode.filter(|&m| m != Mode::Sh) {
            return refuse(format!(
                "{by_sh}: it takes no {}",
                spelling.option_value("mode", mode.name())
            ));
        }
        if self.encoding != Encoding::Sh {
            return refuse(format!(
                "{by_sh} probes: it does not take {}",
                spelling.option_value("encoding", self.encoding.name())
            ));
        }
        Ok(())
    }

    /// Step 1 of [`SceneOptions::check`], for `lightmap`: a lightmap
    /// lights a named scene in SH mode, without a transfer, a volume or
    /// another encoding.
    fn check_lightmap(&self, spelling: Spelling) -> Result<(), SceneError> {
        if !self.lightmap {
            return Ok(());
        }
        let lightmap = spelling.option("lightmap");
        let other = if self.mesh.is_none() {
            Some(format!(
                "the built-in mesh (give the lightmapped scene as {})",
                spelling.pick("MESH", "mesh")
            ))
        } else if self.prt.is_some() {
            Some(spelling.option("prt"))
        } else if self.volume.is_some() {
            Some(spelling.option("volume"))
        } else if let Some(mode) = self.mode.filter(|&m| m != Mode::Sh) {
            Some(spelling.option_value("mode", mode.name()))
        } else if self.encoding != Encoding::Sh {
            Some(spelling.option_value("encoding", self.encoding.name()))
        } else {
            None
        };
        match other {
            Some(other) => refuse(format!(
                "{lightmap} draws a lightmapped scene by its baked light: it does not take {other}"
            )),
            None => Ok(()),
        }
    }

    /// Whether a lightmapped scene is drawn by its lightmap: asked
    /// ([`SceneOptions::lightmap`]), or no light, transfer or volume given
    /// and SH mode.
    #[must_use]
    pub fn wants_lightmap(&self) -> bool {
        self.lightmap
            || (self.env.is_none()
                && self.prt.is_none()
                && self.volume.is_none()
                && self.mode.is_none_or(|m| m == Mode::Sh)
                && self.encoding == Encoding::Sh)
    }

    /// Step 3 of [`SceneOptions::check`]: the mode, resolved.
    fn mode(&self, spelling: Spelling) -> Result<Mode, SceneError> {
        let mode = match (self.mode, &self.prt) {
            (Some(Mode::Encoded), _) => {
                return refuse(format!(
                    "{}: the light's encoding is chosen by {}",
                    spelling.option_value("mode", Mode::Encoded.name()),
                    spelling.option("encoding")
                ));
            }
            (Some(Mode::Prt), None) => {
                return refuse(format!(
                    "{} needs {}",
                    spelling.option_value("mode", Mode::Prt.name()),
                    spelling.option_value("prt", "FILE.shprt")
                ));
            }
            (Some(mode), _) => mode,
            (None, Some(_)) => Mode::Prt,
            (None, None) => Mode::Sh,
        };
        if self.encoding != Encoding::Sh && mode != Mode::Sh {
            return refuse(format!(
                "{} shades the mesh by the light's irradiance: it does not take {}",
                spelling.option_value("encoding", self.encoding.name()),
                spelling.option_value("mode", mode.name())
            ));
        }
        Ok(mode)
    }
}

/// A [`SceneError::Refused`] with `message`.
pub(super) fn refuse<T>(message: String) -> Result<T, SceneError> {
    Err(SceneError::Refused(message))
}

#[cfg(test)]
mod tests {
    use super::*;
    use Spelling::{CommandLine, Python};

    fn message(o: &SceneOptions, spelling: Spelling) -> String {
        o.check(spelling).unwrap_err().to_string()
    }

    fn volume(path: &str) -> SceneOptions {
        SceneOptions {
            mesh: Some("room.obj".into()),
            volume: Some(path.into()),
            ..SceneOptions::default()
        }
    }

    #[test]
    fn object_options_need_a_volume_and_a_volume_needs_its_extension() {
        let object = SceneOptions {
            object: Some("bunny.obj".into()),
            ..Default::default()
        };
        let e = message(&object, CommandLine);
        assert!(e.contains("--object") && e.contains("--volume"), "{e}");
        let e = message(&volume("room.json"), CommandLine);
        assert!(e.contains("room.json") && e.contains(".shvol"), "{e}");
        let right = volume("room.shvol");
        assert!(
            SceneOptions {
                lmax: Some(4),
                ..right.clone()
            }
            .check(CommandLine)
            .is_ok()
        );
        let e = message(
            &SceneOptions {
                lmax: Some(5),
                ..right
            },
            CommandLine,
        );
        assert!(e.contains("--lmax 5") && e.contains("lmax 4"), "{e}");
    }

    /// Each refusal names the settings as the front end spells them.
    #[test]
    fn refusals_are_spelled_for_each_front_end() {
        let cases = [
            (
                SceneOptions {
                    object_size: Some(1.0),
                    ..Default::default()
                },
                "--object-size places an object in an irradiance volume: it needs --volume FILE.shvol",
                "object_size places an object in an irradiance volume: it needs volume=\"FILE.shvol\"",
            ),
            (
                volume("room.json"),
                "room.json: --volume takes a .shvol file (bake one with shlight volume SCENE --env LIGHT -o FILE.shvol)",
                "room.json: volume takes a .shvol file",
            ),
            (
                SceneOptions {
                    object_size: Some(-1.0),
                    ..volume("room.shvol")
                },
                "--object-size -1: expected a positive length",
                "object_size=-1: expected a positive length",
            ),
            (
                SceneOptions {
                    mesh: None,
                    ..volume("room.shvol")
                },
                "--volume lights the scene it was baked in: give that scene as MESH",
                "volume lights the scene it was baked in: give that scene as mesh",
            ),
            (
                SceneOptions {
                    prt: Some("room.shprt".into()),
                    ..volume("room.shvol")
                },
                "--volume shades by the volume's SH: it takes no --prt",
                "volume shades by the volume's SH: it takes no prt",
            ),
            (
                SceneOptions {
                    mode: Some(Mode::Normals),
                    ..volume("room.shvol")
                },
                "--volume shades by the volume's SH: it takes no --mode normals",
                "volume shades by the volume's SH: it takes no mode=\"normals\"",
            ),
            (
                SceneOptions {
                    encoding: Encoding::Zh3,
                    ..volume("room.shvol")
                },
                "--volume shades by the volume's SH probes: it does not take --encoding zh3",
                "volume shades by the volume's SH probes: it does not take encoding=\"zh3\"",
            ),
            (
                SceneOptions {
                    mesh: Some("room.glb".into()),
                    prt: Some("room.shprt".into()),
                    lightmap: true,
                    ..Default::default()
                },
                "--lightmap draws a lightmapped scene by its baked light: it does not take --prt",
                "lightmap draws a lightmapped scene by its baked light: it does not take prt",
            ),
            (
                SceneOptions {
                    lightmap: true,
                    ..Default::default()
                },
                "--lightmap draws a lightmapped scene by its baked light: it does not take the built-in mesh (give the lightmapped scene as MESH)",
                "lightmap draws a lightmapped scene by its baked light: it does not take the built-in mesh (give the lightmapped scene as mesh)",
            ),
            (
                SceneOptions {
                    lmax: Some(9),
                    ..Default::default()
                },
                "--lmax 9: the GPU shades to lmax 8",
                "lmax=9: the GPU shades to lmax 8",
            ),
            (
                SceneOptions {
                    mode: Some(Mode::Prt),
                    ..Default::default()
                },
                "--mode prt needs --prt FILE.shprt",
                "mode=\"prt\" needs prt=\"FILE.shprt\"",
            ),
            (
                SceneOptions {
                    prt: Some("bunny.shprt".into()),
                    encoding: Encoding::Zh3,
                    ..Default::default()
                },
                "--encoding zh3 shades the mesh by the light's irradiance: it does not take --mode prt",
                "encoding=\"zh3\" shades the mesh by the light's irradiance: it does not take mode=\"prt\"",
            ),
        ];
        for (options, cli, python) in cases {
            assert_eq!(message(&options, CommandLine), cli);
            assert_eq!(message(&options, Python), python);
        }
    }

    /// A lightmap is used when asked, or when nothing else lights the
    /// scene.
    #[test]
    fn the_lightmap_is_wanted_when_no_other_light_is_given() {
        let scene = SceneOptions {
            mesh: Some("room.glb".into()),
            ..Default::default()
        };
        assert!(scene.wants_lightmap());
        let lit = SceneOptions {
            env: Some("sky.json".into()),
            ..scene.clone()
        };
        assert!(!lit.wants_lightmap());
        assert!(
            SceneOptions {
                lightmap: true,
                ..lit
            }
            .wants_lightmap()
        );
        for other in [
            SceneOptions {
                mode: Some(Mode::Normals),
                ..scene.clone()
            },
            SceneOptions {
                encoding: Encoding::Zh3,
                ..scene.clone()
            },
            SceneOptions {
                prt: Some("room.shprt".into()),
                ..scene
            },
        ] {
            assert!(!other.wants_lightmap(), "{other:?}");
        }
    }

    /// The mode follows the transfer unless given; the rotation is parsed
    /// in the frame `up` names.
    #[test]
    fn defaults_resolve_the_mode_and_the_rotation() {
        let plain = SceneOptions::default().check(Python).unwrap();
        assert_eq!(plain.mode, Mode::Sh);
        assert_eq!(plain.rotation, DMat3::IDENTITY);
        let prt = SceneOptions {
            prt: Some("bunny.shprt".into()),
            rotate: Some("yaw:90".into()),
            up: Frame::ZUp,
            ..Default::default()
        }
        .check(CommandLine)
        .unwrap();
        assert_eq!(prt.mode, Mode::Prt);
        // A quarter turn about the up axis (+Z): +Z kept, +X turned
        // to the horizontal axis at right angles.
        let z = prt.rotation * glam::DVec3::Z;
        let x = prt.rotation * glam::DVec3::X;
        assert!((z - glam::DVec3::Z).length() < 1e-12, "{z}");
        assert!(
            x.z.abs() < 1e-12 && x.x.abs() < 1e-12 && (x.y.abs() - 1.0).abs() < 1e-12,
            "{x}"
        );
        let normals = SceneOptions {
            prt: Some("bunny.shprt".into()),
            mode: Some(Mode::Normals),
            ..Default::default()
        };
        assert_eq!(normals.check(CommandLine).unwrap().mode, Mode::Normals);
    }
}

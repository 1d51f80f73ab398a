//! [`Environment`]: the distant light of the commands that shade a scene
//! (`shlight render-mesh`, `view`, `volume`): an equirect map projected to
//! radiance SH (and kept, for a background or an encoding), or a radiance
//! coefficient file.

use std::path::{Path, PathBuf};

use glam::DVec3;
use shlight_core::encoding::{
    DominantLightOptions, Encoded, Encoding, encode_coefficients, encode_map,
};
use shlight_core::map::{Layout, MapOrientation};
use shlight_core::sh::{Frame, ShCoeffs, ShRotation};
use shlight_format::{CoeffFile, ExportFormat, Quantity};
use shlight_io::Image;

use crate::cpu_projector::CpuProjector;
use crate::encoded_file::set_encoding;
use crate::load::{LoadedMap, env_map, load_map};
use crate::projector::Projector;
use crate::read_settings::ReadSettings;
use crate::settings::{Method, ProjectSettings};
use crate::{PipelineError, Result};

/// A light read from a file.
#[derive(Clone, Debug)]
pub struct Environment {
    /// The file it came from.
    pub path: PathBuf,
    /// Radiance coefficients: a map's projection in the world frame, or a
    /// coefficient file's as stored (in its own frame, `orientation`).
    pub radiance: ShCoeffs<DVec3>,
    /// The equirect map, when the light came from one.
    pub map: Option<Image>,
    /// How the map's texels meet world directions, or the coefficient
    /// file's frame and mirroring.
    pub orientation: MapOrientation,
    /// Warnings from reading the map ([`crate::load_map`]'s: negative
    /// texels, ...), each naming the file, for the caller to show.
    pub warnings: Vec<String>,
}

impl Environment {
    /// Reads `path`: a `.json` coefficient file (radiance; kept to lmax
    /// `lmax` at most), or an equirect map in any format shlight reads,
    /// read and checked by [`crate::load_map`] (the loader of every map)
    /// and projected by quadrature to `lmax` with its top row facing `up`
    /// ([`Environment::from_loaded`]).
    ///
    /// # Errors
    /// An unreadable file, a map that is not 2:1 or holds non-finite
    /// texels, or a coefficient file that holds irradiance (radiance
    /// cannot be recovered from it); messages name the file.
    pub fn load(path: &Path, up: Frame, lmax: usize) -> Result<Self> {
        let is_json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        if is_json {
            let file = CoeffFile::read_radiance(path, "the light", "project the map as radiance")?;
            let lmax = file.coeffs.lmax().min(lmax);
            return Ok(Self {
                path: path.to_path_buf(),
                radiance: file.coeffs.resized(lmax),
                map: None,
                orientation: MapOrientation {
                    frame: file.frame,
                    mirror: file.mirror,
                },
                warnings: Vec::new(),
            });
        }
        let loaded = load_map(path, &ReadSettings::default())?;
        Self::from_loaded(path, loaded, up, lmax)
    }

    /// A map read and checked by the loader ([`crate::load_map`], or
    /// [`LoadedMap::from_image`] for one decoded from memory, as the
    /// bundled map is), named by `path`, projected as `shlight project`
    /// projects it ([`CpuProjector`]: quadrature) to `lmax`, its top row
    /// facing `up`, not mirrored; the loader's warnings kept.
    ///
    /// # Errors
    /// A map that is not equirect (2:1; other layouts are projected first,
    /// to a coefficient file).
    pub fn from_loaded(path: &Path, loaded: LoadedMap, up: Frame, lmax: usize) -> Result<Self> {
        let name = path.display().to_string();
        let (w, h) = (loaded.image.width(), loaded.image.height());
        if Layout::detect(w, h) != Some(Layout::Equirect) {
            return Err(PipelineError::new(format!(
                "{name}: {w}x{h} is not an equirect map (2:1); project other layouts to a \
                 coefficient file of lmax {lmax} first and pass that"
            )));
        }
        let orientation = MapOrientation {
            frame: up,
            mirror: false,
        };
        let settings =
            ProjectSettings::new(lmax, orientation, Method::Quadrature, Quantity::Radiance);
        let radiance = CpuProjector
            .project(&loaded.map(orientation, &name)?, &settings)?
            .coeffs;
        Ok(Self {
            path: path.to_path_buf(),
            radiance,
            map: Some(loaded.image),
            orientation,
            warnings: loaded.warnings,
        })
    }

    /// The radiance coefficients in `frame`: as held when the light is
    /// already in it, else turned between the y-up and z-up frames
    /// ([`ShRotation::between_frames`]).
    #[must_use]
    pub fn radiance_in(&self, frame: Frame) -> ShCoeffs<DVec3> {
        let from = self.orientation.frame;
        if from == frame {
            self.radiance.clone()
        } else {
            ShRotation::between_frames(self.radiance.lmax(), from, frame).apply(&self.radiance)
        }
    }

    /// The light kept as `encoding`, its SH part (`sh`, `dominant+sh`,
    /// `sloan+sh`) to `lmax`: from the map's texels when the light came from
    /// a map (as `shlight project MAP --encoding E` encodes it), else from
    /// the coefficients held.
    ///
    /// # Errors
    /// `dominant+sh` without a map (its lights are found among the texels),
    /// or coefficients too short for the encoding.
    pub fn encode(&self, encoding: Encoding, lmax: usize) -> Result<Encoded> {
        let name = self.path.display();
        match &self.map {
            Some(image) => {
                let size = (image.width(), image.height());
                let map = env_map(Layout::Equirect, self.orientation, size, image.pixels())
                    .map_err(|e| e.context(&name))?;
                Ok(encode_map(
                    &map,
                    encoding,
                    lmax,
                    &DominantLightOptions::default(),
                ))
            }
            None if encoding == Encoding::DominantSh => Err(PipelineError::new(format!(
                "the dominant+sh encoding finds its lights among a map's texels; {name} holds coefficients (pass the map, or use the sloan+sh encoding)"
            ))),
            None => {
                // The SH part to lmax; the others take what they need (the
                // ambient cube every band, for the irradiance at the axes).
                let coeffs = match encoding {
                    Encoding::Sh | Encoding::SloanSh => self.radiance.resized(lmax),
                    _ => self.radiance.clone(),
                };
                encode_coefficients(&coeffs, encoding).ok_or_else(|| {
                    PipelineError::new(format!(
                        "{name}: lmax {} is too low for the {encoding} encoding",
                        self.radiance.lmax()
                    ))
                })
            }
        }
    }

    /// The light kept as `encoding` ([`Environment::encode`], the SH part
    /// to `lmax`) and its WGSL snippet, as `shlight project MAP --encoding
    /// E --format wgsl` writes it: the plain SH to `lmax` is kept beside it
    /// as a coefficient file keeps it (`sloan+sh` finds its light again
    /// from them).
    ///
    /// # Errors
    /// As [`Environment::encode`], and values a 32-bit float cannot hold.
    pub fn encoded_light(&self, encoding: Encoding, lmax: usize) -> Result<(Encoded, String)> {
        let encoded = self.encode(encoding, lmax)?;
        let mut file = CoeffFile::new(
            self.radiance.resized(lmax),
            self.orientation.frame,
            Quantity::Radiance,
        );
        file.mirror = self.orientation.mirror;
        set_encoding(&mut file, encoding, &encoded);
        let exported = shlight_format::export(&file, ExportFormat::Wgsl)
            .map_err(|e| PipelineError::new(format!("{}: {e}", self.path.display())))?;
        Ok((encoded, exported.text))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_core::map::EnvMap;
    use shlight_core::sh::closed_form;

    /// `image` named `name` through the loader, as the bundled map comes
    /// in.
    fn from_image(name: &str, image: Image, up: Frame, lmax: usize) -> Result<Environment> {
        let loaded = LoadedMap::from_image(name, image, &ReadSettings::default())?;
        Environment::from_loaded(Path::new(name), loaded, up, lmax)
    }

    fn temp_dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("shlight-pipeline-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A uniform map projects to `L_0^0 = 2 sqrt(π) c` (the texels' solid
    /// angles sum to 4π) and the rest within the quadrature's `O(h²)` of 0
    /// (`m != 0` vanish exactly: every row is constant); a coefficient
    /// file keeps its frame and is turned on request.
    #[test]
    fn maps_project_and_files_keep_their_frame() {
        let c = [0.5f32, 1.0, 2.0];
        let image = Image::from_fn(64, 32, |_, _| c);
        let env = from_image("sky.exr", image, Frame::YUp, 4).unwrap();
        assert_eq!(env.radiance.lmax(), 4);
        let want = closed_form::constant(4, DVec3::from(c.map(f64::from)));
        assert!((env.radiance[0] - want[0]).abs().max_element() < 1e-12);
        for i in 1..want.len() {
            // Measured 7.8e-4 of L_0^0 (degree 2 at 64x32).
            let rel = env.radiance[i].abs() / want[0];
            assert!(rel.max_element() < 2e-3, "{i}: {}", env.radiance[i]);
        }
        assert!(env.map.is_some());

        let dir = temp_dir("environment");
        let path = dir.join("light.json");
        let d = DVec3::new(0.2, 0.3, 0.9).normalize();
        let file = CoeffFile::new(
            closed_form::directional(3, d, DVec3::ONE),
            Frame::ZUp,
            Quantity::Radiance,
        );
        std::fs::write(&path, file.to_json_string()).unwrap();
        let env = Environment::load(&path, Frame::YUp, 2).unwrap();
        assert_eq!(env.radiance.lmax(), 2);
        assert_eq!(env.orientation.frame, Frame::ZUp);
        assert!(env.map.is_none());
        // Turned to y-up, the light comes from Frame::ZUp -> YUp of d.
        let y_up = env.radiance_in(Frame::YUp);
        let turned = Frame::ZUp.rotation_to(Frame::YUp) * d;
        let want = closed_form::directional(2, turned, DVec3::ONE);
        for i in 0..want.len() {
            assert!((y_up[i] - want[i]).abs().max_element() < 1e-12, "{i}");
        }
        assert_eq!(env.radiance_in(Frame::ZUp), env.radiance);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_maps_and_missing_texels_are_refused() {
        let e = from_image(
            "square.exr",
            Image::from_fn(16, 16, |_, _| [1.0; 3]),
            Frame::YUp,
            8,
        )
        .unwrap_err();
        assert!(
            e.message()
                .starts_with("square.exr: 16x16 is not an equirect map (2:1)"),
            "{e}"
        );
        // What to do, naming the lmax and no front end's flag.
        assert!(
            e.message().contains("lmax 8") && !e.message().contains("--"),
            "{e}"
        );
        let mut image = Image::from_fn(16, 8, |_, _| [1.0; 3]);
        image.set(3, 2, [f32::NAN, 0.0, 0.0]);
        let e = from_image("nan.exr", image, Frame::YUp, 2).unwrap_err();
        assert!(
            e.message()
                .starts_with("nan.exr: 1 texels are NaN or infinite (the first at x=3, y=2)"),
            "{e}"
        );
        // dominant+sh needs texels.
        let env = Environment {
            path: "light.json".into(),
            radiance: closed_form::constant(2, DVec3::ONE),
            map: None,
            orientation: MapOrientation::default(),
            warnings: Vec::new(),
        };
        let e = env.encode(Encoding::DominantSh, 2).unwrap_err();
        assert!(e.message().contains("holds coefficients"), "{e}");
        assert!(env.encode(Encoding::Zh3, 2).is_ok());
    }

    /// A map file comes in through the loader of every map
    /// ([`crate::load_map`]): its warnings are kept, its refusals given,
    /// and its texels projected as read.
    #[test]
    fn map_files_come_in_through_the_loader() {
        let dir = temp_dir("environment-loader");
        let write = |name: &str, image: &Image| {
            let path = dir.join(name);
            shlight_io::write_image(&path, image, &shlight_io::WriteOptions::default()).unwrap();
            path
        };
        let mut image = Image::from_fn(32, 16, |_, _| [1.0; 3]);
        image.set(4, 3, [-0.5, 1.0, 1.0]);
        let negative = write("negative.exr", &image);
        let env = Environment::load(&negative, Frame::YUp, 2).unwrap();
        assert_eq!(env.warnings.len(), 1, "{:?}", env.warnings);
        assert!(
            env.warnings[0].contains("negative.exr"),
            "{:?}",
            env.warnings
        );
        assert!(env.warnings[0].contains("negative"), "{:?}", env.warnings);
        assert_eq!(env.map.as_ref().unwrap().get(4, 3), [-0.5, 1.0, 1.0]);
        image.set(5, 3, [f32::NAN, 1.0, 1.0]);
        let nan = write("nan.exr", &image);
        let e = Environment::load(&nan, Frame::YUp, 2).unwrap_err();
        assert!(
            e.message()
                .contains("nan.exr: 1 texels are NaN or infinite"),
            "{e}"
        );
        let e = Environment::load(&dir.join("sky_{face}.exr"), Frame::YUp, 2).unwrap_err();
        assert!(e.message().contains("face file"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The snippet is the WGSL export of the encoded light, and the
    /// encoding from a map is the map's own.
    #[test]
    fn the_encoded_light_and_its_snippet() {
        let image = Image::from_fn(32, 16, |x, y| [0.1 + 0.01 * x as f32, 0.2, 0.05 * y as f32]);
        let env = from_image("sky.exr", image.clone(), Frame::YUp, 8).unwrap();
        let (encoded, snippet) = env.encoded_light(Encoding::Zh3, 2).unwrap();
        assert!(snippet.contains("fn shlight_irradiance"), "{snippet}");
        let map = EnvMap::new(Layout::Equirect, env.orientation, 32, 16, image.pixels()).unwrap();
        let direct = encode_map(&map, Encoding::Zh3, 2, &DominantLightOptions::default());
        let n = [DVec3::Y, DVec3::NEG_Z];
        assert_eq!(encoded.irradiance_at(&n), direct.irradiance_at(&n));
    }
}

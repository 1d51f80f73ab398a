//! The light of the GPU commands (`render-mesh`, `view`): `--env` names an
//! equirect map (projected here to radiance SH, and kept for the
//! background) or a coefficient file (radiance).

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow, bail};
use glam::DVec3;
use shlight_core::layout::{EnvMap, Layout};
use shlight_core::projection::{EquirectView, MapOrientation, project_equirect};
use shlight_core::rotation::Frame;
use shlight_core::{
    DominantLightOptions, Encoded, Encoding, ShCoeffs, encode_coefficients, encode_map,
};
use shlight_gpu::MAX_LMAX;
use shlight_io::{Image, ReadOptions, read_image};

use shlight_format::CoeffFile;

/// A light for the GPU commands.
pub struct Environment {
    /// The file it came from.
    pub path: PathBuf,
    /// Radiance coefficients in the world frame, to lmax [`MAX_LMAX`] at most.
    pub radiance: ShCoeffs<DVec3>,
    /// The equirect map, when the light came from one.
    pub map: Option<Image>,
    /// How the map's texels meet world directions.
    pub orientation: MapOrientation,
}

impl Environment {
    /// Reads `path`: a `.json` coefficient file (radiance), or an equirect
    /// map in any format shlight reads, projected by quadrature to lmax 8
    /// with its top row facing `up` (`y` or `z`).
    ///
    /// # Errors
    /// An unreadable file, a map that is not 2:1, or a coefficient file that
    /// holds irradiance (radiance cannot be recovered from it).
    pub fn load(path: &Path, up: Frame) -> Result<Self> {
        let is_json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        if is_json {
            let file =
                CoeffFile::read_radiance(path, "--env", "shlight project --quantity radiance")?;
            let lmax = file.coeffs.lmax().min(MAX_LMAX);
            return Ok(Self {
                path: path.to_path_buf(),
                radiance: file.coeffs.resized(lmax),
                map: None,
                orientation: MapOrientation {
                    frame: file.frame,
                    mirror: file.mirror,
                },
            });
        }
        let image = read_image(path, &ReadOptions::default())?;
        Self::from_map(path, image, up)
    }

    /// The bundled map ([`crate::bundled::ENV_NAME`]), projected as
    /// [`Environment::load`] projects a map.
    ///
    /// # Errors
    /// The bundled map cannot be decoded (a broken build).
    pub fn bundled(up: Frame) -> Result<Self> {
        let image = crate::bundled::env_image()?;
        Self::from_map(Path::new(crate::bundled::ENV_NAME), image, up)
    }

    /// An equirect map read from `path`, checked and projected to lmax 8.
    fn from_map(path: &Path, image: Image, up: Frame) -> Result<Self> {
        let name = path.display().to_string();
        let (w, h) = (image.width(), image.height());
        if Layout::detect(w, h) != Some(Layout::Equirect) {
            bail!(
                "{name}: {w}x{h} is not an equirect map (2:1); project other layouts first \
                 (shlight project {name} --lmax 8 -o light.json) and pass the JSON file"
            );
        }
        if let Some((x, y)) = image.stats().first_non_finite {
            bail!("{name}: non-finite texel at ({x}, {y}); shlight project --sanitize can fix it");
        }
        let orientation = MapOrientation {
            frame: up,
            mirror: false,
        };
        let view = EquirectView {
            width: w,
            height: h,
            pixels: image.pixels(),
        };
        let radiance = project_equirect(view, MAX_LMAX, orientation);
        Ok(Self {
            path: path.to_path_buf(),
            radiance,
            map: Some(image),
            orientation,
        })
    }

    /// The light kept as `encoding`, its SH part (`sh`, `dominant+sh`,
    /// `sloan+sh`) to `lmax`: from the map's texels when the light came from
    /// a map (as `shlight project MAP --encoding E` encodes it), else from
    /// the coefficients (to lmax [`MAX_LMAX`]).
    ///
    /// # Errors
    /// `dominant+sh` without a map (its lights are found among the texels),
    /// or coefficients too short for the encoding.
    pub fn encode(&self, encoding: Encoding, lmax: usize) -> Result<Encoded> {
        let name = self.path.display();
        match &self.map {
            Some(image) => {
                let map = EnvMap::new(
                    Layout::Equirect,
                    self.orientation,
                    image.width(),
                    image.height(),
                    image.pixels(),
                )
                .map_err(|e| anyhow!("{name}: {e}"))?;
                Ok(encode_map(
                    &map,
                    encoding,
                    lmax,
                    &DominantLightOptions::default(),
                ))
            }
            None if encoding == Encoding::DominantSh => bail!(
                "--encoding dominant+sh finds its lights among a map's texels; {name} holds coefficients (pass the map, or use --encoding sloan+sh)"
            ),
            None => {
                // The SH part to lmax; the others take what they need (the
                // ambient cube every band, for the irradiance at the axes).
                let coeffs = match encoding {
                    Encoding::Sh | Encoding::SloanSh => self.radiance.resized(lmax),
                    _ => self.radiance.clone(),
                };
                encode_coefficients(&coeffs, encoding).ok_or_else(|| {
                    anyhow!(
                        "{name}: lmax {} is too low for --encoding {encoding}",
                        self.radiance.lmax()
                    )
                })
            }
        }
    }
}

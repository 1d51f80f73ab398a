//! [`project`]: every step of `shlight project` on one map, in order, for
//! every front end (the command line, the Python package).

use shlight_core::encoding::Encoding;
use shlight_core::map::{EnvMap, TexelSource, contiguous_pixels};
use shlight_core::sh::{Window, apply_channel_windows};
use shlight_format::CoeffFile;
use shlight_io::Image;

use crate::choose_windows::choose_windows;
use crate::coeff_file_of::coeff_file_of;
use crate::cpu_projector::CpuProjector;
use crate::encoded_file::encode_file;
use crate::hooks::{Collected, Hooks, Progress};
use crate::input_layout::is_faces;
use crate::load::{LoadedMap, check_values, env_map, load_map};
use crate::map_info::MapInfo;
use crate::preview::write_preview;
use crate::projector::{Projection, Projector};
use crate::settings::Settings;
use crate::source_stats::source_stats;
use crate::stream_project::{Streamed, project_streaming};
use crate::{PipelineError, Result};

/// Where a map comes from.
#[derive(Clone, Copy)]
pub enum Source<'a> {
    /// A map file, or six `{face}` files ([`crate::load_map`], with the
    /// settings' [`crate::ReadSettings`]); the path as given names it everywhere.
    Path(&'a std::path::Path),
    /// Texels already in memory (a numpy array, a readback), read in place.
    Texels {
        /// The texels and their layout.
        texels: &'a dyn TexelSource,
        /// The map as named to the user (messages, `provenance.input`).
        name: &'a str,
        /// `provenance.layout` (`equirect`, ..., `faces`).
        layout_name: &'a str,
    },
}

/// Reads (or takes), checks, projects and finishes one map: every step of
/// `shlight project` in order, with the same messages whoever calls it.
///
/// 1. A file is read by [`crate::load_map`] (layout settled, values
///    checked, or replaced with `sanitize`); texels in memory are checked
///    ([`check_values`]), or copied into one image and checked or
///    sanitized as a file's are ([`crate::sanitize_image`]).
/// 2. The projector makes radiance coefficients ([`Projector`]).
/// 3. The window of each channel ([`choose_windows`]).
/// 4. The preview, if asked ([`write_preview`]), of the windowed radiance.
/// 5. The coefficient file ([`coeff_file_of`]: windows, rotation,
///    quantity, provenance), then the encoding, if other than plain SH
///    ([`encode_file`]).
///
/// The coefficients of texels in memory equal those of a file holding the
/// same texels, bit for bit.
///
/// # Errors
/// Any step's error; every message names the map.
pub fn project(
    source: Source<'_>,
    s: &Settings,
    projector: &dyn Projector,
    hooks: &dyn Hooks,
) -> Result<CoeffFile> {
    let warn_all = |warnings: &[String]| warnings.iter().for_each(|w| hooks.warn(w));
    let orientation = s.project.orientation;
    match source {
        Source::Path(path) => {
            let name = path.display().to_string();
            hooks.progress(Progress::Step(&format!("reading {name}")));
            let streamed = if streams(path, s, projector) {
                project_streaming(path, &name, s, hooks)?
            } else {
                Streamed::NotEquirect
            };
            let loaded = match streamed {
                Streamed::Projected(done) => {
                    warn_all(&done.warnings);
                    return complete(done.projection, None, done.info, s, hooks);
                }
                Streamed::Whole(image) => LoadedMap::from_image(&name, image, &s.read)?,
                Streamed::NotEquirect => load_map(path, &s.read)?,
            };
            warn_all(&loaded.warnings);
            let layout = if is_faces(path) {
                "faces"
            } else {
                loaded.layout.name()
            };
            let info = loaded.info(&name, layout);
            let map = loaded.map(orientation, &name)?;
            finish(&map, Some((&loaded.image, &map)), info, s, projector, hooks)
        }
        Source::Texels {
            texels,
            name,
            layout_name,
        } => {
            let size = texels.size();
            let layout = texels.layout();
            layout
                .check_size(size.0, size.1)
                .map_err(|e| PipelineError::new(format!("{name}: {e}")))?;
            let stats = source_stats(texels);
            // The preview and the encodings read a contiguous image.
            let needs_copy = s.read.sanitize || s.preview.is_some() || s.encoding != Encoding::Sh;
            if !needs_copy {
                let mut warnings = Vec::new();
                check_values(name, &stats, s.read.spelling, &mut warnings)?;
                warn_all(&warnings);
                let info = MapInfo::new(name, layout_name, size, stats, None);
                return finish(texels, None, info, s, projector, hooks);
            }
            let image = Image::new(size.0, size.1, contiguous_pixels(texels).into_owned())
                .expect("width * height texels");
            let loaded = LoadedMap::checked(name, image, layout, stats, Vec::new(), &s.read)?;
            warn_all(&loaded.warnings);
            let info = loaded.info(name, layout_name);
            let map = env_map(layout, orientation, size, loaded.image.pixels())
                .map_err(|e| e.context(format!("{name}: projecting")))?;
            finish(&map, Some((&loaded.image, &map)), info, s, projector, hooks)
        }
    }
}

/// Whether [`project`] reads the map at `path` by rows into the ring sums
/// ([`project_streaming`]): a single file (not six faces), projected by a
/// projector that allows it ([`Projector::projects_rows`]), with no step
/// that needs the whole map (a preview, an encoding other than plain SH).
fn streams(path: &std::path::Path, s: &Settings, projector: &dyn Projector) -> bool {
    !is_faces(path)
        && s.preview.is_none()
        && s.encoding == Encoding::Sh
        && projector.projects_rows(&s.project)
}

/// Steps 2 to 5 of [`project`] on checked texels (`contiguous`: the same
/// texels as one image and as a map, for the preview and the encodings).
fn finish(
    texels: &dyn TexelSource,
    contiguous: Option<(&Image, &EnvMap<'_>)>,
    info: MapInfo,
    s: &Settings,
    projector: &dyn Projector,
    hooks: &dyn Hooks,
) -> Result<CoeffFile> {
    let name = &info.name;
    let p = &s.project;
    hooks.progress(Progress::Step(&format!(
        "projecting {name} ({}x{}, lmax {})",
        info.width, info.height, p.lmax
    )));
    let projection = projector
        .project(texels, p)
        .map_err(|e| e.context(format!("{name}: projecting")))?;
    complete(projection, contiguous, info, s, hooks)
}

/// Steps 3 to 5 of [`project`] on a map's radiance coefficients.
fn complete(
    projection: Projection,
    contiguous: Option<(&Image, &EnvMap<'_>)>,
    info: MapInfo,
    s: &Settings,
    hooks: &dyn Hooks,
) -> Result<CoeffFile> {
    let name = &info.name;
    let p = &s.project;
    if p.window.is_none() {
        hooks.progress(Progress::Step(&format!("choosing windows for {name}")));
    }
    let windows: [Window; 3] = choose_windows(&projection.coeffs, p, name, s.read.spelling)?;
    if let (Some(preview), Some((image, map))) = (&s.preview, contiguous) {
        hooks.progress(Progress::Step(&format!("preview of {name}")));
        let radiance = apply_channel_windows(&windows, &projection.coeffs);
        write_preview(
            &preview.path,
            image,
            map.layout,
            &radiance,
            p.orientation,
            &preview.options,
        )
        .map_err(|e| e.context(format!("{name}: preview")))?;
    }
    let mut file = coeff_file_of(&projection, windows, p, &info);
    if s.encoding != Encoding::Sh {
        hooks.progress(Progress::Step(&format!(
            "encoding {name} as {}",
            s.encoding
        )));
        let (_, map) = contiguous.expect("an encoding copies the texels into an image");
        encode_file(&mut file, map, s.encoding, p.lmax);
    }
    Ok(file)
}

/// [`project`] with the CPU projector, no progress, and the warnings
/// collected and returned beside the file (for front ends that show them
/// afterwards, as the Python package does).
///
/// # Errors
/// As [`project`].
pub fn project_with_warnings(source: Source<'_>, s: &Settings) -> Result<(CoeffFile, Vec<String>)> {
    let hooks = Collected::new();
    let file = project(source, s, &CpuProjector, &hooks)?;
    Ok((file, hooks.into_warnings()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::{Method, ProjectSettings};
    use glam::DVec3;
    use shlight_core::map::montecarlo::{McOptions, SamplerKind};
    use shlight_core::map::{Layout, MapOrientation, StridedImage};
    use shlight_core::sh::{Frame, ShCoeffs};
    use shlight_format::Quantity;
    use shlight_io::{ReadOptions, read_image};
    use std::path::Path;
    use std::sync::Mutex;

    fn sky() -> (std::path::PathBuf, Image) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../envmaps/sky.exr");
        let image = read_image(&path, &ReadOptions::default()).unwrap();
        (path, image)
    }

    /// A bundled map read from its file and the same texels in memory with
    /// a row pitch give the same coefficient file, bit for bit, for both
    /// methods, plain and encoded.
    #[test]
    fn texels_in_memory_project_as_their_file() {
        let (path, image) = sky();
        let (w, h, stride) = (image.width(), image.height(), image.width() + 3);
        let mut padded = vec![[f32::NAN; 3]; stride * h];
        for y in 0..h {
            padded[y * stride..y * stride + w].copy_from_slice(image.row(y));
        }
        let source = StridedImage::new(Layout::Equirect, w, h, stride, &padded).unwrap();
        let orientation = MapOrientation {
            frame: Frame::ZUp,
            mirror: false,
        };
        let name = path.display().to_string();
        for (method, encoding) in [
            (Method::Quadrature, Encoding::Sh),
            (Method::Quadrature, Encoding::DominantSh),
            (
                Method::MonteCarlo {
                    options: McOptions {
                        samples: 4096,
                        ..McOptions::default()
                    },
                    sampler: SamplerKind::Importance,
                },
                Encoding::Sh,
            ),
        ] {
            let mut p = ProjectSettings::new(4, orientation, method, Quantity::Irradiance);
            p.window = None;
            if encoding != Encoding::Sh {
                p.quantity = Quantity::Radiance;
            }
            let s = Settings {
                encoding,
                ..Settings::new(p)
            };
            let (from_file, _) = project_with_warnings(Source::Path(&path), &s).unwrap();
            let texels = Source::Texels {
                texels: &source,
                name: &name,
                layout_name: "equirect",
            };
            let (in_memory, _) = project_with_warnings(texels, &s).unwrap();
            assert_eq!(in_memory.encoding.encoding(), encoding);
            assert_eq!(in_memory.to_json_string(), from_file.to_json_string());
        }
        // A NaN inside the image is refused, naming the input.
        padded[5 * stride + 7][1] = f32::NAN;
        let source = StridedImage::new(Layout::Equirect, w, h, stride, &padded).unwrap();
        let p = ProjectSettings::new(2, orientation, Method::Quadrature, Quantity::Radiance);
        let texels = Source::Texels {
            texels: &source,
            name: "mem",
            layout_name: "equirect",
        };
        let e = project_with_warnings(texels, &Settings::new(p)).unwrap_err();
        assert!(e.message().starts_with("mem: 1 texels are NaN"), "{e}");
    }

    /// A projector that reports a uniform light of radiance 1 whatever the
    /// map, and counts its calls.
    struct Uniform(Mutex<usize>);

    impl Projector for Uniform {
        fn project(&self, texels: &dyn TexelSource, s: &ProjectSettings) -> Result<Projection> {
            *self.0.lock().unwrap() += 1;
            if texels.layout() != Layout::Equirect {
                return Err(PipelineError::new("equirect only"));
            }
            let mut coeffs = ShCoeffs::<DVec3>::zeros(s.lmax);
            coeffs[0] = DVec3::splat(2.0 * std::f64::consts::PI.sqrt());
            Ok(Projection::exact(coeffs))
        }
    }

    /// The injected projector makes the coefficients (irradiance of a
    /// uniform unit light is pi in every direction), its error is named
    /// with the map, and progress comes in the order of the steps.
    #[test]
    fn the_injected_projector_and_progress_are_used() {
        let (path, _) = sky();
        let projector = Uniform(Mutex::new(0));
        struct Steps(Mutex<Vec<String>>);
        impl Hooks for Steps {
            fn progress(&self, p: Progress<'_>) {
                if let Progress::Step(m) = p {
                    self.0.lock().unwrap().push(m.to_string());
                }
            }
        }
        let hooks = Steps(Mutex::new(Vec::new()));
        let mut p = ProjectSettings::new(
            2,
            MapOrientation::default(),
            Method::Quadrature,
            Quantity::Irradiance,
        );
        p.window = None;
        let file = project(
            Source::Path(&path),
            &Settings::new(p.clone()),
            &projector,
            &hooks,
        )
        .unwrap();
        assert_eq!(*projector.0.lock().unwrap(), 1);
        let e = file.coeffs.eval(DVec3::new(0.2, -0.9, 0.3).normalize());
        assert!((e - DVec3::splat(std::f64::consts::PI)).abs().max_element() < 1e-12);
        let name = path.display().to_string();
        let steps = hooks.0.lock().unwrap().clone();
        assert_eq!(
            steps,
            [
                format!("reading {name}"),
                format!("projecting {name} (512x256, lmax 2)"),
                format!("choosing windows for {name}"),
            ]
        );
        // Its refusal names the map and the step.
        let strip = vec![[1.0f32; 3]; 6 * 8 * 8];
        let source = StridedImage::new(Layout::Strip, 48, 8, 48, &strip).unwrap();
        let texels = Source::Texels {
            texels: &source,
            name: "strip",
            layout_name: "strip",
        };
        let e = project(texels, &Settings::new(p), &projector, &hooks).unwrap_err();
        assert_eq!(e.message(), "strip: projecting: equirect only");
    }
}

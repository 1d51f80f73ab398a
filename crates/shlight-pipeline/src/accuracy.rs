//! How close a map's encodings come to its exact irradiance, for every
//! front end: [`map_irradiance`] (`shlight irradiance`) and
//! [`compare_encodings`] (`shlight compare`), each a map read by the loader
//! ([`crate::load_map`]) and measured by shlight-accuracy.

use std::path::Path;

use glam::DVec3;
use shlight_accuracy::compare::{CompareRow, compare_map};
use shlight_accuracy::map_irradiance::{IrradianceErrors, MapIrradiance};
use shlight_core::encoding::{DominantLightOptions, Encoded, Encoding, encode_map};
use shlight_core::map::MapOrientation;

use crate::load::{LoadedMap, load_map};
use crate::read_settings::ReadSettings;
use crate::{PipelineError, Result};

/// What [`map_irradiance`] measures, decided before the map is read.
#[derive(Clone, Debug)]
pub struct IrradianceSettings {
    /// How the map is read (layout, reader options, `sanitize`).
    pub read: ReadSettings,
    /// How the map's texels meet world directions; the grid of normals is
    /// read in it too.
    pub orientation: MapOrientation,
    /// The equirect grid of normals, `(width, height)`.
    pub size: (usize, usize),
    /// An encoding of the map to measure against the exact irradiance, its
    /// SH part to the lmax given; `None`: the exact irradiance alone.
    pub encoding: Option<(Encoding, usize)>,
}

/// A map's exact irradiance on a grid of normals, and an encoding's
/// against it ([`map_irradiance`]).
#[derive(Clone, Debug)]
pub struct IrradianceReport {
    /// The map's size in texels.
    pub map_size: (usize, usize),
    /// The normals, their solid angles and the exact irradiance at each.
    pub exact: MapIrradiance,
    /// The encoding measured, when one was asked for.
    pub encoded: Option<EncodedIrradiance>,
}

/// An encoding of a map measured against the map's exact irradiance.
#[derive(Clone, Debug)]
pub struct EncodedIrradiance {
    /// The encoding.
    pub encoding: Encoding,
    /// The lmax of its SH part.
    pub lmax: usize,
    /// The encoded light.
    pub light: Encoded,
    /// Its irradiance at the normals.
    pub estimate: Vec<DVec3>,
    /// The estimate minus the exact irradiance at each normal.
    pub difference: Vec<DVec3>,
    /// Its errors; `None` for a map without light (relative errors do not
    /// exist there).
    pub errors: Option<IrradianceErrors>,
}

/// Reads the map at `path` (warnings to `warn` as soon as it is read) and
/// computes its exact irradiance at the texel centres of an equirect grid
/// of normals (shlight-accuracy's [`MapIrradiance`], `progress(n)` as `n`
/// more normals are done) and, when asked, the irradiance of one of its
/// encodings (the dominant lights' default options) and its errors.
///
/// # Errors
/// The loader's ([`load_map`]), or an empty grid of normals.
pub fn map_irradiance(
    path: &Path,
    s: &IrradianceSettings,
    warn: &dyn Fn(&str),
    progress: &(dyn Fn(usize) + Sync),
) -> Result<IrradianceReport> {
    let name = path.display().to_string();
    let loaded = load(path, &s.read, warn)?;
    let map = loaded.map(s.orientation, &name)?;
    let exact = MapIrradiance::on_equirect(&map, s.size, s.orientation, progress)
        .map_err(|e| PipelineError::new(e.to_string()))?;
    let encoded = s.encoding.map(|(encoding, lmax)| {
        let light = encode_map(&map, encoding, lmax, &DominantLightOptions::default());
        let estimate = exact.estimate(&light);
        EncodedIrradiance {
            encoding,
            lmax,
            difference: exact.difference(&estimate),
            errors: exact.errors(&estimate),
            light,
            estimate,
        }
    });
    Ok(IrradianceReport {
        map_size: (map.width, map.height),
        exact,
        encoded,
    })
}

/// The name [`compare_encodings`] gives the map at `path` in its rows: the
/// file's stem (the path itself when it has none).
#[must_use]
pub fn compare_name(path: &Path) -> String {
    path.file_stem().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

/// Reads the map at `path` (warnings to `warn`) and measures every
/// encoding of shlight-accuracy's comparison against its exact irradiance
/// on a `normals` grid ([`compare_map`], the dominant lights' default
/// options), the rows named [`compare_name`].
///
/// # Errors
/// The loader's ([`load_map`]).
pub fn compare_encodings(
    path: &Path,
    read: &ReadSettings,
    orientation: MapOrientation,
    normals: (usize, usize),
    warn: &dyn Fn(&str),
) -> Result<Vec<CompareRow>> {
    let loaded = load(path, read, warn)?;
    let map = loaded.map(orientation, &path.display().to_string())?;
    Ok(compare_map(
        &compare_name(path),
        &map,
        normals,
        &DominantLightOptions::default(),
    ))
}

/// [`load_map`] with `read`, its warnings handed to `warn`.
fn load(path: &Path, read: &ReadSettings, warn: &dyn Fn(&str)) -> Result<LoadedMap> {
    let loaded = load_map(path, read)?;
    for w in &loaded.warnings {
        warn(w);
    }
    Ok(loaded)
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_core::sh::Frame;
    use shlight_io::{Image, WriteOptions, write_image};

    /// The measurement of a map file is the library's own of the same
    /// texels: the exact irradiance, the encoding and its errors; the
    /// loader's warnings reach `warn`, and the comparison's rows are named
    /// by the file's stem.
    #[test]
    fn a_map_file_is_measured_as_its_texels() {
        let dir = std::env::temp_dir().join(format!("shlight-accuracy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("sunny.exr");
        let (w, h) = (32, 16);
        let mut image = Image::from_fn(w, h, |x, y| {
            let sun = if (x, y) == (9, 4) { 400.0 } else { 0.0 };
            [0.2 + sun, 0.3 + sun, 0.4 + 0.01 * y as f32]
        });
        image.set(3, 12, [-0.25, 0.1, 0.1]);
        write_image(&path, &image, &WriteOptions::default()).unwrap();
        let o = MapOrientation {
            frame: Frame::ZUp,
            mirror: true,
        };
        let s = IrradianceSettings {
            read: ReadSettings::default(),
            orientation: o,
            size: (8, 4),
            encoding: Some((Encoding::DominantSh, 2)),
        };
        let warnings = std::cell::RefCell::new(Vec::new());
        let warn = |m: &str| warnings.borrow_mut().push(m.to_string());
        let report = map_irradiance(&path, &s, &warn, &|_| {}).unwrap();
        assert_eq!(warnings.borrow().len(), 1);
        assert!(warnings.borrow()[0].contains("negative"), "{warnings:?}");

        let loaded = load_map(&path, &s.read).unwrap();
        let map = loaded.map(o, "sunny").unwrap();
        let exact = MapIrradiance::on_equirect(&map, (8, 4), o, &|_| {}).unwrap();
        assert_eq!(report.map_size, (w, h));
        assert_eq!(report.exact, exact);
        let light = encode_map(
            &map,
            Encoding::DominantSh,
            2,
            &DominantLightOptions::default(),
        );
        let estimate = exact.estimate(&light);
        let encoded = report.encoded.unwrap();
        assert_eq!((encoded.encoding, encoded.lmax), (Encoding::DominantSh, 2));
        assert_eq!(encoded.light.lights().len(), light.lights().len());
        assert_eq!(encoded.estimate, estimate);
        assert_eq!(encoded.difference, exact.difference(&estimate));
        assert_eq!(encoded.errors, exact.errors(&estimate));

        let rows = compare_encodings(&path, &s.read, o, (8, 4), &|_| {}).unwrap();
        assert_eq!(
            rows,
            compare_map("sunny", &map, (8, 4), &DominantLightOptions::default())
        );
        assert_eq!(compare_name(Path::new("dir/park.exr")), "park");
        let missing = dir.join("missing.exr");
        let e = compare_encodings(&missing, &s.read, o, (8, 4), &|_| {}).unwrap_err();
        assert!(e.message().contains("missing.exr"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

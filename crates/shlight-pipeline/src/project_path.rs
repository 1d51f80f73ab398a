//! [`project_path`] and [`project_source`]: every step of `shlight project`
//! on one file, or on texels already in memory.

use std::path::Path;

use shlight_core::map::{EnvMap, TexelSource};
use shlight_format::CoeffFile;
use shlight_io::{Image, ReadOptions};

use crate::coefficient_file::{MapInfo, choose_windows, coefficient_file};
use crate::input_layout::{InputLayout, is_faces};
use crate::load::{check_values, load_map, sanitize_image};
use crate::projection::{project_radiance, project_radiance_texels};
use crate::settings::ProjectSettings;
use crate::source_stats::source_stats;
use crate::{PipelineError, Result};

/// How input files are read: their layout, the reader's options, and
/// whether bad values are replaced instead of refused.
#[derive(Clone, Debug, Default)]
pub struct ReadSettings {
    /// The layout of the inputs (`auto` by aspect ratio).
    pub layout: InputLayout,
    /// EXR layer and pixel limit.
    pub read: ReadOptions,
    /// Replace NaN, infinities and negatives ([`crate::sanitize_image`]).
    pub sanitize: bool,
}

/// Reads, checks and projects the map at `path` and returns its coefficient
/// file (provenance `input` is `path` as given) with the warnings for the
/// user: [`load_map`], [`project_radiance`], [`choose_windows`],
/// [`coefficient_file`], the same steps and messages as `shlight project`.
///
/// # Errors
/// Any step's error; every message names `path`.
pub fn project_path(
    path: &Path,
    read: &ReadSettings,
    s: &ProjectSettings,
) -> Result<(CoeffFile, Vec<String>)> {
    let name = path.display().to_string();
    let loaded = load_map(path, read.layout, &read.read, read.sanitize)?;
    let (image, layout) = (&loaded.image, loaded.layout);
    let map = EnvMap::new(
        layout,
        s.orientation,
        image.width(),
        image.height(),
        image.pixels(),
    )
    .map_err(|e| PipelineError::new(e.to_string()).context(format!("{name}: projecting")))?;
    let projection = project_radiance(&map, s);
    let windows = choose_windows(&projection.coeffs, s, &name)?;
    let info = MapInfo {
        name: name.clone(),
        width: image.width(),
        height: image.height(),
        layout: if is_faces(path) {
            "faces".into()
        } else {
            layout.name().into()
        },
        stats: loaded.stats,
        sanitized: loaded.sanitized,
    };
    Ok((
        coefficient_file(&projection, windows, s, &info),
        loaded.warnings,
    ))
}

/// Checks and projects texels already in memory (a numpy array, a GPU
/// readback), read in place through [`TexelSource`], and returns their
/// coefficient file (provenance `input` is `name`, `layout` is
/// `layout_name`) with the warnings for the user: the steps of
/// [`project_path`] after reading. With `sanitize` the texels are copied
/// and sanitized ([`sanitize_image`]) first; without it NaN and infinities
/// are refused ([`check_values`]). The coefficients equal those of a file
/// holding the same texels, bit for bit.
///
/// # Errors
/// Non-finite texels without `sanitize`, a size that does not fit the
/// source's layout, no window found for `auto`; messages name `name`.
pub fn project_source<S: TexelSource + ?Sized>(
    source: &S,
    name: &str,
    layout_name: &str,
    sanitize: bool,
    s: &ProjectSettings,
) -> Result<(CoeffFile, Vec<String>)> {
    let (w, h) = source.size();
    let layout = source.layout();
    layout
        .check_size(w, h)
        .map_err(|e| PipelineError::new(format!("{name}: {e}")))?;
    let mut warnings = Vec::new();
    let stats = source_stats(source);
    let (projection, sanitized) = if sanitize {
        let mut image = Image::from_fn(w, h, |x, y| source.texel(x, y));
        let counts = sanitize_image(name, &mut image, &mut warnings);
        let map = EnvMap::new(layout, s.orientation, w, h, image.pixels()).map_err(|e| {
            PipelineError::new(e.to_string()).context(format!("{name}: projecting"))
        })?;
        (project_radiance(&map, s), Some(counts))
    } else {
        check_values(name, &stats, &mut warnings)?;
        let projection = project_radiance_texels(source, s)
            .map_err(|e| e.context(format!("{name}: projecting")))?;
        (projection, None)
    };
    let windows = choose_windows(&projection.coeffs, s, name)?;
    let info = MapInfo {
        name: name.to_string(),
        width: w,
        height: h,
        layout: layout_name.to_string(),
        stats,
        sanitized,
    };
    Ok((coefficient_file(&projection, windows, s, &info), warnings))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Method;
    use shlight_core::map::montecarlo::{McOptions, SamplerKind};
    use shlight_core::map::{Layout, MapOrientation, StridedImage};
    use shlight_core::sh::Frame;
    use shlight_format::Quantity;
    use shlight_io::read_image;

    /// A bundled map read from its file and the same texels in memory with
    /// a row pitch give the same coefficient file but for the input's name
    /// and layout wording, bit for bit, for both methods.
    #[test]
    fn texels_in_memory_project_as_their_file() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../envmaps/sky.exr");
        let image = read_image(&path, &ReadOptions::default()).unwrap();
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
        for method in [
            Method::Quadrature,
            Method::MonteCarlo {
                options: McOptions {
                    samples: 4096,
                    ..McOptions::default()
                },
                sampler: SamplerKind::Importance,
            },
        ] {
            let mut s = ProjectSettings::new(4, orientation, method, Quantity::Irradiance);
            s.window = None;
            let (from_file, _) = project_path(&path, &ReadSettings::default(), &s).unwrap();
            let name = path.display().to_string();
            let (in_memory, _) = project_source(&source, &name, "equirect", false, &s).unwrap();
            assert_eq!(in_memory.to_json_string(), from_file.to_json_string());
        }
        // A NaN inside the image is refused, naming the input.
        padded[5 * stride + 7][1] = f32::NAN;
        let source = StridedImage::new(Layout::Equirect, w, h, stride, &padded).unwrap();
        let s = ProjectSettings::new(2, orientation, Method::Quadrature, Quantity::Radiance);
        let e = project_source(&source, "mem", "equirect", false, &s).unwrap_err();
        assert!(e.message().starts_with("mem: 1 texels are NaN"), "{e}");
    }
}

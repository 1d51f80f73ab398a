//! Reading an input map and checking its values: the first step of
//! `shlight project` ([`load_map`]).

use std::path::Path;

use shlight_core::map::{EnvMap, Layout, MapOrientation};
use shlight_format::SanitizeCounts;
use shlight_io::{
    Image, IoError, IoErrorKind, PixelStats, ReadOptions, read_image, read_image_by_rows,
};

use crate::input_layout::{FACE_NAMES, FACE_PLACEHOLDER, InputLayout, face_paths, is_faces};
use crate::map_info::MapInfo;
use crate::read_settings::ReadSettings;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// `width x height` texels of `layout`, row after row, as a map read in
/// `orientation`: the one place the pipeline makes an [`EnvMap`]; the
/// other steps are handed it.
///
/// # Errors
/// The size does not fit `layout`, or `pixels` is not `width * height`
/// texels; the message is the layout's.
pub(crate) fn env_map(
    layout: Layout,
    orientation: MapOrientation,
    (width, height): (usize, usize),
    pixels: &[[f32; 3]],
) -> Result<EnvMap<'_>> {
    EnvMap::new(layout, orientation, width, height, pixels)
        .map_err(|e| PipelineError::new(e.to_string()))
}

/// A map read and checked by [`load_map`].
#[derive(Debug)]
pub struct LoadedMap {
    /// The texels (six faces as a [`Layout::Strip`]); sanitized when asked.
    pub image: Image,
    /// Its layout.
    pub layout: Layout,
    /// Statistics of the values as read (before any sanitizing).
    pub stats: PixelStats,
    /// What sanitizing replaced, when it was asked for.
    pub sanitized: Option<SanitizeCounts>,
    /// Warnings for the user (a stretched equirect map, negative texels,
    /// replaced values), each naming the input.
    pub warnings: Vec<String>,
}

impl LoadedMap {
    /// The texels as a map in `orientation`, for the steps after reading.
    ///
    /// # Errors
    /// None in practice ([`load_map`] settled a layout the size fits); the
    /// message would name `name`.
    pub fn map(&self, orientation: MapOrientation, name: &str) -> Result<EnvMap<'_>> {
        let size = (self.image.width(), self.image.height());
        env_map(self.layout, orientation, size, self.image.pixels()).map_err(|e| e.context(name))
    }

    /// What the coefficient file records of this map ([`MapInfo`]): named
    /// `name`, its layout named `layout`.
    #[must_use]
    pub fn info(&self, name: &str, layout: &str) -> MapInfo {
        let size = (self.image.width(), self.image.height());
        MapInfo::new(name, layout, size, self.stats, self.sanitized)
    }

    /// A map decoded elsewhere (from memory, say), checked as [`load_map`]
    /// checks a file: its layout settled from its size ([`layout_for_size`])
    /// and its values refused, kept with a warning, or with `sanitize`
    /// replaced. `name` names it in every message.
    ///
    /// # Errors
    /// As [`load_map`] for a single image.
    pub fn from_image(name: &str, image: Image, read: &ReadSettings) -> Result<Self> {
        let mut warnings = Vec::new();
        let (w, h) = (image.width(), image.height());
        let layout = layout_for_size(name, read.layout, w, h, read.spelling, &mut warnings)?;
        let stats = image.stats();
        Self::checked(name, image, layout, stats, warnings, read)
    }

    /// `image` of `layout`, whose values have the statistics `stats`,
    /// refused (NaN or infinite texels) or kept with a warning added to
    /// `warnings` ([`check_values`]), or with `read.sanitize` replaced
    /// ([`sanitize_image`]).
    pub(crate) fn checked(
        name: &str,
        mut image: Image,
        layout: Layout,
        stats: PixelStats,
        mut warnings: Vec<String>,
        read: &ReadSettings,
    ) -> Result<Self> {
        let sanitized = if read.sanitize {
            Some(sanitize_image(
                name,
                &mut image,
                read.spelling,
                &mut warnings,
            ))
        } else {
            check_values(name, &stats, read.spelling, &mut warnings)?;
            None
        };
        Ok(Self {
            image,
            layout,
            stats,
            sanitized,
            warnings,
        })
    }
}

/// Reads the six face files of `path` (all must exist, be square and of
/// one size) and lays them side by side as a strip, +X -X +Y -Y +Z -Z.
fn read_faces(path: &Path, read: &ReadOptions, spelling: Spelling) -> Result<Image> {
    let mut faces: Vec<(std::path::PathBuf, Image)> = Vec::with_capacity(6);
    for p in face_paths(path) {
        if !p.exists() {
            return Err(PipelineError::new(format!(
                "{}: face file {} does not exist (a {FACE_PLACEHOLDER} input needs all six: {})",
                path.display(),
                p.display(),
                FACE_NAMES.join(" ")
            )));
        }
        let image = read_image(&p, read)
            .map_err(|e| read_error(e, spelling).context(format!("reading {}", p.display())))?;
        if image.width() != image.height() {
            return Err(PipelineError::new(format!(
                "{}: a cube face must be square, not {}x{}",
                p.display(),
                image.width(),
                image.height()
            )));
        }
        if let Some((first, f)) = faces.first()
            && f.width() != image.width()
        {
            return Err(PipelineError::new(format!(
                "{}: {}x{} faces, but {} is {}x{}; all six must be the same size",
                p.display(),
                image.width(),
                image.height(),
                first.display(),
                f.width(),
                f.height()
            )));
        }
        faces.push((p, image));
    }
    let n = faces[0].1.width();
    let (w, h) = Layout::Strip.dimensions(n);
    let max = read.max_pixels;
    if w.checked_mul(h).is_none_or(|p| p > max) {
        return Err(PipelineError::new(format!(
            "{}: six faces of {n}x{n} make more than {}",
            path.display(),
            spelling.option_number("max_pixels", max, max)
        )));
    }
    Ok(Image::from_fn(w, h, |x, y| faces[x / n].1.get(x % n, y)))
}

/// Reads an input (or, for `{face}`, six faces as a strip), settles its
/// layout (warning when a map forced to [`Layout::Equirect`] is not 2:1:
/// equirect geometry holds for any size, so it is projected, but such a map
/// is more often a crop or another layout than a stretched panorama), and
/// checks its values: NaN/inf are refused (or with `sanitize` replaced, see
/// [`Image::sanitize`]), negatives are kept with a warning (or replaced).
///
/// # Errors
/// An unreadable file, a size that fits no layout (or not the one named),
/// a `{face}` input with a single-image layout (or the reverse), missing or
/// mismatched faces, NaN or infinite texels without `sanitize`. Every
/// message names the input.
pub fn load_map(path: &Path, read: &ReadSettings) -> Result<LoadedMap> {
    let name = path.display();
    let spelling = read.spelling;
    match (is_faces(path), read.layout) {
        (true, InputLayout::Auto | InputLayout::Faces) => {
            let image = read_faces(path, &read.read, spelling)?;
            let stats = image.stats();
            let name = name.to_string();
            LoadedMap::checked(&name, image, Layout::Strip, stats, Vec::new(), read)
        }
        (true, InputLayout::Image(l)) => Err(PipelineError::new(format!(
            "{name}: an input with {FACE_PLACEHOLDER} names six face files; it needs {} or auto, not {l}",
            spelling.option_value("layout", "faces")
        ))),
        (false, InputLayout::Faces) => Err(faces_need_a_placeholder(&name.to_string(), spelling)),
        (false, _) => {
            // By rows: a large compressed map then takes its texels'
            // memory, not the file's besides.
            let image =
                read_image_by_rows(path, &read.read).map_err(|e| read_error(e, spelling))?;
            LoadedMap::from_image(&name.to_string(), image, read)
        }
    }
}

/// A reader's error, with the setting that raises the pixel limit named as
/// `spelling` does where the image was too large.
pub(crate) fn read_error(e: IoError, spelling: Spelling) -> PipelineError {
    let too_large = matches!(e.kind(), IoErrorKind::TooLarge { .. });
    let error = PipelineError::from(e);
    if too_large {
        error.context_after(format!(
            "raise the limit with {}",
            spelling.option("max_pixels")
        ))
    } else {
        error
    }
}

/// The refusal of the faces layout for an input that names one file.
fn faces_need_a_placeholder(name: &str, spelling: Spelling) -> PipelineError {
    PipelineError::new(format!(
        "{name}: {} reads six files named by an input containing {FACE_PLACEHOLDER} (e.g. sky_{FACE_PLACEHOLDER}.exr for sky_px.exr ... sky_nz.exr)",
        spelling.option_value("layout", "faces")
    ))
}

/// The layout of a single `w x h` image named `name`: by aspect ratio for
/// [`InputLayout::Auto`] ([`Layout::detect`]), or the one named, checked
/// against the size, with a warning pushed when an equirect map is not 2:1
/// (see [`load_map`]).
///
/// # Errors
/// No layout fits the aspect ratio, the size does not fit the layout named,
/// or the layout is [`InputLayout::Faces`] (six files, not one image).
pub fn layout_for_size(
    name: &str,
    layout: InputLayout,
    w: usize,
    h: usize,
    spelling: Spelling,
    warnings: &mut Vec<String>,
) -> Result<Layout> {
    let layout = match layout {
        InputLayout::Faces => return Err(faces_need_a_placeholder(name, spelling)),
        InputLayout::Auto => {
            return Layout::detect(w, h).ok_or_else(|| {
                PipelineError::new(format!(
                    "{name}: a {w}x{h} image fits no layout by its aspect ratio (2:1 equirect, 4:3 cross-h, 3:4 cross-v, 6:1 strip, 1:1 angular); name one with {}",
                    spelling.option("layout")
                ))
            });
        }
        InputLayout::Image(layout) => layout,
    };
    if let Err(e) = layout.check_size(w, h) {
        return Err(PipelineError::new(format!("{name}: {e}")));
    }
    if layout == Layout::Equirect && w != 2 * h {
        warnings.push(format!(
            "{name}: {w}x{h} is not 2:1; projected as an equirect map stretched over the whole sphere ({:.3}° of longitude by {:.3}° of latitude per texel); a crop or another layout gives wrong coefficients",
            360.0 / w as f64,
            180.0 / h as f64
        ));
    }
    Ok(layout)
}

/// The value check of [`load_map`] without sanitizing: NaN or infinite
/// texels are refused, negative ones kept with a warning pushed to
/// `warnings`.
///
/// # Errors
/// `stats` counts non-finite values; the message names `name`, the count
/// and the first such texel.
pub fn check_values(
    name: &str,
    stats: &PixelStats,
    spelling: Spelling,
    warnings: &mut Vec<String>,
) -> Result<()> {
    if stats.non_finite > 0 {
        let (x, y) = stats.first_non_finite.unwrap_or((0, 0));
        return Err(PipelineError::new(format!(
            "{name}: {} texels are NaN or infinite (the first at x={x}, y={y}); {} replaces them",
            stats.non_finite,
            spelling.option("sanitize")
        )));
    }
    if stats.negative > 0 {
        warnings.push(format!(
            "{name}: {} negative texels (minimum {}), kept as data",
            stats.negative, stats.min_value
        ));
    }
    Ok(())
}

/// Sanitizes `image` in place ([`Image::sanitize`]), pushing a warning that
/// names `name` and counts what was replaced, if anything was.
pub fn sanitize_image(
    name: &str,
    image: &mut Image,
    spelling: Spelling,
    warnings: &mut Vec<String>,
) -> SanitizeCounts {
    let counts = SanitizeCounts::from(image.sanitize());
    sanitize_warning(name, &counts, spelling, warnings);
    counts
}

/// The warning of [`sanitize_image`] for `counts`, pushed to `warnings`
/// when anything was replaced.
pub(crate) fn sanitize_warning(
    name: &str,
    counts: &SanitizeCounts,
    spelling: Spelling,
    warnings: &mut Vec<String>,
) {
    if counts.total() > 0 {
        warnings.push(format!(
            "{name}: {} replaced {} values: {} NaN and {} -inf by 0, {} +inf by {}, {} negative by 0",
            spelling.option("sanitize"),
            counts.total(),
            counts.nan,
            counts.negative_infinite,
            counts.positive_infinite,
            counts.infinity_replacement,
            counts.negative
        ));
    }
}

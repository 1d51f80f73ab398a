//! The environment-map inputs of `shlight project` and `shlight irradiance`:
//! `--layout`, six-face `{face}` inputs, and the checks every map passes
//! (layout by size, NaN/inf refused or `--sanitize`d, negatives reported).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use shlight_core::layout::Layout;
use shlight_core::rotation::Frame;
use shlight_format::SanitizeCounts;
use shlight_io::{Image, PixelStats, ReadOptions, read_image};

use crate::progress::Ui;

/// `--up y|z` as a frame.
pub fn frame_of(up: &str) -> Frame {
    if up == "z" { Frame::ZUp } else { Frame::YUp }
}

/// `--layout` of `shlight project`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputLayout {
    /// [`Layout::detect`] by aspect ratio (or six faces for `{face}` inputs).
    Auto,
    /// Six face files, `{face}` in the input name.
    Faces,
    /// One image in this layout.
    Image(Layout),
}

/// `--layout NAME`.
pub fn parse_input_layout(s: &str) -> std::result::Result<InputLayout, String> {
    match s.trim() {
        "auto" => Ok(InputLayout::Auto),
        "faces" => Ok(InputLayout::Faces),
        name => name
            .parse::<Layout>()
            .map(InputLayout::Image)
            .map_err(|e| format!("{e} (or auto, faces)")),
    }
}

/// The placeholder of six-face inputs, and the faces' names in strip order
/// (+X -X +Y -Y +Z -Z).
pub const FACE_PLACEHOLDER: &str = "{face}";
/// Face names replacing [`FACE_PLACEHOLDER`], in strip order.
pub const FACE_NAMES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// Whether an input names six face files (holds [`FACE_PLACEHOLDER`]).
pub fn is_faces(path: &Path) -> bool {
    path.to_string_lossy().contains(FACE_PLACEHOLDER)
}

/// The six face files of a `{face}` input, in strip order.
fn face_paths(path: &Path) -> Vec<PathBuf> {
    let pattern = path.to_string_lossy();
    FACE_NAMES
        .iter()
        .map(|f| PathBuf::from(pattern.replace(FACE_PLACEHOLDER, f)))
        .collect()
}

/// Reads the six face files of `path` (all must exist, be square and of
/// one size) and lays them side by side as a strip, +X -X +Y -Y +Z -Z.
fn read_faces(path: &Path, read: &ReadOptions) -> Result<Image> {
    let mut faces: Vec<(PathBuf, Image)> = Vec::with_capacity(6);
    for p in face_paths(path) {
        if !p.exists() {
            bail!(
                "{}: face file {} does not exist (a {FACE_PLACEHOLDER} input needs all six: {})",
                path.display(),
                p.display(),
                FACE_NAMES.join(" ")
            );
        }
        let image = read_image(&p, read).with_context(|| format!("reading {}", p.display()))?;
        if image.width() != image.height() {
            bail!(
                "{}: a cube face must be square, not {}x{}",
                p.display(),
                image.width(),
                image.height()
            );
        }
        if let Some((first, f)) = faces.first()
            && f.width() != image.width()
        {
            bail!(
                "{}: {}x{} faces, but {} is {}x{}; all six must be the same size",
                p.display(),
                image.width(),
                image.height(),
                first.display(),
                f.width(),
                f.height()
            );
        }
        faces.push((p, image));
    }
    let n = faces[0].1.width();
    let (w, h) = Layout::Strip.dimensions(n);
    let max = read.max_pixels;
    if w.checked_mul(h).is_none_or(|p| p > max) {
        bail!(
            "{}: six faces of {n}x{n} make more than --max-pixels {max}",
            path.display()
        );
    }
    Ok(Image::from_fn(w, h, |x, y| faces[x / n].1.get(x % n, y)))
}

/// Reads an input (or, for `{face}`, six faces as a strip), settles its
/// layout (warning when a map forced to `--layout equirect` is not 2:1:
/// equirect geometry holds for any size, so it is projected, but such a map
/// is more often a crop or another layout than a stretched panorama), and checks its values: NaN/inf are refused (or with
/// `--sanitize` replaced, see [`Image::sanitize`]), negatives are kept with
/// a warning (or replaced). Returns the image, its layout, the statistics
/// of the values as read, and what was replaced.
pub fn load(
    path: &Path,
    input_layout: InputLayout,
    read: &ReadOptions,
    sanitize: bool,
    ui: &Ui,
) -> Result<(Image, Layout, PixelStats, Option<SanitizeCounts>)> {
    let name = path.display();
    let faces = is_faces(path);
    let (mut image, layout) = match (faces, input_layout) {
        (true, InputLayout::Auto | InputLayout::Faces) => (read_faces(path, read)?, Layout::Strip),
        (true, InputLayout::Image(l)) => bail!(
            "{name}: an input with {FACE_PLACEHOLDER} names six face files; it needs --layout faces or auto, not {l}"
        ),
        (false, InputLayout::Faces) => bail!(
            "{name}: --layout faces reads six files named by an INPUT containing {FACE_PLACEHOLDER} (e.g. sky_{FACE_PLACEHOLDER}.exr for sky_px.exr ... sky_nz.exr)"
        ),
        (false, InputLayout::Auto) => {
            let image = read_image(path, read)?;
            let (w, h) = (image.width(), image.height());
            let Some(layout) = Layout::detect(w, h) else {
                bail!(
                    "{name}: a {w}x{h} image fits no layout by its aspect ratio (2:1 equirect, 4:3 cross-h, 3:4 cross-v, 6:1 strip, 1:1 angular); name one with --layout"
                );
            };
            (image, layout)
        }
        (false, InputLayout::Image(layout)) => {
            let image = read_image(path, read)?;
            if let Err(e) = layout.check_size(image.width(), image.height()) {
                bail!("{name}: {e}");
            }
            let (w, h) = (image.width(), image.height());
            if layout == Layout::Equirect && w != 2 * h {
                ui.warn(format!(
                    "{name}: {w}x{h} is not 2:1; projected as an equirect map stretched over the                      whole sphere ({:.3}° of longitude by {:.3}° of latitude per texel);                      a crop or another layout gives wrong coefficients",
                    360.0 / w as f64,
                    180.0 / h as f64
                ));
            }
            (image, layout)
        }
    };
    let stats = image.stats();
    if sanitize {
        let counts = SanitizeCounts::from(image.sanitize());
        if counts.total() > 0 {
            ui.warn(format!(
                "{name}: --sanitize replaced {} values: {} NaN and {} -inf by 0, {} +inf by {}, {} negative by 0",
                counts.total(),
                counts.nan,
                counts.negative_infinite,
                counts.positive_infinite,
                counts.infinity_replacement,
                counts.negative
            ));
        }
        return Ok((image, layout, stats, Some(counts)));
    }
    if stats.non_finite > 0 {
        let (x, y) = stats.first_non_finite.unwrap_or((0, 0));
        bail!(
            "{name}: {} texels are NaN or infinite (the first at x={x}, y={y}); --sanitize replaces them",
            stats.non_finite
        );
    }
    if stats.negative > 0 {
        ui.warn(format!(
            "{name}: {} negative texels (minimum {}), kept as data",
            stats.negative, stats.min_value
        ));
    }
    Ok((image, layout, stats, None))
}

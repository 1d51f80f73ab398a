//! [`project_path`]: every step of `shlight project` on one file.

use std::path::Path;

use shlight_core::layout::EnvMap;
use shlight_format::CoeffFile;
use shlight_io::ReadOptions;

use crate::coefficient_file::{MapInfo, choose_windows, coefficient_file};
use crate::input_layout::{InputLayout, is_faces};
use crate::load::load_map;
use crate::projection::project_radiance;
use crate::settings::ProjectSettings;
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

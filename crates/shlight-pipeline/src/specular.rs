//! The specular half of image-based lighting as files: a map read by the
//! loader and prefiltered by shlight-specular ([`prefilter_map`]), written
//! as one float EXR per mip and face named as cmgen's `--ibl-ld` names
//! them ([`write_prefiltered_faces`]); the DFG table as EXR or PNG
//! ([`write_dfg`]).

use std::path::{Path, PathBuf};

use shlight_core::map::{CubeFace, MapOrientation};
use shlight_io::{Image, WriteOptions, srgb_to_linear, write_image};
use shlight_specular::{DfgTable, PrefilterSettings, Prefiltered, prefilter};

use crate::load::load_map;
use crate::settings::ReadSettings;
use crate::{PipelineError, Result};

/// cmgen's face names, in [`CubeFace::ALL`] order (`+X -X +Y -Y +Z -Z`).
pub const CMGEN_FACE_NAMES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// What [`prefilter_map`] does, decided before the map is read.
#[derive(Clone, Debug)]
pub struct PrefilterRequest {
    /// How the map is read.
    pub read: ReadSettings,
    /// How its texels meet world directions.
    pub orientation: MapOrientation,
    /// The cube, its mips, samples and engine.
    pub settings: PrefilterSettings,
}

/// Reads the map at `path` (warnings to `warn`) and prefilters it
/// (shlight-specular's `prefilter`, `progress(rows)` as rows of faces are
/// done).
///
/// # Errors
/// The loader's ([`load_map`]) or refused settings, naming the input.
pub fn prefilter_map(
    path: &Path,
    request: &PrefilterRequest,
    warn: &dyn Fn(&str),
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Prefiltered> {
    request
        .settings
        .check()
        .map_err(|e| PipelineError::new(e.to_string()))?;
    let name = path.display().to_string();
    let loaded = load_map(
        path,
        request.read.layout,
        &request.read.read,
        request.read.sanitize,
    )?;
    for w in &loaded.warnings {
        warn(w);
    }
    let map = loaded.map(request.orientation, &name)?;
    prefilter(&map, &request.settings, progress).map_err(|e| PipelineError::new(e.to_string()))
}

/// The file cmgen's `--ibl-ld` gives face `face` of mip `level`:
/// `m<level>_<face>.exr`, faces `px nx py ny pz nz`.
#[must_use]
pub fn cmgen_face_file(level: usize, face: CubeFace) -> String {
    format!("m{level}_{}.exr", CMGEN_FACE_NAMES[face.index()])
}

/// Writes every mip and face of `cube` into `dir` (created if missing) as
/// 32-bit float OpenEXR files named by [`cmgen_face_file`], each face
/// upright as cmgen writes it (row 0 at the top, the OpenGL cube-map
/// convention of shlight-core's `CubeFace`); returns the paths written.
///
/// # Errors
/// The directory cannot be made or a file cannot be written (each written
/// atomically), naming the file.
pub fn write_prefiltered_faces(cube: &Prefiltered, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| {
        PipelineError::new(format!("{}: cannot make the directory: {e}", dir.display()))
    })?;
    let mut written = Vec::new();
    for (level, mip) in cube.levels.iter().enumerate() {
        let size = mip.cube.size();
        for face in CubeFace::ALL {
            let path = dir.join(cmgen_face_file(level, face));
            let image = Image::new(size, size, mip.cube.face(face)).expect("size x size texels");
            write_image(&path, &image, &WriteOptions::default())?;
            written.push(path);
        }
    }
    Ok(written)
}

/// Writes `table` to `path`: OpenEXR (`.exr`, 32-bit float, the two values
/// in red and green, blue 0) or PNG (`.png`, 8 bits per channel holding the
/// values themselves, `round(255 v)`, not sRGB-encoded: what engines
/// upload as a linear RG8 table).
///
/// # Errors
/// Another extension, or the file cannot be written, naming the file.
pub fn write_dfg(table: &DfgTable, path: &Path) -> Result<()> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let png = match ext.as_str() {
        "exr" => false,
        "png" => true,
        _ => {
            return Err(PipelineError::new(format!(
                "{}: a DFG table is written as .exr or .png",
                path.display()
            )));
        }
    };
    // PNG: the writer sRGB-encodes, so hand it the values sRGB-decoded.
    let texel = |v: f64| {
        let v = v as f32;
        if png {
            srgb_to_linear(v.clamp(0.0, 1.0))
        } else {
            v
        }
    };
    let pixels = table
        .values
        .iter()
        .map(|[a, b]| [texel(*a), texel(*b), 0.0])
        .collect();
    let image = Image::new(table.size, table.size, pixels).expect("size x size texels");
    write_image(path, &image, &WriteOptions::default())?;
    Ok(())
}

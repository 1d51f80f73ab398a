//! The specular half of image-based lighting as files: a map read by the
//! loader and prefiltered by shlight-specular ([`prefilter_map`]), written
//! as one float EXR per mip and face named as cmgen's `--ibl-ld` names
//! them ([`write_prefiltered_faces`]); the DFG table as EXR or PNG
//! ([`write_dfg`]); a glTF light's RGBD specular images
//! ([`gltf_specular_images`]).

use std::path::{Path, PathBuf};

use shlight_core::map::{CubeFace, MapOrientation};
use shlight_core::sh::Frame;
use shlight_io::{Image, WriteOptions, encode_png_rgba8, srgb_to_linear, write_image};
use shlight_specular::{
    DfgTable, PrefilterSettings, Prefiltered, SourceMips, TargetEngine, prefilter,
    prefilter_source, rgbd_encode,
};

use crate::load::load_map;
use crate::read_settings::ReadSettings;
use crate::{PipelineError, Result};

/// cmgen's face names, in [`CubeFace::ALL`] order (`+X -X +Y -Y +Z -Z`).
pub const CMGEN_FACE_NAMES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// Reads the map at `path` (warnings to `warn`) and prefilters it with
/// `settings`, checked by the caller (shlight-specular's `prefilter`,
/// `progress(rows)` as rows of faces are done).
///
/// # Errors
/// The loader's ([`load_map`]), naming the input.
pub(crate) fn prefilter_map(
    path: &Path,
    read: &ReadSettings,
    orientation: MapOrientation,
    settings: &PrefilterSettings,
    warn: &dyn Fn(&str),
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Prefiltered> {
    let name = path.display().to_string();
    let loaded = load_map(path, read)?;
    for w in &loaded.warnings {
        warn(w);
    }
    let map = loaded.map(orientation, &name)?;
    prefilter(&map, settings, progress).map_err(|e| PipelineError::new(e.to_string()))
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

/// The face size of a glTF light's specular cube when none is asked for.
pub const GLTF_SPECULAR_SIZE: usize = 128;

/// The specular images of a glTF light (shlight-format's
/// `gltf::SpecularImages`) from the map at `path`: read as `read` says in
/// `orientation`, turned by `rotation` (the coefficient file's `--rotate`:
/// a light from `a` comes from `R a`), prefiltered for Babylon.js (its
/// roughness per mip, the full chain from `size` down to 1 pixel,
/// `samples` per texel, faces in the light's frame, Babylon's world), each
/// face RGBD-encoded (Babylon's `toRGBD`) as an 8-bit RGBA PNG, its rows
/// bottom first. `progress(rows)` as rows of faces are done.
///
/// # Errors
/// The loader's, refused settings, or a PNG that cannot be encoded, naming
/// the input.
pub fn gltf_specular_images(
    path: &Path,
    read: &ReadSettings,
    orientation: MapOrientation,
    rotation: Option<glam::DMat3>,
    size: usize,
    samples: u32,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<shlight_format::gltf::SpecularImages> {
    let name = path.display().to_string();
    let settings = PrefilterSettings {
        size,
        samples,
        ..PrefilterSettings::new(TargetEngine::Babylon)
    };
    settings
        .check()
        .map_err(|e| PipelineError::new(format!("{name}: specular images: {e}")))?;
    let loaded = load_map(path, read)?;
    let map = loaded.map(orientation, &name)?;
    // Cube direction c (the light's frame) -> shlight's y-up -> the file's frame
    // -> back through the rotation: where the map is read.
    let to_file = Frame::YUp.rotation_to(orientation.frame);
    let undo = rotation.map_or(glam::DMat3::IDENTITY, |r| r.transpose());
    let world_from_cube = undo * to_file * TargetEngine::Babylon.world_from_cube();
    let source = SourceMips::new(
        &map,
        world_from_cube,
        SourceMips::base_size(&map, settings.size),
    );
    let cube = prefilter_source(&source, &settings, progress);
    let mut mips = Vec::new();
    for (k, level) in cube.levels.iter().enumerate() {
        let size = level.cube.size();
        // Rows bottom first: Babylon's loader puts a PNG's first row at the
        // bottom of the face (t = 1 of the OpenGL cube-map convention), the
        // flip the extension's text asks for (measured in tests/web.rs).
        let face = |f: CubeFace| -> Result<Vec<u8>> {
            let texels = level.cube.face(f);
            let rgba: Vec<u8> = texels
                .chunks_exact(size)
                .rev()
                .flatten()
                .flat_map(|p| rgbd_encode(*p))
                .collect();
            let label = format!(
                "{name}: specular mip {k} face {}",
                CMGEN_FACE_NAMES[f.index()]
            );
            Ok(encode_png_rgba8(&label, size, size, &rgba)?)
        };
        mips.push([
            face(CubeFace::PosX)?,
            face(CubeFace::NegX)?,
            face(CubeFace::PosY)?,
            face(CubeFace::NegY)?,
            face(CubeFace::PosZ)?,
            face(CubeFace::NegZ)?,
        ]);
    }
    Ok(shlight_format::gltf::SpecularImages {
        size: settings.size,
        mips,
    })
}

/// The face size of mip 0 and each mip's six faces, `+X -X +Y -Y +Z -Z`,
/// row-major: what the cube-map writers take.
fn faces_by_level(cube: &Prefiltered) -> (usize, Vec<[Vec<[f32; 3]>; 6]>) {
    let levels = cube
        .levels
        .iter()
        .map(|l| CubeFace::ALL.map(|f| l.cube.face(f)))
        .collect();
    (cube.levels.first().map_or(1, |l| l.cube.size()), levels)
}

/// Writes `cube` to `path` as a KTX2 cube map with its mips (shlight-format's
/// `cube_map_ktx2`: RGBA16F, linear, faces `+X -X +Y -Y +Z -Z` in the
/// engine's cube axes): what Bevy's `EnvironmentMapLight` takes as its
/// specular map. Written atomically.
///
/// # Errors
/// The file cannot be written, naming it.
pub fn write_prefiltered_ktx2(cube: &Prefiltered, path: &Path) -> Result<()> {
    let (size, levels) = faces_by_level(cube);
    let writer = concat!("shlight ", env!("CARGO_PKG_VERSION"));
    let bytes = shlight_format::cube_map_ktx2(size, &levels, writer);
    shlight_io::write_atomically(path, |w| w.write_all(&bytes))?;
    Ok(())
}

/// Writes `cube` to `path` as the KTX 1.1 cube map Filament's `KtxBundle`
/// reads (shlight-format's `filament_ktx1`: `R11F_G11F_B10F`, laid out as
/// `cmgen --format=ktx --ibl-ld` writes it). Written atomically.
///
/// # Errors
/// The file cannot be written, naming it.
pub fn write_prefiltered_ktx1(cube: &Prefiltered, path: &Path) -> Result<()> {
    let (size, levels) = faces_by_level(cube);
    let bytes = shlight_format::filament_ktx1(size, &levels);
    shlight_io::write_atomically(path, |w| w.write_all(&bytes))?;
    Ok(())
}

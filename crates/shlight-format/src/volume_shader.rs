//! A probe volume for engines' own shaders: its probes as three float
//! textures and a WGSL or GLSL snippet that shades with them exactly as
//! `shlight sample --lookup shlight` does (the visibility-weighted lookup of
//! shlight-baked's `visibility.rs`, or the validity-weighted trilinear one
//! for a volume without distance maps).
//!
//! # The textures
//! For an `nx x ny x nz` grid of lmax `L` (`C = (L+1)^2` coefficients),
//! each a KTX2 file of one level ([`crate::ktx2`]):
//!
//! - `sh`: `RGBA32F`, `nx x ny x C nz` texels: texel `(x, y, i nz + z)`
//!   holds `(v L_i, v)` of probe `(x, y, z)`, `L_i` its radiance
//!   coefficient `i = l(l+1)+m` (shlight's basis, the file's frame, linear
//!   Rec.709) and `v` its validity (1, or 0 inside geometry). Coefficient
//!   `i` is a sub-volume of its own, so an engine's plain trilinear sampler
//!   may also filter it (`rgb / a` is then the valid probes' trilinear
//!   mean, as `--lookup trilinear`).
//! - `probes`: `RGBA32F`, `nx x ny x nz`: `(q, v)`, `q` the probe's
//!   position (its cell's centre plus the offset the bake moved it by).
//! - `moments` (volumes with distance maps): `RG32F`, `nx (s+2) x ny (s+2) x
//!   nz` for maps of `s x s` texels: probe `(x, y, z)`'s map is the tile at
//!   `(x (s+2), y (s+2))` of slice `z`, its texel `(a, b)` (each `0..s`) at
//!   `(a + 1, b + 1)` of the tile, `(mean, mean_sq)` of the distance; the
//!   tile's one-texel border repeats the texels across the octahedral map's
//!   folded edges (shlight-baked's `octahedral::wrap`), so a bilinear
//!   lookup reads four texels of one tile, in every direction.
//!
//! Every texel is read with an integer load (`textureLoad`, `texelFetch`):
//! no sampler, no filtering, so the textures may stay non-filterable floats
//! (WebGL2 and WebGPU both load `RGBA32F` and `RG32F`).
//!
//! # The snippet
//! `shlight_volume_irradiance(p, n)` (WGSL: the three textures are its
//! first parameters) returns `E(p, n) = sum_lm A_l L_lm(p) Y_lm(n)`, the
//! irradiance `shlight sample` reports at the point `p` (scene units)
//! facing `n` (the file's frame); a Lambertian surface of albedo `rho`
//! leaves `rho / pi E`. The grid, the lmax and the visibility constants
//! are written into it as constants. This file makes the textures and the
//! header comment; the code is shlight-shader's
//! [`shlight_shader::volume`], with the visibility lookup the GPU's volume
//! pass runs too ([`shlight_shader::visibility`]).

use shlight_baked::octahedral::wrap;
use shlight_baked::visibility::{CHEBYSHEV_FLOOR, CRUSH, NORMAL_BIAS};
use shlight_baked::{SHADED_MAX_LMAX, VolumeView};
use shlight_core::sh::sh_count;
pub use shlight_shader::ShaderLanguage;
use shlight_shader::volume::{VisibilityConstants, VolumeConstants, volume_code};

use crate::ktx2::{Ktx2Format, write_ktx2};
use crate::{FormatError, Result, ShvolFile};

/// One of the textures the snippet reads.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeTexture {
    /// `sh`, `probes` or `moments`: the file is `{stem}.{name}.ktx2`.
    pub name: &'static str,
    /// The texel format (`RGBA32F` or `RG32F`).
    pub format: Ktx2Format,
    /// Width, height, depth.
    pub size: [usize; 3],
    /// The texels' channels, x fastest, then y, then z.
    pub texels: Vec<f32>,
}

impl VolumeTexture {
    /// The texture as a KTX2 file.
    #[must_use]
    pub fn ktx2(&self, writer: &str) -> Vec<u8> {
        let bytes: Vec<u8> = self.texels.iter().flat_map(|v| v.to_le_bytes()).collect();
        write_ktx2(self.format, self.size, &bytes, writer)
    }
}

/// A volume ready for an engine's shader: the snippet, the textures it
/// reads and notes for the user.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeShader {
    /// The snippet's text.
    pub text: String,
    /// `sh`, `probes`, and `moments` where the volume has distance maps.
    pub textures: Vec<VolumeTexture>,
    /// Remarks for the user, one sentence each.
    pub notes: Vec<String>,
}

/// The snippet in `language` and the textures of `file`, shaded to the
/// lmax `shlight sample` shades it to (the file's, at most
/// [`SHADED_MAX_LMAX`]; a note says when degrees are left out). `stem` is
/// the textures' file stem the snippet's header names.
///
/// # Errors
/// A volume whose coefficients do not fit 32-bit floats.
pub fn volume_shader(
    file: &ShvolFile,
    language: ShaderLanguage,
    stem: &str,
) -> Result<VolumeShader> {
    let view = file.view();
    let lmax = view.lmax.min(SHADED_MAX_LMAX);
    let mut notes = Vec::new();
    if lmax < view.lmax {
        notes.push(format!(
            "the volume holds lmax {}; the snippet shades to lmax {lmax}, as shlight's volume pass and `shlight sample` do",
            view.lmax
        ));
    }
    if let Some(v) = view.radiance.iter().find(|v| !v.is_finite()) {
        return Err(FormatError::Export(format!(
            "a probe coefficient is {v}, which a shader cannot hold"
        )));
    }
    let mut textures = vec![sh_texture(&view, lmax), probes_texture(&view)];
    if view.visibility.is_some() {
        textures.push(moments_texture(&view));
    }
    let mut text: String = header(&view, lmax, stem, file)
        .lines()
        .map(|l| format!("// {l}\n"))
        .collect();
    text.push_str(&volume_code(language, &constants(&view, lmax)));
    Ok(VolumeShader {
        text,
        textures,
        notes,
    })
}

/// The `sh` texture: coefficient `i` of probe `(x, y, z)` at `(x, y, i nz +
/// z)`, premultiplied by the validity, which alpha holds.
fn sh_texture(view: &VolumeView<'_>, lmax: usize) -> VolumeTexture {
    let [nx, ny, nz] = view.grid.resolution;
    let (count, per) = (sh_count(lmax), sh_count(view.lmax));
    let probes = nx * ny * nz;
    let mut texels = vec![0.0f32; 4 * probes * count];
    for k in 0..probes {
        let v = if view.valid[k] { 1.0 } else { 0.0 };
        let [x, y, z] = view.grid.grid_index(k);
        for i in 0..count {
            let rgb = &view.radiance[3 * (k * per + i)..][..3];
            let at = 4 * (x + nx * (y + ny * (i * nz + z)));
            texels[at..at + 4].copy_from_slice(&[v * rgb[0], v * rgb[1], v * rgb[2], v]);
        }
    }
    VolumeTexture {
        name: "sh",
        format: Ktx2Format::Rgba32Float,
        size: [nx, ny, count * nz],
        texels,
    }
}

/// The `probes` texture: each probe's position and validity.
fn probes_texture(view: &VolumeView<'_>) -> VolumeTexture {
    let texels = (0..view.grid.probe_count())
        .flat_map(|k| {
            let q = view.position(k);
            [q.x, q.y, q.z, if view.valid[k] { 1.0 } else { 0.0 }]
        })
        .collect();
    VolumeTexture {
        name: "probes",
        format: Ktx2Format::Rgba32Float,
        size: view.grid.resolution,
        texels,
    }
}

/// The `moments` texture: each probe's map in a tile with a border across
/// the folded edges.
///
/// # Panics
/// If the view holds no distance maps.
fn moments_texture(view: &VolumeView<'_>) -> VolumeTexture {
    let vis = view.visibility.as_ref().expect("distance maps");
    let (s, [nx, ny, nz]) = (vis.size, view.grid.resolution);
    let tile = s + 2;
    let (w, h) = (nx * tile, ny * tile);
    let per = 2 * s * s;
    let mut texels = vec![0.0f32; 2 * w * h * nz];
    for k in 0..view.grid.probe_count() {
        let [x, y, z] = view.grid.grid_index(k);
        let map = &vis.moments[k * per..][..per];
        for b in 0..tile {
            for a in 0..tile {
                let (i, j) = wrap(a as i32 - 1, b as i32 - 1, s);
                let at = 2 * (x * tile + a + w * (y * tile + b + h * z));
                texels[at..at + 2].copy_from_slice(&map[2 * (j * s + i)..][..2]);
            }
        }
    }
    VolumeTexture {
        name: "moments",
        format: Ktx2Format::Rg32Float,
        size: [w, h, nz],
        texels,
    }
}

/// The numbers the snippet writes as constants: the grid, and the
/// visibility's constants as shlight-baked's `visibility_weights` computes
/// with them, in f32.
fn constants(view: &VolumeView<'_>, lmax: usize) -> VolumeConstants {
    let grid = &view.grid;
    VolumeConstants {
        lmax,
        min: grid.min.to_array(),
        cell: grid.cell().to_array(),
        resolution: grid.resolution,
        visibility: view.visibility.as_ref().map(|v| VisibilityConstants {
            bias: NORMAL_BIAS * grid.cell().min_element(),
            map_size: v.size,
            floor: CHEBYSHEV_FLOOR,
            crush: CRUSH,
        }),
    }
}

/// The snippet's header comment, uncommented: what it returns, the grid,
/// the textures and the lookup.
fn header(view: &VolumeView<'_>, lmax: usize, stem: &str, file: &ShvolFile) -> String {
    let (frame, generator) = (&file.frame, &file.generator);
    let grid = &view.grid;
    let [nx, ny, nz] = grid.resolution;
    let count = sh_count(lmax);
    let mut header = format!(
        "shlight irradiance volume ({generator}): E(p, n) = sum_lm A_l L_lm(p) Y_lm(n), the irradiance\n\
         `shlight sample --lookup {lookup}` gives at the point p facing the unit normal n (a\n\
         Lambertian surface of albedo rho leaves rho / pi E). Real orthonormal SH with the\n\
         Condon-Shortley phase, index l(l+1)+m, lmax {lmax}, the scene's {frame} frame, linear Rec.709.\n\
         Grid: {nx}x{ny}x{nz} probes at the cell centres of the box ({x0}, {y0}, {z0})..({x1}, {y1}, {z1}).\n\
         Textures (KTX2, integer loads only, docs/shvol.md \"Engines' shaders\"):\n\
         - {stem}.sh.ktx2: RGBA32F {nx}x{ny}x{d}: texel (x, y, i*{nz} + z) = (v L_i, v) of probe (x, y, z).\n\
         - {stem}.probes.ktx2: RGBA32F {nx}x{ny}x{nz}: (position, v) of probe (x, y, z).\n",
        lookup = if view.visibility.is_some() {
            "shlight"
        } else {
            "trilinear"
        },
        d = count * nz,
        x0 = grid.min.x,
        y0 = grid.min.y,
        z0 = grid.min.z,
        x1 = grid.max.x,
        y1 = grid.max.y,
        z1 = grid.max.z,
    );
    if let Some(v) = &view.visibility {
        let (s, t) = (v.size, v.size + 2);
        header.push_str(&format!(
            "- {stem}.moments.ktx2: RG32F {}x{}x{nz}: probe (x, y, z)'s {s}x{s} map of (mean, mean_sq)\n  \
             distance in the tile at ({t} x, {t} y) of slice z, one border texel across the folded edges.\n\
             Each probe's trilinear weight is multiplied by its Chebyshev visibility of p + bias n\n\
             (DDGI), floored and crushed, then the weights are renormalised.\n",
            nx * t,
            ny * t,
        ));
    } else {
        header.push_str(
            "The valid probes' trilinear weights, renormalised (the volume holds no distance maps).\n",
        );
    }
    header
}

/// What [`write_volume_shader`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct WrittenVolumeShader {
    /// The snippet, then each texture.
    pub paths: Vec<std::path::PathBuf>,
    /// Remarks for the user, one sentence each.
    pub notes: Vec<String>,
}

/// Writes [`volume_shader`] of `file`: the snippet to `path` and each
/// texture beside it as `{stem}.{name}.ktx2` (`stem` the snippet's file
/// stem), each file atomically, the textures first.
///
/// # Errors
/// As [`volume_shader`]; [`FormatError::Write`] naming a file that cannot
/// be written.
pub fn write_volume_shader(
    file: &ShvolFile,
    language: ShaderLanguage,
    path: &std::path::Path,
) -> Result<WrittenVolumeShader> {
    let stem = path
        .file_stem()
        .map_or_else(|| "volume".into(), |s| s.to_string_lossy().into_owned());
    let shader = volume_shader(file, language, &stem)?;
    let dir = path.parent().unwrap_or_else(|| std::path::Path::new(""));
    let mut paths = Vec::new();
    for texture in &shader.textures {
        let at = dir.join(format!("{stem}.{}.ktx2", texture.name));
        let bytes = texture.ktx2(&file.generator);
        shlight_io::write_atomically(&at, |w| w.write_all(&bytes))?;
        paths.push(at);
    }
    shlight_io::write_atomically(path, |w| w.write_all(shader.text.as_bytes()))?;
    paths.insert(0, path.to_path_buf());
    Ok(WrittenVolumeShader {
        paths,
        notes: shader.notes,
    })
}

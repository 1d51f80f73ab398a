//! The `.shvol` file: an irradiance volume's SH probes on a grid, and how
//! they were made (docs/shvol.md).
//!
//! ```text
//! {"format":"shlight-volume","format_version":1,"lmax":2,...}\n   one line of JSON
//! f32 f32 f32 ...                                                 little-endian data
//! ```
//!
//! The header is one line of JSON (no newline inside) ending in `\n`. The
//! data that follows is little-endian `f32` in sections, each probe-major
//! with the probes in grid order (x fastest, then y, then z):
//!
//! 1. `radiance`: per probe `(lmax+1)^2` rows of `[r, g, b]`, the incident
//!    radiance SH for the bake's environment (always present);
//! 2. `emitted` (relightable files): per probe `(lmax+1)^2` rows of
//!    `[r, g, b]`, the incident radiance that comes from emitters;
//! 3. `transfer` (relightable files): per probe, per channel r, g, b, a
//!    row-major `(lmax+1)^2 x (lmax+1)^2` matrix `M` with
//!    `L_probe = M L_env + L_emitted` (per channel, SH index order);
//! 4. `offsets` (version 2): per probe `[dx, dy, dz]`, where the bake moved
//!    it from its cell's centre out of geometry;
//! 5. `visibility` (version 2): per probe `size` rows of `size` texels
//!    (column fastest) of `[mean, mean_sq]`, the octahedral map of its
//!    distances to the nearest surface (shlight_baked::visibility).
//!
//! A file with neither of the last two is written as version 1, as shlight
//! wrote volumes before them.
//!
//! A volume baked with punctual lights says so in its header (`lights`:
//! the units their intensities were read in and how many of each kind,
//! [`VolumeLights`]); their light is in the sections above (the static
//! light: `radiance` and `emitted`), so the layout is the same.
//!
//! The JSON form ([`ShvolFile::to_json`], `shlight volume --format json`)
//! holds the same values with per-probe arrays.

use std::path::Path;

use serde_json::{Value, json};
use shlight_baked::visibility::{
    BACKFACE_DISTANCE, DISTANCE_SHARPNESS, MAX_VISIBILITY_SIZE, NORMAL_BIAS,
};
use shlight_baked::{MAX_LMAX, MAX_PROBES, ProbeGrid, ProbeVisibility, Visibility, VolumeView};
use shlight_core::sh::sh_count;

use crate::{FormatError, Result, header_line};

/// The `format` key's value (both the binary and the JSON form).
pub const FORMAT: &str = "shlight-volume";
/// The newest layout version this build writes and reads: 2 adds the
/// probes' `offsets` and `visibility` sections (a file without them is
/// written as version 1).
pub const FORMAT_VERSION: u64 = 2;
/// Longest header a reader accepts, in bytes.
pub const MAX_HEADER: usize = 16 << 20;

/// The punctual lights a volume was baked with (provenance: their light
/// is in the probes' static light, `L_emitted`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VolumeLights {
    /// How their intensities became radiometric units: `"blender"` (glTF's
    /// candela and lux divided by 683) or `"as-written"`.
    pub units: String,
    /// Point lights.
    pub point: u64,
    /// Spot lights.
    pub spot: u64,
    /// Directional lights.
    pub directional: u64,
}

/// A `.shvol` file's content.
#[derive(Clone, Debug, PartialEq)]
pub struct ShvolFile {
    /// Highest SH degree of every probe.
    pub lmax: usize,
    /// Probes along x, y and z.
    pub resolution: [usize; 3],
    /// The grid's box, `(min, max)`, in the scene's units; probes sit at the
    /// centres of its `resolution` cells.
    pub bounds: ([f32; 3], [f32; 3]),
    /// The frame of the scene and of every SH (`"y-up"` or `"z-up"`,
    /// docs/conventions.md).
    pub frame: String,
    /// Per probe: whether interpolation may use it (false inside geometry).
    pub valid: Vec<bool>,
    /// Per probe `(lmax+1)^2 x 3` radiance coefficients for the bake's
    /// environment.
    pub radiance: Vec<f32>,
    /// Per probe `(lmax+1)^2 x 3` coefficients of the emitters' light
    /// (relightable files only).
    pub emitted: Option<Vec<f32>>,
    /// Per probe `3 x (lmax+1)^2 x (lmax+1)^2` transfer matrices (relightable
    /// files only).
    pub transfer: Option<Vec<f32>>,
    /// Per probe `[dx, dy, dz]` from its cell's centre, where the bake
    /// moved probes out of geometry (version 2).
    pub offsets: Option<Vec<f32>>,
    /// The probes' distance maps, for the visibility-weighted lookup
    /// (version 2).
    pub visibility: Option<ProbeVisibility>,
    /// Rays cast per probe (the file's `samples`).
    pub rays_per_probe: u64,
    /// Interreflection bounces of the surfaces' light.
    pub bounces: u32,
    /// Seed of the ray directions.
    pub seed: u64,
    /// The scene file's name (informational).
    pub scene: String,
    /// FNV-1a 64 content hash of the scene's mesh (`Mesh::content_hash`).
    pub scene_hash: u64,
    /// What lit the bake: the environment's file name (informational).
    pub environment: String,
    /// The program that wrote the file, e.g. `shlight 0.1.0`.
    pub generator: String,
    /// The punctual lights of the bake (`None`: none; the header then has
    /// no `lights` key).
    pub lights: Option<VolumeLights>,
}

impl ShvolFile {
    /// Number of probes, `nx * ny * nz`.
    #[must_use]
    pub fn probe_count(&self) -> usize {
        self.resolution.iter().product()
    }

    /// Coefficients per probe and channel, `(lmax+1)^2`.
    #[must_use]
    pub fn coeffs_per_channel(&self) -> usize {
        sh_count(self.lmax)
    }

    /// Whether the file holds transfer matrices (it can be relit).
    #[must_use]
    pub fn relightable(&self) -> bool {
        self.transfer.is_some()
    }

    /// The probes' grid (its box and resolution, as stored).
    #[must_use]
    pub fn grid(&self) -> ProbeGrid {
        ProbeGrid {
            resolution: self.resolution,
            min: self.bounds.0.into(),
            max: self.bounds.1.into(),
        }
    }

    /// The probes borrowed, as the renderer and every reader of a volume
    /// take them (not checked: [`VolumeView::check`]).
    #[must_use]
    pub fn view(&self) -> VolumeView<'_> {
        VolumeView {
            grid: self.grid(),
            lmax: self.lmax,
            valid: &self.valid,
            radiance: &self.radiance,
            offsets: self.offsets.as_deref(),
            visibility: self.visibility.as_ref().map(ProbeVisibility::view),
        }
    }

    /// The layout version of this file: 2 with offsets or visibility, 1
    /// without.
    #[must_use]
    pub fn version(&self) -> u64 {
        if self.offsets.is_some() || self.visibility.is_some() {
            2
        } else {
            1
        }
    }

    /// The probes the bake moved (a non-zero offset), in probe order.
    #[must_use]
    pub fn relocated(&self) -> Vec<usize> {
        self.offsets
            .as_deref()
            .map_or_else(Vec::new, shlight_baked::moved_probes)
    }

    /// Where each probe is: its cell's centre plus its offset, in probe
    /// order.
    #[must_use]
    pub fn positions(&self) -> Vec<[f32; 3]> {
        let view = self.view();
        (0..self.probe_count())
            .map(|k| view.position(k).to_array())
            .collect()
    }

    /// The header line's JSON object.
    #[must_use]
    pub fn header(&self) -> Value {
        let mut holds = vec!["radiance"];
        if self.relightable() {
            holds.extend(["emitted", "transfer"]);
        }
        if self.offsets.is_some() {
            holds.push("offsets");
        }
        if self.visibility.is_some() {
            holds.push("visibility");
        }
        let invalid: Vec<usize> = (0..self.valid.len()).filter(|&i| !self.valid[i]).collect();
        let mut header = json!({
            "format": FORMAT,
            "format_version": self.version(),
            "lmax": self.lmax,
            "resolution": self.resolution,
            "bounds": {"min": shortest(self.bounds.0), "max": shortest(self.bounds.1)},
            "probe_order": "x fastest, then y, then z; probes at cell centres",
            "frame": self.frame,
            "basis": "real orthonormal SH, index l(l+1)+m, Condon-Shortley phase included",
            "quantity": "radiance",
            "colour_space": "linear Rec.709",
            "holds": holds,
            "invalid": invalid,
            "samples": self.rays_per_probe,
            "bounces": self.bounces,
            "seed": self.seed,
            "scene": self.scene,
            "scene_hash": header_line::hash_text(self.scene_hash),
            "environment": self.environment,
            "generator": self.generator,
            "data": "f32 little-endian sections in `holds` order, probe-major: radiance and emitted (lmax+1)^2 rows of [r, g, b]; transfer 3 row-major (lmax+1)^2 x (lmax+1)^2 matrices; offsets [dx, dy, dz]; visibility size rows of size texels of [mean, mean_sq]",
        });
        let object = header.as_object_mut().expect("the header is an object");
        if self.offsets.is_some() {
            object.insert("relocated".into(), json!(self.relocated()));
        }
        if let Some(l) = &self.lights {
            object.insert(
                "lights".into(),
                json!({
                    "units": l.units,
                    "point": l.point,
                    "spot": l.spot,
                    "directional": l.directional,
                }),
            );
        }
        if let Some(v) = &self.visibility {
            object.insert(
                "visibility".into(),
                json!({
                    "size": v.size,
                    "max_distance": f64::from(v.max_distance),
                    "sharpness": DISTANCE_SHARPNESS,
                    "backface_distance": f64::from(BACKFACE_DISTANCE),
                    "normal_bias": f64::from(NORMAL_BIAS),
                    "map": "octahedral, +z at the centre, -z at the corners; texel (i, j) at column i, row j",
                }),
            );
        }
        header
    }

    /// The whole file as bytes.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let sections = [
            Some(&self.radiance),
            self.emitted.as_ref(),
            self.transfer.as_ref(),
            self.offsets.as_ref(),
            self.visibility.as_ref().map(|v| &v.moments),
        ];
        header_line::to_bytes(&self.header(), sections.into_iter().flatten().flatten())
    }

    /// The JSON form (`shlight volume --format json`): the header's keys
    /// (less `data` and `invalid`), plus `positions` (probe centres, x
    /// fastest), `valid` (booleans), `coefficients` (per probe
    /// `(lmax+1)^2` rows of `[r, g, b]`, the radiance for the bake's
    /// environment) and, for relightable volumes, `emitted` (the same shape)
    /// and `transfer` (per probe three matrices of `(lmax+1)^2` rows); in
    /// version 2, `positions` are where the probes are (cell centres plus
    /// `offsets`, per probe `[dx, dy, dz]`), and `distance_moments` holds
    /// per probe `size` rows of `size` `[mean, mean_sq]` (the header's
    /// `visibility` says how they were made).
    #[must_use]
    pub fn to_json(&self) -> Value {
        let mut v = self.header();
        let object = v.as_object_mut().expect("the header is an object");
        object.remove("data");
        object.remove("invalid");
        let nc = self.coeffs_per_channel();
        let rows = |data: &[f32]| -> Value {
            data.chunks_exact(3 * nc)
                .map(|probe| {
                    probe
                        .chunks_exact(3)
                        .map(|rgb| json!([f64::from(rgb[0]), f64::from(rgb[1]), f64::from(rgb[2])]))
                        .collect::<Vec<_>>()
                })
                .collect::<Vec<_>>()
                .into()
        };
        object.insert(
            "positions".into(),
            self.positions()
                .into_iter()
                .map(shortest)
                .collect::<Vec<_>>()
                .into(),
        );
        if let Some(o) = &self.offsets {
            let o: Vec<[f64; 3]> = o
                .chunks_exact(3)
                .map(|d| [d[0], d[1], d[2]].map(f64::from))
                .collect();
            object.insert("offsets".into(), json!(o));
        }
        if let Some(v) = &self.visibility {
            let maps: Vec<Value> = v
                .moments
                .chunks_exact(Visibility::floats_per_probe(v.size))
                .map(|map| {
                    map.chunks_exact(2 * v.size)
                        .map(|row| {
                            row.chunks_exact(2)
                                .map(|t| json!([f64::from(t[0]), f64::from(t[1])]))
                                .collect::<Vec<_>>()
                        })
                        .collect::<Vec<_>>()
                        .into()
                })
                .collect();
            object.insert("distance_moments".into(), maps.into());
        }
        object.insert("valid".into(), json!(self.valid));
        object.insert("coefficients".into(), rows(&self.radiance));
        if let Some(e) = &self.emitted {
            object.insert("emitted".into(), rows(e));
        }
        if let Some(t) = &self.transfer {
            let matrices: Vec<Value> = t
                .chunks_exact(3 * nc * nc)
                .map(|probe| {
                    probe
                        .chunks_exact(nc * nc)
                        .map(|m| {
                            m.chunks_exact(nc)
                                .map(|row| row.iter().map(|&x| f64::from(x)).collect::<Vec<_>>())
                                .collect::<Vec<_>>()
                        })
                        .collect::<Vec<_>>()
                        .into()
                })
                .collect();
            object.insert("transfer".into(), matrices.into());
        }
        v
    }

    /// Writes the file atomically (a temporary file renamed into place).
    ///
    /// # Errors
    /// [`FormatError::Write`] naming the file.
    pub fn write(&self, path: &Path) -> Result<()> {
        let bytes = self.to_bytes();
        shlight_io::write_atomically(path, |w| w.write_all(&bytes))?;
        Ok(())
    }

    /// Writes the JSON form atomically.
    ///
    /// # Errors
    /// [`FormatError::Write`] naming the file.
    pub fn write_json(&self, path: &Path) -> Result<()> {
        let mut text = serde_json::to_string(&self.to_json()).expect("JSON values serialise");
        text.push('\n');
        shlight_io::write_atomically(path, |w| w.write_all(text.as_bytes()))?;
        Ok(())
    }

    /// Reads a `.shvol` file.
    ///
    /// # Errors
    /// [`FormatError::Read`] when it cannot be read; [`FormatError::Invalid`]
    /// naming the file and the problem otherwise.
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = header_line::read_file(path)?;
        Self::from_bytes(&bytes, path)
    }

    /// Parses a file held in memory; `path` names it in errors.
    ///
    /// # Errors
    /// As [`ShvolFile::read`]: a missing header line, a header that is not
    /// JSON or lacks a key, another `format`, a newer `format_version`, an
    /// lmax beyond [`MAX_LMAX`], an empty grid or one of more than
    /// [`MAX_PROBES`] probes, bounds that are not finite with `min < max`,
    /// an invalid probe index out of range, unknown sections, or data
    /// shorter ("truncated") or longer ("wrong length") than the header
    /// says, or not finite.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self> {
        let name = path.display().to_string();
        let bad = |message: String| FormatError::invalid(&name, message);
        let (header, data) = header_line::split(bytes, &name, FORMAT, ".shvol", MAX_HEADER)?;
        let uint = |key: &str| header_line::uint(&header, key, &name);
        let text = |key: &str| header_line::text(&header, key, &name);
        let version = uint("format_version")?;
        if version == 0 || version > FORMAT_VERSION {
            return Err(bad(format!(
                "format_version {version} is not supported (this build reads 1..={FORMAT_VERSION})"
            )));
        }
        let lmax = uint("lmax")? as usize;
        if lmax > MAX_LMAX {
            return Err(bad(format!(
                "bad header (lmax {lmax} is beyond {MAX_LMAX})"
            )));
        }
        let resolution = header
            .get("resolution")
            .and_then(Value::as_array)
            .filter(|a| a.len() == 3)
            .and_then(|a| {
                let n: Vec<usize> = a
                    .iter()
                    .filter_map(Value::as_u64)
                    .map(|x| x as usize)
                    .collect();
                <[usize; 3]>::try_from(n).ok()
            })
            .ok_or_else(|| bad("bad header (\"resolution\" is not [nx, ny, nz])".into()))?;
        let probes = resolution
            .iter()
            .try_fold(1usize, |acc, &n| acc.checked_mul(n))
            .filter(|&p| p > 0 && p <= MAX_PROBES)
            .ok_or_else(|| {
                bad(format!(
                    "bad header (resolution {resolution:?}: the grid must have 1 to {MAX_PROBES} probes)"
                ))
            })?;
        let corner = |key: &str| -> Result<[f32; 3]> {
            header
                .get("bounds")
                .and_then(|b| b.get(key))
                .and_then(Value::as_array)
                .filter(|a| a.len() == 3)
                .and_then(|a| {
                    let v: Vec<f32> = a
                        .iter()
                        .filter_map(Value::as_f64)
                        .map(|x| x as f32)
                        .collect();
                    <[f32; 3]>::try_from(v).ok()
                })
                .filter(|v| v.iter().all(|x| x.is_finite()))
                .ok_or_else(|| {
                    bad(format!(
                        "bad header (\"bounds\".\"{key}\" is not [x, y, z])"
                    ))
                })
        };
        let bounds = (corner("min")?, corner("max")?);
        if (0..3).any(|a| bounds.0[a] >= bounds.1[a]) {
            return Err(bad(format!(
                "bad header (bounds min {:?} is not below max {:?} on every axis)",
                bounds.0, bounds.1
            )));
        }
        let frame = text("frame")?;
        if frame != "y-up" && frame != "z-up" {
            return Err(bad(format!(
                "bad header (frame \"{frame}\", not \"y-up\" or \"z-up\")"
            )));
        }
        let holds: Vec<String> = header
            .get("holds")
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(Value::as_str)
                    .map(str::to_string)
                    .collect()
            })
            .unwrap_or_default();
        // radiance, then emitted and transfer together or neither, then
        // (version 2) offsets and visibility, each or neither.
        let named: Vec<&str> = holds.iter().map(String::as_str).collect();
        let (relightable, rest) = match named[..] {
            ["radiance", "emitted", "transfer", ref rest @ ..] => (true, rest),
            ["radiance", ref rest @ ..] => (false, rest),
            _ => (false, &["?"][..]),
        };
        let (has_offsets, has_visibility) = match rest {
            [] => (false, false),
            ["offsets"] => (true, false),
            ["visibility"] => (false, true),
            ["offsets", "visibility"] => (true, true),
            _ => {
                return Err(bad(format!(
                    "bad header (\"holds\" is {holds:?}, not \"radiance\", then \"emitted\" and \"transfer\" or neither, then \"offsets\" and \"visibility\" or either or neither)"
                )));
            }
        };
        if version < 2 && (has_offsets || has_visibility) {
            return Err(bad(format!(
                "bad header (format_version {version} holds no offsets or visibility)"
            )));
        }
        let visibility_shape = if has_visibility {
            let v = header.get("visibility");
            let size = v
                .and_then(|v| v.get("size"))
                .and_then(Value::as_u64)
                .filter(|&s| s >= 1 && s <= MAX_VISIBILITY_SIZE as u64)
                .ok_or_else(|| {
                    bad(format!(
                        "bad header (\"visibility\".\"size\" is not a whole number from 1 to {MAX_VISIBILITY_SIZE})"
                    ))
                })? as usize;
            let max_distance = v
                .and_then(|v| v.get("max_distance"))
                .and_then(Value::as_f64)
                .map(|x| x as f32)
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or_else(|| {
                    bad(
                        "bad header (\"visibility\".\"max_distance\" is not a positive number)"
                            .into(),
                    )
                })?;
            Some((size, max_distance))
        } else {
            None
        };
        let mut valid = vec![true; probes];
        for i in header
            .get("invalid")
            .and_then(Value::as_array)
            .ok_or_else(|| bad("bad header (\"invalid\" is missing or not a list)".into()))?
        {
            let i = i
                .as_u64()
                .map(|i| i as usize)
                .filter(|&i| i < probes)
                .ok_or_else(|| {
                    bad(format!(
                        "bad header (invalid probe {i} is not below {probes})"
                    ))
                })?;
            valid[i] = false;
        }
        let scene_hash = header_line::hash(&header, "scene_hash", &name)?;
        let lights = match header.get("lights") {
            None => None,
            Some(l) => {
                let count = |kind: &str| l.get(kind).and_then(Value::as_u64);
                let units = l.get("units").and_then(Value::as_str);
                match (units, count("point"), count("spot"), count("directional")) {
                    (Some(units), Some(point), Some(spot), Some(directional)) => {
                        Some(VolumeLights {
                            units: units.to_string(),
                            point,
                            spot,
                            directional,
                        })
                    }
                    _ => {
                        return Err(bad(
                            "bad header (\"lights\" is not {\"units\": text, \"point\", \"spot\", \"directional\": counts})"
                                .into(),
                        ));
                    }
                }
            }
        };

        let nc = sh_count(lmax);
        let per_probe = 3 * nc
            + if relightable { 3 * nc + 3 * nc * nc } else { 0 }
            + if has_offsets { 3 } else { 0 }
            + visibility_shape.map_or(0, |(size, _)| Visibility::floats_per_probe(size));
        let count = probes
            .checked_mul(per_probe)
            .filter(|c| c.checked_mul(4).is_some())
            .ok_or_else(|| bad("bad header (the sizes overflow)".into()))?;
        if data.len() < 4 * count {
            return Err(bad(format!(
                "truncated: {probes} probes need {} bytes of data, the file has {}",
                4 * count,
                data.len()
            )));
        }
        if data.len() > 4 * count {
            return Err(bad(format!(
                "wrong length: {} bytes of data where the header says {}",
                data.len(),
                4 * count
            )));
        }
        let values = header_line::f32s(data);
        if let Some(k) = values.iter().position(|x| !x.is_finite()) {
            return Err(bad(format!("value {k} of the data is not finite")));
        }
        let (radiance, rest) = values.split_at(probes * 3 * nc);
        let (emitted, transfer, rest) = if relightable {
            let (e, rest) = rest.split_at(probes * 3 * nc);
            let (t, rest) = rest.split_at(probes * 3 * nc * nc);
            (Some(e.to_vec()), Some(t.to_vec()), rest)
        } else {
            (None, None, rest)
        };
        let (offsets, rest) = if has_offsets {
            let (o, rest) = rest.split_at(probes * 3);
            (Some(o.to_vec()), rest)
        } else {
            (None, rest)
        };
        let visibility = visibility_shape.map(|(size, max_distance)| ProbeVisibility {
            size,
            max_distance,
            moments: rest.to_vec(),
        });
        Ok(Self {
            lmax,
            resolution,
            bounds,
            frame,
            valid,
            radiance: radiance.to_vec(),
            emitted,
            transfer,
            offsets,
            visibility,
            rays_per_probe: uint("samples")?,
            bounces: uint("bounces")? as u32,
            seed: uint("seed")?,
            scene: text("scene").unwrap_or_default(),
            scene_hash,
            environment: text("environment").unwrap_or_default(),
            generator: text("generator").unwrap_or_default(),
            lights,
        })
    }
}

/// Each f32 as its shortest decimal (0.1, not 0.10000000149011612).
fn shortest(v: [f32; 3]) -> [f64; 3] {
    v.map(|x| x.to_string().parse::<f64>().unwrap_or(f64::NAN))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(relightable: bool) -> ShvolFile {
        // A 2 x 1 x 3 grid at lmax 1.
        let (probes, nc) = (6, 4);
        ShvolFile {
            lmax: 1,
            resolution: [2, 1, 3],
            bounds: ([-1.0, 0.0, -3.0], [1.0, 0.5, 3.0]),
            frame: "y-up".into(),
            valid: vec![true, false, true, true, true, false],
            radiance: (0..probes * 3 * nc).map(|i| i as f32 * 0.25).collect(),
            emitted: relightable.then(|| (0..probes * 3 * nc).map(|i| i as f32).collect()),
            transfer: relightable.then(|| {
                (0..probes * 3 * nc * nc)
                    .map(|i| -(i as f32) / 8.0)
                    .collect()
            }),
            offsets: None,
            visibility: None,
            rays_per_probe: 1035,
            bounces: 2,
            seed: 7,
            scene: "room.obj".into(),
            scene_hash: 0xfeed_beef_0123_4567,
            environment: "sky.exr".into(),
            generator: "shlight test".into(),
            lights: None,
        }
    }

    #[test]
    fn round_trips_with_the_documented_layout() {
        for relightable in [false, true] {
            let f = sample(relightable);
            let bytes = f.to_bytes();
            let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
            let per_probe = if relightable { 12 + 12 + 48 } else { 12 };
            assert_eq!(bytes.len(), nl + 1 + 6 * per_probe * 4);
            // The second value of the radiance section: probe 0, row 0, green.
            let at = nl + 1 + 4;
            assert_eq!(
                f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()),
                0.25
            );
            let back = ShvolFile::from_bytes(&bytes, Path::new("v.shvol")).unwrap();
            assert_eq!(back, f);
        }
    }

    /// [`sample`] with version 2's sections: probe 2 moved, maps of 2x2.
    fn moved(relightable: bool) -> ShvolFile {
        let mut offsets = vec![0.0f32; 18];
        offsets[6..9].copy_from_slice(&[0.25, -0.125, 0.5]);
        ShvolFile {
            offsets: Some(offsets),
            visibility: Some(ProbeVisibility {
                size: 2,
                max_distance: 1.5,
                moments: (0..6 * 8).map(|i| i as f32 / 64.0).collect(),
            }),
            ..sample(relightable)
        }
    }

    #[test]
    fn version_2_round_trips_and_version_1_stays_as_it_was() {
        for relightable in [false, true] {
            let f = moved(relightable);
            let bytes = f.to_bytes();
            let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
            let header: Value = serde_json::from_slice(&bytes[..nl]).unwrap();
            assert_eq!(header["format_version"], 2);
            assert_eq!(header["relocated"], json!([2]));
            assert_eq!(header["visibility"]["size"], 2);
            let per_probe = if relightable { 12 + 12 + 48 } else { 12 } + 3 + 8;
            assert_eq!(bytes.len(), nl + 1 + 6 * per_probe * 4);
            // The offsets follow the earlier sections: probe 2's dx.
            let at = nl + 1 + 4 * (6 * (per_probe - 11) + 6);
            assert_eq!(
                f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()),
                0.25
            );
            let back = ShvolFile::from_bytes(&bytes, Path::new("v.shvol")).unwrap();
            assert_eq!(back, f);
            assert!(back.view().check().is_ok());
            // A file without the new sections is version 1 and names
            // neither.
            let old = sample(relightable).to_bytes();
            let end = old.iter().position(|&b| b == b'\n').unwrap();
            let h: Value = serde_json::from_slice(&old[..end]).unwrap();
            assert_eq!(h["format_version"], 1);
            assert!(h.get("visibility").is_none() && h.get("relocated").is_none());
        }
        let f = moved(false);
        assert_eq!(f.positions()[2], [-0.25, 0.125, 0.5]);
        let j = f.to_json();
        assert_eq!(j["positions"][2], json!([-0.25, 0.125, 0.5]));
        assert_eq!(j["offsets"][2], json!([0.25, -0.125, 0.5]));
        // Probe 1's map, row 1, column 0: values 8 + 4 and 8 + 5 of 64ths.
        assert_eq!(
            j["distance_moments"][1][1][0],
            json!([12.0 / 64.0, 13.0 / 64.0])
        );
        // A version 1 header that claims the new sections is refused.
        let bytes = f.to_bytes();
        let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
        let header = std::str::from_utf8(&bytes[..nl]).unwrap();
        let mut b = header
            .replace("\"format_version\":2", "\"format_version\":1")
            .into_bytes();
        b.extend_from_slice(&bytes[nl..]);
        let e = ShvolFile::from_bytes(&b, Path::new("old.shvol")).unwrap_err();
        assert!(e.to_string().contains("holds no offsets"), "{e}");
        let mut b = header.replace("\"size\":2", "\"size\":0").into_bytes();
        b.extend_from_slice(&bytes[nl..]);
        let e = ShvolFile::from_bytes(&b, Path::new("v.shvol")).unwrap_err();
        assert!(e.to_string().contains("\"visibility\".\"size\""), "{e}");
        let mut b = header
            .replace("\"offsets\",\"visibility\"", "\"visibility\",\"offsets\"")
            .into_bytes();
        b.extend_from_slice(&bytes[nl..]);
        let e = ShvolFile::from_bytes(&b, Path::new("v.shvol")).unwrap_err();
        assert!(e.to_string().contains("\"holds\""), "{e}");
    }

    #[test]
    fn the_lights_of_a_bake_are_recorded_and_read_back() {
        let lit = ShvolFile {
            lights: Some(VolumeLights {
                units: "as-written".into(),
                point: 2,
                spot: 0,
                directional: 1,
            }),
            ..moved(true)
        };
        let bytes = lit.to_bytes();
        let nl = bytes.iter().position(|&b| b == b'\n').unwrap();
        let header: Value = serde_json::from_slice(&bytes[..nl]).unwrap();
        assert_eq!(
            header["lights"],
            json!({"units": "as-written", "point": 2, "spot": 0, "directional": 1})
        );
        // The data are as without lights.
        let plain = moved(true).to_bytes();
        let plain_nl = plain.iter().position(|&b| b == b'\n').unwrap();
        assert_eq!(bytes[nl..], plain[plain_nl..]);
        assert_eq!(
            ShvolFile::from_bytes(&bytes, Path::new("v.shvol")).unwrap(),
            lit
        );
        assert_eq!(lit.to_json()["lights"]["directional"], 1);
        // A file without lights names none.
        assert!(moved(true).header().get("lights").is_none());
        let text = std::str::from_utf8(&bytes[..nl]).unwrap();
        let mut b = text.replace("\"spot\":0", "\"spot\":-1").into_bytes();
        b.extend_from_slice(&bytes[nl..]);
        let e = ShvolFile::from_bytes(&b, Path::new("v.shvol")).unwrap_err();
        assert!(e.to_string().contains("\"lights\""), "{e}");
    }

    #[test]
    fn positions_are_cell_centres_x_fastest() {
        let f = sample(false);
        let p: Vec<[f32; 3]> = f.grid().centres().iter().map(|c| c.to_array()).collect();
        assert_eq!(p.len(), 6);
        assert_eq!(p[0], [-0.5, 0.25, -2.0]);
        assert_eq!(p[1], [0.5, 0.25, -2.0]);
        assert_eq!(p[2], [-0.5, 0.25, 0.0]);
        assert_eq!(p[5], [0.5, 0.25, 2.0]);
        let j = f.to_json();
        assert_eq!(j["format"], "shlight-volume");
        assert_eq!(j["resolution"], json!([2, 1, 3]));
        assert_eq!(j["valid"][1], false);
        // Probe 1 starts at value 3 x 4 = 12 of the radiance section.
        assert_eq!(j["coefficients"][1][0], json!([3.0, 3.25, 3.5]));
        assert_eq!(j["bounds"]["max"], json!([1.0, 0.5, 3.0]));
    }

    #[test]
    fn bad_files_are_refused_naming_the_problem() {
        let good = sample(true).to_bytes();
        let nl = good.iter().position(|&b| b == b'\n').unwrap();
        let header = std::str::from_utf8(&good[..nl]).unwrap().to_string();
        let with = |h: String, data: &[u8]| {
            let mut b = h.into_bytes();
            b.push(b'\n');
            b.extend_from_slice(data);
            ShvolFile::from_bytes(&b, Path::new("bad.shvol"))
                .unwrap_err()
                .to_string()
        };
        let data = &good[nl + 1..];
        let cases = [
            (with(header.clone(), &data[4..]), "truncated"),
            (
                with(header.clone(), &[data, &[0; 4]].concat()),
                "wrong length",
            ),
            (
                with(header.replace("shlight-volume", "shlight-prt"), data),
                "\"format\"",
            ),
            (
                with(
                    header.replace("\"format_version\":1", "\"format_version\":9"),
                    data,
                ),
                "format_version 9",
            ),
            (
                with(header.replace("\"lmax\":1", "\"lmax\":9"), data),
                "lmax 9",
            ),
            (
                with(header.replace("[2,1,3]", "[2,0,3]"), data),
                "resolution",
            ),
            (
                with(header.replace("[2,1,3]", "[70000,70000,70000]"), data),
                "resolution",
            ),
            (
                with(
                    header.replace("\"invalid\":[1,5]", "\"invalid\":[1,6]"),
                    data,
                ),
                "invalid probe 6",
            ),
            (with(header.replace("\"y-up\"", "\"x-up\""), data), "frame"),
            (
                with(header.replace("\"min\":[-1.0", "\"min\":[1.0"), data),
                "not below max",
            ),
            (with(header.replace("\"emitted\",", ""), data), "holds"),
            (with("{".into(), data), "not JSON"),
        ];
        for (message, want) in cases {
            assert!(message.starts_with("bad.shvol: "), "{message}");
            assert!(message.contains(want), "{message} lacks {want}");
        }
        let e = ShvolFile::from_bytes(b"no newline", Path::new("x.shvol")).unwrap_err();
        assert!(e.to_string().contains("no header line"), "{e}");
        let mut nan = good.clone();
        nan[nl + 1..nl + 5].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = ShvolFile::from_bytes(&nan, Path::new("n.shvol")).unwrap_err();
        assert!(e.to_string().contains("not finite"), "{e}");
    }
}

//! A probe volume as three.js's `LightProbeGridWebGL`: the atlas texture its
//! shader samples, and the JSON document (`shlight volume --format threejs`,
//! `shlight convert VOLUME.shvol --format threejs`) that
//! `web/shlight-three.js`'s `loadLightProbeGrid` turns into a grid.
//!
//! # What three.js reads (r187)
//! Source: three.js 0.187.0, `examples/jsm/lighting/LightProbeGridWebGL.js`
//! (`_ensureTextures`, `_repackProbes`, `getProbePosition`,
//! `updateBoundingBox`) and
//! `src/renderers/shaders/ShaderChunk/lightprobes_pars_fragment.glsl.js`
//! (`getLightProbeGridIrradiance`).
//!
//! - **The grid**: a `Light` whose `boundingBox` is centred on its
//!   `position` with size `(width, height, depth)`, split into
//!   `resolution = (nx, ny, nz)` cells with one probe at each cell's centre
//!   (shlight's probes sit at the same points; a bake's relocation offsets
//!   are not carried: three.js knows none).
//! - **The probes**: nine L2 radiance coefficients each, in three.js's
//!   basis (`SphericalHarmonics3`: shlight's with the Condon-Shortley phase
//!   removed, i.e. odd `m` negated), linear Rec.709 RGB, three.js world
//!   (right-handed, +Y up: shlight's y-up frame).
//! - **The atlas**: one RGBA 3D texture of `nx x ny x 7 (nz + 2)` texels
//!   (x fastest, then y, then the atlas slice). Sub-volume `t` (0..7)
//!   occupies slices `t (nz + 2) .. (t + 1)(nz + 2)`: one padding slice (a
//!   copy of data slice 0), the `nz` data slices (slice
//!   `t (nz + 2) + 1 + z` holds grid layer `z`), one padding slice (a copy
//!   of data slice `nz - 1`). The 27 numbers of a probe, `c0.rgb .. c8.rgb`,
//!   are packed four to a texel in order: `t0 = (c0.r, c0.g, c0.b, c1.r)`,
//!   `t1 = (c1.g, c1.b, c2.r, c2.g)`, `t2 = (c2.b, c3.r, c3.g, c3.b)`,
//!   `t3 = (c4.r, c4.g, c4.b, c5.r)`, `t4 = (c5.g, c5.b, c6.r, c6.g)`,
//!   `t5 = (c6.b, c7.r, c7.g, c7.b)`, `t6 = (c8.r, c8.g, c8.b, 0)`.
//! - **The lookup** (`getLightProbeGridIrradiance`): `uvw = clamp((p + n
//!   spacing / 2 - min) / (max - min), 1 / 2n, 1 - 1 / 2n)`, each
//!   sub-volume read with the linear filter at `(uvw.xy, (uvw.z nz + 1 + t
//!   (nz + 2)) / (7 (nz + 2)))`, and the irradiance of the nine
//!   coefficients; shlight-volume's `ThreeJsLookup` computes the same on
//!   the CPU (`shlight sample --lookup threejs`).
//!
//! three.js's own bake renders the atlas as `FloatType`; the export writes
//! half floats by default (`HalfFloatType`, linear filtering everywhere in
//! WebGL 2, half the bytes), or `f32` ([`Precision::F32`]: exactly the
//! numbers `--lookup threejs` reads; linear filtering of float textures
//! needs `OES_texture_float_linear`, which three.js's own bake needs too).
//!
//! # The document
//! One JSON object, the atlas inline as base64 of little-endian texels
//! (one request; a sidecar file would need a second URL):
//!
//! ```text
//! { "metadata": {"type": "shlight.LightProbeGrid", "version": 1, "generator": ...},
//!   "boundingBox": {"min": [x, y, z], "max": [x, y, z]},
//!   "resolution": [nx, ny, nz],
//!   "lmax": 2, "sourceLmax": L,
//!   "atlas": {"width": nx, "height": ny, "depth": 7 (nz + 2),
//!             "format": "RGBAFormat", "type": "HalfFloatType" | "FloatType",
//!             "padding": 1, "byteLength": N, "encoding": "base64", "data": "..."},
//!   "notes": [...],
//!   "shlight": {what each number is, in words; provenance} }
//! ```

use base64::Engine as _;
use glam::Vec3;
use serde_json::json;
use shlight_baked::{VolumeView, dilate};
use shlight_core::sh::{ShCoeffs, sh_count};

use crate::{FormatError, Result, ShvolFile};

/// The highest lmax three.js's grid holds (`SphericalHarmonics3`).
pub const THREEJS_LMAX: usize = 2;
/// The RGBA sub-volumes of the atlas.
pub const SUB_VOLUMES: usize = 7;
/// Padding slices at each end of every sub-volume (three.js's
/// `ATLAS_PADDING`).
pub const ATLAS_PADDING: usize = 1;
/// The `metadata.type` of the document.
pub const DOCUMENT_TYPE: &str = "shlight.LightProbeGrid";
/// The `metadata.version` of the document.
pub const DOCUMENT_VERSION: u64 = 1;

/// How the atlas's numbers are stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Precision {
    /// IEEE half floats, rounded to nearest even (`HalfFloatType`).
    #[default]
    Half,
    /// IEEE single floats (`FloatType`): the probes' `f32` as they are.
    F32,
}

impl std::str::FromStr for Precision {
    type Err = String;

    /// `half` or `f32`.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s.trim() {
            "half" => Ok(Precision::Half),
            "f32" => Ok(Precision::F32),
            _ => Err("unknown precision (expected half or f32)".into()),
        }
    }
}

impl Precision {
    /// The name both front ends take.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Precision::Half => "half",
            Precision::F32 => "f32",
        }
    }

    /// three.js's texture type constant's name.
    #[must_use]
    pub fn threejs_type(self) -> &'static str {
        match self {
            Precision::Half => "HalfFloatType",
            Precision::F32 => "FloatType",
        }
    }
}

/// Every probe of `view` as three.js's grid holds it: dilated
/// ([`shlight_baked::dilate`]; the grid knows no validity), kept to `lmax`
/// (at most [`THREEJS_LMAX`] and the volume's; the rest of the nine
/// coefficients zero), in three.js's basis (no Condon-Shortley phase);
/// nine `[r, g, b]` per probe, probes in grid order.
#[must_use]
pub fn threejs_probes(view: &VolumeView<'_>, lmax: usize) -> Vec<[[f32; 3]; 9]> {
    let lmax = lmax.min(THREEJS_LMAX).min(view.lmax);
    let radiance = dilate(view);
    let nc = sh_count(view.lmax);
    radiance
        .chunks_exact(3 * nc)
        .map(|p| {
            let shlight = ShCoeffs::from_vec(
                p.chunks_exact(3)
                    .take(sh_count(lmax))
                    .map(Vec3::from_slice)
                    .collect(),
            )
            .expect("(lmax+1)^2 rows");
            let mut out = [[0.0f32; 3]; 9];
            for (o, c) in out.iter_mut().zip(shlight.toggled_cs_phase().as_slice()) {
                *o = c.to_array();
            }
            out
        })
        .collect()
}

/// The atlas `LightProbeGridWebGL` samples, in memory, as `f32` (the
/// module's docs give the layout).
#[derive(Clone, Debug, PartialEq)]
pub struct ThreeJsAtlas {
    /// Width, height, depth: `[nx, ny, 7 (nz + 2)]`.
    pub size: [usize; 3],
    /// The texels `[r, g, b, a]`, x fastest, then y, then slice.
    pub texels: Vec<[f32; 4]>,
}

impl ThreeJsAtlas {
    /// The atlas of `probes` (nine `[r, g, b]` each, in grid order) on a
    /// grid of `resolution`.
    ///
    /// # Panics
    /// When `probes` does not hold one entry per grid point.
    #[must_use]
    pub fn from_probes(resolution: [usize; 3], probes: &[[[f32; 3]; 9]]) -> Self {
        let [nx, ny, nz] = resolution;
        assert_eq!(probes.len(), nx * ny * nz, "one probe per grid point");
        let padded = nz + 2 * ATLAS_PADDING;
        let depth = SUB_VOLUMES * padded;
        let mut texels = vec![[0.0f32; 4]; nx * ny * depth];
        for (k, probe) in probes.iter().enumerate() {
            let (x, y, z) = (k % nx, k / nx % ny, k / (nx * ny));
            let flat: Vec<f32> = probe.iter().flatten().copied().collect();
            for t in 0..SUB_VOLUMES {
                let mut texel = [0.0f32; 4];
                for (c, v) in texel.iter_mut().enumerate() {
                    *v = flat.get(4 * t + c).copied().unwrap_or(0.0);
                }
                let base = t * padded;
                let mut slices = vec![base + ATLAS_PADDING + z];
                if z == 0 {
                    slices.push(base);
                }
                if z == nz - 1 {
                    slices.push(base + ATLAS_PADDING + nz);
                }
                for s in slices {
                    texels[x + nx * (y + ny * s)] = texel;
                }
            }
        }
        Self {
            size: [nx, ny, depth],
            texels,
        }
    }

    /// The atlas of `view`'s probes ([`threejs_probes`] to lmax 2).
    #[must_use]
    pub fn from_view(view: &VolumeView<'_>) -> Self {
        Self::from_probes(view.grid.resolution, &threejs_probes(view, THREEJS_LMAX))
    }

    /// The little-endian bytes of the texels at `precision`; an error when
    /// a number is beyond a half float's range (65504).
    pub fn bytes(&self, precision: Precision) -> Result<Vec<u8>> {
        let values = self.texels.iter().flatten();
        match precision {
            Precision::F32 => Ok(values.flat_map(|v| v.to_le_bytes()).collect()),
            Precision::Half => {
                let mut out = Vec::with_capacity(self.texels.len() * 8);
                for &v in values {
                    let h = half::f16::from_f32(v);
                    if !h.is_finite() {
                        return Err(FormatError::Export(format!(
                            "a probe coefficient ({v}) is beyond a half float's range (65504): \
                             use f32 precision"
                        )));
                    }
                    out.extend(h.to_bits().to_le_bytes());
                }
                Ok(out)
            }
        }
    }
}

/// The `--format threejs` document of a volume, and the notes to show.
#[derive(Clone, Debug, PartialEq)]
pub struct ThreeJsGrid {
    /// The JSON document (pretty-printed but for the atlas's data).
    pub text: String,
    /// What the export changed (lmax clipped, probes dilated), for stderr;
    /// the document's `notes` hold them too.
    pub notes: Vec<String>,
}

/// The `--format threejs` document of `file` (the module's docs): its
/// probes dilated, clipped to lmax 2, as three.js's atlas at `precision`.
/// A volume in the z-up frame is refused: three.js's world is y-up and the
/// grid's box is axis-aligned in it.
pub fn threejs_grid(file: &ShvolFile, precision: Precision) -> Result<ThreeJsGrid> {
    if file.frame != "y-up" {
        return Err(FormatError::Export(format!(
            "the volume is in the {} frame; three.js's world is y-up and its grid's box is \
             axis-aligned there: bake the volume in the y-up frame",
            file.frame
        )));
    }
    let view = file.view();
    view.check()
        .map_err(|e| FormatError::Export(format!("the volume is inconsistent: {e}")))?;
    let mut notes = Vec::new();
    if file.lmax > THREEJS_LMAX {
        notes.push(format!(
            "lmax {} clipped to {THREEJS_LMAX}: three.js's LightProbeGrid holds L2 \
             (SphericalHarmonics3)",
            file.lmax
        ));
    } else if file.lmax < THREEJS_LMAX {
        notes.push(format!(
            "lmax {} zero-padded to {THREEJS_LMAX}: three.js's LightProbeGrid reads nine coefficients",
            file.lmax
        ));
    }
    let invalid = file.valid.iter().filter(|&&v| !v).count();
    if invalid > 0 {
        notes.push(format!(
            "{invalid} invalid probes (inside geometry) filled from their valid neighbours \
             (dilation): three.js's grid knows no validity"
        ));
    }
    if file.offsets.is_some() && !file.relocated().is_empty() {
        notes.push(format!(
            "{} probes the bake moved out of geometry are placed at their cells' centres, \
             where three.js puts every probe",
            file.relocated().len()
        ));
    }
    let atlas = ThreeJsAtlas::from_view(&view);
    let bytes = atlas.bytes(precision)?;
    let data = base64::engine::general_purpose::STANDARD.encode(&bytes);
    let [width, height, depth] = atlas.size;
    let doc = json!({
        "metadata": {
            "type": DOCUMENT_TYPE,
            "version": DOCUMENT_VERSION,
            "generator": file.generator.clone(),
            "writer": concat!("shlight ", env!("CARGO_PKG_VERSION")),
        },
        "boundingBox": {"min": file.bounds.0, "max": file.bounds.1},
        "resolution": file.resolution,
        "lmax": THREEJS_LMAX,
        "sourceLmax": file.lmax,
        "atlas": {
            "width": width,
            "height": height,
            "depth": depth,
            "format": "RGBAFormat",
            "type": precision.threejs_type(),
            "padding": ATLAS_PADDING,
            "byteLength": bytes.len(),
            "encoding": "base64",
            "data": "@DATA@",
        },
        "notes": notes,
        "shlight": {
            "target": "three.js r187 LightProbeGridWebGL (examples/jsm/lighting/LightProbeGridWebGL.js); load with loadLightProbeGrid from shlight's web/shlight-three.js",
            "grid": "boundingBox is the grid's box in three.js world units; resolution probes along x, y, z, each at the centre of its cell",
            "atlas": "nx x ny x 7(nz+2) RGBA texels, x fastest, then y, then slice, little-endian; sub-volume t in slices t(nz+2)..(t+1)(nz+2): a padding slice (copy of layer 0), layers 0..nz, a padding slice (copy of layer nz-1); texel t of a probe holds its 27 numbers c0.rgb..c8.rgb from 4t (the last texel's alpha 0)",
            "quantity": "radiance L_lm = integral of L(w) Y_lm(w) dw per probe; three.js shades with the irradiance E(n) of the trilinearly interpolated coefficients, times albedo / pi",
            "basis": "real orthonormal SH without the Condon-Shortley phase, three.js order L00, L1-1, L10, L11, L2-2, L2-1, L20, L21, L22 (SphericalHarmonics3)",
            "frame": "three.js world, right-handed, +Y up",
            "colour_space": "linear Rec.709",
            "dilation": "invalid probes filled from their valid face neighbours (shlight_baked::dilate)",
            "provenance": {
                "scene": file.scene.clone(),
                "scene_hash": format!("{:016x}", file.scene_hash),
                "environment": file.environment.clone(),
                "samples": file.rays_per_probe,
                "bounces": file.bounces,
                "seed": file.seed,
            },
        },
    });
    let text = serde_json::to_string_pretty(&doc).expect("JSON values serialise") + "\n";
    let text = text.replacen("@DATA@", &data, 1);
    Ok(ThreeJsGrid { text, notes })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Probe `k`'s number `i` (of 27) is `1000 k + i`: every texel of the
    /// atlas names the probe and number it must hold, checked against the
    /// layout read off three.js's repack shader (texel `t` of a probe at
    /// `(x, y)` of slice `t (nz + 2) + 1 + z`, numbers `4t..4t+4`, padding
    /// slices copies of the edge layers).
    #[test]
    fn the_atlas_holds_each_number_where_threejs_reads_it() {
        let res = [3, 2, 4];
        let n: usize = res.iter().product();
        let probes: Vec<[[f32; 3]; 9]> = (0..n)
            .map(|k| {
                std::array::from_fn(|c| std::array::from_fn(|ch| (1000 * k + 3 * c + ch) as f32))
            })
            .collect();
        let atlas = ThreeJsAtlas::from_probes(res, &probes);
        let [nx, ny, nz] = res;
        assert_eq!(atlas.size, [nx, ny, 7 * (nz + 2)]);
        for s in 0..atlas.size[2] {
            let t = s / (nz + 2);
            // Padding slices copy the nearest layer.
            let z = (s % (nz + 2)).clamp(1, nz) - 1;
            for y in 0..ny {
                for x in 0..nx {
                    let k = x + nx * (y + ny * z);
                    let texel = atlas.texels[x + nx * (y + ny * s)];
                    for (c, v) in texel.iter().enumerate() {
                        let i = 4 * t + c;
                        let want = if i < 27 { (1000 * k + i) as f32 } else { 0.0 };
                        assert_eq!(*v, want, "slice {s} texel ({x}, {y}) channel {c}");
                    }
                }
            }
        }
    }

    #[test]
    fn half_precision_refuses_numbers_beyond_its_range() {
        let probes = vec![[[7.0e4f32, 0.0, 0.0]; 9]];
        let atlas = ThreeJsAtlas::from_probes([1, 1, 1], &probes);
        let e = atlas.bytes(Precision::Half).unwrap_err().to_string();
        assert!(e.contains("f32 precision") && !e.contains("--"), "{e}");
        assert_eq!(atlas.bytes(Precision::F32).unwrap().len(), 7 * 3 * 16);
    }
}

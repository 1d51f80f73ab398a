//! `--lookup bevy`: what Bevy shows from the `--format bevy` export of a
//! volume, computed on the CPU from the export's own texels.
//!
//! # Source
//! bevy_pbr `light_probe/irradiance_volume.wgsl`, `irradiance_volume_light`
//! (irradiance volumes arrived in Bevy 0.13), and `light_probe/light_probe.wgsl`,
//! which picks the volumes whose box holds the fragment. Later versions
//! blend overlapping volumes by a weight that falls off at the box's faces
//! and divide by the weights' sum: for one volume that changes nothing
//! inside its box, which is all this lookup models.
//!
//! # What is computed, step by step as Bevy does it
//! 1. **The texture**: [`BevyTexture::from_view`], the function the KTX2
//!    export writes: invalid probes dilated ([`shlight_baked::dilate`]),
//!    each probe's ambient cube `E(+-a) / pi` rounded to half floats
//!    (`R16G16B16A16_SFLOAT`), so the lookup reads the very numbers Bevy's
//!    GPU reads.
//! 2. **The box**: the light probe's transform puts the unit cube on the
//!    volume's bounds ([`light_probe_transform`]), so
//!    `unit_pos = (p - centre) / size`. Bevy lights a fragment from the
//!    volume only when `|unit_pos| <= 1/2` on every axis; elsewhere the
//!    volume adds nothing (the scene's environment map lights it), and this
//!    lookup returns 0.
//! 3. **Texel coordinates**: `stp = clamp((unit_pos + 1/2) res, 1/2,
//!    res - 1/2)` with `res = (nx, ny, nz)`: probes at cell centres,
//!    clamped to the outermost ones, so the filter never reads across a
//!    block; `uvw = stp / (nx, 2 ny, 3 nz)`.
//! 4. **Three filtered reads**, one per axis: the block of axis `a` is
//!    offset by `a / 3` in `w`, the negative half by `1/2` in `v` when
//!    `N_a < 0`. Each is the hardware's linear, clamp-to-edge filter: texel
//!    coordinates `uvw size - 1/2`, the eight texels around them weighted by
//!    the products of their fractional parts (exact weights here; a GPU
//!    rounds them to its sub-texel precision, 8 bits on most).
//! 5. **Valve's blend**: `sum_a N_a^2 c_a` (`N` the unit normal), times the
//!    volume's intensity (1) — Bevy's irradiance over pi, which it
//!    multiplies by the material's diffuse colour. This lookup returns
//!    `pi` times it, the irradiance `E` shlight's other lookups return.
//!
//! Arithmetic: the coordinates in `f32` as the shader has them, the filter
//! and the blend in `f64` over the texels' half floats.

use glam::{DVec3, Vec3};
use shlight_baked::VolumeView;
use shlight_core::sh::sh_count;
use shlight_format::bevy_volume::{BevyTexture, light_probe_transform};

use crate::texel_corners::texel_corners;

/// A volume's Bevy export in memory, ready to be looked up as Bevy does.
#[derive(Clone, Debug)]
pub(crate) struct BevyLookup {
    texture: BevyTexture,
    /// The light probe's translation (the box's centre) and scale (its size).
    centre: Vec3,
    size: Vec3,
    /// Probes per axis, as `f32` (`textureDimensions / (1, 2, 3)`).
    resolution: Vec3,
}

impl BevyLookup {
    /// The export of `view`'s probes kept to `lmax` (at most the volume's):
    /// the texels `shlight volume --format bevy` writes when `lmax` is the
    /// volume's.
    #[must_use]
    pub(crate) fn new(view: &VolumeView<'_>, lmax: usize) -> Self {
        let lmax = lmax.min(view.lmax);
        let clipped;
        let view = if lmax == view.lmax {
            *view
        } else {
            let (from, to) = (3 * sh_count(view.lmax), 3 * sh_count(lmax));
            clipped = view
                .radiance
                .chunks_exact(from)
                .flat_map(|p| &p[..to])
                .copied()
                .collect::<Vec<f32>>();
            VolumeView {
                lmax,
                radiance: &clipped,
                ..*view
            }
        };
        let texture = BevyTexture::from_view(&view);
        let (centre, size) =
            light_probe_transform((view.grid.min.to_array(), view.grid.max.to_array()));
        Self {
            texture,
            centre: Vec3::from_array(centre),
            size: Vec3::from_array(size),
            resolution: Vec3::from_array(view.grid.resolution.map(|n| n as f32)),
        }
    }

    /// The irradiance `E = pi sum_a N_a^2 c_a` Bevy shades a point `p`
    /// facing `n` with (the module's docs); 0 outside the volume's box.
    #[must_use]
    pub(crate) fn irradiance_at(&self, p: Vec3, n: Vec3) -> DVec3 {
        let unit_pos = (p - self.centre) / self.size;
        if !unit_pos.abs().cmple(Vec3::splat(0.5)).all() {
            return DVec3::ZERO;
        }
        let n = n.normalize();
        let resolution = self.resolution;
        let atlas_resolution = Vec3::from_array(self.texture.size.map(|s| s as f32));
        let stp = ((unit_pos + 0.5) * resolution).clamp(Vec3::splat(0.5), resolution - 0.5);
        let uvw = stp / atlas_resolution;
        let neg_offset = Vec3::select(n.cmplt(Vec3::ZERO), Vec3::splat(0.5), Vec3::ZERO);
        let rgb_x = self.sample(uvw + Vec3::new(0.0, neg_offset.x, 0.0));
        let rgb_y = self.sample(uvw + Vec3::new(0.0, neg_offset.y, 1.0 / 3.0));
        let rgb_z = self.sample(uvw + Vec3::new(0.0, neg_offset.z, 2.0 / 3.0));
        let nn = (n * n).as_dvec3();
        std::f64::consts::PI * (rgb_x * nn.x + rgb_y * nn.y + rgb_z * nn.z)
    }

    /// A linear, clamp-to-edge filtered read at normalised coordinates.
    fn sample(&self, uvw: Vec3) -> DVec3 {
        let size = self.texture.size;
        let t = uvw * Vec3::from_array(size.map(|s| s as f32)) - 0.5;
        let base = t.floor();
        let f = (t - base).as_dvec3();
        let clamp = |i: f32, a: usize| (i.max(0.0) as usize).min(size[a] - 1);
        let mut sum = DVec3::ZERO;
        for (d, w) in texel_corners(f) {
            let texel = [
                clamp(base.x + d[0] as f32, 0),
                clamp(base.y + d[1] as f32, 1),
                clamp(base.z + d[2] as f32, 2),
            ];
            sum += w * self.texture.rgb(texel).as_dvec3();
        }
        sum
    }
}

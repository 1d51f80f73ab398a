//! `--lookup threejs`: what three.js's `LightProbeGrid` shows from a
//! volume's probes.
//!
//! # Source
//! three.js r187 (npm `three` 0.187.0):
//! `src/renderers/shaders/ShaderChunk/lightprobes_pars_fragment.glsl.js`
//! (`isInsideLightProbeGrid`, `getLightProbeGridIrradiance`), called from
//! `lights_fragment_begin.glsl.js` with the fragment's world position and
//! unit world normal; the grid is `examples/jsm/lighting/LightProbeGridWebGL.js`
//! (`LightProbeGrid.js` and `tsl/lighting/LightProbeGridNode.js`, the
//! WebGPU variant, compute the same).
//!
//! # What is computed, step by step as three.js does it
//! 1. **The grid**: the grid's `boundingBox` is the volume's bounds and its
//!    `resolution` the probe counts; three.js places probe `i` at
//!    `min + (i + 1/2) (max - min) / n` (`getProbePosition`), the cell
//!    centres where shlight bakes them. Each probe holds the nine L2
//!    radiance coefficients in three.js's basis (`SphericalHarmonics3`:
//!    shlight's with the Condon-Shortley phase removed, odd `|m|` negated),
//!    lmax 2: a volume of lower lmax is zero-padded, one of higher lmax
//!    clipped to 2. Invalid probes are dilated first
//!    ([`shlight_baked::dilate`]): the grid knows no validity. Both come from
//!    [`shlight_format::threejs_volume::threejs_probes`], as the export's.
//! 2. **The offset**: `spacing = (max - min) / n`; the point is moved half
//!    a probe spacing along the normal, `s = p + n spacing / 2`
//!    (per axis).
//! 3. **Inside**: three.js uses the grid only when `s` lies within the
//!    bounds grown by 1% of a cell on each side; elsewhere the grid adds
//!    nothing and this lookup returns 0.
//! 4. **Clamp and interpolate**: `uvw = clamp((s - min) / (max - min),
//!    1 / 2n, 1 - 1 / 2n)`, the outermost probes' texel centres; the seven
//!    RGBA sub-volumes of the atlas are sampled there with the linear
//!    filter. The atlas's padding slices copy the edge slices and the clamp
//!    keeps the filter between texel centres, so each read is the
//!    trilinear interpolation of the probes at grid coordinates
//!    `uvw n - 1/2`, clamped to the grid, nothing more (exact weights here;
//!    a GPU rounds them to its sub-texel precision). The probes are the
//!    `f32` numbers the `--format threejs --precision f32` export's atlas
//!    holds ([`shlight_format::threejs_volume`]; three.js's own bake renders
//!    a `FloatType` atlas too); the default half-float export differs by
//!    the rounding of each coefficient, which is not modelled.
//! 5. **Irradiance** of the interpolated coefficients `c0..c8` at the unit
//!    normal `(x, y, z)`, with three.js's constants:
//!    `0.886227 c0 + 2 0.511664 (c1 y + c2 z + c3 x) + 2 0.429043 (c4 xy +
//!    c5 yz + c7 xz) + c6 (0.743125 z^2 - 0.247708) + 0.429043 c8 (x^2 -
//!    y^2)`, clamped to 0 per channel: the irradiance `E` (three.js then
//!    multiplies it by `BRDF_Lambert = albedo / pi`).
//!
//! Arithmetic: the point's offset and `uvw` in `f32` as the shader has
//! them; the interpolation and the irradiance in `f64`.

use glam::{DVec3, Vec3};
use shlight_baked::{ProbeGrid, VolumeView};
use shlight_format::threejs_volume::threejs_probes;

use crate::texel_corners::texel_corners;

/// A volume's probes as three.js's `LightProbeGrid` holds them, ready to
/// be looked up as three.js does.
#[derive(Clone, Debug)]
pub(crate) struct ThreeJsLookup {
    grid: ProbeGrid,
    /// Per probe nine `[r, g, b]` coefficients in three.js's basis.
    probes: Vec<[[f32; 3]; 9]>,
}

impl ThreeJsLookup {
    /// The grid of `view`'s probes: dilated, kept to `lmax` (at most
    /// [`THREEJS_LMAX`](shlight_format::threejs_volume::THREEJS_LMAX) and the volume's; the rest of the nine coefficients
    /// zero), in three.js's basis: the numbers the `--format threejs`
    /// export's atlas holds ([`threejs_probes`]).
    #[must_use]
    pub(crate) fn new(view: &VolumeView<'_>, lmax: usize) -> Self {
        Self {
            grid: view.grid,
            probes: threejs_probes(view, lmax),
        }
    }

    /// The irradiance three.js shades a point `p` facing `n` with (the
    /// module's docs); 0 where the offset point is outside the grid's box.
    #[must_use]
    pub(crate) fn irradiance_at(&self, p: Vec3, n: Vec3) -> DVec3 {
        let world_normal = n.normalize();
        let (min, max) = (self.grid.min, self.grid.max);
        let res = Vec3::from_array(self.grid.resolution.map(|r| r as f32));
        let grid_range = max - min;
        let probe_spacing = grid_range / res;
        let sample_pos = p + world_normal * probe_spacing * 0.5;
        let margin = probe_spacing * 0.01;
        if !(sample_pos.cmpge(min - margin).all() && sample_pos.cmple(max + margin).all()) {
            return DVec3::ZERO;
        }
        let half_texel = Vec3::splat(0.5) / res;
        let uvw = ((sample_pos - min) / grid_range).clamp(half_texel, 1.0 - half_texel);
        // The filter's texel coordinates in the probe grid, between the
        // first and last probe on each axis.
        let t = (uvw * res - 0.5).clamp(Vec3::ZERO, res - 1.0);
        let base = t.floor();
        let f = (t - base).as_dvec3();
        let [nx, ny, nz] = self.grid.resolution;
        let i0 = [base.x as usize, base.y as usize, base.z as usize];
        let mut c = [DVec3::ZERO; 9];
        for (d, w) in texel_corners(f) {
            let [x, y, z] = [
                (i0[0] + d[0]).min(nx - 1),
                (i0[1] + d[1]).min(ny - 1),
                (i0[2] + d[2]).min(nz - 1),
            ];
            for (ci, v) in c.iter_mut().zip(&self.probes[x + nx * (y + ny * z)]) {
                *ci += w * Vec3::from_array(*v).as_dvec3();
            }
        }
        let (x, y, z) = (
            f64::from(world_normal.x),
            f64::from(world_normal.y),
            f64::from(world_normal.z),
        );
        let mut result = c[0] * 0.886227;
        result += c[1] * 2.0 * 0.511664 * y;
        result += c[2] * 2.0 * 0.511664 * z;
        result += c[3] * 2.0 * 0.511664 * x;
        result += c[4] * 2.0 * 0.429043 * x * y;
        result += c[5] * 2.0 * 0.429043 * y * z;
        result += c[6] * (0.743125 * z * z - 0.247708);
        result += c[7] * 2.0 * 0.429043 * x * z;
        result += c[8] * 0.429043 * (x * x - y * y);
        result.max(DVec3::ZERO)
    }
}

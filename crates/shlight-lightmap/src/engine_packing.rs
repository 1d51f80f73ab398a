//! Each engine's packing of a texel and the matching reconstruction,
//! ported from the engine's shader (sources, commits and lines quoted in
//! docs/lightmaps.md, "What a texel holds, engine by engine").

use glam::{DVec3, Vec3};
use shlight_core::sh::ShL1Rgb;

use crate::diffuse_l1::DiffuseL1;
use crate::geomerics::geomerics_l1;
use crate::texel_format::{Engine, L1Reconstruction, TexelBasis, TexelFormat};

/// One texel as the engine's textures hold it: up to four RGBA layers of
/// `f32` (layer `k` goes to the format's `k`-th texture or array slice),
/// before any quantisation to the file's pixel format.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PackedTexel {
    layers: [[f32; 4]; 4],
    count: usize,
    clamped: bool,
}

impl PackedTexel {
    /// The layers, [`TexelFormat::layer_count`] of them.
    #[must_use]
    pub fn layers(&self) -> &[[f32; 4]] {
        &self.layers[..self.count]
    }

    /// Whether the packing had to clamp a value to its `0..=1` range
    /// (Godot's L1 beyond `4 L0`, Bakery's beyond `2 L0`: never for
    /// radiance that is nowhere negative, where `|L1| <= 2 L0`).
    #[must_use]
    pub fn clamped(&self) -> bool {
        self.clamped
    }

    /// A texel from layers as read back from a file (at most four; the
    /// rest are ignored), to reconstruct.
    #[must_use]
    pub fn from_layers(layers: &[[f32; 4]]) -> Self {
        let mut t = Self {
            layers: [[0.0; 4]; 4],
            count: layers.len().min(4),
            clamped: false,
        };
        t.layers[..t.count].copy_from_slice(&layers[..t.count]);
        t
    }

    fn push(&mut self, rgb: DVec3) {
        self.layers[self.count] = [rgb.x as f32, rgb.y as f32, rgb.z as f32, 1.0];
        self.count += 1;
    }

    fn push_unit(&mut self, v: DVec3) {
        let c = v.clamp(DVec3::ZERO, DVec3::ONE);
        self.clamped |= c != v;
        self.push(c);
    }
}

/// Godot's `MODE_PACK_L1_COEFFS` (lm_compute.glsl), one channel:
/// `c /= base * 8` where `base != 0`, then `clamp(c + 0.5, 0, 1)`.
fn godot_pack(l1: f64, l0: f64) -> f64 {
    let c = if l0.abs() > 0.0 { l1 / (l0 * 8.0) } else { l1 };
    c + 0.5
}

/// The inverse of Bakery's decode `L1 = (t * 2 - 1) * L0 * 2`, one
/// channel: `t = L1 / (4 L0) + 1/2` (1/2 where `L0 = 0`, which the decode
/// multiplies away).
fn bakery_pack(l1: f64, l0: f64) -> f64 {
    if l0 == 0.0 {
        0.5
    } else {
        l1 / (4.0 * l0) + 0.5
    }
}

fn rgb(layer: &[f32; 4]) -> Vec3 {
    Vec3::new(layer[0], layer[1], layer[2])
}

impl TexelFormat {
    /// The texel for radiance `sh` (lmax 1, RGB, shlight's basis and
    /// world axes) at a surface of unit `normal` (used by
    /// [`TexelBasis::Irradiance`] only). Computed in `f64` from
    /// [`DiffuseL1`] in the engine's units, rounded to `f32`:
    ///
    /// - irradiance: `(E(normal), 1)`;
    /// - three.js sh-l1 (shlight's layout): `(a, 1)`, then `(b.x, 1)`,
    ///   `(b.y, 1)`, `(b.z, 1)` per channel, plain floats;
    /// - Godot sh-l1: `(a, 1)`, then `b / (8 a) + 1/2` for y, z, x,
    ///   clamped to `0..=1` (Godot's own pack step);
    /// - Unity sh-l1 (Bakery SH: the lightmap, `_RNM0`, `_RNM1`,
    ///   `_RNM2`): `(a, 1)`, then `b / (4 a) + 1/2` for x, y, z, clamped;
    /// - Unity MonoSH (the lightmap, `unity_LightmapInd`): `(a, 1)`, then
    ///   `d / 2 + 1/2` with the shared `d = sum_c b_c / (2 sum_c a_c)`,
    ///   clamped.
    ///
    /// MonoSH's `d` makes the decoded `L1_c = 2 a_c d` keep the channel
    /// sum (Bakery's luma, `dot(., 1)`) of the full L1 exactly, and every
    /// channel exactly when all light comes from one direction.
    #[must_use]
    pub fn pack(self, sh: &ShL1Rgb<f64>, normal: DVec3) -> PackedTexel {
        let d = DiffuseL1::from_radiance(sh, self.units());
        let a = d.constant;
        let axis = |i: usize| DVec3::new(d.linear[0][i], d.linear[1][i], d.linear[2][i]);
        let per_channel =
            |b: DVec3, f: fn(f64, f64) -> f64| DVec3::new(f(b.x, a.x), f(b.y, a.y), f(b.z, a.z));
        let mut t = PackedTexel {
            layers: [[0.0; 4]; 4],
            count: 0,
            clamped: false,
        };
        match (self.basis(), self.engine()) {
            (TexelBasis::Irradiance, _) => t.push(d.eval(normal)),
            (TexelBasis::ShL1, Engine::Godot) => {
                t.push(a);
                for i in [1, 2, 0] {
                    t.push_unit(per_channel(axis(i), godot_pack));
                }
            }
            (TexelBasis::ShL1, Engine::Unity) => {
                t.push(a);
                for i in 0..3 {
                    t.push_unit(per_channel(axis(i), bakery_pack));
                }
            }
            (TexelBasis::MonoSh, _) => {
                t.push(a);
                let luma = a.x + a.y + a.z;
                let dir = if luma > 0.0 {
                    (d.linear[0] + d.linear[1] + d.linear[2]) / (2.0 * luma)
                } else {
                    DVec3::ZERO
                };
                t.push_unit(dir * 0.5 + 0.5);
            }
            (TexelBasis::ShL1, _) => {
                t.push(a);
                for i in 0..3 {
                    t.push(axis(i));
                }
            }
        }
        t
    }

    /// The diffuse light the engine's shader computes from `texel` at
    /// normal `n` (world axes, the lightmap's frame), in the engine's
    /// units, before the albedo: a port of that shader in `f32`, with
    /// every intensity or exposure multiplier at 1.
    ///
    /// - irradiance: the texel's RGB. three.js:
    ///   `lightMapTexel.rgb * lightMapIntensity`; Bevy:
    ///   `sample(...) * exposure`; Godot: `textureLod(...).rgb *
    ///   exposure_normalization`; Unity: `DecodeLightmap` of a full-HDR
    ///   lightmap (multiplier 1).
    /// - Godot sh-l1 (scene_forward_clustered.glsl, `uses_sh`):
    ///   `n = normalize(normal_xform * indirect_normal)`,
    ///   `l1 = (t - 0.5) * 2.0`, `ambient = l0 * en + l1n1 * n.y * (l0 *
    ///   en * 4.0) + l1_0 * n.z * (...) + l1p1 * n.x * (...)`.
    /// - Unity sh-l1 (Bakery SH): `nL1x = t * 2 - 1`, `L1x = nL1x * L0 *
    ///   2` (and y, z); linear: `L0 + n.x * L1x + n.y * L1y + n.z * L1z`;
    ///   non-linear: Bakery's `BakerySH_float`: that sum scaled by
    ///   `lerp(1, lumaSH / regularLumaSH, saturate(regularLumaSH * 16))`,
    ///   `lumaSH` [`geomerics_l1`] of the channel sums, then `max(sh, 0)`.
    /// - Unity MonoSH (`BakeryMonoSH_float`): the same with `nL1 = dir *
    ///   2 - 1` shared, `L1x = nL1.x * L0 * 2`.
    /// - three.js sh-l1 (shlight's layout): `a + b . n`; non-linear:
    ///   [`geomerics_l1`] per channel.
    ///
    /// Where Bakery's `regularLumaSH` is 0 the rescale is skipped (the
    /// shader's `lerp` weight is 0 there, but `0 / 0` makes it NaN).
    #[must_use]
    pub fn reconstruct(self, texel: &PackedTexel, n: Vec3) -> Vec3 {
        let layers = texel.layers();
        let l0 = rgb(&layers[0]);
        match (self.basis(), self.engine()) {
            (TexelBasis::Irradiance, _) => l0,
            (TexelBasis::ShL1, Engine::Godot) => {
                let lm_light_l0 = l0;
                let lm_light_l1n1 = (rgb(&layers[1]) - Vec3::splat(0.5)) * 2.0;
                let lm_light_l1_0 = (rgb(&layers[2]) - Vec3::splat(0.5)) * 2.0;
                let lm_light_l1p1 = (rgb(&layers[3]) - Vec3::splat(0.5)) * 2.0;
                let n = n.normalize();
                let en = 1.0f32;
                let mut ambient_light = Vec3::ZERO;
                ambient_light += lm_light_l0 * en;
                ambient_light += lm_light_l1n1 * n.y * (lm_light_l0 * en * 4.0);
                ambient_light += lm_light_l1_0 * n.z * (lm_light_l0 * en * 4.0);
                ambient_light += lm_light_l1p1 * n.x * (lm_light_l0 * en * 4.0);
                ambient_light
            }
            (TexelBasis::ShL1, Engine::Unity) => {
                let nl1x = rgb(&layers[1]) * 2.0 - 1.0;
                let nl1y = rgb(&layers[2]) * 2.0 - 1.0;
                let nl1z = rgb(&layers[3]) * 2.0 - 1.0;
                bakery_sh(
                    l0,
                    nl1x * l0 * 2.0,
                    nl1y * l0 * 2.0,
                    nl1z * l0 * 2.0,
                    n,
                    self,
                )
            }
            (TexelBasis::MonoSh, _) => {
                let nl1 = rgb(&layers[1]) * 2.0 - 1.0;
                let l1x = nl1.x * l0 * 2.0;
                let l1y = nl1.y * l0 * 2.0;
                let l1z = nl1.z * l0 * 2.0;
                bakery_sh(l0, l1x, l1y, l1z, n, self)
            }
            (TexelBasis::ShL1, _) => {
                let (bx, by, bz) = (rgb(&layers[1]), rgb(&layers[2]), rgb(&layers[3]));
                match self.reconstruction() {
                    L1Reconstruction::Linear => l0 + bx * n.x + by * n.y + bz * n.z,
                    L1Reconstruction::NonLinear => {
                        let ch = |c: usize| geomerics_l1(l0[c], Vec3::new(bx[c], by[c], bz[c]), n);
                        Vec3::new(ch(0), ch(1), ch(2))
                    }
                }
            }
        }
    }
}

/// Bakery's decode after the L1 vectors are known (`BakerySH_float` /
/// `BakeryMonoSH_float`, and their linear `#else` branch).
fn bakery_sh(l0: Vec3, l1x: Vec3, l1y: Vec3, l1z: Vec3, n: Vec3, format: TexelFormat) -> Vec3 {
    let mut sh = l0 + n.x * l1x + n.y * l1y + n.z * l1z;
    if format.reconstruction() == L1Reconstruction::Linear {
        return sh;
    }
    let luma = |v: Vec3| v.dot(Vec3::ONE);
    let luma_l0 = luma(l0);
    let luma_l1 = Vec3::new(luma(l1x), luma(l1y), luma(l1z));
    let luma_sh = geomerics_l1(luma_l0, luma_l1, n);
    let regular_luma_sh = luma(sh);
    let w = (regular_luma_sh * 16.0).clamp(0.0, 1.0);
    if w > 0.0 {
        sh *= 1.0 + w * (luma_sh / regular_luma_sh - 1.0);
    }
    sh.max(Vec3::ZERO)
}

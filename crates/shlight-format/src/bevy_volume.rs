//! A probe volume as Bevy's `IrradianceVolume` texture: a KTX2 3D texture
//! of ambient cubes, in the layout and units Bevy's own shader reads
//! (bevy_pbr `light_probe/irradiance_volume.wgsl`).
//!
//! # What Bevy reads
//! The texture is `nx x 2 ny x 3 nz` texels for an `nx x ny x nz` grid:
//! probe `(x, y, z)`'s ambient cube (Valve 2006, "Shading in Valve's Source
//! Engine", slide 28) sits at texel `(x, y + ny s, z + nz a)` for axis `a`
//! (0 = X, 1 = Y, 2 = Z) and sign `s` (0 for `+a`, 1 for `-a`). The shader
//! maps the fragment into the light probe's unit cube, to texel coordinates
//! `stp = (p + 1/2) resolution` clamped to `[1/2, resolution - 1/2]` (so
//! probes sit at cell centres, as shlight's), samples the three faces the
//! normal `N` looks at with the linear sampler and returns
//! `sum_a N_a^2 c_{sign(N_a) a}`, which Bevy multiplies by the material's
//! diffuse colour (albedo, no `1/pi`) and the volume's `intensity`. So each
//! texel holds `E(+-a) / pi`: the exit radiance of a white Lambertian
//! surface facing that way, `E` the irradiance of the probe's radiance SH
//! (Ramamoorthi & Hanrahan 2001), which makes the six axes exact.
//!
//! The light probe's `Transform` places the unit cube on the grid's bounds:
//! translation the box's centre, scale its size (docs/shvol.md;
//! [`light_probe_transform`]).
//!
//! # The file
//! KTX2 (Khronos), `VK_FORMAT_R16G16B16A16_SFLOAT` (linear, filterable
//! everywhere; alpha 1), one level, one layer, one face, no
//! supercompression, a basic data format descriptor (RGBSDA, BT.709
//! primaries, linear transfer) and a `KTXwriter` key. Bevy's sampler knows
//! no validity, so invalid probes are filled first by
//! [`shlight_baked::dilate`] (the mean of their valid face neighbours, pass
//! by pass from the valid probes outwards; zero when none is valid).
//!
//! [`BevyTexture`] holds the texels in memory: the KTX2 export writes them
//! and `shlight sample --lookup bevy` (shlight-volume) looks them up as
//! Bevy's shader does.

use glam::{DVec3, Vec3};
use shlight_baked::{VolumeView, dilate};
use shlight_core::encoding::AmbientCube;
use shlight_core::sh::{ShCoeffs, sh_count};

use crate::ShvolFile;

/// `VK_FORMAT_R16G16B16A16_SFLOAT`.
pub const VK_FORMAT: u32 = 97;

/// The six ambient-cube colours of every probe of `view`, `E(+-a) / pi` in
/// the order of [`shlight_core::encoding::AMBIENT_CUBE_AXES`] (+X, -X, +Y,
/// -Y, +Z, -Z), probes in grid order, each from its radiance as `view`
/// holds it (invalid probes too: [`BevyTexture::from_view`] dilates
/// first).
#[must_use]
pub fn ambient_cubes(view: &VolumeView<'_>) -> Vec<[Vec3; 6]> {
    let nc = sh_count(view.lmax);
    view.radiance
        .chunks_exact(3 * nc)
        .map(|p| {
            let l = ShCoeffs::from_vec(
                p.chunks_exact(3)
                    .map(|c| Vec3::from_slice(c).as_dvec3())
                    .collect(),
            )
            .expect("(lmax+1)^2 rows");
            AmbientCube::from_sh(&l)
                .colours
                .map(|e: DVec3| (e / std::f64::consts::PI).as_vec3())
        })
        .collect()
}

/// The translation and scale of the `Transform` of the `LightProbe` that
/// carries a volume of `bounds` (min, max): Bevy's light probe is the unit
/// cube `[-1/2, 1/2]^3` under its transform, so the translation is the
/// box's centre `(min + max) / 2` and the scale its size `max - min`.
#[must_use]
pub fn light_probe_transform((lo, hi): ([f32; 3], [f32; 3])) -> ([f32; 3], [f32; 3]) {
    (
        std::array::from_fn(|a| (lo[a] + hi[a]) / 2.0),
        std::array::from_fn(|a| hi[a] - lo[a]),
    )
}

/// The texture Bevy's `IrradianceVolume` samples, in memory: `nx x 2 ny x
/// 3 nz` RGBA16F texels, x fastest, then y, then z, probe `(x, y, z)`'s
/// colour for axis `a` and sign `s` at texel `(x, y + ny s, z + nz a)`
/// (the module's docs).
#[derive(Clone, Debug, PartialEq)]
pub struct BevyTexture {
    /// Width, height, depth: `[nx, 2 ny, 3 nz]`.
    pub size: [usize; 3],
    /// The texels' half-float bits `[r, g, b, a]` (alpha 1).
    pub texels: Vec<[u16; 4]>,
}

impl BevyTexture {
    /// The texture of `view`: invalid probes dilated
    /// ([`shlight_baked::dilate`]), each probe's [`ambient_cubes`] rounded to
    /// half floats (round to nearest even, as `half::f16::from_f32`).
    #[must_use]
    pub fn from_view(view: &VolumeView<'_>) -> Self {
        let [nx, ny, nz] = view.grid.resolution;
        let radiance = dilate(view);
        let cubes = ambient_cubes(&VolumeView {
            radiance: &radiance,
            ..*view
        });
        let (w, h, d) = (nx, 2 * ny, 3 * nz);
        let mut texels = vec![[0u16; 4]; w * h * d];
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let cube = &cubes[x + nx * (y + ny * z)];
                    for a in 0..3 {
                        for s in 0..2 {
                            let c = cube[2 * a + s];
                            let (ty, tz) = (y + ny * s, z + nz * a);
                            texels[x + w * (ty + h * tz)] = [
                                half::f16::from_f32(c.x).to_bits(),
                                half::f16::from_f32(c.y).to_bits(),
                                half::f16::from_f32(c.z).to_bits(),
                                half::f16::ONE.to_bits(),
                            ];
                        }
                    }
                }
            }
        }
        Self {
            size: [w, h, d],
            texels,
        }
    }

    /// The colour of texel `(x, y, z)`, its half floats widened to `f32`
    /// (exactly, as a GPU reads them).
    #[must_use]
    pub fn rgb(&self, [x, y, z]: [usize; 3]) -> Vec3 {
        let [w, h, _] = self.size;
        let t = self.texels[x + w * (y + h * z)];
        Vec3::new(
            half::f16::from_bits(t[0]).to_f32(),
            half::f16::from_bits(t[1]).to_f32(),
            half::f16::from_bits(t[2]).to_f32(),
        )
    }

    /// The KTX2 file of the texture, `writer` in its `KTXwriter` key.
    #[must_use]
    pub fn ktx2(&self, writer: &str) -> Vec<u8> {
        let data: Vec<u8> = self
            .texels
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        crate::ktx2_file::write_ktx2(self.size, 1, &[data], writer)
    }
}

/// The KTX2 file Bevy's `IrradianceVolume` takes ([`BevyTexture`] of the
/// file's probes).
#[must_use]
pub fn bevy_ktx2(file: &ShvolFile, writer: &str) -> Vec<u8> {
    BevyTexture::from_view(&file.view()).ktx2(writer)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's corners under the transform are the bounds.
    #[test]
    fn the_light_probe_transform_puts_the_unit_cube_on_the_bounds() {
        let bounds = ([-1.0, 0.0, 2.5], [3.0, 0.5, 4.0]);
        let (t, s) = light_probe_transform(bounds);
        assert_eq!((t, s), ([1.0, 0.25, 3.25], [4.0, 0.5, 1.5]));
        for a in 0..3 {
            assert_eq!(t[a] - 0.5 * s[a], bounds.0[a]);
            assert_eq!(t[a] + 0.5 * s[a], bounds.1[a]);
        }
    }
}

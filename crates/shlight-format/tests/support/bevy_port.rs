//! Bevy's lookup of an irradiance volume, ported line for line from
//! bevy_pbr's `light_probe/irradiance_volume.wgsl` (`irradiance_volume_light`)
//! and `light_probe/light_probe.wgsl` (which volumes hold the fragment),
//! over a KTX2 file read back with the `ktx2` crate: the independent route
//! the Bevy export (shlight-format's tests) and `--lookup bevy`
//! (shlight-volume's tests) are held to.
#![allow(dead_code)]

use glam::Vec3;

/// The texture as a GPU holds it: the KTX2 file's RGBA16F texels widened
/// to `f32`.
pub struct Texture {
    pub size: [usize; 3],
    pub texels: Vec<Vec3>,
}

impl Texture {
    pub fn read(bytes: &[u8]) -> Self {
        let reader = ktx2::Reader::new(bytes).expect("a valid KTX2 file");
        let h = reader.header();
        assert_eq!(h.format, Some(ktx2::Format::R16G16B16A16_SFLOAT));
        assert_eq!((h.layer_count, h.face_count, h.level_count), (0, 1, 1));
        let size = [
            h.pixel_width as usize,
            h.pixel_height as usize,
            h.pixel_depth as usize,
        ];
        let level = reader.levels().next().unwrap();
        let texels = level
            .data
            .chunks_exact(8)
            .map(|t| {
                let c = |k: usize| {
                    half::f16::from_bits(u16::from_le_bytes([t[2 * k], t[2 * k + 1]])).to_f32()
                };
                assert_eq!(c(3), 1.0);
                Vec3::new(c(0), c(1), c(2))
            })
            .collect();
        Self { size, texels }
    }

    fn texel(&self, x: i64, y: i64, z: i64) -> Vec3 {
        let [w, h, d] = self.size.map(|s| s as i64);
        let (x, y, z) = (x.clamp(0, w - 1), y.clamp(0, h - 1), z.clamp(0, d - 1));
        self.texels[(x + w * (y + h * z)) as usize]
    }

    /// A linear, clamp-to-edge sampler at normalised coordinates.
    fn sample(&self, uvw: Vec3) -> Vec3 {
        let t = uvw * Vec3::from_array(self.size.map(|s| s as f32)) - 0.5;
        let base = t.floor();
        let f = t - base;
        let (bx, by, bz) = (base.x as i64, base.y as i64, base.z as i64);
        let mut sum = Vec3::ZERO;
        for corner in 0..8 {
            let (dx, dy, dz) = (corner & 1, corner >> 1 & 1, corner >> 2 & 1);
            let w = if dx == 1 { f.x } else { 1.0 - f.x }
                * if dy == 1 { f.y } else { 1.0 - f.y }
                * if dz == 1 { f.z } else { 1.0 - f.z };
            sum += w * self.texel(bx + dx, by + dy, bz + dz);
        }
        sum
    }

    /// Bevy's `irradiance_volume_light`, line for line, with the fragment
    /// already in the probe's unit cube.
    pub fn bevy_light(&self, unit_pos: Vec3, n: Vec3) -> Vec3 {
        let atlas_resolution = Vec3::from_array(self.size.map(|s| s as f32));
        let resolution =
            Vec3::from_array([self.size[0], self.size[1] / 2, self.size[2] / 3].map(|s| s as f32));
        let stp = ((unit_pos + 0.5) * resolution).clamp(Vec3::splat(0.5), resolution - 0.5);
        let uvw = stp / atlas_resolution;
        let neg = Vec3::select(n.cmplt(Vec3::ZERO), Vec3::splat(0.5), Vec3::ZERO);
        let rgb_x = self.sample(uvw + Vec3::new(0.0, neg.x, 0.0));
        let rgb_y = self.sample(uvw + Vec3::new(0.0, neg.y, 1.0 / 3.0));
        let rgb_z = self.sample(uvw + Vec3::new(0.0, neg.z, 2.0 / 3.0));
        let nn = n * n;
        rgb_x * nn.x + rgb_y * nn.y + rgb_z * nn.z
    }

    /// What a fragment at `world_position` with unit normal `n` gets from
    /// the volume on a light probe of `translation` and `scale`:
    /// `light_probe.wgsl`'s query (the point in the light probe's unit
    /// cube `|p| <= 1/2`, else no volume) and then [`Texture::bevy_light`].
    pub fn world_light(
        &self,
        (translation, scale): (Vec3, Vec3),
        world_position: Vec3,
        n: Vec3,
    ) -> Vec3 {
        let probe_space_pos = (world_position - translation) / scale;
        if !probe_space_pos.abs().cmple(Vec3::splat(0.5)).all() {
            return Vec3::ZERO;
        }
        self.bevy_light(probe_space_pos, n)
    }
}

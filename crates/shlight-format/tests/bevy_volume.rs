//! The Bevy irradiance volume file, read back with the `ktx2` crate and
//! looked up with a port of Bevy's own shader (bevy_pbr
//! `light_probe/irradiance_volume.wgsl`): at every probe and axis it gives
//! the probe's irradiance over pi, computed here by quadrature of the
//! radiance SH (not through the exporter's R&H route).

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use shlight_core::sh::{ShCoeffs, closed_form, sh_count};
use shlight_format::ShvolFile;
use shlight_format::bevy_volume::bevy_ktx2;

fn probe_light(i: usize) -> ShCoeffs<DVec3> {
    // A different light per probe: a lobe whose axis and colour move.
    let a = i as f64 * 0.7;
    let axis = DVec3::new(a.cos(), 0.5 * (1.3 * a).sin(), a.sin()).normalize();
    let lobe = closed_form::cosine_lobe(2, axis, DVec3::new(1.0 + 0.1 * i as f64, 0.6, 0.3));
    let base = closed_form::constant(2, DVec3::new(0.2, 0.3, 0.4));
    ShCoeffs::from_vec(
        lobe.as_slice()
            .iter()
            .zip(base.as_slice())
            .map(|(a, b)| *a + *b)
            .collect(),
    )
    .unwrap()
}

fn volume(valid: Vec<bool>) -> ShvolFile {
    let resolution = [3, 2, 2];
    let probes = 12;
    let mut radiance = Vec::new();
    for i in 0..probes {
        for c in probe_light(i).as_slice() {
            radiance.extend(c.as_vec3().to_array());
        }
    }
    ShvolFile {
        lmax: 2,
        resolution,
        bounds: ([-1.0, 0.0, -2.0], [2.0, 1.0, 2.0]),
        frame: "y-up".into(),
        valid,
        radiance,
        emitted: None,
        transfer: None,
        offsets: None,
        visibility: None,
        samples: 1,
        bounces: 0,
        seed: 0,
        scene: "s".into(),
        scene_hash: 0,
        environment: "e".into(),
        generator: "test".into(),
    }
}

/// E(n) / pi by a dense midpoint rule over the sphere.
fn irradiance_over_pi(l: &ShCoeffs<DVec3>, n: DVec3) -> DVec3 {
    let (rows, cols) = (200, 400);
    let mut sum = DVec3::ZERO;
    for r in 0..rows {
        let t = (r as f64 + 0.5) / rows as f64 * PI;
        for c in 0..cols {
            let p = (c as f64 + 0.5) / cols as f64 * 2.0 * PI;
            let s = DVec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin());
            let w = t.sin() * (PI / rows as f64) * (2.0 * PI / cols as f64);
            sum += l.eval(s) * n.dot(s).max(0.0) * w;
        }
    }
    sum / PI
}

struct Texture {
    size: [usize; 3],
    texels: Vec<Vec3>,
}

impl Texture {
    fn read(bytes: &[u8]) -> Self {
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
    fn bevy_light(&self, unit_pos: Vec3, n: Vec3) -> Vec3 {
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
}

/// The probe's position in the light probe's unit cube (what Bevy's
/// `light_from_world` gives for a probe at its cell centre).
fn unit(file: &ShvolFile, p: [f32; 3]) -> Vec3 {
    let (lo, hi) = (
        Vec3::from_array(file.bounds.0),
        Vec3::from_array(file.bounds.1),
    );
    (Vec3::from_array(p) - (lo + hi) / 2.0) / (hi - lo)
}

#[test]
fn bevy_reads_each_probes_irradiance_over_pi_at_the_six_axes() {
    let file = volume(vec![true; 12]);
    let bytes = bevy_ktx2(&file, "shlight test");
    let tex = Texture::read(&bytes);
    assert_eq!(tex.size, [3, 4, 6]);
    assert_eq!(sh_count(file.lmax), 9);
    for (i, p) in centres(&file).into_iter().enumerate() {
        let l = probe_light(i);
        for n in [
            DVec3::X,
            DVec3::NEG_X,
            DVec3::Y,
            DVec3::NEG_Y,
            DVec3::Z,
            DVec3::NEG_Z,
        ] {
            let got = tex.bevy_light(unit(&file, p), n.as_vec3()).as_dvec3();
            let want = irradiance_over_pi(&l, n);
            // f16 texels: 11 significant bits.
            assert!(
                (got - want).abs().max_element() < 2e-3 * want.max_element().max(0.1),
                "probe {i} {n}: {got} vs {want}"
            );
        }
    }
    // Halfway between two probes along x the sampler blends them equally.
    let (a, b) = (
        file.grid().centre([0, 1, 1]).to_array(),
        file.grid().centre([1, 1, 1]).to_array(),
    );
    let mid = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
    let got = tex.bevy_light(unit(&file, mid), Vec3::Y);
    let want =
        0.5 * (tex.bevy_light(unit(&file, a), Vec3::Y) + tex.bevy_light(unit(&file, b), Vec3::Y));
    assert!((got - want).abs().max_element() < 1e-5);
}

#[test]
fn invalid_probes_take_their_valid_neighbours_light() {
    let mut valid = vec![true; 12];
    valid[0] = false;
    let file = volume(valid);
    let tex = Texture::read(&bevy_ktx2(&file, "t"));
    // Probe 0's face neighbours: probe 1 (+x), probe 3 (+y), probe 6 (+z).
    let positions = centres(&file);
    for n in [Vec3::X, Vec3::NEG_Y] {
        let got = tex.bevy_light(unit(&file, positions[0]), n);
        let want = [1usize, 3, 6]
            .iter()
            .map(|&j| tex.bevy_light(unit(&file, positions[j]), n))
            .sum::<Vec3>()
            / 3.0;
        assert!(
            (got - want).abs().max_element() < 2e-3 * want.max_element(),
            "{got} vs {want}"
        );
    }
}

/// Every probe's centre as an array, in probe order.
fn centres(file: &ShvolFile) -> Vec<[f32; 3]> {
    file.grid().centres().iter().map(|c| c.to_array()).collect()
}

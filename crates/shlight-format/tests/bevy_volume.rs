//! The Bevy irradiance volume file, read back with the `ktx2` crate and
//! looked up with a port of Bevy's own shader (bevy_pbr
//! `light_probe/irradiance_volume.wgsl`, in `support/bevy_port.rs`, which
//! shlight-volume's `--lookup bevy` is held to as well): at every probe and axis it gives
//! the probe's irradiance over pi, computed here by quadrature of the
//! radiance SH (not through the exporter's R&H route).

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use shlight_core::sh::{ShCoeffs, closed_form, sh_count};
use shlight_format::ShvolFile;
use shlight_format::bevy_volume::bevy_ktx2;

#[path = "support/bevy_port.rs"]
mod bevy_port;
use bevy_port::Texture;

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
        rays_per_probe: 1,
        bounces: 0,
        seed: 0,
        scene: "s".into(),
        scene_hash: 0,
        environment: "e".into(),
        generator: "test".into(),
        lights: None,
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

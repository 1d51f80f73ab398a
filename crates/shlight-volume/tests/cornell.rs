//! The Cornell box (published geometry and colours, its ceiling light and
//! the open front under a sky) against an independent brute-force path
//! tracer written here: per probe, uniformly random directions traced
//! through the unsubdivided scene in f64 with the same transport (the
//! environment where a path escapes, emission, diffuse bounces up to the
//! bake's count), projected onto the SH basis.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use shlight_baked::ProbeGrid;
use shlight_core::sh::{ShCoeffs, closed_form, sh_count, sh_eval};
use shlight_mesh::{Mesh, generate};
use shlight_rays::brute_force_closest_hit as closest_hit;
use shlight_volume::{VolumeOptions, bake};

const BOUNCES: u32 = 2;

struct Tracer<'a> {
    mesh: &'a Mesh,
    sky: &'a ShCoeffs<DVec3>,
}

impl Tracer<'_> {
    /// Radiance arriving at `o` from `d`, having met `surfaces` surfaces
    /// already: a path may meet at most `BOUNCES + 1` (the bake's surfaces
    /// hold direct light plus `BOUNCES` bounces, and emission plus as many).
    fn radiance(&self, o: DVec3, d: DVec3, surfaces: u32, rng: &mut StdRng) -> DVec3 {
        let Some((_, k, u, v)) = closest_hit(self.mesh, o, d, 1e-9) else {
            return self.sky.eval(d);
        };
        let tri = self.mesh.triangles[k];
        let [a, b, c] = tri.map(|i| self.mesh.positions[i as usize].as_dvec3());
        let n = (b - a).cross(c - a).normalize();
        if n.dot(d) >= 0.0 || surfaces > BOUNCES {
            return DVec3::ZERO;
        }
        let at = |values: &[Vec3]| {
            let [x, y, z] = tri.map(|i| values[i as usize].as_dvec3());
            x * (1.0 - u - v) + y * u + z * v
        };
        let albedo = at(self.mesh.colors.as_ref().unwrap());
        let emitted = at(self.mesh.emission.as_ref().unwrap());
        let q = a * (1.0 - u - v) + b * u + c * v + n * 1e-7;
        // Cosine-distributed continuation: the albedo is the whole weight.
        let (r1, r2): (f64, f64) = (rng.random(), rng.random());
        let (t, s) = n.any_orthonormal_pair();
        let (r, phi) = (r1.sqrt(), 2.0 * PI * r2);
        let next = (t * (r * phi.cos()) + s * (r * phi.sin()) + n * (1.0 - r1).max(0.0).sqrt())
            .normalize();
        emitted + albedo * self.radiance(q, next, surfaces + 1, rng)
    }

    fn probe(&self, x: DVec3, lmax: usize, paths: usize, seed: u64) -> ShCoeffs<DVec3> {
        let mut rng = StdRng::seed_from_u64(seed);
        let mut sum = vec![DVec3::ZERO; sh_count(lmax)];
        for _ in 0..paths {
            let z: f64 = rng.random_range(-1.0..1.0);
            let phi: f64 = rng.random_range(0.0..2.0 * PI);
            let r = (1.0 - z * z).sqrt();
            let d = DVec3::new(r * phi.cos(), z, r * phi.sin());
            let l = self.radiance(x, d, 0, &mut rng);
            for (s, y) in sum.iter_mut().zip(sh_eval(lmax, d)) {
                *s += l * y;
            }
        }
        ShCoeffs::from_vec(
            sum.into_iter()
                .map(|s| s * (4.0 * PI / paths as f64))
                .collect(),
        )
        .unwrap()
    }
}

#[test]
fn cornell_box_probes_match_a_path_tracer() {
    let room = generate::cornell_box();
    let lmax = 2;
    // A sky brighter above, coloured, seen through the open front.
    let sky = closed_form::linear_gradient(
        lmax,
        DVec3::new(0.2, 1.0, -0.4).normalize(),
        DVec3::new(0.6, 0.7, 0.9),
        DVec3::splat(0.4),
    );
    let points = [
        Vec3::new(0.278, 0.274, 0.28),
        Vec3::new(0.08, 0.1, 0.45),
        Vec3::new(0.47, 0.45, 0.12),
        Vec3::new(0.3, 0.04, 0.05),
    ];
    let tracer = Tracer {
        mesh: &room,
        sky: &sky,
    };
    let options = VolumeOptions {
        lmax,
        samples: 16384,
        bounces: BOUNCES,
        surface_samples: 2048,
        seed: 1,
        ..VolumeOptions::default()
    };
    for (k, p) in points.iter().enumerate() {
        let grid = ProbeGrid::new([1, 1, 1], *p - 0.001, *p + 0.001).unwrap();
        let volume = bake(Some(&room), &grid, &options, &|_, _, _| {}).unwrap();
        assert!(volume.valid[0]);
        let baked = volume.relight(&sky);
        let reference = tracer.probe(p.as_dvec3(), lmax, 60_000, 7 + k as u64);
        let scale = reference.as_slice()[0].max_element();
        for (i, r) in reference.as_slice().iter().enumerate() {
            let b = Vec3::from_slice(&baked[3 * i..3 * i + 3]).as_dvec3();
            eprintln!("probe {k} coefficient {i}: bake {b:.4} path tracer {r:.4}");
        }
        for (i, r) in reference.as_slice().iter().enumerate() {
            let b = Vec3::from_slice(&baked[3 * i..3 * i + 3]).as_dvec3();
            let tolerance = if i == 0 { 0.03 } else { 0.05 };
            assert!(
                (b - *r).abs().max_element() < tolerance * scale,
                "probe {k} at {p}, coefficient {i}: bake {b} vs path tracer {r}"
            );
        }
    }
}

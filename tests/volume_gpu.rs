//! Irradiance-volume shading on the GPU (`shaders/volume.wgsl`) against the
//! CPU: the interpolation the fragments use, run as a compute pass, equals
//! shlight-volume's `sample` (checked once by hand) followed by
//! shlight-core's irradiance at random points and normals, for lmax 0..4;
//! an invalid probe takes no weight; a volume of higher lmax is shaded to
//! lmax 4.

use glam::{DVec3, Vec3};
use shlight_core::sh_count;
use shlight_gpu::{GpuContext, HEADLESS_FORMAT, Shading, VolumeProbes, VolumeRenderer};
use shlight_volume::{Grid, sample};

use crate::util::gpu_context;

/// GPU (f32, the basis by recurrence) against CPU (f64 sums of the f32
/// probes): each irradiance within this fraction of the largest one among
/// the queries. f32 rounding of sums of some 200 terms of size 1 is a few
/// 1e-6 of the largest; a wrong weight, index or basis function is off by
/// tenths.
const VOLUME_TOL: f64 = 2e-5;

/// A fixed linear congruential sequence (Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    /// A value in `[lo, hi)`.
    fn range(&mut self, r: std::ops::Range<f32>) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let u = (self.0 >> 40) as f32 / (1u64 << 24) as f32;
        r.start + (r.end - r.start) * u
    }
}

struct TestVolume {
    grid: Grid,
    lmax: usize,
    valid: Vec<bool>,
    radiance: Vec<f32>,
}

impl TestVolume {
    fn random(lmax: usize, seed: u64) -> Self {
        let grid = Grid::new(
            [4, 3, 2],
            Vec3::new(-1.0, 0.0, 2.0),
            Vec3::new(3.0, 1.5, 3.0),
        )
        .unwrap();
        let mut rng = Lcg(seed);
        let n = grid.probe_count();
        let radiance = (0..n * sh_count(lmax) * 3)
            .map(|_| rng.range(-1.0f32..1.0))
            .collect();
        // Probes 5 and 17 inside geometry.
        let valid = (0..n).map(|k| k != 5 && k != 17).collect();
        Self {
            grid,
            lmax,
            valid,
            radiance,
        }
    }

    fn probes(&self) -> VolumeProbes<'_> {
        VolumeProbes {
            resolution: self.grid.resolution,
            min: self.grid.min,
            max: self.grid.max,
            lmax: self.lmax,
            valid: &self.valid,
            radiance: &self.radiance,
        }
    }

    /// The CPU's irradiance at `p` facing `n` to `lmax`, `None` when every
    /// probe around `p` is invalid.
    fn cpu(&self, p: Vec3, n: Vec3, lmax: usize) -> Option<DVec3> {
        let l = sample(&self.grid, &self.valid, &self.radiance, self.lmax, p)?;
        Some(shlight_core::irradiance(&l.resized(lmax)).eval(n.as_dvec3()))
    }
}

fn gpu(
    ctx: &GpuContext,
    volume: &TestVolume,
    lmax: usize,
    queries: &[(Vec3, Vec3)],
) -> Vec<[f32; 4]> {
    let renderer = VolumeRenderer::new(ctx, HEADLESS_FORMAT, &volume.probes()).unwrap();
    let shading = Shading {
        lmax,
        ..Shading::default()
    };
    renderer.irradiance_at(ctx, &shading, queries).unwrap()
}

/// Random points in and a little around the grid box, random unit normals.
fn queries(count: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut rng = Lcg(seed);
    (0..count)
        .map(|_| {
            let p = Vec3::new(
                rng.range(-1.5..3.5),
                rng.range(-0.3..1.8),
                rng.range(1.8..3.2),
            );
            let n = loop {
                let v = Vec3::new(
                    rng.range(-1.0..1.0),
                    rng.range(-1.0..1.0),
                    rng.range(-1.0..1.0),
                );
                if v.length() > 0.1 && v.length() < 1.0 {
                    break v.normalize();
                }
            };
            (p, n)
        })
        .collect()
}

#[test]
fn the_cpu_interpolation_matches_a_hand_computation() {
    // Two probes along x at 0.5 and 1.5 (box 0..2): at x = 0.75 the
    // weights are 3/4 and 1/4; with probe 1 invalid, probe 0 alone.
    let grid = Grid::new([2, 1, 1], Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)).unwrap();
    let radiance = [4.0, 8.0, 12.0, 0.0, 4.0, 40.0];
    let got = sample(
        &grid,
        &[true, true],
        &radiance,
        0,
        Vec3::new(0.75, 0.5, 0.5),
    )
    .unwrap();
    assert_eq!(got[0], DVec3::new(3.0, 7.0, 19.0));
    let got = sample(
        &grid,
        &[true, false],
        &radiance,
        0,
        Vec3::new(0.75, 0.5, 0.5),
    )
    .unwrap();
    assert_eq!(got[0], DVec3::new(4.0, 8.0, 12.0));
    assert!(sample(&grid, &[false, false], &radiance, 0, Vec3::splat(0.5)).is_none());
}

#[test]
fn gpu_interpolation_equals_the_cpu_at_random_points() {
    let Some(ctx) = gpu_context("gpu_interpolation_equals_the_cpu_at_random_points") else {
        return;
    };
    let points = queries(500, 11);
    for lmax in 0..=4 {
        let volume = TestVolume::random(lmax, 3 + lmax as u64);
        let got = gpu(&ctx, &volume, lmax, &points);
        let want: Vec<Option<DVec3>> = points
            .iter()
            .map(|&(p, n)| volume.cpu(p, n, lmax))
            .collect();
        let scale = want
            .iter()
            .flatten()
            .map(|e| e.abs().max_element())
            .fold(0.0, f64::max);
        let mut worst = 0.0f64;
        for ((g, w), (p, n)) in got.iter().zip(&want).zip(&points) {
            let w = w.unwrap_or_else(|| panic!("{p}: every probe invalid in the test volume"));
            let err = (Vec3::new(g[0], g[1], g[2]).as_dvec3() - w)
                .abs()
                .max_element()
                / scale;
            worst = worst.max(err);
            assert!(
                err < VOLUME_TOL,
                "lmax {lmax} at {p} facing {n}: GPU {g:?}, CPU {w} ({err:.2e} of {scale})"
            );
            assert!(g[3] > 0.0 && g[3] <= 1.0 + 1e-5, "{g:?}");
        }
        eprintln!("lmax {lmax}: worst {worst:.2e} of the largest irradiance");
    }
}

#[test]
fn an_invalid_probe_takes_no_weight_on_the_gpu() {
    let Some(ctx) = gpu_context("an_invalid_probe_takes_no_weight_on_the_gpu") else {
        return;
    };
    let points = queries(300, 5);
    let plain = TestVolume::random(2, 9);
    // Probe 5 is invalid; give it a huge value: nothing may change.
    let mut huge = TestVolume::random(2, 9);
    let nc = sh_count(2);
    for v in &mut huge.radiance[5 * nc * 3..6 * nc * 3] {
        *v = 1e6;
    }
    let a = gpu(&ctx, &plain, 2, &points);
    let b = gpu(&ctx, &huge, 2, &points);
    assert_eq!(a, b, "an invalid probe's values reached the result");
    // The same probe made valid does change the points around it (so the
    // comparison above can fail).
    huge.valid[5] = true;
    let c = gpu(&ctx, &huge, 2, &points);
    let changed = a.iter().zip(&c).filter(|(x, y)| x != y).count();
    assert!(changed > 10, "only {changed} points changed");
    // Every probe around a point invalid: no light, weight 0.
    let mut dark = TestVolume::random(1, 2);
    dark.valid.iter_mut().for_each(|v| *v = false);
    let d = gpu(&ctx, &dark, 1, &points[..8]);
    assert!(d.iter().all(|x| *x == [0.0; 4]), "{d:?}");
}

#[test]
fn a_volume_above_lmax_4_is_shaded_to_lmax_4() {
    let Some(ctx) = gpu_context("a_volume_above_lmax_4_is_shaded_to_lmax_4") else {
        return;
    };
    let volume = TestVolume::random(6, 21);
    let renderer = VolumeRenderer::new(&ctx, HEADLESS_FORMAT, &volume.probes()).unwrap();
    assert_eq!(renderer.lmax(), 4);
    let points = queries(100, 8);
    let got = gpu(&ctx, &volume, 6, &points);
    for (g, &(p, n)) in got.iter().zip(&points) {
        let want = volume.cpu(p, n, 4).unwrap();
        let err = (Vec3::new(g[0], g[1], g[2]).as_dvec3() - want)
            .abs()
            .max_element();
        assert!(err < 1e-3, "at {p}: GPU {g:?}, CPU to lmax 4 {want}");
    }
}

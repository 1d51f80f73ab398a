//! Monte Carlo projection: unbiasedness against closed forms, honest standard
//! errors, convergence rates, importance sampling in every frame, and
//! bit-for-bit reproducibility.
//!
//! Run: `cargo test --release -p shlight-core --test montecarlo -- --nocapture`
//! (the figures are printed).

use core::f64::consts::PI;

use glam::DVec3;
use shlight_core::map::montecarlo::{
    ImportanceGrid, McEstimate, McOptions, Sampler, SamplerKind, project_montecarlo,
};
use shlight_core::map::{MapOrientation, RadianceMap, equirect_direction, luminance};
use shlight_core::sh::{Frame, ShCoeffs, closed_form};

const RGB: DVec3 = DVec3::new(1.0, 0.5, 0.25);
const LMAX: usize = 4;

fn unit(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z).normalize()
}

/// A test map with its exact coefficients.
struct Case {
    name: &'static str,
    map: Box<dyn Fn(DVec3) -> DVec3 + Sync>,
    exact: ShCoeffs<DVec3>,
}

impl RadianceMap for Case {
    fn radiance(&self, d: DVec3) -> DVec3 {
        (self.map)(d)
    }
}

/// `1 + 0.5 d·a`: smooth, band-limited to degree 1.
fn gradient() -> Case {
    let a = unit(0.48, 0.6, -0.64);
    Case {
        name: "gradient",
        map: Box::new(move |d| RGB * (1.0 + 0.5 * d.dot(a))),
        exact: closed_form::linear_gradient(LMAX, a, RGB, RGB * 0.5),
    }
}

/// Radiance `value` inside a cap of half-angle `half` about `axis` over a
/// uniform sky of `sky`.
fn cap(name: &'static str, axis: DVec3, half: f64, value: f64, sky: f64) -> Case {
    let c = half.cos();
    let mut exact = closed_form::cap(LMAX, axis, half, RGB * value);
    exact += &closed_form::constant(LMAX, RGB * sky);
    Case {
        name,
        map: Box::new(move |d| RGB * (sky + if d.dot(axis) >= c { value } else { 0.0 })),
        exact,
    }
}

fn wide_cap() -> Case {
    cap("cap 40deg", unit(-0.3, 0.5, 0.8), 0.7, 2.0, 0.0)
}

/// A small bright cap over a dim sky: the importance sampler's case.
fn peaked() -> Case {
    cap("peaked", unit(0.6, -0.2, 0.3), 0.15, 40.0, 0.1)
}

fn opts(sampler: Sampler, samples: usize, seed: u64) -> McOptions {
    McOptions {
        lmax: LMAX,
        samples,
        sampler,
        seed,
    }
}

fn run(case: &Case, o: &McOptions) -> McEstimate {
    project_montecarlo(case, o)
}

/// The sampler of `kind`, importance sampling drawing from `grid`.
fn sampler_of(kind: SamplerKind, grid: &ImportanceGrid) -> Sampler {
    match kind {
        SamplerKind::Uniform => Sampler::Uniform,
        SamplerKind::Stratified => Sampler::Stratified,
        SamplerKind::Sobol => Sampler::Sobol,
        SamplerKind::Importance => Sampler::Importance(grid.clone()),
    }
}

fn grid_for(case: &Case, o: MapOrientation) -> ImportanceGrid {
    ImportanceGrid::from_map(case, 128, 64, o)
}

/// Root of the summed squares of channel 0 over all coefficients.
fn norm(c: &ShCoeffs<DVec3>) -> f64 {
    c.as_slice().iter().map(|v| v.x * v.x).sum::<f64>().sqrt()
}

#[test]
fn each_sampler_is_unbiased_within_its_reported_standard_error() {
    let cases = [gradient(), wide_cap(), peaked()];
    for case in &cases {
        let grid = grid_for(case, MapOrientation::default());
        for sampler in SamplerKind::ALL {
            let (mut over3, mut over4, mut checks) = (0, 0, 0);
            for seed in 0..4 {
                let e = run(case, &opts(sampler_of(sampler, &grid), 16384, seed));
                for k in 0..e.coeffs.len() {
                    // The channels are scaled copies: a coefficient counts once,
                    // as its worst channel.
                    let mut z: f64 = 0.0;
                    for ch in 0..3 {
                        let err = (e.coeffs[k][ch] - case.exact[k][ch]).abs();
                        let se = e.std_error[k][ch];
                        assert!(se.is_finite() && se >= 0.0);
                        // Rounding floor for terms that are exactly 0 or constant.
                        let slack = 1e-12 * (1.0 + case.exact[k][ch].abs());
                        z = z.max(err / (se + slack));
                    }
                    checks += 1;
                    over3 += usize::from(z > 3.0);
                    over4 += usize::from(z > 4.0);
                }
            }
            println!(
                "{:>10} {:>10}: {over3} beyond 3 se, {over4} beyond 4 se of {checks}",
                case.name, sampler
            );
            // Expected beyond 3 se: 0.27% (Gaussian) to 0.9% (t, 15 dof), beyond
            // 4 se 0.006% to 0.12%; measured over 200 seeds: 0.1-1.0% and 0-0.2%.
            assert!(over4 <= 1 && over3 <= 5, "{} {sampler}", case.name);
        }
    }
}

#[test]
fn reported_standard_errors_match_the_spread_over_seeds() {
    let seeds = 30;
    for case in [gradient(), wide_cap(), peaked()] {
        let grid = grid_for(&case, MapOrientation::default());
        for sampler in SamplerKind::ALL {
            let runs: Vec<McEstimate> = (0..seeds)
                .map(|s| run(&case, &opts(sampler_of(sampler, &grid), 4096, 1000 + s)))
                .collect();
            let count = runs[0].coeffs.len();
            let (mut var_obs, mut var_rep) = (0.0, 0.0);
            for k in 0..count {
                let mean = runs.iter().map(|r| r.coeffs[k].x).sum::<f64>() / seeds as f64;
                var_obs += runs
                    .iter()
                    .map(|r| (r.coeffs[k].x - mean).powi(2))
                    .sum::<f64>()
                    / (seeds - 1) as f64;
                var_rep +=
                    runs.iter().map(|r| r.std_error[k].x.powi(2)).sum::<f64>() / seeds as f64;
            }
            let ratio = (var_obs / var_rep).sqrt();
            println!(
                "{:>10} {:>10}: observed spread / reported se = {ratio:.3}",
                case.name, sampler
            );
            assert!(
                (0.7..=1.4).contains(&ratio),
                "{} {sampler}: {ratio}",
                case.name
            );
        }
    }
}

/// Least-squares slope of `log y` against `log x`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|&(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn uniform_error_falls_as_inverse_sqrt_n_and_stratified_and_sobol_faster() {
    let case = gradient();
    let sizes = [256, 1024, 4096, 16384, 65536];
    let seeds = 12;
    let mut last = Vec::new();
    for sampler in [Sampler::Uniform, Sampler::Stratified, Sampler::Sobol] {
        let mut pts = Vec::new();
        for &n in &sizes {
            let mut sq = 0.0;
            let mut used = 0;
            for s in 0..seeds {
                let e = run(&case, &opts(sampler.clone(), n, 77 + s));
                used = e.samples;
                sq += norm(&(&e.coeffs - &case.exact)).powi(2);
            }
            pts.push((used as f64, (sq / seeds as f64).sqrt()));
        }
        let k = slope(&pts);
        let rms: Vec<String> = pts.iter().map(|p| format!("{:.2e}", p.1)).collect();
        println!("{sampler:>10}: RMS error {} slope {k:.3}", rms.join(" "));
        match sampler {
            Sampler::Uniform => assert!((-0.6..=-0.4).contains(&k), "uniform slope {k}"),
            _ => assert!(k < -0.6, "{sampler} slope {k}"),
        }
        last.push(pts.last().unwrap().1);
    }
    assert!(last[1] < last[0] && last[2] < last[0], "{last:?}");
}

#[test]
fn importance_sampling_cuts_the_error_on_a_peaked_map_in_every_frame() {
    let case = peaked();
    let uni = run(&case, &opts(Sampler::Uniform, 16384, 5));
    for o in MapOrientation::ALL {
        let grid = grid_for(&case, o);
        let imp = run(&case, &opts(Sampler::Importance(grid.clone()), 16384, 5));
        let ratio = norm(&imp.std_error) / norm(&uni.std_error);
        let err = &imp.coeffs - &case.exact;
        let worst = (0..err.len())
            .map(|k| err[k].x.abs() / imp.std_error[k].x)
            .fold(0.0, f64::max);
        println!(
            "{:>5} mirror {:>5}: se importance / uniform = {ratio:.3}, worst |err|/se {worst:.2}",
            o.frame.to_string(),
            o.mirror
        );
        assert!(ratio < 0.25, "{o:?}: {ratio}");
        assert!(worst < 4.5, "{o:?}: {worst}");
        // Control: the same cell values laid out in the mirrored frame put
        // the light elsewhere (a grid whose geometry disagreed with
        // `equirect_direction` would do the same).
        let (w, h) = (grid.width(), grid.height());
        let lum: Vec<f64> = (0..w * h)
            .map(|k| luminance(case.radiance(equirect_direction(k % w, k / w, w, h, o))))
            .collect();
        let flipped = MapOrientation {
            mirror: !o.mirror,
            ..o
        };
        let wrong = ImportanceGrid::from_cell_luminance(w, h, flipped, &lum);
        let bad = run(&case, &opts(Sampler::Importance(wrong), 16384, 5));
        let bad_ratio = norm(&bad.std_error) / norm(&uni.std_error);
        assert!(bad_ratio > 1.0, "{o:?}: control {bad_ratio}");
    }
}

/// Nearest-texel lookup of an equirect map, from the conventions table
/// (independent of the grid's own inverse).
struct Texels {
    w: usize,
    h: usize,
    px: Vec<[f32; 3]>,
    o: MapOrientation,
}

impl RadianceMap for Texels {
    fn radiance(&self, d: DVec3) -> DVec3 {
        let (t, mut p) = match self.o.frame {
            Frame::YUp => (d.y.clamp(-1.0, 1.0).acos(), d.z.atan2(d.x)),
            Frame::ZUp => (d.z.clamp(-1.0, 1.0).acos(), (-d.y).atan2(d.x)),
        };
        if self.o.mirror {
            p = -p;
        }
        let i = (((p / (2.0 * PI) + 0.5) * self.w as f64) as usize).min(self.w - 1);
        let j = ((t / PI * self.h as f64) as usize).min(self.h - 1);
        DVec3::from(self.px[j * self.w + i].map(f64::from))
    }
}

#[test]
fn importance_grid_from_equirect_texels_matches_the_map_in_every_frame() {
    let (w, h) = (96, 48);
    let sun = unit(-0.2, 0.7, 0.5);
    for o in MapOrientation::ALL {
        let px: Vec<[f32; 3]> = (0..w * h)
            .map(|k| {
                let d = equirect_direction(k % w, k / w, w, h, o);
                let v = if d.dot(sun) > 0.12f64.cos() {
                    30.0
                } else {
                    0.05
                };
                [v, 0.8 * v, 0.6 * v]
            })
            .collect();
        let grid = ImportanceGrid::from_equirect(w, h, &px, o);
        let map = Texels { w, h, px, o };
        let o_uni = McOptions {
            lmax: 3,
            samples: 8192,
            sampler: Sampler::Uniform,
            seed: 9,
        };
        let o_imp = McOptions {
            sampler: Sampler::Importance(grid),
            ..o_uni.clone()
        };
        let uni = project_montecarlo(&map, &o_uni);
        let imp = project_montecarlo(&map, &o_imp);
        let ratio = norm(&imp.std_error) / norm(&uni.std_error);
        // Both are unbiased for the same texel map: they agree within the errors.
        let mut worst: f64 = 0.0;
        for k in 0..imp.coeffs.len() {
            let se = imp.std_error[k].x.hypot(uni.std_error[k].x);
            worst = worst.max((imp.coeffs[k].x - uni.coeffs[k].x).abs() / se);
        }
        println!(
            "{:>5} mirror {:>5}: from_equirect se ratio {ratio:.4}, worst |diff|/se {worst:.2}",
            o.frame.to_string(),
            o.mirror
        );
        assert!(ratio < 0.2, "{o:?}: {ratio}");
        assert!(worst < 4.5, "{o:?}: {worst}");
        // Control: the same texels read in the other frame miss the sun.
        let other = MapOrientation {
            frame: if o.frame == Frame::YUp {
                Frame::ZUp
            } else {
                Frame::YUp
            },
            ..o
        };
        let wrong = ImportanceGrid::from_equirect(w, h, &map.px, other);
        let o_bad = McOptions {
            sampler: Sampler::Importance(wrong),
            ..o_uni.clone()
        };
        let bad = project_montecarlo(&map, &o_bad);
        let bad_ratio = norm(&bad.std_error) / norm(&uni.std_error);
        assert!(bad_ratio > 1.0, "{o:?}: control {bad_ratio}");
    }
}

#[test]
fn results_repeat_for_a_seed_and_differ_between_seeds() {
    let case = wide_cap();
    let grid = grid_for(&case, MapOrientation::default());
    for sampler in SamplerKind::ALL {
        let a = run(&case, &opts(sampler_of(sampler, &grid), 5000, 42));
        let b = run(&case, &opts(sampler_of(sampler, &grid), 5000, 42));
        let c = run(&case, &opts(sampler_of(sampler, &grid), 5000, 43));
        assert_eq!(a, b, "{sampler}");
        assert_ne!(a.coeffs, c.coeffs, "{sampler}");
        assert_eq!(a.samples, c.samples);
    }
}

#[cfg(feature = "rayon")]
#[test]
fn results_are_identical_with_one_and_two_threads() {
    let case = peaked();
    let grid = grid_for(&case, MapOrientation::default());
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    for sampler in SamplerKind::ALL {
        // Enough chunks (2048 points each) that the split really differs.
        let o = opts(sampler_of(sampler, &grid), 40_000, 11);
        let one = pool(1).install(|| run(&case, &o));
        let two = pool(2).install(|| run(&case, &o));
        let three = pool(3).install(|| run(&case, &o));
        assert_eq!(one, two, "{sampler}");
        assert_eq!(one, three, "{sampler}");
    }
}

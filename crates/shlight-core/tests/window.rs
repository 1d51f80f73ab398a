//! Windows against ringing: factor values, the CLI spelling, the automatic
//! window (non-negative, and the weakest such) and the sphere minimum search.
//!
//! The main oracle is a directional light `L_l^m = Y_l^m(d)` (unit
//! irradiance from `d`), whose truncated expansions ring. Because it is zonal
//! about `d`, every windowed version has the closed form
//! `g(n) = sum_l a_l w_l (2l+1)/(4 pi) P_l(n . d)` (addition theorem, with
//! `a_l = A_l` for irradiance, 1 for radiance), which gives a 1-D check
//! independent of the basis evaluator; a 200k-point Fibonacci check with the
//! basis evaluator is run as well.

use std::f64::consts::PI;
use std::time::Instant;

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use shlight_core::sh::{
    AUTO_WINDOW_MARGIN, AutoWindow, AutoWindowError, ParseWindowErrorKind, ShBasis, ShCoeffs,
    Window, WindowFamily, WindowTarget, auto_window, clamped_cosine_eigenvalue, fibonacci_sphere,
    irradiance, legendre_polynomials, sh_eval, sh_index, sphere_minimum, zonal_to_sh,
};

/// Factor formulas vs hand values: a few ulps of numbers of order 1.
const FACTOR_TOL: f64 = 1e-15;
/// `min_before` vs the independent 1-D scan of the zonal form: the scan's
/// step in angle is `pi / 1e5`, so it overestimates the minimum by at most
/// `curvature * (1.6e-5)^2 / 2`, below `1e-9` for these functions of size ~1.
const MIN_AGREEMENT: f64 = 1e-8;
/// Points of the independent Fibonacci check.
const DENSE_POINTS: usize = 200_000;
/// Samples of `n . d` in the 1-D zonal check (uniform in angle, ends included).
const ZONAL_SAMPLES: usize = 100_001;
/// How much weaker than the chosen window must already fail (2%).
const WEAKER: f64 = 1.02;
/// `sphere_minimum` vs a great-circle scan refined by golden section; both
/// resolve the minimum to rounding of values of order 1.
const SPHERE_MIN_TOL: f64 = 1e-10;
/// Position of the minimum: the value pins it only to
/// `sqrt(value error / curvature)`, about `1e-7` here.
const ARGMIN_TOL: f64 = 1e-5;

const FAMILIES: [WindowFamily; 3] = [
    WindowFamily::Hanning,
    WindowFamily::Lanczos,
    WindowFamily::Laplacian,
];

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The light direction: off every axis.
fn light_dir() -> [f64; 3] {
    normalize([0.31, -0.52, 0.79])
}

/// A directional light of unit irradiance from `d`: `L_l^m = Y_l^m(d)`.
fn directional(lmax: usize, d: [f64; 3]) -> ShCoeffs<f64> {
    ShCoeffs::from_vec(sh_eval(lmax, glam::DVec3::from(d))).unwrap()
}

/// `1 / (2 sqrt(pi))`.
fn y00() -> f64 {
    0.5 / PI.sqrt()
}

/// Minimum over a Fibonacci set plus extra points of windowed versions of
/// one expansion, with per-degree sums computed once by `ShBasis::eval`.
struct DenseCheck {
    lmax: usize,
    points: usize,
    /// `bands[l * points + p] = sum_m t_l^m Y_l^m(p)`.
    bands: Vec<f64>,
}

impl DenseCheck {
    fn new(t: &ShCoeffs<f64>, n: usize, extra: &[[f64; 3]]) -> Self {
        let lmax = t.lmax();
        let mut dirs = fibonacci_sphere(n);
        dirs.extend(extra.iter().map(|&d| glam::DVec3::from(d)));
        let points = dirs.len();
        let basis = ShBasis::<f64>::new(lmax);
        let mut y = vec![0.0; basis.count()];
        let mut bands = vec![0.0; (lmax + 1) * points];
        for (p, d) in dirs.iter().enumerate() {
            basis.eval(*d, &mut y);
            for l in 0..=lmax {
                let s: f64 = (l * l..(l + 1) * (l + 1)).map(|i| t[i] * y[i]).sum();
                bands[l * points + p] = s;
            }
        }
        Self {
            lmax,
            points,
            bands,
        }
    }

    fn min(&self, window: &Window) -> f64 {
        let n = self.points;
        let mut v = vec![0.0; n];
        for l in 0..=self.lmax {
            let w = window.factor(l);
            for (v, b) in v.iter_mut().zip(&self.bands[l * n..(l + 1) * n]) {
                *v += w * b;
            }
        }
        v.into_iter().fold(f64::INFINITY, f64::min)
    }
}

/// Minimum over `n . d` of `sum_l a_l w_l (2l+1)/(4 pi) P_l(n . d)`: the zonal
/// closed form of a windowed directional light (ends `n = d` and `n = -d`
/// included).
fn zonal_min(lmax: usize, target: WindowTarget, window: &Window) -> f64 {
    zonal_min_with_sky(lmax, target, window, 0.0, ZONAL_SAMPLES)
}

/// As [`zonal_min`], for the light plus a uniform sky of radiance `sky`
/// (which adds `pi sky` to irradiance, `sky` to radiance), on `samples`
/// values of the angle.
fn zonal_min_with_sky(
    lmax: usize,
    target: WindowTarget,
    window: &Window,
    sky: f64,
    samples: usize,
) -> f64 {
    let (weights, constant): (Vec<f64>, f64) = match target {
        WindowTarget::Function => ((0..=lmax).map(|_| 1.0).collect(), sky),
        WindowTarget::Irradiance => (
            (0..=lmax).map(clamped_cosine_eigenvalue).collect(),
            PI * sky,
        ),
    };
    let weights: Vec<f64> = weights
        .iter()
        .enumerate()
        .map(|(l, a)| a * window.factor(l) * (2 * l + 1) as f64 / (4.0 * PI))
        .collect();
    (0..samples)
        .map(|k| {
            let t = PI * k as f64 / (samples - 1) as f64;
            let x = if k == samples - 1 { -1.0 } else { t.cos() };
            let p = legendre_polynomials(lmax, x);
            constant + weights.iter().zip(&p).map(|(w, p)| w * p).sum::<f64>()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The same window with its parameter made weaker by `WEAKER`.
fn weaker(window: &Window) -> Window {
    let (family, p) = window.family().expect("a window");
    match family {
        WindowFamily::Hanning | WindowFamily::Lanczos => family.window(p * WEAKER),
        WindowFamily::Laplacian => family.window(p / WEAKER),
    }
}

/// Checks one auto window of a directional light independently: the windowed
/// target is non-negative on the dense set and in the 1-D form, the margin is
/// met, and (when a window was needed) a 2% weaker one fails.
fn check_auto(
    auto: &AutoWindow,
    lmax: usize,
    target: WindowTarget,
    dense: &DenseCheck,
    mean: f64,
    label: &str,
) {
    let after = dense
        .min(&auto.window)
        .min(zonal_min(lmax, target, &auto.window));
    assert!(
        after >= 0.0,
        "{label}: {} leaves minimum {after:e}",
        auto.window
    );
    assert!(
        auto.min_after >= AUTO_WINDOW_MARGIN * mean,
        "{label}: reported min_after {:e} below the margin",
        auto.min_after
    );
    if auto.window != Window::None {
        let weak = weaker(&auto.window);
        let weak_min = dense.min(&weak).min(zonal_min(lmax, target, &weak));
        assert!(
            weak_min < 0.0,
            "{label}: {} is not the weakest: {weak} still has minimum {weak_min:e}",
            auto.window
        );
    }
}

#[test]
fn factors_take_their_defining_values() {
    for w in [0.5, 1.0, 4.0, 4.5, 17.25] {
        for window in [Window::Hanning { w }, Window::Lanczos { w }] {
            assert_eq!(window.factor(0), 1.0, "{window}");
            for l in 1..40usize {
                let f = window.factor(l);
                if l as f64 >= w {
                    assert_eq!(f, 0.0, "{window} l={l}");
                } else {
                    assert!(f > 0.0 && f < 1.0, "{window} l={l}: {f}");
                }
            }
        }
    }
    // Half width: Hanning (1 + cos(pi/2))/2 = 1/2, Lanczos sin(pi/2)/(pi/2) = 2/pi.
    assert!((Window::Hanning { w: 6.0 }.factor(3) - 0.5).abs() < FACTOR_TOL);
    assert!((Window::Lanczos { w: 6.0 }.factor(3) - 2.0 / PI).abs() < FACTOR_TOL);
    // Hanning at l = w/3: (1 + 1/2)/2.
    assert!((Window::Hanning { w: 6.0 }.factor(2) - 0.75).abs() < FACTOR_TOL);
    let lap = Window::Laplacian { lambda: 0.25 };
    assert_eq!(lap.factor(0), 1.0);
    assert!((lap.factor(1) - 0.5).abs() < FACTOR_TOL); // 1 / (1 + 0.25 * 4)
    assert!((lap.factor(3) - 1.0 / 37.0).abs() < FACTOR_TOL); // 1 / (1 + 0.25 * 144)
    assert_eq!(Window::Laplacian { lambda: 0.0 }.factor(50), 1.0);
    assert!((0..100).all(|l| Window::None.factor(l) == 1.0));
    assert_eq!(lap.factors(3).len(), 4);
}

#[test]
fn apply_scales_each_degree_for_scalars_and_rgb() {
    let f = ShCoeffs::<f64>::from_fn(5, |l, m| 1.0 + l as f64 + 0.1 * m as f64);
    let rgb = f.splat_rgb::<glam::DVec3>();
    for window in [
        Window::None,
        Window::Hanning { w: 4.5 },
        Window::Lanczos { w: 3.0 },
        Window::Laplacian { lambda: 0.01 },
    ] {
        let g = window.apply(&f);
        let h = window.apply(&rgb);
        for l in 0..=5usize {
            for m in -(l as isize)..=l as isize {
                let want = window.factor(l) * f[(l, m)];
                assert!((g[(l, m)] - want).abs() <= FACTOR_TOL * want.abs());
                assert!((h[(l, m)] - glam::DVec3::splat(want)).abs().max_element() < 1e-14);
            }
        }
    }
}

#[test]
fn display_and_parse_round_trip() {
    for window in [
        Window::None,
        Window::Hanning { w: 6.0 },
        Window::Hanning {
            w: 17.123456789012345,
        },
        Window::Lanczos { w: 0.1 },
        Window::Laplacian { lambda: 0.0 },
        Window::Laplacian { lambda: 3.7e-9 },
    ] {
        let s = window.to_string();
        assert_eq!(s.parse::<Window>().unwrap(), window, "{s}");
    }
    assert_eq!(Window::Lanczos { w: 9.5 }.to_string(), "lanczos:9.5");
    assert_eq!(
        Window::Laplacian { lambda: 0.5 }.to_string(),
        "laplacian:0.5"
    );
    assert_eq!(
        " Hanning:4 ".parse::<Window>().unwrap(),
        Window::Hanning { w: 4.0 }
    );
    assert_eq!("NONE".parse::<Window>().unwrap(), Window::None);
    for family in FAMILIES {
        assert_eq!(family.to_string().parse::<WindowFamily>().unwrap(), family);
    }
}

#[test]
fn bad_window_strings_give_clear_errors() {
    use ParseWindowErrorKind as K;
    let cases = [
        ("", K::Empty),
        ("  ", K::Empty),
        ("hamming:4", K::UnknownFamily),
        ("gauss", K::UnknownFamily),
        ("hanning", K::MissingParameter),
        ("lanczos:", K::MissingParameter),
        ("none:3", K::UnexpectedParameter),
        ("hanning:four", K::BadNumber),
        ("laplacian:1e", K::BadNumber),
        ("hanning:0", K::OutOfRange),
        ("lanczos:-2", K::OutOfRange),
        ("lanczos:inf", K::OutOfRange),
        ("hanning:NaN", K::OutOfRange),
        ("laplacian:-0.1", K::OutOfRange),
        ("auto", K::Auto),
        ("auto:hanning", K::Auto),
    ];
    for (s, kind) in cases {
        let err = s.parse::<Window>().expect_err(s);
        assert_eq!(err.kind(), kind, "{s:?}: {err}");
        let msg = err.to_string();
        assert!(!msg.is_empty() && msg.contains(s.trim()), "{s:?}: {msg}");
        let _: &dyn std::error::Error = &err;
    }
    assert!(
        "auto"
            .parse::<Window>()
            .unwrap_err()
            .to_string()
            .contains("auto_window")
    );
    assert_eq!(
        "cosine".parse::<WindowFamily>().unwrap_err().kind(),
        K::UnknownFamily
    );
}

#[test]
fn nine_term_irradiance_minimum_is_minus_19_over_480() {
    // E2 = 1/4 + c/2 + (5/32)(3c^2 - 1) is lowest at c = -8/15 with value -19/480
    // (not at the antipode, where it is +1/16).
    let d = light_dir();
    let e = irradiance(&directional(2, d));
    let (min, at) = sphere_minimum(&e);
    assert!((min + 19.0 / 480.0).abs() < 1e-13, "{min}");
    assert!(
        (dot(at.to_array(), d) + 8.0 / 15.0).abs() < ARGMIN_TOL,
        "{at:?}"
    );
    let auto = auto_window(
        &directional(2, d),
        WindowFamily::Hanning,
        WindowTarget::Irradiance,
    )
    .unwrap();
    assert!((auto.min_before + 19.0 / 480.0).abs() < 1e-13);
    assert!((dot(auto.argmin_before.to_array(), d) + 8.0 / 15.0).abs() < ARGMIN_TOL);
}

#[test]
fn auto_window_makes_directional_irradiance_non_negative_lmax_2_to_16() {
    let d = light_dir();
    let antipode = [-d[0], -d[1], -d[2]];
    let mut negative = Vec::new();
    println!("lmax  family     min_before       window                 min_after   ms");
    for lmax in 2..=16 {
        let f = directional(lmax, d);
        let e = irradiance(&f);
        let mean = e[0] * y00();
        let dense = DenseCheck::new(&e, DENSE_POINTS, &[antipode, d]);
        let zonal_before = zonal_min(lmax, WindowTarget::Irradiance, &Window::None);
        let before = dense.min(&Window::None).min(zonal_before);
        if before < 0.0 {
            negative.push(lmax);
        }
        for family in FAMILIES {
            let label = format!("lmax {lmax} {family}");
            let t0 = Instant::now();
            let auto = auto_window(&f, family, WindowTarget::Irradiance).unwrap();
            let ms = t0.elapsed().as_secs_f64() * 1e3;
            println!(
                "{lmax:4}  {family:9} {:+.9e}  {:22} {:+.3e}  {ms:.0}",
                auto.min_before,
                auto.window.to_string(),
                auto.min_after
            );
            assert!(
                (auto.min_before - zonal_before).abs() < MIN_AGREEMENT,
                "{label}: min_before {} vs 1-D scan {zonal_before}",
                auto.min_before
            );
            assert!(auto.min_before <= before + MIN_AGREEMENT, "{label}");
            if before < 0.0 {
                assert!(auto.min_before < 0.0, "{label}");
                assert_eq!(
                    auto.window.family().map(|(f, _)| f),
                    Some(family),
                    "{label}"
                );
            } else {
                assert_eq!(auto.window, Window::None, "{label}");
            }
            check_auto(&auto, lmax, WindowTarget::Irradiance, &dense, mean, &label);
        }
    }
    println!("negative before windowing at lmax {negative:?}");
    // The 9-term minimum is -19/480, so lmax 2 (and 3, since A_3 = 0) must be negative.
    assert!(
        negative.contains(&2) && negative.contains(&3),
        "{negative:?}"
    );
}

/// Feasible Hanning widths need not form one interval: for a sun over a dim
/// sky they are about (2, 2.03) and (9.7, 16.3) at lmax 8 (sky 0.002), and
/// (2, 2.016) and (16.4, 33.7) at lmax 16 (sky 0.001), failing at `lmax + 1`.
/// The search must find the upper range, and nothing weaker may pass.
#[test]
fn auto_window_finds_the_weakest_of_separate_feasible_ranges() {
    let d = normalize([0.0, 0.6, 0.8]);
    let target = WindowTarget::Irradiance;
    for (lmax, sky, above) in [(8usize, 0.002, 9.5), (16, 0.001, 16.0)] {
        let mut f = directional(lmax, d);
        f[0] += sky * 2.0 * PI.sqrt();
        let auto = auto_window(&f, WindowFamily::Hanning, target).unwrap();
        println!("lmax {lmax} sky {sky}: {}", auto.window);
        let Window::Hanning { w } = auto.window else {
            panic!("{}", auto.window)
        };
        assert!(
            w > above,
            "lmax {lmax}: stopped in the lower range at w = {w}"
        );
        let at =
            |w: f64| zonal_min_with_sky(lmax, target, &Window::Hanning { w }, sky, ZONAL_SAMPLES);
        assert!(at(w) >= 0.0, "lmax {lmax}: w = {w} leaves {:e}", at(w));
        assert!(at(w * WEAKER) < 0.0, "lmax {lmax}: w * 1.02 still passes");
        // Sweep every weaker width up to 8 (lmax + 1) on a coarse grid of
        // angles (which can only overestimate the minimum), confirming any
        // apparent pass on the fine grid.
        let mut v = w * WEAKER;
        while v < 8.0 * (lmax + 1) as f64 {
            let coarse = zonal_min_with_sky(lmax, target, &Window::Hanning { w: v }, sky, 2001);
            assert!(
                coarse < 0.0 || at(v) < 0.0,
                "lmax {lmax}: weaker w = {v} passes"
            );
            v *= 1.005;
        }
    }
}

#[test]
fn auto_window_makes_truncated_radiance_non_negative() {
    let d = normalize([-0.7, 0.2, -0.4]);
    let lmax = 8;
    let f = directional(lmax, d);
    let mean = f[0] * y00();
    let dense = DenseCheck::new(&f, DENSE_POINTS, &[[-d[0], -d[1], -d[2]], d]);
    let before =
        dense
            .min(&Window::None)
            .min(zonal_min(lmax, WindowTarget::Function, &Window::None));
    assert!(
        before < 0.0,
        "the truncated delta rings below zero: {before}"
    );
    for family in FAMILIES {
        let auto = auto_window(&f, family, WindowTarget::Function).unwrap();
        assert!(auto.min_before < 0.0 && (auto.min_before - before).abs() < MIN_AGREEMENT);
        assert_ne!(auto.window, Window::None);
        check_auto(
            &auto,
            lmax,
            WindowTarget::Function,
            &dense,
            mean,
            &format!("radiance {family}"),
        );
    }
}

#[test]
fn non_negative_input_gets_no_window() {
    // Radiance 1 + 0.3 sqrt(3/(4 pi)) (n . a): positive everywhere.
    let a = normalize([0.2, 0.9, -0.1]);
    let y = sh_eval(1, glam::DVec3::from(a));
    let mut f = ShCoeffs::<f64>::zeros(1);
    f[0] = 2.0 * PI.sqrt();
    for i in 1..4 {
        f[i] = 0.3 * (4.0 * PI / 3.0).sqrt() * y[i];
    }
    let want = 1.0 - 0.3 * (3.0 / (4.0 * PI)).sqrt();
    for target in [WindowTarget::Function, WindowTarget::Irradiance] {
        for family in FAMILIES {
            let auto = auto_window(&f, family, target).unwrap();
            assert_eq!(auto.window, Window::None);
            assert_eq!(auto.min_after, auto.min_before);
            assert!(auto.min_before > 0.0);
        }
    }
    let auto = auto_window(&f, WindowFamily::Hanning, WindowTarget::Function).unwrap();
    assert!(
        (auto.min_before - want).abs() < 1e-13,
        "{}",
        auto.min_before
    );
    assert!(dot(auto.argmin_before.to_array(), a) < -1.0 + 1e-12);
    // The zero function is non-negative too.
    let zero = ShCoeffs::<f64>::zeros(4);
    let auto = auto_window(&zero, WindowFamily::Lanczos, WindowTarget::Function).unwrap();
    assert_eq!(auto.window, Window::None);
}

#[test]
fn non_positive_mean_is_an_error() {
    let mut f = ShCoeffs::<f64>::zeros(2);
    f[sh_index(1, 0)] = 1.0;
    for c00 in [0.0, -0.5] {
        f[0] = c00;
        for family in FAMILIES {
            let err = auto_window(&f, family, WindowTarget::Function).unwrap_err();
            let AutoWindowError::NonPositiveMean { mean, min, .. } = err else {
                panic!("{err}")
            };
            assert!(mean <= 0.0 && min < 0.0);
            assert!(err.to_string().contains("no window"));
        }
    }
}

/// Golden-section minimum of `g` on `[a, b]` (unimodal there).
fn golden(mut a: f64, mut b: f64, mut g: impl FnMut(f64) -> f64) -> (f64, f64) {
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let mut c = b - r * (b - a);
    let mut d = a + r * (b - a);
    let (mut gc, mut gd) = (g(c), g(d));
    while b - a > 1e-12 {
        if gc < gd {
            b = d;
            d = c;
            gd = gc;
            c = b - r * (b - a);
            gc = g(c);
        } else {
            a = c;
            c = d;
            gc = gd;
            d = a + r * (b - a);
            gd = g(d);
        }
    }
    let t = 0.5 * (a + b);
    (g(t), t)
}

#[test]
fn sphere_minimum_finds_the_minimum_of_a_rotated_zonal_function() {
    let mut rng = StdRng::seed_from_u64(2008);
    for (case, lmax) in [3usize, 6, 9, 12, 16, 24].into_iter().enumerate() {
        let h: Vec<f64> = (0..=lmax)
            .map(|l| rng.random_range(-1.0..1.0) / (1.0 + l as f64))
            .collect();
        let axis = normalize([
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        ]);
        let f = zonal_to_sh(&h, glam::DVec3::from(axis));
        let (min, at) = sphere_minimum(&f);

        // The great circle through the axis: cos(t) axis + sin(t) u.
        let u = normalize([axis[1], -axis[0], 0.0]);
        let basis = ShBasis::<f64>::new(lmax);
        let circle = |t: f64| {
            let (s, c) = t.sin_cos();
            let d = [
                c * axis[0] + s * u[0],
                c * axis[1] + s * u[1],
                c * axis[2] + s * u[2],
            ];
            let mut y = vec![0.0; basis.count()];
            f.eval_with(&basis, glam::DVec3::from(d), &mut y)
        };
        let n = 20_000;
        let step = 2.0 * PI / n as f64;
        let k = (0..n)
            .min_by(|&a, &b| circle(a as f64 * step).total_cmp(&circle(b as f64 * step)))
            .unwrap();
        let t0 = k as f64 * step;
        let (scan_min, t_min) = golden(t0 - step, t0 + step, circle);

        assert!(
            (min - scan_min).abs() < SPHERE_MIN_TOL,
            "case {case} lmax {lmax}: sphere_minimum {min} vs great circle {scan_min}"
        );
        // The value returned is the value at the point returned.
        assert!((f.eval(at) - min).abs() < 1e-14);
        // The polar angle of the argmin (the minimum is a ring about the axis
        // or a pole) matches the scan's.
        let polar = dot(at.to_array(), axis).clamp(-1.0, 1.0).acos();
        let t_fold = {
            let t = t_min.rem_euclid(2.0 * PI);
            if t > PI { 2.0 * PI - t } else { t }
        };
        assert!(
            (polar - t_fold).abs() < ARGMIN_TOL,
            "case {case}: polar angle {polar} vs {t_fold}"
        );
    }
}

/// Polar coordinates about `axis`: the unit vector at polar angle `t`,
/// azimuth `p`, with azimuth 0 along `u` (a unit vector orthogonal to `axis`).
fn polar(axis: [f64; 3], u: [f64; 3], t: f64, p: f64) -> [f64; 3] {
    let v = [
        axis[1] * u[2] - axis[2] * u[1],
        axis[2] * u[0] - axis[0] * u[2],
        axis[0] * u[1] - axis[1] * u[0],
    ];
    let (st, ct) = t.sin_cos();
    let (sp, cp) = p.sin_cos();
    std::array::from_fn(|i| ct * axis[i] + st * (cp * u[i] + sp * v[i]))
}

/// A nearly zonal function has a long, curved, nearly flat valley (a ring)
/// where a local search on the sphere converges slowly; in polar coordinates
/// about the axis the valley is a coordinate line, so a grid in (t, p) plus
/// alternating golden-section searches is an independent reference. The
/// perturbed lmax 16 irradiance case failed (by 4e-9) with a Newton iteration
/// whose Hessian came from the gradient's narrow stencil.
#[test]
fn sphere_minimum_follows_the_nearly_flat_ring_of_a_nearly_zonal_function() {
    let mut rng = StdRng::seed_from_u64(33);
    let mut rings = 0;
    // (lmax, perturbation, irradiance of a directional light or random zonal)
    let cases = [
        (8usize, 1e-3, false),
        (12, 1e-5, false),
        (20, 1e-4, false),
        (8, 1e-6, true),
        (16, 1e-7, true),
        (32, 1e-6, true),
    ];
    for (lmax, eps, light) in cases {
        let axis = normalize([0.3, -0.8, 0.4]);
        let mut f = if light {
            irradiance(&directional(lmax, axis))
        } else {
            let h: Vec<f64> = (0..=lmax)
                .map(|l| rng.random_range(-1.0..1.0) / (1.0 + l as f64))
                .collect();
            zonal_to_sh(&h, glam::DVec3::from(axis))
        };
        for c in f.as_mut_slice() {
            *c += eps * rng.random_range(-1.0..1.0);
        }
        let (min, _) = sphere_minimum(&f);

        let u = normalize([axis[1], -axis[0], 0.0]);
        let basis = ShBasis::<f64>::new(lmax);
        let mut y = vec![0.0; basis.count()];
        let mut at =
            |t: f64, p: f64| f.eval_with(&basis, glam::DVec3::from(polar(axis, u, t, p)), &mut y);
        let (nt, np) = (400, 800);
        let (dt, dp) = (PI / nt as f64, 2.0 * PI / np as f64);
        let (mut t0, mut p0, mut best) = (0.0, 0.0, f64::INFINITY);
        for i in 0..=nt {
            for j in 0..np {
                let (t, p) = (i as f64 * dt, j as f64 * dp);
                let v = at(t, p);
                if v < best {
                    (t0, p0, best) = (t, p, v);
                }
            }
        }
        // Near a pole of the chart (a point minimum on the axis) the polar
        // coordinates degenerate: continue in a chart whose axis is `u`.
        println!("lmax {lmax} eps {eps}: minimum at polar angle {t0:.4} about the axis");
        let (chart, chart_u) = if t0.sin() < 0.3 {
            let d = polar(axis, u, t0, p0);
            // The chart's second tangent axis, u x axis (as in `polar`).
            let w = [
                u[1] * axis[2] - u[2] * axis[1],
                u[2] * axis[0] - u[0] * axis[2],
                u[0] * axis[1] - u[1] * axis[0],
            ];
            t0 = dot(d, u).clamp(-1.0, 1.0).acos();
            p0 = dot(d, w).atan2(dot(d, axis));
            (u, axis)
        } else {
            rings += 1;
            (axis, u)
        };
        let mut at = |t: f64, p: f64| {
            f.eval_with(
                &basis,
                glam::DVec3::from(polar(chart, chart_u, t, p)),
                &mut y,
            )
        };
        for _ in 0..200 {
            let (_, t) = golden(t0 - 2.0 * dt, t0 + 2.0 * dt, |t| at(t, p0));
            t0 = t;
            let (v, p) = golden(p0 - 2.0 * dp, p0 + 2.0 * dp, |p| at(t0, p));
            p0 = p;
            best = best.min(v);
        }
        assert!(
            (min - best).abs() < SPHERE_MIN_TOL,
            "lmax {lmax} eps {eps}: sphere_minimum {min} vs polar search {best} ({:e})",
            min - best
        );
    }
    assert!(rings >= 2, "the cases should exercise ring minima");
}

#[test]
fn auto_window_works_at_lmax_32() {
    let d = light_dir();
    let lmax = 32;
    let f = directional(lmax, d);
    let e = irradiance(&f);
    let mean = e[0] * y00();
    let dense = DenseCheck::new(&e, 50_000, &[[-d[0], -d[1], -d[2]], d]);
    for family in FAMILIES {
        let t0 = Instant::now();
        let auto = auto_window(&f, family, WindowTarget::Irradiance).unwrap();
        println!(
            "lmax 32 {family}: min_before {:+.6e}, {}, min_after {:+.3e}, {:.0} ms",
            auto.min_before,
            auto.window,
            auto.min_after,
            t0.elapsed().as_secs_f64() * 1e3
        );
        let zonal_before = zonal_min(lmax, WindowTarget::Irradiance, &Window::None);
        assert!((auto.min_before - zonal_before).abs() < MIN_AGREEMENT);
        check_auto(
            &auto,
            lmax,
            WindowTarget::Irradiance,
            &dense,
            mean,
            &format!("lmax 32 {family}"),
        );
    }
}

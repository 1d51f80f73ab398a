//! Accuracy of SH irradiance against analytic irradiance (issue 4):
//! `shlight accuracy` (its rows checked against the bounds and rates the
//! suite states), the published 9-term figures, the bundled real maps
//! against brute-force irradiance, and `shlight irradiance`.

use std::f64::consts::PI;
use std::path::Path;

use glam::DVec3;
use shlight_accuracy::error::relative_to_peak;
use shlight_accuracy::oracle::{Oracle, Shape, unit};
use shlight_core::map::{
    EnvMap, Layout, MapOrientation, equirect_direction, irradiance_brute_force, luminance,
    project_map,
};
use shlight_core::sh::fibonacci_sphere;
use shlight_io::{ReadOptions, read_image};

use crate::util::{s, shlight, shlight_err, shlight_ok, temp_dir};

/// `shlight accuracy --quick --json`, parsed (the run must exit 0).
fn quick_rows() -> Vec<serde_json::Value> {
    let out = shlight(&["accuracy", "--quick", "--json"]);
    assert!(
        out.status.success(),
        "shlight accuracy --quick failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON rows");
    v.as_array().expect("an array").clone()
}

fn f(row: &serde_json::Value, key: &str) -> f64 {
    row[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} in {row}"))
}

fn text<'a>(row: &'a serde_json::Value, key: &str) -> &'a str {
    row[key]
        .as_str()
        .unwrap_or_else(|| panic!("{key} in {row}"))
}

/// One run of the quick suite, checked row by row against what the issue
/// asks: every row within its bound, band-limited oracles to 1e-6,
/// quadrature error falling as W^-2, Monte Carlo as N^-1/2 (uniform,
/// importance) or faster (stratified, Sobol), inside 3 reported standard
/// errors, and the directional light's published 9-term figures.
#[test]
fn accuracy_quick_json_rows_meet_their_bounds_and_rates() {
    let rows = quick_rows();
    let required = [
        "case",
        "method",
        "lmax",
        "mean_rel_err",
        "max_rel_err",
        "bound",
        "pass",
    ];
    for row in &rows {
        for key in required {
            assert!(row.get(key).is_some(), "{key} missing in {row}");
        }
        assert_eq!(row["pass"], true, "failed row {row}");
        if !row["bound"].is_null() {
            assert!(f(row, "max_rel_err") <= f(row, "bound"), "{row}");
        }
    }
    let find = |case: &str, method: &str| -> Vec<&serde_json::Value> {
        rows.iter()
            .filter(|r| text(r, "case") == case && text(r, "method") == method)
            .collect()
    };

    // Every renderable oracle by both quadratures, truncation for all.
    for case in [
        "sphere",
        "hemisphere",
        "cap10-el50",
        "cap30-el10",
        "cap60-el45",
        "cap120-el-20",
        "rect",
        "quad-horizon",
        "sky-gradient",
    ] {
        for method in ["truncation", "quadrature-equirect", "quadrature-cross"] {
            assert!(!find(case, method).is_empty(), "{case} {method}");
        }
    }
    assert!(!find("directional", "truncation").is_empty());

    // Band-limited oracles: their SH irradiance is exact from their band
    // on (truncation at rounding level), and the cube rule projects the
    // polynomial ones exactly (f32 rounding only).
    for (case, band) in [("sphere", 0), ("hemisphere", 1), ("sky-gradient", 1)] {
        for r in find(case, "truncation") {
            if r["lmax"].as_u64().unwrap() >= band {
                assert!(f(r, "max_rel_err") < 1e-6, "{r}");
            }
        }
    }
    for case in ["sphere", "sky-gradient"] {
        for r in find(case, "quadrature-cross") {
            assert!(f(r, "max_rel_err") < 1e-6, "{r}");
        }
    }

    // Quadrature: error ∝ W^-2 (texel means at edges make the caps and
    // polygons converge like smooth radiance; see the suite docs).
    for r in rows
        .iter()
        .filter(|r| text(r, "method").starts_with("quadrature-"))
    {
        if let Some(slope) = r["slope"].as_f64() {
            assert!((-2.4..=-1.4).contains(&slope), "{r}");
        }
    }
    for case in ["hemisphere", "sky-gradient", "cap60-el45", "rect"] {
        let slope = f(find(case, "quadrature-equirect")[0], "slope");
        assert!((slope + 2.0).abs() < 0.2, "{case}: slope {slope}");
    }

    // Monte Carlo: N^-1/2 for independent samples, faster for the
    // stratified ones; each row inside 3 reported standard errors (its
    // pass), few coefficients beyond 3 se over all seeds.
    for sampler in ["uniform", "stratified", "sobol", "importance"] {
        let method = format!("mc-{sampler}");
        let mc: Vec<&serde_json::Value> = rows
            .iter()
            .filter(|r| text(r, "method") == method)
            .collect();
        assert!(mc.len() >= 8, "{method}: {} rows", mc.len());
        for r in &mc {
            let slope = f(r, "slope");
            if matches!(sampler, "uniform" | "importance") {
                assert!((-0.6..=-0.4).contains(&slope), "{r}");
            } else {
                assert!(slope <= -0.6, "{r}");
            }
            if let Some(z) = r["max_z"].as_f64() {
                assert!(z < 6.0, "{r}");
            }
        }
        // Pooled over rows: Gaussian errors would put 0.27% beyond 3 se,
        // Student's t with 15 degrees of freedom (16 replicates) 0.9%;
        // measured 0.2% to 2.0%.
        let z: Vec<f64> = mc
            .iter()
            .filter_map(|r| r["frac_z_over_3"].as_f64())
            .collect();
        let pooled = z.iter().sum::<f64>() / z.len() as f64;
        assert!(pooled < 0.03, "{method}: {pooled}");
    }

    // Ramamoorthi & Hanrahan's figures for a directional light, lmax 2:
    // mean error 0.0307 E, largest 3/32 E (at 90 degrees; the normals come
    // within a few thousandths of it).
    let d2 = find("directional", "truncation")
        .into_iter()
        .find(|r| r["lmax"] == 2)
        .unwrap();
    assert!((f(d2, "mean_rel_err") - 0.0307).abs() < 2e-4, "{d2}");
    assert!((f(d2, "max_rel_err") - 3.0 / 32.0).abs() < 1e-3, "{d2}");
}

/// The published 9-term figures from the oracle alone, on a finer set of
/// normals: 3/32 at 90 degrees, 1/16 at 180, 17/16 facing the light,
/// area mean 0.0307.
#[test]
fn directional_nine_term_figures_reproduce_the_published_numbers() {
    let d = unit(0.3, 0.8, 0.5);
    let sun = Oracle::new("sun", Shape::Directional { dir: d }, 1.0);
    let e2 = sun.truncated(2);
    let perpendicular = d.cross(DVec3::X).normalize();
    assert!((e2.eval(perpendicular) - 3.0 / 32.0).abs() < 1e-14);
    assert!((e2.eval(-d) - 1.0 / 16.0).abs() < 1e-14);
    assert!((e2.eval(d) - 17.0 / 16.0).abs() < 1e-14);
    let normals: Vec<DVec3> = fibonacci_sphere(200_000).into_iter().collect();
    let exact: Vec<f64> = normals.iter().map(|n| sun.irradiance(*n)).collect();
    let est: Vec<f64> = normals.iter().map(|n| e2.eval(*n)).collect();
    let stats = relative_to_peak(&est, &exact);
    // The mean of |E2 - max(cos, 0)| over the sphere is 0.030740.
    assert!((stats.mean - 0.0307).abs() < 1e-4, "{}", stats.mean);
    // The largest error is at exactly 90 degrees, which no normal hits:
    // measured 0.0937421 against 3/32 = 0.09375.
    assert!((stats.max - 3.0 / 32.0).abs() < 2e-5, "{}", stats.max);
}

/// Brute-force and 9-term irradiance of a bundled map at Fibonacci normals:
/// `(mean, max)` relative to max E and `(mean, max)` relative to E(n).
fn real_map_errors(path: &Path, normals: &[DVec3]) -> ((f64, f64), (f64, f64)) {
    let mut image = read_image(path, &ReadOptions::default()).unwrap();
    // The files hold DWAB ringing below zero (envmaps/README.md).
    let _ = image.sanitize();
    let o = MapOrientation::default();
    let map = EnvMap::new(
        Layout::Equirect,
        o,
        image.width(),
        image.height(),
        image.pixels(),
    )
    .unwrap();
    let exact: Vec<f64> = irradiance_brute_force(&map, normals, &|_| {})
        .into_iter()
        .map(luminance)
        .collect();
    let e = shlight_core::sh::irradiance(&project_map(&map, 2));
    let est: Vec<f64> = normals.iter().map(|n| luminance(e.eval(*n))).collect();
    let peak = relative_to_peak(&est, &exact);
    let point = shlight_accuracy::error::pointwise(&est, &exact, 1e-3);
    ((peak.mean, peak.max), (point.mean, point.max))
}

/// Each bundled map's limits on the 9-term irradiance's error against
/// brute force: mean and max relative to max E, then mean and max relative
/// to E(n), each about 1.3x the value measured (in the comment).
const REAL_MAP_LIMITS: [(&str, [f64; 4]); 4] = [
    // Measured 1.38%, 4.46%; 3.96%, 28.4%.
    ("park", [0.018, 0.058, 0.051, 0.37]),
    // Measured 0.39%, 1.08%; 1.77%, 14.5%.
    ("city", [0.0051, 0.014, 0.023, 0.19]),
    // Measured 2.38%, 7.31%; 16.3%, 72.9%.
    ("sky", [0.031, 0.095, 0.21, 0.95]),
    // Measured 2.77%, 9.36%; 27.1%, 714%.
    ("studio", [0.036, 0.122, 0.35, 9.3]),
];

/// The bundled real maps: 9-term irradiance against brute force (every
/// texel) at 2000 equal-area normals, each error held to about 1.3x its
/// measured value ([`REAL_MAP_LIMITS`]).
/// Ramamoorthi & Hanrahan's claim "under 3% average for any lighting"
/// holds in their normalisation (relative to the peak) on every map; their
/// 9% is a directional light's own worst case, and two bright sources on
/// opposite sides (the studio's softboxes) add up beyond it, so the
/// largest errors are held to 10% on every map as well. Pointwise errors
/// are large where E(n) is small (facing away from the sun or the
/// softboxes).
#[test]
fn real_maps_nine_term_irradiance_against_brute_force() {
    let normals: Vec<DVec3> = fibonacci_sphere(2000).into_iter().collect();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("envmaps");
    for (name, limits) in REAL_MAP_LIMITS {
        let ((mean, max), (pmean, pmax)) =
            real_map_errors(&root.join(format!("{name}.exr")), &normals);
        eprintln!(
            "{name}: 9-term irradiance vs brute force: of max E mean {:.3}% max {:.3}%; of E(n) mean {:.2}% max {:.1}%",
            100.0 * mean,
            100.0 * max,
            100.0 * pmean,
            100.0 * pmax
        );
        let errors = [mean, max, pmean, pmax];
        let what = [
            "mean of max E",
            "max of max E",
            "mean of E(n)",
            "max of E(n)",
        ];
        for ((e, limit), what) in errors.iter().zip(limits).zip(what) {
            assert!(e < &limit, "{name}: {what} {e} (limit {limit})");
        }
        // The published claims, on every map.
        assert!(mean < 0.03, "{name}: mean {mean}");
        assert!(max < 0.10, "{name}: max {max}");
    }
}

/// `shlight irradiance` of a synthesized one-texel sun: the brute-force
/// sum has a single term, so every output texel is exactly
/// `E max(n · d_c, 0)` for the sun texel's centre `d_c` (up to f32), and
/// of a hemisphere about up, `π (1 + n_y) / 2` to the sum's `O(h²)`. With
/// `--sh 1` the hemisphere's SH irradiance is exact too (only projection
/// error), and the difference file is SH minus exact.
#[test]
fn irradiance_cli_matches_closed_forms() {
    let dir = temp_dir("accuracy_irradiance_cli");
    let sun = dir.join("sun.exr");
    shlight_ok(&[
        "synth",
        "directional",
        "-o",
        s(&sun),
        "--size",
        "128x64",
        "--direction",
        "0.3,0.8,0.5",
        "--value",
        "3",
    ]);
    let out = dir.join("sun-e.exr");
    shlight_ok(&[
        "irradiance",
        s(&sun),
        "-o",
        s(&out),
        "--size",
        "64x32",
        "-q",
    ]);
    let map = read_image(&sun, &ReadOptions::default()).unwrap();
    let (k, _) = map
        .pixels()
        .iter()
        .enumerate()
        .max_by(|a, b| a.1[0].total_cmp(&b.1[0]))
        .unwrap();
    let o = MapOrientation::default();
    let dc = equirect_direction(k % 128, k / 128, 128, 64, o);
    let e = read_image(&out, &ReadOptions::default()).unwrap();
    assert_eq!((e.width(), e.height()), (64, 32));
    for y in 0..32 {
        for x in 0..64 {
            let n = equirect_direction(x, y, 64, 32, o);
            let want = 3.0 * n.dot(dc).max(0.0);
            let got = f64::from(e.get(x, y)[1]);
            assert!((got - want).abs() < 1e-5 * 3.0, "{x} {y}: {got} vs {want}");
        }
    }

    let sky = dir.join("sky.exr");
    shlight_ok(&["synth", "hemisphere", "-o", s(&sky), "--size", "256x128"]);
    let out = dir.join("sky-e.exr");
    let run = shlight_ok(&[
        "irradiance",
        s(&sky),
        "-o",
        s(&out),
        "--size",
        "32x16",
        "--sh",
        "1",
    ]);
    let printed = String::from_utf8_lossy(&run.stdout);
    assert!(printed.contains("relative to max E"), "{printed}");
    let read = |p: &Path| read_image(p, &ReadOptions::default()).unwrap();
    let (exact, sh, diff) = (
        read(&out),
        read(&dir.join("sky-e-sh.exr")),
        read(&dir.join("sky-e-diff.exr")),
    );
    for y in 0..16 {
        for x in 0..32 {
            let n = equirect_direction(x, y, 32, 16, o);
            let want = PI * (1.0 + n.y) / 2.0;
            // The texel-centre sum errs by O(h²): 5.5e-5 of π measured at
            // 256x128 (crates/shlight-core/src/map/irradiance_map.rs).
            let e = f64::from(exact.get(x, y)[0]);
            let h = f64::from(sh.get(x, y)[0]);
            assert!((e - want).abs() < 2e-4 * PI, "{x} {y}: {e} vs {want}");
            assert!((h - want).abs() < 2e-4 * PI, "sh {x} {y}: {h} vs {want}");
            let d = f64::from(diff.get(x, y)[0]);
            assert!((d - (h - e)).abs() < 1e-6, "diff {x} {y}");
        }
    }
}

/// `--error-map`: a sun straight up, nine terms: the error follows R&H's
/// closed form row by row (1/16 of the peak facing the sun, 17/16 against
/// 1; 3/32 on its horizon), drawn on the fixed 0-10% scale with the colour
/// bar underneath.
#[test]
fn irradiance_error_map_shows_the_nine_term_errors_of_a_sun() {
    let dir = temp_dir("accuracy_irradiance_error_map");
    let sun = dir.join("sun.exr");
    shlight_ok(&[
        "synth",
        "directional",
        "-o",
        s(&sun),
        "--size",
        "256x128",
        "--direction",
        "0,1,0",
    ]);
    let map = dir.join("sun-error.png");
    shlight_ok(&[
        "irradiance",
        s(&sun),
        "-o",
        s(&dir.join("e.exr")),
        "--size",
        "64x32",
        "--sh",
        "2",
        "--error-map",
        s(&map),
    ]);
    let image = read_image(&map, &ReadOptions::default()).unwrap();
    assert_eq!((image.width(), image.height()), (64, 32 + 36));
    let linear = |c: f64| {
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let near = |x: usize, y: usize, error: f64| {
        let want = shlight_accuracy::plot::colour_scale(error / 0.1).map(linear);
        let got = image.get(x, y);
        for c in 0..3 {
            assert!(
                (f64::from(got[c]) - want[c]).abs() < 0.03,
                "({x}, {y}): {got:?} vs {want:?} for {error}"
            );
        }
    };
    // R&H's nine-term irradiance of a unit sun at angle t from the normal,
    // against the truth max(cos t, 0), at each row's centre.
    let nine_term_error = |y: usize| {
        let c = ((y as f64 + 0.5) / 32.0 * PI).cos();
        (0.25 + c / 2.0 + 5.0 / 32.0 * (3.0 * c * c - 1.0) - c.max(0.0)).abs()
    };
    // Rows away from the horizon, where the error changes slowly.
    for y in [0, 4, 8, 23, 27, 31] {
        near(32, y, nine_term_error(y));
    }
    assert!((nine_term_error(0) - 1.0 / 16.0).abs() < 2e-3);
    let err = shlight_err(&[
        "irradiance",
        s(&sun),
        "-o",
        s(&dir.join("f.exr")),
        "--error-map",
        s(&map),
    ]);
    assert!(err.contains("--error-map needs --sh"), "{err}");
    let err = shlight_err(&[
        "irradiance",
        s(&sun),
        "-o",
        s(&dir.join("f.exr")),
        "--sh",
        "2",
        "--error-map",
        s(&dir.join("m.exr")),
    ]);
    assert!(err.contains("m.exr") && err.contains("PNG"), "{err}");
}

/// Any layout and frame: a 40° cap drawn in a z-up cube cross, whose
/// brute-force irradiance must follow Snyder's closed form
/// (`shlight_accuracy::oracle::cap_irradiance`) at every output texel.
#[test]
fn irradiance_cli_reads_cube_crosses_in_the_z_up_frame() {
    let dir = temp_dir("accuracy_irradiance_cross");
    let cap = dir.join("cap.exr");
    shlight_ok(&[
        "synth",
        "cap",
        "-o",
        s(&cap),
        "--layout",
        "cross-h",
        "--size",
        "512x384",
        "--up",
        "z",
        "--half-angle",
        "40",
        "--direction",
        "0.2,0.9,0.1",
    ]);
    let out = dir.join("cap-e.exr");
    shlight_ok(&[
        "irradiance",
        s(&cap),
        "-o",
        s(&out),
        "--up",
        "z",
        "--size",
        "64x32",
        "-q",
    ]);
    let e = read_image(&out, &ReadOptions::default()).unwrap();
    let axis = DVec3::new(0.2, 0.9, 0.1).normalize();
    let o = MapOrientation {
        frame: shlight_core::sh::Frame::ZUp,
        mirror: false,
    };
    let peak = PI * 40f64.to_radians().sin().powi(2);
    let mut worst = 0.0f64;
    for y in 0..32 {
        for x in 0..64 {
            let n = equirect_direction(x, y, 64, 32, o);
            let want = shlight_accuracy::oracle::cap_irradiance(40f64.to_radians(), n.dot(axis));
            worst = worst.max((f64::from(e.get(x, y)[0]) - want).abs() / peak);
        }
    }
    // synth point-samples cube texels, so the rim is resolved to a texel
    // (faces of 128): measured 6.6e-4 of the peak.
    assert!(worst < 2e-3, "{worst}");
}

#[test]
fn irradiance_cli_refuses_bad_input() {
    let dir = temp_dir("accuracy_irradiance_errors");
    let missing = dir.join("missing.exr");
    let err = shlight_err(&["irradiance", s(&missing), "-o", s(&dir.join("e.exr"))]);
    assert!(err.contains("missing.exr"), "{err}");

    let sky = dir.join("sky.exr");
    shlight_ok(&["synth", "hemisphere", "-o", s(&sky), "--size", "64x32"]);
    let err = shlight_err(&["irradiance", s(&sky), "-o", s(&sky)]);
    assert!(err.contains("refusing to write over the input"), "{err}");
    let err = shlight_err(&[
        "irradiance",
        s(&sky),
        "-o",
        s(&dir.join("e.exr")),
        "--size",
        "64x64",
    ]);
    assert!(err.contains("--size") && err.contains("twice"), "{err}");
    let err = shlight_err(&["irradiance", s(&sky), "-o", s(&dir.join("e.txt"))]);
    assert!(err.contains("e.txt"), "{err}");
    assert!(!dir.join("e.txt").exists());

    // A directory where pictures should go that is a file.
    let file = dir.join("file");
    std::fs::write(&file, "x").unwrap();
    let err = shlight_err(&["accuracy", "--quick", "-o", s(&file)]);
    assert!(err.contains("not a directory"), "{err}");
}

//! `shlight synth`: each analytic map projects to its closed-form
//! coefficients (`shlight_core::sh::closed_form`).

use shlight_core::map::{MapOrientation, equirect_direction};
use shlight_core::sh::{Frame, ShCoeffs, closed_form};

use crate::util::{assert_rows_near, project_rows, s, shlight_err, shlight_ok, temp_dir};

const LMAX: usize = 4;
const SIZE: &str = "256x128";

/// Quadrature by texel centres on 128 rows errs in the zonal terms by
/// `O(dθ²)` (dθ = π/128); maps whose texels are exact means (constant,
/// gradient, a hemisphere on a row boundary) measured 7.5e-5 of the largest
/// coefficient at lmax 4. Allowed 3e-4.
const SMOOTH_TOL: f64 = 3e-4;

/// A cap's edge crosses texels whose 4x4 coverage is off by up to 1/32 of a
/// texel each, partly cancelling; measured 3.5e-4, allowed 1.5e-3.
const EDGE_TOL: f64 = 1.5e-3;

fn scaled(f: &ShCoeffs<f64>, colour: [f64; 3]) -> Vec<[f64; 3]> {
    (0..f.len()).map(|i| colour.map(|c| c * f[i])).collect()
}

fn lmax_arg() -> String {
    LMAX.to_string()
}

#[test]
fn constant_and_gradient_maps_give_their_closed_forms() {
    let dir = temp_dir("synth_smooth");
    let map = dir.join("constant.exr");
    shlight_ok(&[
        "synth",
        "constant",
        "-o",
        s(&map),
        "--size",
        SIZE,
        "--color",
        "1,2,0.5",
        "--value",
        "2",
    ]);
    let want = scaled(&closed_form::constant(LMAX, 1.0), [2.0, 4.0, 1.0]);
    for up in ["y", "z"] {
        // The map is the same in both frames (constant); project it either way.
        let got = project_rows(&map, &["--lmax", &lmax_arg(), "--up", up]);
        assert_rows_near(&got, &want, SMOOTH_TOL, "constant");
    }

    // a + b (d . axis) about a tilted axis, in the z-up frame.
    let axis = [0.48, 0.6, -0.64];
    let map = dir.join("gradient.exr");
    shlight_ok(&[
        "synth",
        "gradient",
        "-o",
        s(&map),
        "--size",
        SIZE,
        "--up",
        "z",
        "--value",
        "1.5",
        "--slope",
        "-0.75",
        "--direction",
        "0.48,0.6,-0.64",
        "--color",
        "1,0.5,0.25",
    ]);
    let got = project_rows(&map, &["--lmax", &lmax_arg(), "--up", "z"]);
    let want = scaled(
        &closed_form::linear_gradient(LMAX, glam::DVec3::from(axis), 1.5, -0.75),
        [1.0, 0.5, 0.25],
    );
    assert_rows_near(&got, &want, SMOOTH_TOL, "gradient");
}

#[test]
fn hemisphere_and_caps_give_their_closed_forms() {
    let dir = temp_dir("synth_caps");
    // Upper hemisphere about each frame's own up axis: the edge is a row boundary.
    for (up, axis) in [("y", [0.0, 1.0, 0.0]), ("z", [0.0, 0.0, 1.0])] {
        let map = dir.join(format!("hemi-{up}.exr"));
        shlight_ok(&[
            "synth",
            "hemisphere",
            "-o",
            s(&map),
            "--size",
            SIZE,
            "--up",
            up,
            "--color",
            "3,2,1",
        ]);
        let got = project_rows(&map, &["--lmax", &lmax_arg(), "--up", up]);
        let want = scaled(
            &closed_form::cap(
                LMAX,
                glam::DVec3::from(axis),
                std::f64::consts::FRAC_PI_2,
                1.0,
            ),
            [3.0, 2.0, 1.0],
        );
        assert_rows_near(&got, &want, SMOOTH_TOL, &format!("hemisphere, {up}-up"));
    }
    // A 40° cap about a direction that no texel grid line follows, mirrored.
    let raw = [1.0f64, 1.0, 0.5];
    let n = raw.iter().map(|v| v * v).sum::<f64>().sqrt();
    let axis = raw.map(|v| v / n);
    let map = dir.join("cap.exr");
    shlight_ok(&[
        "synth",
        "cap",
        "-o",
        s(&map),
        "--size",
        SIZE,
        "--direction",
        "1,1,0.5",
        "--half-angle",
        "40",
        "--mirror",
        "--value",
        "4",
    ]);
    let got = project_rows(&map, &["--lmax", &lmax_arg(), "--mirror"]);
    let want = scaled(
        &closed_form::cap(LMAX, glam::DVec3::from(axis), 40f64.to_radians(), 4.0),
        [1.0; 3],
    );
    assert_rows_near(&got, &want, EDGE_TOL, "cap");
}

#[test]
fn a_one_texel_sun_is_the_delta_at_its_texel_centre() {
    let dir = temp_dir("synth_sun");
    let (w, h) = (256, 128);
    let o = MapOrientation {
        frame: Frame::ZUp,
        mirror: false,
    };
    // Aim at a texel centre: the single-texel sun is then exactly the delta.
    let d = equirect_direction(77, 30, w, h, o);
    let dir_arg = format!("{:.17},{:.17},{:.17}", d.x, d.y, d.z);
    let map = dir.join("sun.exr");
    let out = shlight_ok(&[
        "synth",
        "directional",
        "-o",
        s(&map),
        "--size",
        SIZE,
        "--up",
        "z",
        "--direction",
        &dir_arg,
        "--value",
        "5",
        "--color",
        "1,0.9,0.8",
    ]);
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let got = project_rows(&map, &["--lmax", &lmax_arg(), "--up", "z"]);
    let want = scaled(&closed_form::directional(LMAX, d, 5.0), [1.0, 0.9, 0.8]);
    // Exact but for the f32 texel value.
    assert_rows_near(&got, &want, 1e-6, "one-texel sun");

    // Off a texel centre it lands in the texel and says where.
    let out = shlight_ok(&[
        "synth",
        "directional",
        "-o",
        s(&map),
        "--size",
        SIZE,
        "--direction",
        "0.3,0.4,0.5",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("lands in texel"), "{err}");
}

#[test]
fn a_small_cap_sun_keeps_its_irradiance_and_is_near_the_delta() {
    let dir = temp_dir("synth_cap_sun");
    let map = dir.join("sun.exr");
    let half = 3.0f64;
    shlight_ok(&[
        "synth",
        "directional",
        "-o",
        s(&map),
        "--size",
        "512x256",
        "--direction",
        "0.2,0.9,-0.3",
        "--half-angle",
        "3",
        "--value",
        "2",
    ]);
    let raw = [0.2f64, 0.9, -0.3];
    let n = raw.iter().map(|v| v * v).sum::<f64>().sqrt();
    let axis = raw.map(|v| v / n);
    let got = project_rows(&map, &["--lmax", "2"]);
    let a = half.to_radians();
    let radiance = 2.0 / (std::f64::consts::PI * a.sin().powi(2));
    let cap = scaled(
        &closed_form::cap(2, glam::DVec3::from(axis), a, radiance),
        [1.0; 3],
    );
    // The cap is ~9 texels across and normalised to its power; measured 1e-4.
    assert_rows_near(&got, &cap, 1e-3, "cap sun vs cap");
    // The cap and the delta differ by l(l+1)a²/4 relatively in degree l
    // (4e-3 at l = 2, a = 3°); measured 1.3e-3 of the largest coefficient.
    let delta = scaled(
        &closed_form::directional(2, glam::DVec3::from(axis), 2.0),
        [1.0; 3],
    );
    assert_rows_near(&got, &delta, 3e-3, "cap sun vs delta");
    // Its power is exact: L_00 = 2 sqrt(pi) * mean = L * solid angle / (2 sqrt(pi)).
    let want00 = radiance * 2.0 * std::f64::consts::PI * (1.0 - a.cos())
        / (2.0 * std::f64::consts::PI.sqrt());
    assert!(
        (got[0][0] - want00).abs() < 1e-5 * want00,
        "{} vs {want00}",
        got[0][0]
    );
}

#[test]
fn synth_writes_every_format_and_refuses_bad_arguments() {
    let dir = temp_dir("synth_formats");
    for ext in ["exr", "hdr", "png"] {
        let path = dir.join(format!("g.{ext}"));
        shlight_ok(&[
            "synth",
            "gradient",
            "-o",
            s(&path),
            "--size",
            "64x32",
            "--exposure",
            "-1",
            "--tone-map",
            "aces",
        ]);
        let img = shlight_io::read_image(&path, &Default::default()).unwrap();
        assert_eq!((img.width(), img.height()), (64, 32), "{ext}");
    }
    let keep = dir.join("g.exr");
    let before = std::fs::read(&keep).unwrap();
    for (args, needle) in [
        (vec!["--size", "64x64"], "twice its height"),
        (vec!["--size", "64"], "WIDTHxHEIGHT"),
        (vec!["--direction", "0,0,0"], "no direction"),
        (vec!["--color", "1,2"], "three finite numbers"),
        (vec!["--half-angle", "200"], "between 0 and 180"),
    ] {
        let mut all = vec!["synth", "cap", "-o", s(&keep)];
        all.extend(args);
        let err = shlight_err(&all);
        assert!(err.contains(needle), "{all:?}: {err}");
    }
    assert_eq!(
        std::fs::read(&keep).unwrap(),
        before,
        "the old map was touched"
    );
    let err = shlight_err(&[
        "synth",
        "directional",
        "--half-angle",
        "120",
        "-o",
        s(&keep),
    ]);
    assert!(err.contains("at most 90 degrees"), "{err}");
    assert_eq!(std::fs::read(&keep).unwrap(), before);
    let err = shlight_err(&["synth", "constant", "-o", s(&dir.join("x.jpg"))]);
    assert!(err.contains("x.jpg"), "{err}");
}

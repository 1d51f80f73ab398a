//! Every `--layout` end to end: render and project round trips, the
//! orientation of cube and disc layouts, six face files, and size errors.

use std::path::Path;

use crate::util::{
    assert_rows_near, coefficients, json, project_rows, s, shlight, shlight_err, shlight_ok,
    temp_dir, write_map,
};
use crate::util::{band1_direction, read_json, write_radiance_rows, write_spot};

/// An lmax-2 radiance expansion: a constant 3 and smaller terms.
fn rows() -> Vec<[f64; 3]> {
    (0..9)
        .map(|i| {
            if i == 0 {
                [3.0, 2.5, 2.0]
            } else {
                let v = 0.3 * (i as f64 * 0.7).sin();
                [v, -0.5 * v, 0.25 * v]
            }
        })
        .collect()
}

fn assert_points(rows: &[[f64; 3]], want: [f64; 3], what: &str) {
    let d = band1_direction(rows);
    let dot = d[0] * want[0] + d[1] * want[1] + d[2] * want[2];
    assert!(dot > 0.999, "{what}: band 1 points to {d:?}, not {want:?}");
}

#[test]
fn rendered_layouts_project_back_to_their_coefficients() {
    let dir = temp_dir("layouts_round_trip");
    let file = dir.join("sh.json");
    let want = rows();
    write_radiance_rows(&file, &want);
    // Faces of 64, discs of 256: the midpoint error is a few 1e-4 of the
    // largest coefficient (crates/shlight-core/src/map/projection/mod.rs).
    for (layout, size) in [
        ("cross-h", "256x192"),
        ("cross-v", "192x256"),
        ("strip", "384x64"),
        ("angular", "256x256"),
    ] {
        let img = dir.join(format!("{layout}.exr"));
        shlight_ok(&[
            "render",
            s(&file),
            "-o",
            s(&img),
            "--layout",
            layout,
            "--size",
            size,
        ]);
        let out = json(&shlight(&["project", s(&img), "--lmax", "2"]));
        assert_eq!(out["provenance"]["layout"], layout);
        assert_rows_near(&coefficients(&out), &want, 2e-3, layout);
    }
    // A mirror ball must be named; its rim is coarser (N = 256: ~1e-3).
    let img = dir.join("ball.exr");
    shlight_ok(&[
        "render",
        s(&file),
        "-o",
        s(&img),
        "--layout",
        "mirror-ball",
        "--size",
        "256x256",
    ]);
    let got = project_rows(&img, &["--layout", "mirror-ball"]);
    assert_rows_near(&got, &want, 5e-3, "mirror-ball");
}

/// A `w x h` map, black but for a 2x2 block of 100 whose top-left is `(x, y)`
/// (or one texel when `single`).
fn spot(path: &Path, w: usize, h: usize, at: (usize, usize), single: bool) {
    write_spot(path, w, h, at, if single { 1 } else { 2 }, [100.0; 3]);
}

#[test]
fn orientation_is_pinned_for_crosses_faces_and_angular_maps() {
    let dir = temp_dir("layouts_orientation");
    let f = 16;
    // +Z is row 1, column 1 of a horizontal cross; its centre is between
    // texels f + f/2 - 1 and f + f/2.
    let cross = dir.join("cross.exr");
    spot(&cross, 4 * f, 3 * f, (f + f / 2 - 1, f + f / 2 - 1), false);
    let y_up = project_rows(&cross, &[]);
    assert_points(&y_up, [0.0, 0.0, 1.0], "cross-h +Z, y-up");
    // z-up turns the map's y-up sphere +90° about X: (x, y, z) -> (x, -z, y).
    let z_up = project_rows(&cross, &["--up", "z"]);
    assert_points(&z_up, [0.0, -1.0, 0.0], "cross-h +Z, z-up");

    // Six faces: only pz lit.
    for face in ["px", "nx", "py", "ny", "pz", "nz"] {
        let path = dir.join(format!("sky_{face}.exr"));
        if face == "pz" {
            spot(&path, f, f, (f / 2 - 1, f / 2 - 1), false);
        } else {
            write_map(&path, f, f, |_, _| [0.0; 3]);
        }
    }
    let pattern = dir.join("sky_{face}.exr");
    let out = json(&shlight(&["project", s(&pattern)]));
    assert_eq!(out["provenance"]["layout"], "faces");
    let faces = coefficients(&out);
    assert_points(&faces, [0.0, 0.0, 1.0], "pz face");
    assert_rows_near(&faces, &y_up, 1e-9, "six faces = cross");
    let out = json(&shlight(&["project", s(&pattern), "--layout", "faces"]));
    assert_rows_near(&coefficients(&out), &y_up, 1e-9, "--layout faces");
    // In a batch, the six faces write one file named without the placeholder.
    let batch = dir.join("batch");
    shlight(&["project", s(&pattern), s(&cross), "-o", s(&batch), "-q"]);
    let from_faces = coefficients(&read_json(&batch.join("sky.json")));
    assert_rows_near(&from_faces, &y_up, 1e-9, "batch of faces");
    assert!(batch.join("cross.json").is_file());

    // The centre texel of an angular map looks along -Z.
    let angular = dir.join("angular.exr");
    spot(&angular, 33, 33, (16, 16), true);
    assert_points(&project_rows(&angular, &[]), [0.0, 0.0, -1.0], "angular");
}

#[test]
fn monte_carlo_reads_cube_layouts() {
    let dir = temp_dir("layouts_montecarlo");
    let img = dir.join("white.exr");
    write_map(&img, 64, 48, |_, _| [1.0; 3]);
    for sampler in ["sobol", "importance"] {
        let out = json(&shlight(&[
            "project",
            s(&img),
            "--method",
            "montecarlo",
            "--sampler",
            sampler,
            "--samples",
            "4096",
        ]));
        assert_eq!(out["provenance"]["layout"], "cross-h");
        let l00 = coefficients(&out)[0][0];
        let exact = 2.0 * std::f64::consts::PI.sqrt();
        assert!((l00 - exact).abs() < 1e-2 * exact, "{sampler}: {l00}");
    }
}

#[test]
fn missing_faces_and_wrong_sizes_are_errors_naming_the_file() {
    let dir = temp_dir("layouts_errors");
    for face in ["px", "nx", "py", "ny", "pz"] {
        write_map(&dir.join(format!("sky_{face}.exr")), 8, 8, |_, _| [1.0; 3]);
    }
    let pattern = dir.join("sky_{face}.exr");
    let err = shlight_err(&["project", s(&pattern)]);
    assert!(err.contains(s(&dir.join("sky_nz.exr"))), "{err}");
    // A face of another size.
    write_map(&dir.join("sky_nz.exr"), 4, 4, |_, _| [1.0; 3]);
    let err = shlight_err(&["project", s(&pattern)]);
    assert!(
        err.contains("sky_nz.exr") && err.contains("same size"),
        "{err}"
    );
    // A face that is not square.
    write_map(&dir.join("sky_nz.exr"), 8, 4, |_, _| [1.0; 3]);
    let err = shlight_err(&["project", s(&pattern)]);
    assert!(
        err.contains("sky_nz.exr") && err.contains("square"),
        "{err}"
    );

    let odd = dir.join("odd.exr");
    write_map(&odd, 30, 20, |_, _| [1.0; 3]);
    let err = shlight_err(&["project", s(&odd)]);
    assert!(err.contains(s(&odd)) && err.contains("no layout"), "{err}");
    let wide = dir.join("wide.exr");
    write_map(&wide, 64, 32, |_, _| [1.0; 3]);
    let err = shlight_err(&["project", s(&wide), "--layout", "cross-h"]);
    assert!(err.contains(s(&wide)), "{err}");
    let err = shlight_err(&["project", s(&wide), "--layout", "faces"]);
    assert!(err.contains("{face}"), "{err}");
    let sh = dir.join("sh.json");
    write_radiance_rows(&sh, &rows());
    let out = dir.join("x.exr");
    let err = shlight_err(&[
        "render",
        s(&sh),
        "-o",
        s(&out),
        "--layout",
        "strip",
        "--size",
        "64x32",
    ]);
    assert!(err.contains("--size"), "{err}");
}

#[test]
fn synth_writes_every_layout_and_previews_read_them() {
    let dir = temp_dir("layouts_synth");
    let exact = 2.0 * std::f64::consts::PI.sqrt();
    for (layout, size) in [
        ("equirect", "64x32"),
        ("cross-h", "64x48"),
        ("cross-v", "48x64"),
        ("strip", "96x16"),
        ("angular", "33x33"),
        ("mirror-ball", "33x33"),
    ] {
        let img = dir.join(format!("{layout}.exr"));
        shlight_ok(&[
            "synth",
            "constant",
            "-o",
            s(&img),
            "--layout",
            layout,
            "--size",
            size,
        ]);
        let png = dir.join(format!("{layout}.png"));
        let out = json(&shlight(&[
            "project",
            s(&img),
            "--layout",
            layout,
            "--preview",
            s(&png),
            "--preview-size",
            "32x16",
        ]));
        assert!(png.exists(), "{layout}: no preview");
        let l00 = coefficients(&out)[0][0];
        assert!((l00 - exact).abs() < 1e-5, "{layout}: {l00}");

        // A sun along +X lands in one texel; its band 1 points along +X.
        let sun = dir.join(format!("{layout}-sun.exr"));
        shlight_ok(&[
            "synth",
            "directional",
            "-o",
            s(&sun),
            "--layout",
            layout,
            "--size",
            size,
            "--direction",
            "1,0,0",
        ]);
        let rows = project_rows(&sun, &["--layout", layout]);
        let d = band1_direction(&rows);
        assert!(d[0] > 0.99, "{layout}: sun band 1 {d:?}");
    }
}

#[test]
fn a_forced_equirect_map_that_is_not_2_to_1_is_projected_with_a_warning() {
    let dir = temp_dir("layouts_equirect_aspect");
    let odd = dir.join("odd.exr");
    // A constant map: whatever its aspect, equirect geometry covers the
    // sphere, so L_0^0 = sqrt(4π) and the rest is 0.
    write_map(&odd, 37, 10, |_, _| [1.0; 3]);
    let out = shlight(&["project", s(&odd), "--layout", "equirect"]);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let rows = coefficients(&json(&out));
    // The quadrature's exact texel solid angles sum to 4π to rounding.
    const SUM_TOL: f64 = 1e-9;
    assert!(
        (rows[0][0] - (4.0 * std::f64::consts::PI).sqrt()).abs() < SUM_TOL,
        "{:?}",
        rows[0]
    );
    let warning: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect();
    assert!(
        warning.len() == 1 && warning[0].contains(s(&odd)) && warning[0].contains("37x10"),
        "{stderr}"
    );
    assert!(warning[0].contains("not 2:1"), "{stderr}");
    // --quiet silences it; a 2:1 map forced to equirect gets none.
    let quiet = shlight(&["project", s(&odd), "--layout", "equirect", "--quiet"]);
    assert!(quiet.status.success() && quiet.stderr.is_empty());
    let fine = dir.join("fine.exr");
    write_map(&fine, 40, 20, |_, _| [1.0; 3]);
    let out = shlight(&["project", s(&fine), "--layout", "equirect"]);
    assert!(out.status.success() && out.stderr.is_empty(), "{out:?}");
}

//! `shlight render`: rendering a coefficient file and projecting the image
//! gives the file's coefficients back.

use std::path::Path;

use serde_json::json;
use shlight_core::sh::{ShCoeffs, irradiance};

use crate::util::{assert_rows_near, project_rows, s, shlight, shlight_err, shlight_ok, temp_dir};

/// A band-limited function rendered on 256 rows and projected by texel
/// centres comes back to `O(dθ²)` (dθ = π/256) of the largest coefficient:
/// measured 2e-5 at lmax 4 (f32 texels add ~1e-7). Allowed 1e-4.
const ROUND_TRIP_TOL: f64 = 1e-4;

/// Rows of a smooth, positive lmax 4 radiance in shlight's basis.
fn sample_rows() -> Vec<[f64; 3]> {
    let f = ShCoeffs::<f64>::from_fn(4, |l, m| {
        if l == 0 {
            6.0
        } else {
            0.4 * (1.0 + m as f64 * 0.3) / (l * l) as f64
        }
    });
    (0..f.len())
        .map(|i| [f[i], 0.5 * f[i], if i == 0 { f[i] } else { -0.25 * f[i] }])
        .collect()
}

fn write_file(
    path: &std::path::Path,
    rows: &[[f64; 3]],
    frame: &str,
    mirror: bool,
    quantity: &str,
) {
    let lmax = (rows.len() as f64).sqrt() as usize - 1;
    let doc = json!({
        "format": "shlight-sh",
        "format_version": 1,
        "lmax": lmax,
        "frame": frame,
        "mirror": mirror,
        "quantity": quantity,
        "coefficients": rows,
        "provenance": {},
    });
    std::fs::write(path, doc.to_string()).unwrap();
}

#[test]
fn render_then_project_returns_the_coefficients_in_the_files_frame() {
    let dir = temp_dir("render_round_trip");
    let rows = sample_rows();
    for (frame, up, mirror) in [("y-up", "y", false), ("z-up", "z", true)] {
        let file = dir.join(format!("{frame}.json"));
        write_file(&file, &rows, frame, mirror, "radiance");
        let img = dir.join(format!("{frame}.exr"));
        shlight_ok(&["render", s(&file), "-o", s(&img), "--size", "512x256"]);
        let mut args = vec!["--lmax", "4", "--up", up];
        if mirror {
            args.push("--mirror");
        }
        let got = project_rows(&img, &args);
        assert_rows_near(&got, &rows, ROUND_TRIP_TOL, frame);
    }
}

#[test]
fn irradiance_is_rendered_on_request_and_an_irradiance_file_as_it_is() {
    let dir = temp_dir("render_irradiance");
    let rows = sample_rows();
    let file = dir.join("l.json");
    write_file(&file, &rows, "y-up", false, "radiance");
    let img = dir.join("e.exr");
    let out = shlight_ok(&["render", s(&file), "-o", s(&img), "--irradiance"]);
    assert!(out.stderr.is_empty());
    let channels: Vec<ShCoeffs<f64>> = (0..3)
        .map(|c| irradiance(&ShCoeffs::from_vec(rows.iter().map(|r| r[c]).collect()).unwrap()))
        .collect();
    let want: Vec<[f64; 3]> = (0..rows.len())
        .map(|i| [channels[0][i], channels[1][i], channels[2][i]])
        .collect();
    assert_rows_near(
        &project_rows(&img, &["--lmax", "4"]),
        &want,
        ROUND_TRIP_TOL,
        "E",
    );

    // A file of irradiance renders what it holds, and says so unless --quiet.
    let efile = dir.join("e.json");
    write_file(&efile, &want, "y-up", false, "irradiance");
    let img2 = dir.join("e2.exr");
    let out = shlight_ok(&["render", s(&efile), "-o", s(&img2)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("holds irradiance"), "{err}");
    assert_rows_near(
        &project_rows(&img2, &["--lmax", "4"]),
        &want,
        ROUND_TRIP_TOL,
        "E file",
    );
    let out = shlight_ok(&["render", s(&efile), "-o", s(&img2), "--quiet"]);
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn png_output_is_exposed_and_tone_mapped_and_bad_input_is_refused() {
    let dir = temp_dir("render_png");
    let file = dir.join("c.json");
    // Constant radiance 1: L_00 = 2 sqrt(pi).
    let c0 = 2.0 * std::f64::consts::PI.sqrt();
    write_file(&file, &[[c0, c0, c0]], "y-up", false, "radiance");
    let png = dir.join("c.png");
    for (ev, tone, want) in [
        ("-1", "clamp", 0.5f32),
        ("0", "reinhard", 0.5),
        ("1", "clamp", 1.0),
    ] {
        shlight_ok(&[
            "render",
            s(&file),
            "-o",
            s(&png),
            "--size",
            "32x16",
            "--exposure",
            ev,
            "--tone-map",
            tone,
        ]);
        let img = shlight_io::read_image(&png, &Default::default()).unwrap();
        assert_eq!((img.width(), img.height()), (32, 16));
        // 8-bit sRGB: half a code value is about 2e-3 linear near 0.5.
        assert!(
            (img.get(5, 5)[0] - want).abs() < 3e-3,
            "{ev} {tone}: {:?}",
            img.get(5, 5)
        );
    }

    let before = std::fs::read(&png).unwrap();
    let missing = dir.join("missing.json");
    let err = shlight_err(&["render", s(&missing), "-o", s(&png)]);
    assert!(err.contains("missing.json"), "{err}");
    let err = shlight_err(&["render", s(&file), "-o", s(&png), "--size", "30x30"]);
    assert!(err.contains("--size") && err.contains("twice"), "{err}");
    let err = shlight_err(&["render", s(&file), "-o", s(&file)]);
    assert!(err.contains("refusing"), "{err}");
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{\"format\": \"other\"}").unwrap();
    let err = shlight_err(&["render", s(&bad), "-o", s(&png)]);
    assert!(err.contains("bad.json"), "{err}");
    assert_eq!(
        std::fs::read(&png).unwrap(),
        before,
        "the old image was touched"
    );
    // And nothing was written on error.
    assert!(
        !shlight(&["render", s(&missing), "-o", s(&dir.join("new.exr"))])
            .status
            .success()
    );
    assert!(!dir.join("new.exr").exists());
}

/// `sqrt(3 / (4 pi))`: `Y_1^0 = C z`, `Y_1^-1 = -C y`, `Y_1^1 = -C x`
/// with the Condon-Shortley phase.
const C1: f64 = 0.488_602_511_902_919_9;

/// Rows of a file holding `c` (grey) on coefficient `index` of lmax 1.
fn one_coefficient(index: usize, c: f64) -> Vec<[f64; 3]> {
    (0..4)
        .map(|i| if i == index { [c; 3] } else { [0.0; 3] })
        .collect()
}

/// What a pixel of a lobe picture shows: red, blue or the white background.
fn colour_of(p: [f32; 3]) -> char {
    match p {
        [r, g, b] if r > 2.0 * b && r > g => 'r',
        [r, g, b] if b > 2.0 * r && b > g => 'b',
        [1.0, 1.0, 1.0] => 'w',
        other => panic!("neither red, blue nor white: {other:?}"),
    }
}

/// `--layout lobe` of `Y_1^0 = C z` seen from `+X` is two spheres of
/// radius `C/2` at `+-C/2 z` seen side on: discs of radius `C/2` above
/// and below the image's centre, the image's half-size `1.05 C`. Every
/// pixel of the PNG is red inside the upper disc, blue inside the lower
/// and white outside (centres within 0.02 pixel of a rim skipped): the
/// silhouette's extent and the colours are the closed form's. Seen from
/// `+X`, `Y_1^1 = -C x` shows its negative lobe (blue), from `-X` its
/// positive one; a y-up file is drawn with `+Y` up (the default view).
/// `shlight render FILE -o PNG --layout lobe [--view VIEW] --size SIZE`,
/// the picture read back.
fn render_lobe(file: &Path, png: &Path, view: Option<&str>, size: &str) -> shlight_io::Image {
    let mut args = vec![
        "render",
        s(file),
        "-o",
        s(png),
        "--layout",
        "lobe",
        "--size",
        size,
    ];
    if let Some(view) = view {
        args.extend(["--view", view]);
    }
    shlight_ok(&args);
    shlight_io::read_image(png, &Default::default()).unwrap()
}

#[test]
fn lobes_have_the_closed_forms_silhouette_and_sign() {
    let dir = temp_dir("render_lobe");
    let n = 64usize;
    let file = dir.join("y10.json");
    write_file(&file, &one_coefficient(2, 1.0), "z-up", false, "radiance");
    let png = dir.join("y10.png");
    let size = format!("{n}x{n}");
    let img = render_lobe(&file, &png, Some("1,0,0"), &size);
    assert_eq!((img.width(), img.height()), (n, n));
    // Pixels per unit: the half-size n/2 spans 1.05 C.
    let scale = 0.5 * n as f64 / (1.05 * C1);
    let r = 0.5 * C1 * scale;
    let (mut counts, mut skipped) = ([0usize; 3], 0);
    for y in 0..n {
        for x in 0..n {
            // From +X with +Z up the image's right is +Y.
            let (u, v) = (
                x as f64 + 0.5 - 0.5 * n as f64,
                0.5 * n as f64 - y as f64 - 0.5,
            );
            let rim = |cv: f64| u.hypot(v - cv) - r;
            let (up, down) = (rim(r), rim(-r));
            if up.abs() < 0.02 || down.abs() < 0.02 {
                skipped += 1;
                continue;
            }
            let want = if up < 0.0 {
                'r'
            } else if down < 0.0 {
                'b'
            } else {
                'w'
            };
            assert_eq!(colour_of(img.get(x, y)), want, "pixel ({x}, {y})");
            counts["rbw".find(want).unwrap()] += 1;
        }
    }
    // About 190 pixels along the rims, 4% of them within the band.
    assert!(skipped < 30, "{skipped}");
    // Each disc covers about pi r^2 = 583 pixels.
    assert!(counts[0] > 550 && counts[1] > 550, "{counts:?}");

    let file = dir.join("y11.json");
    write_file(&file, &one_coefficient(3, 1.0), "z-up", false, "radiance");
    for (view, want) in [("1,0,0", 'b'), ("-1,0,0", 'r')] {
        let img = render_lobe(&file, &png, Some(view), "32x32");
        assert_eq!(colour_of(img.get(16, 16)), want, "--view {view}");
    }

    // C y in a y-up file: +Y is the frame's up, red on top, blue below.
    let file = dir.join("yup.json");
    write_file(&file, &one_coefficient(1, -1.0), "y-up", false, "radiance");
    let img = render_lobe(&file, &png, None, "32x32");
    let column: String = (0..32).map(|y| colour_of(img.get(16, y))).collect();
    let trimmed = column.trim_matches('w');
    assert!(
        trimmed.starts_with('r') && trimmed.ends_with('b'),
        "{column}"
    );
}

#[test]
fn lobe_options_are_checked() {
    let dir = temp_dir("render_lobe_errors");
    let file = dir.join("y10.json");
    write_file(&file, &one_coefficient(2, 1.0), "z-up", false, "radiance");
    let png = dir.join("out.png");
    let lobe = |extra: &[&str]| {
        let mut args = vec!["render", s(&file), "-o", s(&png), "--layout", "lobe"];
        args.extend_from_slice(extra);
        shlight_err(&args)
    };
    let err = lobe(&["--view", "0,0,0"]);
    assert!(err.contains("--view 0,0,0 has no direction"), "{err}");
    let err = lobe(&["--view", "1,2"]);
    assert!(
        err.contains("--view") && err.contains("three finite numbers"),
        "{err}"
    );
    let err = shlight_err(&["render", s(&file), "-o", s(&png), "--view", "1,0,0"]);
    assert!(
        err.contains("--view is where --layout lobe is seen from"),
        "{err}"
    );
    let err = shlight_err(&["render", s(&file), "-o", s(&png), "--layout", "lobes"]);
    assert!(err.contains("lobe"), "{err}");
    let zero = dir.join("zero.json");
    write_file(&zero, &one_coefficient(0, 0.0), "z-up", false, "radiance");
    let err = shlight_err(&["render", s(&zero), "-o", s(&png), "--layout", "lobe"]);
    assert!(
        err.contains("zero.json") && err.contains("zero everywhere"),
        "{err}"
    );
    assert!(!png.exists(), "an image was written on error");
}

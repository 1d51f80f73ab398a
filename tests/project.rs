//! `shlight project`: orientation, output, and bad input.

use crate::util::{coefficients, json, shlight, temp_dir, write_map};

/// Direction (unit) of the band-1 part of red-channel coefficients: for a
/// light from `d`, `(L_1^-1, L_1^0, L_1^1) ∝ (-d.y, d.z, -d.x)`.
fn band1_direction(c: &[[f64; 3]]) -> [f64; 3] {
    let v = [-c[3][0], -c[1][0], c[2][0]];
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

fn assert_near(a: [f64; 3], b: [f64; 3], tol: f64, what: &str) {
    let d = (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max);
    assert!(d < tol, "{what}: {a:?} vs {b:?}");
}

#[test]
fn a_bright_texel_lands_on_the_documented_direction_in_both_frames() {
    let dir = temp_dir("orientation");
    let (w, h) = (64, 32);
    // Equator, u = (16 + .5)/64 ≈ 0.25: faces -Z in y-up, +Y in z-up.
    let spot = dir.join("spot.exr");
    write_map(&spot, w, h, |x, y| {
        if x == 16 && y == 16 {
            [1000.0, 0.0, 0.0]
        } else {
            [0.0; 3]
        }
    });
    // Row 0, all columns: up (+Y in y-up, +Z in z-up).
    let top = dir.join("top.exr");
    write_map(&top, w, h, |_, y| {
        if y == 0 { [1000.0, 0.0, 0.0] } else { [0.0; 3] }
    });
    // Centre column faces +X in both frames.
    let centre = dir.join("centre.exr");
    write_map(&centre, w, h, |x, y| {
        if x == 32 && y == 16 {
            [1000.0, 0.0, 0.0]
        } else {
            [0.0; 3]
        }
    });

    // The texel centres sit half a texel off the axes: allow that angle.
    let tol = 0.1;
    let run = |path: &std::path::Path, up: &str| {
        band1_direction(&coefficients(&json(&shlight(&[
            "project",
            path.to_str().unwrap(),
            "--lmax",
            "1",
            "--up",
            up,
        ]))))
    };
    assert_near(run(&spot, "y"), [0.0, 0.0, -1.0], tol, "spot, y-up");
    assert_near(run(&spot, "z"), [0.0, 1.0, 0.0], tol, "spot, z-up");
    assert_near(run(&top, "y"), [0.0, 1.0, 0.0], 1e-6, "top row, y-up");
    assert_near(run(&top, "z"), [0.0, 0.0, 1.0], 1e-6, "top row, z-up");
    assert_near(run(&centre, "y"), [1.0, 0.0, 0.0], tol, "centre, y-up");
    assert_near(run(&centre, "z"), [1.0, 0.0, 0.0], tol, "centre, z-up");
    // --mirror turns the spot at u = .25 to +Z (y-up).
    let mirrored = band1_direction(&coefficients(&json(&shlight(&[
        "project",
        spot.to_str().unwrap(),
        "--lmax",
        "1",
        "--mirror",
    ]))));
    assert_near(mirrored, [0.0, 0.0, 1.0], tol, "spot, y-up mirrored");
}

#[test]
fn a_constant_map_gives_the_constant_coefficient_and_irradiance_pi() {
    let dir = temp_dir("constant");
    let path = dir.join("c.exr");
    write_map(&path, 128, 64, |_, _| [1.0, 2.0, 0.5]);
    // z-up: the map's pole is the basis's pole, so rings are m-orthogonal.
    let v = json(&shlight(&[
        "project",
        path.to_str().unwrap(),
        "--lmax",
        "4",
        "--up",
        "z",
    ]));
    let c = coefficients(&v);
    assert_eq!(c.len(), 25);
    let k = 2.0 * std::f64::consts::PI.sqrt();
    for (ch, want) in [1.0, 2.0, 0.5].iter().enumerate() {
        assert!(
            (c[0][ch] - k * want).abs() < 1e-5 * k * want,
            "channel {ch}"
        );
    }
    // m != 0 terms cancel exactly over each ring; the zonal ones carry the
    // texel-centre rule's O(dθ²) error (dθ = π/64).
    for (i, r) in c.iter().enumerate().skip(1) {
        let m_is_zero = [2, 6, 12, 20].contains(&i);
        let tol = if m_is_zero { 5e-3 } else { 1e-6 };
        assert!(r.iter().all(|x| x.abs() < tol), "coefficient {i}: {r:?}");
    }
    // Irradiance of constant radiance L is pi L: E_00 = pi * L_00.
    let e = coefficients(&json(&shlight(&[
        "project",
        path.to_str().unwrap(),
        "--quantity",
        "irradiance",
    ])));
    assert!((e[0][0] - std::f64::consts::PI * k).abs() < 1e-4);
    assert_eq!(v["quantity"], "radiance");
    assert_eq!(v["basis"]["condon_shortley_phase"], true);
    assert_eq!(v["frame"], "z-up");
}

#[test]
fn output_file_is_written_and_read_back() {
    let dir = temp_dir("output");
    let map = dir.join("m.exr");
    write_map(&map, 32, 16, |x, y| [x as f32, y as f32, 1.0]);
    let out = dir.join("m.json");
    let o = shlight(&[
        "project",
        map.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["lmax"], 2);
    assert_eq!(v["provenance"]["width"], 32);
    let show = shlight(&["show", out.to_str().unwrap()]);
    assert!(show.status.success());
    let table = String::from_utf8_lossy(&show.stdout);
    assert!(
        table.contains("lmax 2 (9 coefficients)") && table.lines().count() == 12,
        "{table}"
    );
    // No temporary file is left beside the output.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn bad_input_fails_with_the_file_named_and_keeps_existing_output() {
    let dir = temp_dir("bad");
    let out = dir.join("keep.json");
    std::fs::write(&out, "precious").unwrap();
    let check = |args: &[&str], needle: &str| {
        let o = shlight(args);
        assert!(!o.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
    };
    let missing = dir.join("missing.exr");
    check(
        &[
            "project",
            missing.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        "missing.exr",
    );
    let square = dir.join("square.exr");
    write_map(&square, 16, 16, |_, _| [1.0; 3]);
    check(
        &[
            "project",
            square.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        "square.exr",
    );
    let truncated = dir.join("truncated.exr");
    write_map(&truncated, 64, 32, |x, _| [x as f32; 3]);
    let bytes = std::fs::read(&truncated).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    check(
        &[
            "project",
            truncated.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        "truncated.exr",
    );
    let nan = dir.join("nan.exr");
    write_map(&nan, 32, 16, |x, y| {
        if (x, y) == (3, 5) {
            [f32::NAN; 3]
        } else {
            [1.0; 3]
        }
    });
    check(
        &[
            "project",
            nan.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        "x=3, y=5",
    );
    check(&["project", "Cargo.toml"], "Cargo.toml");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "precious");
}

//! `shlight project`: orientation, output, and bad input.

use crate::util::{band1_direction, coefficients, json, shlight, temp_dir, write_map, write_spot};

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
    write_spot(&spot, w, h, (16, 16), 1, [1000.0, 0.0, 0.0]);
    // Row 0, all columns: up (+Y in y-up, +Z in z-up).
    let top = dir.join("top.exr");
    write_map(&top, w, h, |_, y| {
        if y == 0 { [1000.0, 0.0, 0.0] } else { [0.0; 3] }
    });
    // Centre column faces +X in both frames.
    let centre = dir.join("centre.exr");
    write_spot(&centre, w, h, (32, 16), 1, [1000.0, 0.0, 0.0]);

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
    // The minimum of a constant is the constant; past lmax 16 the (lmax^4)
    // search is skipped and the field is null, so high lmax stays fast.
    let m = &v["statistics"]["minimum"]["green"]["value"];
    assert!((m.as_f64().unwrap() - 2.0).abs() < 1e-3, "{m}");
    let hi = json(&shlight(&[
        "project",
        path.to_str().unwrap(),
        "--lmax",
        "40",
    ]));
    assert!(
        hi["statistics"]["minimum"]["red"].is_null(),
        "{}",
        hi["statistics"]
    );
    assert_eq!(coefficients(&hi).len(), 41 * 41);
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
    // 5:3 fits no layout (a square image is an angular map).
    let odd = dir.join("odd.exr");
    write_map(&odd, 20, 12, |_, _| [1.0; 3]);
    check(
        &[
            "project",
            odd.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        "odd.exr",
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

#[test]
fn sanitize_replaces_bad_values_and_records_the_counts() {
    use crate::util::{assert_rows_near, project_rows, read_json, s, shlight_err, shlight_ok};
    let dir = temp_dir("sanitize");
    let dirty = |x: usize, y: usize| -> [f32; 3] {
        match (x, y) {
            (3, 5) => [f32::NAN; 3],
            (7, 2) => [f32::INFINITY, 1.0, 1.0],
            (1, 1) => [1.0, f32::NEG_INFINITY, 1.0],
            (10, 10) => [-0.5; 3],
            _ => [1.0, 0.5 + x as f32 / 64.0, 0.25],
        }
    };
    let map = dir.join("dirty.exr");
    write_map(&map, 32, 16, dirty);
    // What --sanitize documents: NaN, -inf, negatives to 0; +inf to the largest finite value.
    let clean = dir.join("clean.exr");
    write_map(&clean, 32, 16, |x, y| {
        let largest = 1.0f32; // the largest finite value of the dirty map
        dirty(x, y).map(|v| {
            if v == f32::INFINITY {
                largest
            } else if v.is_nan() || v < 0.0 {
                0.0
            } else {
                v
            }
        })
    });

    let err = shlight_err(&["project", s(&map)]);
    assert!(
        err.contains("x=1, y=1") && err.contains("--sanitize"),
        "{err}"
    );

    let out = dir.join("dirty.json");
    let o = shlight_ok(&[
        "project",
        s(&map),
        "--sanitize",
        "-o",
        s(&out),
        "--lmax",
        "3",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--sanitize replaced 8 values"), "{err}");
    let v = read_json(&out);
    let counts = &v["statistics"]["sanitized"];
    assert_eq!(counts["nan"], 3);
    assert_eq!(counts["positive_infinite"], 1);
    assert_eq!(counts["negative_infinite"], 1);
    assert_eq!(counts["negative"], 3);
    assert_eq!(counts["infinity_replacement"], 1.0);
    // The statistics of the input describe it as read.
    assert_eq!(v["statistics"]["input_negative_texels"], 3);
    let want = project_rows(&clean, &["--lmax", "3"]);
    assert_rows_near(&crate::util::coefficients(&v), &want, 1e-12, "sanitized");
    // --quiet silences the warning; without --sanitize the record is null.
    let o = shlight_ok(&["project", s(&map), "--sanitize", "--quiet"]);
    assert!(o.stderr.is_empty());
    let plain = json(&shlight(&["project", s(&clean)]));
    assert!(plain["statistics"]["sanitized"].is_null());
}

#[test]
fn negatives_warn_unless_quiet_and_a_clean_run_prints_nothing_on_stderr() {
    use crate::util::{s, shlight_ok};
    let dir = temp_dir("quiet");
    let map = dir.join("neg.exr");
    write_map(
        &map,
        32,
        16,
        |x, _| if x == 4 { [-0.25; 3] } else { [1.0; 3] },
    );
    let o = shlight_ok(&["project", s(&map)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("warning") && err.contains("48 negative texels"),
        "{err}"
    );
    let o = shlight_ok(&["project", s(&map), "-q"]);
    assert!(o.stderr.is_empty());
    // No progress bar when stderr is not a terminal.
    let ok = dir.join("ok.exr");
    write_map(&ok, 32, 16, |_, _| [1.0; 3]);
    let o = shlight_ok(&["project", s(&ok), "--lmax", "8"]);
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // --quiet does not silence errors.
    let err = crate::util::shlight_err(&["project", s(&dir.join("nope.exr")), "-q"]);
    assert!(err.contains("nope.exr"), "{err}");
}

#[test]
fn rotate_carries_a_bright_spot_to_the_rotated_direction() {
    use crate::util::{read_json, s};
    let dir = temp_dir("rotate");
    let (w, h) = (64, 32);
    // The centre column at the equator faces +X in both frames.
    let centre = dir.join("centre.exr");
    write_spot(&centre, w, h, (32, 16), 1, [1000.0, 0.0, 0.0]);
    let tol = 0.1; // the texel centre sits half a texel off +X
    let s45 = std::f64::consts::FRAC_1_SQRT_2.to_string();
    let quat_z = format!("quat:0,0,{s45},{s45}");
    for (up, spec, want) in [
        ("y", "yaw:90", [0.0, 0.0, -1.0]),
        ("z", "yaw:90", [0.0, 1.0, 0.0]),
        ("y", "yaw:-90", [0.0, 0.0, 1.0]),
        ("y", quat_z.as_str(), [0.0, 1.0, 0.0]),
        ("y", "euler:0,0,90", [0.0, 1.0, 0.0]),
        ("z", "euler:0,-90,0", [0.0, 0.0, 1.0]),
    ] {
        let v = json(&shlight(&[
            "project",
            s(&centre),
            "--lmax",
            "3",
            "--up",
            up,
            "--rotate",
            spec,
        ]));
        assert_near(
            band1_direction(&coefficients(&v)),
            want,
            tol,
            &format!("{up} {spec}"),
        );
        assert_eq!(v["provenance"]["rotate"]["spec"], spec);
    }
    // The matrix is recorded rows first: yaw:90 in y-up takes +X to -Z (column 0).
    let out = dir.join("r.json");
    let o = shlight(&["project", s(&centre), "--rotate", "yaw:90", "-o", s(&out)]);
    assert!(o.status.success());
    let m = &read_json(&out)["provenance"]["rotate"]["matrix"];
    let col0 = [0, 1, 2].map(|r| m[r][0].as_f64().unwrap());
    assert_near(col0, [0.0, 0.0, -1.0], 1e-12, "matrix column 0");
    // Unrotated files record null.
    let v = json(&shlight(&["project", s(&centre)]));
    assert!(v["provenance"]["rotate"].is_null());
    for bad in ["yaw", "spin:30", "quat:0,0,0,0", "euler:1,2"] {
        let o = shlight(&["project", s(&centre), "--rotate", bad]);
        assert!(!o.status.success(), "{bad}");
        assert!(
            String::from_utf8_lossy(&o.stderr).contains("--rotate"),
            "{bad}"
        );
    }
}

#[test]
fn auto_window_is_chosen_per_channel() {
    use crate::util::{assert_rows_near, project_rows, s};
    let dir = temp_dir("window_per_channel");
    // Red: a bright spot on a dim sky (rings negative); green: constant
    // (needs nothing); blue: a weaker spot (needs a weaker window).
    let map = dir.join("m.exr");
    write_map(&map, 64, 32, |x, y| {
        let spot = x == 20 && y == 10;
        [
            if spot { 500.0 } else { 0.05 },
            1.0,
            if spot { 100.0 } else { 0.1 },
        ]
    });
    let v = json(&shlight(&[
        "project",
        s(&map),
        "--lmax",
        "6",
        "--window",
        "auto",
    ]));
    let windows = &v["provenance"]["windows"];
    assert_eq!(v["provenance"]["window"], "auto");
    let red = windows["red"].as_str().unwrap();
    let blue = windows["blue"].as_str().unwrap();
    assert!(
        red.starts_with("hanning:") && blue.starts_with("hanning:"),
        "{windows}"
    );
    assert_eq!(windows["green"], "none");
    assert_ne!(red, blue, "each channel gets its own window");
    let got = coefficients(&v);
    // Each channel is its own window applied to the unwindowed projection.
    for (c, spec) in [(0, red), (1, "none"), (2, blue)] {
        let want = project_rows(&map, &["--lmax", "6", "--window", spec]);
        let pick =
            |rows: &[[f64; 3]]| -> Vec<[f64; 3]> { rows.iter().map(|r| [r[c]; 3]).collect() };
        assert_rows_near(&pick(&got), &pick(&want), 1e-12, spec);
    }
    // The table (`shlight show`, and a terminal) names the three.
    let file = dir.join("m.json");
    crate::util::shlight_ok(&[
        "project",
        s(&map),
        "--lmax",
        "6",
        "--window",
        "auto",
        "-o",
        s(&file),
    ]);
    let table =
        String::from_utf8_lossy(&crate::util::shlight_ok(&["show", s(&file)]).stdout).into_owned();
    assert!(
        table.contains(&format!("windows r {red}, g none, b {blue}")),
        "{table}"
    );
}

#[test]
fn preview_shows_input_radiance_and_irradiance_side_by_side() {
    use crate::util::{s, shlight_ok};
    let dir = temp_dir("preview");
    // A constant map: all three panels show the same value; the automatic
    // exposure puts the mean radiance at 0.18 and ACES maps that to ~0.135.
    let map = dir.join("c.exr");
    write_map(&map, 128, 64, |_, _| [2.0, 2.0, 2.0]);
    let png = dir.join("p.png");
    shlight_ok(&[
        "project",
        s(&map),
        "--preview",
        s(&png),
        "--preview-size",
        "64x32",
    ]);
    let img = shlight_io::read_image(&png, &Default::default()).unwrap();
    assert_eq!((img.width(), img.height()), (192, 32));
    let aces = shlight_io::ToneMap::Aces.apply(0.18);
    for x in [5, 64 + 5, 128 + 5, 191] {
        for y in [3, 16, 31] {
            let v = img.get(x, y);
            assert!(
                (v[0] - aces).abs() < 4e-3,
                "panel at x={x}, y={y}: {v:?} vs {aces}"
            );
        }
    }
    // A spot: panel 1 has it, panel 2 blurs it, panel 3 is smooth and wide.
    let spot = dir.join("s.exr");
    write_map(&spot, 64, 32, |x, y| {
        if (x, y) == (32, 16) {
            [100.0; 3]
        } else {
            [0.1; 3]
        }
    });
    shlight_ok(&[
        "project",
        s(&spot),
        "--preview",
        s(&png),
        "--preview-size",
        "64x32",
        "--preview-exposure",
        "0",
        "--preview-tone-map",
        "clamp",
        "--lmax",
        "4",
    ]);
    let img = shlight_io::read_image(&png, &Default::default()).unwrap();
    assert_eq!(img.get(32, 16)[0], 1.0, "input panel: the spot clips");
    assert!(
        img.get(64 + 32, 16)[0] > img.get(64 + 32, 2)[0],
        "radiance panel peaks at the spot"
    );
    assert!(
        img.get(128 + 32, 16)[0] > img.get(128 + 2, 16)[0],
        "irradiance panel faces the spot"
    );
    let err = crate::util::shlight_err(&[
        "project",
        s(&spot),
        "--preview",
        s(&png),
        "--preview-size",
        "64x64",
    ]);
    assert!(err.contains("--preview-size"), "{err}");
}

#[test]
fn too_large_and_empty_inputs_are_refused_with_the_file_named() {
    use crate::util::{s, shlight_err};
    let dir = temp_dir("limits");
    let out = dir.join("keep.json");
    std::fs::write(&out, "precious").unwrap();
    let map = dir.join("big.exr");
    write_map(&map, 64, 32, |_, _| [1.0; 3]);
    let err = shlight_err(&["project", s(&map), "--max-pixels", "1000", "-o", s(&out)]);
    assert!(
        err.contains("big.exr") && err.contains("too large"),
        "{err}"
    );
    // The setting that raises the limit, as the command line spells it.
    assert!(err.contains("raise the limit with --max-pixels"), "{err}");
    let empty = dir.join("empty.exr");
    std::fs::write(&empty, b"").unwrap();
    let err = shlight_err(&["project", s(&empty), "-o", s(&out)]);
    assert!(err.contains("empty.exr") && err.contains("empty"), "{err}");
    let err = shlight_err(&["project", s(&map), "--window", "bogus:3", "-o", s(&out)]);
    assert!(err.contains("--window"), "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "precious");
}

/// Every `--format` but json, with the extension `-o DIR` gives it.
const EXPORT_FORMATS: [(&str, &str); 9] = [
    ("txt", "txt"),
    ("threejs", "json"),
    ("gltf", "gltf"),
    ("filament", "txt"),
    ("unity", "json"),
    ("wgsl", "wgsl"),
    ("glsl", "glsl"),
    ("hlsl", "hlsl"),
    ("c", "h"),
];

/// `a` and `b` are the same text with the same numbers, up to the last
/// bits of a number (the coefficient file's JSON is read back to within an
/// ulp or so), and three.js's uuid (a hash of those bits) aside.
fn assert_same_text_and_numbers(a: &str, b: &str, what: &str) {
    let tokens = |t: &str| -> Vec<String> {
        t.split(|c: char| !(c.is_ascii_alphanumeric() || "._+-".contains(c)))
            .filter(|w| !w.is_empty())
            .map(str::to_string)
            .collect()
    };
    let (ta, tb) = (tokens(a), tokens(b));
    assert_eq!(ta.len(), tb.len(), "{what}: token counts\n{a}\n{b}");
    for (k, (x, y)) in ta.iter().zip(&tb).enumerate() {
        if k > 0 && ta[k - 1] == "uuid" {
            continue;
        }
        // C# and HLSL float literals end in f.
        let number = |w: &str| w.strip_suffix('f').unwrap_or(w).parse::<f64>();
        match (number(x), number(y)) {
            (Ok(u), Ok(v)) => assert!(
                (u - v).abs() <= 1e-15 * u.abs().max(v.abs()),
                "{what}: {x} vs {y}"
            ),
            _ => assert_eq!(x, y, "{what}: token {k}"),
        }
    }
}

#[test]
fn project_format_writes_what_convert_writes_from_the_coefficient_file() {
    use crate::util::{read_json, s, shlight_ok};
    let dir = temp_dir("project_formats");
    let map = dir.join("m.exr");
    write_map(&map, 64, 32, |x, y| {
        [1.0 + x as f32 / 64.0, 0.5 + y as f32 / 32.0, 0.25]
    });
    let file = dir.join("m.json");
    shlight_ok(&["project", s(&map), "-o", s(&file)]);
    for (format, _) in EXPORT_FORMATS {
        let direct = dir.join(format!("direct-{format}"));
        let via = dir.join(format!("via-{format}"));
        shlight_ok(&[
            "project",
            s(&map),
            "--format",
            format,
            "-o",
            s(&direct),
            "--specular-size",
            "8",
        ]);
        shlight_ok(&[
            "convert",
            s(&file),
            "--format",
            format,
            "-o",
            s(&via),
            "--irradiance-only",
        ]);
        let text = std::fs::read_to_string(&direct).unwrap();
        let via_text = std::fs::read_to_string(&via).unwrap();
        if format == "gltf" {
            // From the map the light also carries its specular images; its
            // coefficients are the file's.
            let light = |t: &str| {
                let v: serde_json::Value = serde_json::from_str(t).unwrap();
                v["extensions"]["EXT_lights_image_based"]["lights"][0]["irradianceCoefficients"]
                    .to_string()
            };
            assert_same_text_and_numbers(&light(&text), &light(&via_text), format);
            assert!(text.contains("specularImages") && !via_text.contains("\"specularImages\""));
        } else {
            assert_same_text_and_numbers(&text, &via_text, format);
        }
        assert!(!text.trim().is_empty(), "{format}");
        // Filament's sh.txt is nine bare lines, as cmgen prints them.
        let header: String = text.lines().take(4).collect::<Vec<_>>().join("\n");
        if format == "filament" {
            assert_eq!(text.lines().count(), 9, "{text}");
            assert!(
                header.contains("L00, irradiance, pre-scaled base"),
                "{header}"
            );
        } else if text.starts_with('{') {
            assert!(text.contains("shlight"), "{format}: {text}");
        } else {
            assert!(header.contains("shlight"), "{format}: {header}");
        }
    }
    // The same numbers as the file: three.js holds the radiance without
    // the CS phase (odd |m| negated), y-up.
    let probe = read_json(&dir.join("direct-threejs"));
    let sh: Vec<f64> = probe["object"]["sh"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let rows = coefficients(&read_json(&file));
    for (i, row) in rows.iter().enumerate() {
        let sign = if [1, 3, 5, 7].contains(&i) { -1.0 } else { 1.0 };
        for c in 0..3 {
            let want = sign * row[c];
            assert!(
                (sh[3 * i + c] - want).abs() <= 1e-12 * want.abs().max(1.0),
                "coefficient {i} channel {c}: {} vs {want}",
                sh[3 * i + c]
            );
        }
    }
    // txt is the Ramamoorthi-Hanrahan table, not the `show` table.
    let txt = std::fs::read_to_string(dir.join("direct-txt")).unwrap();
    assert!(
        txt.contains("Ramamoorthi-Hanrahan") && txt.contains("L2-2"),
        "{txt}"
    );
    // An explicit --format json is the default.
    let default = shlight_ok(&["project", s(&map)]).stdout;
    let explicit = shlight_ok(&["project", s(&map), "--format", "json"]).stdout;
    assert_eq!(default, explicit);
}

#[test]
fn formats_go_to_stdout_name_their_notes_and_batches_get_their_extension() {
    use crate::util::{s, shlight_ok};
    let dir = temp_dir("project_format_io");
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    write_map(&a, 32, 16, |x, _| [x as f32, 1.0, 2.0]);
    write_map(&b, 32, 16, |_, y| [1.0, y as f32, 0.5]);
    // C to stdout: the snippet, nothing on stderr.
    let o = shlight_ok(&["project", s(&a), "--format", "c"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.starts_with("// shlight")
            && text.contains("static const double shlight_coeffs")
            && text.contains("shlight_irradiance"),
        "{text}"
    );
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // An engine format's notes name the input; --quiet silences them.
    let o = shlight_ok(&["project", s(&a), "--lmax", "4", "--format", "threejs"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("note:") && err.contains("a.exr") && err.contains("dropped"),
        "{err}"
    );
    let o = shlight_ok(&["-q", "project", s(&a), "--lmax", "4", "--format", "threejs"]);
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // -o DIR: one file per input with the format's extension.
    for (format, ext) in EXPORT_FORMATS {
        let out = dir.join(format!("out-{format}"));
        shlight_ok(&[
            "-q",
            "project",
            s(&a),
            s(&b),
            "--format",
            format,
            "-o",
            s(&out),
            "--specular-size",
            "8",
        ]);
        let mut names: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, [format!("a.{ext}"), format!("b.{ext}")], "{format}");
    }
}

/// From lmax 129 on, the file's `coefficients` are base64 of little-endian
/// f64 (docs/coefficient-file.md): decoded here by hand, their first rows
/// equal the decimal rows of the same map projected to lmax 3, and the
/// whole file reads back through `shlight show`.
#[test]
fn high_lmax_files_hold_binary_coefficients_equal_to_the_decimal_rows() {
    use base64::Engine;
    let dir = temp_dir("binary_coefficients");
    let map = dir.join("map.exr");
    write_map(&map, 512, 256, |x, y| {
        [1.0 + (x % 7) as f32 * 0.1, 0.5 + (y % 5) as f32 * 0.2, 0.25]
    });
    let low = json(&shlight(&["project", map.to_str().unwrap(), "--lmax", "3"]));
    let high = json(&shlight(&[
        "project",
        map.to_str().unwrap(),
        "--lmax",
        "130",
    ]));
    let c = &high["coefficients"];
    assert_eq!(c["dtype"], "<f8");
    assert_eq!(c["shape"], serde_json::json!([131 * 131, 3]));
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(c["base64"].as_str().unwrap())
        .unwrap();
    assert_eq!(bytes.len(), 131 * 131 * 24);
    let f = |i: usize| f64::from_le_bytes(bytes[i * 8..i * 8 + 8].try_into().unwrap());
    for (i, row) in coefficients(&low).iter().enumerate() {
        for (k, want) in row.iter().enumerate() {
            let got = f(i * 3 + k);
            // The two lmax take different ring-transform paths (direct sums
            // against FFTs): rounding apart only.
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1e-3),
                "row {i}: {got} vs {want}"
            );
        }
    }
    let path = dir.join("high.json");
    let out = shlight(&[
        "project",
        map.to_str().unwrap(),
        "--lmax",
        "130",
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let table = shlight(&["show", path.to_str().unwrap()]);
    assert!(
        table.status.success(),
        "{}",
        String::from_utf8_lossy(&table.stderr)
    );
    assert_eq!(
        String::from_utf8_lossy(&table.stdout)
            .lines()
            .filter(|l| l.starts_with(" 130 "))
            .count(),
        261
    );
}

/// Output piped into a reader that stops early ends the process quietly,
/// never with a panic about a broken pipe.
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_the_output_quietly() {
    use std::io::{BufRead, BufReader};
    use std::process::{Command, Stdio};
    let dir = temp_dir("closed_pipe");
    let map = dir.join("map.exr");
    write_map(&map, 256, 128, |x, _| [x as f32 * 0.01, 1.0, 0.5]);
    let path = dir.join("c.json");
    let out = shlight(&[
        "project",
        map.to_str().unwrap(),
        "--lmax",
        "60",
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let mut child = Command::new(env!("CARGO_BIN_EXE_shlight"))
        .args(["show", path.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.starts_with("# shlight"), "{first}");
    // The reader is gone; the table (3721 rows) is far longer than a pipe's buffer.
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("panicked") && !stderr.contains("Broken pipe"),
        "{stderr}"
    );
}

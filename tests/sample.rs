//! `shlight sample`: a volume's irradiance at points and a PRT file's exit
//! radiance, against closed forms and against the GPU's own volume pass.

use std::f64::consts::PI;
use std::path::Path;

use serde_json::Value;
use shlight_format::ShvolFile;

use crate::util::{shlight, shlight_ok, temp_dir, write_two_rooms};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Two probes along x of lmax 1 on the box (0,0,0)..(2,1,1): probe 0 a
/// grey-ish L00, probe 1 L00 and an L11 (light along -x); relightable with
/// identity transfer matrices and no emitters, when asked.
fn two_probes(relightable: bool) -> ShvolFile {
    let nc = 4;
    let mut radiance = vec![0.0f32; 2 * nc * 3];
    radiance[..3].copy_from_slice(&[1.0, 2.0, 3.0]);
    radiance[12..15].copy_from_slice(&[2.0, 2.0, 2.0]);
    radiance[21..24].copy_from_slice(&[-0.5, -0.5, -0.5]);
    let identity: Vec<f32> = (0..2 * 3)
        .flat_map(|_| (0..nc * nc).map(|k| if k % (nc + 1) == 0 { 1.0 } else { 0.0 }))
        .collect();
    ShvolFile {
        lmax: 1,
        resolution: [2, 1, 1],
        bounds: ([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]),
        frame: "y-up".into(),
        valid: vec![true, true],
        radiance,
        emitted: relightable.then(|| vec![0.0; 2 * nc * 3]),
        transfer: relightable.then_some(identity),
        offsets: None,
        visibility: None,
        rays_per_probe: 1,
        bounces: 0,
        seed: 0,
        scene: "two probes".into(),
        scene_hash: 0,
        environment: "by hand".into(),
        generator: "tests/sample.rs".into(),
        lights: None,
    }
}

fn values(v: &Value, key: &str) -> Vec<[f64; 3]> {
    v[key]
        .as_array()
        .unwrap_or_else(|| panic!("no {key}: {v}"))
        .iter()
        .map(|r| [0, 1, 2].map(|c| r[c].as_f64().unwrap()))
        .collect()
}

/// The irradiance of the interpolated probes, worked out by hand:
/// `E = pi L00 Y00 + 2 pi / 3 L11 Y11(n)`, `Y00 = 1 / (2 sqrt(pi))`,
/// `Y11 = -sqrt(3 / 4 pi) n.x`; JSON and CSV give the same numbers.
#[test]
fn a_volume_gives_the_closed_form_of_its_interpolated_probes() {
    let dir = temp_dir("sample-closed-form");
    let vol = dir.join("two.shvol");
    two_probes(false).write(&vol).unwrap();
    let points = dir.join("points.json");
    std::fs::write(
        &points,
        r#"{"points": [[0.75, 0.5, 0.5], [0.75, 0.2, 0.9], [1.5, 0.5, 0.5], [-3, 0.5, 0.5]],
            "normals": [[1, 0, 0], [-2, 0, 0], [0, 1, 0], [1, 1, 0]]}"#,
    )
    .unwrap();
    let out = dir.join("e.json");
    shlight_ok(&["sample", s(&vol), "--points", s(&points), "-o", s(&out)]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["format"], "shlight-samples");
    // The default lookup of a file without distance maps is trilinear,
    // and the output says so.
    assert_eq!(v["lookup"], "trilinear");
    assert_eq!(v["visibility"], false);
    assert_eq!(v["lmax"], 1);
    assert_eq!(v["count"], 4);
    assert_eq!(v["provenance"]["scene"], "two probes");
    let c1 = (3.0 / (4.0 * PI)).sqrt();
    let y00 = 0.5 / PI.sqrt();
    let e = |w1: f64, nx: f64| {
        let l00 = [1.0, 2.0, 3.0].map(|c| (1.0 - w1) * c + w1 * 2.0);
        let l11 = -0.5 * w1;
        l00.map(|l| PI * l * y00 + 2.0 * PI / 3.0 * l11 * (-c1 * nx))
    };
    let want = [
        e(0.25, 1.0),
        e(0.25, -1.0),
        e(1.0, 0.0),
        // Outside the box: clamped to probe 0.
        e(0.0, std::f64::consts::FRAC_1_SQRT_2),
    ];
    let got = values(&v, "irradiance");
    for (g, w) in got.iter().zip(&want) {
        for c in 0..3 {
            assert!((g[c] - w[c]).abs() < 1e-5, "{got:?} vs {want:?}");
        }
    }
    // CSV in and out: the same numbers.
    let csv_points = dir.join("points.csv");
    std::fs::write(
        &csv_points,
        "x,y,z,nx,ny,nz\n0.75,0.5,0.5,1,0,0\n0.75,0.2,0.9,-2,0,0\n1.5,0.5,0.5,0,1,0\n-3,0.5,0.5,1,1,0\n",
    )
    .unwrap();
    let csv = dir.join("e.csv");
    shlight_ok(&[
        "sample",
        s(&vol),
        "--points",
        s(&csv_points),
        "-o",
        s(&csv),
        "--lookup",
        "trilinear",
    ]);
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<[f64; 3]> = text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [f[0], f[1], f[2]]
        })
        .collect();
    assert_eq!(text.lines().next(), Some("r,g,b"));
    assert_eq!(rows, got);
    // lmax 0 drops the directional term.
    shlight_ok(&[
        "sample",
        s(&vol),
        "--points",
        s(&points),
        "-o",
        s(&out),
        "--lmax",
        "0",
    ]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let g0 = values(&v, "irradiance");
    assert!((g0[0][0] - g0[1][0]).abs() < 1e-9 && (g0[0][0] - g0[1][0]).abs() < 1e-9);
}

/// A relightable volume relit under a constant sky of radiance `c` holds
/// `c` at every probe (identity transfer): the irradiance is `pi c`
/// facing anywhere. A static volume refuses `--env`.
#[test]
fn env_relights_a_relightable_volume_first() {
    let dir = temp_dir("sample-relight");
    let vol = dir.join("relit.shvol");
    two_probes(true).write(&vol).unwrap();
    let sky = dir.join("sky.exr");
    shlight_ok(&[
        "synth",
        "constant",
        "-o",
        s(&sky),
        "--value",
        "0.5",
        "--size",
        "64x32",
    ]);
    let points = dir.join("p.json");
    std::fs::write(
        &points,
        r#"{"points": [[0.2, 0.1, 0.3], [1.9, 0.9, 0.6]], "normals": [[0, 1, 0], [0.3, -0.2, 0.9]]}"#,
    )
    .unwrap();
    let out = dir.join("e.json");
    shlight_ok(&[
        "sample",
        s(&vol),
        "--points",
        s(&points),
        "--env",
        s(&sky),
        "-o",
        s(&out),
    ]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    for e in values(&v, "irradiance") {
        for c in e {
            // The projected constant map's degree-1 terms are within the
            // quadrature's O(h^2) of zero.
            assert!((c - PI * 0.5).abs() < 1e-3 * PI, "{e:?}");
        }
    }
    let fixed = dir.join("static.shvol");
    two_probes(false).write(&fixed).unwrap();
    let o = shlight(&[
        "sample",
        s(&fixed),
        "--points",
        s(&points),
        "--env",
        s(&sky),
        "-o",
        s(&out),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("static.shvol") && err.contains("--static"),
        "{err}"
    );
}

/// Writes `points` and `normals` as a POINTS.json file.
fn write_points(path: &Path, points: &[[f64; 3]], normals: &[[f64; 3]]) {
    let json = serde_json::json!({"points": points, "normals": normals});
    std::fs::write(path, json.to_string()).unwrap();
}

/// `--lookup bevy` at points where Bevy's ambient cube is exact, worked
/// out by hand from the two probes' SH: at a probe facing an axis, the
/// probe's `E = pi L00 Y00 + 2 pi / 3 L11 Y11(n)`; facing between two axes,
/// `N^2`-weighted axis values; halfway between the probes along x, their
/// mean; outside the volume's box, nothing (Bevy lights it from
/// elsewhere). Within the texels' half floats.
#[test]
fn lookup_bevy_gives_bevys_ambient_cubes() {
    let dir = temp_dir("sample-bevy");
    let vol = dir.join("two.shvol");
    two_probes(false).write(&vol).unwrap();
    let points = dir.join("p.json");
    let d = std::f64::consts::FRAC_1_SQRT_2;
    write_points(
        &points,
        &[
            [0.5, 0.5, 0.5],
            [1.5, 0.5, 0.5],
            [1.0, 0.2, 0.9],
            [-3.0, 0.5, 0.5],
        ],
        &[
            [1.0, 0.0, 0.0],
            [d, d, 0.0],
            [-1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
        ],
    );
    let out = dir.join("e.json");
    shlight_ok(&[
        "sample",
        s(&vol),
        "--points",
        s(&points),
        "--lookup",
        "bevy",
        "-o",
        s(&out),
    ]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["lookup"], "bevy");
    assert_eq!(v["lmax"], 1);
    let (y00, c1) = (0.5 / PI.sqrt(), (3.0 / (4.0 * PI)).sqrt());
    // Probe 0: L00 = (1, 2, 3), nothing else; probe 1: L00 = 2, L11 = -0.5
    // (so E(+-x) = 2 pi Y00 +- pi / 3 sqrt(3 / 4 pi)).
    let e0 = [1.0, 2.0, 3.0].map(|l| PI * y00 * l);
    let e1 = |nx: f64| [2.0 * PI * y00 + nx * PI / 3.0 * c1; 3];
    let want = [
        e0,
        [0, 1, 2].map(|c| 0.5 * e1(1.0)[c] + 0.5 * e1(0.0)[c]),
        [0, 1, 2].map(|c| 0.5 * e0[c] + 0.5 * e1(-1.0)[c]),
        [0.0; 3],
    ];
    let got = values(&v, "irradiance");
    for (g, w) in got.iter().zip(&want) {
        for c in 0..3 {
            assert!(
                (g[c] - w[c]).abs() <= 1e-3 * w[c].abs(),
                "{got:?} vs {want:?}"
            );
        }
    }
}

/// `--lookup threejs` by three.js's formula worked out by hand for the two
/// probes (spacing 1 on every axis, probes at x = 0.5 and 1.5): the point
/// moved half a spacing along the normal, x clamped to the probes, the
/// interpolated three.js coefficients (`c3 = -L11`: no Condon-Shortley
/// phase), `0.886227 c0 + 2 0.511664 c3 x`; nothing where the moved point
/// leaves the box. A volume of lmax 3 is clipped to 2 with a note; `--lmax
/// 3` is refused.
#[test]
fn lookup_threejs_gives_threejs_light_probe_grid() {
    let dir = temp_dir("sample-threejs");
    let vol = dir.join("two.shvol");
    two_probes(false).write(&vol).unwrap();
    let points = dir.join("p.json");
    write_points(
        &points,
        &[
            [0.6, 0.5, 0.5],
            [0.6, 0.5, 0.7],
            [0.2, 0.5, 0.5],
            [1.9, 0.5, 0.5],
        ],
        &[
            [2.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0],
        ],
    );
    let out = dir.join("e.json");
    let run = |vol: &Path, extra: &[&str]| -> (Value, String) {
        let mut args = vec![
            "sample",
            s(vol),
            "--points",
            s(&points),
            "--lookup",
            "threejs",
            "-o",
            s(&out),
        ];
        args.extend(extra);
        let o = shlight_ok(&args);
        let v = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        (v, String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (v, _) = run(&vol, &[]);
    assert_eq!(v["lookup"], "threejs");
    assert_eq!(v["lmax"], 1);
    assert_eq!(v["notes"], serde_json::json!([]));
    // w: the weight of probe 1; nx the normal's x.
    let e = |w: f64, nx: f64| {
        let c3 = -(w * -0.5);
        [1.0, 2.0, 3.0].map(|l| 0.886227 * ((1.0 - w) * l + w * 2.0) + 2.0 * 0.511664 * c3 * nx)
    };
    let want = [
        // Moved to x = 1.1: grid coordinate 0.6.
        e(0.6, 1.0),
        // Moved to z = 1.2, beyond the box's 1 + 0.01.
        [0.0; 3],
        // Moved to y = 1.0, still in the box; x = 0.2 clamped to probe 0.
        e(0.0, 0.0),
        // Moved to x = 1.4: grid coordinate 0.9.
        e(0.9, -1.0),
    ];
    let got = values(&v, "irradiance");
    for (g, w) in got.iter().zip(&want) {
        for c in 0..3 {
            assert!((g[c] - w[c]).abs() < 1e-5, "{got:?} vs {want:?}");
        }
    }
    // lmax 3: the same probes with a degree-3 term three.js cannot hold.
    let mut deep = two_probes(false);
    deep.lmax = 3;
    deep.radiance = deep
        .radiance
        .chunks_exact(12)
        .flat_map(|p| {
            let mut rows = p.to_vec();
            rows.resize(16 * 3, 0.0);
            rows[10 * 3..10 * 3 + 3].copy_from_slice(&[5.0, 5.0, 5.0]);
            rows
        })
        .collect();
    let deep_vol = dir.join("deep.shvol");
    deep.write(&deep_vol).unwrap();
    let (v, stderr) = run(&deep_vol, &[]);
    assert_eq!(v["lmax"], 2);
    assert!(v["notes"][0].as_str().unwrap().contains("left out"), "{v}");
    assert!(
        stderr.contains("note:") && stderr.contains("degree 3 is left out"),
        "{stderr}"
    );
    assert_eq!(values(&v, "irradiance"), got);
    let o = shlight(&[
        "sample",
        s(&deep_vol),
        "--points",
        s(&points),
        "--lookup",
        "threejs",
        "--lmax",
        "3",
        "-o",
        s(&out),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("deep.shvol") && err.contains("lmax 2 at most"),
        "{err}"
    );
}

/// Unshadowed PRT transfer of a surface of albedo `rho` under a constant
/// sky of radiance `c`: every vertex leaves `rho c` (the cosine integral
/// over the hemisphere is `pi`).
#[test]
fn a_prt_file_gives_each_vertexs_exit_radiance() {
    let dir = temp_dir("sample-prt");
    let prt = dir.join("bunny.shprt");
    shlight_ok(&[
        "prt",
        "meshes/bunny.obj",
        "--mode",
        "unshadowed",
        "--samples",
        "256",
        "--albedo",
        "0.8,0.5,0.25",
        "-o",
        s(&prt),
    ]);
    let sky = dir.join("sky.exr");
    shlight_ok(&[
        "synth",
        "constant",
        "-o",
        s(&sky),
        "--value",
        "2",
        "--size",
        "64x32",
    ]);
    let out = dir.join("l.json");
    shlight_ok(&["sample", s(&prt), "--light", s(&sky), "-o", s(&out)]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let file = shlight_format::ShprtFile::read(&prt).unwrap();
    let got = values(&v, "radiance");
    assert_eq!(got.len(), file.vertex_count);
    let mut worst = 0.0f64;
    for l in &got {
        for (c, rho) in [0.8, 0.5, 0.25].into_iter().enumerate() {
            worst = worst.max((l[c] - 2.0 * rho).abs() / (2.0 * rho));
        }
    }
    assert!(worst < 0.02, "worst relative error {worst:.3e}");
    eprintln!("unshadowed furnace: worst {worst:.2e} of rho c");
    // What a volume needs, a PRT file refuses, and the reverse.
    let o = shlight(&[
        "sample",
        s(&prt),
        "--light",
        s(&sky),
        "--points",
        s(&sky),
        "-o",
        s(&out),
    ]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("--points samples a volume"));
    let o = shlight(&["sample", s(&prt), "-o", s(&out)]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("needs --light"));
    let o = shlight(&["sample", s(&sky), "--light", s(&sky), "-o", s(&out)]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("sample reads irradiance volumes"));
}

/// Bad points files are refused naming the file, and nothing is written.
#[test]
fn bad_points_are_refused_naming_the_file() {
    let dir = temp_dir("sample-bad");
    let vol = dir.join("two.shvol");
    two_probes(false).write(&vol).unwrap();
    let out = dir.join("e.json");
    for (name, text, want) in [
        ("a.json", r#"{"points": [[0, 0, 0]]}"#, "no \"normals\""),
        (
            "b.json",
            r#"{"points": [[0, 0, 0]], "normals": [[0, 0, 0]]}"#,
            "not a direction",
        ),
        ("c.csv", "1,2,3\n", "line 1"),
    ] {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let o = shlight(&["sample", s(&vol), "--points", s(&p), "-o", s(&out)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains(name) && err.contains(want),
            "{err}"
        );
        assert!(!out.exists());
    }
    let o = shlight(&["sample", s(&vol), "-o", s(&out)]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("needs --points"));
    let o = shlight(&[
        "sample",
        s(&vol),
        "--points",
        s(&vol),
        "-o",
        s(&out),
        "--lmax",
        "5",
    ]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("lmax 4 at most"));
}

/// A baked volume sampled by the CLI gives what the GPU's volume pass
/// computes at the same points (its compute entry, the fragments' code).
#[cfg(feature = "gpu")]
#[test]
fn sampling_equals_the_gpus_volume_pass() {
    use glam::Vec3;
    let Some(ctx) = crate::util::gpu_context("sampling_equals_the_gpus_volume_pass") else {
        return;
    };
    let dir = temp_dir("sample-gpu");
    let light = dir.join("sun.json");
    let sun = dir.join("sun.exr");
    shlight_ok(&[
        "synth",
        "directional",
        "-o",
        s(&sun),
        "--direction=-0.4,0.8,0.45",
        "--value",
        "3",
        "--size",
        "64x32",
    ]);
    shlight_ok(&["project", s(&sun), "--lmax", "4", "-o", s(&light)]);
    let vol = dir.join("cornell.shvol");
    shlight_ok(&[
        "volume",
        "meshes/cornell_box.obj",
        "--env",
        s(&light),
        "--resolution",
        "3x2x3",
        "--samples",
        "128",
        "--lmax",
        "4",
        "-o",
        s(&vol),
    ]);
    let file = ShvolFile::read(&vol).unwrap();
    // Baked with distance maps (the default): the GPU's pass weighs the
    // probes by visibility, as the default lookup does.
    assert!(file.visibility.is_some());
    let (lo, hi) = (
        Vec3::from_array(file.bounds.0),
        Vec3::from_array(file.bounds.1),
    );
    let mut queries = Vec::new();
    for k in 0..200u32 {
        let f = |i: u32| ((k * 2_654_435_761u32).wrapping_add(i * 40_503) % 1000) as f32 / 1000.0;
        let p = lo + (hi - lo) * Vec3::new(f(1), f(2), f(3));
        let n = Vec3::new(f(4) - 0.5, f(5) - 0.5, f(6) - 0.5).normalize_or(Vec3::Y);
        queries.push((p, n));
    }
    let points = dir.join("p.json");
    let json = serde_json::json!({
        "points": queries.iter().map(|q| q.0.to_array()).collect::<Vec<_>>(),
        "normals": queries.iter().map(|q| q.1.to_array()).collect::<Vec<_>>(),
    });
    std::fs::write(&points, json.to_string()).unwrap();
    let out = dir.join("e.json");
    shlight_ok(&["sample", s(&vol), "--points", s(&points), "-o", s(&out)]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let got = values(&v, "irradiance");
    assert_eq!(v["lookup"], "shlight", "{v}");
    let renderer =
        shlight_gpu::VolumeRenderer::new(&ctx, shlight_gpu::HEADLESS_FORMAT, &file.view()).unwrap();
    assert!(renderer.visibility());
    let shading = shlight_gpu::Shading {
        lmax: 4,
        ..shlight_gpu::Shading::default()
    };
    // The pass takes unit normals as given; `sample` normalises what it
    // reads first (a unit vector normalised again may move by a rounding),
    // so the pass gets that. Where every probe is all but shut out (points
    // inside the blocks) the weights are ratios of crushed Chebyshev
    // factors, and that rounding of the normal moved the light by 8e-6 of
    // the largest at one point (3e-7 with the same normal).
    let unit: Vec<(Vec3, Vec3)> = queries.iter().map(|&(p, n)| (p, n.normalize())).collect();
    let gpu = renderer.irradiance_at(&ctx, &shading, &unit).unwrap();
    let scale = got.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0f64;
    for (c, g) in got.iter().zip(&gpu) {
        for k in 0..3 {
            worst = worst.max((c[k] - f64::from(g[k])).abs() / scale);
        }
    }
    // The trilinear lookup, which ignores the maps, is far from both: a
    // pass that ignored them would fail.
    shlight_ok(&[
        "sample",
        s(&vol),
        "--points",
        s(&points),
        "--lookup",
        "trilinear",
        "-o",
        s(&out),
    ]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let trilinear = values(&v, "irradiance");
    let apart = trilinear
        .iter()
        .zip(&got)
        .filter(|(t, c)| (0..3).any(|k| (t[k] - c[k]).abs() / scale > 1e-3))
        .count();
    eprintln!(
        "sample against the GPU: worst {worst:.2e} of the largest; trilinear off by more than \
         1e-3 at {apart} of {} points",
        got.len()
    );
    assert!(worst < 1e-5, "worst {worst:.2e}");
    assert!(apart >= 10, "{apart}");
}

/// `shlight volume` then `shlight sample`, as a user would: the dark room's
/// floor next to the wall stays dark under the default lookup of the
/// default bake, and leaks under trilinear interpolation, as it does in a
/// bake without visibility or relocation (a version 1 file).
#[test]
fn a_bake_of_two_rooms_does_not_leak_through_the_wall() {
    let dir = temp_dir("sample-rooms");
    let scene = dir.join("rooms.obj");
    write_two_rooms(&scene, 2.0);
    let sky = dir.join("black.exr");
    shlight_ok(&[
        "synth",
        "constant",
        "-o",
        s(&sky),
        "--value",
        "0",
        "--size",
        "32x16",
    ]);
    let points = dir.join("floor.json");
    // The dark room 7 cm from the wall, then the lit room's floor.
    let mut p = Vec::new();
    for z in [0.5, 1.0, 1.5] {
        p.push(format!("[2.09, 0.05, {z}]"));
    }
    for x in [0.25, 0.75, 1.25, 1.75] {
        for z in [0.25, 0.75, 1.25, 1.75] {
            p.push(format!("[{x}, 0.05, {z}]"));
        }
    }
    let normals = vec!["[0, 1, 0]"; p.len()].join(", ");
    std::fs::write(
        &points,
        format!(
            "{{\"points\": [{}], \"normals\": [{normals}]}}",
            p.join(", ")
        ),
    )
    .unwrap();
    let bake = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "volume",
            s(&scene),
            "--env",
            s(&sky),
            "--resolution",
            "8x3x4",
            "--bounds",
            "0,0,0:4,1.5,2",
            "--samples",
            "512",
            "--surface-samples",
            "128",
            "--bounces",
            "1",
            "-o",
            s(&out),
        ];
        args.extend_from_slice(extra);
        shlight_ok(&args);
        out
    };
    let leak = |vol: &Path, lookup: &str| -> (f64, Value) {
        let out = dir.join(format!("e-{lookup}.json"));
        let _ = std::fs::remove_file(&out);
        shlight_ok(&[
            "sample",
            s(vol),
            "--points",
            s(&points),
            "--lookup",
            lookup,
            "-o",
            s(&out),
        ]);
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        let e: Vec<f64> = values(&v, "irradiance")
            .iter()
            .map(|c| c.iter().sum::<f64>() / 3.0)
            .collect();
        let mean = e[3..].iter().sum::<f64>() / (e.len() - 3) as f64;
        assert!(mean > 0.1, "the lamp lights the floor: {mean}");
        (e[..3].iter().fold(0.0f64, |m, x| m.max(*x)) / mean, v)
    };
    let vol = bake("rooms.shvol", &[]);
    let file = ShvolFile::read(&vol).unwrap();
    assert!(file.visibility.is_some() && file.offsets.is_some());
    let (shlight_leak, v) = leak(&vol, "shlight");
    assert_eq!(v["lookup"], "shlight");
    assert_eq!(v["visibility"], true);
    let (trilinear_leak, _) = leak(&vol, "trilinear");
    assert!(shlight_leak <= 0.02, "dark side {shlight_leak}");
    assert!(trilinear_leak > 0.1, "trilinear {trilinear_leak}");
    let plain = bake("plain.shvol", &["--no-visibility", "--no-relocate"]);
    let header = std::fs::read(&plain).unwrap();
    let end = header.iter().position(|&b| b == b'\n').unwrap();
    let header: Value = serde_json::from_slice(&header[..end]).unwrap();
    assert_eq!(header["format_version"], 1);
    assert_eq!(
        header["holds"],
        serde_json::json!(["radiance", "emitted", "transfer"])
    );
    let (plain_leak, v) = leak(&plain, "shlight");
    assert_eq!(v["lookup"], "trilinear");
    assert!((plain_leak - trilinear_leak).abs() < 1e-6 * trilinear_leak.max(1.0));
    eprintln!(
        "two rooms through the CLI: dark side {:.2}% of the lit floor's mean (trilinear {:.1}%)",
        100.0 * shlight_leak,
        100.0 * trilinear_leak
    );
}

/// `--points SCENE.glb` samples every vertex of the flattened scene facing
/// its normal: a volume of 2 x 2 x 2 identical probes (L00 and L11, over a
/// box holding the room) gives at each vertex the closed form
/// `E(n) = pi L00 Y00 + 2 pi / 3 L11 Y11(n)`, with the normals of the
/// scene's instances in world space; the same points written as a JSON
/// points file give the same numbers.
#[test]
fn points_from_a_gltf_scene_are_its_vertices() {
    let dir = temp_dir("sample-scene");
    let nc = 4;
    let mut radiance = vec![0.0f32; 8 * nc * 3];
    for probe in radiance.chunks_exact_mut(nc * 3) {
        probe[..3].copy_from_slice(&[1.0, 2.0, 3.0]);
        probe[9..12].copy_from_slice(&[-0.5, -0.25, 0.5]);
    }
    let volume = ShvolFile {
        lmax: 1,
        resolution: [2, 2, 2],
        bounds: ([-3.0, -1.0, -3.0], [3.0, 4.0, 3.0]),
        valid: vec![true; 8],
        radiance,
        emitted: None,
        transfer: None,
        ..two_probes(false)
    };
    let vol = dir.join("room.shvol");
    volume.write(&vol).unwrap();
    let scene_path = Path::new("tests/scenes/instances.glb");
    let out = dir.join("at-vertices.json");
    shlight_ok(&["sample", s(&vol), "--points", s(scene_path), "-o", s(&out)]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["at"], "vertices");
    let got = values(&v, "irradiance");
    let scene = shlight_mesh::load_scene(scene_path, &Default::default()).unwrap();
    assert!(scene.instances.len() > 3, "the chairs are instances");
    let mesh = scene.flatten(glam::Vec3::ONE).unwrap().mesh;
    assert_eq!(got.len(), mesh.vertex_count());
    let y00 = 0.5 / PI.sqrt();
    let y1 = (3.0 / (4.0 * PI)).sqrt();
    for (e, n) in got.iter().zip(&mesh.normals) {
        let n = n.as_dvec3().normalize();
        let want = [[1.0, -0.5], [2.0, -0.25], [3.0, 0.5]]
            .map(|[l00, l11]| PI * l00 * y00 + 2.0 * PI / 3.0 * l11 * (-y1 * n.x));
        for c in 0..3 {
            assert!((e[c] - want[c]).abs() <= 1e-5, "{n}: {e:?} vs {want:?}");
        }
    }
    let points = dir.join("vertices.json");
    let as_f64 =
        |v: &[glam::Vec3]| -> Vec<[f64; 3]> { v.iter().map(|p| p.as_dvec3().to_array()).collect() };
    write_points(&points, &as_f64(&mesh.positions), &as_f64(&mesh.normals));
    let out_json = dir.join("at-points.json");
    shlight_ok(&[
        "sample",
        s(&vol),
        "--points",
        s(&points),
        "-o",
        s(&out_json),
    ]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out_json).unwrap()).unwrap();
    let from_json = values(&v, "irradiance");
    for (a, b) in got.iter().zip(&from_json) {
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-6 * b[c].abs().max(1.0),
                "{a:?} vs {b:?}"
            );
        }
    }
}

//! `shlight sample`: a volume's irradiance at points and a PRT file's exit
//! radiance, against closed forms and against the GPU's own volume pass.

use std::f64::consts::PI;
use std::path::Path;

use serde_json::Value;
use shlight_format::ShvolFile;

use crate::util::{shlight, shlight_ok, temp_dir};

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
        samples: 1,
        bounces: 0,
        seed: 0,
        scene: "two probes".into(),
        scene_hash: 0,
        environment: "by hand".into(),
        generator: "tests/sample.rs".into(),
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
    assert_eq!(v["lookup"], "shlight");
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

//! `--encoding` of `project` and `irradiance`, and `shlight compare`: the
//! file round-trips every encoding, a synthetic sun comes back as one light,
//! and the comparison covers every encoding.

use glam::DVec3;
use shlight_core::encoding::{DominantLightOptions, Encoding, encode_map};
use shlight_core::map::{EnvMap, Layout, MapOrientation};
use shlight_format::CoeffFile;
use shlight_io::{ReadOptions, read_image};

use crate::util::{
    read_json, s, shlight_err, shlight_ok, sphere_directions, synth_sun_map, temp_dir,
};

/// The bounds for an extracted sun: half a degree, 1% of the power.
const ANGLE_DEG: f64 = 0.5;
const POWER: f64 = 0.01;

#[test]
fn a_synthetic_sun_is_one_light_in_the_file() {
    let dir = temp_dir("encoding_sun");
    let map = synth_sun_map(&dir);
    let out = dir.join("sun.json");
    shlight_ok(&[
        "project",
        s(&map),
        "--encoding",
        "dominant+sh",
        "-o",
        s(&out),
    ]);
    let v = read_json(&out);
    assert_eq!(v["format_version"], 2);
    assert_eq!(v["encoding"]["kind"], "dominant+sh");
    let lights = v["encoding"]["lights"].as_array().unwrap();
    assert_eq!(lights.len(), 1, "{lights:?}");
    let d = &lights[0]["direction"];
    let d = DVec3::new(
        d[0].as_f64().unwrap(),
        d[1].as_f64().unwrap(),
        d[2].as_f64().unwrap(),
    );
    let angle = d.angle_between(DVec3::new(1.0, 1.0, 0.5)).to_degrees();
    assert!(angle < ANGLE_DEG, "{angle}°");
    // synth's cap: L = E / (π sin² A), power 2π(1 - cos A) L = 2E / (1 + cos A).
    let a = 2f64.to_radians();
    for (c, colour) in [1.0, 0.8, 0.6].iter().enumerate() {
        let want = 2.0 * 5.0 * colour / (1.0 + a.cos());
        let got = lights[0]["power"][c].as_f64().unwrap();
        assert!(
            (got / want - 1.0).abs() < POWER,
            "channel {c}: {got} {want}"
        );
    }
    // The irradiance report: the light kept exactly beats 9 coefficients.
    let err = |args: &[&str]| -> f64 {
        let o = shlight_ok(args);
        let text = String::from_utf8_lossy(&o.stdout).to_string();
        let line = text
            .lines()
            .find(|l| l.contains("relative to max E"))
            .unwrap()
            .to_string();
        let max = line
            .split("max")
            .nth(2)
            .unwrap()
            .trim()
            .trim_end_matches('%');
        max.parse::<f64>().unwrap()
    };
    let e = dir.join("e.exr");
    let plain = err(&[
        "irradiance",
        s(&map),
        "-o",
        s(&e),
        "--size",
        "64x32",
        "--sh",
        "2",
    ]);
    let dom = err(&[
        "irradiance",
        s(&map),
        "-o",
        s(&e),
        "--size",
        "64x32",
        "--encoding",
        "dominant+sh",
    ]);
    assert!(dom < plain / 10.0, "dominant+sh {dom}% against sh {plain}%");
    assert!(dir.join("e-dominant+sh.exr").exists() && dir.join("e-diff.exr").exists());
}

#[test]
fn every_encoding_round_trips_through_the_file() {
    let dir = temp_dir("encoding_files");
    let map = synth_sun_map(&dir);
    let image = read_image(&map, &ReadOptions::default()).unwrap();
    let env = EnvMap::new(
        Layout::Equirect,
        MapOrientation::default(),
        image.width(),
        image.height(),
        image.pixels(),
    )
    .unwrap();
    let normals = sphere_directions(100);
    for e in Encoding::ALL {
        let out = dir.join(format!("{e}.json"));
        shlight_ok(&["project", s(&map), "--encoding", e.name(), "-o", s(&out)]);
        let file = CoeffFile::read(&out).unwrap();
        assert_eq!(file.encoding.encoding(), e);
        let read = file.encoded().unwrap();
        let made = encode_map(&env, e, 2, &DominantLightOptions::default());
        for n in &normals {
            let (a, b) = (read.irradiance(*n), made.irradiance(*n));
            // JSON keeps every f64 exactly; only sums reorder.
            assert!(
                (a - b).abs().max_element() <= 1e-12 * b.abs().max_element().max(1.0),
                "{e} {n}"
            );
        }
    }
    let err = shlight_err(&[
        "project",
        s(&map),
        "--encoding",
        "zh3",
        "--rotate",
        "yaw:30",
    ]);
    assert!(err.contains("--rotate") && err.contains("zh3"), "{err}");
}

#[test]
fn compare_lists_every_encoding_and_writes_json_and_plots() {
    let dir = temp_dir("encoding_compare");
    let map = synth_sun_map(&dir);
    let out = dir.join("cmp");
    let o = shlight_ok(&["compare", s(&map), "--normals", "32x16", "-o", s(&out)]);
    let table = String::from_utf8_lossy(&o.stdout);
    let rows = read_json(&out.join("compare.json"));
    let rows = rows.as_array().unwrap();
    for e in Encoding::ALL {
        assert!(table.contains(e.name()), "{e} missing from\n{table}");
        assert!(
            rows.iter().any(|r| r["encoding"] == e.name()),
            "{e} missing from the JSON"
        );
    }
    let dom = rows
        .iter()
        .find(|r| r["encoding"] == "dominant+sh" && r["lmax"] == 2)
        .unwrap();
    assert_eq!(dom["lights"], 1);
    assert!(dom["light_angle_degrees"].as_f64().unwrap() < 2.0);
    let svg = std::fs::read_to_string(out.join("compare-sun.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("dominant+sh"));
}

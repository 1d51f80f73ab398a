//! Exporters: each test proves what the exported numbers mean.
//!
//! Known radiance (a directional light plus a constant, a random set, a
//! z-up lmax-4 set, an irradiance file, an lmax-1 file) goes through
//! `shlight convert`; the target's own shading formula, ported from its
//! source (three.js `getIrradianceAt`, Babylon.js's reading of glTF
//! `irradianceCoefficients`, Filament `Irradiance_SphericalHarmonics`,
//! Unity `ShadeSH9`, R&H eq. 13, the generated C / GLSL / HLSL compiled and
//! run), is evaluated at many normals and compared with shlight's `E(n)`
//! (or `E/pi`, or `L`, as the target defines). The C snippet is compiled
//! as C99 (`cc`) and C++17 (`c++`); the GLSL and HLSL ones as C++ in double
//! precision. `export_shaders` compiles the shader snippets with naga and
//! glslang and runs them on the GPU. A missing compiler prints a SKIPPED
//! line, and fails the test under `SHLIGHT_REQUIRE_ALL=1`.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use glam::{DMat3, DVec3};
use serde_json::{Value, json};
use shlight_core::sh::{Frame, ShCoeffs, closed_form, irradiance};

#[cfg(feature = "gpu")]
use crate::export_shaders;
use crate::util::{compile_and_run, have_tool, shlight, temp_dir};

// ---------------------------------------------------------------- helpers

/// A test light: radiance coefficients in `frame`, stored as `quantity`.
#[derive(Clone)]
pub(crate) struct Case {
    pub(crate) name: &'static str,
    pub(crate) radiance: ShCoeffs<DVec3>,
    pub(crate) frame: Frame,
    pub(crate) irradiance_file: bool,
}

impl Case {
    /// The coefficients the file holds.
    fn stored(&self) -> ShCoeffs<DVec3> {
        if self.irradiance_file {
            irradiance(&self.radiance)
        } else {
            self.radiance.clone()
        }
    }

    pub(crate) fn write(&self, dir: &Path) -> PathBuf {
        let path = dir.join(format!("{}.json", self.name));
        let c = self.stored();
        let doc = json!({
            "format": "shlight-sh",
            "format_version": 1,
            "lmax": c.lmax(),
            "frame": if self.frame == Frame::YUp { "y-up" } else { "z-up" },
            "quantity": if self.irradiance_file { "irradiance" } else { "radiance" },
            "coefficients": c.as_slice().iter().map(|v| [v.x, v.y, v.z]).collect::<Vec<_>>(),
            "provenance": { "input": "tests/export.rs" },
        });
        std::fs::write(&path, doc.to_string()).unwrap();
        path
    }

    /// shlight's `E(n)` of the radiance kept to `lmax`, at `n` given in the
    /// y-up world axes (engines) or in the file's own axes (`own_frame`).
    pub(crate) fn irradiance_at(&self, lmax: usize, n: DVec3, own_frame: bool) -> DVec3 {
        let d = if own_frame {
            n
        } else {
            Frame::YUp.rotation_to(self.frame) * n
        };
        irradiance(&self.radiance.resized(lmax)).eval(d)
    }

    pub(crate) fn radiance_at(&self, lmax: usize, w: DVec3, own_frame: bool) -> DVec3 {
        let d = if own_frame {
            w
        } else {
            Frame::YUp.rotation_to(self.frame) * w
        };
        self.radiance.resized(lmax).eval(d)
    }
}

/// Deterministic numbers in [-1, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn random_radiance(lmax: usize, seed: u64) -> ShCoeffs<DVec3> {
    let mut r = Lcg(seed);
    ShCoeffs::from_fn(lmax, |l, _| {
        let s = 1.0 / (1.0 + l as f64);
        DVec3::new(r.next(), r.next(), r.next()) * s
    })
}

pub(crate) fn cases() -> Vec<Case> {
    let sun = &closed_form::directional(2, DVec3::new(0.48, 0.6, 0.64), DVec3::new(3.0, 2.5, 2.0))
        + &closed_form::constant(2, DVec3::new(0.2, 0.3, 0.5));
    vec![
        Case {
            name: "sun",
            radiance: sun,
            frame: Frame::YUp,
            irradiance_file: false,
        },
        Case {
            name: "random",
            radiance: random_radiance(2, 7),
            frame: Frame::YUp,
            irradiance_file: false,
        },
        Case {
            name: "zup4",
            radiance: &closed_form::directional(
                4,
                DVec3::new(0.0, -0.6, 0.8),
                DVec3::new(1.0, 2.0, 0.5),
            ) + &random_radiance(4, 11),
            frame: Frame::ZUp,
            irradiance_file: false,
        },
        Case {
            name: "irr",
            radiance: random_radiance(2, 13),
            frame: Frame::YUp,
            irradiance_file: true,
        },
        Case {
            name: "lmax1",
            radiance: random_radiance(1, 17),
            frame: Frame::ZUp,
            irradiance_file: false,
        },
    ]
}

/// Unit normals: a Fibonacci sphere plus the axes.
fn normals() -> Vec<DVec3> {
    crate::util::sphere_directions(102)
}

/// Compares `got(n)` with `want(n)` at every normal, to `tol` relative to
/// the largest `|want|` (the function's scale).
fn assert_matches(
    what: &str,
    got: impl Fn(DVec3) -> DVec3,
    want: impl Fn(DVec3) -> DVec3,
    tol: f64,
) {
    let ns = normals();
    let wants: Vec<DVec3> = ns.iter().map(|n| want(*n)).collect();
    let scale = wants
        .iter()
        .map(|w| w.abs().max_element())
        .fold(0.0, f64::max)
        .max(1e-30);
    for (n, w) in ns.iter().zip(&wants) {
        let g = got(*n);
        let err = (g - *w).abs().max_element() / scale;
        assert!(
            err <= tol,
            "{what}: at n = {n}: got {g}, want {w} (error {err:.2e} of scale {scale:.3})"
        );
    }
}

pub(crate) fn convert(input: &Path, out: &Path, format: &str) -> String {
    // A coefficient file holds no map: its glTF light goes without the
    // specular images, knowingly.
    let flag = if format == "gltf" {
        "--irradiance-only"
    } else {
        "-q"
    };
    let o = shlight(&[
        "convert",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--format",
        format,
        flag,
    ]);
    assert!(
        o.status.success(),
        "convert --format {format} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::read_to_string(out).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn rgb(v: &[f64]) -> DVec3 {
    DVec3::new(v[0], v[1], v[2])
}

// ---------------------------------------------------------------- txt

/// Ramamoorthi & Hanrahan 2001, eq. 13, with their constants.
fn rh_eq13(l: &[DVec3], n: DVec3) -> DVec3 {
    let (c1, c2, c3, c4, c5) = (0.429043, 0.511664, 0.743125, 0.886227, 0.247708);
    let (x, y, z) = (n.x, n.y, n.z);
    l[8] * (c1 * (x * x - y * y)) + l[6] * (c3 * z * z) + l[0] * c4 - l[6] * c5
        + (l[4] * (x * y) + l[7] * (x * z) + l[5] * (y * z)) * (2.0 * c1)
        + (l[3] * x + l[1] * y + l[2] * z) * (2.0 * c2)
}

fn read_table(text: &str) -> Vec<(String, DVec3)> {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let v: Vec<f64> = f[1..].iter().map(|s| s.parse().unwrap()).collect();
            (f[0].to_string(), rgb(&v))
        })
        .collect()
}

#[test]
fn txt_is_a_rh_table_that_eq_13_turns_into_shlight_irradiance() {
    let dir = temp_dir("export_txt");
    for case in cases() {
        let text = convert(&case.write(&dir), &dir.join("t.txt"), "txt");
        let rows = read_table(&text);
        let lmax = case.radiance.lmax();
        assert_eq!(rows.len(), (lmax + 1) * (lmax + 1), "{}", case.name);
        assert_eq!(rows[1].0, "L1-1");
        let frame = if case.frame == Frame::YUp {
            "y-up"
        } else {
            "z-up"
        };
        assert!(text.contains(frame) && text.contains("WITHOUT the Condon-Shortley"));
        let values: Vec<DVec3> = rows.iter().map(|r| r.1).collect();
        if case.irradiance_file {
            // Irradiance table: E(n) = sum E_lm Y_lm(n) in the phase-free basis.
            assert!(text.contains("quantity: irradiance"));
            let basis = |n: DVec3| {
                let (x, y, z) = (n.x, n.y, n.z);
                [
                    0.282095,
                    0.488603 * y,
                    0.488603 * z,
                    0.488603 * x,
                    1.092548 * x * y,
                    1.092548 * y * z,
                    0.315392 * (3.0 * z * z - 1.0),
                    1.092548 * x * z,
                    0.546274 * (x * x - y * y),
                ]
            };
            assert_matches(
                "txt irradiance",
                |n| (0..9).map(|i| values[i] * basis(n)[i]).sum(),
                |n| case.irradiance_at(2, n, true),
                1e-5,
            );
        } else if lmax == 2 {
            assert!(text.contains("R&H eq. 13"));
            assert_matches(
                &format!("txt {} (R&H eq. 13)", case.name),
                |n| rh_eq13(&values, n),
                |n| case.irradiance_at(2, n, true),
                1e-5,
            );
        } else {
            // The table holds the file's coefficients with odd |m| negated.
            for (i, (got, want)) in values.iter().zip(case.stored().as_slice()).enumerate() {
                let (_, m) = shlight_core::sh::lm_from_index(i);
                let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
                assert!((*got - *want * sign).abs().max_element() < 1e-8 * (1.0 + want.length()));
            }
        }
    }
}

// ---------------------------------------------------------------- three.js

/// three.js `SphericalHarmonics3.getIrradianceAt` (src/math/SphericalHarmonics3.js).
pub(crate) fn three_get_irradiance_at(c: &[DVec3], n: DVec3) -> DVec3 {
    let (x, y, z) = (n.x, n.y, n.z);
    let mut t = c[0] * 0.886227;
    t += c[1] * (2.0 * 0.511664 * y);
    t += c[2] * (2.0 * 0.511664 * z);
    t += c[3] * (2.0 * 0.511664 * x);
    t += c[4] * (2.0 * 0.429043 * x * y);
    t += c[5] * (2.0 * 0.429043 * y * z);
    t += c[6] * (0.743125 * z * z - 0.247708);
    t += c[7] * (2.0 * 0.429043 * x * z);
    t += c[8] * (0.429043 * (x * x - y * y));
    t
}

/// three.js `SphericalHarmonics3.getAt` (radiance).
fn three_get_at(c: &[DVec3], n: DVec3) -> DVec3 {
    let (x, y, z) = (n.x, n.y, n.z);
    c[0] * 0.282095
        + c[1] * (0.488603 * y)
        + c[2] * (0.488603 * z)
        + c[3] * (0.488603 * x)
        + c[4] * (1.092548 * x * y)
        + c[5] * (1.092548 * y * z)
        + c[6] * (0.315392 * (3.0 * z * z - 1.0))
        + c[7] * (1.092548 * x * z)
        + c[8] * (0.546274 * (x * x - y * y))
}

#[test]
fn threejs_light_probe_gives_shlight_irradiance_and_radiance() {
    let dir = temp_dir("export_threejs");
    for case in cases() {
        let v: Value =
            serde_json::from_str(&convert(&case.write(&dir), &dir.join("p.json"), "threejs"))
                .unwrap();
        assert_eq!(v["metadata"]["type"], "Object");
        let obj = &v["object"];
        assert_eq!(obj["type"], "LightProbe");
        // LightProbe.fromJSON: intensity, then sh.fromArray(json.sh).
        let intensity = obj["intensity"].as_f64().unwrap();
        let sh = floats(&obj["sh"]);
        assert_eq!(sh.len(), 27);
        let c: Vec<DVec3> = sh.chunks(3).map(|c| rgb(c) * intensity).collect();
        assert_matches(
            &format!("threejs getIrradianceAt, {}", case.name),
            |n| three_get_irradiance_at(&c, n),
            |n| case.irradiance_at(2, n, false),
            1e-5,
        );
        if !case.irradiance_file {
            assert_matches(
                &format!("threejs getAt, {}", case.name),
                |n| three_get_at(&c, n),
                |n| case.radiance_at(2, n, false),
                1e-5,
            );
        }
    }
}

// ---------------------------------------------------------------- glTF

/// Babylon.js's reading of an `EXT_lights_image_based` light (the
/// extension's reference loader): `SphericalHarmonics.FromArray`,
/// `scaleInPlace(intensity)`, `convertIrradianceToLambertianRadiance`
/// (1/pi), evaluated with `SH3ylmBasisConstants` (with the CS phase) times
/// `SH3ylmBasisTrigonometricTerms`.
pub(crate) fn babylon_lambertian_radiance(light: &Value, n: DVec3) -> DVec3 {
    let k = [
        (1.0 / (4.0 * PI)).sqrt(),
        -(3.0 / (4.0 * PI)).sqrt(),
        (3.0 / (4.0 * PI)).sqrt(),
        -(3.0 / (4.0 * PI)).sqrt(),
        (15.0 / (4.0 * PI)).sqrt(),
        -(15.0 / (4.0 * PI)).sqrt(),
        (5.0 / (16.0 * PI)).sqrt(),
        -(15.0 / (4.0 * PI)).sqrt(),
        (15.0 / (16.0 * PI)).sqrt(),
    ];
    let (x, y, z) = (n.x, n.y, n.z);
    let t = [
        1.0,
        y,
        z,
        x,
        x * y,
        y * z,
        3.0 * z * z - 1.0,
        x * z,
        x * x - y * y,
    ];
    let intensity = light["intensity"].as_f64().unwrap();
    (0..9)
        .map(|i| rgb(&floats(&light["irradianceCoefficients"][i])) * (intensity / PI * k[i] * t[i]))
        .sum()
}

#[test]
fn gltf_irradiance_coefficients_read_by_babylon_give_irradiance_over_pi() {
    let dir = temp_dir("export_gltf");
    for case in cases() {
        let path = case.write(&dir);
        let out = shlight(&[
            "convert",
            path.to_str().unwrap(),
            "-o",
            dir.join("l.gltf").to_str().unwrap(),
            "--irradiance-only",
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("specularImages"), "{stderr}");
        let v: Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("l.gltf")).unwrap()).unwrap();
        assert_eq!(v["extensionsUsed"][0], "EXT_lights_image_based");
        let light = &v["extensions"]["EXT_lights_image_based"]["lights"][0];
        assert_eq!(floats(&light["rotation"]), [0.0, 0.0, 0.0, 1.0]);
        // Babylon looks the texel shlight reads at n up at (n.z, n.y, n.x)
        // of its left-handed world (docs/exporters.md; tests/web.rs renders
        // it in Babylon).
        assert_matches(
            &format!("gltf (Babylon.js), {}", case.name),
            |n| babylon_lambertian_radiance(light, DVec3::new(n.z, n.y, n.x)),
            |n| case.irradiance_at(2, n, false) / PI,
            1e-9,
        );
    }
}

// ---------------------------------------------------------------- Filament

/// Filament `Irradiance_SphericalHarmonics` (shaders/src/light_indirect.fs).
pub(crate) fn filament_irradiance_sh(sh: &[DVec3], n: DVec3) -> DVec3 {
    (sh[0]
        + sh[1] * n.y
        + sh[2] * n.z
        + sh[3] * n.x
        + sh[4] * (n.y * n.x)
        + sh[5] * (n.y * n.z)
        + sh[6] * (3.0 * n.z * n.z - 1.0)
        + sh[7] * (n.z * n.x)
        + sh[8] * (n.x * n.x - n.y * n.y))
        .max(DVec3::ZERO)
}

fn read_sh_txt(text: &str) -> Vec<DVec3> {
    text.lines()
        .map(|l| {
            assert!(l.starts_with('(') && l.contains("); // L"), "{l}");
            assert!(l.ends_with(", irradiance, pre-scaled base"), "{l}");
            let v: Vec<f64> = l[1..l.find(')').unwrap()]
                .split(',')
                .map(|s| s.trim().parse().unwrap())
                .collect();
            rgb(&v)
        })
        .collect()
}

#[test]
fn filament_sh_txt_in_its_shader_gives_irradiance_over_pi() {
    let dir = temp_dir("export_filament");
    for case in cases() {
        let text = convert(&case.write(&dir), &dir.join("sh.txt"), "filament");
        assert_eq!(text.lines().count(), 9);
        let names: Vec<&str> = text
            .lines()
            .map(|l| l.split("// ").nth(1).unwrap().split(',').next().unwrap())
            .collect();
        assert_eq!(
            names,
            [
                "L00", "L1-1", "L10", "L11", "L2-2", "L2-1", "L20", "L21", "L22"
            ]
        );
        let sh = read_sh_txt(&text);
        // cmgen shows the texel shlight reads at n at (-n.z, n.y, n.x)
        // (docs/exporters.md).
        assert_matches(
            &format!("filament, {}", case.name),
            |n| filament_irradiance_sh(&sh, DVec3::new(-n.z, n.y, n.x)),
            |n| (case.irradiance_at(2, n, false) / PI).max(DVec3::ZERO),
            1e-9,
        );
    }
}

// ---------------------------------------------------------------- Unity

#[test]
fn unity_shade_sh9_gives_irradiance_over_pi_in_unity_axes() {
    let dir = temp_dir("export_unity");
    for case in cases() {
        let v: Value =
            serde_json::from_str(&convert(&case.write(&dir), &dir.join("u.json"), "unity"))
                .unwrap();
        let sh = floats(&v["SphericalHarmonicsL2"]);
        assert_eq!(sh.len(), 27);
        let vec4 = |k: &str| -> [f64; 4] { floats(&v[k]).try_into().unwrap() };
        let (sha, shb) = (
            [vec4("unity_SHAr"), vec4("unity_SHAg"), vec4("unity_SHAb")],
            [vec4("unity_SHBr"), vec4("unity_SHBg"), vec4("unity_SHBb")],
        );
        let shc = vec4("unity_SHC");
        // HDRP SphericalHarmonicMath.PackCoefficients from sh[rgb, i] = sh[rgb * 9 + i].
        let same = |a: [f64; 4], b: [f64; 4]| {
            a.iter()
                .zip(&b)
                .all(|(x, y)| (x - y).abs() <= 1e-15 * y.abs().max(1e-300))
        };
        for c in 0..3 {
            let s = |i: usize| sh[c * 9 + i];
            assert!(same(sha[c], [s(3), s(1), s(2), s(0) - s(6)]), "SHA {c}");
            assert!(same(shb[c], [s(4), s(5), 3.0 * s(6), s(7)]), "SHB {c}");
            assert!((shc[c] - s(8)).abs() <= 1e-15 * s(8).abs(), "SHC {c}");
        }
        assert_eq!(shc[3], 1.0);
        let dot = |a: [f64; 4], b: [f64; 4]| a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>();
        // UnityCG.cginc ShadeSH9 = SHEvalLinearL0L1 + SHEvalLinearL2, normal.w = 1.
        let shade_sh9 = |n: DVec3| {
            let n4 = [n.x, n.y, n.z, 1.0];
            let vb = [n.x * n.y, n.y * n.z, n.z * n.z, n.z * n.x];
            let vc = n.x * n.x - n.y * n.y;
            DVec3::from_array(std::array::from_fn(|c| {
                dot(sha[c], n4) + dot(shb[c], vb) + shc[c] * vc
            }))
        };
        // Unity (x, y, z) is shlight y-up (x, y, -z).
        assert_matches(
            &format!("unity ShadeSH9, {}", case.name),
            shade_sh9,
            |n| case.irradiance_at(2, DVec3::new(n.x, n.y, -n.z), false) / PI,
            1e-9,
        );
    }
}

// ---------------------------------------------------------------- C, GLSL, HLSL

/// Compiles `source` (C or C++) with a `main` that evaluates `calls` at every
/// normal of [`normals`] and prints them; returns, per normal, the values
/// of each call.
fn run_native(dir: &Path, compiler: &str, source: &str, lang: &str) -> Vec<Vec<DVec3>> {
    compile_and_run(dir, "main", compiler, lang, source)
        .iter()
        .map(|v| v.chunks(3).map(rgb).collect())
        .collect()
}

fn normals_initialiser() -> String {
    normals()
        .iter()
        .map(|n| format!("{{{:?}, {:?}, {:?}}}", n.x, n.y, n.z))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Checks the values a compiled snippet printed against shlight.
fn check_snippet_values(what: &str, case: &Case, values: &[Vec<DVec3>]) {
    let ns = normals();
    let index = |n: DVec3| ns.iter().position(|m| *m == n).unwrap();
    let lmax = case.radiance.lmax();
    assert_matches(
        &format!("{what} irradiance, {}", case.name),
        |n| values[index(n)][0],
        |n| case.irradiance_at(lmax, n, true),
        1e-9,
    );
    if !case.irradiance_file {
        assert_matches(
            &format!("{what} radiance, {}", case.name),
            |n| values[index(n)][1],
            |n| case.radiance_at(lmax, n, true),
            1e-9,
        );
    }
}

/// A case of high lmax to show the loops work beyond 2.
pub(crate) fn high_lmax_case() -> Case {
    Case {
        name: "lmax8",
        radiance: &closed_form::cap(
            8,
            DVec3::new(0.36, 0.48, 0.8),
            0.4,
            DVec3::new(4.0, 3.0, 2.0),
        ) + &random_radiance(8, 23),
        frame: Frame::ZUp,
        irradiance_file: false,
    }
}

#[test]
fn c_snippet_compiled_and_run_gives_shlight_values() {
    let test = "c_snippet_compiled_and_run_gives_shlight_values";
    // The header is C99 and is also included from C++.
    let compilers: Vec<(&str, &str)> = [("cc", "c"), ("c++", "cpp")]
        .into_iter()
        .filter(|(tool, _)| have_tool(tool, test))
        .collect();
    if compilers.is_empty() {
        return;
    }
    let dir = temp_dir("export_c");
    let mut all = cases();
    all.push(high_lmax_case());
    for case in all {
        let text = convert(&case.write(&dir), &dir.join("sh.c"), "c");
        assert!(text.starts_with("// shlight"));
        let radiance_call = if case.irradiance_file {
            "o[1][0] = o[1][1] = o[1][2] = 0.0;"
        } else {
            "shlight_radiance(ns[i], o[1]);"
        };
        let main = format!(
            "{text}\n#include <stdio.h>\nint main(void) {{\n    static const double ns[][3] = {{{}}};\n    \
             for (unsigned i = 0; i < sizeof ns / sizeof ns[0]; i++) {{\n        double o[2][3];\n        \
             shlight_irradiance(ns[i], o[0]);\n        {radiance_call}\n        \
             printf(\"%.17g %.17g %.17g %.17g %.17g %.17g\\n\", o[0][0], o[0][1], o[0][2], o[1][0], o[1][1], o[1][2]);\n    \
             }}\n    return 0;\n}}\n",
            normals_initialiser()
        );
        for (compiler, lang) in &compilers {
            let values = run_native(&dir, compiler, &main, lang);
            check_snippet_values(&format!("C ({compiler})"), &case, &values);
        }
    }
}

/// A C++ prelude that gives GLSL's / HLSL's vector type the operations the
/// snippets use, in double precision (`float` is redefined to `double`), so
/// that the test checks the formulas, not 32-bit rounding.
fn cpp_prelude(vec3: &str) -> String {
    format!(
        "#include <cmath>\n#include <cstdio>\nusing std::sqrt;\n\
         struct {vec3} {{ double x, y, z; {vec3}(double a, double b, double c) : x(a), y(b), z(c) {{}} }};\n\
         static {vec3} operator*({vec3} a, double s) {{ return {vec3}(a.x * s, a.y * s, a.z * s); }}\n\
         static {vec3} operator+({vec3} a, {vec3} b) {{ return {vec3}(a.x + b.x, a.y + b.y, a.z + b.z); }}\n\
         static {vec3}& operator+=({vec3}& a, {vec3} b) {{ a = a + b; return a; }}\n\
         #define float double\n"
    )
}

fn cpp_main(vec3: &str, irradiance_only: bool) -> String {
    let radiance = if irradiance_only {
        format!("{vec3} r(0.0, 0.0, 0.0);")
    } else {
        format!("{vec3} r = shlight_radiance(n);")
    };
    format!(
        "int main() {{\n    static const double ns[][3] = {{{}}};\n    \
         for (const auto& d : ns) {{\n        {vec3} n(d[0], d[1], d[2]);\n        \
         {vec3} e = shlight_irradiance(n);\n        {radiance}\n        \
         std::printf(\"%.17g %.17g %.17g %.17g %.17g %.17g\\n\", e.x, e.y, e.z, r.x, r.y, r.z);\n    }}\n    return 0;\n}}\n",
        normals_initialiser()
    )
}

#[test]
fn hlsl_snippet_compiled_as_cpp_gives_shlight_values() {
    if !have_tool("c++", "hlsl_snippet_compiled_as_cpp_gives_shlight_values") {
        return;
    }
    let dir = temp_dir("export_hlsl");
    let mut all = cases();
    all.push(high_lmax_case());
    for case in all {
        let text = convert(&case.write(&dir), &dir.join("sh.hlsl"), "hlsl");
        assert!(text.contains("static const float3 SHLIGHT_COEFFS["));
        // The snippet is compiled verbatim.
        let source = format!(
            "{}{text}\n{}",
            cpp_prelude("float3"),
            cpp_main("float3", case.irradiance_file)
        );
        let values = run_native(&dir, "c++", &source, "cpp");
        check_snippet_values("HLSL", &case, &values);
    }
}

#[cfg(feature = "gpu")]
/// GLSL's array constructors `T[n](a, b)` become C++ initialisers `{a, b}`;
/// everything else is compiled verbatim.
fn glsl_as_cpp(text: &str) -> String {
    let mut out = String::new();
    let mut open = false;
    for line in text.lines() {
        let mut l = line.to_string();
        for ty in ["vec3", "float"] {
            if let Some(start) = l.find(&format!("= {ty}[")) {
                let paren = start + l[start..].find("](").unwrap() + 2;
                l = format!("{}= {{{}", &l[..start], &l[paren..]);
                if l.trim_end().ends_with(");") {
                    l = l.trim_end().trim_end_matches(");").to_string() + "};";
                } else {
                    open = true;
                }
            }
        }
        if open && l.trim() == ");" {
            l = "};".into();
            open = false;
        }
        out.push_str(&l);
        out.push('\n');
    }
    out
}

#[cfg(feature = "gpu")]
#[test]
fn glsl_snippet_validates_and_compiled_as_cpp_gives_shlight_values() {
    let dir = temp_dir("export_glsl");
    let cpp = have_tool(
        "c++",
        "glsl_snippet_validates_and_compiled_as_cpp_gives_shlight_values",
    );
    let mut all = cases();
    all.push(high_lmax_case());
    for case in all {
        let text = convert(&case.write(&dir), &dir.join("sh.glsl"), "glsl");
        assert!(text.contains("const vec3 SHLIGHT_COEFFS["));
        // naga, in-process: the snippet inside the compute shader that the
        // GPU test runs (the snippet has no entry point of its own).
        let shader = export_shaders::glsl_compute(&text, !case.irradiance_file);
        if let Err(e) = export_shaders::naga_glsl(&shader) {
            panic!("naga rejects the GLSL of {}:\n{e}", case.name);
        }
        if cpp {
            let source = format!(
                "{}{}\n{}",
                cpp_prelude("vec3"),
                glsl_as_cpp(&text),
                cpp_main("vec3", case.irradiance_file)
            );
            let values = run_native(&dir, "c++", &source, "cpp");
            check_snippet_values("GLSL", &case, &values);
        }
    }
}

// ---------------------------------------------------------------- WGSL

#[cfg(feature = "gpu")]
/// The statements of `shlight_expand` (its signature from the name on) with
/// declarations and types spelled out of the way, to compare two languages
/// statement by statement. WGSL has no `?:`: its band weight
/// `var w: f32 = 1.0; if (irradiance) { w = SHLIGHT_A[l]; }` is read as
/// GLSL's `float w = irradiance ? SHLIGHT_A[l] : 1.0;`.
fn expand_statements(text: &str) -> Vec<String> {
    let start = text.find("shlight_expand(").unwrap();
    let body = &text[start..];
    let end = body.find("\n}\n").unwrap();
    let lines: Vec<String> = body[..end]
        .lines()
        .map(|l| l.split("//").next().unwrap().trim().to_string())
        .filter(|l| !l.is_empty())
        .map(|l| {
            let mut l = l
                .replace("vec3<f32>", "vec3")
                .replace("f32(", "float(")
                .replace(": f32", "")
                .replace(": i32", "")
                .replace(": bool", "")
                .replace(": vec3", "");
            for decl in ["var ", "let ", "float ", "int ", "vec3 ", "bool "] {
                l = l.replace(&format!("({decl}"), "(");
                l = l.replace(&format!(", {decl}"), ", ");
                if let Some(rest) = l.strip_prefix(decl) {
                    l = rest.to_string();
                }
            }
            // The signature (from its name on): WGSL's return type.
            l.replace(") -> vec3 {", ") {")
        })
        .collect();
    let wgsl_weight = ["w = 1.0;", "if (irradiance) {", "w = SHLIGHT_A[l];", "}"];
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        if lines[i..].starts_with(&wgsl_weight.map(String::from)) {
            out.push("w = irradiance ? SHLIGHT_A[l] : 1.0;".to_string());
            i += wgsl_weight.len();
        } else {
            out.push(lines[i].clone());
            i += 1;
        }
    }
    out
}

#[cfg(feature = "gpu")]
#[test]
fn wgsl_snippet_validates_holds_the_numbers_and_is_the_tested_evaluator() {
    let dir = temp_dir("export_wgsl");
    let mut all = cases();
    all.push(high_lmax_case());
    for case in all {
        let text = convert(&case.write(&dir), &dir.join("sh.wgsl"), "wgsl");
        // The numbers: every coefficient of the file, exactly, in index order.
        let stored = case.stored();
        let coeffs: Vec<DVec3> = text
            .lines()
            .filter(|l| l.trim_start().starts_with("vec3<f32>(") && l.contains("// l="))
            .map(|l| {
                let inner = &l[l.find('(').unwrap() + 1..l.find(')').unwrap()];
                rgb(&inner
                    .split(',')
                    .map(|s| s.trim().parse().unwrap())
                    .collect::<Vec<_>>())
            })
            .collect();
        // (serde_json may read a decimal 1 ulp off, hence the tolerance.)
        assert_eq!(coeffs.len(), stored.len(), "{}", case.name);
        for (got, want) in coeffs.iter().zip(stored.as_slice()) {
            assert!(
                (*got - *want).abs().max_element() <= 1e-15 * want.abs().max_element(),
                "{}: {got} vs {want}",
                case.name
            );
        }
        let lmax = stored.lmax();
        assert!(text.contains(&format!("const SHLIGHT_LMAX: i32 = {lmax};")));
        if !case.irradiance_file {
            let a_line = text
                .lines()
                .find(|l| l.contains("var<private> SHLIGHT_A"))
                .unwrap();
            let a: Vec<f64> = a_line[a_line.rfind('(').unwrap() + 1..a_line.rfind(')').unwrap()]
                .split(',')
                .map(|s| s.trim().parse().unwrap())
                .collect();
            let want: Vec<f64> = (0..=lmax)
                .map(shlight_core::sh::clamped_cosine_eigenvalue)
                .collect();
            assert_eq!(a, want);
        }
        // The evaluator: statement for statement the GLSL one that the test
        // above compiles and runs.
        let glsl = convert(&case.write(&dir), &dir.join("sh.glsl"), "glsl");
        assert_eq!(
            expand_statements(&text),
            expand_statements(&glsl),
            "{}",
            case.name
        );
        // naga, in-process: the snippet as written (a module of its own) and
        // inside the compute shader that the GPU test runs.
        let shader = export_shaders::wgsl_compute(&text, !case.irradiance_file);
        for (what, source) in [("snippet", &text), ("compute shader", &shader)] {
            if let Err(e) = export_shaders::naga_wgsl(source) {
                panic!("naga rejects the WGSL {what} of {}:\n{e}", case.name);
            }
        }
    }
}

// ---------------------------------------------------------------- round trips

fn read_coeff_file(path: &Path) -> (Vec<DVec3>, String, String) {
    let v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let c = crate::util::coefficients(&v)
        .into_iter()
        .map(DVec3::from_array)
        .collect();
    (
        c,
        v["frame"].as_str().unwrap().to_string(),
        v["quantity"].as_str().unwrap().to_string(),
    )
}

#[test]
fn json_to_engine_formats_and_back_keeps_the_coefficients() {
    let dir = temp_dir("export_round_trip");
    let radiance = random_radiance(2, 29);
    let case = Case {
        name: "rt",
        radiance: radiance.clone(),
        frame: Frame::YUp,
        irradiance_file: false,
    };
    let input = case.write(&dir);
    let e = irradiance(&radiance);
    for (format, file, quantity, want) in [
        ("threejs", "p.json", "radiance", &radiance),
        ("gltf", "l.gltf", "irradiance", &e),
        ("filament", "sh.txt", "irradiance", &e),
        ("unity", "u.json", "irradiance", &e),
    ] {
        let exported = dir.join(file);
        convert(&input, &exported, format);
        let back = dir.join(format!("{format}-back.json"));
        convert(&exported, &back, "json");
        let (c, frame, q) = read_coeff_file(&back);
        assert_eq!((frame.as_str(), q.as_str()), ("y-up", quantity), "{format}");
        for (i, (got, want)) in c.iter().zip(want.as_slice()).enumerate() {
            assert!(
                (*got - *want).abs().max_element() <= 1e-6 * want.abs().max_element().max(1.0),
                "{format}: coefficient {i}: {got} vs {want}"
            );
        }
    }
    // A z-up file comes back y-up: the same light, turned.
    let zup = Case {
        name: "rt-zup",
        radiance: radiance.clone(),
        frame: Frame::ZUp,
        irradiance_file: false,
    };
    convert(&zup.write(&dir), &dir.join("z.json"), "threejs");
    convert(&dir.join("z.json"), &dir.join("z-back.json"), "json");
    let (c, frame, _) = read_coeff_file(&dir.join("z-back.json"));
    assert_eq!(frame, "y-up");
    let back = ShCoeffs::from_vec(c).unwrap();
    let m: DMat3 = Frame::YUp.rotation_to(Frame::ZUp);
    for n in normals() {
        let got = back.eval(n);
        let want = radiance.eval(m * n);
        assert!((got - want).abs().max_element() < 1e-9, "{n}");
    }
}

#[test]
fn convert_infers_the_format_from_the_extension_or_asks() {
    let dir = temp_dir("export_infer");
    let input = cases().remove(0).write(&dir);
    let inp = input.to_str().unwrap();
    for (file, marker) in [
        ("a.wgsl", "var<private> SHLIGHT_COEFFS"),
        ("a.frag", "const vec3 SHLIGHT_COEFFS"),
        ("a.hlsl", "static const float3 SHLIGHT_COEFFS"),
        ("a.h", "static const double shlight_coeffs"),
        ("a.gltf", "EXT_lights_image_based"),
    ] {
        let out = dir.join(file);
        let o = shlight(&[
            "convert",
            inp,
            "-o",
            out.to_str().unwrap(),
            "--irradiance-only",
        ]);
        assert!(
            o.status.success(),
            "{file}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            std::fs::read_to_string(&out).unwrap().contains(marker),
            "{file}"
        );
    }
    for (file, words) in [
        ("a.json", "threejs"),
        ("a.txt", "filament"),
        ("a.xyz", ".xyz"),
    ] {
        let o = shlight(&["convert", inp, "-o", dir.join(file).to_str().unwrap()]);
        assert!(!o.status.success(), "{file}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(file) && err.contains(words) && err.contains("--format"),
            "{err}"
        );
        assert!(!dir.join(file).exists());
    }
    // stdout with --format; without it, a clear refusal.
    let o = shlight(&["convert", inp, "--format", "txt"]);
    assert!(o.status.success() && String::from_utf8_lossy(&o.stdout).contains("L2-2"));
    let o = shlight(&["convert", inp]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--format"));
}

#[test]
fn convert_refuses_bad_input_naming_the_file() {
    let dir = temp_dir("export_bad");
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let out = dir.join("out.json");
    let bad = [
        (
            dir.join("missing.json").to_str().unwrap().to_string(),
            "cannot read",
        ),
        (write("broken.json", "{\"format\": "), "not valid JSON"),
        (
            write("other.json", "{\"hello\": 1}"),
            "not a file shlight reads",
        ),
        (
            write(
                "short.json",
                r#"{"object": {"type": "LightProbe", "sh": [1, 2, 3]}}"#,
            ),
            "27 numbers",
        ),
        (write("lines.txt", "( 1.0, 2.0 ); // L00\n"), "line 1"),
        (write("words.txt", "hello\n"), "not a file shlight reads"),
        (
            write(
                "nan.json",
                r#"{"format":"shlight-sh","format_version":1,"lmax":0,"frame":"y-up","quantity":"radiance","coefficients":[[1,2]],"provenance":{}}"#,
            ),
            "not three numbers",
        ),
    ];
    for (path, words) in bad {
        let o = shlight(&[
            "convert",
            &path,
            "-o",
            out.to_str().unwrap(),
            "--format",
            "json",
        ]);
        assert!(!o.status.success(), "{path}");
        let err = String::from_utf8_lossy(&o.stderr);
        let file = Path::new(&path).file_name().unwrap().to_str().unwrap();
        assert!(err.contains(file) && err.contains(words), "{path}: {err}");
        assert!(!out.exists(), "{path}: nothing may be written");
    }
    // A directory as output: the write fails, naming it.
    let input = cases().remove(0).write(&dir);
    let o = shlight(&[
        "convert",
        input.to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
        "--format",
        "c",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("writing"));
}

#[test]
fn engine_formats_say_when_they_truncate_or_pad() {
    let dir = temp_dir("export_notes");
    for (case, words) in [
        (cases().remove(2), "degrees 3..=4 of the input are dropped"),
        (cases().remove(4), "written as zeros"),
    ] {
        let input = case.write(&dir);
        for format in ["threejs", "gltf", "filament", "unity"] {
            let o = shlight(&[
                "convert",
                input.to_str().unwrap(),
                "--format",
                format,
                "--irradiance-only",
            ]);
            assert!(o.status.success());
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(
                err.contains("note:") && err.contains(words),
                "{format}: {err}"
            );
        }
    }
}

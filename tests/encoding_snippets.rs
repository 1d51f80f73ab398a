//! Every encoding's shader and C snippet against the core's CPU evaluation
//! of the same coefficient file (`CoeffFile::encoded`, what `shlight
//! irradiance --encoding` evaluates).
//!
//! Light: a synthetic sun (`shlight synth directional`, a 2-degree cap, so
//! `dominant+sh` extracts one light), the bundled sunny `park.exr` and the
//! softbox-lit `studio.exr`; each projected with every `--encoding`, then
//! converted to each snippet.
//!
//! - C (cc, and c++ for the header's C++ compatibility): compiled with
//!   `-Wall -Wextra -Werror`, run at a Fibonacci sphere plus directions in
//!   every light's horizon band (where Snyder's formula takes its second
//!   branch), printed to 17 digits, against the core in f64.
//! - WGSL, GLSL, HLSL (`gpu` feature): compiled into the compute shaders of
//!   the plain-SH snippet tests (naga's WGSL and GLSL front ends; HLSL
//!   through glslang to SPIR-V), validated by naga, then run on the GPU
//!   adapter (lavapipe in CI) against the core.

use std::path::{Path, PathBuf};

use glam::DVec3;
use shlight_core::encoding::Encoding;
use shlight_format::CoeffFile;

use crate::export::convert;
use crate::util::{
    compile_and_run, have_tool, s, shlight_ok, sphere_directions, synth_sun_map, temp_dir,
};

/// C in double against the core in f64, relative to the largest `|E|`: the
/// same formulas in the same order but for the SH sums (the snippet's
/// Legendre recurrence against the core's basis), a few ulps of 1e-16 at
/// lmax 2; a wrong constant or branch is off by far more than 1e-9.
const C_TOL: f64 = 1e-9;

/// One coefficient file per (map, encoding).
#[derive(Clone)]
struct Fixture {
    name: String,
    encoding: Encoding,
    json: PathBuf,
    file: CoeffFile,
}

/// Every encoding of the sun and two bundled maps, as coefficient files.
fn fixtures(dir: &Path) -> Vec<Fixture> {
    let envmaps = Path::new(env!("CARGO_MANIFEST_DIR")).join("envmaps");
    let maps = [
        ("sun", synth_sun_map(dir)),
        ("park", envmaps.join("park.exr")),
        ("studio", envmaps.join("studio.exr")),
    ];
    let mut out = Vec::new();
    for (name, map) in &maps {
        for encoding in Encoding::ALL {
            let json = dir.join(format!("{name}-{}.json", encoding.name().replace('+', "_")));
            shlight_ok(&[
                "project",
                s(map),
                "--encoding",
                encoding.name(),
                "-o",
                s(&json),
            ]);
            let file = CoeffFile::read(&json).unwrap();
            assert_eq!(file.encoding.encoding(), encoding);
            out.push(Fixture {
                name: format!("{name} {encoding}"),
                encoding,
                json,
                file,
            });
        }
    }
    // The sun really is extracted: one light within a degree of it.
    let sun = out
        .iter()
        .find(|f| f.name == "sun dominant+sh")
        .unwrap()
        .file
        .encoded()
        .unwrap();
    assert_eq!(sun.lights().len(), 1, "{:?}", sun.lights());
    let angle = sun.lights()[0]
        .direction
        .angle_between(DVec3::new(1.0, 1.0, 0.5))
        .to_degrees();
    assert!(angle < 1.0, "{angle}");
    out
}

/// The core's irradiance of the fixture's file.
fn cpu(f: &Fixture, n: DVec3) -> DVec3 {
    f.file.encoded().unwrap().irradiance(n)
}

/// A Fibonacci sphere plus, for every light, directions whose angle to it
/// is within its half-angle of 90 degrees (the cap crosses the horizon).
fn c_directions(f: &Fixture) -> Vec<DVec3> {
    let mut d = sphere_directions(1000);
    let encoded = f.file.encoded().unwrap();
    for light in encoded.lights() {
        let (u, v) = light.direction.any_orthonormal_pair();
        for i in 0..64 {
            let t = std::f64::consts::FRAC_PI_2 + light.half_angle * (i as f64 / 31.5 - 1.0);
            let phi = i as f64 * 2.399_963;
            let w = (u * phi.cos() + v * phi.sin()) * t.sin() + light.direction * t.cos();
            d.push(w.normalize());
        }
    }
    d
}

/// The worst error of `got` against `want`, relative to the largest `|want|`.
fn worst(dirs: &[DVec3], got: &[DVec3], want: impl Fn(DVec3) -> DVec3) -> f64 {
    let wants: Vec<DVec3> = dirs.iter().map(|d| want(*d)).collect();
    let scale = wants
        .iter()
        .map(|w| w.abs().max_element())
        .fold(0.0, f64::max)
        .max(1e-30);
    got.iter()
        .zip(&wants)
        .map(|(g, w)| (*g - *w).abs().max_element() / scale)
        .fold(0.0, f64::max)
}

/// Compiles `main` with `compiler` and returns the irradiance it printed,
/// one line per direction.
fn run_c(dir: &Path, compiler: &str, lang: &str, source: &str) -> Vec<DVec3> {
    compile_and_run(dir, "enc", compiler, lang, source)
        .iter()
        .map(|v| DVec3::new(v[0], v[1], v[2]))
        .collect()
}

#[test]
fn every_encodings_c_snippet_gives_the_cpu_irradiance() {
    let test = "every_encodings_c_snippet_gives_the_cpu_irradiance";
    let compilers: Vec<(&str, &str)> = [("cc", "c"), ("c++", "cpp")]
        .into_iter()
        .filter(|(tool, _)| have_tool(tool, test))
        .collect();
    if compilers.is_empty() {
        return;
    }
    let dir = temp_dir("encoding_snippets_c");
    let mut worst_all = 0.0f64;
    let mut horizon = 0;
    for f in fixtures(&dir) {
        let text = convert(&f.json, &dir.join("enc.h"), "c");
        assert!(
            f.encoding == Encoding::Sh || text.contains(&format!("the {} encoding", f.encoding)),
            "{}",
            f.name
        );
        let dirs = c_directions(&f);
        for light in f.file.encoded().unwrap().lights() {
            let sin_a = light.half_angle.sin();
            horizon += dirs
                .iter()
                .filter(|d| {
                    light.half_angle > 0.0 && d.dot(light.direction).powi(2) < sin_a * sin_a
                })
                .count();
        }
        let init: Vec<String> = dirs
            .iter()
            .map(|n| format!("{{{:?}, {:?}, {:?}}}", n.x, n.y, n.z))
            .collect();
        let main = format!(
            "{text}\n#include <stdio.h>\nint main(void) {{\n    static const double ns[][3] = {{{}}};\n    \
             for (unsigned i = 0; i < sizeof ns / sizeof ns[0]; i++) {{\n        double o[3];\n        \
             shlight_irradiance(ns[i], o);\n        \
             printf(\"%.17g %.17g %.17g\\n\", o[0], o[1], o[2]);\n    }}\n    return 0;\n}}\n",
            init.join(", ")
        );
        for (compiler, lang) in &compilers {
            let got = run_c(&dir, compiler, lang, &main);
            assert_eq!(got.len(), dirs.len());
            let e = worst(&dirs, &got, |n| cpu(&f, n));
            assert!(
                e <= C_TOL,
                "C ({compiler}) snippet of {}: off by {e:.2e} of max E (tolerance {C_TOL:e})",
                f.name
            );
            worst_all = worst_all.max(e);
        }
    }
    // The horizon branch of the cap formula was exercised.
    assert!(horizon > 50, "{horizon} directions in a horizon band");
    eprintln!("{test}: worst error {worst_all:.2e} of max E");
}

#[test]
fn the_lights_are_in_the_snippet_not_only_in_the_residual() {
    // Without its light the sun's snippet would be far off: the light's
    // irradiance is most of E, so the C test above can tell a lost light.
    let dir = temp_dir("encoding_snippets_lights");
    let map = synth_sun_map(&dir);
    let json = dir.join("sun.json");
    shlight_ok(&[
        "project",
        s(&map),
        "--encoding",
        "dominant+sh",
        "-o",
        s(&json),
    ]);
    let file = CoeffFile::read(&json).unwrap();
    let text = convert(&json, &dir.join("sun.wgsl"), "wgsl");
    assert!(
        text.contains("const SHLIGHT_LIGHT_COUNT: i32 = 1;"),
        "{text}"
    );
    let encoded = file.encoded().unwrap();
    let dirs = sphere_directions(200);
    let residual_only: Vec<DVec3> = dirs
        .iter()
        .map(|n| shlight_core::sh::irradiance(&file.coeffs).eval(*n))
        .collect();
    let e = worst(&dirs, &residual_only, |n| encoded.irradiance(n));
    assert!(e > 0.5, "the light is {e} of max E");
}

#[test]
fn project_writes_encoded_snippets_and_other_formats_refuse_them() {
    let dir = temp_dir("encoding_snippets_project");
    let map = synth_sun_map(&dir);
    let json = dir.join("zh3.json");
    shlight_ok(&["project", s(&map), "--encoding", "zh3", "-o", s(&json)]);
    let via_convert = convert(&json, &dir.join("a.glsl"), "glsl");
    let glsl = dir.join("b.glsl");
    shlight_ok(&[
        "project",
        s(&map),
        "--encoding",
        "zh3",
        "--format",
        "glsl",
        "-o",
        s(&glsl),
    ]);
    assert_eq!(std::fs::read_to_string(&glsl).unwrap(), via_convert);
    for format in ["threejs", "unity", "txt", "filament", "gltf"] {
        let err = crate::util::shlight_err(&[
            "convert",
            s(&json),
            "--format",
            format,
            "-o",
            s(&dir.join("x.out")),
        ]);
        assert!(
            err.contains("zh3") && err.contains(format) && err.contains("wgsl"),
            "{format}: {err}"
        );
    }
}

#[cfg(feature = "gpu")]
mod gpu {
    use super::*;
    use crate::export_shaders::{
        directions, glsl_compute, hlsl_compute, hlsl_via_glslang, naga_glsl, naga_wgsl, run,
        wgsl_compute,
    };
    use crate::util::gpu_context;

    /// f32 shaders against the core in f64, relative to the largest `|E|`:
    /// the values round to f32 (6e-8), the SH sums and the cap formula add a
    /// few ulps each, and GPU `atan`/`acos`/`pow` may be off by thousands of
    /// ulps (Vulkan's bounds); lavapipe measures 1.1e-6 (printed). Snyder's
    /// formula as the core writes it cancels in its horizon branch and was
    /// 1.7e-4 off for a 2-degree sun in f32, which the snippets' series form
    /// removes: this tolerance tells the two apart, and a wrong sign, branch
    /// or constant is off by 1e-3 or more.
    const GPU_TOL: f64 = 1e-5;

    /// Every fixture's snippet in every shader language, compiled into its
    /// compute shader and validated by naga.
    fn compile_all(test: &str, dir: &Path) -> Vec<(String, Fixture, naga::Module)> {
        let hlsl = have_tool("glslangValidator", test);
        let mut out = Vec::new();
        for f in fixtures(dir) {
            for format in ["wgsl", "glsl", "hlsl"] {
                if format == "hlsl" && !hlsl {
                    continue;
                }
                let snippet = convert(&f.json, &dir.join(format!("enc.{format}")), format);
                let what = format!("{format} snippet of {}", f.name);
                let module = match format {
                    "wgsl" => naga_wgsl(&wgsl_compute(&snippet, false)),
                    "glsl" => naga_glsl(&glsl_compute(&snippet, false)),
                    _ => hlsl_via_glslang(dir, &hlsl_compute(&snippet, false)),
                }
                .unwrap_or_else(|e| panic!("{what}: {e}\n{snippet}"));
                out.push((what, f.clone(), module));
            }
        }
        out
    }

    #[test]
    fn every_encodings_shader_snippets_compile() {
        let test = "every_encodings_shader_snippets_compile";
        let all = compile_all(test, &temp_dir("encoding_snippets_compile"));
        // 3 maps x 7 encodings in 2 or 3 languages.
        assert!(all.len() >= 42, "{}", all.len());
    }

    #[test]
    fn every_encodings_shader_snippets_run_on_the_gpu_give_the_cpu_irradiance() {
        let test = "every_encodings_shader_snippets_run_on_the_gpu_give_the_cpu_irradiance";
        let Some(ctx) = gpu_context(test) else {
            return;
        };
        let dirs = directions();
        let mut worst_all = 0.0f64;
        for (what, f, module) in compile_all(test, &temp_dir("encoding_snippets_gpu")) {
            let values = run(&ctx, module, &what);
            let got: Vec<DVec3> = values.iter().map(|v| v.0).collect();
            let e = worst(&dirs, &got, |n| cpu(&f, n));
            assert!(
                e <= GPU_TOL,
                "{what}: off by {e:.2e} of max E (tolerance {GPU_TOL:e})"
            );
            worst_all = worst_all.max(e);
        }
        eprintln!(
            "{test}: worst error {worst_all:.2e} of max E on {}",
            ctx.adapter_name()
        );
    }
}

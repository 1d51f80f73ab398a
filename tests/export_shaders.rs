//! The shader exporters' snippets compiled by real shader compilers and run
//! on the GPU: each snippet (`shlight convert` or `shlight project ...
//! --format wgsl|glsl|hlsl`) is included verbatim in a compute shader that
//! evaluates `shlight_irradiance(n)` and `shlight_radiance(n)` at many
//! directions into a storage buffer, which is read back and compared with
//! shlight's own `E(n)` and `L(n)` in f64.
//!
//! - WGSL: naga's WGSL front end and validator, then the driver.
//! - GLSL: naga's GLSL front end (`#version 450`) and validator.
//! - HLSL: glslang's HLSL front end (`glslangValidator -D`) to SPIR-V,
//!   read back and validated by naga.
//!
//! The compiling and validating is a test of its own, without a GPU. Every
//! module is handed to wgpu as naga IR, so the one that ran is the one that
//! was validated. Without a GPU adapter (Mesa's lavapipe in CI) the GPU
//! test prints a SKIPPED line, or fails under `SHLIGHT_REQUIRE_GPU=1` /
//! `SHLIGHT_REQUIRE_ALL=1`; a missing `glslangValidator` skips the HLSL
//! likewise, failing under `SHLIGHT_REQUIRE_ALL=1`.

use std::path::Path;
use std::process::Command;

use glam::DVec3;
use shlight_core::sh::{Frame, ShCoeffs};
use shlight_gpu::GpuContext;
use shlight_gpu::wgpu;
use wgpu::util::DeviceExt as _;

use crate::export::{Case, cases, convert, high_lmax_case};
use crate::util::{coefficients, gpu_context, have_tool, json, s, shlight, temp_dir, write_map};

/// Directions evaluated per shader: a Fibonacci sphere plus the six axes,
/// a whole number of 64-wide workgroups.
const DIRECTIONS: usize = 17 * 64;

/// Workgroup width of the three compute shaders.
const WORKGROUP: usize = 64;

/// f32 evaluation against f64, relative to the function's largest value:
/// the coefficients round to f32 (6e-8 relative), and the Legendre and
/// azimuth recurrences and the up-to-81-term sums at lmax 8 add a few ulps
/// each. The worst case measured on lavapipe is printed by the test (a few
/// 1e-7); 1e-5 leaves room for other drivers' `sqrt` and fused
/// multiply-adds while a wrong coefficient, sign or band weight is off by
/// far more (a band-weight slip alone is several percent of the scale).
const GPU_TOL: f64 = 1e-5;

/// Unit directions: a Fibonacci sphere plus the axes.
pub fn directions() -> Vec<DVec3> {
    crate::util::sphere_directions(DIRECTIONS)
}

// ---------------------------------------------------------------- shaders

/// The WGSL snippet inside a compute shader: value `2i` is `E(d_i)`, value
/// `2i + 1` is `L(d_i)` (zero for an irradiance snippet, which has no
/// `shlight_radiance`).
pub fn wgsl_compute(snippet: &str, radiance: bool) -> String {
    let r = if radiance {
        "vec4<f32>(shlight_radiance(d), 0.0)"
    } else {
        "vec4<f32>(0.0)"
    };
    format!(
        "{snippet}\n\
         @group(0) @binding(0) var<storage, read> test_directions: array<vec4<f32>>;\n\
         @group(0) @binding(1) var<storage, read_write> test_values: array<vec4<f32>>;\n\
         @compute @workgroup_size({WORKGROUP})\n\
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{\n    \
             let d = test_directions[id.x].xyz;\n    \
             test_values[2u * id.x] = vec4<f32>(shlight_irradiance(d), 0.0);\n    \
             test_values[2u * id.x + 1u] = {r};\n\
         }}\n"
    )
}

/// The GLSL snippet inside a `#version 450` compute shader (values as in
/// [`wgsl_compute`]).
pub fn glsl_compute(snippet: &str, radiance: bool) -> String {
    let r = if radiance {
        "vec4(shlight_radiance(d), 0.0)"
    } else {
        "vec4(0.0)"
    };
    format!(
        "#version 450\n{snippet}\n\
         layout(local_size_x = {WORKGROUP}) in;\n\
         layout(std430, set = 0, binding = 0) readonly buffer TestDirections {{ vec4 test_directions[]; }};\n\
         layout(std430, set = 0, binding = 1) buffer TestValues {{ vec4 test_values[]; }};\n\
         void main() {{\n    \
             uint i = gl_GlobalInvocationID.x;\n    \
             vec3 d = test_directions[i].xyz;\n    \
             test_values[2u * i] = vec4(shlight_irradiance(d), 0.0);\n    \
             test_values[2u * i + 1u] = {r};\n\
         }}\n"
    )
}

/// The HLSL snippet inside a compute shader (values as in [`wgsl_compute`]).
pub fn hlsl_compute(snippet: &str, radiance: bool) -> String {
    let r = if radiance {
        "float4(shlight_radiance(d), 0.0)"
    } else {
        "float4(0.0, 0.0, 0.0, 0.0)"
    };
    format!(
        "{snippet}\n\
         [[vk::binding(0, 0)]] StructuredBuffer<float4> test_directions;\n\
         [[vk::binding(1, 0)]] RWStructuredBuffer<float4> test_values;\n\
         [numthreads({WORKGROUP}, 1, 1)]\n\
         void main(uint3 id : SV_DispatchThreadID) {{\n    \
             float3 d = test_directions[id.x].xyz;\n    \
             test_values[2 * id.x] = float4(shlight_irradiance(d), 0.0);\n    \
             test_values[2 * id.x + 1] = {r};\n\
         }}\n"
    )
}

fn validate(module: naga::Module, source: &str) -> Result<naga::Module, String> {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(source))?;
    Ok(module)
}

/// WGSL parsed and validated by naga.
pub fn naga_wgsl(source: &str) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    validate(module, source)
}

/// A GLSL compute shader parsed and validated by naga.
pub fn naga_glsl(source: &str) -> Result<naga::Module, String> {
    let module = naga::front::glsl::Frontend::default()
        .parse(
            &naga::front::glsl::Options::from(naga::ShaderStage::Compute),
            source,
        )
        .map_err(|e| e.emit_to_string(source))?;
    validate(module, source)
}

/// An HLSL compute shader compiled to SPIR-V by glslang (its HLSL front
/// end), then read back and validated by naga.
pub fn hlsl_via_glslang(dir: &Path, source: &str) -> Result<naga::Module, String> {
    let (src, spv) = (dir.join("test.comp.hlsl"), dir.join("test.comp.spv"));
    std::fs::write(&src, source).unwrap();
    let out = Command::new("glslangValidator")
        .args(["-D", "-V", "-S", "comp", "-e", "main", "-o"])
        .arg(&spv)
        .arg(&src)
        .output()
        .map_err(|e| format!("glslangValidator: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "glslangValidator rejects {}:\n{}{}",
            src.display(),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let words = std::fs::read(&spv).unwrap();
    let module = naga::front::spv::parse_u8_slice(&words, &naga::front::spv::Options::default())
        .map_err(|e| format!("naga cannot read glslang's SPIR-V: {e}"))?;
    validate(module, source)
}

// ---------------------------------------------------------------- the GPU

/// Runs `module`'s `main` over [`directions`] and returns, per direction,
/// `(E, L)` as the shader computed them.
pub fn run(ctx: &GpuContext, module: naga::Module, what: &str) -> Vec<(DVec3, DVec3)> {
    let device = &ctx.device;
    let dirs = directions();
    let input: Vec<u8> = dirs
        .iter()
        .flat_map(|d| [d.x as f32, d.y as f32, d.z as f32, 0.0])
        .flat_map(f32::to_le_bytes)
        .collect();
    let size = (2 * dirs.len() * 16) as u64;
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(what),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(what),
        layout: None,
        module: &shader,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let directions = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("test directions"),
        contents: &input,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let values = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("test values"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("test readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: directions.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: values.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups((dirs.len() / WORKGROUP) as u32, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&values, 0, &readback, 0, None);
    ctx.queue.submit([encoder.finish()]);
    if let Some(e) = pollster::block_on(validation.pop()) {
        panic!("{what}: wgpu refuses the shader: {e}");
    }
    let bytes = shlight_gpu::read_buffer(ctx, &readback).unwrap();
    let f: Vec<f64> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()) as f64)
        .collect();
    f.chunks_exact(8)
        .map(|v| (DVec3::new(v[0], v[1], v[2]), DVec3::new(v[4], v[5], v[6])))
        .collect()
}

/// The largest error of `got` against `want` over [`directions`], relative
/// to the largest `|want|`.
fn worst_error(got: impl Fn(usize) -> DVec3, want: impl Fn(DVec3) -> DVec3) -> f64 {
    let dirs = directions();
    let wants: Vec<DVec3> = dirs.iter().map(|d| want(*d)).collect();
    let scale = wants
        .iter()
        .map(|w| w.abs().max_element())
        .fold(0.0, f64::max)
        .max(1e-30);
    (0..dirs.len())
        .map(|i| (got(i) - wants[i]).abs().max_element() / scale)
        .fold(0.0, f64::max)
}

/// The GPU's values against shlight's `E` and `L` of `case` at lmax `lmax`,
/// at the directions in the file's own axes (the snippets' axes).
fn check(what: &str, case: &Case, values: &[(DVec3, DVec3)]) -> f64 {
    let lmax = case.radiance.lmax();
    let e = worst_error(|i| values[i].0, |d| case.irradiance_at(lmax, d, true));
    assert!(
        e <= GPU_TOL,
        "{what}: irradiance off by {e:.2e} of its scale (tolerance {GPU_TOL:e})"
    );
    let mut worst = e;
    if !case.irradiance_file {
        let l = worst_error(|i| values[i].1, |d| case.radiance_at(lmax, d, true));
        assert!(
            l <= GPU_TOL,
            "{what}: radiance off by {l:.2e} of its scale (tolerance {GPU_TOL:e})"
        );
        worst = worst.max(l);
    }
    worst
}

/// `shlight project` of a small map, as the coefficient file's light (for
/// the reference) and the path of the map (to export from).
fn projected_case(dir: &Path) -> (Case, std::path::PathBuf) {
    let map = dir.join("map.exr");
    // Smooth and asymmetric: every band up to lmax 3 carries light.
    write_map(&map, 64, 32, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / 64.0, (y as f32 + 0.5) / 32.0);
        [
            1.0 + (std::f32::consts::TAU * u).cos() * (std::f32::consts::PI * v).sin(),
            0.5 + v * v,
            0.2 + u * (1.0 - v),
        ]
    });
    let file = json(&shlight(&["project", s(&map), "--lmax", "3"]));
    let frame = match file["frame"].as_str().unwrap() {
        "y-up" => Frame::YUp,
        "z-up" => Frame::ZUp,
        other => panic!("frame {other}"),
    };
    assert_eq!(file["quantity"], "radiance");
    let rows = coefficients(&file);
    let case = Case {
        name: "projected",
        radiance: ShCoeffs::from_vec(rows.into_iter().map(DVec3::from_array).collect()).unwrap(),
        frame,
        irradiance_file: false,
    };
    (case, map)
}

/// A snippet compiled into its compute shader and validated, with the case
/// it holds.
struct Compiled {
    what: String,
    case: Case,
    module: naga::Module,
}

/// Every case (and a projected map) exported as WGSL, GLSL and HLSL (HLSL
/// only when `glslangValidator` is installed, else [`have_tool`] skips it
/// for `test`), each put into its compute shader, compiled and validated;
/// a rejected shader fails `test`.
fn compile_all(test: &str, dir: &Path) -> Vec<Compiled> {
    let hlsl = have_tool("glslangValidator", test);
    let (projected, map) = projected_case(dir);
    let mut all: Vec<(Case, Option<std::path::PathBuf>)> =
        cases().into_iter().map(|c| (c, None)).collect();
    all.push((high_lmax_case(), None));
    all.push((projected, Some(map)));
    let mut compiled = Vec::new();
    for (case, map) in all {
        let input = match map {
            Some(_) => None,
            None => Some(case.write(dir)),
        };
        for format in ["wgsl", "glsl", "hlsl"] {
            if format == "hlsl" && !hlsl {
                continue;
            }
            let out = dir.join(format!("sh.{format}"));
            // Coefficient files through `convert`; the map through
            // `project --format`.
            let snippet = match (&input, &map) {
                (Some(file), _) => convert(file, &out, format),
                (None, Some(map)) => {
                    let o = shlight(&[
                        "project",
                        s(map),
                        "--lmax",
                        "3",
                        "--format",
                        format,
                        "-o",
                        s(&out),
                    ]);
                    assert!(
                        o.status.success(),
                        "project --format {format}: {}",
                        String::from_utf8_lossy(&o.stderr)
                    );
                    std::fs::read_to_string(&out).unwrap()
                }
                (None, None) => unreachable!(),
            };
            let radiance = !case.irradiance_file;
            let what = format!("{format} snippet of {}", case.name);
            let module = match format {
                "wgsl" => naga_wgsl(&wgsl_compute(&snippet, radiance)),
                "glsl" => naga_glsl(&glsl_compute(&snippet, radiance)),
                _ => hlsl_via_glslang(dir, &hlsl_compute(&snippet, radiance)),
            }
            .unwrap_or_else(|e| panic!("{what}: {e}"));
            compiled.push(Compiled {
                what,
                case: case.clone(),
                module,
            });
        }
    }
    compiled
}

/// Without a GPU: every snippet compiles and validates inside its compute
/// shader (the GPU test below runs these very modules).
#[test]
fn shader_snippets_compile_into_compute_shaders() {
    let test = "shader_snippets_compile_into_compute_shaders";
    let compiled = compile_all(test, &temp_dir("export_shaders_compile"));
    // 7 light sets (5 cases, lmax 8, a projected map) in 2 or 3 languages.
    assert!(compiled.len() >= 14, "{} shaders", compiled.len());
}

#[test]
fn shader_snippets_run_on_the_gpu_give_shlight_values() {
    let test = "shader_snippets_run_on_the_gpu_give_shlight_values";
    let Some(ctx) = gpu_context(test) else {
        return;
    };
    let mut worst = 0.0f64;
    for c in compile_all(test, &temp_dir("export_shaders_gpu")) {
        let values = run(&ctx, c.module, &c.what);
        worst = worst.max(check(&c.what, &c.case, &values));
    }
    // Shown with --nocapture: the measured margin under GPU_TOL.
    eprintln!(
        "{test}: worst error {worst:.2e} of scale on {}",
        ctx.adapter_name()
    );
}

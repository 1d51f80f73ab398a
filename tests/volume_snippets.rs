//! An irradiance volume in engines' own shaders: `shlight convert
//! VOLUME.shvol -o FILE.wgsl|glsl` writes the visibility-weighted lookup as
//! a snippet and its textures as KTX2 files (docs/shvol.md, "Engines'
//! shaders"). Each snippet runs in a compute shader on the GPU adapter
//! (lavapipe in CI) with the textures as the KTX2 files hold them (read by
//! the `ktx2` crate, an independent reader), at random points of two
//! sealed rooms split by a thin wall, half of them beside the wall; what it
//! returns must equal `shlight sample` (the CPU's one definition) at every
//! point. The GLSL runs through naga's GLSL front end with the fetch
//! macros defined to Vulkan textures, and glslang compiles the snippet as
//! written (its own `sampler3D` uniforms) in a WebGL2 (`#version 300 es`)
//! and a desktop (`#version 330`) fragment shader.

use std::path::{Path, PathBuf};

use glam::Vec3;
use serde_json::Value;
use shlight_gpu::{GpuContext, wgpu};
use wgpu::util::DeviceExt as _;

use crate::export_shaders::{naga_glsl, naga_wgsl};
use crate::util::{bake_two_rooms, gpu_context, have_tool, s, shlight, shlight_ok, temp_dir};

/// Queries per run: a whole number of 64-wide workgroups.
const QUERIES: usize = 16 * 64;

/// f32 on the GPU against the CPU's f32 weights and f64 sums: within this
/// fraction of the largest irradiance among the queries (the GPU's volume
/// pass meets the same bound against the same lookup, tests/volume_gpu.rs,
/// where the reasons are given; measured here: printed by the test).
const TOL: f64 = 1e-5;

/// A fixed linear congruential sequence (Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        lo + (hi - lo) * ((self.0 >> 40) as f32 / (1u64 << 24) as f32)
    }
}

/// The wall's centre in x.
const WALL: f32 = 2.1;

/// The two rooms baked (8x3x4 probes over 4 x 1.5 x 2 m, visibility and
/// relocation on, as by default), `n` random points and normals written
/// as POINTS.json, and `shlight sample`'s irradiance at them.
fn baked(dir: &Path) -> (PathBuf, Vec<(Vec3, Vec3)>, Vec<[f64; 3]>) {
    let mut sky = [[0.0; 3]; 9];
    sky[0] = [1.0; 3];
    let volume = bake_two_rooms(dir, WALL, &sky, "8x3x4");
    // Half anywhere in (and a little beyond) the box, half within 0.3 of
    // the wall on either side, where the visibility weights matter most.
    let mut rng = Lcg(7);
    let queries: Vec<(Vec3, Vec3)> = (0..QUERIES)
        .map(|k| {
            let x = if k % 2 == 0 {
                rng.range(-0.2, 4.2)
            } else {
                WALL + rng.range(-0.3, 0.3)
            };
            let p = Vec3::new(x, rng.range(0.02, 1.48), rng.range(0.02, 1.98));
            let n = loop {
                let v = Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                );
                if (0.1..1.0).contains(&v.length()) {
                    break v.normalize();
                }
            };
            (p, n)
        })
        .collect();
    let json = serde_json::json!({
        "points": queries.iter().map(|(p, _)| p.to_array()).collect::<Vec<_>>(),
        "normals": queries.iter().map(|(_, n)| n.to_array()).collect::<Vec<_>>(),
    });
    let points = dir.join("points.json");
    std::fs::write(&points, json.to_string()).unwrap();
    let out = dir.join("sampled.json");
    shlight_ok(&["sample", s(&volume), "--points", s(&points), "-o", s(&out)]);
    let v: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(v["lookup"], "shlight");
    let want = v["irradiance"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            let e = e.as_array().unwrap();
            [0, 1, 2].map(|c| e[c].as_f64().unwrap())
        })
        .collect();
    (volume, queries, want)
}

/// A texture of the export as the `ktx2` crate reads it: format, size,
/// texels.
struct Texture {
    format: wgpu::TextureFormat,
    size: [u32; 3],
    bytes: Vec<u8>,
}

fn read_texture(path: &Path) -> Texture {
    let file = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let reader = ktx2::Reader::new(&file[..]).expect("a KTX2 file");
    let h = reader.header();
    let format = match h.format.map(|f| f.value()) {
        Some(109) => wgpu::TextureFormat::Rgba32Float,
        Some(103) => wgpu::TextureFormat::Rg32Float,
        other => panic!("{}: format {other:?}", path.display()),
    };
    Texture {
        format,
        size: [h.pixel_width, h.pixel_height, h.pixel_depth.max(1)],
        bytes: reader.levels().next().unwrap().data.to_vec(),
    }
}

/// Runs `module`'s `main` over the queries with the textures at bindings
/// 0, 1, 2 (group 0), a non-filtering sampler at 3 where the module has
/// one, the queries at 4 and the answers at 5; returns the answers.
fn run(
    ctx: &GpuContext,
    module: naga::Module,
    textures: &[Texture],
    queries: &[(Vec3, Vec3)],
) -> Vec<[f64; 3]> {
    let device = &ctx.device;
    let has_sampler = module
        .global_variables
        .iter()
        .any(|(_, g)| matches!(module.types[g.ty].inner, naga::TypeInner::Sampler { .. }));
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("volume snippet"),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
    });
    let mut layout_entries: Vec<wgpu::BindGroupLayoutEntry> = (0..textures.len() as u32)
        .map(|binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D3,
                multisampled: false,
            },
            count: None,
        })
        .collect();
    if has_sampler {
        layout_entries.push(wgpu::BindGroupLayoutEntry {
            binding: 3,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::NonFiltering),
            count: None,
        });
    }
    for (binding, read_only) in [(4, true), (5, false)] {
        layout_entries.push(wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        });
    }
    let group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &layout_entries,
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&group_layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("volume snippet"),
        layout: Some(&layout),
        module: &shader,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let views: Vec<wgpu::TextureView> = textures
        .iter()
        .map(|t| {
            let texture = device.create_texture_with_data(
                &ctx.queue,
                &wgpu::TextureDescriptor {
                    label: None,
                    size: wgpu::Extent3d {
                        width: t.size[0],
                        height: t.size[1],
                        depth_or_array_layers: t.size[2],
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D3,
                    format: t.format,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                },
                wgpu::util::TextureDataOrder::LayerMajor,
                &t.bytes,
            );
            texture.create_view(&Default::default())
        })
        .collect();
    let sampler = device.create_sampler(&Default::default());
    let input: Vec<u8> = queries
        .iter()
        .flat_map(|(p, n)| [p.x, p.y, p.z, 0.0, n.x, n.y, n.z, 0.0])
        .flat_map(f32::to_le_bytes)
        .collect();
    let size = (queries.len() * 16) as u64;
    let query_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("queries"),
        contents: &input,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let answers = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("answers"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut entries: Vec<wgpu::BindGroupEntry> = views
        .iter()
        .enumerate()
        .map(|(k, v)| wgpu::BindGroupEntry {
            binding: k as u32,
            resource: wgpu::BindingResource::TextureView(v),
        })
        .collect();
    if has_sampler {
        entries.push(wgpu::BindGroupEntry {
            binding: 3,
            resource: wgpu::BindingResource::Sampler(&sampler),
        });
    }
    entries.push(wgpu::BindGroupEntry {
        binding: 4,
        resource: query_buffer.as_entire_binding(),
    });
    entries.push(wgpu::BindGroupEntry {
        binding: 5,
        resource: answers.as_entire_binding(),
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &group_layout,
        entries: &entries,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups((queries.len() / 64) as u32, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&answers, 0, &readback, 0, None);
    ctx.queue.submit([encoder.finish()]);
    if let Some(e) = pollster::block_on(validation.pop()) {
        panic!("wgpu refuses the snippet's shader: {e}");
    }
    shlight_gpu::read_buffer(ctx, &readback)
        .unwrap()
        .chunks_exact(16)
        .map(|b| {
            [0, 1, 2]
                .map(|c| f64::from(f32::from_le_bytes(b[4 * c..4 * c + 4].try_into().unwrap())))
        })
        .collect()
}

/// The worst difference, relative to the largest `want`.
fn worst(got: &[[f64; 3]], want: &[[f64; 3]]) -> (f64, usize) {
    let scale = want
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(1e-30);
    let mut out = (0.0, 0);
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        for c in 0..3 {
            let e = (g[c] - w[c]).abs() / scale;
            if e > out.0 || e.is_nan() {
                out = (e, k);
            }
        }
    }
    out
}

fn wgsl_compute(snippet: &str) -> String {
    format!(
        "{snippet}\n\
         @group(0) @binding(0) var test_sh: texture_3d<f32>;\n\
         @group(0) @binding(1) var test_probes: texture_3d<f32>;\n\
         @group(0) @binding(2) var test_moments: texture_3d<f32>;\n\
         @group(0) @binding(4) var<storage, read> test_queries: array<vec4<f32>>;\n\
         @group(0) @binding(5) var<storage, read_write> test_answers: array<vec4<f32>>;\n\
         @compute @workgroup_size(64)\n\
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{\n    \
             let p = test_queries[2u * id.x].xyz;\n    \
             let n = test_queries[2u * id.x + 1u].xyz;\n    \
             test_answers[id.x] = vec4<f32>(shlight_volume_irradiance(test_sh, test_probes, test_moments, p, n), 0.0);\n\
         }}\n"
    )
}

/// The GLSL snippet in a Vulkan (`#version 450`) compute shader, its fetch
/// macros defined to textures and a sampler of set 0.
fn glsl_compute(snippet: &str) -> String {
    format!(
        "#version 450\n\
         layout(set = 0, binding = 0) uniform texture3D test_sh;\n\
         layout(set = 0, binding = 1) uniform texture3D test_probes;\n\
         layout(set = 0, binding = 2) uniform texture3D test_moments;\n\
         layout(set = 0, binding = 3) uniform sampler test_sampler;\n\
         #define SHLIGHT_VOLUME_SH(c) texelFetch(sampler3D(test_sh, test_sampler), c, 0)\n\
         #define SHLIGHT_VOLUME_PROBES(c) texelFetch(sampler3D(test_probes, test_sampler), c, 0)\n\
         #define SHLIGHT_VOLUME_MOMENTS(c) texelFetch(sampler3D(test_moments, test_sampler), c, 0)\n\
         {snippet}\n\
         layout(local_size_x = 64) in;\n\
         layout(std430, set = 0, binding = 4) readonly buffer TestQueries {{ vec4 test_queries[]; }};\n\
         layout(std430, set = 0, binding = 5) buffer TestAnswers {{ vec4 test_answers[]; }};\n\
         void main() {{\n    \
             uint i = gl_GlobalInvocationID.x;\n    \
             test_answers[i] = vec4(shlight_volume_irradiance(test_queries[2u * i].xyz, test_queries[2u * i + 1u].xyz), 0.0);\n\
         }}\n"
    )
}

/// `convert` of the rooms' volume to `name` (.wgsl or .glsl): the snippet
/// and the three textures (sh, probes, moments) as read back.
fn converted(dir: &Path, volume: &Path, name: &str) -> (String, Vec<Texture>) {
    let out = dir.join(name);
    shlight_ok(&["convert", s(volume), "-o", s(&out)]);
    let stem = out.file_stem().unwrap().to_str().unwrap().to_string();
    let textures = ["sh", "probes", "moments"]
        .map(|t| read_texture(&dir.join(format!("{stem}.{t}.ktx2"))))
        .into_iter()
        .collect();
    (std::fs::read_to_string(&out).unwrap(), textures)
}

#[test]
fn volume_snippets_on_the_gpu_equal_shlight_sample_beside_a_wall() {
    let test = "volume_snippets_on_the_gpu_equal_shlight_sample_beside_a_wall";
    let Some(ctx) = gpu_context(test) else {
        return;
    };
    let dir = temp_dir("volume-snippets");
    let (volume, queries, want) = baked(&dir);
    // The lookup must matter here: trilinear interpolation through the
    // wall is far off at the points beside it (so a snippet that dropped
    // the visibility weights would fail).
    let tri = dir.join("trilinear.json");
    shlight_ok(&[
        "sample",
        s(&volume),
        "--points",
        s(&dir.join("points.json")),
        "--lookup",
        "trilinear",
        "-o",
        s(&tri),
    ]);
    let v: Value = serde_json::from_slice(&std::fs::read(&tri).unwrap()).unwrap();
    let trilinear: Vec<[f64; 3]> = v["irradiance"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| [0, 1, 2].map(|c| e[c].as_f64().unwrap()))
        .collect();
    let (leak, _) = worst(&trilinear, &want);
    assert!(leak > 0.05, "trilinear differs by only {leak:e}");

    let (wgsl, textures) = converted(&dir, &volume, "rooms.wgsl");
    let module = naga_wgsl(&wgsl_compute(&wgsl)).unwrap_or_else(|e| panic!("{e}"));
    let got = run(&ctx, module, &textures, &queries);
    let (e, k) = worst(&got, &want);
    eprintln!("WGSL volume snippet vs shlight sample: worst {e:.2e} of the largest (query {k})");
    assert!(
        e < TOL,
        "WGSL snippet at {:?} facing {:?}: {:?}, shlight sample {:?} ({e:e} of the largest)",
        queries[k].0,
        queries[k].1,
        got[k],
        want[k]
    );

    let (glsl, textures) = converted(&dir, &volume, "rooms.glsl");
    let module = naga_glsl(&glsl_compute(&glsl)).unwrap_or_else(|e| panic!("{e}"));
    let got = run(&ctx, module, &textures, &queries);
    let (e, k) = worst(&got, &want);
    eprintln!("GLSL volume snippet vs shlight sample: worst {e:.2e} of the largest (query {k})");
    assert!(
        e < TOL,
        "GLSL snippet at {:?} facing {:?}: {:?}, shlight sample {:?} ({e:e} of the largest)",
        queries[k].0,
        queries[k].1,
        got[k],
        want[k]
    );
}

/// glslang compiles the GLSL snippet as written (its default `sampler3D`
/// uniforms and `texelFetch`) in a WebGL2 and a desktop fragment shader.
#[test]
fn the_glsl_volume_snippet_compiles_for_webgl2_and_desktop() {
    let test = "the_glsl_volume_snippet_compiles_for_webgl2_and_desktop";
    if !have_tool("glslangValidator", test) {
        return;
    }
    let dir = temp_dir("volume-snippet-glslang");
    let mut sky = [[0.0; 3]; 9];
    sky[0] = [1.0; 3];
    let volume = bake_two_rooms(&dir, WALL, &sky, "4x2x2");
    let out = dir.join("rooms.glsl");
    shlight_ok(&["convert", s(&volume), "-o", s(&out)]);
    let snippet = std::fs::read_to_string(&out).unwrap();
    for (version, extra) in [
        (
            "300 es",
            "precision highp float;\nprecision highp int;\nprecision highp sampler3D;\n",
        ),
        ("330", ""),
    ] {
        let shader = dir.join(format!("test-{}.frag", version.replace(' ', "")));
        std::fs::write(
            &shader,
            format!(
                "#version {version}\n{extra}{snippet}\nin vec3 world;\nin vec3 normal;\nout vec4 colour;\n\
                 void main() {{\n    colour = vec4(shlight_volume_irradiance(world, normal) / 3.14159265, 1.0);\n}}\n"
            ),
        )
        .unwrap();
        let o = std::process::Command::new("glslangValidator")
            .arg(&shader)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "glslang rejects the snippet in a #version {version} fragment shader:\n{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

/// Bad requests are clear errors, and nothing is written.
#[test]
fn a_volume_converts_only_to_wgsl_or_glsl_with_an_output() {
    let dir = temp_dir("volume-snippet-errors");
    let mut sky = [[0.0; 3]; 9];
    sky[0] = [1.0; 3];
    let volume = bake_two_rooms(&dir, WALL, &sky, "2x1x1");
    for (args, message) in [
        (
            vec!["convert", s(&volume), "--format", "unity", "-o", "x.json"],
            "converts to --format threejs (three.js's LightProbeGrid), wgsl or glsl",
        ),
        (vec!["convert", s(&volume), "--format", "wgsl"], "needs -o"),
    ] {
        let out = shlight(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(message),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    assert!(!Path::new("x.json").exists());
}

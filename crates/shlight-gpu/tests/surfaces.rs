//! A glTF scene's surfaces on the GPU (`shaders/material.wgsl`), against
//! values worked out by hand: base colour textures decoded from sRGB and
//! multiplied by the factor, `COLOR_0` and `1 - metallic`; `MASK` cut-outs
//! showing what lies behind; `BLEND` as dithered coverage; instancing
//! against the flattened scene; double-sided and single-sided faces seen
//! from behind; the same albedo under the volume pass, PRT and an
//! encoding. Without an adapter each test prints a SKIPPED line and
//! passes, unless `SHLIGHT_REQUIRE_GPU=1` or `SHLIGHT_REQUIRE_ALL=1`, when
//! it fails.

use std::f64::consts::PI;

use glam::{Affine2, DVec3, Mat4, Vec2, Vec3, Vec4};
use shlight_baked::{ProbeGrid, TransferView, VolumeView};
use shlight_core::sh::closed_form;
use shlight_gpu::{
    Background, Camera, Frame, GltfScene, GpuContext, HEADLESS_FORMAT, Mode, Offscreen, Renderer,
    Scene as GpuScene, Shading, Shot, VolumeRenderer, render_frame,
};
use shlight_mesh::{
    AlphaMode, Filter, Instance, Material, Primitive, Scene, Texture, TextureRef, Wrap, generate,
};

/// The frame's side in pixels: a texel of the 2x2 textures below covers
/// about 100 pixels, so the pixel nearest a texel's centre lies within half
/// a percent of a texel of it, where bilinear filtering mixes in at most
/// half a percent of a neighbour.
const SIZE: usize = 256;

/// Frames against the linear albedo worked out on the CPU: within 1 % of
/// white (bilinear filtering half a pixel from a texel's centre, f32
/// shading).
const TOL: f32 = 0.01;

fn context(test: &str) -> Option<GpuContext> {
    match GpuContext::headless() {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            for var in ["SHLIGHT_REQUIRE_GPU", "SHLIGHT_REQUIRE_ALL"] {
                if std::env::var(var).as_deref() == Ok("1") {
                    panic!("{test}: {var}=1 but it would be skipped: {e}");
                }
            }
            eprintln!("SKIPPED {test}: {e}");
            None
        }
    }
}

/// A 2x2 texture, its texels (sRGB) in rows from the top.
fn texture(texels: [[u8; 4]; 4], filter: Filter) -> Texture {
    Texture {
        width: 2,
        height: 2,
        texels: texels.to_vec(),
        wrap_u: Wrap::ClampToEdge,
        wrap_v: Wrap::ClampToEdge,
        filter,
    }
}

/// The unit quad in the xz plane at height `y`, normal +Y, `size` on a
/// side, UV `(u, v) = (x, z) / size + 0.5`, with `material` and `COLOR_0`
/// `color` (RGBA) at every vertex.
fn quad(size: f32, y: f32, material: usize, color: Vec4) -> Primitive {
    let mut mesh = generate::plane(size, 1);
    let uv = mesh
        .positions
        .iter()
        .map(|p| Vec2::new(p.x / size + 0.5, p.z / size + 0.5))
        .collect();
    mesh.positions.iter_mut().for_each(|p| p.y = y);
    let n = mesh.vertex_count();
    mesh.colors = Some(vec![color.truncate(); n]);
    Primitive {
        mesh,
        uvs: vec![uv],
        color_alpha: Some(vec![color.w; n]),
        material: Some(material),
        label: format!("quad at y = {y}"),
    }
}

/// A scene of `primitives`, each placed once untransformed, with
/// `materials` and `textures`.
fn scene(primitives: Vec<Primitive>, materials: Vec<Material>, textures: Vec<Texture>) -> Scene {
    let instances = (0..primitives.len())
        .map(|primitive| Instance {
            primitive,
            transform: Mat4::IDENTITY,
        })
        .collect();
    Scene {
        source: "hand-made.glb".into(),
        primitives,
        instances,
        materials,
        textures,
        ..Scene::default()
    }
}

/// A material reading texture 0 through UV set 0.
fn textured(base_color: Vec4, alpha_mode: AlphaMode) -> Material {
    Material {
        base_color,
        base_color_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
            transform: Affine2::IDENTITY,
        }),
        alpha_mode,
        ..Material::default()
    }
}

/// The constant white environment: radiance 1 everywhere, irradiance `pi`
/// on every normal, so a Lambertian surface of albedo `rho` shows `rho`.
fn white() -> shlight_core::sh::ShCoeffs<DVec3> {
    closed_form::constant(2, DVec3::ONE)
}

/// Linear output, nothing behind.
fn shading(mode: Mode) -> Shading {
    Shading {
        mode,
        ..Shading::default()
    }
}

/// Looking straight down at the origin from `height` above it.
fn from_above(height: f32) -> Camera {
    Camera::looking_at(Vec3::new(0.0, height, 0.0), Vec3::ZERO, 2.0, 0.6)
}

/// The pixel of `frame` that world point `p` falls in, seen by `camera`.
fn pixel_at(frame: &Frame, camera: &Camera, p: Vec3) -> [f32; 4] {
    let clip = camera.view_proj(1.0) * p.extend(1.0);
    let (x, y) = (clip.x / clip.w, clip.y / clip.w);
    let px = ((x + 1.0) * 0.5 * frame.width as f32) as usize;
    let py = ((1.0 - y) * 0.5 * frame.height as f32) as usize;
    frame.pixels[py * frame.width + px]
}

/// The centre of texel `(i, j)` (row `j` from the top) of a 2x2 texture on
/// [`quad`] of `size` at height `y`, in world space.
fn texel_centre(i: usize, j: usize, size: f32, y: f32) -> Vec3 {
    let uv = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) / 2.0;
    Vec3::new((uv.x - 0.5) * size, y, (uv.y - 0.5) * size)
}

/// An 8-bit sRGB texel as linear RGB (shlight-io's decoding, the CPU's).
fn linear(t: [u8; 4]) -> Vec3 {
    let c = |v: u8| shlight_io::srgb_to_linear(f32::from(v) / 255.0);
    Vec3::new(c(t[0]), c(t[1]), c(t[2]))
}

fn assert_rgb(got: [f32; 4], want: Vec3, what: &str) -> f32 {
    let err = (Vec3::new(got[0], got[1], got[2]) - want)
        .abs()
        .max_element();
    assert!(
        got[3] == 1.0 && err <= TOL,
        "{what}: got {got:?}, want {want}"
    );
    err
}

const TEXELS: [[u8; 4]; 4] = [
    [200, 60, 20, 255],
    [30, 180, 90, 255],
    [120, 120, 250, 255],
    [255, 255, 255, 255],
];

/// Each texel's centre shows `baseColorFactor x texel (sRGB decoded) x
/// COLOR_0 x (1 - metallic)` under the white environment (irradiance pi),
/// in SH mode, through an encoding whose irradiance is pi, and in PRT mode
/// with transfer per unit albedo whose exit radiance is 1; with linear and
/// nearest filtering.
#[test]
fn texel_centres_show_factor_times_texel_times_colour_times_one_less_metallic() {
    let Some(ctx) =
        context("texel_centres_show_factor_times_texel_times_colour_times_one_less_metallic")
    else {
        return;
    };
    let factor = Vec4::new(0.9, 0.8, 1.0, 1.0);
    let color = Vec4::new(1.0, 1.0, 0.5, 1.0);
    let metallic = 0.25;
    let camera = from_above(2.0);
    for filter in [Filter::Linear, Filter::Nearest] {
        let mut worst = 0.0f32;
        let material = Material {
            metallic,
            ..textured(factor, AlphaMode::Opaque)
        };
        let s = scene(
            vec![quad(1.0, 0.0, 0, color)],
            vec![material],
            vec![texture(TEXELS, filter)],
        );
        let mut instanced = Renderer::new(&ctx, HEADLESS_FORMAT);
        instanced.set_scene(&ctx, &s, [0.8; 3]).unwrap();
        instanced.set_light(&ctx, &white());
        // Through an encoding: the snippet's irradiance is pi everywhere.
        let mut encoded = Renderer::new(&ctx, HEADLESS_FORMAT);
        encoded.set_scene(&ctx, &s, [0.8; 3]).unwrap();
        encoded.set_light(&ctx, &white());
        encoded
            .set_encoding(
                &ctx,
                "fn shlight_irradiance(n: vec3<f32>) -> vec3<f32> {\n    return vec3<f32>(3.14159265);\n}\n",
            )
            .unwrap();
        // PRT on the flattened scene: T_00 L_00 = 1 per unit albedo.
        let flat = s.flatten(Vec3::splat(0.8)).unwrap();
        let mut prt = Renderer::new(&ctx, HEADLESS_FORMAT);
        prt.set_surfaces(&ctx, &flat).unwrap();
        prt.set_light(&ctx, &white());
        let t = vec![(1.0 / (2.0 * PI.sqrt())) as f32; flat.mesh.vertex_count()];
        prt.set_transfer(&ctx, &TransferView::new(0, 1, t.len(), &t).unwrap())
            .unwrap();
        for (renderer, mode) in [
            (&instanced, Mode::Sh),
            (&encoded, Mode::Encoded),
            (&prt, Mode::Prt),
        ] {
            let frame = render_frame(&ctx, renderer, &camera, &shading(mode), SIZE, SIZE).unwrap();
            for j in 0..2 {
                for i in 0..2 {
                    let want = factor.truncate()
                        * linear(TEXELS[2 * j + i])
                        * color.truncate()
                        * (1.0 - metallic);
                    let got = pixel_at(&frame, &camera, texel_centre(i, j, 1.0, 0.0));
                    let what = format!("{filter:?} {mode:?} texel ({i}, {j})");
                    worst = worst.max(assert_rgb(got, want, &what));
                }
            }
        }
        eprintln!(
            "textured quad, {filter:?}: worst channel error {worst:.2e} against the CPU's albedo"
        );
    }
}

/// A `MASK` quad in front of another: where its texels' alpha is below
/// the cutoff the quad behind shows, elsewhere the front texel.
#[test]
fn cut_out_texels_show_the_quad_behind() {
    let Some(ctx) = context("cut_out_texels_show_the_quad_behind") else {
        return;
    };
    // Texels 1 and 2 are cut out (alpha 0.4 and 0 under the cutoff 0.5).
    let texels = [
        [200, 60, 20, 255],
        [30, 180, 90, 102],
        [120, 120, 250, 0],
        [255, 255, 255, 140],
    ];
    let back = Vec3::new(0.2, 0.4, 0.6);
    let s = scene(
        vec![quad(1.0, 0.5, 0, Vec4::ONE), quad(3.0, 0.0, 1, Vec4::ONE)],
        vec![
            textured(Vec4::ONE, AlphaMode::Mask { cutoff: 0.5 }),
            Material {
                base_color: back.extend(1.0),
                ..Material::default()
            },
        ],
        vec![texture(texels, Filter::Linear)],
    );
    let mut renderer = Renderer::new(&ctx, HEADLESS_FORMAT);
    renderer.set_scene(&ctx, &s, [0.8; 3]).unwrap();
    renderer.set_light(&ctx, &white());
    let camera = from_above(2.5);
    let frame = render_frame(&ctx, &renderer, &camera, &shading(Mode::Sh), SIZE, SIZE).unwrap();
    for j in 0..2 {
        for i in 0..2 {
            let t = texels[2 * j + i];
            let want = if f32::from(t[3]) / 255.0 < 0.5 {
                back
            } else {
                linear(t)
            };
            let got = pixel_at(&frame, &camera, texel_centre(i, j, 1.0, 0.5));
            assert_rgb(got, want, &format!("texel ({i}, {j}), alpha {}", t[3]));
        }
    }
}

/// `BLEND` is coverage by an ordered 4x4 dither: over any 8x8 pixels of a
/// quad of alpha 1/4 in front of a black one, exactly a quarter of the
/// pixels show the front quad.
#[test]
fn blend_keeps_the_fraction_alpha_of_the_pixels() {
    let Some(ctx) = context("blend_keeps_the_fraction_alpha_of_the_pixels") else {
        return;
    };
    let s = scene(
        vec![quad(1.0, 0.5, 0, Vec4::ONE), quad(3.0, 0.0, 1, Vec4::ONE)],
        vec![
            Material {
                base_color: Vec4::new(1.0, 1.0, 1.0, 0.25),
                alpha_mode: AlphaMode::Blend,
                ..Material::default()
            },
            Material {
                base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
                ..Material::default()
            },
        ],
        vec![],
    );
    let mut renderer = Renderer::new(&ctx, HEADLESS_FORMAT);
    renderer.set_scene(&ctx, &s, [0.8; 3]).unwrap();
    renderer.set_light(&ctx, &white());
    let camera = from_above(2.5);
    let frame = render_frame(&ctx, &renderer, &camera, &shading(Mode::Sh), SIZE, SIZE).unwrap();
    let centre = SIZE / 2;
    for (x0, y0) in [(centre - 4, centre - 4), (centre + 7, centre - 13)] {
        let mut front = 0;
        for y in y0..y0 + 8 {
            for x in x0..x0 + 8 {
                let p = frame.pixels[y * SIZE + x];
                assert_eq!(p[3], 1.0);
                if p[0] > 0.5 {
                    front += 1;
                    assert!((p[0] - 1.0).abs() < TOL, "{p:?}");
                } else {
                    assert_eq!(p[0], 0.0);
                }
            }
        }
        assert_eq!(
            front, 16,
            "pixels of the front quad among 64 at ({x0}, {y0})"
        );
    }
}

/// Three instances of one quad (one mirrored, one turned and scaled) give
/// the frame of the scene flattened into three copies, pixel for pixel,
/// with a third of the flattened copies' vertices on the GPU: the one
/// quad's four against twelve.
#[test]
fn instances_draw_as_the_flattened_copies() {
    let Some(ctx) = context("instances_draw_as_the_flattened_copies") else {
        return;
    };
    let mut s = scene(
        vec![quad(1.0, 0.0, 0, Vec4::new(1.0, 0.9, 0.8, 1.0))],
        vec![textured(Vec4::ONE, AlphaMode::Opaque)],
        vec![texture(TEXELS, Filter::Linear)],
    );
    // Exact entries: the CPU's and the GPU's world positions agree to the
    // bit. Mirrored in x; turned a quarter about y and halved.
    let mirrored = Mat4::from_cols(
        Vec4::new(-1.0, 0.0, 0.0, 0.0),
        Vec4::Y,
        Vec4::Z,
        Vec4::new(1.5, 0.0, 0.0, 1.0),
    );
    let turned = Mat4::from_cols(
        Vec4::new(0.0, 0.0, -0.5, 0.0),
        Vec4::new(0.0, 0.5, 0.0, 0.0),
        Vec4::new(0.5, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 1.25, 1.0),
    );
    s.instances = [
        Mat4::from_translation(Vec3::new(-1.5, 0.0, 0.0)),
        mirrored,
        turned,
    ]
    .map(|transform| Instance {
        primitive: 0,
        transform,
    })
    .to_vec();
    let flat = s.flatten(Vec3::splat(0.8)).unwrap();
    let mut instanced = Renderer::new(&ctx, HEADLESS_FORMAT);
    instanced.set_scene(&ctx, &s, [0.8; 3]).unwrap();
    let mut flattened = Renderer::new(&ctx, HEADLESS_FORMAT);
    flattened.set_surfaces(&ctx, &flat).unwrap();
    assert_eq!(instanced.vertex_count(), 4);
    assert_eq!(flattened.vertex_count(), 12);
    let light = closed_form::directional(2, DVec3::new(0.3, 1.0, 0.2).normalize(), DVec3::ONE);
    let camera = Camera::looking_at(Vec3::new(0.3, 4.0, 0.5), Vec3::ZERO, 3.0, 0.9);
    let mut frames = Vec::new();
    for r in [&mut instanced, &mut flattened] {
        r.set_light(&ctx, &light);
        frames.push(render_frame(&ctx, r, &camera, &shading(Mode::Sh), SIZE, SIZE).unwrap());
    }
    // All three copies show (the mirrored one too: its front faces wind
    // clockwise).
    for at in [
        Vec3::new(-1.5, 0.0, 0.0),
        Vec3::new(1.5, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.25),
    ] {
        assert_eq!(
            pixel_at(&frames[0], &camera, at)[3],
            1.0,
            "the copy at {at}"
        );
    }
    let mut worst = 0.0f32;
    for (k, (a, b)) in frames[0].pixels.iter().zip(&frames[1].pixels).enumerate() {
        assert_eq!(a[3], b[3], "coverage differs at pixel {k}");
        for c in 0..3 {
            worst = worst.max((a[c] - b[c]).abs());
        }
    }
    assert!(worst <= 1e-6, "instanced and flattened differ by {worst}");
}

/// A metal (metallic 1) reflects no diffuse light: black where the same
/// quad as a dielectric is not.
#[test]
fn a_metal_is_black_in_the_diffuse_pass() {
    let Some(ctx) = context("a_metal_is_black_in_the_diffuse_pass") else {
        return;
    };
    let camera = from_above(2.0);
    let centre = Vec3::new(0.1, 0.0, -0.2);
    let mut seen = Vec::new();
    for metallic in [1.0, 0.0] {
        let s = scene(
            vec![quad(1.0, 0.0, 0, Vec4::ONE)],
            vec![Material {
                metallic,
                ..Material::default()
            }],
            vec![],
        );
        let mut renderer = Renderer::new(&ctx, HEADLESS_FORMAT);
        renderer.set_scene(&ctx, &s, [0.8; 3]).unwrap();
        renderer.set_light(&ctx, &white());
        let frame = render_frame(&ctx, &renderer, &camera, &shading(Mode::Sh), SIZE, SIZE).unwrap();
        seen.push(pixel_at(&frame, &camera, centre));
    }
    assert_eq!(seen[0], [0.0, 0.0, 0.0, 1.0], "metal");
    assert_rgb(seen[1], Vec3::ONE, "dielectric");
}

/// Seen from behind under a light from below, a double-sided quad shows
/// the light on its back (the normal flipped toward the viewer:
/// `E(-y) = 17/16` of the directional light's irradiance at lmax 2, not
/// the `1/16` of its front normal), and a single-sided one is not drawn.
#[test]
fn a_double_sided_quad_is_lit_from_behind_and_a_single_sided_one_is_culled() {
    let Some(ctx) =
        context("a_double_sided_quad_is_lit_from_behind_and_a_single_sided_one_is_culled")
    else {
        return;
    };
    let light = closed_form::directional(2, DVec3::NEG_Y, DVec3::ONE);
    let camera = Camera::looking_at(Vec3::new(0.0, -2.0, 0.0), Vec3::ZERO, 2.0, 0.6);
    let centre = Vec3::new(0.1, 0.0, 0.2);
    let mut seen = Vec::new();
    for double_sided in [true, false] {
        let s = scene(
            vec![quad(1.0, 0.0, 0, Vec4::ONE)],
            vec![Material {
                double_sided,
                ..Material::default()
            }],
            vec![],
        );
        let mut renderer = Renderer::new(&ctx, HEADLESS_FORMAT);
        renderer.set_scene(&ctx, &s, [0.8; 3]).unwrap();
        renderer.set_light(&ctx, &light);
        let frame = render_frame(&ctx, &renderer, &camera, &shading(Mode::Sh), SIZE, SIZE).unwrap();
        seen.push(pixel_at(&frame, &camera, centre));
    }
    let lit = (17.0 / 16.0 / PI) as f32;
    assert_rgb(seen[0], Vec3::splat(lit), "double-sided, from behind");
    assert_eq!(seen[1], [0.0; 4], "single-sided, from behind");
}

/// Under the volume pass, probes of constant radiance 1 give irradiance pi
/// everywhere: each texel's centre shows its linear albedo, as in SH mode.
#[test]
fn the_volume_pass_lights_the_texels() {
    let Some(ctx) = context("the_volume_pass_lights_the_texels") else {
        return;
    };
    let s = scene(
        vec![quad(1.0, 0.0, 0, Vec4::ONE)],
        vec![textured(Vec4::ONE, AlphaMode::Opaque)],
        vec![texture(TEXELS, Filter::Linear)],
    );
    let valid = [true; 8];
    let radiance: Vec<f32> = vec![(2.0 * PI.sqrt()) as f32; 8 * 3];
    let probes = VolumeView {
        grid: ProbeGrid {
            resolution: [2, 2, 2],
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        },
        lmax: 0,
        valid: &valid,
        radiance: &radiance,
        offsets: None,
        visibility: None,
    };
    let mut volume = VolumeRenderer::new(&ctx, HEADLESS_FORMAT, &probes).unwrap();
    volume.set_scene_surfaces(&ctx, &s, [0.8; 3]).unwrap();
    let clear = Renderer::new(&ctx, HEADLESS_FORMAT);
    let camera = from_above(2.0);
    let shading = shading(Mode::Sh);
    let target = Offscreen::new(&ctx, SIZE, SIZE).unwrap();
    let frame = target
        .render_with(&ctx, true, |encoder, color, depth| {
            clear.draw(&ctx, encoder, color, depth, &camera, 1.0, &shading)?;
            volume.draw(&ctx, encoder, color, depth, &camera, 1.0, &shading, false);
            Ok(())
        })
        .unwrap()
        .unwrap();
    for j in 0..2 {
        for i in 0..2 {
            let got = pixel_at(&frame, &camera, texel_centre(i, j, 1.0, 0.0));
            assert_rgb(got, linear(TEXELS[2 * j + i]), &format!("texel ({i}, {j})"));
        }
    }
}

/// The scene `render-mesh` draws (shlight-gpu's `Scene`, as `Scene::read`
/// makes it for a glTF file) of the textured quad under the white
/// environment, in SH mode and, with a diffuse transfer baked at albedo
/// 0.5 whose exit radiance is 0.5, in PRT mode: both show each texel's
/// linear albedo at its centre (PRT: the transfer taken per unit albedo,
/// the flattened scene drawn).
#[test]
fn render_mesh_draws_a_gltf_scene_with_its_textures_in_sh_and_prt_modes() {
    if context("render_mesh_draws_a_gltf_scene_with_its_textures_in_sh_and_prt_modes").is_none() {
        return;
    }
    let s = scene(
        vec![quad(1.0, 0.0, 0, Vec4::ONE)],
        vec![textured(Vec4::ONE, AlphaMode::Opaque)],
        vec![texture(TEXELS, Filter::Linear)],
    );
    let gltf = GltfScene::new(s, [0.8; 3]).unwrap();
    let n = gltf.mesh().vertex_count();
    let transfer = shlight_format::ShprtFile {
        lmax: 0,
        channels: 1,
        vertex_count: n,
        transfer: vec![(0.5 / (2.0 * PI.sqrt())) as f32; n],
        mode: "unshadowed".into(),
        rays_per_vertex: 1,
        bounces: 0,
        seed: 0,
        albedo: Some([0.5; 3]),
        mesh_hash: gltf.mesh().content_hash(),
        mesh: "hand-made.glb".into(),
        glossy: None,
        static_light: None,
    };
    let eye = Vec3::new(0.0, 2.0, 0.0);
    let shot = Shot {
        camera: Some(eye),
        target: Some(Vec3::ZERO),
        fov_degrees: 0.6f32.to_degrees(),
        size: (SIZE, SIZE),
        window: shlight_core::sh::Window::None,
    };
    let camera =
        Camera::aimed(gltf.mesh().bounds(), Some(eye), Some(Vec3::ZERO), 0.6, 1.0).unwrap();
    for (mode, transfer) in [(Mode::Sh, None), (Mode::Prt, Some(transfer))] {
        let scene = GpuScene {
            mesh: gltf.mesh().clone(),
            gltf: Some(gltf.clone()),
            mesh_name: "hand-made.glb".into(),
            transfer,
            light: shlight_pipeline::Environment {
                path: "white.json".into(),
                radiance: white(),
                map: None,
                orientation: Default::default(),
                warnings: Vec::new(),
            },
            rotation: glam::DMat3::IDENTITY,
            mode,
            encoding: shlight_core::encoding::Encoding::Sh,
            lmax: 2,
            albedo: None,
            background: Background::None,
            volume: None,
            spelling: shlight_pipeline::Spelling::CommandLine,
            lightmap: None,
        };
        let frame = scene
            .render_headless(&shot, &shlight_pipeline::Silent)
            .unwrap();
        for j in 0..2 {
            for i in 0..2 {
                let got = pixel_at(&frame, &camera, texel_centre(i, j, 1.0, 0.0));
                let what = format!("{mode:?} texel ({i}, {j})");
                assert_rgb(got, linear(TEXELS[2 * j + i]), &what);
            }
        }
    }
}

/// A 64x64 checker of black and white texels seen from afar (about four
/// texels to a pixel) is grey, not aliased: its mip levels average the
/// light, sRGB 188 (linear 0.5029; averaging the stored values would give
/// sRGB 128, linear 0.216), where the top level alone shows black or white
/// pixels.
#[test]
fn a_minified_checker_is_its_mean_light() {
    let Some(ctx) = context("a_minified_checker_is_its_mean_light") else {
        return;
    };
    let texels: Vec<[u8; 4]> = (0..64 * 64)
        .map(|k| {
            let v = if (k % 64 + k / 64) % 2 == 0 { 255 } else { 0 };
            [v, v, v, 255]
        })
        .collect();
    let checker = Texture {
        width: 64,
        height: 64,
        texels,
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Linear,
    };
    let s = scene(
        vec![quad(1.0, 0.0, 0, Vec4::ONE)],
        vec![textured(Vec4::ONE, AlphaMode::Opaque)],
        vec![checker],
    );
    let mut renderer = Renderer::new(&ctx, HEADLESS_FORMAT);
    renderer.set_scene(&ctx, &s, [0.8; 3]).unwrap();
    renderer.set_light(&ctx, &white());
    // 64 pixels across show about 1 / (2 x 6.5 tan 0.3) = 0.25 of the
    // view per unit: the quad covers some 16 pixels, four texels each.
    let camera = from_above(6.5);
    let size = 64;
    let frame = render_frame(&ctx, &renderer, &camera, &shading(Mode::Sh), size, size).unwrap();
    let grey = shlight_io::srgb_to_linear(188.0 / 255.0);
    let mut worst = 0.0f32;
    for y in size / 2 - 4..size / 2 + 4 {
        for x in size / 2 - 4..size / 2 + 4 {
            let p = frame.pixels[y * size + x];
            assert_rgb(p, Vec3::splat(grey), &format!("pixel ({x}, {y})"));
            worst = worst.max((p[0] - grey).abs());
        }
    }
    eprintln!("minified checker: worst pixel {worst:.2e} from the mean light {grey:.4}");
}

/// Standard base64 of `bytes` (for a glTF buffer's data URI).
fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = u32::from(b[0]) << 16 | u32::from(b[1]) << 8 | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// `render-mesh` on a `.gltf` file reads it as a scene (shlight-mesh's
/// `load_scene`) and draws each primitive with its material: a quad of
/// `baseColorFactor` (0.2, 0.5, 0.9) shows that colour under the white
/// light (a mesh would show `--albedo`'s 0.8 grey), the same quad as a
/// metal shows black, and a third node placing the coloured quad again
/// shows it too.
#[test]
fn render_mesh_reads_a_gltf_file_as_a_scene_with_its_materials() {
    if context("render_mesh_reads_a_gltf_file_as_a_scene_with_its_materials").is_none() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("shlight-gpu-surfaces-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // One quad facing +y: positions, normals, then two triangles.
    let mut buffer = Vec::new();
    for p in [
        [-0.5f32, 0.0, -0.5],
        [0.5, 0.0, -0.5],
        [0.5, 0.0, 0.5],
        [-0.5, 0.0, 0.5],
    ] {
        p.iter().for_each(|x| buffer.extend(x.to_le_bytes()));
    }
    for _ in 0..4 {
        [0.0f32, 1.0, 0.0]
            .iter()
            .for_each(|x| buffer.extend(x.to_le_bytes()));
    }
    for i in [0u16, 2, 1, 0, 3, 2] {
        buffer.extend(i.to_le_bytes());
    }
    let gltf = format!(
        r#"{{"asset": {{"version": "2.0"}},
  "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{data}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 96}},
                  {{"buffer": 0, "byteOffset": 96, "byteLength": 12}}],
  "accessors": [
    {{"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC3",
      "min": [-0.5, 0, -0.5], "max": [0.5, 0, 0.5]}},
    {{"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3"}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
  "materials": [
    {{"pbrMetallicRoughness": {{"baseColorFactor": [0.2, 0.5, 0.9, 1], "metallicFactor": 0}}}},
    {{"pbrMetallicRoughness": {{"metallicFactor": 1}}}}],
  "meshes": [
    {{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2, "material": 0}}]}},
    {{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2, "material": 1}}]}}],
  "nodes": [{{"mesh": 0, "translation": [-0.75, 0, 0]}}, {{"mesh": 1, "translation": [0.75, 0, 0]}},
            {{"mesh": 0, "translation": [0, 0, 1.25]}}],
  "scenes": [{{"nodes": [0, 1, 2]}}], "scene": 0}}"#,
        len = buffer.len(),
        data = base64(&buffer),
    );
    let path = dir.join("quads.gltf");
    std::fs::write(&path, gltf).unwrap();
    let light = dir.join("white.json");
    let file = shlight_format::CoeffFile::new(
        white(),
        shlight_core::sh::Frame::YUp,
        shlight_format::Quantity::Radiance,
    );
    std::fs::write(&light, file.to_json_string()).unwrap();
    let options = shlight_gpu::SceneOptions {
        mesh: Some(path),
        env: Some(light),
        ..shlight_gpu::SceneOptions::default()
    };
    let settings = options
        .check(shlight_pipeline::Spelling::CommandLine)
        .unwrap();
    let built_in = shlight_gpu::BuiltIn {
        mesh_name: "none.obj",
        mesh_obj: b"",
        map_name: "none.exr",
        map: b"",
    };
    let scene = GpuScene::read(&settings, &built_in, &shlight_pipeline::Silent).unwrap();
    assert!(scene.gltf.is_some(), "a .gltf file is read as a scene");
    let eye = Vec3::new(0.0, 4.0, 0.4);
    let shot = Shot {
        camera: Some(eye),
        target: Some(Vec3::new(0.0, 0.0, 0.4)),
        fov_degrees: 0.6f32.to_degrees(),
        size: (SIZE, SIZE),
        window: shlight_core::sh::Window::None,
    };
    let camera = Camera::aimed(scene.mesh.bounds(), shot.camera, shot.target, 0.6, 1.0).unwrap();
    let frame = scene
        .render_headless(&shot, &shlight_pipeline::Silent)
        .unwrap();
    let coloured = Vec3::new(0.2, 0.5, 0.9);
    assert_rgb(
        pixel_at(&frame, &camera, Vec3::new(-0.75, 0.0, 0.1)),
        coloured,
        "node 0",
    );
    assert_rgb(
        pixel_at(&frame, &camera, Vec3::new(0.75, 0.0, 0.1)),
        Vec3::ZERO,
        "the metal",
    );
    assert_rgb(
        pixel_at(&frame, &camera, Vec3::new(0.1, 0.0, 1.25)),
        coloured,
        "node 2",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

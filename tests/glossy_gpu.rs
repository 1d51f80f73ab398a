//! Glossy PRT on the GPU (`render-mesh --prt` and `view --prt` with a
//! glossy file) against `shlight sample --eye`, the CPU's evaluation of
//! the same material: each vertex drawn as one point of a float frame and
//! read where it lands. Without a GPU adapter each test prints a SKIPPED
//! line and passes, unless `SHLIGHT_REQUIRE_GPU=1` or
//! `SHLIGHT_REQUIRE_ALL=1`.

use std::path::{Path, PathBuf};

use glam::{DMat3, DVec3, Vec3, Vec4};
use shlight_core::sh::{Frame as Up, ShCoeffs, ShRotation, closed_form};
use shlight_format::ShprtFile;
use shlight_gpu::{Camera, GpuContext, HEADLESS_FORMAT, Mode, Renderer, Shading, render_frame};
use shlight_mesh::Mesh;
use shlight_pipeline::Environment;

use crate::util::{gpu_context, read_json, s, shlight_err, shlight_ok, temp_dir};

/// Frame size of the point renders.
const W: usize = 400;
const H: usize = 300;

/// The bundled teapot: 792 vertices, concave enough for shadows.
fn teapot() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/teapot.obj")
}

/// A light with every band to 8: a bright coloured cap and a constant.
fn write_light(path: &Path) {
    let mut l: ShCoeffs<DVec3> =
        closed_form::cap(8, DVec3::new(0.3, 0.8, 0.5), 0.4, DVec3::new(6.0, 3.0, 2.0));
    l += &closed_form::constant(8, DVec3::new(0.5, 0.6, 0.8));
    let rows: Vec<[f64; 3]> = l.as_slice().iter().map(|v| v.to_array()).collect();
    crate::util::write_radiance_rows(path, &rows);
}

/// Bakes `shlight prt teapot --mode glossy` with `extra` into `dir/name`
/// (`--brdf phong:20` unless `extra` names one).
fn bake(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mesh = teapot();
    let mut args = vec![
        "prt",
        s(&mesh),
        "--mode",
        "glossy",
        "--samples",
        "128",
        "-o",
        s(&out),
    ];
    if !extra.contains(&"--brdf") {
        args.extend(["--brdf", "phong:20"]);
    }
    args.extend(extra);
    shlight_ok(&args);
    out
}

/// `shlight sample FILE --light LIGHT --eye EYE [--albedo A]`: each
/// vertex's `[r, g, b]`.
fn sample(file: &Path, light: &Path, eye: Vec3, albedo: Option<&str>) -> Vec<[f64; 3]> {
    let json = file.with_extension("json");
    let eye = format!("{},{},{}", eye.x, eye.y, eye.z);
    let mut args = vec![
        "sample",
        s(file),
        "--light",
        s(light),
        "--eye",
        &eye,
        "-o",
        s(&json),
    ];
    if let Some(a) = albedo {
        args.extend(["--albedo", a]);
    }
    shlight_ok(&args);
    read_json(&json)["radiance"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| [0, 1, 2].map(|k| c[k].as_f64().unwrap()))
        .collect()
}

/// The renderer `render-mesh --prt FILE --env LIGHT` builds, drawing the
/// mesh's vertices as points.
fn point_renderer(ctx: &GpuContext, mesh: &Mesh, file: &Path, light: &Path) -> Renderer {
    let transfer = ShprtFile::read(file).unwrap();
    let env = Environment::load(light, Up::YUp, shlight_baked::LIGHT_MAX_LMAX).unwrap();
    let mut renderer =
        shlight_gpu::mesh_renderer(ctx, HEADLESS_FORMAT, mesh, Some(&transfer), &env).unwrap();
    renderer.set_points(true);
    renderer
}

/// Each vertex's value read off a point render from `eye`, where it lands
/// alone in its pixel and well inside it (`None` elsewhere: off screen,
/// within a tenth of a pixel of an edge, or sharing its pixel).
fn vertex_values(
    ctx: &GpuContext,
    renderer: &Renderer,
    mesh: &Mesh,
    eye: Vec3,
    shading: &Shading,
) -> Vec<Option<[f32; 3]>> {
    let aspect = W as f32 / H as f32;
    let camera = Camera::aimed(mesh.bounds(), Some(eye), None, 35f32.to_radians(), aspect)
        .expect("eye off the target");
    let frame = render_frame(ctx, renderer, &camera, shading, W, H).unwrap();
    let vp = camera.view_proj(aspect);
    let pixel = |p: Vec3| -> Option<usize> {
        let c = vp * Vec4::new(p.x, p.y, p.z, 1.0);
        let ndc = c.truncate() / c.w;
        let (x, y) = (
            (ndc.x + 1.0) * 0.5 * W as f32,
            (1.0 - ndc.y) * 0.5 * H as f32,
        );
        let inside = |t: f32| (t - t.floor() - 0.5).abs() < 0.4;
        (c.w > 0.0
            && (0.0..1.0).contains(&ndc.z)
            && x >= 0.0
            && y >= 0.0
            && x < W as f32
            && y < H as f32
            && inside(x)
            && inside(y))
        .then(|| y as usize * W + x as usize)
    };
    let pixels: Vec<Option<usize>> = mesh.positions.iter().map(|p| pixel(*p)).collect();
    let mut count = vec![0u32; W * H];
    for p in mesh.positions.iter() {
        // Any vertex that lands in a pixel, near an edge or not.
        let c = vp * Vec4::new(p.x, p.y, p.z, 1.0);
        let ndc = c.truncate() / c.w;
        let (x, y) = (
            (ndc.x + 1.0) * 0.5 * W as f32,
            (1.0 - ndc.y) * 0.5 * H as f32,
        );
        if x >= 0.0 && y >= 0.0 && x < W as f32 && y < H as f32 {
            count[y as usize * W + x as usize] += 1;
        }
    }
    pixels
        .iter()
        .map(|p| {
            p.filter(|&i| count[i] == 1).map(|i| {
                let v = frame.pixels[i];
                assert_eq!(v[3], 1.0, "a point was drawn at pixel {i}");
                [v[0], v[1], v[2]]
            })
        })
        .collect()
}

/// GPU shading equals `shlight sample --eye` at the vertices: lmax 2 and
/// 4, plain and CPCA-compressed, grey and coloured (bounces) matrices, with
/// and without a diffuse base, Phong (evaluated by the shader) and GGX
/// (its direction table), every vertex the frame shows alone within
/// 1e-5 of the largest value (f32 on the GPU, f64 in `sample`); then the
/// environment turned (the renderer's new light against `sample` under a
/// file of the turned coefficients).
#[test]
fn gpu_glossy_shading_equals_sample_at_the_vertices() {
    let test = "gpu_glossy_shading_equals_sample_at_the_vertices";
    let Some(ctx) = gpu_context(test) else {
        return;
    };
    let dir = temp_dir("glossy_gpu_sample");
    let light = dir.join("light.json");
    write_light(&light);
    let mesh = shlight_mesh::load(&teapot()).unwrap();
    let eye = Vec3::new(20.0, 16.0, 44.0);
    for (name, extra, albedo) in [
        ("l2.shprt", vec!["--lmax", "2"], None),
        ("l4.shprt", vec!["--lmax", "4"], Some("0.25,0.5,0.75")),
        (
            "l2c.shprt",
            vec!["--lmax", "2", "--compress", "cpca:6,2"],
            Some("0.5"),
        ),
        (
            "l4c.shprt",
            vec![
                "--lmax",
                "4",
                "--compress",
                "cpca:8,3",
                "--bounces",
                "1",
                "--albedo",
                "0.9,0.5,0.2",
            ],
            None,
        ),
        (
            "l4g.shprt",
            vec!["--lmax", "4", "--brdf", "ggx:0.3,0.04"],
            Some("0.5,0.4,0.3"),
        ),
        (
            "l2gc.shprt",
            vec!["--lmax", "2", "--brdf", "ggx:0.2", "--compress", "cpca:6,2"],
            None,
        ),
    ] {
        let file = bake(&dir, name, &extra);
        let want = sample(&file, &light, eye, albedo);
        let mut renderer = point_renderer(&ctx, &mesh, &file, &light);
        let base = albedo.map_or([0.0; 3], |a| {
            let v: Vec<f32> = a.split(',').map(|x| x.parse().unwrap()).collect();
            if v.len() == 1 {
                [v[0]; 3]
            } else {
                [v[0], v[1], v[2]]
            }
        });
        let shading = Shading {
            mode: Mode::Prt,
            lmax: ShprtFile::read(&file).unwrap().lmax,
            albedo: base,
            ..Shading::default()
        };
        let got = vertex_values(&ctx, &renderer, &mesh, eye, &shading);
        compare(name, &got, &want);
        // The environment turned: the renderer recomputes the transferred
        // radiance for the new light.
        let env = Environment::load(&light, Up::YUp, shlight_baked::LIGHT_MAX_LMAX).unwrap();
        let turned = ShRotation::from_mat3(8, DMat3::from_rotation_y(1.2)).apply(&env.radiance);
        let turned_path = dir.join(format!("turned-{name}.json"));
        let rows: Vec<[f64; 3]> = turned.as_slice().iter().map(|v| v.to_array()).collect();
        crate::util::write_radiance_rows(&turned_path, &rows);
        let want_turned = sample(&file, &turned_path, eye, albedo);
        let change = want
            .iter()
            .zip(&want_turned)
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
            .fold(0.0f64, f64::max);
        assert!(
            change > 0.1,
            "{name}: turning the light changed little ({change})"
        );
        renderer.set_light(&ctx, &turned);
        let got = vertex_values(&ctx, &renderer, &mesh, eye, &shading);
        compare(&format!("{name} turned"), &got, &want_turned);
    }
}

/// Each vertex the frame shows alone against `sample`'s value, within
/// 1e-5 of the largest value; more than 150 of them.
fn compare(name: &str, got: &[Option<[f32; 3]>], want: &[[f64; 3]]) {
    let largest = want
        .iter()
        .flatten()
        .map(|x| x.abs())
        .fold(0.0f64, f64::max);
    assert!(largest > 0.1, "{name}: the light shows ({largest})");
    let (mut compared, mut worst) = (0, 0.0f64);
    for (v, (g, w)) in got.iter().zip(want).enumerate() {
        let Some(g) = g else { continue };
        compared += 1;
        for c in 0..3 {
            let d = (f64::from(g[c]) - w[c]).abs() / largest;
            worst = worst.max(d);
            assert!(
                d <= 1e-5,
                "{name}: vertex {v} channel {c}: GPU {} vs sample {} (largest {largest})",
                g[c],
                w[c]
            );
        }
    }
    eprintln!("{name}: {compared} vertices, worst {worst:.2e} of the largest {largest:.3}");
    assert!(compared > 150, "{name}: only {compared} vertices compared");
}

/// A glossy file's vertices (Phong and GGX) change when the eye moves; a diffuse file's
/// do not (but for f32 rounding), each vertex read where it lands from
/// both eyes.
#[test]
fn glossy_vertices_change_with_the_eye_and_diffuse_ones_do_not() {
    let test = "glossy_vertices_change_with_the_eye_and_diffuse_ones_do_not";
    let Some(ctx) = gpu_context(test) else {
        return;
    };
    let dir = temp_dir("glossy_gpu_eye");
    let light = dir.join("light.json");
    write_light(&light);
    let mesh = shlight_mesh::load(&teapot()).unwrap();
    let glossy = bake(&dir, "glossy.shprt", &["--lmax", "4"]);
    let ggx = bake(&dir, "ggx.shprt", &["--lmax", "4", "--brdf", "ggx:0.25"]);
    let diffuse = dir.join("diffuse.shprt");
    let path = teapot();
    shlight_ok(&[
        "prt",
        s(&path),
        "--lmax",
        "4",
        "--samples",
        "128",
        "-o",
        s(&diffuse),
    ]);
    let shading = Shading {
        mode: Mode::Prt,
        lmax: 4,
        ..Shading::default()
    };
    let (a, b) = (Vec3::new(20.0, 16.0, 44.0), Vec3::new(-30.0, 20.0, 36.0));
    let mut moved = Vec::new();
    for file in [&glossy, &ggx, &diffuse] {
        let renderer = point_renderer(&ctx, &mesh, file, &light);
        let from_a = vertex_values(&ctx, &renderer, &mesh, a, &shading);
        let from_b = vertex_values(&ctx, &renderer, &mesh, b, &shading);
        let (mut both, mut largest, mut change) = (0, 0.0f32, 0.0f32);
        for (x, y) in from_a.iter().zip(&from_b) {
            if let (Some(x), Some(y)) = (x, y) {
                both += 1;
                for c in 0..3 {
                    largest = largest.max(x[c].abs());
                    change = change.max((x[c] - y[c]).abs());
                }
            }
        }
        assert!(
            both > 100,
            "{}: {both} vertices seen from both",
            file.display()
        );
        moved.push(change / largest);
    }
    for (name, m) in [("phong", moved[0]), ("ggx", moved[1])] {
        assert!(m > 0.05, "{name}: largest change {m} of the largest value");
    }
    // Only the rasteriser's rounding of a point's attribute (measured about
    // 1e-7 on lavapipe).
    assert!(
        moved[2] < 1e-6,
        "diffuse: the eye changed a vertex by {}",
        moved[2]
    );
}

/// What the GPU still cannot shade is refused, naming the file: a glossy
/// file above lmax 8 (the GPU's basis), and `--albedo` for a diffuse file
/// in `sample` (its albedo is in the transfer).
#[test]
fn glossy_files_the_gpu_cannot_shade_are_refused() {
    let dir = temp_dir("glossy_gpu_refused");
    let light = dir.join("light.json");
    write_light(&light);
    let obj = dir.join("ball.obj");
    crate::util::write_obj(&obj, &shlight_mesh::generate::uv_sphere(1.0, 6, 3));
    let deep = dir.join("deep.shprt");
    shlight_ok(&[
        "prt",
        s(&obj),
        "--mode",
        "glossy",
        "--brdf",
        "phong:4",
        "--lmax",
        "9",
        "--samples",
        "64",
        "-o",
        s(&deep),
    ]);
    let png = dir.join("x.png");
    if gpu_context("glossy_files_the_gpu_cannot_shade_are_refused").is_some() {
        let err = shlight_err(&[
            "render-mesh",
            s(&obj),
            "--prt",
            s(&deep),
            "--env",
            s(&light),
            "--size",
            "16x16",
            "-o",
            s(&png),
        ]);
        assert!(
            err.contains("glossy transfer of lmax 9: the GPU shades to lmax 8"),
            "{err}"
        );
        assert!(!png.exists());
    }
    let diffuse = dir.join("diffuse.shprt");
    shlight_ok(&["prt", s(&obj), "--samples", "64", "-o", s(&diffuse)]);
    let json = dir.join("x.json");
    let err = shlight_err(&[
        "sample",
        s(&diffuse),
        "--light",
        s(&light),
        "--albedo",
        "0.5",
        "-o",
        s(&json),
    ]);
    assert!(
        err.contains(
            "diffuse.shprt: --albedo is the diffuse base under a glossy file's glossy layer"
        ),
        "{err}"
    );
}

//! The GPU commands end to end: `render-mesh` against the CPU evaluation of
//! SH irradiance at each pixel's normal, `project --gpu` against the CPU
//! quadrature, `view --screenshot` under Xvfb, and their error messages.
//! Without a GPU adapter (or Xvfb, for the viewer) the tests that need one
//! print a SKIPPED line and pass, unless `SHLIGHT_REQUIRE_GPU=1` or
//! `SHLIGHT_REQUIRE_ALL=1`.

use std::path::Path;
use std::process::{Child, Command, Stdio};

use glam::DVec3;
use shlight_core::sh::{ShCoeffs, closed_form, irradiance};
use shlight_io::{ReadOptions, read_image};

use crate::util::{
    coefficients, gpu_context, json, s, shlight, shlight_err, shlight_ok, skip_gpu, temp_dir,
    write_map, write_obj, write_radiance_rows,
};

/// Whether GPU tests can run; [`skip_gpu`] (SKIPPED line, or a failure
/// under `SHLIGHT_REQUIRE_GPU=1` / `SHLIGHT_REQUIRE_ALL=1`) when not.
fn have_gpu(test: &str) -> bool {
    gpu_context(test).is_some()
}

/// Writes radiance coefficients as a coefficient file (y-up).
fn write_coeffs(path: &Path, c: &ShCoeffs<DVec3>) {
    let rows: Vec<[f64; 3]> = c.as_slice().iter().map(|v| v.to_array()).collect();
    write_radiance_rows(path, &rows);
}

/// A light positive everywhere with bands 0..4 present.
fn light() -> ShCoeffs<DVec3> {
    let mut l = closed_form::cap(4, DVec3::new(0.3, 0.8, 0.5), 0.5, DVec3::new(5.0, 3.0, 2.0));
    l += &closed_form::constant(4, DVec3::new(1.0, 1.1, 1.3));
    l
}

/// The bound for per-pixel shading against the CPU; f32 shading of
/// 25 terms measures a few 1e-6 (printed by the test).
const SHADING_TOL: f64 = 1e-3;

#[test]
fn render_mesh_shades_each_pixel_as_the_cpu_irradiance_at_its_normal() {
    if !have_gpu("render_mesh_shades_each_pixel_as_the_cpu_irradiance_at_its_normal") {
        return;
    }
    let dir = temp_dir("gpu_render_mesh");
    let (mesh, env) = (dir.join("sphere.obj"), dir.join("light.json"));
    write_obj(&mesh, &shlight_mesh::generate::uv_sphere(2.0, 48, 24));
    let light = light();
    write_coeffs(&env, &light);
    let (normals, shaded) = (dir.join("n.exr"), dir.join("sh.exr"));
    let common = ["--size", "80x60", "--lmax", "4", "--albedo", "0.5,0.75,1"];
    let mut args = vec![
        "render-mesh",
        s(&mesh),
        "--env",
        s(&env),
        "--mode",
        "normals",
        "-o",
        s(&normals),
    ];
    args.extend(common);
    shlight_ok(&args);
    let mut args = vec!["render-mesh", s(&mesh), "--env", s(&env), "-o", s(&shaded)];
    args.extend(common);
    shlight_ok(&args);
    let n = read_image(&normals, &ReadOptions::default()).unwrap();
    let c = read_image(&shaded, &ReadOptions::default()).unwrap();
    assert_eq!((n.width(), n.height()), (80, 60));
    let e = irradiance(&light);
    let albedo = [0.5, 0.75, 1.0];
    let (mut covered, mut worst) = (0, 0.0f64);
    for (normal, colour) in n.pixels().iter().zip(c.pixels()) {
        let d = DVec3::from_array(normal.map(f64::from));
        if d.length() == 0.0 {
            assert_eq!(*colour, [0.0; 3], "no mesh, no background: 0");
            continue;
        }
        assert!((d.length() - 1.0).abs() < 1e-5, "unit normals: {d}");
        covered += 1;
        let want = e.eval(d);
        for k in 0..3 {
            let want = albedo[k] / std::f64::consts::PI * want[k];
            let err = (f64::from(colour[k]) - want).abs() / want;
            assert!(err <= SHADING_TOL, "{colour:?} vs {want} at {d}");
            worst = worst.max(err);
        }
    }
    assert!(
        covered > 80 * 60 / 8,
        "the sphere is framed ({covered} pixels)"
    );
    eprintln!("render-mesh vs CPU irradiance over {covered} pixels: worst {worst:.2e}");
}

/// Every encoding shaded by `render-mesh --encoding` against the core's
/// evaluation of the same encoding ([`shlight_core::encoding::Encoded::irradiance`])
/// at each pixel's normal, under the light as it is and turned by a
/// rotation `R` (the shader evaluates the unturned encoding at `R^T n`).
/// Errors are relative to the frame's largest value; lavapipe measures
/// about 1e-6 (printed).
#[test]
fn render_mesh_shades_every_encoding_as_the_cpu_evaluates_it() {
    let test = "render_mesh_shades_every_encoding_as_the_cpu_evaluates_it";
    if !have_gpu(test) {
        return;
    }
    use glam::{DMat3, DQuat};
    use shlight_core::encoding::{DominantLightOptions, Encoding, encode_map};
    use shlight_core::map::{EnvMap, Layout, MapOrientation};

    let dir = temp_dir("gpu_render_encodings");
    let mesh = dir.join("sphere.obj");
    write_obj(&mesh, &shlight_mesh::generate::uv_sphere(1.0, 64, 32));
    // The sun, and a blue lamp below the horizon on the other side: a
    // light far from zonal (ZH3 is exact for zonal ones, so it would be
    // plain SH's twin).
    let sun = read_image(&crate::util::synth_sun_map(&dir), &ReadOptions::default()).unwrap();
    let map_path = dir.join("sun-and-lamp.exr");
    write_map(&map_path, sun.width(), sun.height(), |x, y| {
        let p = sun.get(x, y);
        let lamp = if (80..92).contains(&y) && (150..180).contains(&x) {
            2.0
        } else {
            0.0
        };
        [p[0], p[1], p[2] + lamp]
    });
    let map = read_image(&map_path, &ReadOptions::default()).unwrap();
    let env = EnvMap::new(
        Layout::Equirect,
        MapOrientation::default(),
        map.width(),
        map.height(),
        map.pixels(),
    )
    .unwrap();
    let albedo = [0.5, 0.75, 1.0];
    let common = ["--size", "72x54", "--albedo", "0.5,0.75,1"];
    let render = |name: &str, more: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render-mesh",
            s(&mesh),
            "--env",
            s(&map_path),
            "-o",
            s(&out),
        ];
        args.extend(common);
        args.extend_from_slice(more);
        shlight_ok(&args);
        read_image(&out, &ReadOptions::default()).unwrap()
    };
    let normals = render("n.exr", &["--mode", "normals"]);
    // 60 degrees about +Y: a light from a comes from R a.
    let q = DQuat::from_xyzw(0.0, 0.5, 0.0, 0.75f64.sqrt());
    let turns: [(&str, DMat3); 2] = [
        ("", DMat3::IDENTITY),
        ("quat:0,0.5,0,0.8660254037844386", DMat3::from_quat(q)),
    ];
    let plain = encode_map(&env, Encoding::Sh, 2, &DominantLightOptions::default());
    for encoding in Encoding::ALL.into_iter().filter(|&e| e != Encoding::Sh) {
        let encoded = encode_map(&env, encoding, 2, &DominantLightOptions::default());
        let (mut covered, mut worst, mut apart) = (0, 0.0f64, 0.0f64);
        for (spec, r) in turns {
            let name = format!(
                "{encoding}{}.exr",
                if spec.is_empty() { "" } else { "-turned" }
            );
            let mut more = vec!["--encoding", encoding.name()];
            if !spec.is_empty() {
                more.extend(["--rotate", spec]);
            }
            let shaded = render(&name, &more);
            let mut pixels = Vec::new();
            for (normal, colour) in normals.pixels().iter().zip(shaded.pixels()) {
                let n = DVec3::from_array(normal.map(f64::from));
                if n.length() == 0.0 {
                    assert_eq!(*colour, [0.0; 3], "{encoding}: no mesh, no background: 0");
                    continue;
                }
                let unturned = r.transpose() * n.normalize();
                let e = encoded.irradiance(unturned);
                let want = DVec3::from_array(albedo) / std::f64::consts::PI * e;
                let sh =
                    DVec3::from_array(albedo) / std::f64::consts::PI * plain.irradiance(unturned);
                pixels.push((DVec3::from_array(colour.map(f64::from)), want, sh));
            }
            let top = pixels.iter().map(|p| p.1.max_element()).fold(0.0, f64::max);
            assert!(top > 0.0, "{encoding}: lit");
            for (got, want, sh) in &pixels {
                let err = (*got - *want).abs().max_element() / top;
                assert!(err < 1e-4, "{encoding} {spec}: {got} vs {want}");
                worst = worst.max(err);
                apart = apart.max((*want - *sh).abs().max_element() / top);
            }
            covered += pixels.len();
        }
        assert!(
            covered > 72 * 54 / 4,
            "{encoding}: the sphere is framed ({covered})"
        );
        // The test can tell the encoding from plain lmax 2 SH.
        assert!(apart > 1e-2, "{encoding} is within {apart:.1e} of plain SH");
        eprintln!(
            "render-mesh --encoding {encoding} vs the CPU over {covered} pixels: worst {worst:.2e} (of max); {apart:.2e} from plain SH"
        );
    }
}

#[test]
fn render_mesh_writes_a_png_with_the_map_behind() {
    if !have_gpu("render_mesh_writes_a_png_with_the_map_behind") {
        return;
    }
    let dir = temp_dir("gpu_render_mesh_png");
    let (mesh, env, out) = (dir.join("s.obj"), dir.join("sky.exr"), dir.join("s.png"));
    write_obj(&mesh, &shlight_mesh::generate::uv_sphere(1.0, 32, 16));
    // Bright upper half, dark lower half.
    write_map(&env, 64, 32, |_, y| {
        if y < 16 { [2.0, 2.0, 2.5] } else { [0.05; 3] }
    });
    shlight_ok(&[
        "render-mesh",
        s(&mesh),
        "--env",
        s(&env),
        "--background",
        "map",
        "--size",
        "64x48",
        "-o",
        s(&out),
        "--camera",
        "0,0,4",
    ]);
    let img = read_image(&out, &ReadOptions::default()).unwrap();
    // Corners: the map (bright sky above, dark ground below); centre: the sphere.
    let top = img.get(0, 0)[2];
    let bottom = img.get(0, 47)[2];
    assert!(top > 0.5 && bottom < 0.2, "sky {top}, ground {bottom}");
    let centre = img.get(32, 24);
    assert!(
        centre != img.get(0, 0) && centre[0] > 0.05,
        "the sphere at the centre: {centre:?}"
    );
}

#[test]
fn project_gpu_matches_the_cpu_quadrature() {
    if !have_gpu("project_gpu_matches_the_cpu_quadrature") {
        return;
    }
    let dir = temp_dir("gpu_project");
    let map = dir.join("map.exr");
    write_map(&map, 256, 128, |x, y| {
        let spot = if (100..110).contains(&x) && (30..36).contains(&y) {
            30.0
        } else {
            0.0
        };
        [
            1.0 + spot + x as f32 / 256.0,
            0.5 + y as f32 / 128.0,
            0.25 + spot * 0.5,
        ]
    });
    for up in ["y", "z"] {
        let cpu = coefficients(&json(&shlight(&[
            "project",
            s(&map),
            "--lmax",
            "8",
            "--up",
            up,
            "--format",
            "json",
        ])));
        let gpu = coefficients(&json(&shlight(&[
            "project",
            s(&map),
            "--lmax",
            "8",
            "--up",
            up,
            "--gpu",
            "--format",
            "json",
        ])));
        let largest = cpu.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for (g, c) in gpu.iter().zip(&cpu) {
            for k in 0..3 {
                let scale = c[k].abs().max(1e-2 * largest);
                assert!(
                    (g[k] - c[k]).abs() <= 1e-4 * scale,
                    "up {up}: {g:?} vs {c:?}"
                );
            }
        }
    }
}

#[test]
fn gpu_commands_refuse_bad_input_by_name() {
    let dir = temp_dir("gpu_errors");
    let (mesh, env, out) = (dir.join("s.obj"), dir.join("light.json"), dir.join("o.exr"));
    write_obj(&mesh, &shlight_mesh::generate::uv_sphere(1.0, 8, 4));
    write_coeffs(&env, &light());
    // A mesh that is not one.
    let broken = dir.join("broken.obj");
    std::fs::write(&broken, "v 0 0 0\nf 1 2 3\n").unwrap();
    let missing = dir.join("missing.obj");
    // An environment that is not 2:1, one that is missing, one of irradiance.
    let square = dir.join("square.exr");
    write_map(&square, 16, 16, |_, _| [1.0; 3]);
    let irr = dir.join("irr.json");
    std::fs::write(
        &irr,
        std::fs::read_to_string(&env)
            .unwrap()
            .replace("\"radiance\"", "\"irradiance\""),
    )
    .unwrap();
    let (none, jpg) = (dir.join("none.exr"), dir.join("o.jpg"));
    // Mesh, environment, output, more arguments, what the error names.
    type Case<'a> = (&'a Path, &'a Path, &'a Path, &'a [&'a str], &'a [&'a str]);
    let cases: [Case; 9] = [
        (&broken, &env, &out, &[], &["broken.obj"]),
        (&missing, &env, &out, &[], &["missing.obj"]),
        (
            &mesh,
            &square,
            &out,
            &[],
            &["square.exr", "not an equirect"],
        ),
        (&mesh, &none, &out, &[], &["none.exr"]),
        (&mesh, &irr, &out, &[], &["irr.json", "irradiance"]),
        // Options the GPU path cannot honour.
        (&mesh, &env, &out, &["--lmax", "9"], &["--lmax 9"]),
        (&mesh, &env, &jpg, &[], &["o.jpg"]),
        // Encodings: dominant+sh needs a map; encodings shade irradiance.
        (
            &mesh,
            &env,
            &out,
            &["--encoding", "dominant+sh"],
            &["light.json", "dominant+sh", "sloan+sh"],
        ),
        (
            &mesh,
            &env,
            &out,
            &["--encoding", "zh3", "--mode", "normals"],
            &["--encoding zh3", "--mode normals"],
        ),
    ];
    for (mesh, env, out, more, names) in cases {
        let mut args = vec!["render-mesh", s(mesh), "--env", s(env), "-o", s(out)];
        args.extend_from_slice(more);
        let err = shlight_err(&args);
        assert!(names.iter().all(|n| err.contains(n)), "{err}");
    }
    let map = dir.join("map.exr");
    write_map(&map, 16, 8, |_, _| [1.0; 3]);
    let err = shlight_err(&["project", s(&map), "--gpu", "--lmax", "9"]);
    assert!(err.contains("lmax 8"), "{err}");
    let err = shlight_err(&["project", s(&map), "--gpu", "--method", "montecarlo"]);
    assert!(err.contains("--gpu"), "{err}");
    assert!(!out.exists(), "nothing written on failure");
}

/// An X server for the viewer: our own Xvfb on a free display number,
/// killed (by its process id) when dropped.
pub(crate) struct Xvfb {
    child: Child,
    /// The display to name in `DISPLAY`.
    pub(crate) display: String,
}

impl Xvfb {
    fn start() -> Option<Self> {
        // One start at a time in this process: tests run on threads, and
        // two of them finding the same display free would each clear its
        // lock and socket and start a server there, and the second would
        // break the first's connections.
        static STARTING: std::sync::Mutex<()> = std::sync::Mutex::new(());
        let _one = STARTING
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        for n in 90..110 {
            let socket = format!("/tmp/.X11-unix/X{n}");
            // Taken while its lock names a live process; a lock or socket
            // left by a killed server does not keep a display.
            let lock = std::fs::read_to_string(format!("/tmp/.X{n}-lock")).ok();
            let pid = lock.as_deref().map(str::trim).filter(|p| !p.is_empty());
            if pid.is_some_and(|p| Path::new(&format!("/proc/{p}")).exists()) {
                continue;
            }
            let _ = std::fs::remove_file(format!("/tmp/.X{n}-lock"));
            let _ = std::fs::remove_file(&socket);
            let display = format!(":{n}");
            let Ok(mut child) = Command::new("Xvfb")
                .args([
                    display.as_str(),
                    "-screen",
                    "0",
                    "800x600x24",
                    "-nolisten",
                    "tcp",
                ])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
            else {
                return None;
            };
            for _ in 0..100 {
                if Path::new(&socket).exists() {
                    return Some(Self { child, display });
                }
                if let Ok(Some(_)) = child.try_wait() {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(50));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
        None
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        // Killed, the server leaves its lock and socket behind.
        let n = &self.display[1..];
        let _ = std::fs::remove_file(format!("/tmp/.X{n}-lock"));
        let _ = std::fs::remove_file(format!("/tmp/.X11-unix/X{n}"));
    }
}

/// An adapter and a running Xvfb for a windowed test, or `None` after a
/// SKIPPED line (a failure under the CI switches).
pub(crate) fn gpu_and_xvfb(test: &str) -> Option<Xvfb> {
    if !have_gpu(test) {
        return None;
    }
    let x = Xvfb::start();
    if x.is_none() {
        skip_gpu(test, "Xvfb cannot be started (apt install xvfb)");
    }
    x
}

/// `view ARGS` on `x`'s display (160 x 120, three frames, no panel) with
/// its screenshot, and `render-mesh ARGS` of the same framing, both
/// written in `dir`: the largest difference of a channel between the two
/// pictures, the screenshot's brightest channel, and the screenshot.
pub(crate) fn view_against_render_mesh(
    x: Xvfb,
    args: &[&str],
    dir: &Path,
) -> (f32, f32, shlight_io::Image) {
    let (shot, png) = (dir.join("view.png"), dir.join("render.png"));
    let out = Command::new(env!("CARGO_BIN_EXE_shlight"))
        .arg("view")
        .args(args)
        .args(["--size", "160x120", "--frames", "3", "--hide-panel"])
        .args(["--screenshot", s(&shot)])
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    drop(x);
    assert!(
        out.status.success(),
        "view failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut render = vec!["render-mesh"];
    render.extend(args);
    render.extend(["--size", "160x120", "-o", s(&png)]);
    shlight_ok(&render);
    let (view, render) = (
        read_image(&shot, &ReadOptions::default()).unwrap(),
        read_image(&png, &ReadOptions::default()).unwrap(),
    );
    assert_eq!((view.width(), view.height()), (160, 120));
    let worst = view
        .pixels()
        .iter()
        .zip(render.pixels())
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0f32, f32::max);
    let brightest = view
        .pixels()
        .iter()
        .map(|p| p[0].max(p[1]).max(p[2]))
        .fold(0.0f32, f32::max);
    (worst, brightest, view)
}

#[test]
fn view_screenshot_shows_the_mesh_under_xvfb() {
    let Some(x) = gpu_and_xvfb("view_screenshot_shows_the_mesh_under_xvfb") else {
        return;
    };
    let dir = temp_dir("gpu_view");
    let mesh = dir.join("s.obj");
    write_obj(&mesh, &shlight_mesh::generate::uv_sphere(1.0, 48, 24));
    let env = Path::new(env!("CARGO_MANIFEST_DIR")).join("envmaps/default.exr");
    let screenshot = |name: &str, extra: &[&str]| {
        let shot = dir.join(name);
        let out = Command::new(env!("CARGO_BIN_EXE_shlight"))
            .args([
                "view",
                s(&mesh),
                "--env",
                s(&env),
                "--size",
                "480x320",
                "--frames",
                "3",
            ])
            .args(["--screenshot", s(&shot)])
            .args(extra)
            .env("DISPLAY", &x.display)
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "view failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let img = read_image(&shot, &ReadOptions::default()).unwrap();
        assert_eq!((img.width(), img.height()), (480, 320));
        img
    };
    let bare = screenshot("bare.png", &["--hide-panel"]);
    let with_panel = screenshot("panel.png", &[]);
    // The same frame shaded by the light's ambient cube: the sphere changes
    // (a cube blends six colours; lmax 2 SH carries nine per channel), the
    // background does not.
    let cube = screenshot("cube.png", &["--hide-panel", "--encoding", "ambient-cube"]);
    // A glossy PRT file of the sphere: the viewer starts in PRT mode and
    // shades it toward its camera.
    let glossy_bake = |brdf: &str, out: &Path| {
        shlight_ok(&[
            "prt",
            s(&mesh),
            "--mode",
            "glossy",
            "--brdf",
            brdf,
            "--lmax",
            "2",
            "--samples",
            "64",
            "-o",
            s(out),
        ]);
    };
    let glossy_file = dir.join("s.shprt");
    glossy_bake("phong:8", &glossy_file);
    let glossy = screenshot("glossy.png", &["--hide-panel", "--prt", s(&glossy_file)]);
    // --albedo: a red diffuse base under the glossy layer, and a dark
    // Lambertian sphere in SH mode.
    let glossy_red = screenshot(
        "glossy-red.png",
        &[
            "--hide-panel",
            "--prt",
            s(&glossy_file),
            "--albedo",
            "0.9,0.05,0.05",
        ],
    );
    let dark = screenshot("dark.png", &["--hide-panel", "--albedo", "0.2,0.2,0.2"]);
    // GGX, shaded per vertex on the GPU toward the viewer's camera.
    let ggx_file = dir.join("g.shprt");
    glossy_bake("ggx:0.3", &ggx_file);
    let ggx = screenshot("ggx.png", &["--hide-panel", "--prt", s(&ggx_file)]);
    drop(x);
    let channel_mean = |img: &shlight_io::Image, c: usize| {
        let mut sum = 0.0;
        for y in 140..160 {
            for x in 220..240 {
                sum += img.get(x, y)[c];
            }
        }
        sum / 400.0
    };
    let (red_gain, green_gain) = (
        channel_mean(&glossy_red, 0) - channel_mean(&glossy, 0),
        channel_mean(&glossy_red, 1) - channel_mean(&glossy, 1),
    );
    assert!(
        red_gain > 0.02 && red_gain > 5.0 * green_gain.abs(),
        "view --albedo 0.9,0.05,0.05 adds a red base under the glossy layer: red {red_gain}, green {green_gain}"
    );
    for c in 0..3 {
        assert!(
            channel_mean(&dark, c) < 0.8 * channel_mean(&bare, c),
            "view --albedo 0.2 darkens the sphere (channel {c}): {} vs {}",
            channel_mean(&dark, c),
            channel_mean(&bare, c)
        );
    }
    let ggx_change: f32 = (0..3)
        .map(|c| (channel_mean(&ggx, c) - channel_mean(&glossy, c)).abs())
        .sum();
    assert!(
        ggx_change > 0.005 && channel_mean(&ggx, 0) > 0.01,
        "view --prt GGX shades the sphere, otherwise than Phong ({ggx_change})"
    );
    let lum = |img: &shlight_io::Image, x: usize, y: usize| {
        let p = img.get(x, y);
        p[0] + p[1] + p[2]
    };
    let mean = |img: &shlight_io::Image, x0: usize, y0: usize, n: usize| {
        let mut sum = 0.0;
        for y in y0..y0 + n {
            for x in x0..x0 + n {
                sum += lum(img, x, y);
            }
        }
        sum / (n * n) as f32
    };
    let sphere_change = (mean(&cube, 230, 150, 20) - mean(&bare, 230, 150, 20)).abs()
        + (mean(&cube, 200, 120, 10) - mean(&bare, 200, 120, 10)).abs()
        + (mean(&cube, 260, 180, 10) - mean(&bare, 260, 180, 10)).abs();
    assert!(
        sphere_change > 0.005,
        "--encoding ambient-cube shades the sphere ({sphere_change})"
    );
    let glossy_change = (mean(&glossy, 230, 150, 20) - mean(&bare, 230, 150, 20)).abs()
        + (mean(&glossy, 200, 120, 10) - mean(&bare, 200, 120, 10)).abs();
    assert!(
        glossy_change > 0.005,
        "view --prt GLOSSY shades the sphere otherwise than SH irradiance ({glossy_change})"
    );
    let corner_change = (mean(&cube, 0, 0, 20) - mean(&bare, 0, 0, 20)).abs();
    assert!(
        corner_change < 1e-6,
        "the background stays ({corner_change})"
    );
    let all: Vec<f32> = bare.pixels().iter().map(|p| p[0] + p[1] + p[2]).collect();
    let (lo, hi) = all
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(hi - lo > 0.05, "not blank: luminance {lo}..{hi}");
    // The sphere at the centre against the background in the four corners.
    let centre = mean(&bare, 230, 150, 20);
    for (x0, y0) in [(0, 0), (460, 0), (0, 300), (460, 300)] {
        let corner = mean(&bare, x0, y0, 20);
        assert!(
            (centre - corner).abs() > 0.01,
            "centre {centre} vs corner {corner}"
        );
    }
    // The overlay panel, at the top left, changes what is there.
    let d = (mean(&with_panel, 20, 20, 40) - mean(&bare, 20, 20, 40)).abs();
    assert!(d > 0.01, "the panel shows ({d})");
}

#[test]
fn render_mesh_shades_a_prt_bake_as_the_sh_irradiance_it_transfers() {
    // On a convex sphere, unshadowed transfer is albedo/π times the R&H
    // irradiance transfer, so `--prt` shading must match `--mode sh`
    // shading, up to the vertex interpolation of the transfer and the bake's
    // quadrature error.
    if !have_gpu("render_mesh_shades_a_prt_bake_as_the_sh_irradiance_it_transfers") {
        return;
    }
    let dir = temp_dir("gpu_render_prt");
    let (mesh, env, bake) = (
        dir.join("sphere.obj"),
        dir.join("light.json"),
        dir.join("sphere.shprt"),
    );
    write_obj(&mesh, &shlight_mesh::generate::uv_sphere(2.0, 64, 32));
    write_coeffs(&env, &light());
    shlight_ok(&[
        "prt",
        s(&mesh),
        "--mode",
        "unshadowed",
        "--lmax",
        "4",
        "--samples",
        "4096",
        "--albedo",
        "0.5,0.75,1",
        "-o",
        s(&bake),
        "-q",
    ]);
    let (sh, prt) = (dir.join("sh.exr"), dir.join("prt.exr"));
    let common = ["--size", "64x48", "--env", s(&env)];
    let mut args = vec![
        "render-mesh",
        s(&mesh),
        "--lmax",
        "4",
        "--albedo",
        "0.5,0.75,1",
        "-o",
        s(&sh),
    ];
    args.extend(common);
    shlight_ok(&args);
    // --prt alone selects PRT mode and the transfer's lmax.
    let mut args = vec!["render-mesh", s(&mesh), "--prt", s(&bake), "-o", s(&prt)];
    args.extend(common);
    shlight_ok(&args);
    let a = read_image(&sh, &ReadOptions::default()).unwrap();
    let b = read_image(&prt, &ReadOptions::default()).unwrap();
    let (mut covered, mut worst) = (0, 0.0f64);
    for (x, y) in a.pixels().iter().zip(b.pixels()) {
        if x[0] == 0.0 {
            assert_eq!(*y, [0.0; 3], "the same silhouette");
            continue;
        }
        covered += 1;
        for k in 0..3 {
            let err = (f64::from(y[k]) - f64::from(x[k])).abs() / f64::from(x[k]);
            worst = worst.max(err);
        }
    }
    assert!(covered > 64 * 48 / 8, "the sphere is framed ({covered})");
    assert!(worst < 1e-2, "PRT vs SH shading: worst {worst:.2e}");
    eprintln!("render-mesh --prt vs --mode sh over {covered} pixels: worst {worst:.2e}");

    // A bake of another mesh is refused, naming both files.
    let other = dir.join("other.obj");
    write_obj(&other, &shlight_mesh::generate::uv_sphere(2.0, 32, 16));
    let err = shlight_err(&[
        "render-mesh",
        s(&other),
        "--prt",
        s(&bake),
        "--env",
        s(&env),
        "-o",
        s(&dir.join("x.png")),
    ]);
    assert!(err.contains(s(&bake)) && err.contains(s(&other)), "{err}");
    let moved = dir.join("moved.obj");
    let mut m = shlight_mesh::generate::uv_sphere(2.0, 64, 32);
    m.positions[0].y += 0.01;
    write_obj(&moved, &m);
    let err = shlight_err(&[
        "render-mesh",
        s(&moved),
        "--prt",
        s(&bake),
        "--env",
        s(&env),
        "-o",
        s(&dir.join("x.png")),
    ]);
    assert!(err.contains("another mesh"), "{err}");
    let err = shlight_err(&[
        "render-mesh",
        s(&mesh),
        "--mode",
        "prt",
        "--env",
        s(&env),
        "-o",
        s(&dir.join("x.png")),
    ]);
    assert!(err.contains("--prt"), "{err}");
}

#[test]
fn a_headless_render_prints_no_error_lines() {
    let test = "a_headless_render_prints_no_error_lines";
    if !have_gpu(test) {
        return;
    }
    let dir = temp_dir("gpu_headless_quiet");
    let (mesh, env, out) = (dir.join("s.obj"), dir.join("sky.exr"), dir.join("s.exr"));
    write_obj(&mesh, &shlight_mesh::generate::uv_sphere(1.0, 16, 8));
    write_map(&env, 32, 16, |_, y| [1.0 + y as f32; 3]);
    // As on a server or in CI: no session, no display.
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_shlight"))
            .args(extra)
            .env_remove("XDG_RUNTIME_DIR")
            .env_remove("WAYLAND_DISPLAY")
            .env_remove("DISPLAY")
            .output()
            .unwrap()
    };
    let render = run(&[
        "render-mesh",
        s(&mesh),
        "--env",
        s(&env),
        "--size",
        "32x24",
        "-o",
        s(&out),
    ]);
    let project = run(&["project", s(&env), "--gpu"]);
    for (what, o) in [("render-mesh", &render), ("project --gpu", &project)] {
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{what}: {stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert!(errors.is_empty(), "{what} succeeded but printed {errors:?}");
    }
    assert!(out.exists());
}

#[test]
fn view_defaults_are_built_in_and_work_from_any_directory() {
    let Some(x) = gpu_and_xvfb("view_defaults_are_built_in_and_work_from_any_directory") else {
        return;
    };
    // A working directory without meshes/ or envmaps/.
    let dir = temp_dir("gpu_view_defaults");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shot = |name: &str, files: &[&str]| {
        let path = dir.join(name);
        let out = Command::new(env!("CARGO_BIN_EXE_shlight"))
            .current_dir(&dir)
            .arg("view")
            .args(files)
            .args(["--size", "160x120", "--frames", "2", "--hide-panel"])
            .args(["--screenshot", s(&path)])
            .env("DISPLAY", &x.display)
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "view {files:?} from {}: {}",
            dir.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        read_image(&path, &ReadOptions::default()).unwrap()
    };
    let built_in = shot("built_in.png", &[]);
    let bunny = root.join("meshes/bunny.obj");
    let env = root.join("envmaps/default.exr");
    let named = shot("named.png", &[s(&bunny), "--env", s(&env)]);
    drop(x);
    // The same files, so the same picture, texel for texel.
    assert_eq!(built_in.pixels(), named.pixels());
    let all: Vec<f32> = built_in
        .pixels()
        .iter()
        .map(|p| p[0] + p[1] + p[2])
        .collect();
    let (lo, hi) = all
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(hi - lo > 0.05, "not blank: luminance {lo}..{hi}");
}

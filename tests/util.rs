//! Shared helpers: temporary directories, running the binary, writing maps.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use shlight_io::{Image, WriteOptions, write_image};

/// A fresh directory under the target dir, removed and recreated per test.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `shlight ARGS` and returns its output.
pub fn shlight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shlight"))
        .args(args)
        .output()
        .expect("the shlight binary runs")
}

/// Writes an equirect map of `w x h` texels, `f(x, y)` each, as EXR.
pub fn write_map(path: &Path, w: usize, h: usize, f: impl Fn(usize, usize) -> [f32; 3]) {
    let img = Image::from_fn(w, h, f);
    write_image(path, &img, &WriteOptions::default()).unwrap();
}

/// Parses stdout as JSON, with the output shown on failure.
pub fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

/// The coefficients of a coefficient file as `[r, g, b]` rows.
pub fn coefficients(v: &serde_json::Value) -> Vec<[f64; 3]> {
    v["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            [
                c[0].as_f64().unwrap(),
                c[1].as_f64().unwrap(),
                c[2].as_f64().unwrap(),
            ]
        })
        .collect()
}

/// Runs `shlight ARGS`, asserting success (stderr shown on failure).
pub fn shlight_ok(args: &[&str]) -> Output {
    let out = shlight(args);
    assert!(
        out.status.success(),
        "shlight {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs `shlight ARGS`, asserting failure, and returns its stderr.
pub fn shlight_err(args: &[&str]) -> String {
    let out = shlight(args);
    assert!(!out.status.success(), "shlight {args:?} succeeded");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A path as `&str` (test paths are UTF-8).
pub fn s(path: &Path) -> &str {
    path.to_str().expect("UTF-8 test path")
}

/// Reads a JSON file.
pub fn read_json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `shlight project MAP ARGS` to stdout, as coefficient rows.
pub fn project_rows(map: &Path, args: &[&str]) -> Vec<[f64; 3]> {
    let mut all = vec!["project", s(map)];
    all.extend_from_slice(args);
    coefficients(&json(&shlight(&all)))
}

/// Asserts `got` and `want` agree to `tol` times the largest `|want|`,
/// coefficient by coefficient and channel by channel.
pub fn assert_rows_near(got: &[[f64; 3]], want: &[[f64; 3]], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: coefficient count");
    let scale = want
        .iter()
        .flatten()
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        for c in 0..3 {
            assert!(
                (g[c] - w[c]).abs() <= tol * scale,
                "{what}: coefficient {i} channel {c}: {} vs {} (tolerance {})",
                g[c],
                w[c],
                tol * scale
            );
        }
    }
}

/// Direction (unit) of the band-1 part of red-channel coefficients: for a
/// light from `d`, `(L_1^-1, L_1^0, L_1^1) ∝ (-d.y, d.z, -d.x)`, so this is
/// `(-L_1^1, -L_1^-1, L_1^0)` normalised.
pub fn band1_direction(c: &[[f64; 3]]) -> [f64; 3] {
    let v = [-c[3][0], -c[1][0], c[2][0]];
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

/// Writes a `w x h` map, black but for a `k x k` block of `value` whose
/// top-left texel is `(x0, y0)`.
pub fn write_spot(
    path: &Path,
    w: usize,
    h: usize,
    (x0, y0): (usize, usize),
    k: usize,
    value: [f32; 3],
) {
    write_map(path, w, h, |x, y| {
        if (x0..x0 + k).contains(&x) && (y0..y0 + k).contains(&y) {
            value
        } else {
            [0.0; 3]
        }
    });
}

/// Writes `mesh` as OBJ with normals (`v`, `vn`, `f a//a b//b c//c`), so it
/// loads back with the same vertex order.
pub fn write_obj(path: &Path, mesh: &shlight_mesh::Mesh) {
    let mut text = String::new();
    for p in &mesh.positions {
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for n in &mesh.normals {
        text += &format!("vn {} {} {}\n", n.x, n.y, n.z);
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        text += &format!("f {a}//{a} {b}//{b} {c}//{c}\n");
    }
    std::fs::write(path, text).unwrap();
}

/// Writes a radiance coefficient file (y-up) holding `rows` (`(lmax+1)^2`
/// of them).
pub fn write_radiance_rows(path: &Path, rows: &[[f64; 3]]) {
    write_coefficient_rows(path, rows, "radiance");
}

/// A y-up coefficient file holding `quantity` (`radiance`, `irradiance`)
/// with these coefficient rows.
pub fn write_coefficient_rows(path: &Path, rows: &[[f64; 3]], quantity: &str) {
    let lmax = (rows.len() as f64).sqrt() as usize - 1;
    assert_eq!(
        (lmax + 1) * (lmax + 1),
        rows.len(),
        "a square number of rows"
    );
    let doc = serde_json::json!({
        "format": "shlight-sh",
        "format_version": 1,
        "lmax": lmax,
        "frame": "y-up",
        "mirror": false,
        "quantity": quantity,
        "coefficients": rows,
        "provenance": {},
    });
    std::fs::write(path, doc.to_string()).unwrap();
}

/// `SHLIGHT_REQUIRE_ALL=1` (set by CI): no test may skip, for any reason.
pub const REQUIRE_ALL: &str = "SHLIGHT_REQUIRE_ALL";

/// `SHLIGHT_REQUIRE_GPU=1`: no test may skip for want of a GPU adapter (or
/// the X server the viewer needs).
pub const REQUIRE_GPU: &str = "SHLIGHT_REQUIRE_GPU";

fn switched_on(var: &str) -> bool {
    std::env::var(var).as_deref() == Ok("1")
}

/// Skips `test` because `why` (a missing tool): prints a SKIPPED line, or
/// panics under `SHLIGHT_REQUIRE_ALL=1`.
pub fn skip(test: &str, why: &str) {
    skip_unless(test, why, &[REQUIRE_ALL]);
}

/// Skips `test` for want of a GPU: prints a SKIPPED line, or panics under
/// `SHLIGHT_REQUIRE_GPU=1` or `SHLIGHT_REQUIRE_ALL=1`.
pub fn skip_gpu(test: &str, why: &str) {
    skip_unless(test, why, &[REQUIRE_GPU, REQUIRE_ALL]);
}

/// Prints `SKIPPED test: why` for something no machine can run unattended
/// (an interactive window), whatever the switches say.
pub fn skip_interactive(test: &str, why: &str) {
    skip_unless(test, why, &[]);
}

/// Panics when one of `switches` is `1`, else prints `SKIPPED test: why`.
///
/// The line is written with `write!` on the process's own stderr handle:
/// the test harness captures only the `print!`/`eprint!` macros, so this
/// line shows in a passing run (`cargo test` without `--nocapture`).
fn skip_unless(test: &str, why: &str, switches: &[&str]) {
    if let Some(var) = switches.iter().find(|v| switched_on(v)) {
        panic!("{test}: {var}=1 but it would be skipped: {why}");
    }
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
}

/// The headless GPU context, or `None` after [`skip_gpu`] when there is no
/// adapter.
#[cfg(feature = "gpu")]
pub fn gpu_context(test: &str) -> Option<shlight_gpu::GpuContext> {
    match shlight_gpu::GpuContext::headless() {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            skip_gpu(test, &e.to_string());
            None
        }
    }
}

/// Whether `tool --version` runs; [`skip`]s `test` when it does not.
pub fn have_tool(tool: &str, test: &str) -> bool {
    let ok = std::process::Command::new(tool)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        skip(test, &format!("`{tool}` is not installed"));
    }
    ok
}

/// `n` unit directions: the core's Fibonacci sphere of `n - 6` points plus
/// the six axis directions.
pub fn sphere_directions(n: usize) -> Vec<glam::DVec3> {
    use glam::DVec3;
    let mut v = shlight_core::sh::fibonacci_sphere(n - 6);
    v.extend([
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        DVec3::NEG_X,
        DVec3::NEG_Y,
        DVec3::NEG_Z,
    ]);
    v
}

/// Compiles `source` as C99 (`lang` "c") or C++17 (anything else) with
/// `compiler`, warnings as errors, into `dir/NAME` (the source as
/// `dir/NAME.LANG`), runs it and returns the numbers of each line it
/// prints; a compiler error fails the test with its message.
pub fn compile_and_run(
    dir: &Path,
    name: &str,
    compiler: &str,
    lang: &str,
    source: &str,
) -> Vec<Vec<f64>> {
    let src = dir.join(format!("{name}.{lang}"));
    let exe = dir.join(name);
    std::fs::write(&src, source).unwrap();
    let mut cmd = Command::new(compiler);
    if lang == "c" {
        cmd.args(["-std=c99", "-pedantic"]);
    } else {
        cmd.arg("-std=c++17");
    }
    let out = cmd
        .args(["-O1", "-Wall", "-Wextra", "-Werror", "-o"])
        .arg(&exe)
        .arg(&src)
        .arg("-lm")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{compiler} failed on {}:\n{}",
        src.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let run = Command::new(&exe).output().unwrap();
    assert!(run.status.success());
    String::from_utf8(run.stdout)
        .unwrap()
        .lines()
        .map(|l| l.split_whitespace().map(|s| s.parse().unwrap()).collect())
        .collect()
}

/// `dir/sun.exr`: a 256x128 map of a 2-degree sun from (1, 1, 0.5), value
/// 5 and colour (1, 0.8, 0.6), over a dim sky (`shlight synth directional`).
pub fn synth_sun_map(dir: &Path) -> PathBuf {
    let map = dir.join("sun.exr");
    shlight_ok(&[
        "synth",
        "directional",
        "-o",
        s(&map),
        "--direction",
        "1,1,0.5",
        "--half-angle",
        "2",
        "--value",
        "5",
        "--color",
        "1,0.8,0.6",
        "--size",
        "256x128",
    ]);
    map
}

/// Two sealed rooms side by side (x 0..4, 1.5 high, 2 deep), split by a
/// wall 4 cm thick centred at x = `wall`, a lamp under the left room's
/// ceiling facing down (0.4 from its walls): every face towards the inside
/// of its room, as an OBJ with its MTL `rooms.mtl` beside it (white walls,
/// the lamp emitting 4).
pub fn write_two_rooms(obj: &std::path::Path, wall: f32) {
    let mut quads: Vec<([glam::Vec3; 4], &str)> = Vec::new();
    let c = glam::Vec3::new;
    let mut room = |a: glam::Vec3, b: glam::Vec3| {
        for q in [
            [
                c(a.x, a.y, a.z),
                c(a.x, a.y, b.z),
                c(b.x, a.y, b.z),
                c(b.x, a.y, a.z),
            ],
            [
                c(a.x, b.y, a.z),
                c(b.x, b.y, a.z),
                c(b.x, b.y, b.z),
                c(a.x, b.y, b.z),
            ],
            [
                c(a.x, a.y, a.z),
                c(a.x, b.y, a.z),
                c(a.x, b.y, b.z),
                c(a.x, a.y, b.z),
            ],
            [
                c(b.x, a.y, a.z),
                c(b.x, a.y, b.z),
                c(b.x, b.y, b.z),
                c(b.x, b.y, a.z),
            ],
            [
                c(a.x, a.y, a.z),
                c(b.x, a.y, a.z),
                c(b.x, b.y, a.z),
                c(a.x, b.y, a.z),
            ],
            [
                c(a.x, a.y, b.z),
                c(a.x, b.y, b.z),
                c(b.x, b.y, b.z),
                c(b.x, a.y, b.z),
            ],
        ] {
            quads.push((q, "wall"));
        }
    };
    room(glam::Vec3::ZERO, c(wall - 0.02, 1.5, 2.0));
    room(c(wall + 0.02, 0.0, 0.0), c(4.0, 1.5, 2.0));
    let y = 1.45;
    quads.push((
        [
            c(0.4, y, 0.5),
            c(wall - 0.42, y, 0.5),
            c(wall - 0.42, y, 1.5),
            c(0.4, y, 1.5),
        ],
        "lamp",
    ));
    let mut text = String::from("mtllib rooms.mtl\n");
    for (k, (q, material)) in quads.iter().enumerate() {
        text += &format!("usemtl {material}\n");
        for p in q {
            text += &format!("v {} {} {}\n", p.x, p.y, p.z);
        }
        let v = 4 * k + 1;
        text += &format!("f {} {} {}\nf {} {} {}\n", v, v + 1, v + 2, v, v + 2, v + 3);
    }
    std::fs::write(obj, text).unwrap();
    std::fs::write(
        obj.with_file_name("rooms.mtl"),
        "newmtl wall\nKd 0.8 0.8 0.8\nnewmtl lamp\nKd 0.8 0.8 0.8\nKe 4 4 4\n",
    )
    .unwrap();
}

/// [`write_two_rooms`] (`dir/rooms.obj`, the wall at `wall`) baked into
/// `dir/rooms.shvol` by `shlight volume` under a sky of the lmax-2
/// radiance rows `sky` (`dir/sky.json`), probes at `resolution` over the
/// rooms' box, 512 rays a probe and 64 directions a surface vertex, with
/// the defaults otherwise (visibility and relocation on); returns the
/// volume's path.
pub fn bake_two_rooms(dir: &Path, wall: f32, sky: &[[f64; 3]; 9], resolution: &str) -> PathBuf {
    let rooms = dir.join("rooms.obj");
    write_two_rooms(&rooms, wall);
    let env = dir.join("sky.json");
    write_radiance_rows(&env, sky);
    let volume = dir.join("rooms.shvol");
    shlight_ok(&[
        "volume",
        s(&rooms),
        "--env",
        s(&env),
        "--resolution",
        resolution,
        "--bounds",
        "0,0,0:4,1.5,2",
        "--samples",
        "512",
        "--surface-samples",
        "64",
        "-o",
        s(&volume),
    ]);
    volume
}

/// A GLB: the header, a JSON chunk (space-padded) and a BIN chunk.
pub fn glb(json: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let length = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((length as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

//! shlight's web exports in a real browser: headless Chromium (WebGL 2
//! through SwiftShader) runs three.js r187 from npm and shlight's
//! `web/shlight-three.js` on pages under `tests/web/`, served from
//! 127.0.0.1 by a small server in the test; each page renders into
//! `FloatType` targets, reads the pixels back (`readRenderTargetPixels`)
//! and POSTs them as JSON to the server's `/result`, which the test
//! compares with shlight's own numbers.
//!
//! The same harness runs Babylon.js 8.56.2 (its UMD builds, npm
//! `babylonjs` and `babylonjs-loaders`) on `tests/web/babylon.html`, which
//! loads shlight's `EXT_lights_image_based` glTF with Babylon's own glTF
//! loader.
//!
//! Needs Chromium (`chromium` on the PATH, or `SHLIGHT_CHROMIUM`), three.js
//! (`.ci/run` installs `three@0.187.0` into `target/web-deps`, or
//! `SHLIGHT_THREEJS` names its folder) and, for the Babylon test,
//! Babylon.js (`.ci/run` installs `babylonjs@8.56.2` and
//! `babylonjs-loaders@8.56.2` into `target/web-deps`, or
//! `SHLIGHT_BABYLONJS` names the `node_modules` folder holding both);
//! without them a test prints a SKIPPED line, and fails under
//! `SHLIGHT_REQUIRE_ALL=1`. One browser runs at a time (two cores).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::time::Duration;

use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::sh::{Frame, irradiance};
use shlight_format::{CoeffFile, Quantity};

use crate::util::{s, shlight_err, shlight_ok, skip, temp_dir, write_coefficient_rows};

/// One browser at a time.
static BROWSER: Mutex<()> = Mutex::new(());

/// How long a page may take to report.
const PAGE_TIMEOUT: Duration = Duration::from_secs(90);

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Chromium: `SHLIGHT_CHROMIUM`, else `chromium` or `chromium-browser` on
/// the PATH.
fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("SHLIGHT_CHROMIUM") {
        return Some(PathBuf::from(p)).filter(|p| p.is_file());
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|d| ["chromium", "chromium-browser"].map(|n| d.join(n)))
        .find(|p| p.is_file())
}

/// The npm package `three`: `SHLIGHT_THREEJS`, else where `.ci/run`
/// installs it.
fn three_dir() -> PathBuf {
    std::env::var_os("SHLIGHT_THREEJS").map_or_else(
        || repo().join("target/web-deps/node_modules/three"),
        PathBuf::from,
    )
}

/// The Babylon.js version the Babylon test is written against (`.ci/run`
/// installs it).
const BABYLON_VERSION: &str = "8.56.2";

/// The `node_modules` folder holding the npm packages `babylonjs` and
/// `babylonjs-loaders`: `SHLIGHT_BABYLONJS`, else where `.ci/run` installs
/// them.
fn babylon_dir() -> PathBuf {
    std::env::var_os("SHLIGHT_BABYLONJS").map_or_else(
        || repo().join("target/web-deps/node_modules"),
        PathBuf::from,
    )
}

/// What the server maps URL prefixes to.
#[derive(Clone)]
struct Roots {
    three: PathBuf,
    babylon: PathBuf,
    data: PathBuf,
}

impl Roots {
    fn file(&self, url_path: &str) -> Option<PathBuf> {
        let path = url_path.split(['?', '#']).next()?;
        if path.split('/').any(|p| p == "..") {
            return None;
        }
        let (root, rest) = if let Some(r) = path.strip_prefix("/three/") {
            (self.three.clone(), r)
        } else if let Some(r) = path.strip_prefix("/web/node_modules/three/") {
            // Where web/index.html's import map looks.
            (self.three.clone(), r)
        } else if let Some(r) = path.strip_prefix("/babylon/") {
            (self.babylon.clone(), r)
        } else if let Some(r) = path.strip_prefix("/web/") {
            (repo().join("web"), r)
        } else if let Some(r) = path.strip_prefix("/tests/web/") {
            (repo().join("tests/web"), r)
        } else if let Some(r) = path.strip_prefix("/data/") {
            (self.data.clone(), r)
        } else {
            return None;
        };
        Some(root.join(rest))
    }
}

fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()) {
        Some("html") => "text/html; charset=utf-8",
        Some("js") => "text/javascript",
        Some("json") => "application/json",
        Some("glb") => "model/gltf-binary",
        Some("gltf") => "model/gltf+json",
        Some("png") => "image/png",
        _ => "application/octet-stream",
    }
}

/// Serves one HTTP/1.1 request on `stream`: GET of a file under the roots,
/// or POST `/result`, whose body goes to `results`.
fn handle(stream: TcpStream, roots: &Roots, results: &Sender<Vec<u8>>) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut line = String::new();
    reader.read_line(&mut line)?;
    let mut parts = line.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    let mut length = 0usize;
    loop {
        let mut header = String::new();
        if reader.read_line(&mut header)? == 0 || header.trim().is_empty() {
            break;
        }
        if let Some((k, v)) = header.split_once(':')
            && k.eq_ignore_ascii_case("content-length")
        {
            length = v.trim().parse().unwrap_or(0);
        }
    }
    let mut stream = stream;
    if method == "POST" && target == "/result" {
        let mut body = vec![0; length];
        reader.read_exact(&mut body)?;
        let _ = results.send(body);
        return stream.write_all(
            b"HTTP/1.1 204 No Content\r\nConnection: close\r\nContent-Length: 0\r\n\r\n",
        );
    }
    match roots
        .file(target)
        .and_then(|p| Some((std::fs::read(&p).ok()?, p)))
    {
        Some((bytes, path)) => {
            write!(
                stream,
                "HTTP/1.1 200 OK\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
                content_type(&path),
                bytes.len()
            )?;
            stream.write_all(&bytes)
        }
        None => stream.write_all(
            b"HTTP/1.1 404 Not Found\r\nConnection: close\r\nContent-Length: 9\r\n\r\nnot found",
        ),
    }
}

/// Starts the server on 127.0.0.1 (a free port): its port and the channel
/// the pages' results arrive on. The thread ends with the test binary.
fn serve(roots: Roots) -> (u16, Receiver<Vec<u8>>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a loopback port");
    let port = listener.local_addr().unwrap().port();
    let (tx, rx) = channel();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let (roots, tx) = (roots.clone(), tx.clone());
            std::thread::spawn(move || {
                let _ = handle(stream, &roots, &tx);
            });
        }
    });
    (port, rx)
}

/// The library a page runs.
#[derive(Clone, Copy, PartialEq)]
enum Library {
    Three,
    Babylon,
}

/// Loads `page` (a path with its query, e.g.
/// `/tests/web/probe.html?probe=/data/p.json`) in headless Chromium with
/// `data` served under `/data/`, and returns what the page reported; `None`
/// after a SKIPPED line when Chromium or three.js is missing. Panics on a
/// page's `error` report, or when it reports nothing in time (Chromium's
/// log shown).
fn run_page(test: &str, data: &Path, page: &str) -> Option<Value> {
    run_library_page(test, data, page, Library::Three)
}

/// [`run_page`] for a page that runs Babylon.js (skipped without it).
fn run_babylon_page(test: &str, data: &Path, page: &str) -> Option<Value> {
    run_library_page(test, data, page, Library::Babylon)
}

fn run_library_page(test: &str, data: &Path, page: &str, library: Library) -> Option<Value> {
    let _one = BROWSER
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let Some(chromium) = chromium() else {
        skip(test, "Chromium is not installed (apt-get install chromium)");
        return None;
    };
    let (three, babylon) = (three_dir(), babylon_dir());
    if library == Library::Three
        && !three
            .join("examples/jsm/lighting/LightProbeGridWebGL.js")
            .is_file()
    {
        skip(
            test,
            &format!(
                "three.js r187 is not at {} (npm install --prefix target/web-deps three@0.187.0)",
                three.display()
            ),
        );
        return None;
    }
    if library == Library::Babylon {
        let version = |package: &str| -> Option<String> {
            let text = std::fs::read_to_string(babylon.join(package).join("package.json")).ok()?;
            let v: Value = serde_json::from_str(&text).ok()?;
            v["version"].as_str().map(str::to_string)
        };
        let want = Some(BABYLON_VERSION.to_string());
        if version("babylonjs") != want || version("babylonjs-loaders") != want {
            skip(
                test,
                &format!(
                    "Babylon.js {BABYLON_VERSION} is not in {} (npm install --prefix target/web-deps babylonjs@{BABYLON_VERSION} babylonjs-loaders@{BABYLON_VERSION})",
                    babylon.display()
                ),
            );
            return None;
        }
    }
    let (port, results) = serve(Roots {
        three,
        babylon,
        data: data.to_path_buf(),
    });
    let profile = data.join("chromium-profile");
    let log_path = data.join("chromium.log");
    let log = std::fs::File::create(&log_path).unwrap();
    let mut child = Command::new(&chromium)
        .args([
            "--headless=new",
            "--no-sandbox",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--ignore-gpu-blocklist",
            "--no-first-run",
            "--no-default-browser-check",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-quic",
            "--disable-default-apps",
            "--disable-extensions",
            "--enable-logging=stderr",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("http://127.0.0.1:{port}{page}"))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(log)
        .spawn()
        .unwrap_or_else(|e| panic!("{test}: cannot start {}: {e}", chromium.display()));
    let got = results.recv_timeout(PAGE_TIMEOUT);
    let _ = child.kill();
    let _ = child.wait();
    let body = got.unwrap_or_else(|_| {
        let log = std::fs::read_to_string(&log_path).unwrap_or_default();
        let tail: String = log
            .lines()
            .rev()
            .take(40)
            .collect::<Vec<_>>()
            .into_iter()
            .rev()
            .collect::<Vec<_>>()
            .join("\n");
        panic!("{test}: {page} reported nothing in {PAGE_TIMEOUT:?}; Chromium's log:\n{tail}")
    });
    let v: Value = serde_json::from_slice(&body).expect("the page reports JSON");
    if let Some(e) = v.get("error") {
        panic!("{test}: {page} failed: {e}");
    }
    Some(v)
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array of numbers")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// The RGBA pixels of a report's `key`, as `[f64; 4]`.
fn pixels(v: &Value, key: &str) -> Vec<[f64; 4]> {
    floats(&v[key])
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect()
}

/// three.js's `LightProbe` from shlight's `--format threejs` export of a
/// bundled map lights a white Lambert sphere with shlight's irradiance:
/// every covered pixel equals `E(n) / pi`, `E` computed here from the
/// coefficient file by shlight-core (the radiance times the clamped
/// cosine's `A_l`, the SH evaluated at the pixel's own interpolated normal,
/// which the page reads back too). Fails on any basis, phase, frame or
/// normalisation slip in the export (a sign on `L1-1` alone moves pixels by
/// a tenth of the maximum).
#[test]
fn threejs_light_probe_lights_a_sphere_with_shlights_irradiance() {
    let test = "web::threejs_light_probe_lights_a_sphere_with_shlights_irradiance";
    let dir = temp_dir("web-probe");
    let coeffs = dir.join("studio.json");
    shlight_ok(&[
        "project",
        "envmaps/studio.exr",
        "--lmax",
        "2",
        "-o",
        s(&coeffs),
    ]);
    shlight_ok(&[
        "convert",
        s(&coeffs),
        "--format",
        "threejs",
        "-o",
        s(&dir.join("probe.json")),
    ]);
    let Some(r) = run_page(test, &dir, "/tests/web/probe.html?probe=/data/probe.json") else {
        return;
    };
    assert_eq!(r["three"], "187");
    let file = CoeffFile::read(&coeffs).unwrap();
    assert_eq!(
        (file.frame, file.quantity),
        (Frame::YUp, Quantity::Radiance)
    );
    let e = irradiance(&file.coeffs);
    let (lit, normal) = (pixels(&r, "lit"), pixels(&r, "normal"));
    let mut worst = 0.0f64;
    let mut peak = 0.0f64;
    let mut covered = 0;
    for (l, n) in lit.iter().zip(&normal) {
        if n[3] == 0.0 {
            assert_eq!(l[3], 0.0, "the two passes cover the same pixels");
            continue;
        }
        covered += 1;
        let want = e.eval(DVec3::new(n[0], n[1], n[2]).normalize()) / std::f64::consts::PI;
        for c in 0..3 {
            worst = worst.max((l[c] - want[c]).abs());
            peak = peak.max(want[c].abs());
        }
    }
    assert!(covered > 1000, "the sphere covers {covered} pixels");
    let rel = worst / peak;
    eprintln!(
        "{test}: {covered} pixels, worst |three.js - E/pi| = {worst:.3e} ({rel:.2e} of the peak {peak:.4})"
    );
    assert!(
        rel < 1e-5,
        "worst {worst:.3e} ({rel:.2e} of the peak {peak:.4})"
    );
}

/// The specular cube as Babylon.js holds it after its glTF loader's
/// `updateRGBDAsync`: every face texel decoded from RGBD (`fromRGBD`:
/// `rgb^2.2 / a`) into a half-float cube (what `UploadLevelsAsync` does
/// where the GPU renders to and filters half floats), read here from the
/// glTF's PNGs with the `image` crate (not shlight's code).
struct BabylonCube {
    size: usize,
    /// `mips[k][face]`: `(size >> k)^2` texels, rows as in the PNG.
    mips: Vec<Vec<Vec<DVec3>>>,
}

impl BabylonCube {
    fn read(doc: &Value, light: &Value, half_floats: bool) -> Self {
        use base64::Engine as _;
        let size = light["specularImageSize"].as_u64().unwrap() as usize;
        let mips = light["specularImages"]
            .as_array()
            .unwrap()
            .iter()
            .map(|faces| {
                faces
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|index| {
                        let uri = doc["images"][index.as_u64().unwrap() as usize]["uri"]
                            .as_str()
                            .unwrap();
                        let bytes = base64::engine::general_purpose::STANDARD
                            .decode(uri.strip_prefix("data:image/png;base64,").unwrap())
                            .unwrap();
                        let img = image::load_from_memory(&bytes).unwrap().to_rgba8();
                        img.pixels()
                            .map(|p| {
                                let a = f64::from(p.0[3]) / 255.0;
                                let c = |i: usize| {
                                    let v = (f64::from(p.0[i]) / 255.0).powf(2.2) / a;
                                    if half_floats {
                                        half::f16::from_f64(v).to_f64()
                                    } else {
                                        v
                                    }
                                };
                                DVec3::new(c(0), c(1), c(2))
                            })
                            .collect()
                    })
                    .collect()
            })
            .collect();
        BabylonCube { size, mips }
    }

    /// WebGL 2's bilinear lookup of mip `k` at direction `r`: OpenGL's
    /// face selection and `(s, t)` (the cube-map table of the GL spec), the
    /// PNG's first row at `t = 1` when `png_row0_at_bottom` (else at `t =
    /// 0`). Returns the value and, per channel, the largest of the four
    /// texels it mixes; `None` where the four texels are not on one face.
    fn sample(&self, k: usize, r: DVec3, png_row0_at_bottom: bool) -> Option<(DVec3, DVec3)> {
        let a = r.abs();
        let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
            if r.x > 0.0 {
                (0, -r.z, -r.y, a.x)
            } else {
                (1, r.z, -r.y, a.x)
            }
        } else if a.y >= a.z {
            if r.y > 0.0 {
                (2, r.x, r.z, a.y)
            } else {
                (3, r.x, -r.z, a.y)
            }
        } else if r.z > 0.0 {
            (4, r.x, -r.y, a.z)
        } else {
            (5, -r.x, -r.y, a.z)
        };
        let n = self.size >> k;
        let (s, t) = ((sc / ma + 1.0) / 2.0, (tc / ma + 1.0) / 2.0);
        let t = if png_row0_at_bottom { 1.0 - t } else { t };
        let (u, v) = (s * n as f64 - 0.5, t * n as f64 - 0.5);
        if u < 0.0 || v < 0.0 || u >= (n - 1) as f64 || v >= (n - 1) as f64 {
            return None;
        }
        let (i, j) = (u.floor() as usize, v.floor() as usize);
        let (fu, fv) = (u - i as f64, v - j as f64);
        let texels = &self.mips[k][face];
        let at = |i: usize, j: usize| texels[j * n + i];
        let (t00, t10, t01, t11) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
        let value = t00 * ((1.0 - fu) * (1.0 - fv))
            + t10 * (fu * (1.0 - fv))
            + t01 * ((1.0 - fu) * fv)
            + t11 * (fu * fv);
        Some((value, t00.max(t10).max(t01).max(t11)))
    }
}

/// Babylon.js 8.56.2's own glTF loader reads shlight's
/// `EXT_lights_image_based` export of a bundled map (`shlight project MAP
/// --format gltf`), in a default left-handed scene and in a right-handed
/// one (`useRightHandedSystem`), and lights three white spheres
/// (`PBRMaterial`, linear output) with it:
///
/// - a rough dielectric without a specular lobe (`metallicF0Factor` 0, so
///   F0 = F90 = 0: the irradiance term alone) shows shlight-core's
///   `max(E(d) / pi, 0)`, `E` from shlight's own coefficient file of the
///   map, at each pixel's normal `n` (read back) taken to shlight's frame
///   as `d = (n.z, n.y, n.x)`, with `n.z` negated first in the right-handed
///   scene (Babylon flips z on every environment lookup there). Babylon
///   evaluates the coefficients in its own world: the glTF root node's
///   mirror of x is not undone. Within 1e-5 of the peak (f32 shading of an
///   exact polynomial form; the `max` is Babylon's `max(finalColor, 0)`).
/// - a mirror (metallic 1, roughness 0) shows mip 0 at the reflected view
///   direction, and a metal at roughness `sqrt(4/S - 0.0005)` (Babylon's
///   `alphaG = r^2 + 0.0005`, so `lod = log2(S alphaG) = 2`) shows mip 2:
///   each pixel the bilinear mix of the four half-float texels decoded from
///   the PNGs, the PNG's first row at the bottom of each face, within a
///   half-float step of the largest (2^-10) plus 2e-5 of the peak.
///
/// Babylon's loader leaves the cube's `gammaSpace` at its default (true),
/// so as loaded the shader raises the decoded radiance to the power 2.2;
/// the page renders the mirror that way too (checked here: a Babylon that
/// fixes it fails this test), then sets `gammaSpace = false`.
///
/// Each check is shown able to fail: the same pixels against the light
/// read in the glTF world (x mirrored back: the Sample Viewer's frame),
/// against the coefficients without the Condon-Shortley phase, and against
/// the PNGs read upright, are off by far more than allowed.
#[test]
fn babylon_loads_the_gltf_light_with_shlights_irradiance_and_specular_mips() {
    let test = "web::babylon_loads_the_gltf_light_with_shlights_irradiance_and_specular_mips";
    let dir = temp_dir("web-babylon");
    let (size, rough_mip) = (64usize, 2usize);
    let gltf = dir.join("light.gltf");
    let coeffs = dir.join("studio.json");
    shlight_ok(&[
        "project",
        "envmaps/studio.exr",
        "--format",
        "gltf",
        "--specular-size",
        &size.to_string(),
        "--specular-samples",
        "256",
        "-q",
        "-o",
        s(&gltf),
    ]);
    shlight_ok(&[
        "project",
        "envmaps/studio.exr",
        "--lmax",
        "2",
        "-q",
        "-o",
        s(&coeffs),
    ]);
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&gltf).unwrap()).unwrap();
    let light = &doc["extensions"]["EXT_lights_image_based"]["lights"][0];
    let file = CoeffFile::read(&coeffs).unwrap();
    assert_eq!(
        (file.frame, file.quantity),
        (Frame::YUp, Quantity::Radiance)
    );
    let e = irradiance(&file.coeffs);
    // The same irradiance without the Condon-Shortley phase (odd m negated).
    let e_no_phase = shlight_core::sh::ShCoeffs::from_vec(
        e.as_slice()
            .iter()
            .enumerate()
            .map(|(i, c)| if [1, 3, 5, 7].contains(&i) { -*c } else { *c })
            .collect(),
    )
    .unwrap();
    let alpha = 2f64.powi(rough_mip as i32) / size as f64;
    let roughness = (alpha - 0.0005).sqrt();
    for right_handed in [false, true] {
        let page = format!(
            "/tests/web/babylon.html?gltf=/data/light.gltf&roughness={roughness}&rh={}",
            u8::from(right_handed)
        );
        let Some(r) = run_babylon_page(test, &dir, &page) else {
            return;
        };
        let hand = if right_handed { "right" } else { "left" };
        assert_eq!(r["babylon"], BABYLON_VERSION);
        assert_eq!(r["rightHanded"], right_handed);
        let env = &r["environment"];
        assert_eq!(env["size"].as_u64(), Some(size as u64), "{env}");
        assert_eq!(env["lodGenerationScale"].as_f64(), Some(1.0), "{env}");
        assert_eq!(env["gammaSpace"], true, "{env}");
        assert_eq!(
            floats(&env["reflectionMatrix"]),
            glam::DMat4::IDENTITY.to_cols_array()
        );
        assert_eq!(
            env["isRGBD"], false,
            "Babylon kept the cube RGBD-packed (no half-float render targets); this test models the decoded cube: {env}"
        );
        // Babylon's TEXTURETYPE_HALF_FLOAT (2) or FLOAT (1).
        let half_floats = match env["textureType"].as_u64() {
            Some(2) => true,
            Some(1) => false,
            t => panic!("cube texture type {t:?}"),
        };
        let cube = BabylonCube::read(&doc, light, half_floats);
        // Babylon's lookup direction for a world direction.
        let lookup = |w: DVec3| {
            if right_handed {
                DVec3::new(w.x, w.y, -w.z)
            } else {
                w
            }
        };
        // Babylon's world (the light's frame) to shlight's y-up frame.
        let shlight_dir = |c: DVec3| DVec3::new(c.z, c.y, c.x);
        let gltf_world = |c: DVec3| DVec3::new(-c.x, c.y, c.z);
        let (normal, position) = (pixels(&r, "normal"), pixels(&r, "position"));
        let eye = DVec3::from_slice(&floats(&r["eye"]));
        let covered: Vec<usize> = (0..normal.len()).filter(|&i| normal[i][3] != 0.0).collect();
        assert!(
            covered.len() > 1000,
            "the sphere covers {} pixels",
            covered.len()
        );

        // The irradiance term.
        let diffuse = pixels(&r, "diffuse");
        let (mut worst, mut peak) = (0.0f64, 0.0f64);
        let (mut worst_gltf_world, mut worst_no_phase) = (0.0f64, 0.0f64);
        for &i in &covered {
            let n = DVec3::new(normal[i][0], normal[i][1], normal[i][2]).normalize();
            let c = lookup(n);
            let want = |e: &shlight_core::sh::ShCoeffs<DVec3>, c: DVec3| {
                (e.eval(shlight_dir(c)) / std::f64::consts::PI).max(DVec3::ZERO)
            };
            let got = DVec3::new(diffuse[i][0], diffuse[i][1], diffuse[i][2]);
            let w = want(&e, c);
            worst = worst.max((got - w).abs().max_element());
            peak = peak.max(w.max_element());
            worst_gltf_world =
                worst_gltf_world.max((got - want(&e, gltf_world(c))).abs().max_element());
            worst_no_phase = worst_no_phase.max((got - want(&e_no_phase, c)).abs().max_element());
        }
        eprintln!(
            "{test}: {hand}-handed: irradiance over {} pixels: worst |Babylon - max(E/pi, 0)| = {worst:.3e} ({:.2e} of the peak {peak:.4}); read in the glTF world {:.3}, without the CS phase {:.3} of the peak",
            covered.len(),
            worst / peak,
            worst_gltf_world / peak,
            worst_no_phase / peak
        );
        assert!(
            worst < 1e-5 * peak,
            "{hand}-handed: worst {worst:.3e}, peak {peak:.4}"
        );
        assert!(worst_gltf_world > 0.1 * peak && worst_no_phase > 0.1 * peak);

        // The specular mips: the mirror (mip 0) and the rough metal.
        let sphere = |key: &str, mip: usize, power: f64| {
            let lit = pixels(&r, key);
            let (mut excess, mut worst, mut peak, mut compared) = (0.0f64, 0.0f64, 0.0f64, 0);
            let (mut worst_gltf_world, mut worst_upright) = (0.0f64, 0.0f64);
            for &i in &covered {
                let n = DVec3::new(normal[i][0], normal[i][1], normal[i][2]).normalize();
                let p = DVec3::new(position[i][0], position[i][1], position[i][2]);
                let v = (p - eye).normalize();
                let c = lookup(v - 2.0 * v.dot(n) * n);
                let Some((want, largest)) = cube.sample(mip, c, true) else {
                    continue;
                };
                compared += 1;
                // As loaded, Babylon shows want^2.2: compare its 2.2th root.
                let got = DVec3::new(lit[i][0], lit[i][1], lit[i][2]).powf(1.0 / power);
                let d = (got - want).abs();
                worst = worst.max(d.max_element());
                peak = peak.max(want.max_element());
                excess = excess.max((d - largest * 2f64.powi(-10)).max_element());
                if let Some((w, _)) = cube.sample(mip, gltf_world(c), true) {
                    worst_gltf_world = worst_gltf_world.max((got - w).abs().max_element());
                }
                if let Some((w, _)) = cube.sample(mip, c, false) {
                    worst_upright = worst_upright.max((got - w).abs().max_element());
                }
            }
            eprintln!(
                "{test}: {hand}-handed: {key} (mip {mip}) over {compared} pixels: worst |Babylon - mip| = {worst:.3e} ({:.2e} of the peak {peak:.1}); read in the glTF world {:.3}, upright {:.3} of the peak",
                worst / peak,
                worst_gltf_world / peak,
                worst_upright / peak
            );
            assert!(compared > 500, "{key}: {compared} pixels compared");
            assert!(
                excess <= 2e-5 * peak,
                "{hand}-handed {key}: beyond a half-float step by {excess:.3e} (peak {peak:.1})"
            );
            assert!(worst_gltf_world > 0.1 * peak && worst_upright > 0.1 * peak);
        };
        sphere("mirrorAsLoaded", 0, 2.2);
        sphere("mirror", 0, 1.0);
        sphere("rough", rough_mip, 1.0);
    }
}

/// Babylon.js's own picture of an equirect map (an `HDRCubeTexture` of the
/// same image: `PanoramaToCubeMapTools`, then harmonics from that cube)
/// lights a surface as the glTF light `shlight project MAP --format gltf`
/// writes does, in Babylon's default left-handed scene: the two
/// `sphericalPolynomial`s Babylon evaluates agree as functions, to 2% of
/// the peak (Babylon resamples the RGBE map into a 128-pixel cube), on a
/// smooth map with a broad lobe off the axes; the light mirrored into the
/// glTF world (the Sample Viewer's frame) does not agree.
#[test]
fn babylon_lights_with_the_gltf_light_as_with_its_own_picture_of_the_map() {
    let test = "web::babylon_lights_with_the_gltf_light_as_with_its_own_picture_of_the_map";
    let dir = temp_dir("web-babylon-hdr");
    let lobe = DVec3::new(0.3, 0.5, -0.8).normalize();
    crate::util::write_map(&dir.join("smooth.hdr"), 512, 256, |x, y| {
        let (u, v) = ((x as f64 + 0.5) / 512.0, (y as f64 + 0.5) / 256.0);
        let (t, p) = (
            std::f64::consts::PI * v,
            2.0 * std::f64::consts::PI * (u - 0.5),
        );
        let d = DVec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin());
        let value = 0.3 + 0.2 * d.y.max(0.0) + 4.0 * d.dot(lobe).max(0.0).powi(6);
        [value as f32, (0.8 * value) as f32, (0.6 * value) as f32]
    });
    shlight_ok(&[
        "project",
        s(&dir.join("smooth.hdr")),
        "--format",
        "gltf",
        "--specular-size",
        "16",
        "--specular-samples",
        "64",
        "-q",
        "-o",
        s(&dir.join("light.gltf")),
    ]);
    let page = "/tests/web/babylon.html?gltf=/data/light.gltf&hdr=/data/smooth.hdr";
    let Some(r) = run_babylon_page(test, &dir, page) else {
        return;
    };
    assert_eq!(r["babylon"], BABYLON_VERSION);
    let sh = |key: &str| {
        let rows: Vec<DVec3> = r[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| DVec3::from_slice(&floats(v)))
            .collect();
        assert_eq!(rows.len(), 9, "{key}");
        shlight_core::sh::ShCoeffs::from_vec(rows).unwrap()
    };
    // Babylon's SH3ylmBasisConstants are the real orthonormal basis with
    // the Condon-Shortley phase, shlight's own.
    let (gltf, own) = (sh("gltf"), sh("own"));
    let (mut worst, mut worst_mirrored, mut peak) = (0.0f64, 0.0f64, 0.0f64);
    let count = 2000;
    for i in 0..count {
        // A Fibonacci sphere.
        let z = 1.0 - (2.0 * i as f64 + 1.0) / count as f64;
        let phi = i as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let n = DVec3::new(
            (1.0 - z * z).sqrt() * phi.cos(),
            (1.0 - z * z).sqrt() * phi.sin(),
            z,
        );
        let want = own.eval(n);
        peak = peak.max(want.max_element());
        worst = worst.max((gltf.eval(n) - want).abs().max_element());
        let mirrored = DVec3::new(-n.x, n.y, n.z);
        worst_mirrored = worst_mirrored.max((gltf.eval(mirrored) - want).abs().max_element());
    }
    eprintln!(
        "{test}: Babylon's harmonics of the glTF light against those of its own HDRCubeTexture of the map: worst {:.2e} of the peak {peak:.4}; the light in the glTF world: {:.2e}",
        worst / peak,
        worst_mirrored / peak
    );
    assert!(worst < 0.02 * peak, "worst {worst:.3e}, peak {peak:.4}");
    assert!(worst_mirrored > 0.2 * peak, "{worst_mirrored:.3e}");
}

/// The Cornell box's volume, baked small, and its three.js grid documents
/// (`half`, `f32`); returns the `.shvol`.
fn cornell_volume(dir: &Path) -> PathBuf {
    let sky = dir.join("sky.json");
    let mut rows = vec![[0.0; 3]; 9];
    rows[0] = [2.0, 2.2, 2.6];
    rows[2] = [0.8, 0.9, 1.1];
    rows[3] = [0.3, -0.2, 0.1];
    rows[6] = [0.1, 0.05, 0.0];
    write_coefficient_rows(&sky, &rows, "radiance");
    let vol = dir.join("box.shvol");
    shlight_ok(&[
        "volume",
        "meshes/cornell_box.obj",
        "--env",
        s(&sky),
        "--resolution",
        "5x4x3",
        "--samples",
        "256",
        "--surface-samples",
        "64",
        "--bounces",
        "1",
        "-o",
        s(&vol),
    ]);
    shlight_ok(&[
        "convert",
        s(&vol),
        "--format",
        "threejs",
        "-o",
        s(&dir.join("grid-half.json")),
    ]);
    shlight_ok(&[
        "convert",
        s(&vol),
        "--format",
        "threejs",
        "--precision",
        "f32",
        "-o",
        s(&dir.join("grid-f32.json")),
    ]);
    vol
}

/// three.js's `LightProbeGridWebGL`, made by `loadLightProbeGrid` from
/// shlight's export of a baked Cornell-box volume, lights a tilted white
/// Lambert plane inside the box: every pixel equals `shlight sample
/// --lookup threejs` at that pixel's world position (read back from the
/// page) and the plane's normal, over pi. The `f32` atlas to within the
/// GPU's filtering; the `half` atlas within what rounding each of the
/// probes' 27 numbers to a half float can move the irradiance (bounded
/// here from the probes' largest coefficient). Fails on any slip in the
/// atlas layout (a probe in the wrong texel, a missing padding slice, a
/// coefficient in the wrong channel), the box, or the basis.
#[test]
fn threejs_light_probe_grid_lights_a_plane_as_sample_lookup_threejs_says() {
    let test = "web::threejs_light_probe_grid_lights_a_plane_as_sample_lookup_threejs_says";
    let dir = temp_dir("web-grid");
    let vol = cornell_volume(&dir);
    let file = shlight_format::ShvolFile::read(&vol).unwrap();
    // A half float rounds a number by at most 2^-11 of itself, so an
    // interpolated coefficient k moves by at most 2^-11 max |c_k| over the
    // probes, and the irradiance by that times |three.js's weight of k at
    // the normal|, summed over k.
    let nc = file.coeffs_per_channel();
    let mut cmax = [[0.0f64; 3]; 9];
    for probe in file.radiance.chunks_exact(3 * nc) {
        for (k, row) in probe.chunks_exact(3).take(9).enumerate() {
            for c in 0..3 {
                cmax[k][c] = cmax[k][c].max(f64::from(row[c]).abs());
            }
        }
    }
    let half_bound = |n: DVec3| -> f64 {
        let n = n.normalize();
        let (x, y, z) = (n.x, n.y, n.z);
        let w = [
            0.886227,
            1.023328 * y.abs(),
            1.023328 * z.abs(),
            1.023328 * x.abs(),
            0.858086 * (x * y).abs(),
            0.858086 * (y * z).abs(),
            (0.743125 * z * z - 0.247708).abs(),
            0.858086 * (x * z).abs(),
            0.429043 * (x * x - y * y).abs(),
        ];
        (0..3)
            .map(|c| (0..9).map(|k| w[k] * cmax[k][c]).sum::<f64>())
            .fold(0.0, f64::max)
            * 2f64.powi(-11)
            / std::f64::consts::PI
    };
    let tilt = DVec3::new(0.35, 1.0, -0.45);
    // The middle of the box, and a corner where the lookup clamps to the
    // outermost probes (the atlas's padding slices).
    let views = [([0.29, 0.26, 0.3], 0.16), ([0.07, 0.49, 0.5], 0.06)];
    let runs = views.iter().flat_map(|v| {
        [("grid-f32.json", 0.0), ("grid-half.json", half_bound(tilt))].map(move |d| (v, d))
    });
    for (&([cx, cy, cz], extent), (doc, bound)) in runs {
        let page = format!(
            "/tests/web/grid.html?grid=/data/{doc}&centre=[{cx},{cy},{cz}]&normal=[{},{},{}]&extent={extent}",
            tilt.x, tilt.y, tilt.z
        );
        let Some(r) = run_page(test, &dir, &page) else {
            return;
        };
        let (lit, position) = (pixels(&r, "lit"), pixels(&r, "position"));
        let normal = floats(&r["normal"]);
        let covered: Vec<usize> = (0..lit.len()).filter(|&i| position[i][3] == 1.0).collect();
        assert_eq!(covered.len(), lit.len(), "the plane fills the view");
        let points = dir.join("points.json");
        std::fs::write(
            &points,
            json!({
                "points": covered.iter().map(|&i| &position[i][..3]).collect::<Vec<_>>(),
                "normals": vec![&normal; covered.len()],
            })
            .to_string(),
        )
        .unwrap();
        let out = dir.join("sampled.json");
        shlight_ok(&[
            "sample",
            s(&vol),
            "--points",
            s(&points),
            "--lookup",
            "threejs",
            "-o",
            s(&out),
        ]);
        let sampled: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        let want: Vec<Vec<f64>> = sampled["irradiance"]
            .as_array()
            .unwrap()
            .iter()
            .map(floats)
            .collect();
        let mut worst = 0.0f64;
        let mut peak = 0.0f64;
        for (&i, w) in covered.iter().zip(&want) {
            for c in 0..3 {
                let w = w[c] / std::f64::consts::PI;
                worst = worst.max((lit[i][c] - w).abs());
                peak = peak.max(w);
            }
        }
        // The GPU's trilinear filter and f32 arithmetic, on top of the
        // atlas's own rounding.
        let allowed = bound + 2e-5 * peak;
        eprintln!(
            "{test}: {doc} around [{cx}, {cy}, {cz}]: {} pixels, worst |three.js - sample/pi| = {worst:.3e} ({:.2e} of the peak {peak:.4}; allowed {allowed:.3e}); loadLightProbeGrid {:.1} ms",
            covered.len(),
            worst / peak,
            r["loadMs"].as_f64().unwrap_or(f64::NAN)
        );
        assert!(peak > 0.05, "the plane is lit ({peak})");
        assert!(
            worst <= allowed,
            "{doc}: worst {worst:.3e} beyond {allowed:.3e}"
        );
    }
}

/// A PRT bake written as glTF (`shlight prt ... -o X.glb`) loads in
/// three.js's own `GLTFLoader` with its vertex colours intact: the loader's
/// `color` attribute holds the mesh's linear colours (the Cornell box's
/// material albedos, as shlight-mesh reads the OBJ) at every vertex, at
/// the positions shlight-mesh reads, and the material shows them. Fails
/// if the colours are dropped, re-encoded (sRGB), normalised to integers,
/// or moved to other vertices.
#[test]
fn a_prt_glb_loads_in_gltfloader_with_its_vertex_colours() {
    let test = "web::a_prt_glb_loads_in_gltfloader_with_its_vertex_colours";
    let dir = temp_dir("web-prt");
    shlight_ok(&[
        "prt",
        "meshes/cornell_box.obj",
        "--lmax",
        "2",
        "--samples",
        "64",
        "-q",
        "-o",
        s(&dir.join("box.glb")),
    ]);
    let Some(r) = run_page(test, &dir, "/tests/web/prt.html?glb=/data/box.glb") else {
        return;
    };
    let mesh = shlight_mesh::load(Path::new("meshes/cornell_box.obj")).unwrap();
    let colours = mesh.colors.as_ref().expect("the Cornell box has colours");
    let meshes = r["meshes"].as_array().unwrap();
    assert_eq!(meshes.len(), 1, "{r}");
    let m = &meshes[0];
    assert_eq!(m["vertexColors"], true, "the material uses the colours");
    assert_eq!(m["colorItemSize"], 3);
    let (got, pos) = (floats(&m["color"]), floats(&m["position"]));
    assert_eq!(got.len(), 3 * colours.len(), "one colour per vertex");
    let mut worst = 0.0f64;
    for (v, (c, p)) in colours.iter().zip(&mesh.positions).enumerate() {
        for a in 0..3 {
            assert_eq!(pos[3 * v + a], f64::from(p[a]), "vertex {v}'s position");
            worst = worst.max((got[3 * v + a] - f64::from(c[a])).abs());
        }
    }
    eprintln!(
        "{test}: {} vertices, worst colour difference {worst:e}",
        colours.len()
    );
    assert_eq!(worst, 0.0, "the colours arrive as written (f32)");
    // Not all one colour: red, green and white walls.
    assert!(colours.iter().any(|c| c.x > 2.0 * c.y) && colours.iter().any(|c| c.y > 2.0 * c.x));
}

/// A broken export gives the page an error naming the file and the
/// problem, not a black scene: a grid cut short (not JSON any more), a grid
/// whose atlas lost bytes but is still JSON, a missing file, a LightProbe
/// given to `loadLightProbeGrid` and a grid to `loadLightProbe`, a
/// LightProbe with 26 numbers, a LightProbe cut short. The whole grid and
/// LightProbe load (so the errors come from the damage).
#[test]
fn broken_exports_give_the_page_a_clear_error() {
    let test = "web::broken_exports_give_the_page_a_clear_error";
    let dir = temp_dir("web-broken");
    let vol = dir.join("box.shvol");
    shlight_ok(&[
        "volume",
        "meshes/cornell_box.obj",
        "--env",
        "envmaps/sky.exr",
        "--resolution",
        "3x2x2",
        "--samples",
        "64",
        "--surface-samples",
        "32",
        "--bounces",
        "0",
        "-q",
        "-o",
        s(&vol),
    ]);
    shlight_ok(&[
        "convert",
        s(&vol),
        "--format",
        "threejs",
        "-o",
        s(&dir.join("grid.json")),
    ]);
    let coeffs = dir.join("sky.json");
    shlight_ok(&[
        "project",
        "envmaps/sky.exr",
        "--lmax",
        "2",
        "-q",
        "-o",
        s(&coeffs),
    ]);
    shlight_ok(&[
        "convert",
        s(&coeffs),
        "--format",
        "threejs",
        "-o",
        s(&dir.join("probe.json")),
    ]);
    let grid = std::fs::read_to_string(dir.join("grid.json")).unwrap();
    let probe = std::fs::read_to_string(dir.join("probe.json")).unwrap();
    std::fs::write(dir.join("cut.json"), &grid[..grid.len() / 2]).unwrap();
    let mut doc: Value = serde_json::from_str(&grid).unwrap();
    let data = doc["atlas"]["data"].as_str().unwrap().to_string();
    doc["atlas"]["data"] = json!(data[..data.len() - 400]);
    std::fs::write(dir.join("short-atlas.json"), doc.to_string()).unwrap();
    let mut p: Value = serde_json::from_str(&probe).unwrap();
    p["object"]["sh"].as_array_mut().unwrap().pop();
    std::fs::write(dir.join("probe-26.json"), p.to_string()).unwrap();
    std::fs::write(dir.join("probe-cut.json"), &probe[..probe.len() - 30]).unwrap();
    let page = "/tests/web/broken.html?grid=/data/grid.json&grid=/data/cut.json\
        &grid=/data/short-atlas.json&grid=/data/missing.json&grid=/data/probe.json\
        &probe=/data/probe.json&probe=/data/grid.json&probe=/data/probe-26.json\
        &probe=/data/probe-cut.json";
    let Some(r) = run_page(test, &dir, page) else {
        return;
    };
    let results = r["results"].as_array().unwrap();
    let want: [(&str, Option<&str>); 9] = [
        ("/data/grid.json", None),
        ("/data/cut.json", Some("not a JSON document")),
        (
            "/data/short-atlas.json",
            Some("the file is truncated or damaged"),
        ),
        ("/data/missing.json", Some("HTTP 404")),
        (
            "/data/probe.json",
            Some("is a LightProbe (load it with loadLightProbe)"),
        ),
        ("/data/probe.json", None),
        (
            "/data/grid.json",
            Some("is a volume (load it with loadLightProbeGrid)"),
        ),
        ("/data/probe-26.json", Some("not 27 finite numbers")),
        ("/data/probe-cut.json", Some("not a JSON document")),
    ];
    assert_eq!(results.len(), want.len(), "{r}");
    for (got, (url, problem)) in results.iter().zip(want) {
        assert_eq!(got["url"], url);
        match problem {
            None => assert_eq!(got["loaded"], true, "{got}"),
            Some(p) => {
                assert_eq!(got["loaded"], false, "{got}");
                assert_eq!(got["name"], "ShlightLoadError", "{got}");
                let m = got["message"].as_str().unwrap();
                assert!(m.starts_with(url) && m.contains(p), "{url}: {m}");
                eprintln!("{test}: {m}");
            }
        }
    }
}

/// `shlight volume --format threejs` and `shlight convert VOLUME.shvol
/// --format threejs` write the same document; its atlas holds, at the
/// texel three.js's `LightProbeGridWebGL` reads (slice `t (nz + 2) + 1 +
/// z`, number `3 i + c` of the probe at `4 t + channel`; the padding slices
/// copies of the edge layers), the probe's coefficient `i` with odd `m`
/// negated (three.js's basis has no Condon-Shortley phase), from the
/// dilated probes (three.js knows no validity), clipped from lmax 3 to 2
/// with a note on stderr and in the file; `--precision half` holds those
/// numbers rounded to half floats. Bad requests are errors naming the file.
#[test]
fn threejs_volume_export_holds_the_probes_where_threejs_reads_them() {
    use shlight_format::threejs_volume::Precision;
    let dir = temp_dir("web-export");
    let (vol, direct) = (dir.join("box.shvol"), dir.join("direct.json"));
    let bake = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "volume",
            "meshes/cornell_box.obj",
            "--env",
            "envmaps/sky.exr",
            "--resolution",
            "4x3x4",
            "--samples",
            "64",
            "--surface-samples",
            "32",
            "--bounces",
            "0",
            "--no-relocate",
            "--lmax",
            "3",
            "-o",
            s(out),
        ];
        args.extend(extra);
        String::from_utf8_lossy(&shlight_ok(&args).stderr).into_owned()
    };
    bake(&vol, &[]);
    let stderr = bake(&direct, &["--format", "threejs", "--precision", "f32"]);
    assert!(stderr.contains("lmax 3 clipped to 2"), "{stderr}");
    assert!(stderr.contains("3 invalid probes"), "{stderr}");
    let converted = dir.join("converted.json");
    let o = shlight_ok(&[
        "convert",
        s(&vol),
        "--format",
        "threejs",
        "--precision",
        "f32",
        "-o",
        s(&converted),
    ]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("lmax 3 clipped to 2"));
    let text = std::fs::read_to_string(&converted).unwrap();
    assert_eq!(text, std::fs::read_to_string(&direct).unwrap());
    let doc: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        (doc["lmax"].as_u64(), doc["sourceLmax"].as_u64()),
        (Some(2), Some(3))
    );
    assert!(
        doc["notes"][0].as_str().unwrap().contains("clipped"),
        "{}",
        doc["notes"]
    );

    let file = shlight_format::ShvolFile::read(&vol).unwrap();
    assert_eq!(doc["resolution"], json!(file.resolution));
    assert_eq!(doc["boundingBox"]["min"], json!(file.bounds.0));
    assert_eq!(doc["boundingBox"]["max"], json!(file.bounds.1));
    assert_eq!(file.valid.iter().filter(|v| !**v).count(), 3);
    let radiance = shlight_baked::dilate(&file.view());
    let (size, texels) = read_threejs_grid(&text);
    let [nx, ny, nz] = file.resolution;
    assert_eq!(size, [nx, ny, 7 * (nz + 2)]);
    for s in 0..size[2] {
        let t = s / (nz + 2);
        let z = (s % (nz + 2)).clamp(1, nz) - 1;
        for y in 0..ny {
            for x in 0..nx {
                let k = x + nx * (y + ny * z);
                let texel = texels[x + nx * (y + ny * s)];
                for (ch, got) in texel.into_iter().enumerate() {
                    let j = 4 * t + ch;
                    let want = if j < 27 {
                        let (i, c) = (j / 3, j % 3);
                        let sign = if [1, 3, 5, 7].contains(&i) { -1.0 } else { 1.0 };
                        sign * radiance[k * 16 * 3 + 3 * i + c]
                    } else {
                        0.0
                    };
                    assert_eq!(got, want, "slice {s} ({x}, {y}) {ch}");
                }
            }
        }
    }
    // Half floats: the same numbers rounded.
    let half = dir.join("half.json");
    shlight_ok(&["convert", s(&vol), "--format", "threejs", "-o", s(&half)]);
    let half_doc = std::fs::read_to_string(&half).unwrap();
    assert!(half_doc.contains("\"HalfFloatType\""));
    let (half_size, half_texels) = read_threejs_grid(&half_doc);
    assert_eq!(half_size, size);
    for (a, b) in half_texels.iter().flatten().zip(texels.iter().flatten()) {
        assert_eq!(*a, half::f16::from_f32(*b).to_f32());
    }
    assert_eq!(Precision::default(), Precision::Half);

    // Bad requests.
    let out = dir.join("x.json");
    let e = shlight_err(&["convert", s(&vol), "--format", "gltf", "-o", s(&out)]);
    assert!(
        e.contains("box.shvol") && e.contains("--format threejs"),
        "{e}"
    );
    let e = shlight_err(&["convert", s(&vol), "-o", s(&out)]);
    assert!(e.contains("needs --format threejs"), "{e}");
    let cut = dir.join("cut.shvol");
    let bytes = std::fs::read(&vol).unwrap();
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let e = shlight_err(&["convert", s(&cut), "--format", "threejs", "-o", s(&out)]);
    assert!(e.contains("cut.shvol"), "{e}");
    assert!(!out.exists(), "nothing written");
}

/// The bundled examples of `web/` are what the README's commands write
/// today (so the viewer's test below shows the current export).
#[test]
fn the_bundled_web_examples_are_todays_exports() {
    let dir = temp_dir("web-examples");
    let (grid, probe) = (dir.join("cornell-grid.json"), dir.join("park-probe.json"));
    shlight_ok(&[
        "volume",
        "meshes/cornell_box.obj",
        "--env",
        "envmaps/park.exr",
        "--resolution",
        "4x4x4",
        "--samples",
        "256",
        "--format",
        "threejs",
        "-q",
        "-o",
        s(&grid),
    ]);
    shlight_ok(&[
        "project",
        "envmaps/park.exr",
        "--lmax",
        "2",
        "--format",
        "threejs",
        "-q",
        "-o",
        s(&probe),
    ]);
    for (made, bundled) in [
        (&grid, "web/examples/cornell-grid.json"),
        (&probe, "web/examples/park-probe.json"),
    ] {
        assert!(
            std::fs::read_to_string(made).unwrap() == std::fs::read_to_string(bundled).unwrap(),
            "{bundled} is not what the README's command writes now: regenerate it"
        );
    }
}

/// `web/index.html` opens each bundled example (`?src=`), draws it
/// (probe spheres in the volume's box, or a sphere for the LightProbe) and
/// reports no error or warning on the console; the drawn pixels are not
/// the background alone and not black. A broken file shows its error.
#[test]
fn the_viewer_page_draws_the_bundled_examples_without_console_errors() {
    let test = "web::the_viewer_page_draws_the_bundled_examples_without_console_errors";
    let dir = temp_dir("web-viewer");
    std::fs::write(
        dir.join("cut.json"),
        "{\"metadata\": {\"type\": \"shlight.Light",
    )
    .unwrap();
    for (src, kind, probes) in [
        ("examples/cornell-grid.json", "grid", 64),
        ("examples/park-probe.json", "probe", 0),
        ("/data/cut.json", "", 0),
    ] {
        let page = format!("/web/index.html?src={src}&report=/result");
        let Some(r) = run_page(test, &dir, &page) else {
            return;
        };
        eprintln!(
            "{test}: {src}: drawn {:.3} of the pixels, brightest {}, status {}",
            r["drawnShare"], r["brightest"], r["status"]
        );
        if kind.is_empty() {
            assert_eq!(r["kind"], Value::Null, "{r}");
            assert!(
                r["status"]
                    .as_str()
                    .unwrap()
                    .contains("/data/cut.json: not a JSON document"),
                "{r}"
            );
            continue;
        }
        assert_eq!(r["errors"], json!([]), "{src}: {r}");
        assert_eq!(r["kind"], kind, "{r}");
        assert_eq!(r["probes"], probes, "{r}");
        assert!(
            r["drawnShare"].as_f64().unwrap() > 0.01,
            "{src}: nothing drawn: {r}"
        );
        assert!(
            r["brightest"].as_u64().unwrap() > 100,
            "{src}: drawn black: {r}"
        );
    }
}

/// The atlas of a three.js grid document, read here as docs/shvol.md
/// states it (not by shlight's code): `[width, height, depth]` and the
/// RGBA texels as `f32` (half floats widened exactly).
fn read_threejs_grid(text: &str) -> ([usize; 3], Vec<[f32; 4]>) {
    use base64::Engine as _;
    let doc: Value = serde_json::from_str(text).unwrap();
    assert_eq!(doc["metadata"]["type"], "shlight.LightProbeGrid");
    let atlas = &doc["atlas"];
    let size = ["width", "height", "depth"].map(|k| atlas[k].as_u64().unwrap() as usize);
    assert_eq!(
        (atlas["format"].as_str(), atlas["encoding"].as_str()),
        (Some("RGBAFormat"), Some("base64"))
    );
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(atlas["data"].as_str().unwrap())
        .unwrap();
    assert_eq!(atlas["byteLength"].as_u64(), Some(bytes.len() as u64));
    let values: Vec<f32> = match atlas["type"].as_str().unwrap() {
        "HalfFloatType" => bytes
            .chunks_exact(2)
            .map(|b| half::f16::from_le_bytes([b[0], b[1]]).to_f32())
            .collect(),
        "FloatType" => bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect(),
        t => panic!("atlas type {t}"),
    };
    assert_eq!(values.len(), 4 * size.iter().product::<usize>());
    (
        size,
        values
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect(),
    )
}

/// `loadLightmappedScene` in three.js r187 lights a floor `shlight
/// lightmap --for threejs` baked under a lamp as `shlight sample` reads the
/// file: each pixel of the white-lit floor is `albedo / pi E` with `E` the
/// sampled irradiance at the pixel's point, for the `irradiance` basis and
/// for `sh-l1` reconstructed for the normal of a floor turned 35 degrees
/// (so that every L1 page counts). Fails if a page is not found, read in
/// the wrong channel or units, or an L1 axis is swapped.
#[test]
fn threejs_renders_the_lightmapped_scene_as_sample_reads_it() {
    let test = "web::threejs_renders_the_lightmapped_scene_as_sample_reads_it";
    let dir = temp_dir("web-lightmap");
    let (s35, c35) = (17.5f32.to_radians().sin(), 17.5f32.to_radians().cos());
    // Turned about (1, 0, 1)/sqrt 2 by 35 degrees: the normal leaves y
    // towards both x and z.
    let axis = glam::Vec3::new(1.0, 0.0, 1.0).normalize() * s35;
    let rotation = [axis.x, axis.y, axis.z, c35];
    let normal = glam::Quat::from_array(rotation) * glam::Vec3::Y;
    let scene = dir.join("floor.glb");
    std::fs::write(
        &scene,
        crate::lightmap::turned_floor_glb(683.0 * 6.0, [0.3, 1.5, -0.2], true, rotation),
    )
    .unwrap();
    let env = crate::lightmap::black_sky(&dir);
    for basis in ["irradiance", "sh-l1"] {
        let lit_glb = dir.join(format!("lit-{basis}.glb"));
        crate::lightmap::bake_quick(&scene, &env, "threejs", basis, 64, &["-o", s(&lit_glb)]);
        let page = format!(
            "/tests/web/lightmap.html?scene=/data/lit-{basis}.glb&centre=[0,0,0]&normal=[{},{},{}]&extent=0.6",
            normal.x, normal.y, normal.z
        );
        let Some(r) = run_page(test, &dir, &page) else {
            return;
        };
        assert_eq!(r["basis"], basis);
        assert_eq!(r["hasLightMap"], true);
        assert_eq!(r["lightMapChannel"], 1);
        assert_eq!(r["lights"], 1, "the lamp is taken out of the page's scene");
        let albedo = floats(&r["albedo"]);
        let (lit, position) = (pixels(&r, "lit"), pixels(&r, "position"));
        let covered: Vec<usize> = (0..lit.len()).filter(|&i| position[i][3] == 1.0).collect();
        assert_eq!(covered.len(), lit.len(), "the floor fills the view");
        let points = dir.join("points.json");
        std::fs::write(
            &points,
            json!({
                "points": covered.iter().map(|&i| &position[i][..3]).collect::<Vec<_>>(),
                "normals": vec![normal.to_array(); covered.len()],
            })
            .to_string(),
        )
        .unwrap();
        let out = dir.join("sampled.json");
        shlight_ok(&["sample", s(&lit_glb), "--points", s(&points), "-o", s(&out)]);
        let sampled: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        let want: Vec<Vec<f64>> = sampled["irradiance"]
            .as_array()
            .unwrap()
            .iter()
            .map(floats)
            .collect();
        let (mut worst, mut peak) = (0.0f64, 0.0f64);
        for (&i, w) in covered.iter().zip(&want) {
            for c in 0..3 {
                let w = albedo[c] * w[c] / std::f64::consts::PI;
                worst = worst.max((lit[i][c] - w).abs());
                peak = peak.max(w);
            }
        }
        eprintln!(
            "{test}: {basis}: {} pixels, worst |three.js - albedo/pi sample| = {worst:.3e} ({:.2e} of the peak {peak:.4}); loadLightmappedScene {:.1} ms",
            covered.len(),
            worst / peak,
            r["loadMs"].as_f64().unwrap_or(f64::NAN)
        );
        assert!(peak > 0.1, "the floor is lit ({peak})");
        // The GPU's filter weights and f32 arithmetic against sample's (a
        // few 1e-7 of the peak on SwiftShader).
        assert!(
            worst <= 1e-4 * peak,
            "{basis}: worst {worst:.3e} of peak {peak:.4}"
        );
    }
}

//! Each engine export lines up with that engine's own picture of the map:
//! a map with one bright texel is exported, the engine's own irradiance
//! formula is evaluated on the export, and its peak must lie where the
//! engine's own equirect mapping (written out here from the engine's
//! source) puts that texel. Filament is also compared with `cmgen` itself.

use std::f64::consts::PI;
use std::path::Path;
use std::process::Command;

use glam::DVec3;
use shlight_core::sh::fibonacci_sphere;

use crate::export::{babylon_lambertian_radiance, filament_irradiance_sh, three_get_irradiance_at};
use crate::util::{s, shlight_ok, skip, temp_dir, write_map};

/// Map size of the spot maps (2:1).
const W: usize = 256;
const H: usize = 128;
/// Texels that carry the spot, one at a time: around the horizon, near the
/// top, below the horizon, on both sides of the seam.
const SPOTS: [(usize, usize); 5] = [(64, 40), (200, 90), (128, 12), (20, 70), (236, 55)];
/// Largest angle between the export's irradiance peak and the engine's
/// direction of the texel: the peak search's grid spacing (about 0.9
/// degrees) plus, for cmgen's formula, half a texel of its `(W-1)` scaling.
const PEAK_TOLERANCE_DEG: f64 = 2.0;

type Dir = [f64; 3];

fn normalize(v: Dir) -> Dir {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

fn angle_deg(a: Dir, b: Dir) -> f64 {
    let (a, b) = (normalize(a), normalize(b));
    (a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// The direction (on a Fibonacci set of 50,000 points) where `f` is largest.
fn peak(f: impl Fn(Dir) -> f64) -> Dir {
    fibonacci_sphere(50_000)
        .into_iter()
        .map(|d| d.to_array())
        .max_by(|a, b| f(*a).total_cmp(&f(*b)))
        .unwrap()
}

/// The texel centre `(u, v)`, from the top-left corner.
fn uv(x: usize, y: usize) -> (f64, f64) {
    ((x as f64 + 0.5) / W as f64, (y as f64 + 0.5) / H as f64)
}

/// A black map but for one texel.
fn write_spot(path: &Path, (sx, sy): (usize, usize)) {
    write_map(path, W, H, |x, y| {
        if (x, y) == (sx, sy) {
            [500.0, 400.0, 300.0]
        } else {
            [0.0; 3]
        }
    });
}

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .flat_map(|x| match x.as_array() {
            Some(a) => a.iter().map(|y| y.as_f64().unwrap()).collect(),
            None => vec![x.as_f64().unwrap()],
        })
        .collect()
}

/// Exports the spot map at `(x, y)` in `format` and returns the file's text.
fn export(dir: &Path, spot: (usize, usize), format: &str, ext: &str) -> String {
    let map = dir.join(format!("spot-{}-{}.exr", spot.0, spot.1));
    write_spot(&map, spot);
    let out = dir.join(format!("{format}-{}-{}.{ext}", spot.0, spot.1));
    shlight_ok(&[
        "project",
        s(&map),
        "--format",
        format,
        "-o",
        s(&out),
        "-q",
        "--specular-size",
        "4",
        "--specular-samples",
        "16",
    ]);
    std::fs::read_to_string(out).unwrap()
}

/// Exports the map of each of [`SPOTS`] in `format`, reads the file with
/// `parse`, and asserts that the engine's own irradiance (`irradiance`)
/// peaks where the engine's own mapping (`direction`) puts the texel.
fn assert_peaks_at_the_engines_texels<T>(
    format: &str,
    ext: &str,
    engine: &str,
    parse: impl Fn(&str) -> T,
    irradiance: impl Fn(&T, Dir) -> f64,
    direction: fn(usize, usize) -> Dir,
) {
    let dir = temp_dir(&format!("engine_{format}"));
    for spot in SPOTS {
        let file = parse(&export(&dir, spot, format, ext));
        let got = peak(|n| irradiance(&file, n));
        let want = direction(spot.0, spot.1);
        let angle = angle_deg(got, want);
        assert!(
            angle < PEAK_TOLERANCE_DEG,
            "spot {spot:?}: peak {got:?}, {engine} puts the texel at {want:?} ({angle:.2} deg)"
        );
    }
}

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap()
}

/// The nine `(r, g, b);` rows of an sh.txt (shlight's or cmgen's).
fn sh_txt_rows(text: &str) -> Vec<DVec3> {
    text.lines()
        .filter_map(|l| {
            let inner = l.trim().strip_prefix('(')?.split(')').next()?;
            let v: Vec<f64> = inner
                .split(',')
                .map(|t| t.trim().parse().unwrap())
                .collect();
            Some(DVec3::new(v[0], v[1], v[2]))
        })
        .collect()
}

/// The red channel of Filament's shader on sh.txt rows, at `n`.
fn filament_irradiance(sh: &[DVec3], n: Dir) -> f64 {
    filament_irradiance_sh(sh, DVec3::from(n)).x
}

/// Where cmgen shows the texel `(x, y)` in Filament's world:
/// `equirectangularToCubemap`'s `toRectilinear` (longitude
/// `atan2(s.x, s.z)`, latitude `asin(s.y)`, scaled by `W-1`, `H-1`),
/// then its default `mirrorCubemap` (`sampleAt(-N.x, N.y, N.z)`).
fn cmgen_direction(x: usize, y: usize) -> Dir {
    let a = PI * (2.0 * (x as f64 + 0.5) / (W - 1) as f64 - 1.0);
    let b = PI / 2.0 * (1.0 - 2.0 * (y as f64 + 0.5) / (H - 1) as f64);
    [-a.sin() * b.cos(), b.sin(), a.cos() * b.cos()]
}

#[test]
fn filament_export_peaks_where_cmgen_puts_the_texel() {
    assert_peaks_at_the_engines_texels(
        "filament",
        "txt",
        "cmgen",
        sh_txt_rows,
        |sh, n| filament_irradiance(sh, n),
        cmgen_direction,
    );
}

/// Where three.js shows the texel `(x, y)`: the inverse of `equirectUv`
/// (`u = atan(dir.z, dir.x) / 2pi + 0.5`, `v = asin(dir.y) / pi + 0.5`),
/// `v` counted from the bottom (equirect textures are uploaded with the
/// image's top row at `v = 1`).
fn threejs_direction(x: usize, y: usize) -> Dir {
    let (u, v_top) = uv(x, y);
    let v = 1.0 - v_top;
    let azimuth = (u - 0.5) * 2.0 * PI;
    let dy = ((v - 0.5) * PI).sin();
    let r = (1.0 - dy * dy).sqrt();
    [r * azimuth.cos(), dy, r * azimuth.sin()]
}

#[test]
fn threejs_export_peaks_where_equirect_uv_puts_the_texel() {
    assert_peaks_at_the_engines_texels(
        "threejs",
        "json",
        "three.js",
        |text| {
            let sh = numbers(&json(text)["object"]["sh"]);
            sh.chunks(3).map(DVec3::from_slice).collect::<Vec<_>>()
        },
        |sh, n| three_get_irradiance_at(sh, DVec3::from(n)).x,
        threejs_direction,
    );
}

/// Unity's `ShadeSH9` (`UnityCG.cginc`: `SHEvalLinearL0L1` +
/// `SHEvalLinearL2`) on the packed `unity_SH*` vectors, red channel.
fn unity_shade_sh9(v: &serde_json::Value, n: Dir) -> f64 {
    let [x, y, z] = n;
    let a = numbers(&v["unity_SHAr"]);
    let b = numbers(&v["unity_SHBr"]);
    let c = numbers(&v["unity_SHC"]);
    let l0l1 = a[0] * x + a[1] * y + a[2] * z + a[3];
    let vb = [x * y, y * z, z * z, z * x];
    let l2 = (0..4).map(|i| b[i] * vb[i]).sum::<f64>() + c[0] * (x * x - y * y);
    l0l1 + l2
}

/// Where Unity's `Skybox/Panoramic` shows the texel `(x, y)`, in Unity's
/// (left-handed) world: the inverse of `ToRadialCoords`,
/// `(u, v) = (0.5, 1) - (atan2(z, x) / 2pi, acos(y) / pi)`, `v` from the
/// bottom.
fn unity_direction(x: usize, y: usize) -> Dir {
    let (u, v_top) = uv(x, y);
    let v = 1.0 - v_top;
    let longitude = (0.5 - u) * 2.0 * PI;
    let latitude = (1.0 - v) * PI;
    [
        latitude.sin() * longitude.cos(),
        latitude.cos(),
        latitude.sin() * longitude.sin(),
    ]
}

#[test]
fn unity_export_peaks_where_the_panoramic_skybox_puts_the_texel() {
    assert_peaks_at_the_engines_texels(
        "unity",
        "json",
        "Unity",
        json,
        unity_shade_sh9,
        unity_direction,
    );
}

/// Where Babylon.js, reading the glTF light in its default left-handed
/// scene, shows the texel `(x, y)` in its world: where the Khronos glTF
/// Sample Viewer puts it around a glTF asset, carried through the root node
/// Babylon's glTF loader adds (glTF `(x, y, z)` is Babylon `(-x, y, z)`).
/// The Sample Viewer: `panorama_to_cubemap`'s `dirToUV`
/// (`u = 0.5 + 0.5 atan(g.z, g.x) / pi`, `v = 1 - acos(g.y) / pi` with the
/// image's top row at `v = 0` after its `uvToXYZ` face flips) gives the
/// cube-lookup direction `g`; the viewer looks world direction `w` up at
/// `g = rotateY(environmentRotation = 90 deg) w = (w.z, w.y, -w.x)`, so the
/// texel is at glTF `w = (-g.z, g.y, g.x)` and at Babylon `(g.z, g.y, g.x)`.
fn babylon_direction(x: usize, y: usize) -> Dir {
    let (u, v_top) = uv(x, y);
    let azimuth = (u - 0.5) * 2.0 * PI;
    let polar = v_top * PI;
    let g = [
        polar.sin() * azimuth.cos(),
        polar.cos(),
        polar.sin() * azimuth.sin(),
    ];
    [g[2], g[1], g[0]]
}

#[test]
fn gltf_export_peaks_where_babylon_shows_the_sample_viewers_texel() {
    assert_peaks_at_the_engines_texels(
        "gltf",
        "gltf",
        "Babylon.js",
        |text| {
            let v = json(text);
            let scene_light = v["scenes"][0]["extensions"]["EXT_lights_image_based"]["light"]
                .as_u64()
                .unwrap() as usize;
            v["extensions"]["EXT_lights_image_based"]["lights"][scene_light].clone()
        },
        |light, n| babylon_lambertian_radiance(light, DVec3::from(n)).x,
        babylon_direction,
    );
}

/// Runs `cmgen --sh=3 --sh-shader --sh-window=no MAP` and returns the nine
/// rows it prints, or `None` (with a SKIPPED line, a failure under
/// `SHLIGHT_REQUIRE_ALL=1`) without cmgen.
fn cmgen_sh(map: &Path, test: &str) -> Option<Vec<DVec3>> {
    let out = match Command::new("cmgen")
        .args(["--sh=3", "--sh-shader", "--sh-window=no"])
        .arg(map)
        .output()
    {
        Ok(out) => out,
        Err(e) => {
            skip(
                test,
                &format!("cmgen not found ({e}); apt install libfilament-tools"),
            );
            return None;
        }
    };
    assert!(
        out.status.success(),
        "cmgen failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows = sh_txt_rows(&String::from_utf8_lossy(&out.stdout));
    assert_eq!(rows.len(), 9, "{}", String::from_utf8_lossy(&out.stdout));
    Some(rows)
}

/// Worst difference of two functions over a Fibonacci set, relative to the
/// largest value of `b`.
fn max_relative_difference(a: impl Fn(Dir) -> f64, b: impl Fn(Dir) -> f64) -> f64 {
    let dirs: Vec<Dir> = fibonacci_sphere(2000)
        .into_iter()
        .map(|d| d.to_array())
        .collect();
    let peak = dirs.iter().map(|d| b(*d).abs()).fold(0.0, f64::max);
    dirs.iter()
        .map(|d| (a(*d) - b(*d)).abs() / peak)
        .fold(0.0, f64::max)
}

/// What cmgen itself computes from the same image (read from a Radiance
/// `.hdr`, which cmgen decodes): the peak of a spot and the whole
/// irradiance of a smooth map agree with shlight's Filament export.
#[test]
fn filament_export_agrees_with_cmgen_itself() {
    const TEST: &str = "engine_frames::filament_export_agrees_with_cmgen_itself";
    /// cmgen resamples the map to a cube map with nearest texels and
    /// `(W-1)` scaling; on a smooth map its irradiance and shlight's differ
    /// by about 2% of the peak (measured 1.3%).
    const SMOOTH_TOLERANCE: f64 = 0.05;
    let dir = temp_dir("engine_cmgen");
    let spot = (64, 40);
    let spot_hdr = dir.join("spot.hdr");
    // A 3x3 block, so cmgen's cube resampling cannot miss it.
    write_map(&spot_hdr, W, H, |x, y| {
        if x.abs_diff(spot.0) <= 1 && y.abs_diff(spot.1) <= 1 {
            [50.0; 3]
        } else {
            [0.0; 3]
        }
    });
    let Some(theirs) = cmgen_sh(&spot_hdr, TEST) else {
        return;
    };
    let ours_file = dir.join("spot.txt");
    shlight_ok(&[
        "project",
        s(&spot_hdr),
        "--format",
        "filament",
        "-o",
        s(&ours_file),
        "-q",
    ]);
    let ours = sh_txt_rows(&std::fs::read_to_string(&ours_file).unwrap());
    let (a, b) = (
        peak(|n| filament_irradiance(&theirs, n)),
        peak(|n| filament_irradiance(&ours, n)),
    );
    let angle = angle_deg(a, b);
    assert!(
        angle < 2.5,
        "cmgen's peak {a:?}, shlight's {b:?} ({angle:.2} deg apart)"
    );

    // A smooth map: sky, ground and a broad lobe off the axes.
    let lobe = normalize([0.3, 0.5, -0.8]);
    let smooth_hdr = dir.join("smooth.hdr");
    write_map(&smooth_hdr, 512, 256, |x, y| {
        let u = (x as f64 + 0.5) / 512.0;
        let v = (y as f64 + 0.5) / 256.0;
        let (t, p) = (PI * v, 2.0 * PI * (u - 0.5));
        let d = [t.sin() * p.cos(), t.cos(), t.sin() * p.sin()];
        let c = (d[0] * lobe[0] + d[1] * lobe[1] + d[2] * lobe[2]).max(0.0);
        let value = 0.3 + 0.2 * d[1].max(0.0) + 4.0 * c.powi(6);
        [value as f32, (0.8 * value) as f32, (0.6 * value) as f32]
    });
    let theirs = cmgen_sh(&smooth_hdr, TEST).unwrap();
    shlight_ok(&[
        "project",
        s(&smooth_hdr),
        "--format",
        "filament",
        "-o",
        s(&ours_file),
        "-q",
    ]);
    let ours = sh_txt_rows(&std::fs::read_to_string(&ours_file).unwrap());
    let diff = max_relative_difference(
        |n| filament_irradiance(&theirs, n),
        |n| filament_irradiance(&ours, n),
    );
    assert!(
        diff < SMOOTH_TOLERANCE,
        "cmgen and shlight's Filament irradiance differ by {:.1}% of the peak",
        100.0 * diff
    );
    // Without the quarter turn they would not agree: the test can tell.
    let turned = max_relative_difference(
        |n| filament_irradiance(&theirs, [n[2], n[1], -n[0]]),
        |n| filament_irradiance(&ours, n),
    );
    assert!(turned > 4.0 * SMOOTH_TOLERANCE, "{turned}");
}

//! A glTF scene's static term on the GPU: `render-mesh --prt` and `view
//! --prt` draw a format version 3 file as `T . L + S` (docs/shprt.md,
//! "glTF scenes"), `S` the exit radiance its lamps leave at each vertex,
//! interpolated across the triangles as the transfer is.
//!
//! The scene is built here: a 4 m floor of 32 x 32 quads under a coloured
//! point lamp, open to the sky. Each pixel's surface point is found by a
//! ray from the camera (a pinhole of the documented look-at camera) meeting
//! the floor, and the pixel is held to the CPU's values there: `shlight
//! sample`'s exit radiance at the triangle's corners, interpolated by the
//! point's barycentric coordinates, and, for the static term, the closed
//! form `rho/pi I cos / d^2` itself (within the linear interpolation's
//! error on this grid).

use std::path::Path;

use glam::{DVec2, DVec3};
use shlight_format::ShprtFile;
use shlight_io::{Image, ReadOptions, read_image};

use crate::gpu::{gpu_and_xvfb, view_against_render_mesh};
use crate::util::{glb, gpu_context, read_json, s, shlight_ok, temp_dir, write_radiance_rows};

/// Quads along each side of the floor.
const CELLS: usize = 32;
/// The floor's half width (m): it covers x, z in [-2, 2] at y = 0.
const HALF: f64 = 2.0;
/// The floor's albedo (its material's base colour).
const ALBEDO: [f64; 3] = [0.6, 0.5, 0.4];
/// The lamp: where it is, its colour and its intensity (cd, divided by 683
/// as `--light-units blender` reads it).
const LAMP: [f64; 3] = [0.3, 1.2, -0.2];
const LAMP_COLOR: [f64; 3] = [1.0, 0.8, 0.6];
const LAMP_CD: f64 = 683.0 * 4.0;

/// The camera of every render: eye, target, vertical field of view
/// (degrees) and size.
const EYE: [f64; 3] = [0.8, 2.0, 1.6];
const TARGET: [f64; 3] = [0.0, 0.0, -0.3];
const FOV: f64 = 50.0;
const SIZE: (usize, usize) = (96, 72);

/// A GLB of the floor (`CELLS` x `CELLS` quads, two triangles each, facing
/// +Y, single-sided, of base colour [`ALBEDO`]) and the point lamp.
fn floor_glb() -> Vec<u8> {
    let n = CELLS + 1;
    let mut bin = Vec::new();
    let coord = |i: usize| (-HALF + 2.0 * HALF * i as f64 / CELLS as f64) as f32;
    for j in 0..n {
        for i in 0..n {
            [coord(i), 0.0, coord(j)]
                .iter()
                .for_each(|x| bin.extend(x.to_le_bytes()));
        }
    }
    for _ in 0..n * n {
        [0.0f32, 1.0, 0.0]
            .iter()
            .for_each(|x| bin.extend(x.to_le_bytes()));
    }
    let mut indices = Vec::new();
    for j in 0..CELLS {
        for i in 0..CELLS {
            let a = (j * n + i) as u16;
            let (b, c, d) = (a + 1, a + n as u16 + 1, a + n as u16);
            // (b - a) x (c - a) along +Y: counter-clockwise seen from above.
            indices.extend([a, d, c, a, c, b]);
        }
    }
    indices.iter().for_each(|i| bin.extend(i.to_le_bytes()));
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let vertex_bytes = 12 * n * n;
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "name": "lamp", "intensity": LAMP_CD, "color": LAMP_COLOR}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"translation": LAMP, "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "materials": [{"pbrMetallicRoughness": {
            "baseColorFactor": [ALBEDO[0], ALBEDO[1], ALBEDO[2], 1.0],
            "metallicFactor": 0.0
        }}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}
        ]}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": vertex_bytes},
            {"buffer": 0, "byteOffset": vertex_bytes, "byteLength": vertex_bytes},
            {"buffer": 0, "byteOffset": 2 * vertex_bytes, "byteLength": 2 * indices.len()}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3",
             "min": [-HALF, 0, -HALF], "max": [HALF, 0, HALF]},
            {"bufferView": 1, "componentType": 5126, "count": n * n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": indices.len(), "type": "SCALAR"}
        ]
    });
    glb(&doc, &bin)
}

/// Where the ray through the centre of pixel `(x, y)` meets the plane
/// `y = 0`: the camera of shlight-gpu's `Camera` (docs: a right-handed
/// look-at view, +Y up on screen, vertical field of view, row 0 at the
/// top) written out as a pinhole.
fn floor_point(x: usize, y: usize) -> Option<DVec3> {
    let (eye, target) = (DVec3::from(EYE), DVec3::from(TARGET));
    let forward = (target - eye).normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let up = right.cross(forward);
    let (w, h) = (SIZE.0 as f64, SIZE.1 as f64);
    let t = (FOV.to_radians() / 2.0).tan();
    let ndc_x = (x as f64 + 0.5) / w * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f64 + 0.5) / h * 2.0;
    let d = forward + right * (ndc_x * t * w / h) + up * (ndc_y * t);
    (d.y < 0.0).then(|| eye + d * (-eye.y / d.y))
}

/// The flattened floor's triangles as the file's vertex indices, and each
/// vertex's (x, z).
struct Floor {
    triangles: Vec<[u32; 3]>,
    xz: Vec<DVec2>,
}

impl Floor {
    /// The corners of the triangle holding `p` (on the floor, at least
    /// `margin` inside its edge) and `p`'s barycentric coordinates in it.
    fn locate(&self, p: DVec3, margin: f64) -> Option<([u32; 3], [f64; 3])> {
        if p.x.abs() > HALF - margin || p.z.abs() > HALF - margin {
            return None;
        }
        let q = DVec2::new(p.x, p.z);
        self.triangles.iter().find_map(|t| {
            let [a, b, c] = t.map(|i| self.xz[i as usize]);
            let area = (b - a).perp_dot(c - a);
            let wb = (q - a).perp_dot(c - a) / area;
            let wc = (b - a).perp_dot(q - a) / area;
            let wa = 1.0 - wb - wc;
            (wa.min(wb).min(wc) >= -1e-9).then_some((*t, [wa, wb, wc]))
        })
    }

    /// `values` (per vertex) interpolated at `p`, or `None` off the floor.
    fn at(&self, p: DVec3, values: &[DVec3]) -> Option<DVec3> {
        let (t, w) = self.locate(p, 0.02)?;
        Some((0..3).map(|k| values[t[k] as usize] * w[k]).sum())
    }
}

/// `render-mesh SCENE --prt FILE --env LIGHT` at the test's camera, as
/// linear EXR.
fn render(scene: &Path, prt: &Path, light: &Path, out: &Path) -> Image {
    let camera = format!("{},{},{}", EYE[0], EYE[1], EYE[2]);
    let target = format!("{},{},{}", TARGET[0], TARGET[1], TARGET[2]);
    let (fov, size) = (FOV.to_string(), format!("{}x{}", SIZE.0, SIZE.1));
    shlight_ok(&[
        "render-mesh",
        s(scene),
        "--prt",
        s(prt),
        "--env",
        s(light),
        "--camera",
        &camera,
        "--target",
        &target,
        "--fov",
        &fov,
        "--size",
        &size,
        "--background",
        "none",
        "-o",
        s(out),
    ]);
    read_image(out, &ReadOptions::default()).unwrap()
}

/// `shlight sample FILE --light LIGHT`: each vertex's exit radiance.
fn sample(prt: &Path, light: &Path, out: &Path) -> Vec<DVec3> {
    shlight_ok(&["sample", s(prt), "--light", s(light), "-o", s(out), "-q"]);
    read_json(out)["radiance"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| DVec3::from_array([0, 1, 2].map(|c| r[c].as_f64().unwrap())))
        .collect()
}

/// The pixel at `(x, y)`.
fn pixel(image: &Image, x: usize, y: usize) -> DVec3 {
    DVec3::from_array(image.pixels()[y * image.width() + x].map(f64::from))
}

/// Over the pixels showing the floor: the largest and the mean of
/// `|got - want|` per channel, relative to `scale`, and how many pixels.
struct Errors {
    worst: f64,
    mean: f64,
    pixels: usize,
}

fn compare(image: &Image, want: impl Fn(DVec3) -> Option<DVec3>, scale: f64) -> Errors {
    let (mut worst, mut sum, mut pixels) = (0.0f64, 0.0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let Some(w) = floor_point(x, y).and_then(&want) else {
                continue;
            };
            let e = (pixel(image, x, y) - w).abs().max_element() / scale;
            worst = worst.max(e);
            sum += e;
            pixels += 1;
        }
    }
    Errors {
        worst,
        mean: sum / pixels.max(1) as f64,
        pixels,
    }
}

/// The test's floor and its bake (shadowed, lmax 2), written in `dir`.
fn bake(dir: &Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let scene = dir.join("floor.glb");
    std::fs::write(&scene, floor_glb()).unwrap();
    let prt = dir.join("floor.shprt");
    shlight_ok(&[
        "prt",
        s(&scene),
        "--samples",
        "256",
        "--lmax",
        "2",
        "-o",
        s(&prt),
        "-q",
    ]);
    (scene, prt)
}

#[test]
fn render_mesh_draws_a_scenes_static_term_with_its_transfer() {
    let test = "render_mesh_draws_a_scenes_static_term_with_its_transfer";
    if gpu_context(test).is_none() {
        return;
    }
    let dir = temp_dir("prt_static_gpu");
    let (scene, prt) = bake(&dir);
    let file = ShprtFile::read(&prt).unwrap();
    assert_eq!(file.format_version(), 3, "a static term");
    let mesh = shlight_mesh::load_scene(&scene, &Default::default())
        .unwrap()
        .flatten(glam::Vec3::splat(0.8))
        .unwrap()
        .mesh;
    assert_eq!(mesh.vertex_count(), file.vertex_count);
    let floor = Floor {
        triangles: mesh.triangles.clone(),
        xz: mesh
            .positions
            .iter()
            .map(|p| DVec2::new(f64::from(p.x), f64::from(p.z)))
            .collect(),
    };

    // Under a black sky the picture is the static term alone: the CPU's
    // per vertex, interpolated at each pixel's point, and the lamp's closed
    // form there, which the linear interpolation over 0.125 m quads follows
    // within about 1% under the lamp.
    let black = dir.join("black.json");
    write_radiance_rows(&black, &[[0.0; 3]]);
    let lit = render(&scene, &prt, &black, &dir.join("static.exr"));
    let s_cpu = sample(&prt, &black, &dir.join("static.json"));
    let static_term: Vec<DVec3> = file
        .static_light
        .as_ref()
        .unwrap()
        .radiance
        .iter()
        .map(|r| DVec3::from_array(r.map(f64::from)))
        .collect();
    for (a, b) in s_cpu.iter().zip(&static_term) {
        assert!((*a - *b).abs().max_element() <= 1e-6 * b.max_element().max(1.0));
    }
    let lamp = DVec3::from(LAMP);
    let closed_form = |p: DVec3| {
        let to = lamp - p;
        let (d2, cos) = (to.length_squared(), to.y / to.length());
        DVec3::from(ALBEDO) / std::f64::consts::PI
            * DVec3::from(LAMP_COLOR)
            * (LAMP_CD / 683.0)
            * cos
            / d2
    };
    let peak = closed_form(DVec3::new(lamp.x, 0.0, lamp.z)).max_element();
    let interpolated = compare(&lit, |p| floor.at(p, &s_cpu), peak);
    let exact = compare(
        &lit,
        |p| floor.locate(p, 0.02).map(|_| closed_form(p)),
        peak,
    );
    eprintln!(
        "static term, {} pixels (of the peak {peak:.3}): CPU interpolated worst {:.2e} mean {:.2e}; \
         closed form worst {:.2e} mean {:.2e}",
        interpolated.pixels, interpolated.worst, interpolated.mean, exact.worst, exact.mean
    );
    assert!(
        interpolated.pixels > SIZE.0 * SIZE.1 / 2,
        "the floor fills the frame"
    );
    assert!(
        interpolated.worst < 1e-3,
        "against the CPU: {:.2e}",
        interpolated.worst
    );
    assert!(
        exact.worst < 1e-2,
        "against the closed form: {:.2e}",
        exact.worst
    );

    // Under a sky: T . L + S, the CPU's exit radiance interpolated; the
    // same file without its static term draws T . L, and the two pictures
    // differ by the static term's.
    let sky = dir.join("sky.json");
    let mut rows = vec![[0.0; 3]; 9];
    rows[0] = [1.2, 1.5, 2.0];
    rows[1] = [0.4, 0.5, 0.6];
    rows[3] = [0.1, -0.1, 0.2];
    rows[6] = [0.05, 0.1, -0.05];
    write_radiance_rows(&sky, &rows);
    let both = render(&scene, &prt, &sky, &dir.join("both.exr"));
    let both_cpu = sample(&prt, &sky, &dir.join("both.json"));
    let scale = both_cpu.iter().map(|v| v.max_element()).fold(0.0, f64::max);
    let full = compare(&both, |p| floor.at(p, &both_cpu), scale);
    let mut bare_file = file.clone();
    bare_file.static_light = None;
    let bare_prt = dir.join("bare.shprt");
    bare_file.write(&bare_prt).unwrap();
    assert_eq!(ShprtFile::read(&bare_prt).unwrap().format_version(), 1);
    let bare = render(&scene, &bare_prt, &sky, &dir.join("bare.exr"));
    let (mut worst_sum, mut bare_mean, mut static_mean) = (0.0f64, 0.0, 0.0);
    let mut n = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            if floor_point(x, y)
                .and_then(|p| floor.locate(p, 0.02))
                .is_none()
            {
                continue;
            }
            let (a, b, c) = (pixel(&both, x, y), pixel(&bare, x, y), pixel(&lit, x, y));
            worst_sum = worst_sum.max((a - b - c).abs().max_element() / scale);
            bare_mean += b.element_sum() / 3.0;
            static_mean += c.element_sum() / 3.0;
            n += 1;
        }
    }
    let (bare_mean, static_mean) = (bare_mean / n as f64, static_mean / n as f64);
    eprintln!(
        "T . L + S, {} pixels (of {scale:.3}): CPU interpolated worst {:.2e} mean {:.2e}; \
         (T . L + S) - (T . L) - S worst {worst_sum:.2e}; mean T . L {bare_mean:.3}, S {static_mean:.3}",
        full.pixels, full.worst, full.mean
    );
    assert!(
        bare_mean > 0.3 * static_mean && static_mean > 0.3 * bare_mean,
        "both terms show: T . L {bare_mean}, S {static_mean}"
    );
    assert!(
        full.worst < 1e-3,
        "T . L + S against the CPU: {:.2e}",
        full.worst
    );
    assert!(
        worst_sum < 1e-4,
        "the two renders differ by S: {worst_sum:.2e}"
    );
}

/// `view --prt` under a black sky shows the static term: its screenshot
/// is `render-mesh`'s PNG of the same framing, the lamp's pool of light on
/// the floor, not a black picture.
#[test]
fn view_draws_a_scenes_static_term() {
    let Some(x) = gpu_and_xvfb("view_draws_a_scenes_static_term") else {
        return;
    };
    let dir = temp_dir("prt_static_gpu_view");
    let (scene, prt) = bake(&dir);
    let black = dir.join("black.json");
    write_radiance_rows(&black, &[[0.0; 3]]);
    let files = [s(&scene), "--prt", s(&prt), "--env", s(&black)];
    let (worst, brightest, _) = view_against_render_mesh(x, &files, &dir);
    eprintln!(
        "view --prt vs render-mesh --prt (PNG, linear): worst {worst:.2e}; brightest {brightest:.3}"
    );
    assert!(brightest > 0.05, "the lamp's light shows: {brightest}");
    assert!(worst < 0.02, "view and render-mesh differ by {worst}");
}

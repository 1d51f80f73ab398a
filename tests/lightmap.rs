//! `shlight lightmap` end to end: a glTF floor with a second UV set under
//! a point lamp baked to the closed form `E = I cos / d^2` in each
//! engine's units (its layers read back from the OpenEXR files), and bad
//! scenes refused by name with nothing written.

use std::path::Path;

use shlight_io::{ReadOptions, read_image};

use crate::util::{glb, s, shlight_err, shlight_ok, temp_dir, write_coefficient_rows};

/// A 2 m floor (y = 0, facing up) whose UV sets are both `(x / 2 + 1/2, z
/// / 2 + 1/2)` (only the first with `uv1: false`), and a white point lamp
/// of `candela` at `lamp`.
fn floor_glb(candela: f64, lamp: [f32; 3], uv1: bool) -> Vec<u8> {
    turned_floor_glb(candela, lamp, uv1, [0.0, 0.0, 0.0, 1.0])
}

/// [`floor_glb`] with the floor's node turned by the quaternion `rotation`
/// (x, y, z, w).
pub fn turned_floor_glb(candela: f64, lamp: [f32; 3], uv1: bool, rotation: [f32; 4]) -> Vec<u8> {
    let corners = [
        [-1.0f32, 0.0, -1.0],
        [1.0, 0.0, -1.0],
        [1.0, 0.0, 1.0],
        [-1.0, 0.0, 1.0],
    ];
    let mut bin = Vec::new();
    for c in corners {
        c.iter().for_each(|x| bin.extend(x.to_le_bytes()));
    }
    for _ in corners {
        [0.0f32, 1.0, 0.0]
            .iter()
            .for_each(|x| bin.extend(x.to_le_bytes()));
    }
    for c in corners {
        [c[0] / 2.0 + 0.5, c[2] / 2.0 + 0.5]
            .iter()
            .for_each(|x| bin.extend(x.to_le_bytes()));
    }
    for i in [0u16, 3, 2, 0, 2, 1] {
        bin.extend(i.to_le_bytes());
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut attributes = serde_json::json!({"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2});
    if uv1 {
        attributes["TEXCOORD_1"] = 2.into();
    }
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "name": "lamp", "intensity": candela, "color": [1, 1, 1]}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0, "name": "Floor", "rotation": rotation},
            {"translation": lamp, "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}],
        "meshes": [{"name": "Floor", "primitives": [{"attributes": attributes, "indices": 3, "material": 0}]}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1, 0, -1], "max": [1, 0, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    glb(&doc, &bin)
}

pub fn black_sky(dir: &Path) -> std::path::PathBuf {
    let env = dir.join("black.json");
    write_coefficient_rows(&env, &[[0.0; 3]; 9], "radiance");
    env
}

/// `shlight lightmap SCENE --env ENV --for ENGINE --basis BASIS --size
/// SIZE` at the tests' quick settings (16 rays a texel, 16 directions a
/// surface vertex), then `extra`; it must succeed.
pub fn bake_quick(
    scene: &Path,
    env: &Path,
    engine: &str,
    basis: &str,
    size: u32,
    extra: &[&str],
) -> std::process::Output {
    let size = size.to_string();
    let mut args = vec![
        "lightmap",
        s(scene),
        "--env",
        s(env),
        "--for",
        engine,
        "--basis",
        basis,
        "--size",
        &size,
        "--samples",
        "16",
        "--surface-samples",
        "16",
    ];
    args.extend_from_slice(extra);
    shlight_ok(&args)
}

#[test]
fn a_floor_under_a_lamp_bakes_to_i_cos_over_d_squared_for_each_engine() {
    let dir = temp_dir("lightmap_floor");
    let scene = dir.join("floor.glb");
    // 683 x 6 cd in Blender's units: 6 W/sr.
    let lamp = [0.3f32, 1.5, -0.2];
    std::fs::write(&scene, floor_glb(683.0 * 6.0, lamp, true)).unwrap();
    let env = black_sky(&dir);
    for (engine, scale) in [("threejs", 1.0), ("bevy", 1.0 / std::f64::consts::PI)] {
        let prefix = dir.join(engine);
        let run = bake_quick(
            &scene,
            &env,
            engine,
            "irradiance",
            64,
            &["--exr", s(&prefix)],
        );
        let said = String::from_utf8_lossy(&run.stderr);
        assert!(said.contains("64 x 64 lightmap, 1 regions"), "{said}");
        let image = read_image(
            &dir.join(format!("{engine}.irradiance.exr")),
            &ReadOptions::default(),
        )
        .unwrap();
        assert_eq!((image.width(), image.height()), (64, 64));
        // The region: padding 2, so texels 2..62 hold the floor (its side
        // the largest that fits: 60).
        let (mut checked, mut worst) = (0, 0.0f64);
        for y in 2..62 {
            for x in 2..62 {
                let uv = [(x - 2) as f32 + 0.5, (y - 2) as f32 + 0.5].map(|t| t / 60.0);
                let p = [uv[0] * 2.0 - 1.0, 0.0, uv[1] * 2.0 - 1.0];
                let d = [lamp[0] - p[0], lamp[1] - p[1], lamp[2] - p[2]];
                let d2 = f64::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                let want = 6.0 * f64::from(d[1]) / d2.powf(1.5) * scale;
                let got = f64::from(image.get(x, y)[0]);
                worst = worst.max((got / want - 1.0).abs());
                checked += 1;
            }
        }
        assert_eq!(checked, 3600);
        // Each texel is sampled within half a texel of its centre (1.7 cm),
        // where the lamp's light changes by under 1.5%.
        assert!(worst < 0.015, "{engine}: worst {worst}");
    }
}

#[test]
fn a_scene_without_a_second_uv_set_is_refused_by_name_and_nothing_is_written() {
    let dir = temp_dir("lightmap_no_uv1");
    let scene = dir.join("floor.glb");
    std::fs::write(&scene, floor_glb(683.0, [0.0, 1.0, 0.0], false)).unwrap();
    let env = black_sky(&dir);
    let prefix = dir.join("out");
    let e = shlight_err(&[
        "lightmap",
        s(&scene),
        "--env",
        s(&env),
        "--size",
        "32",
        "--exr",
        s(&prefix),
    ]);
    assert!(
        e.contains("floor.glb")
            && e.contains("(Floor)")
            && e.contains("has no UV set 1 (TEXCOORD_1)")
            && e.contains("does not unwrap"),
        "{e}"
    );
    assert!(!dir.join("out.irradiance.exr").exists());
    let e = shlight_err(&[
        "lightmap",
        s(&scene),
        "--env",
        s(&env),
        "--basis",
        "monosh",
        "--for",
        "godot",
    ]);
    assert!(e.contains("--basis monosh with --for godot"), "{e}");
    let e = shlight_err(&[
        "lightmap",
        s(&scene),
        "--env",
        s(&env),
        "-o",
        s(&dir.join("out.gltf")),
    ]);
    assert!(e.contains("a .glb file"), "{e}");
}

/// The JSON and binary chunks of a GLB file (glTF 2.0, section 4.4).
fn glb_chunks(bytes: &[u8]) -> (serde_json::Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let json_len = word(12);
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin_at = 20 + json_len;
    let bin_len = word(bin_at);
    (json, bytes[bin_at + 8..bin_at + 8 + bin_len].to_vec())
}

#[test]
fn the_lightmapped_scene_holds_its_pages_and_says_what_they_hold() {
    let dir = temp_dir("lightmap_glb");
    let scene = dir.join("floor.glb");
    let lamp = [0.3f32, 1.5, -0.2];
    std::fs::write(&scene, floor_glb(683.0 * 6.0, lamp, true)).unwrap();
    let env = black_sky(&dir);
    for (engine, basis, layers, denoise) in [
        ("threejs", "irradiance", vec!["irradiance"], "3"),
        ("godot", "sh-l1", vec!["l0", "l1y", "l1z", "l1x"], "0"),
    ] {
        let out = dir.join(format!("{engine}.glb"));
        let prefix = dir.join(engine);
        bake_quick(
            &scene,
            &env,
            engine,
            basis,
            32,
            &["--denoise", denoise, "-o", s(&out), "--exr", s(&prefix)],
        );
        // `show` says what the file holds.
        let shown = String::from_utf8_lossy(&shlight_ok(&["show", s(&out)]).stdout).into_owned();
        assert!(shown.contains("a scene with shlight's lightmap"), "{shown}");
        assert!(shown.contains(&format!("{basis} for {engine}")), "{shown}");
        assert!(
            shown.contains(&format!("layers {}", layers.join(", "))),
            "{shown}"
        );
        assert!(shown.contains("baked nodes  1"), "{shown}");
        assert!(
            shown.contains(&format!("denoised over {denoise} texels")),
            "{shown}"
        );
        let (doc, bin) = glb_chunks(&std::fs::read(&out).unwrap());
        let root = &doc["extensions"]["SHLIGHT_lightmap"];
        assert_eq!(root["basis"], basis);
        assert_eq!(root["engine"], engine);
        assert_eq!(
            root["units"],
            if engine == "threejs" {
                "irradiance"
            } else {
                "irradiance/pi"
            }
        );
        assert_eq!(root["layers"], serde_json::json!(layers));
        assert_eq!(root["size"], serde_json::json!([32, 32]));
        assert_eq!(root["denoise"].to_string(), denoise);
        let e = shlight_err(&[
            "lightmap",
            s(&scene),
            "--env",
            s(&env),
            "--denoise",
            "17",
            "-o",
            s(&dir.join("wide.glb")),
        ]);
        assert!(e.contains("at most 16"), "{e}");
        assert!(!dir.join("wide.glb").exists());
        let node = &doc["nodes"][0]["extensions"]["SHLIGHT_lightmap"];
        assert_eq!(node["rect"], serde_json::json!([2, 2, 28]));
        // The material reads the first page through MOZ_lightmap, its
        // intensity bringing the texels back to irradiance.
        let material = doc["meshes"][doc["nodes"][0]["mesh"].as_u64().unwrap() as usize]["primitives"][0]["material"]
            .as_u64()
            .unwrap() as usize;
        let moz = &doc["materials"][material]["extensions"]["MOZ_lightmap"];
        assert_eq!(moz["texCoord"], 1);
        let intensity = moz["intensity"].as_f64().unwrap();
        let want = if engine == "threejs" {
            1.0
        } else {
            std::f64::consts::PI
        };
        assert!((intensity - want).abs() < 1e-6, "{intensity}");
        // Each page is a half-float KTX2 file holding the layer the EXR
        // holds, to half-float rounding.
        for (k, name) in layers.iter().enumerate() {
            let texture = &doc["textures"][moz["index"].as_u64().unwrap() as usize + k];
            let image = &doc["images"][texture["extensions"]["KHR_texture_basisu"]["source"]
                .as_u64()
                .unwrap() as usize];
            assert_eq!(image["mimeType"], "image/ktx2");
            let view = &doc["bufferViews"][image["bufferView"].as_u64().unwrap() as usize];
            let at = view["byteOffset"].as_u64().unwrap_or(0) as usize;
            let len = view["byteLength"].as_u64().unwrap() as usize;
            let page = shlight_io::decode_ktx2(&bin[at..at + len]).unwrap();
            assert_eq!((page.width, page.height), (32, 32));
            let exr = read_image(
                &dir.join(format!("{engine}.{name}.exr")),
                &ReadOptions::default(),
            )
            .unwrap();
            for (t, p) in page.texels.iter().zip(exr.pixels()) {
                for c in 0..3 {
                    assert!(
                        (t[c] - p[c]).abs() <= 1e-3 * p[c].abs().max(1e-3),
                        "{name}: {t:?} against {p:?}"
                    );
                }
            }
        }
        // three.js reads no per-node rectangle: the floor's TEXCOORD_1 was
        // moved into its region. The scene still loads with its triangle.
        let loaded = shlight_mesh::load_scene(&out, &shlight_mesh::LoadOptions::default()).unwrap();
        let uv1 = &loaded.primitives[0].uvs[1];
        let (lo, hi) = (2.0 / 32.0, 30.0 / 32.0);
        if engine == "threejs" {
            assert!(
                uv1.iter()
                    .all(|uv| (uv.x - lo).abs() < 1e-6 || (uv.x - hi).abs() < 1e-6),
                "{uv1:?}"
            );
        } else {
            assert!(
                uv1.iter()
                    .all(|uv| uv.x.abs() < 1e-6 || (uv.x - 1.0).abs() < 1e-6),
                "{uv1:?}"
            );
        }
        assert_eq!(loaded.primitives[0].mesh.triangle_count(), 2);
    }
}

#[test]
fn sample_reads_the_lightmapped_scene_as_the_engines_shader_does() {
    // The floor under the lamp, for three.js (irradiance) and for Godot
    // (sh-l1): `sample` at points of the floor gives I cos / d^2 for the
    // floor's normal, and for Godot's L1 also, for tilted normals, the
    // lmax-1 closed form of one point light, E_perp (1/4 + n . t / 2).
    let dir = temp_dir("lightmap_sample");
    let scene = dir.join("floor.glb");
    let lamp = [0.3f32, 1.5, -0.2];
    std::fs::write(&scene, floor_glb(683.0 * 6.0, lamp, true)).unwrap();
    let env = black_sky(&dir);
    let mut points = Vec::new();
    let mut normals = Vec::new();
    for k in 0..20 {
        let t = k as f32 / 19.0;
        let p = [-0.8 + 1.6 * t, 0.0, 0.7 - 1.4 * (t * 7.0).fract()];
        let tilt = (k % 4) as f32 * 0.3;
        points.push(p);
        normals.push([tilt.sin(), tilt.cos(), 0.0]);
    }
    let points_file = dir.join("points.json");
    std::fs::write(
        &points_file,
        serde_json::json!({"points": points, "normals": normals}).to_string(),
    )
    .unwrap();
    for (engine, basis) in [("threejs", "irradiance"), ("godot", "sh-l1")] {
        let out = dir.join(format!("{engine}.glb"));
        bake_quick(&scene, &env, engine, basis, 128, &["-o", s(&out)]);
        let answer = dir.join(format!("{engine}.json"));
        shlight_ok(&[
            "sample",
            s(&out),
            "--points",
            s(&points_file),
            "-o",
            s(&answer),
        ]);
        let doc = crate::util::read_json(&answer);
        assert_eq!(doc["lightmap"]["engine"], engine);
        let values = doc["irradiance"].as_array().unwrap();
        for ((p, n), v) in points.iter().zip(&normals).zip(values) {
            let d = [lamp[0] - p[0], lamp[1] - p[1], lamp[2] - p[2]];
            let d2 = f64::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            let toward = d.map(|x| f64::from(x) / d2.sqrt());
            let perp = 6.0 / d2;
            let cos = f64::from(n[0]) * toward[0] + f64::from(n[1]) * toward[1];
            let want = if basis == "irradiance" {
                // The lightmap holds E for the floor's normal, whatever
                // the point's.
                perp * toward[1]
            } else {
                perp * (0.25 + 0.5 * cos)
            };
            let got = v[0].as_f64().unwrap();
            assert!(
                (got / want - 1.0).abs() < 0.02,
                "{engine} at {p:?} facing {n:?}: {got} against {want}"
            );
        }
    }
    // A point off every surface is named.
    let off = dir.join("off.json");
    std::fs::write(
        &off,
        serde_json::json!({"points": [[0, 1, 0]], "normals": [[0, 1, 0]]}).to_string(),
    )
    .unwrap();
    let e = shlight_err(&[
        "sample",
        s(&dir.join("threejs.glb")),
        "--points",
        s(&off),
        "-o",
        s(&dir.join("off-answer.json")),
    ]);
    assert!(
        e.contains("point 0") && e.contains("is on no surface"),
        "{e}"
    );
    // A GLB without a lightmap is refused by name.
    let e = shlight_err(&[
        "sample",
        s(&scene),
        "--points",
        s(&points_file),
        "-o",
        s(&dir.join("none.json")),
    ]);
    assert!(
        e.contains("floor.glb") && e.contains("no SHLIGHT_lightmap"),
        "{e}"
    );
}

/// `render-mesh` draws a lightmapped floor by its lightmap: with no
/// `--env` (and with `--lightmap` under a black `--env`), each pixel of
/// the floor holds `albedo / pi x E`, `E` what `shlight sample` reads at
/// the floor point under the pixel (the GPU's bilinear filter and the
/// engine's reconstruction against the CPU's port), and the closed form
/// `I cos / d^2` of the lamp (for the SH bases its lmax-1 form,
/// `E_perp (1/4 + cos / 2)`). Four texel formats: three.js irradiance and
/// sh-l1 (shlight's float layout), Godot's packed sh-l1 and Bakery's
/// MonoSH (Unity); a flat floor, and one turned so that its normal is off
/// the vertical.
///
/// Tolerances: 1e-4 of the pixel against `sample` at the same point (the
/// rasteriser's interpolated UV and normal against the CPU's ray, the
/// sampler's filter weights, f32 arithmetic; measured worst 4.6e-6 on
/// lavapipe, every format), and 1.5% against the closed form (the bake's
/// own error at 32 x 32 texels: its bilinear reconstruction across 7 cm
/// texels and the Monte Carlo estimate; measured worst 0.98%, the turned
/// floor's irradiance texels).
#[cfg(feature = "gpu")]
#[test]
fn render_mesh_draws_a_lightmapped_floor_as_sample_reads_it() {
    const TEST: &str = "render_mesh_draws_a_lightmapped_floor_as_sample_reads_it";
    if crate::util::gpu_context(TEST).is_none() {
        return;
    }
    let mut report = Vec::new();
    // Flat, and turned 25 degrees about x toward the camera (its normal
    // then has a z part: the L1 texels reshaded off the vertical).
    for (floor, degrees) in [("flat", 0.0f64), ("turned", 25.0)] {
        render_lightmapped_floor(floor, degrees, &mut report);
    }
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "{}", report.join("\n"));
}

/// The body of [`render_mesh_draws_a_lightmapped_floor_as_sample_reads_it`]
/// for the floor turned `degrees` about x, named `floor`; each render's
/// worst errors pushed to `report`.
#[cfg(feature = "gpu")]
fn render_lightmapped_floor(floor: &str, degrees: f64, report: &mut Vec<String>) {
    use glam::{DQuat, DVec3};
    let dir = temp_dir(&format!("lightmap_render_{floor}"));
    let scene = dir.join("floor.glb");
    let lamp = [0.3f32, 1.5, -0.2];
    let turn = DQuat::from_rotation_x(degrees.to_radians());
    let q = turn.to_array().map(|x| x as f32);
    std::fs::write(&scene, turned_floor_glb(683.0 * 6.0, lamp, true, q)).unwrap();
    let normal = turn * DVec3::Y;
    let env = black_sky(&dir);
    // The camera: above the floor's front edge, looking at its centre.
    let (eye, target, fov, (w, h)) = (
        DVec3::new(0.2, 2.4, 1.6),
        DVec3::new(0.0, 0.0, -0.1),
        45.0f64,
        (64usize, 48usize),
    );
    let floor_point = |x: usize, y: usize| -> Option<DVec3> {
        let forward = (target - eye).normalize();
        let right = forward.cross(DVec3::Y).normalize();
        let up = right.cross(forward);
        let t = (fov.to_radians() / 2.0).tan();
        let ndc_x = (x as f64 + 0.5) / w as f64 * 2.0 - 1.0;
        let ndc_y = 1.0 - (y as f64 + 0.5) / h as f64 * 2.0;
        let d = forward + right * (ndc_x * t * w as f64 / h as f64) + up * (ndc_y * t);
        let p = eye + d * (-eye.dot(normal) / d.dot(normal));
        let local = turn.inverse() * p;
        (d.dot(normal) < 0.0 && local.x.abs() < 0.9 && local.z.abs() < 0.9).then_some(p)
    };
    let pixels: Vec<(usize, usize, DVec3)> = (0..h)
        .step_by(3)
        .flat_map(|y| (0..w).step_by(3).map(move |x| (x, y)))
        .filter_map(|(x, y)| floor_point(x, y).map(|p| (x, y, p)))
        .collect();
    assert!(pixels.len() > 100, "{} floor pixels", pixels.len());
    let points_file = dir.join("points.json");
    let points: Vec<[f64; 3]> = pixels.iter().map(|p| p.2.to_array()).collect();
    let normals = vec![normal.to_array(); points.len()];
    std::fs::write(
        &points_file,
        serde_json::json!({"points": points, "normals": normals}).to_string(),
    )
    .unwrap();
    let camera = format!("{},{},{}", eye.x, eye.y, eye.z);
    let look = format!("{},{},{}", target.x, target.y, target.z);
    let (fov, size) = (fov.to_string(), format!("{w}x{h}"));
    let albedo_over_pi = 0.5 / std::f64::consts::PI;
    // Every reconstruction of shaders/lightmap.wgsl: the non-linear ones
    // (Geomerics') are held to `sample` only, the closed form being
    // linear's.
    for (engine, basis, non_linear) in [
        ("threejs", "irradiance", false),
        ("threejs", "sh-l1", false),
        ("threejs", "sh-l1", true),
        ("godot", "sh-l1", false),
        ("unity", "sh-l1", false),
        ("unity", "sh-l1", true),
        ("unity", "monosh", false),
        ("unity", "monosh", true),
    ] {
        let name = format!("{engine}-{basis}{}", if non_linear { "-nl" } else { "" });
        let baked = dir.join(format!("{name}.glb"));
        let mut extra = vec!["-o", s(&baked)];
        if non_linear {
            extra.push("--non-linear");
        }
        bake_quick(&scene, &env, engine, basis, 32, &extra);
        let answer = dir.join(format!("{name}.json"));
        shlight_ok(&[
            "sample",
            s(&baked),
            "--points",
            s(&points_file),
            "-o",
            s(&answer),
        ]);
        let sampled: Vec<f64> = crate::util::read_json(&answer)["irradiance"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v[0].as_f64().unwrap())
            .collect();
        for extra in [&[][..], &["--lightmap", "--env", s(&env)][..]] {
            let out = dir.join(format!("{name}-{}.exr", extra.len()));
            let mut args = vec![
                "render-mesh",
                s(&baked),
                "--camera",
                &camera,
                "--target",
                &look,
                "--fov",
                &fov,
                "--size",
                &size,
                "-o",
                s(&out),
            ];
            args.extend_from_slice(extra);
            shlight_ok(&args);
            let image = read_image(&out, &ReadOptions::default()).unwrap();
            let (mut worst_sample, mut worst_closed) = (0.0f64, 0.0f64);
            for (&(x, y, p), &e) in pixels.iter().zip(&sampled) {
                let got = image.get(x, y);
                let d = DVec3::from(lamp.map(f64::from)) - p;
                let perp = 6.0 / d.length_squared();
                let cos = d.dot(normal) / d.length();
                // An irradiance texel holds the floor's own E; an L1 texel
                // the lmax-1 irradiance of the one lamp, E_perp (1/4 + n .
                // t / 2), at the normal the renderer reconstructs it for.
                let closed = if basis == "irradiance" {
                    perp * cos
                } else {
                    perp * (0.25 + 0.5 * cos)
                };
                for c in got {
                    let c = f64::from(c);
                    worst_sample = worst_sample.max((c / (albedo_over_pi * e) - 1.0).abs());
                    if !non_linear {
                        worst_closed =
                            worst_closed.max((c / (albedo_over_pi * closed) - 1.0).abs());
                    }
                }
            }
            report.push(format!(
                "{floor} {name} {extra:?}: worst {worst_sample:.2e} against sample, {worst_closed:.2e} against I cos / d^2"
            ));
            assert!(
                worst_sample < 1e-4 && worst_closed < 0.015,
                "{}",
                report.join("\n")
            );
        }
    }
}

/// A scene without a lightmap: `render-mesh` without `--env` says it
/// needs one, and `--lightmap` says the scene holds none; nothing is
/// written either way.
#[cfg(feature = "gpu")]
#[test]
fn render_mesh_refuses_a_lightmap_the_scene_does_not_hold() {
    let dir = temp_dir("lightmap_render_refused");
    let scene = dir.join("floor.glb");
    std::fs::write(&scene, floor_glb(683.0, [0.0, 1.0, 0.0], true)).unwrap();
    let env = black_sky(&dir);
    let out = dir.join("frame.exr");
    let e = shlight_err(&["render-mesh", s(&scene), "-o", s(&out)]);
    assert!(
        e.contains("floor.glb") && e.contains("holds no lightmap") && e.contains("--env"),
        "{e}"
    );
    let e = shlight_err(&[
        "render-mesh",
        s(&scene),
        "--env",
        s(&env),
        "--lightmap",
        "-o",
        s(&out),
    ]);
    assert!(
        e.contains("floor.glb") && e.contains("--lightmap") && e.contains("no SHLIGHT_lightmap"),
        "{e}"
    );
    let e = shlight_err(&[
        "render-mesh",
        s(&scene),
        "--env",
        s(&env),
        "--lightmap",
        "--mode",
        "normals",
        "-o",
        s(&out),
    ]);
    assert!(
        e.contains("--lightmap") && e.contains("--mode normals"),
        "{e}"
    );
    assert!(!out.exists());
}

/// `view OUT.glb` (no `--env`) draws the lightmapped floor as
/// `render-mesh OUT.glb` does: the screenshot against render-mesh's PNG
/// at the same default camera, within 0.02 a channel (PNG, tone-mapped
/// alike); the floor lit (its only light is the lightmap's) and the
/// background black (no built-in map).
#[cfg(feature = "gpu")]
#[test]
fn view_draws_a_lightmapped_floor_as_render_mesh_does() {
    let Some(x) = crate::gpu::gpu_and_xvfb("view_draws_a_lightmapped_floor_as_render_mesh_does")
    else {
        return;
    };
    let dir = temp_dir("lightmap_view");
    let scene = dir.join("floor.glb");
    std::fs::write(&scene, floor_glb(683.0 * 6.0, [0.3, 1.5, -0.2], true)).unwrap();
    let env = black_sky(&dir);
    let baked = dir.join("baked.glb");
    bake_quick(&scene, &env, "godot", "sh-l1", 32, &["-o", s(&baked)]);
    let (worst, brightest, view) = crate::gpu::view_against_render_mesh(x, &[s(&baked)], &dir);
    let corner = view.get(0, 0);
    eprintln!(
        "view vs render-mesh of a lightmapped floor: worst {worst:.2e}; brightest {brightest:.3}"
    );
    assert!(brightest > 0.05, "the lightmap's light shows: {brightest}");
    assert_eq!(corner, [0.0; 3], "no background");
    assert!(worst < 0.02, "view and render-mesh differ by {worst}");
}

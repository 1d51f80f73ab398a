//! `shlight volume`: the bundled Cornell box is the published scene, the
//! files hold the library's bake in the documented layout (binary and JSON
//! agree), the bake is the same at any thread count, `--static` drops the
//! transfer, a glTF's punctual light lights the probes in the units asked
//! for, and bad input is an error naming the problem with nothing
//! written.

use std::path::Path;
use std::process::Command;

use glam::{DVec3, Vec3};
use shlight_baked::ProbeGrid;
use shlight_core::sh::ShCoeffs;
use shlight_format::ShvolFile;
use shlight_mesh::generate;
use shlight_volume::{VolumeOptions, bake};

use crate::util::{glb, read_json, s, shlight_err, shlight_ok, temp_dir, write_coefficient_rows};

const SCENE: &str = "meshes/cornell_box.obj";

/// A sky of lmax 2: brighter above, with some colour.
fn sky_rows() -> Vec<[f64; 3]> {
    let mut rows = vec![[0.0; 3]; 9];
    rows[0] = [2.0, 2.2, 2.6];
    rows[2] = [0.8, 0.9, 1.1];
    rows[6] = [0.1, 0.05, 0.0];
    rows
}

fn sky() -> ShCoeffs<DVec3> {
    ShCoeffs::from_vec(sky_rows().into_iter().map(DVec3::from_array).collect()).unwrap()
}

#[test]
fn the_bundled_cornell_box_is_the_generated_one() {
    // The OBJ and its MTL go through tobj and shlight's material reading;
    // the generator builds the same quads from the published numbers.
    let file = shlight_mesh::load(Path::new(SCENE)).unwrap();
    let made = generate::cornell_box();
    assert_eq!(file.triangles, made.triangles);
    let close = |a: &[Vec3], b: &[Vec3]| a.iter().zip(b).all(|(x, y)| x.distance(*y) < 1e-6);
    assert!(close(&file.positions, &made.positions));
    assert!(close(&file.normals, &made.normals));
    assert!(close(
        file.colors.as_ref().unwrap(),
        made.colors.as_ref().unwrap()
    ));
    assert!(close(
        file.emission.as_ref().unwrap(),
        made.emission.as_ref().unwrap()
    ));
}

fn bake_args<'a>(env: &'a Path, out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "volume",
        SCENE,
        "--env",
        s(env),
        "--resolution",
        "3x2x3",
        "--samples",
        "256",
        "--surface-samples",
        "128",
        "--seed",
        "5",
        "-o",
        s(out),
    ];
    args.extend_from_slice(extra);
    args
}

#[test]
fn the_file_holds_the_library_bake_and_the_json_agrees() {
    let dir = temp_dir("volume_file");
    let env = dir.join("sky.json");
    write_coefficient_rows(&env, &sky_rows(), "radiance");
    let out = dir.join("box.shvol");
    let run = shlight_ok(&bake_args(&env, &out, &[]));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("18 probes (0 invalid"), "{stderr}");
    let file = ShvolFile::read(&out).unwrap();
    assert_eq!((file.lmax, file.resolution), (2, [3, 2, 3]));
    assert!(file.relightable());
    assert_eq!(
        (file.scene.as_str(), file.environment.as_str()),
        ("cornell_box.obj", "sky.json")
    );

    // The library, given the same options and the scene's padded box.
    let scene = shlight_mesh::load(Path::new(SCENE)).unwrap();
    assert_eq!(file.scene_hash, scene.content_hash());
    let grid = ProbeGrid::around([3, 2, 3], scene.bounds()).unwrap();
    assert_eq!(file.bounds, (grid.min.to_array(), grid.max.to_array()));
    let options = VolumeOptions {
        samples: 256,
        surface_samples: 128,
        seed: 5,
        ..VolumeOptions::default()
    };
    let volume = bake(Some(&scene), &grid, &options, &|_, _, _| {}).unwrap();
    assert_eq!(file.radiance, volume.relight(&sky()));
    assert_eq!(file.transfer.as_ref(), Some(&volume.transfer));
    assert_eq!(file.offsets, volume.offsets);
    assert_eq!(file.visibility, volume.visibility);
    // Light reaches every probe: the ceiling lamp and the sky through the
    // open front.
    assert!(file.radiance.chunks_exact(27).all(|p| p[0] > 0.1));

    // JSON: the same numbers in the documented keys.
    let json_out = dir.join("box.json");
    shlight_ok(&bake_args(&env, &json_out, &[]));
    let j = read_json(&json_out);
    assert_eq!(j["format"], "shlight-volume");
    assert_eq!(j["resolution"], serde_json::json!([3, 2, 3]));
    let positions = j["positions"].as_array().unwrap();
    assert_eq!(positions.len(), 18);
    // Where the probes are: their cells' centres, moved where the bake
    // moved them out of geometry.
    let offsets = volume.offsets.as_ref().unwrap();
    assert!(
        volume.relocated_count() > 0,
        "the box's probes near its walls move"
    );
    for (i, c) in grid.centres().iter().enumerate() {
        let p = &(*c + Vec3::from_slice(&offsets[3 * i..3 * i + 3]));
        let got = Vec3::new(
            positions[i][0].as_f64().unwrap() as f32,
            positions[i][1].as_f64().unwrap() as f32,
            positions[i][2].as_f64().unwrap() as f32,
        );
        assert!(got.distance(*p) < 1e-6, "probe {i}: {got} vs {p}");
    }
    let coefficients = j["coefficients"].as_array().unwrap();
    for (p, probe) in coefficients.iter().enumerate() {
        for (i, row) in probe.as_array().unwrap().iter().enumerate() {
            for c in 0..3 {
                let want = file.radiance[(p * 9 + i) * 3 + c];
                assert_eq!(row[c].as_f64().unwrap() as f32, want);
            }
        }
    }
    assert!(j["valid"].as_array().unwrap().iter().all(|v| v == true));
}

#[test]
fn the_bake_is_the_same_at_any_thread_count_and_static_drops_the_transfer() {
    let dir = temp_dir("volume_threads");
    let env = dir.join("sky.json");
    write_coefficient_rows(&env, &sky_rows(), "radiance");
    let mut files = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.join(format!("t{threads}.shvol"));
        let status = Command::new(env!("CARGO_BIN_EXE_shlight"))
            .args(bake_args(&env, &out, &[]))
            .env("RAYON_NUM_THREADS", threads)
            .status()
            .unwrap();
        assert!(status.success());
        files.push(std::fs::read(&out).unwrap());
    }
    assert_eq!(files[0], files[1]);
    let out = dir.join("static.shvol");
    shlight_ok(&bake_args(&env, &out, &["--static"]));
    let fixed = ShvolFile::read(&out).unwrap();
    let full = ShvolFile::from_bytes(&files[0], Path::new("t1.shvol")).unwrap();
    assert!(fixed.transfer.is_none() && fixed.emitted.is_none());
    assert_eq!(fixed.radiance, full.radiance);
    // The Bevy texture of the same bake is what the format crate makes of
    // the file (its layout is tested there against Bevy's shader).
    let ktx2 = dir.join("box.ktx2");
    shlight_ok(&bake_args(&env, &ktx2, &[]));
    assert_eq!(
        std::fs::read(&ktx2).unwrap(),
        shlight_format::bevy_volume::bevy_ktx2(&full, &full.generator)
    );
}

#[test]
fn bad_input_is_an_error_naming_the_problem_and_nothing_is_written() {
    let dir = temp_dir("volume_errors");
    let env = dir.join("sky.json");
    write_coefficient_rows(&env, &sky_rows(), "radiance");
    let irradiance = dir.join("irr.json");
    write_coefficient_rows(&irradiance, &sky_rows(), "irradiance");
    let out = dir.join("v.shvol");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--resolution", "4x4"], "resolution \"4x4\""),
        (vec!["--bounds", "1,0,0:0,1,1"], "bounds \"1,0,0:0,1,1\""),
        (vec!["--lmax", "9"], "lmax 9"),
        (vec!["--lmax", "3"], "lmax 2, the bake needs 3"),
        (vec!["--samples", "0"], "samples must be at least 1"),
        (
            vec!["--max-edge", "0"],
            "--max-edge 0 is not a positive length",
        ),
        (
            vec!["--max-edge", "0.00001"],
            "would split the scene's 32 triangles into about",
        ),
    ];
    for (extra, want) in cases {
        let mut args = vec![
            "volume",
            SCENE,
            "--env",
            s(&env),
            "--surface-samples",
            "32",
            "-o",
            s(&out),
        ];
        args.extend_from_slice(&extra);
        let e = shlight_err(&args);
        assert!(e.contains(want), "{extra:?}: {e}");
    }
    let e = shlight_err(&bake_args(&irradiance, &out, &[]));
    assert!(e.contains("irr.json") && e.contains("irradiance"), "{e}");
    let missing = dir.join("missing.obj");
    let e = shlight_err(&["volume", s(&missing), "--env", s(&env), "-o", s(&out)]);
    assert!(e.contains("missing.obj"), "{e}");
    assert!(!out.exists(), "nothing written on error");
    // A corrupt file is refused by the reader, naming it.
    std::fs::write(&out, b"{\"format\":\"shlight-volume\"}\n").unwrap();
    let e = ShvolFile::read(&out).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}: ", out.display())), "{e}");
}

/// A GLB of a 4 m floor (y = 0, facing +Y, no material) and a white point
/// light of `intensity` cd 1 m above its centre (`KHR_lights_punctual`),
/// assembled here: the JSON chunk, then the binary chunk of positions,
/// normals and indices.
fn floor_with_a_lamp_glb(intensity: f64) -> Vec<u8> {
    floor_tiles_with_a_lamp_glb(intensity, &[], false)
}

/// [`floor_with_a_lamp_glb`] with the floor placed again at each of
/// `more` (translations): by the same glTF mesh (`copies` false), or each
/// by a mesh of its own (the same accessors).
fn floor_tiles_with_a_lamp_glb(intensity: f64, more: &[[f32; 3]], copies: bool) -> Vec<u8> {
    let corners = [
        [-2.0f32, 0.0, -2.0],
        [2.0, 0.0, -2.0],
        [2.0, 0.0, 2.0],
        [-2.0, 0.0, 2.0],
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
    // (b - a) x (c - a) along +Y for both triangles.
    for i in [0u16, 3, 2, 0, 2, 1] {
        bin.extend(i.to_le_bytes());
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "name": "lamp", "intensity": intensity, "color": [1, 1, 1]}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": (0..more.len() + 2).collect::<Vec<_>>()}],
        "nodes": [
            {"mesh": 0},
            {"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-2, 0, -2], "max": [2, 0, 2]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let mut doc = doc;
    for (k, at) in more.iter().enumerate() {
        let mesh = if copies { k + 1 } else { 0 };
        if copies {
            let first = doc["meshes"][0].clone();
            doc["meshes"].as_array_mut().unwrap().push(first);
        }
        doc["nodes"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!({"mesh": mesh, "translation": at}));
    }
    glb(&doc, &bin)
}

#[test]
fn a_mesh_placed_by_several_nodes_bakes_through_two_levels_to_the_light_of_copies() {
    // Four floor tiles by one glTF mesh, placed by four nodes, and the same
    // tiles by four meshes of their own: the first bakes through the
    // unique tile and its instances (and says so), the second through one
    // hierarchy of every triangle; the probes see the same light.
    let dir = temp_dir("volume_gltf_instances");
    let env = dir.join("sky.json");
    let mut sky = [[0.0; 3]; 9];
    sky[0] = [1.0, 0.8, 0.6];
    sky[2] = [0.5, 0.4, 0.3];
    write_coefficient_rows(&env, &sky, "radiance");
    let more = [[4.0, 0.0, 0.0], [0.0, 0.0, 4.0], [4.0, 0.5, 4.0]];
    let bake = |copies: bool| {
        let scene = dir.join(if copies {
            "copies.glb"
        } else {
            "instances.glb"
        });
        std::fs::write(&scene, floor_tiles_with_a_lamp_glb(6830.0, &more, copies)).unwrap();
        let out = dir.join(if copies {
            "copies.json"
        } else {
            "instances.json"
        });
        let run = shlight_ok(&[
            "volume",
            s(&scene),
            "--env",
            s(&env),
            "--resolution",
            "3x2x3",
            "--bounces",
            "1",
            "--samples",
            "256",
            "--surface-samples",
            "32",
            "-o",
            s(&out),
        ]);
        let said = String::from_utf8_lossy(&run.stderr).into_owned();
        let rows: Vec<f64> = read_json(&out)["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|p| p.as_array().unwrap().clone())
            .flat_map(|r| [0, 1, 2].map(|c| r[c].as_f64().unwrap()))
            .collect();
        (said, rows)
    };
    let (said, instanced) = bake(false);
    assert!(
        said.contains("rays cast through its unique geometry (1 primitive, 2 triangles) placed 4 times, not through 8 flattened triangles"),
        "{said}"
    );
    let (said, copied) = bake(true);
    assert!(!said.contains("rays cast through"), "{said}");
    assert_eq!(instanced.len(), copied.len());
    assert_eq!(instanced.len(), 18 * 9 * 3);
    let max = copied.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(max > 1.0, "{max}");
    for (a, b) in instanced.iter().zip(&copied) {
        assert!((a - b).abs() <= 2e-4 * max, "{a} vs {b} of {max}");
    }
}

#[test]
fn a_gltf_lamp_lights_the_volume_in_the_units_asked_for() {
    // One probe 0.5 m above the floor, straight under a point light of
    // 683 x 10 cd (Blender's exporter's 10 W/sr), a black sky, a black
    // floor (only the lamp's own light): E_perp = 10 / 0.5^2 = 40 W/m2 from
    // +Y, so the probe's SH are 40 Y_lm(+Y): Y_00 = 1 / (2 sqrt(pi)), Y_1-1
    // = -sqrt(3 / (4 pi)) y (docs/conventions.md), Y_10 = Y_11 = 0.
    // `--light-units as-written` reads the intensity as 6830 W/sr: 683
    // times as much. A static file's probes hold the same light, and the
    // file and `shlight show` say which lights were baked.
    let dir = temp_dir("volume_gltf_lamp");
    let scene = dir.join("floor.glb");
    std::fs::write(&scene, floor_with_a_lamp_glb(6830.0)).unwrap();
    let env = dir.join("black.json");
    write_coefficient_rows(&env, &[[0.0; 3]; 9], "radiance");
    let bake = |units: &str, out: &Path, extra: &[&str]| {
        let mut args = vec![
            "volume",
            s(&scene),
            "--env",
            s(&env),
            "--resolution",
            "1x1x1",
            "--bounds",
            "-0.1,0.4,-0.1:0.1,0.6,0.1",
            "--no-relocate",
            "--no-visibility",
            "--albedo",
            "0",
            "--bounces",
            "0",
            "--samples",
            "256",
            "--surface-samples",
            "16",
            "--light-units",
            units,
            "-o",
            s(out),
        ];
        args.extend_from_slice(extra);
        let run = shlight_ok(&args);
        String::from_utf8_lossy(&run.stderr).into_owned()
    };
    let (blender, written, fixed) = (
        dir.join("blender.json"),
        dir.join("written.json"),
        dir.join("static.json"),
    );
    let said = bake("blender", &blender, &[]);
    assert!(
        said.contains(
            "1 punctual light (1 point, 0 spot, 0 directional), intensities divided by 683"
        ),
        "{said}"
    );
    bake("as-written", &written, &[]);
    bake("blender", &fixed, &["--static"]);
    let y00 = 0.5 / std::f64::consts::PI.sqrt();
    let y1 = -(3.0 / (4.0 * std::f64::consts::PI)).sqrt();
    let rows = |path: &Path| -> Vec<[f64; 3]> {
        read_json(path)["coefficients"][0]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| [0, 1, 2].map(|c| r[c].as_f64().unwrap()))
            .collect()
    };
    for (path, e) in [(&blender, 40.0), (&written, 683.0 * 40.0), (&fixed, 40.0)] {
        let got = rows(path);
        for (i, want) in [e * y00, e * y1, 0.0, 0.0].iter().enumerate() {
            for c in got[i] {
                assert!(
                    (c - want).abs() <= 1e-5 * e,
                    "{}: row {i}: {c} vs {want}",
                    path.display()
                );
            }
        }
    }
    let lights = &read_json(&blender)["lights"];
    assert_eq!(
        *lights,
        serde_json::json!({"units": "blender", "point": 1, "spot": 0, "directional": 0})
    );
    assert_eq!(read_json(&written)["lights"]["units"], "as-written");
    assert_eq!(read_json(&fixed)["lights"], *lights);
    let shown = shlight_ok(&["show", s(&blender)]);
    let shown = String::from_utf8_lossy(&shown.stdout);
    assert!(
        shown.contains("1 point, 0 spot, 0 directional (punctual, in the static light); intensities divided by 683 (blender)"),
        "{shown}"
    );
}

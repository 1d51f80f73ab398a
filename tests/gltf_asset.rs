//! `--format gltf` writes a complete glTF 2.0 asset, and
//! `shlight convert --into SCENE.gltf|glb` adds the light to an existing
//! asset without changing anything else in it.

use std::path::{Path, PathBuf};
use std::process::Command;

use base64::Engine as _;
use serde_json::{Value, json};

use crate::util::{glb, s, shlight_err, shlight_ok, skip, temp_dir, write_radiance_rows};

/// A light to add: a sun and a sky, nine radiance rows (y-up).
const LIGHT: [[f64; 3]; 9] = [
    [2.0, 1.8, 1.6],
    [-0.4, -0.3, -0.2],
    [0.3, 0.2, 0.1],
    [-0.5, -0.4, -0.3],
    [0.1, 0.05, 0.02],
    [-0.2, -0.1, -0.05],
    [0.15, 0.1, 0.05],
    [-0.1, -0.08, -0.06],
    [0.05, 0.04, 0.03],
];

/// A small glTF 2.0 asset of its own: one triangle (positions in an
/// embedded buffer), a node, a material, a second scene, an extension
/// shlight does not know, and extras.
fn scene_json() -> Value {
    json!({
        "asset": {"version": "2.0", "generator": "a modelling tool", "copyright": "CC0"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 1,
        "scenes": [{"name": "other", "nodes": [0]}, {"name": "main", "nodes": [0], "extras": {"keep": true}}],
        "nodes": [{"name": "tri", "mesh": 0, "translation": [0.25, 0.5, -1.5]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "materials": [{"name": "glow", "emissiveFactor": [1.0, 0.5, 0.25],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3.5}}}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36}],
    })
}

/// The triangle's positions, little-endian f32.
fn positions() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// The JSON and BIN chunks of a GLB, checked against its header.
fn glb_parts(bytes: &[u8]) -> (Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(&bytes[0..4], b"glTF");
    assert_eq!(word(4), 2);
    assert_eq!(word(8), bytes.len());
    let json_len = word(12);
    assert_eq!(&bytes[16..20], b"JSON");
    assert!(json_len.is_multiple_of(4));
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let at = 20 + json_len;
    let bin_len = word(at);
    assert_eq!(&bytes[at + 4..at + 8], b"BIN\0");
    (json, bytes[at + 8..at + 8 + bin_len].to_vec())
}

/// `after` without what `--into` adds must be `before`: the light list,
/// its entry in `extensionsUsed`, and the default scene's reference.
fn assert_only_the_light_was_added(before: &Value, after: &Value) {
    let mut stripped = after.clone();
    let lights = stripped["extensions"]
        .as_object_mut()
        .unwrap()
        .remove("EXT_lights_image_based")
        .expect("the light was added");
    assert_eq!(lights["lights"].as_array().unwrap().len(), 1);
    if stripped["extensions"].as_object().unwrap().is_empty() {
        stripped.as_object_mut().unwrap().remove("extensions");
    }
    let used = stripped["extensionsUsed"].as_array_mut().unwrap();
    let n = used.len();
    used.retain(|e| e != "EXT_lights_image_based");
    assert_eq!(used.len(), n - 1, "declared once in extensionsUsed");
    let scene = &mut stripped["scenes"][1];
    assert_eq!(scene["extensions"]["EXT_lights_image_based"]["light"], 0);
    scene.as_object_mut().unwrap().remove("extensions");
    assert_eq!(&stripped, before, "nothing else in the asset changed");
}

fn light_file(dir: &Path) -> PathBuf {
    let light = dir.join("light.json");
    write_radiance_rows(&light, &LIGHT);
    light
}

/// The coefficients `shlight convert FILE --format json` reads back.
fn read_back(path: &Path) -> Vec<[f64; 3]> {
    let out = shlight_ok(&["convert", s(path), "--format", "json"]);
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["quantity"], "irradiance");
    crate::util::coefficients(&v)
}

/// The irradiance rows of [`LIGHT`]: `A_l L_lm`.
fn light_irradiance() -> Vec<[f64; 3]> {
    let pi = std::f64::consts::PI;
    let a = [pi, 2.0 * pi / 3.0, 2.0 * pi / 3.0, 2.0 * pi / 3.0];
    LIGHT
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let w = if i < 4 { a[i] } else { pi / 4.0 };
            [c[0] * w, c[1] * w, c[2] * w]
        })
        .collect()
}

#[test]
fn into_a_gltf_adds_the_light_and_changes_nothing_else() {
    let dir = temp_dir("gltf_into");
    let light = light_file(&dir);
    let scene = dir.join("scene.gltf");
    let mut doc = scene_json();
    doc["buffers"][0]["uri"] = json!(format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(positions())
    ));
    std::fs::write(&scene, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    shlight_ok(&[
        "convert",
        s(&light),
        "--into",
        s(&scene),
        "--irradiance-only",
    ]);
    let after: Value = serde_json::from_slice(&std::fs::read(&scene).unwrap()).unwrap();
    assert_only_the_light_was_added(&doc, &after);
    crate::util::assert_rows_near(
        &read_back(&scene),
        &light_irradiance(),
        1e-12,
        "light read back",
    );
    // Twice gives one light, replaced.
    shlight_ok(&[
        "convert",
        s(&light),
        "--into",
        s(&scene),
        "-q",
        "--irradiance-only",
    ]);
    let again: Value = serde_json::from_slice(&std::fs::read(&scene).unwrap()).unwrap();
    assert_eq!(again, after);
    validate(
        &scene,
        "gltf_asset::into_a_gltf_adds_the_light_and_changes_nothing_else",
    );
}

#[test]
fn into_a_glb_keeps_the_binary_chunk_byte_for_byte() {
    let dir = temp_dir("gltf_into_glb");
    let light = light_file(&dir);
    let scene = dir.join("scene.glb");
    let mut doc = scene_json();
    // 36 bytes of positions and 4 more the buffer holds but nothing uses.
    let mut bin = positions();
    bin.extend([7, 7, 7, 7]);
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    std::fs::write(&scene, glb(&doc, &bin)).unwrap();
    shlight_ok(&[
        "convert",
        s(&light),
        "--into",
        s(&scene),
        "--irradiance-only",
    ]);
    let (after, after_bin) = glb_parts(&std::fs::read(&scene).unwrap());
    assert_eq!(after_bin, bin);
    assert_only_the_light_was_added(&doc, &after);
    crate::util::assert_rows_near(
        &read_back(&scene),
        &light_irradiance(),
        1e-12,
        "light read back from the GLB",
    );
    validate(
        &scene,
        "gltf_asset::into_a_glb_keeps_the_binary_chunk_byte_for_byte",
    );
}

#[test]
fn into_refuses_what_is_not_a_gltf_2_asset_and_leaves_it_alone() {
    let dir = temp_dir("gltf_into_bad");
    let light = light_file(&dir);
    for (name, content) in [
        ("old.gltf", r#"{"asset": {"version": "1.0"}}"#),
        ("none.gltf", r#"{"scenes": []}"#),
        ("text.gltf", "not json"),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, content).unwrap();
        let err = shlight_err(&[
            "convert",
            s(&light),
            "--into",
            s(&path),
            "--irradiance-only",
        ]);
        assert!(err.contains(name), "{err}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), content);
    }
    let glb_path = dir.join("short.glb");
    let mut bytes = glb(&scene_json(), &positions());
    bytes.truncate(bytes.len() - 5);
    std::fs::write(&glb_path, &bytes).unwrap();
    let err = shlight_err(&[
        "convert",
        s(&light),
        "--into",
        s(&glb_path),
        "--irradiance-only",
    ]);
    assert!(err.contains("short.glb") && err.contains("GLB"), "{err}");
    assert_eq!(std::fs::read(&glb_path).unwrap(), bytes);
}

/// `project MAP --format gltf` writes the light whole (coefficients and
/// specular images); the validator finds no error in it, nor in the light
/// `convert --irradiance-only` writes from coefficients, which plain
/// `convert` refuses, naming what is missing.
#[test]
fn format_gltf_is_a_valid_gltf_2_asset() {
    let dir = temp_dir("gltf_format");
    let map = dir.join("sky.exr");
    crate::util::write_map(&map, 64, 32, |x, y| {
        [1.0 + x as f32 / 64.0, 0.5 + y as f32 / 32.0, 0.25]
    });
    let out = dir.join("light.gltf");
    shlight_ok(&[
        "project",
        s(&map),
        "--format",
        "gltf",
        "-o",
        s(&out),
        "--specular-size",
        "16",
        "-q",
    ]);
    let v: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(v["asset"]["version"], "2.0");
    assert_eq!(
        v["scenes"][0]["extensions"]["EXT_lights_image_based"]["light"],
        0
    );
    let light = &v["extensions"]["EXT_lights_image_based"]["lights"][0];
    assert_eq!(light["specularImageSize"], 16);
    // 16, 8, 4, 2, 1: five mips of six faces, each an image.
    let mips = light["specularImages"].as_array().unwrap();
    assert_eq!(mips.len(), 5);
    assert!(mips.iter().all(|m| m.as_array().unwrap().len() == 6));
    assert_eq!(v["images"].as_array().unwrap().len(), 30);
    validate(&out, "gltf_asset::format_gltf_is_a_valid_gltf_2_asset");

    let light_file = light_file(&dir);
    let err = shlight_err(&["convert", s(&light_file), "-o", s(&dir.join("c.gltf"))]);
    assert!(
        err.contains("light.json") && err.contains("specularImages"),
        "{err}"
    );
    let irradiance_only = dir.join("irradiance-only.gltf");
    shlight_ok(&[
        "convert",
        s(&light_file),
        "-o",
        s(&irradiance_only),
        "--irradiance-only",
        "-q",
    ]);
    validate(
        &irradiance_only,
        "gltf_asset::format_gltf_is_a_valid_gltf_2_asset",
    );
}

/// Where `.ci/run` installs the Khronos glTF validator (npm
/// `gltf-validator`), unless `SHLIGHT_GLTF_VALIDATOR` names its folder.
fn validator_dir() -> PathBuf {
    std::env::var_os("SHLIGHT_GLTF_VALIDATOR").map_or_else(
        || {
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("target/gltf-validator/node_modules/gltf-validator")
        },
        PathBuf::from,
    )
}

/// Runs the Khronos glTF validator on `path` and fails on any error it
/// reports; skips loudly where it is not installed (fails instead under
/// `SHLIGHT_REQUIRE_ALL=1`, which CI sets).
fn validate(path: &Path, test: &str) {
    let validator = validator_dir();
    if !validator.join("package.json").exists() {
        let why = format!(
            "the glTF validator is not at {} (npm install --prefix target/gltf-validator gltf-validator)",
            validator.display()
        );
        skip(test, &why);
        return;
    }
    let script = r#"
const fs = require('fs');
const validator = require(process.argv[1]);
const bytes = new Uint8Array(fs.readFileSync(process.argv[2]));
validator.validateBytes(bytes, { uri: process.argv[2], maxIssues: 0 }).then((r) => {
    console.log(JSON.stringify({ errors: r.issues.numErrors, warnings: r.issues.numWarnings,
        messages: r.issues.messages.filter((m) => m.severity <= 1) }));
}, (e) => { console.error(String(e)); process.exit(2); });
"#;
    let out = match Command::new("node")
        .arg("-e")
        .arg(script)
        .arg(&validator)
        .arg(path)
        .output()
    {
        Ok(out) => out,
        Err(e) => {
            skip(test, &format!("node is not installed ({e})"));
            return;
        }
    };
    assert!(
        out.status.success(),
        "the validator failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        report["errors"],
        0,
        "{}: the glTF validator reports {}",
        path.display(),
        report
    );
    assert_eq!(report["warnings"], 0, "{}: {}", path.display(), report);
}

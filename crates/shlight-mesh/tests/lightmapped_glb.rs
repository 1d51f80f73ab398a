//! The lightmapped GLB writer, read back by the `gltf` crate (validation,
//! its accessor reader) and by hand from the GLB's chunks: the original
//! data byte for byte, the new images, `MOZ_lightmap` and
//! `SHLIGHT_lightmap` where asked, unshared `TEXCOORD_1` against
//! `uv * scale + offset` of the input's integers, and shlight's scene
//! loader finding the same triangles.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use base64::Engine as _;
use glam::Vec3;
use serde_json::{Value, json};
use shlight_io::{Ktx2TexelFormat, encode_ktx2, encode_png_rgba8};
use shlight_mesh::{
    BakedNode, LightmapImage, LightmapImageFormat, LightmapRequest, LoadOptions, MeshError,
    load_scene, write_lightmapped_glb,
};

/// A fresh directory under the target's test directory.
fn temp_dir(name: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("lightmapped-glb-{name}-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A GLB's JSON and BIN chunks.
fn split(glb: &[u8]) -> (Value, Vec<u8>) {
    assert_eq!(&glb[..4], b"glTF");
    let word = |at: usize| u32::from_le_bytes(glb[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(word(4), 2);
    assert_eq!(word(8), glb.len());
    let json_len = word(12);
    assert_eq!(&glb[16..20], b"JSON");
    let json = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let at = 20 + json_len;
    assert_eq!(&glb[at + 4..at + 8], b"BIN\0");
    let bin = glb[at + 8..at + 8 + word(at)].to_vec();
    (json, bin)
}

/// A GLB of `json` and `bin`.
fn glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    j.resize(j.len().next_multiple_of(4), b' ');
    let mut b = bin.to_vec();
    b.resize(b.len().next_multiple_of(4), 0);
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&b);
    out
}

/// The bytes of buffer view `view` of a document whose buffers hold
/// `buffers`.
fn view_bytes<'a>(json: &Value, buffers: &'a [Vec<u8>], view: usize) -> &'a [u8] {
    let v = &json["bufferViews"][view];
    let offset = v["byteOffset"].as_u64().unwrap_or(0) as usize;
    let length = v["byteLength"].as_u64().unwrap() as usize;
    &buffers[v["buffer"].as_u64().unwrap() as usize][offset..offset + length]
}

/// The world-space triangles of a scene file, as shlight's loader reads
/// them.
fn triangles(path: &Path) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let scene = load_scene(path, &LoadOptions::default()).unwrap();
    let mesh = scene.flatten(Vec3::ONE).unwrap().mesh;
    (mesh.positions, mesh.triangles)
}

/// The document as the `gltf` crate validates it (the input's
/// `KHR_mesh_quantization`, which the crate does not list as supported,
/// taken out of `extensionsRequired` first, as shlight's loader does).
fn validate(glb: &[u8]) -> gltf::Document {
    let (json, _) = split(glb);
    let mut root: gltf::json::Root = serde_json::from_value(json).unwrap();
    root.extensions_required
        .retain(|e| e != "KHR_mesh_quantization");
    gltf::Document::from_json(root).expect("a valid glTF document")
}

/// The `gltf` crate's reading of `TEXCOORD_1` of mesh `mesh`'s first
/// primitive, as floats.
fn texcoord_1(glb: &[u8], mesh: usize) -> Vec<[f32; 2]> {
    let document = validate(glb);
    let (_, blob) = split(glb);
    let m = document.meshes().nth(mesh).unwrap();
    let p = m.primitives().next().unwrap();
    let reader = p.reader(|b| (b.index() == 0).then_some(&blob[..]));
    reader.read_tex_coords(1).unwrap().into_f32().collect()
}

fn png(name: &str) -> Vec<u8> {
    let rgba: Vec<u8> = (0..4 * 4 * 2).map(|i| (i * 37 % 256) as u8).collect();
    encode_png_rgba8(name, 4, 2, &rgba).unwrap()
}

fn ktx2() -> Vec<u8> {
    let texels: Vec<[f32; 4]> = (0..8).map(|i| [i as f32, 0.5, 2.0, 1.0]).collect();
    encode_ktx2(Ktx2TexelFormat::Rgba16Float, 4, 2, &texels).unwrap()
}

/// `tests/scenes/instances.glb` with `TEXCOORD_1` added: the chair's (one
/// mesh, three nodes) as normalized unsigned shorts
/// (`KHR_mesh_quantization`), the floor's and ceiling's their
/// `TEXCOORD_0`. Gives the file and the chair's integers.
fn instances_with_uv1(dir: &Path) -> (PathBuf, Vec<[u16; 2]>) {
    let original = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/scenes/instances.glb"),
    )
    .unwrap();
    let (mut json, mut bin) = split(&original);
    let chair = 3;
    let position = json["meshes"][chair]["primitives"][0]["attributes"]["POSITION"]
        .as_u64()
        .unwrap() as usize;
    let count = json["accessors"][position]["count"].as_u64().unwrap() as usize;
    let quantized: Vec<[u16; 2]> = (0..count)
        .map(|i| {
            [
                (i * 7919 % 65536) as u16,
                (65535 - i * 104_729 % 65536) as u16,
            ]
        })
        .collect();
    bin.resize(bin.len().next_multiple_of(4), 0);
    let offset = bin.len();
    bin.extend(quantized.iter().flatten().flat_map(|v| v.to_le_bytes()));
    let view = json["bufferViews"].as_array().unwrap().len();
    json["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 4 * count}));
    let accessor = json["accessors"].as_array().unwrap().len();
    json["accessors"].as_array_mut().unwrap().push(json!({
        "bufferView": view, "componentType": 5123, "normalized": true,
        "count": count, "type": "VEC2",
    }));
    json["meshes"][chair]["primitives"][0]["attributes"]["TEXCOORD_1"] = accessor.into();
    for mesh in [1, 2] {
        let uv0 = json["meshes"][mesh]["primitives"][0]["attributes"]["TEXCOORD_0"].clone();
        json["meshes"][mesh]["primitives"][0]["attributes"]["TEXCOORD_1"] = uv0;
    }
    for list in ["extensionsUsed", "extensionsRequired"] {
        json[list]
            .as_array_mut()
            .unwrap()
            .push("KHR_mesh_quantization".into());
    }
    json["buffers"][0]["byteLength"] = bin.len().into();
    let path = dir.join("instances_uv1.glb");
    std::fs::write(&path, glb(&json, &bin)).unwrap();
    (path, quantized)
}

fn node(node: usize, image: usize, unshare: bool, rect: [f32; 4]) -> BakedNode {
    BakedNode {
        node,
        scale: [rect[0], rect[1]],
        offset: [rect[2], rect[3]],
        image: Some(image),
        unshare,
        extension: json!({"page": image, "rect": rect, "node": node}),
    }
}

#[test]
fn instances_keep_their_data_and_gain_lightmaps() {
    let dir = temp_dir("instances");
    let (input, quantized) = instances_with_uv1(&dir);
    let output = dir.join("lit.glb");
    let rects = [
        [0.5, 0.5, 0.0, 0.0],
        [0.25, 0.5, 0.5, 0.0],
        [0.25, 0.25, 0.75, 0.5],
        [0.5, 0.25, 0.0, 0.75],
        [0.125, 0.125, 0.5, 0.5],
        [1.0, 1.0, 0.0, 0.0],
    ];
    let request = LightmapRequest {
        images: vec![
            LightmapImage {
                name: "page0".into(),
                format: LightmapImageFormat::Png,
                bytes: png("page0"),
                intensity: 2.5,
            },
            LightmapImage {
                name: "page1".into(),
                format: LightmapImageFormat::Ktx2,
                bytes: ktx2(),
                intensity: 1.0,
            },
        ],
        nodes: vec![
            node(0, 0, false, rects[5]), // the walls: no TEXCOORD_1
            node(1, 0, false, rects[0]),
            node(2, 1, false, rects[1]),
            node(3, 0, true, rects[2]),
            node(4, 1, true, rects[3]),
            node(5, 0, true, rects[4]),
        ],
        root_extension: json!({"basis": "irradiance", "units": "E"}),
        load_options: LoadOptions::default(),
    };
    let made = write_lightmapped_glb(&input, &output, &request).unwrap();
    let bytes = std::fs::read(&output).unwrap();
    validate(&bytes);
    let (before, bin_before) = split(&std::fs::read(&input).unwrap());
    let (after, bin_after) = split(&bytes);

    // Every original buffer view's bytes and every original accessor as
    // they were.
    let views = before["bufferViews"].as_array().unwrap().len();
    for v in 0..views {
        assert_eq!(
            view_bytes(&before, std::slice::from_ref(&bin_before), v),
            view_bytes(&after, std::slice::from_ref(&bin_after), v),
            "buffer view {v}"
        );
        let (a, b) = (&before["bufferViews"][v], &after["bufferViews"][v]);
        assert_eq!(
            (&a["byteStride"], &a["target"]),
            (&b["byteStride"], &b["target"])
        );
    }
    for (i, a) in before["accessors"].as_array().unwrap().iter().enumerate() {
        assert_eq!(a, &after["accessors"][i], "accessor {i}");
    }
    // Everything else the input held.
    for key in ["asset", "scene", "scenes", "extensionsRequired"] {
        assert_eq!(before[key], after[key], "{key}");
    }
    assert_eq!(
        before["extensions"]["KHR_lights_punctual"],
        after["extensions"]["KHR_lights_punctual"]
    );
    assert_eq!(before["nodes"][6], after["nodes"][6], "the lamp");
    assert_eq!(after["buffers"].as_array().unwrap().len(), 1);

    // The new images, textures and sampler.
    let images = after["images"].as_array().unwrap();
    assert_eq!(images.len(), 2);
    for (k, (image, given)) in images.iter().zip(&request.images).enumerate() {
        let v = image["bufferView"].as_u64().unwrap() as usize;
        assert_eq!(
            view_bytes(&after, std::slice::from_ref(&bin_after), v),
            &given.bytes[..],
            "image {k}"
        );
        assert_eq!(image["name"], given.name.as_str());
        let texture = &after["textures"][made.textures[k]];
        let sampler = &after["samplers"][texture["sampler"].as_u64().unwrap() as usize];
        assert_eq!(
            sampler,
            &json!({"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071})
        );
        match given.format {
            LightmapImageFormat::Png => {
                assert_eq!(image["mimeType"], "image/png");
                assert_eq!(texture["source"], k);
            }
            LightmapImageFormat::Ktx2 => {
                assert_eq!(image["mimeType"], "image/ktx2");
                assert!(texture.get("source").is_none());
                assert_eq!(texture["extensions"]["KHR_texture_basisu"]["source"], k);
            }
        }
    }
    let used: Vec<&str> = after["extensionsUsed"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    for name in [
        "MOZ_lightmap",
        "SHLIGHT_lightmap",
        "KHR_texture_basisu",
        "KHR_materials_specular",
    ] {
        assert!(used.contains(&name), "{name} in {used:?}");
    }

    // SHLIGHT_lightmap on each baked node and the root.
    for n in &request.nodes {
        assert_eq!(
            after["nodes"][n.node]["extensions"]["SHLIGHT_lightmap"],
            n.extension
        );
    }
    assert_eq!(
        after["extensions"]["SHLIGHT_lightmap"],
        request.root_extension
    );

    // MOZ_lightmap where baked: the walls (no TEXCOORD_1) without.
    let material_of = |node: usize| {
        let mesh = after["nodes"][node]["mesh"].as_u64().unwrap() as usize;
        after["meshes"][mesh]["primitives"][0]["material"]
            .as_u64()
            .unwrap() as usize
    };
    let moz =
        |node: usize| after["materials"][material_of(node)]["extensions"]["MOZ_lightmap"].clone();
    let expected = |image: usize| {
        json!({"index": made.textures[image], "texCoord": 1,
               "intensity": request.images[image].intensity})
    };
    for m in [0, 1] {
        assert!(
            after["materials"][m]["extensions"]
                .get("MOZ_lightmap")
                .is_none()
        );
    }
    assert_eq!(made.notes.len(), 2, "{:?}", made.notes);
    assert!(
        made.notes
            .iter()
            .all(|n| n.contains("mesh 0") && n.contains("TEXCOORD_1"))
    );
    assert_eq!(moz(1), expected(0));
    assert_eq!(moz(2), expected(1));
    assert_eq!(moz(3), expected(0));
    assert_eq!(moz(4), expected(1));
    assert_eq!(moz(5), expected(0));
    assert_eq!(material_of(3), material_of(5), "one copy per image");
    assert_ne!(material_of(3), material_of(4));
    let copy = &after["materials"][material_of(4)];
    assert_eq!(
        copy["pbrMetallicRoughness"],
        before["materials"][4]["pbrMetallicRoughness"]
    );
    assert_eq!(
        copy["extensions"]["KHR_materials_specular"],
        before["materials"][4]["extensions"]["KHR_materials_specular"]
    );

    // Each chair its own mesh, its TEXCOORD_1 the rectangle applied to the
    // input's integers; other attributes shared.
    let chair = &before["meshes"][3]["primitives"][0]["attributes"];
    for (k, n) in [3, 4, 5].into_iter().enumerate() {
        let mesh = made.meshes[n];
        assert_eq!(after["nodes"][n]["mesh"], mesh);
        assert!(mesh >= 4, "a new mesh");
        let attributes = &after["meshes"][mesh]["primitives"][0]["attributes"];
        assert_eq!(attributes["POSITION"], chair["POSITION"]);
        assert_eq!(attributes["NORMAL"], chair["NORMAL"]);
        let rect = rects[2 + k];
        let read = texcoord_1(&bytes, mesh);
        assert_eq!(read.len(), quantized.len());
        for (uv, q) in read.iter().zip(&quantized) {
            for c in 0..2 {
                let want = f64::from(q[c]) / 65535.0 * f64::from(rect[c]) + f64::from(rect[2 + c]);
                assert!((f64::from(uv[c]) - want).abs() < 1e-6, "{uv:?} vs {want}");
            }
        }
    }
    // The floor and ceiling keep their shared TEXCOORD_1.
    assert_eq!(made.meshes[1..3], [1, 2]);

    assert_eq!(triangles(&input), triangles(&output));
}

#[test]
fn a_gltf_with_external_and_data_uri_buffers_becomes_one_glb() {
    let dir = temp_dir("external");
    // Buffer 0 (geo.bin): a quad's positions, then its indices. Buffer 1
    // (a data URI): its TEXCOORD_0 then TEXCOORD_1, floats.
    let positions: [[f32; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let uv1: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let mut geo: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    geo.extend(indices.iter().flat_map(|v| v.to_le_bytes()));
    let mut uvs: Vec<u8> = uv1
        .iter()
        .rev()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    uvs.extend(uv1.iter().flatten().flat_map(|v| v.to_le_bytes()));
    std::fs::write(dir.join("geo.bin"), &geo).unwrap();
    let tex = png("tex");
    std::fs::write(dir.join("tex.png"), &tex).unwrap();
    let b64 = |b: &[u8]| base64::engine::general_purpose::STANDARD.encode(b);
    let inline_png = png("inline");
    let doc = json!({
        "asset": {"version": "2.0", "extras": {"kept": true}},
        "extensionsUsed": ["EXT_unknown_to_shlight"],
        "extensions": {"EXT_unknown_to_shlight": {"x": 1}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0, "name": "lit", "extras": {"tag": 7}},
            {"mesh": 1, "translation": [0.0, 0.0, 2.0]}
        ],
        "meshes": [
            {"name": "quad", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 2, "TEXCOORD_1": 3}, "indices": 1, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_1": 3}, "indices": 1}]}
        ],
        "materials": [{"name": "painted", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}],
        "textures": [{"source": 0}, {"source": 1}],
        "images": [{"uri": "tex.png"}, {"uri": format!("data:image/png;base64,{}", b64(&inline_png))}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "byteOffset": 32, "componentType": 5126, "count": 4, "type": "VEC2"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 12},
            {"buffer": 1, "byteLength": 64}
        ],
        "buffers": [
            {"uri": "geo.bin", "byteLength": geo.len()},
            {"uri": format!("data:application/octet-stream;base64,{}", b64(&uvs)), "byteLength": uvs.len()}
        ]
    });
    let input = dir.join("scene.gltf");
    std::fs::write(&input, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let output = dir.join("scene.glb");
    let request = LightmapRequest {
        images: vec![LightmapImage {
            name: "lm".into(),
            format: LightmapImageFormat::Ktx2,
            bytes: ktx2(),
            intensity: 3.0,
        }],
        nodes: vec![
            node(0, 0, true, [0.5, 0.25, 0.5, 0.75]),
            node(1, 0, false, [0.5, 0.5, 0.0, 0.0]),
        ],
        root_extension: json!({"packing": "three"}),
        load_options: LoadOptions::default(),
    };
    let made = write_lightmapped_glb(&input, &output, &request).unwrap();
    assert!(made.notes.is_empty(), "{:?}", made.notes);
    let bytes = std::fs::read(&output).unwrap();
    validate(&bytes);
    let (after, bin) = split(&bytes);
    let bin = vec![bin];

    // One buffer, no URI left; every original view's bytes as they were.
    assert_eq!(after["buffers"], json!([{"byteLength": bin[0].len()}]));
    let before_buffers = [geo.clone(), uvs.clone()];
    for v in 0..3 {
        assert_eq!(
            view_bytes(&doc, &before_buffers, v),
            view_bytes(&after, &bin, v),
            "view {v}"
        );
    }
    for i in 0..4 {
        assert_eq!(doc["accessors"][i], after["accessors"][i], "accessor {i}");
    }
    // The external and data-URI images embedded, with their MIME type.
    for (i, given) in [&tex, &inline_png].into_iter().enumerate() {
        let image = &after["images"][i];
        assert!(image.get("uri").is_none());
        assert_eq!(image["mimeType"], "image/png");
        let v = image["bufferView"].as_u64().unwrap() as usize;
        assert_eq!(view_bytes(&after, &bin, v), &given[..], "image {i}");
    }
    let lm = &after["images"][2];
    assert_eq!(
        view_bytes(&after, &bin, lm["bufferView"].as_u64().unwrap() as usize),
        &request.images[0].bytes[..]
    );
    // What shlight does not model, kept.
    assert_eq!(after["asset"], doc["asset"]);
    assert_eq!(
        after["extensions"]["EXT_unknown_to_shlight"],
        json!({"x": 1})
    );
    assert_eq!(after["nodes"][0]["extras"], json!({"tag": 7}));
    assert_eq!(after["nodes"][0]["name"], "lit");
    assert_eq!(after["nodes"][1]["translation"], json!([0.0, 0.0, 2.0]));
    // The painted material is used only by the baked, unshared quad: given
    // the lightmap in place; the material-less quad gets a new default one.
    let texture = made.textures[0];
    let moz = json!({"index": texture, "texCoord": 1, "intensity": 3.0});
    let quad = made.meshes[0];
    assert_eq!(quad, 2);
    assert_eq!(after["meshes"][quad]["primitives"][0]["material"], 0);
    assert_eq!(after["materials"][0]["extensions"]["MOZ_lightmap"], moz);
    assert_eq!(
        after["materials"][0]["pbrMetallicRoughness"],
        doc["materials"][0]["pbrMetallicRoughness"]
    );
    let default = after["meshes"][1]["primitives"][0]["material"]
        .as_u64()
        .unwrap() as usize;
    assert_eq!(default, 1);
    assert_eq!(after["materials"][1]["extensions"]["MOZ_lightmap"], moz);
    assert!(after["materials"][1].get("pbrMetallicRoughness").is_none());
    // The unshared quad's TEXCOORD_1: the rectangle applied.
    let read = texcoord_1(&bytes, quad);
    for (uv, given) in read.iter().zip(&uv1) {
        assert_eq!(uv[0], (f64::from(given[0]) * 0.5 + 0.5) as f32);
        assert_eq!(uv[1], (f64::from(given[1]) * 0.25 + 0.75) as f32);
    }
    assert_eq!(triangles(&input), triangles(&output));
}

#[test]
fn bad_requests_and_paths_are_errors_naming_the_file() {
    let dir = temp_dir("errors");
    let (input, _) = instances_with_uv1(&dir);
    let output = dir.join("out.glb");
    let image = || LightmapImage {
        name: "p".into(),
        format: LightmapImageFormat::Png,
        bytes: png("p"),
        intensity: 1.0,
    };
    let cases = [
        (
            vec![node(9, 0, false, [1.0; 4])],
            "node 9, which does not exist",
        ),
        (
            vec![node(6, 0, false, [1.0; 4])],
            "node 6, which places no mesh",
        ),
        (
            vec![node(1, 3, false, [1.0; 4])],
            "lightmap image 3, which does not exist",
        ),
        (
            vec![node(1, 0, false, [1.0; 4]), node(1, 0, true, [1.0; 4])],
            "node 1 twice",
        ),
        (
            vec![node(3, 0, false, [1.0; 4]), node(4, 1, false, [1.0; 4])],
            "nodes 3 and 4 place mesh 3 with different lightmap images",
        ),
    ];
    for (nodes, message) in cases {
        let request = LightmapRequest {
            images: vec![image(), image()],
            nodes,
            root_extension: Value::Null,
            load_options: LoadOptions::default(),
        };
        let e = write_lightmapped_glb(&input, &output, &request).unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, MeshError::Invalid { .. }), "{e:?}");
        assert!(text.starts_with(&input.display().to_string()), "{text}");
        assert!(text.contains(message), "{text}");
    }
    assert!(!output.exists());

    let request = LightmapRequest {
        images: vec![image()],
        nodes: vec![node(1, 0, false, [1.0; 4])],
        root_extension: Value::Null,
        load_options: LoadOptions::default(),
    };
    let unwritable = dir.join("missing-dir").join("out.glb");
    let e = write_lightmapped_glb(&input, &unwritable, &request).unwrap_err();
    assert!(matches!(e, MeshError::Write(_)), "{e:?}");
    assert!(
        e.to_string().starts_with(&unwritable.display().to_string()),
        "{e}"
    );
    let missing = dir.join("nothing.glb");
    let e = write_lightmapped_glb(&missing, &output, &request).unwrap_err();
    assert!(
        e.to_string().starts_with(&missing.display().to_string()),
        "{e}"
    );
}

/// A `.gltf` whose positions, indices and `TEXCOORD_1` are
/// `EXT_meshopt_compression` views: the compressed bytes in data-URI
/// buffers 0 and 2, decoded into fallback buffer 1. The output re-points
/// the compressed sources into the BIN chunk, keeps the fallback, and the
/// unshared `TEXCOORD_1` is read decompressed.
#[test]
fn meshopt_compressed_views_are_re_pointed_and_read() {
    let dir = temp_dir("meshopt");
    let positions: [[f32; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.25],
    ];
    let uv1: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.5, 0.75]];
    let indices = [0u32, 1, 2, 0, 2, 3];
    let vertices = meshopt::encoding::encode_vertex_buffer(&positions).unwrap();
    let index_stream = meshopt::encoding::encode_index_buffer(&indices, 4).unwrap();
    let uvs = meshopt::encoding::encode_vertex_buffer(&uv1).unwrap();
    let mut first = vertices.clone();
    first.resize(first.len().next_multiple_of(4), 0);
    let at = first.len();
    first.extend(&index_stream);
    let b64 = |b: &[u8]| base64::engine::general_purpose::STANDARD.encode(b);
    let compressed = |buffer: usize,
                      offset: usize,
                      length: usize,
                      stride: usize,
                      count: usize,
                      mode: &str| {
        json!({"EXT_meshopt_compression": {"buffer": buffer, "byteOffset": offset, "byteLength": length,
               "byteStride": stride, "count": count, "mode": mode}})
    };
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["EXT_meshopt_compression"],
        "extensionsRequired": ["EXT_meshopt_compression"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_1": 2}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0.25]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}
        ],
        "bufferViews": [
            {"buffer": 1, "byteOffset": 0, "byteLength": 48, "byteStride": 12,
             "extensions": compressed(0, 0, vertices.len(), 12, 4, "ATTRIBUTES")},
            {"buffer": 1, "byteOffset": 48, "byteLength": 12,
             "extensions": compressed(0, at, index_stream.len(), 2, 6, "TRIANGLES")},
            {"buffer": 1, "byteOffset": 60, "byteLength": 32, "byteStride": 8,
             "extensions": compressed(2, 0, uvs.len(), 8, 4, "ATTRIBUTES")}
        ],
        "buffers": [
            {"uri": format!("data:application/octet-stream;base64,{}", b64(&first)), "byteLength": first.len()},
            {"byteLength": 92, "extensions": {"EXT_meshopt_compression": {"fallback": true}}},
            {"uri": format!("data:application/octet-stream;base64,{}", b64(&uvs)), "byteLength": uvs.len()}
        ]
    });
    let input = dir.join("packed.gltf");
    std::fs::write(&input, serde_json::to_vec(&doc).unwrap()).unwrap();
    let output = dir.join("packed.glb");
    let request = LightmapRequest {
        images: vec![LightmapImage {
            name: "lm".into(),
            format: LightmapImageFormat::Png,
            bytes: png("lm"),
            intensity: 1.0,
        }],
        nodes: vec![node(0, 0, true, [0.5, 0.5, 0.25, 0.5])],
        root_extension: json!({}),
        load_options: LoadOptions::default(),
    };
    let made = write_lightmapped_glb(&input, &output, &request).unwrap();
    let bytes = std::fs::read(&output).unwrap();
    let (after, bin) = split(&bytes);
    // The merged buffer, then the fallback as it was.
    assert_eq!(after["buffers"][1], doc["buffers"][1]);
    assert_eq!(after["buffers"].as_array().unwrap().len(), 2);
    for (v, given) in [(0, &vertices), (1, &index_stream), (2, &uvs)] {
        let ext = &after["bufferViews"][v]["extensions"]["EXT_meshopt_compression"];
        assert_eq!(ext["buffer"], 0, "view {v}");
        let offset = ext["byteOffset"].as_u64().unwrap() as usize;
        assert_eq!(&bin[offset..offset + given.len()], &given[..], "view {v}");
        assert_eq!(after["bufferViews"][v]["buffer"], 1);
    }
    // shlight's loader reads the output: the same triangles, and the
    // unshared TEXCOORD_1 (a plain float accessor) moved into the rectangle.
    assert_eq!(triangles(&input), triangles(&output));
    let scene = load_scene(&output, &LoadOptions::default()).unwrap();
    let moved: Vec<[f32; 2]> = scene.primitives[0].uvs[1]
        .iter()
        .map(|v| v.to_array())
        .collect();
    let want: Vec<[f32; 2]> = uv1
        .iter()
        .map(|[u, v]| {
            [
                (f64::from(*u) * 0.5 + 0.25) as f32,
                (f64::from(*v) * 0.5 + 0.5) as f32,
            ]
        })
        .collect();
    assert_eq!(moved, want);
    assert_eq!(made.meshes, [1]);
}

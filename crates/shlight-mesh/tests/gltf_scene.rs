//! glTF files read as scenes (`load_scene_bytes`): assets built here in
//! code, each checked against values worked out by hand (transforms,
//! texels, the specification's examples), not against the loader itself.

use std::f32::consts::{FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_4};
use std::path::Path;

use base64::Engine as _;
use glam::{Vec2, Vec3, Vec4};
use serde_json::{Value, json};
use shlight_mesh::{
    AlphaMode, LightKind, LoadOptions, MeshError, MeshFormat, Scene, load_bytes, load_scene,
    load_scene_bytes,
};

/// A glTF asset under construction: its JSON and its one binary buffer.
struct Asset {
    json: Value,
    bin: Vec<u8>,
}

impl Asset {
    fn new() -> Self {
        Self {
            json: json!({
                "asset": {"version": "2.0"},
                "scene": 0,
                "scenes": [{"nodes": []}],
                "nodes": [], "meshes": [], "accessors": [], "bufferViews": [],
                "buffers": [{"byteLength": 0}],
            }),
            bin: Vec::new(),
        }
    }

    fn push(&mut self, key: &str, value: Value) -> usize {
        let list = self.json[key].as_array_mut().unwrap();
        list.push(value);
        list.len() - 1
    }

    /// A buffer view of `bytes` (4-byte aligned).
    fn view(&mut self, bytes: &[u8]) -> usize {
        let offset = self.bin.len();
        self.bin.extend(bytes);
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        self.json["buffers"][0]["byteLength"] = self.bin.len().into();
        self.push(
            "bufferViews",
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}),
        )
    }

    /// An accessor of `count` elements of `ty` over `bytes`, with extra
    /// fields (`normalized`, `min`, `max`).
    fn accessor(
        &mut self,
        bytes: &[u8],
        component: u32,
        ty: &str,
        count: usize,
        extra: Value,
    ) -> usize {
        let view = self.view(bytes);
        let mut a =
            json!({"bufferView": view, "componentType": component, "count": count, "type": ty});
        for (k, v) in extra.as_object().unwrap() {
            a[k] = v.clone();
        }
        self.push("accessors", a)
    }

    fn floats(&mut self, values: &[f32], ty: &str, extra: Value) -> usize {
        let n = match ty {
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 1,
        };
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.accessor(&bytes, 5126, ty, values.len() / n, extra)
    }

    /// Float positions with their bounds.
    fn positions(&mut self, p: &[Vec3]) -> usize {
        let min = p.iter().fold(Vec3::INFINITY, |a, &b| a.min(b));
        let max = p.iter().fold(Vec3::NEG_INFINITY, |a, &b| a.max(b));
        let flat: Vec<f32> = p.iter().flat_map(|v| v.to_array()).collect();
        self.floats(
            &flat,
            "VEC3",
            json!({"min": min.to_array(), "max": max.to_array()}),
        )
    }

    fn indices(&mut self, i: &[u16]) -> usize {
        let bytes: Vec<u8> = i.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.accessor(&bytes, 5123, "SCALAR", i.len(), json!({}))
    }

    /// A mesh of one primitive.
    fn mesh(&mut self, primitive: Value) -> usize {
        self.push("meshes", json!({"primitives": [primitive]}))
    }

    fn node(&mut self, node: Value) -> usize {
        self.push("nodes", node)
    }

    fn root_node(&mut self, node: Value) -> usize {
        let n = self.node(node);
        self.json["scenes"][0]["nodes"]
            .as_array_mut()
            .unwrap()
            .push(n.into());
        n
    }

    fn extension(&mut self, name: &str, required: bool) {
        for key in ["extensionsUsed"]
            .into_iter()
            .chain(required.then_some("extensionsRequired"))
        {
            if self.json.get(key).is_none() {
                self.json[key] = json!([]);
            }
            self.json[key].as_array_mut().unwrap().push(name.into());
        }
    }

    /// The asset as a GLB.
    fn glb(&self) -> Vec<u8> {
        let mut j = serde_json::to_vec(&self.json).unwrap();
        j.resize(j.len().next_multiple_of(4), b' ');
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(((12 + 8 + j.len() + 8 + self.bin.len()) as u32).to_le_bytes());
        out.extend((j.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(j);
        out.extend((self.bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(&self.bin);
        out
    }

    /// The asset as `.gltf` JSON with the buffer in a data URI.
    fn gltf(&self) -> Vec<u8> {
        let mut json = self.json.clone();
        json["buffers"][0]["uri"] = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bin)
        )
        .into();
        serde_json::to_vec(&json).unwrap()
    }

    fn load(&self) -> Result<Scene, MeshError> {
        load_scene_bytes(Path::new("t.glb"), &self.glb(), &LoadOptions::default())
    }
}

/// The unit square in z = 0 facing +z (two triangles, normals +z), with
/// UVs equal to x and y.
fn square(asset: &mut Asset, material: Option<usize>) -> usize {
    let p = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    let position = asset.positions(&p);
    let normal = asset.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3", json!({}));
    let uv = asset.floats(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], "VEC2", json!({}));
    let indices = asset.indices(&[0, 1, 2, 0, 2, 3]);
    let mut primitive = json!({"attributes": {"POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv}, "indices": indices});
    if let Some(m) = material {
        primitive["material"] = m.into();
    }
    asset.mesh(primitive)
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn a_required_unknown_extension_is_refused_by_name() {
    let mut a = Asset::new();
    let m = square(&mut a, None);
    a.root_node(json!({"mesh": m}));
    a.extension("EXT_made_up", true);
    let e = a.load().unwrap_err().to_string();
    assert_eq!(
        e,
        "t.glb: requires extension EXT_made_up, which shlight does not read"
    );
}

#[test]
fn an_optional_unknown_extension_is_noted() {
    let mut a = Asset::new();
    let m = square(&mut a, None);
    a.root_node(json!({"mesh": m}));
    a.extension("EXT_made_up", false);
    // A handled required extension does not stop the file.
    a.extension("KHR_mesh_quantization", true);
    let s = a.load().unwrap();
    assert_eq!(s.instances.len(), 1);
    assert_eq!(s.notes.len(), 1, "{:?}", s.notes);
    assert!(s.notes[0].contains("EXT_made_up"), "{:?}", s.notes);
}

#[test]
fn a_mesh_used_by_two_nodes_is_stored_once_and_flattened_twice() {
    let mut a = Asset::new();
    let m = square(&mut a, None);
    a.root_node(json!({"mesh": m, "translation": [0, 0, 5]}));
    a.root_node(json!({"mesh": m, "scale": [2, 2, 2]}));
    for bytes in [a.glb(), a.gltf()] {
        let s = load_scene_bytes(Path::new("t.gltf"), &bytes, &LoadOptions::default()).unwrap();
        assert_eq!(s.primitives.len(), 1);
        assert_eq!(s.instances.len(), 2);
        assert!(s.instances.iter().all(|i| i.primitive == 0));
        // Nodes 0 and 1 place mesh 0 (the square is the first mesh).
        let sources: Vec<_> = s
            .instance_sources
            .iter()
            .map(|i| (i.node, i.mesh, i.gpu_instance))
            .collect();
        assert_eq!(sources, [(0, m, None), (1, m, None)]);
        let f = s.flatten(Vec3::splat(0.5)).unwrap();
        assert_eq!(f.mesh.vertex_count(), 8);
        // Vertex 2, (1, 1, 0): first translated by z + 5, then doubled.
        assert_eq!(f.mesh.positions[2], Vec3::new(1.0, 1.0, 5.0));
        assert_eq!(f.mesh.positions[6], Vec3::new(2.0, 2.0, 0.0));
        assert!((f.mesh.surface_area() - 5.0).abs() < 1e-9);
    }
    // `load` keeps the old vertex order: both copies, no colours (nothing
    // gives albedo).
    let m = load_bytes(Path::new("t.glb"), MeshFormat::Gltf, &a.glb()).unwrap();
    assert_eq!(m.vertex_count(), 8);
    assert_eq!(m.report.computed_normals, 0, "the square has normals");
    assert_eq!(m.positions[6], Vec3::new(2.0, 2.0, 0.0));
    assert!(m.colors.is_none() && m.emission.is_none());
}

#[test]
fn gpu_instancing_places_each_instance_after_the_node() {
    let mut a = Asset::new();
    let m = square(&mut a, None);
    let t = a.floats(
        &[0.0, 0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 0.0, -10.0],
        "VEC3",
        json!({}),
    );
    // Rotations as normalized SHORTs: identity, 90 degrees about y
    // (0, 0.7071, 0, 0.7071 -> 23170 of 32767) and 180 about z.
    let r: Vec<u8> = [0i16, 0, 0, 32767, 0, 23170, 0, 23170, 0, 0, 32767, 0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let r = a.accessor(&r, 5122, "VEC4", 3, json!({"normalized": true}));
    let s = a.floats(
        &[1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0],
        "VEC3",
        json!({}),
    );
    a.root_node(
        json!({"mesh": m, "translation": [0, 1, 0], "extensions": {"EXT_mesh_gpu_instancing":
        {"attributes": {"TRANSLATION": t, "ROTATION": r, "SCALE": s}}}}),
    );
    a.extension("EXT_mesh_gpu_instancing", true);
    a.extension("KHR_mesh_quantization", true);
    let scene = a.load().unwrap();
    assert_eq!(scene.primitives.len(), 1);
    assert_eq!(scene.instances.len(), 3);
    let gpu: Vec<_> = scene
        .instance_sources
        .iter()
        .map(|i| (i.node, i.gpu_instance))
        .collect();
    assert_eq!(gpu, [(0, Some(0)), (0, Some(1)), (0, Some(2))]);
    let f = scene.flatten(Vec3::ONE).unwrap();
    assert_eq!(f.mesh.vertex_count(), 12);
    // Vertex 1 of the square is (1, 0, 0); the node lifts everything by y 1.
    // Instance 0: (1, 1, 0).
    assert!(close(f.mesh.positions[1], Vec3::new(1.0, 1.0, 0.0), 1e-6));
    // Instance 1: scaled 2, turned 90 degrees about y (x -> -z), moved x + 10.
    assert!(
        close(f.mesh.positions[5], Vec3::new(10.0, 1.0, -2.0), 1e-4),
        "{}",
        f.mesh.positions[5]
    );
    // Instance 2: turned 180 degrees about z (x -> -x), moved z - 10.
    assert!(
        close(f.mesh.positions[9], Vec3::new(-1.0, 1.0, -10.0), 1e-4),
        "{}",
        f.mesh.positions[9]
    );
}

/// Positions quantized as gltfpack writes them: normalized SHORTs of the
/// mesh's bounding cube, dequantized by the node's scale and translation.
#[test]
fn quantized_positions_give_the_float_files_world_positions() {
    let points = [
        Vec3::new(-1.5, 0.25, 2.0),
        Vec3::new(2.5, -0.75, 1.0),
        Vec3::new(0.5, 3.0, -1.0),
        Vec3::new(1.0, 1.0, 1.0),
    ];
    let mut float = Asset::new();
    let position = float.positions(&points);
    let indices = float.indices(&[0, 1, 2, 0, 2, 3]);
    let m = float.mesh(json!({"attributes": {"POSITION": position}, "indices": indices}));
    float.root_node(json!({"mesh": m, "translation": [3, 0, 0]}));

    let lo = Vec3::new(-1.5, -0.75, -1.0);
    let extent = 4.0; // the largest side, x from -1.5 to 2.5
    let q: Vec<[i16; 3]> = points
        .iter()
        .map(|p| {
            ((*p - lo) / extent * 32767.0)
                .round()
                .to_array()
                .map(|v| v as i16)
        })
        .collect();
    let mut quantized = Asset::new();
    let bytes: Vec<u8> = q
        .iter()
        .flat_map(|p| {
            p.iter()
                .chain(&[0])
                .flat_map(|v| v.to_le_bytes())
                .collect::<Vec<_>>()
        })
        .collect();
    // Padded to 8 bytes an element, with the stride saying so.
    let view = quantized.view(&bytes);
    quantized.json["bufferViews"][view]["byteStride"] = 8.into();
    let qmin: Vec<i16> = (0..3)
        .map(|k| q.iter().map(|p| p[k]).min().unwrap())
        .collect();
    let qmax: Vec<i16> = (0..3)
        .map(|k| q.iter().map(|p| p[k]).max().unwrap())
        .collect();
    let position = quantized.push(
        "accessors",
        json!({"bufferView": view, "componentType": 5122, "normalized": true, "count": 4,
               "type": "VEC3", "min": qmin, "max": qmax}),
    );
    let indices = quantized.indices(&[0, 1, 2, 0, 2, 3]);
    let m = quantized.mesh(json!({"attributes": {"POSITION": position}, "indices": indices}));
    let outer = quantized.root_node(json!({"translation": [3, 0, 0], "children": [1]}));
    assert_eq!(outer, 0);
    quantized
        .node(json!({"mesh": m, "translation": lo.to_array(), "scale": [extent, extent, extent]}));
    quantized.extension("KHR_mesh_quantization", true);

    let a = float.load().unwrap().flatten(Vec3::ONE).unwrap().mesh;
    let b = quantized.load().unwrap().flatten(Vec3::ONE).unwrap().mesh;
    for (p, q) in a.positions.iter().zip(&b.positions) {
        // Half a quantization step of the 4-unit cube.
        assert!(close(*p, *q, 0.5 * extent / 32767.0 + 1e-6), "{p} {q}");
    }
    assert_eq!(a.positions[1], Vec3::new(5.5, -0.75, 1.0));
}

/// A PNG of `width x height` RGBA texels.
fn png(width: u32, height: u32, texels: &[[u8; 4]]) -> Vec<u8> {
    let raw: Vec<u8> = texels.iter().flatten().copied().collect();
    let img = image::RgbaImage::from_raw(width, height, raw).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// The sRGB transfer function's inverse, written out.
fn srgb(v: u8) -> f32 {
    let c = f64::from(v) / 255.0;
    (if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }) as f32
}

/// A square with a material whose base colour texture is `image` (in the
/// GLB), sampled nearest, with the given texture info extras.
fn textured(image: &[u8], info: Value, material: Value) -> Asset {
    let mut a = Asset::new();
    let view = a.view(image);
    a.json["images"] = json!([{"bufferView": view, "mimeType": "image/png"}]);
    a.json["samplers"] = json!([{"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}]);
    a.json["textures"] = json!([{"source": 0, "sampler": 0}]);
    let mut info = info;
    info["index"] = 0.into();
    let mut mat = material;
    mat["pbrMetallicRoughness"]["baseColorTexture"] = info;
    mat["pbrMetallicRoughness"]["metallicFactor"] = 0.into();
    a.json["materials"] = json!([mat]);
    let m = square(&mut a, Some(0));
    a.root_node(json!({"mesh": m}));
    a
}

/// Texels of a 4 x 4 image, each different: texel (i, j) = (60 i, 60 j, 7, 255).
fn four_by_four() -> Vec<[u8; 4]> {
    (0..16)
        .map(|k| [60 * (k % 4) as u8, 60 * (k / 4) as u8, 7, 255])
        .collect()
}

#[test]
fn a_textured_surface_samples_the_texel_times_the_factor() {
    let a = textured(
        &png(4, 4, &four_by_four()),
        json!({}),
        json!({"pbrMetallicRoughness": {"baseColorFactor": [0.5, 1.0, 0.25, 1.0]}}),
    );
    let s = a.load().unwrap();
    assert_eq!(s.textures.len(), 1);
    assert_eq!((s.textures[0].width, s.textures[0].height), (4, 4));
    let f = s.flatten(Vec3::ONE).unwrap();
    // Triangle 0 is (0,0,0), (1,0,0), (1,1,0): UV = (x, y). The point
    // (0.625, 0.375) is in texel (2, 1) = (120, 60, 7).
    let bary = [1.0 - 0.625, 0.625 - 0.375, 0.375];
    let got = f.sample(0, bary).albedo;
    let want = Vec3::new(0.5 * srgb(120), srgb(60), 0.25 * srgb(7));
    assert!(close(got, want, 1e-5), "{got} {want}");
    // `load` gives each vertex the albedo at its UV: vertex 2, UV (1, 1),
    // clamps to texel (3, 3) = (180, 180, 7).
    let m = load_bytes(Path::new("t.glb"), MeshFormat::Gltf, &a.glb()).unwrap();
    let c = m.colors.unwrap()[2];
    assert!(
        close(
            c,
            Vec3::new(0.5 * srgb(180), srgb(180), 0.25 * srgb(7)),
            1e-5
        ),
        "{c}"
    );
}

#[test]
fn sixteen_bit_pngs_are_reduced_to_eight_bits() {
    let raw: Vec<u16> = vec![0x8080, 0xFFFF, 0x0000, 0xFFFF];
    let img = image::ImageBuffer::<image::Rgba<u16>, _>::from_raw(1, 1, raw).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    let a = textured(&out.into_inner(), json!({}), json!({}));
    let s = a.load().unwrap();
    assert_eq!(s.textures[0].texels, [[128, 255, 0, 255]]);
}

#[test]
fn the_texture_transform_follows_the_specification() {
    // The specification's example: offset (0, 1), rotation pi/2, scale
    // 0.5 uses the lower left quadrant of the image, rotated. UV (0.25,
    // 0.75): scaled (0.125, 0.375), turned (0.375, -0.125), moved
    // (0.375, 0.875): texel (1, 3).
    let a = textured(
        &png(4, 4, &four_by_four()),
        json!({"texCoord": 0, "extensions": {"KHR_texture_transform":
            {"offset": [0, 1], "rotation": FRAC_PI_2, "scale": [0.5, 0.5], "texCoord": 1}}}),
        json!({}),
    );
    let s = a.load().unwrap();
    let t = s.materials[0].base_color_texture.unwrap();
    assert_eq!(t.tex_coord, 1, "the extension's texCoord overrides");
    let uv = t.transform.transform_point2(Vec2::new(0.25, 0.75));
    assert!((uv - Vec2::new(0.375, 0.875)).length() < 1e-6, "{uv}");
    // Every corner of the UV square lands in the lower left quadrant.
    for corner in [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE] {
        let uv = t.transform.transform_point2(corner);
        assert!(
            uv.x > -1e-6 && uv.x < 0.5 + 1e-6 && uv.y > 0.5 - 1e-6 && uv.y < 1.0 + 1e-6,
            "{uv}"
        );
    }
    // Sampled through the material: texel (1, 3) = (60, 180, 7).
    let sample =
        s.materials[0].surface(&s.textures, &[Vec2::ZERO, Vec2::new(0.25, 0.75)], Vec4::ONE);
    assert!(
        close(sample.albedo, Vec3::new(srgb(60), srgb(180), srgb(7)), 1e-6),
        "{sample:?}"
    );
}

#[test]
fn alpha_mask_uses_the_cutoff_and_vertex_alpha() {
    let mut a = Asset::new();
    a.json["materials"] = json!([
        {"alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true},
        {"alphaMode": "MASK"},
        {"alphaMode": "BLEND"},
    ]);
    let p = a.positions(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    // COLOR_0 as normalized UNSIGNED_BYTE RGBA: alpha 51/255 = 0.2 at
    // vertex 0, 102/255 = 0.4 at the others.
    let c = a.accessor(
        &[255, 0, 0, 51, 0, 255, 0, 102, 0, 0, 255, 102],
        5121,
        "VEC4",
        3,
        json!({"normalized": true}),
    );
    let mut meshes = Vec::new();
    for material in 0..3 {
        meshes.push(
            a.mesh(json!({"attributes": {"POSITION": p, "COLOR_0": c}, "material": material})),
        );
    }
    for m in meshes {
        a.root_node(json!({"mesh": m}));
    }
    let s = a.load().unwrap();
    assert_eq!(s.materials[0].alpha_mode, AlphaMode::Mask { cutoff: 0.3 });
    assert!(s.materials[0].double_sided);
    assert_eq!(s.materials[1].alpha_mode, AlphaMode::Mask { cutoff: 0.5 });
    assert_eq!(s.materials[2].alpha_mode, AlphaMode::Blend);
    let alpha = s.primitives[0].color_alpha.as_ref().unwrap();
    assert!((alpha[0] - 0.2).abs() < 1e-6 && (alpha[1] - 0.4).abs() < 1e-6);
    assert_eq!(s.primitives[0].mesh.colors.as_ref().unwrap()[1], Vec3::Y);
    let f = s.flatten(Vec3::ONE).unwrap();
    // At vertex 0 (alpha 0.2) triangle 0 (cutoff 0.3) is cut out; at
    // vertex 1 (0.4) it is there; with the default cutoff 0.5 both are
    // out; blended, the alpha is the coverage.
    let at = |t: u32, bary: [f32; 3]| f.material(t).opacity(f.sample(t, bary).alpha);
    assert_eq!(at(0, [1.0, 0.0, 0.0]), 0.0);
    assert_eq!(at(0, [0.0, 1.0, 0.0]), 1.0);
    assert_eq!(at(1, [0.0, 1.0, 0.0]), 0.0);
    assert!((at(2, [0.0, 1.0, 0.0]) - 0.4).abs() < 1e-6);
    assert!(f.any_cut_out());
}

#[test]
fn lights_take_their_place_and_direction_from_the_node_hierarchy() {
    let mut a = Asset::new();
    a.extension("KHR_lights_punctual", false);
    a.json["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "name": "bulb", "range": 5},
        {"type": "spot", "spot": {}, "intensity": 20, "color": [1, 0.5, 0.25]},
        {"type": "directional", "intensity": 3},
    ]}});
    // The parent turns 90 degrees about x (y -> z, z -> -y) and moves by
    // (1, 2, 3); each child sits at local (0, 0, -2).
    let parent = a.root_node(json!({"rotation": [FRAC_1_SQRT_2, 0, 0, FRAC_1_SQRT_2],
        "translation": [1, 2, 3], "children": [1, 2, 3]}));
    assert_eq!(parent, 0);
    for light in 0..3 {
        a.node(json!({"translation": [0, 0, -2], "extensions": {"KHR_lights_punctual": {"light": light}}}));
    }
    let s = a.load().unwrap();
    assert_eq!(s.lights.len(), 3);
    for l in &s.lights {
        // Local (0, 0, -2) turned: (0, 2, 0), moved: (1, 4, 3).
        assert!(close(l.position, Vec3::new(1.0, 4.0, 3.0), 1e-5), "{l:?}");
        // Local -z turned: +y.
        assert!(close(l.direction, Vec3::Y, 1e-6), "{l:?}");
    }
    assert_eq!(s.lights[0].kind, LightKind::Point);
    assert_eq!(s.lights[0].name.as_deref(), Some("bulb"));
    assert_eq!((s.lights[0].intensity, s.lights[0].color), (1.0, Vec3::ONE));
    assert_eq!(s.lights[0].range, Some(5.0));
    assert_eq!(
        s.lights[1].kind,
        LightKind::Spot {
            inner_cone: 0.0,
            outer_cone: FRAC_PI_4
        }
    );
    assert_eq!(s.lights[1].color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(s.lights[2].kind, LightKind::Directional);
    assert_eq!((s.lights[2].intensity, s.lights[2].range), (3.0, None));

    // Bad lights are named.
    for (light, what) in [
        (
            json!({"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.4}}),
            "cone angles",
        ),
        (
            json!({"type": "spot", "spot": {"outerConeAngle": 2.0}}),
            "cone angles",
        ),
        (json!({"type": "point", "intensity": -1}), "intensity"),
        (json!({"type": "point", "name": "x", "range": 0}), "range"),
    ] {
        a.json["extensions"]["KHR_lights_punctual"]["lights"][1] = light;
        let e = a.load().unwrap_err().to_string();
        assert!(
            e.starts_with("t.glb: node 2: light 1") && e.contains(what),
            "{e}"
        );
    }
}

#[test]
fn a_missing_texture_file_is_named() {
    let dir = std::env::temp_dir().join(format!("shlight-gltf-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut a = textured(&png(1, 1, &[[1, 2, 3, 4]]), json!({}), json!({}));
    a.json["images"] = json!([{"uri": "wood%20grain.png"}]);
    a.json["textures"][0]["name"] = "wood".into();
    let path = dir.join("s.gltf");
    std::fs::write(&path, a.gltf()).unwrap();
    let e = load_scene(&path, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("texture 0 (wood)"), "{e}");
    assert!(
        e.contains(&format!(
            "cannot read {}",
            dir.join("wood grain.png").display()
        )),
        "{e}"
    );
    // Beside the file, it loads.
    std::fs::write(dir.join("wood grain.png"), png(1, 1, &[[1, 2, 3, 4]])).unwrap();
    let s = load_scene(&path, &LoadOptions::default());
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(s.unwrap().textures[0].texels, [[1, 2, 3, 4]]);
}

#[test]
fn a_texture_over_the_pixel_limit_is_refused_before_decoding() {
    let a = textured(&png(4, 4, &four_by_four()), json!({}), json!({}));
    let options = LoadOptions {
        max_texture_pixels: 15,
        ..LoadOptions::default()
    };
    let e = load_scene_bytes(Path::new("t.glb"), &a.glb(), &options).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::TextureTooLarge {
                pixels: 16,
                max: 15,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn ktx2_textures_are_refused_by_name_where_used() {
    let mut a = textured(&png(1, 1, &[[0; 4]]), json!({}), json!({}));
    a.json["textures"] =
        json!([{"name": "bark", "extensions": {"KHR_texture_basisu": {"source": 0}}}]);
    a.extension("KHR_texture_basisu", true);
    let e = a.load().unwrap_err().to_string();
    assert!(
        e.contains("texture 0 (bark)") && e.contains("KHR_texture_basisu"),
        "{e}"
    );
    // With a PNG fallback, the fallback is read.
    a.json["textures"][0]["source"] = 0.into();
    assert_eq!(a.load().unwrap().textures.len(), 1);
}

#[test]
fn non_finite_and_singular_transforms_are_refused_by_node() {
    let mut a = Asset::new();
    let m = square(&mut a, None);
    a.root_node(json!({"scale": [1e30, 1e30, 1e30], "children": [1]}));
    a.node(json!({"name": "huge", "mesh": m, "scale": [1e30, 1e30, 1e30]}));
    let e = a.load().unwrap_err().to_string();
    assert!(
        e.contains("node 1 (huge) has a non-finite world transform"),
        "{e}"
    );
    a.json["nodes"][1]["scale"] = json!([1, 0, 1]);
    a.json["nodes"][0]["scale"] = json!([1, 1, 1]);
    let e = a.load().unwrap_err().to_string();
    assert!(
        e.contains("node 1 (huge) has a singular world transform"),
        "{e}"
    );
    // A zero rotation quaternion.
    a.json["nodes"][1] = json!({"mesh": m, "rotation": [0, 0, 0, 0]});
    let e = a.load().unwrap_err().to_string();
    assert!(
        e.contains("node 1 has a non-finite transform (or a zero rotation"),
        "{e}"
    );
    // A number JSON holds but f32 does not: refused by the parser.
    a.json["nodes"][1] =
        json!({"mesh": m, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1e39, 0, 0, 1]});
    let e = a.load().unwrap_err().to_string();
    assert!(
        e.contains("not a valid glTF file: number out of range"),
        "{e}"
    );
}

#[test]
fn a_mirrored_node_flips_the_winding() {
    let mut a = Asset::new();
    let m = square(&mut a, None);
    a.root_node(json!({"mesh": m, "scale": [-1, 1, 1]}));
    a.root_node(json!({"mesh": m, "rotation": [0, 0, 1, 0], "scale": [1, 1, -1]}));
    let f = a.load().unwrap().flatten(Vec3::ONE).unwrap();
    assert_eq!(f.mesh.triangle_count(), 4);
    for (t, tri) in f.mesh.triangles.iter().enumerate() {
        let [p0, p1, p2] = tri.map(|i| f.mesh.positions[i as usize]);
        let face = (p1 - p0).cross(p2 - p0).normalize();
        for &i in tri {
            assert!(face.dot(f.mesh.normals[i as usize]) > 0.999, "triangle {t}");
        }
        // Mirrored in x, the square still faces +z; mirrored in z and
        // turned about z, it faces -z.
        let want = if t < 2 { Vec3::Z } else { Vec3::NEG_Z };
        assert!(close(face, want, 1e-6), "triangle {t}: {face}");
    }
}

#[test]
fn points_and_all_degenerate_primitives_are_skipped_with_a_note() {
    let mut a = Asset::new();
    let p = a.positions(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    let flat = a.positions(&[Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0)]);
    a.push(
        "meshes",
        json!({"name": "mixed", "primitives": [
            {"attributes": {"POSITION": p}, "mode": 0},
            {"attributes": {"POSITION": flat}},
            {"attributes": {"POSITION": p}},
        ]}),
    );
    a.root_node(json!({"mesh": 0}));
    let s = a.load().unwrap();
    assert_eq!(s.primitives.len(), 1);
    assert_eq!(s.primitives[0].label, "mesh 0 (mixed) primitive 2");
    assert_eq!(s.notes.len(), 2, "{:?}", s.notes);
    assert!(s.notes[0].contains("mesh 0 (mixed) primitive 0 draws points"));
    assert!(s.notes[1].contains("primitive 1") && s.notes[1].contains("degenerate"));
    // Flattened by `load`, the kept primitive's normals were computed
    // (it has none), once per placement.
    let m = load_bytes(Path::new("t.glb"), MeshFormat::Gltf, &a.glb()).unwrap();
    assert_eq!((m.vertex_count(), m.report.computed_normals), (3, 3));
}

#[test]
fn emissive_strength_and_metallic_reach_the_material() {
    let mut a = Asset::new();
    a.json["materials"] = json!([{"emissiveFactor": [1, 0.5, 0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
        "pbrMetallicRoughness": {"metallicFactor": 0.25, "baseColorFactor": [0.8, 0.8, 0.8, 1]}}]);
    let m = square(&mut a, Some(0));
    a.root_node(json!({"mesh": m}));
    let s = a.load().unwrap();
    assert_eq!(s.materials[0].emissive, Vec3::new(4.0, 2.0, 0.0));
    let mesh = load_bytes(Path::new("t.glb"), MeshFormat::Gltf, &a.glb()).unwrap();
    // Albedo 0.8 x (1 - 0.25).
    assert!(close(mesh.colors.unwrap()[0], Vec3::splat(0.6), 1e-6));
    assert_eq!(mesh.emission.unwrap()[3], Vec3::new(4.0, 2.0, 0.0));
}

#[test]
fn meshopt_compressed_views_decode_to_the_original_data() {
    let positions: [[f32; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.25],
    ];
    let indices = [0u32, 1, 2, 0, 2, 3];
    let vertices = meshopt::encoding::encode_vertex_buffer(&positions).unwrap();
    let triangles = meshopt::encoding::encode_index_buffer(&indices, 4).unwrap();
    let mut a = Asset::new();
    let v0 = a.view(&vertices);
    let v1 = a.view(&triangles);
    // The views as the file gives them: over a fallback buffer without
    // data, the compressed bytes in the GLB's chunk.
    a.json["buffers"].as_array_mut().unwrap().push(
        json!({"byteLength": 60, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}),
    );
    for (view, offset, length, stride, count, mode) in [
        (v0, 0, 48, 12, 4, "ATTRIBUTES"),
        (v1, 48, 12, 2, 6, "TRIANGLES"),
    ] {
        let compressed = a.json["bufferViews"][view].clone();
        a.json["bufferViews"][view] = json!({"buffer": 1, "byteOffset": offset, "byteLength": length,
            "extensions": {"EXT_meshopt_compression": {"buffer": 0, "byteOffset": compressed["byteOffset"],
                "byteLength": compressed["byteLength"], "byteStride": stride, "count": count, "mode": mode}}});
    }
    a.json["bufferViews"][v0]["byteStride"] = 12.into();
    let p = a.push(
        "accessors",
        json!({"bufferView": v0, "componentType": 5126, "count": 4, "type": "VEC3",
        "min": [0, 0, 0], "max": [1, 1, 0.25]}),
    );
    let i = a.push(
        "accessors",
        json!({"bufferView": v1, "componentType": 5123, "count": 6, "type": "SCALAR"}),
    );
    let m = a.mesh(json!({"attributes": {"POSITION": p}, "indices": i}));
    a.root_node(json!({"mesh": m}));
    a.extension("EXT_meshopt_compression", true);
    let s = a.load().unwrap();
    let mesh = &s.primitives[0].mesh;
    let want: Vec<Vec3> = positions.iter().map(|p| Vec3::from_array(*p)).collect();
    assert_eq!(mesh.positions, want);
    assert_eq!(mesh.triangles, [[0, 1, 2], [0, 2, 3]]);
    // A damaged stream is an error naming the view.
    let mut bad = a.glb();
    let at = bad.len() - a.bin.len();
    bad[at..at + vertices.len()].fill(0xFF);
    let e = load_scene_bytes(Path::new("t.glb"), &bad, &LoadOptions::default()).unwrap_err();
    assert!(
        e.to_string()
            .contains("buffer view 0: EXT_meshopt_compression"),
        "{e}"
    );
}

#[test]
fn draco_is_refused_by_name_where_required() {
    let mut a = Asset::new();
    let m = square(&mut a, None);
    a.root_node(json!({"mesh": m}));
    a.extension("KHR_draco_mesh_compression", true);
    let e = a.load().unwrap_err().to_string();
    assert!(e.contains("requires extension KHR_draco_mesh_compression (Draco-compressed geometry), which shlight does not read"), "{e}");
}

#[test]
fn uv_sets_are_read_in_order_and_a_far_one_is_not_a_burden() {
    let mut a = Asset::new();
    let p = a.positions(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    let uv = a.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", json!({}));
    let m =
        a.mesh(json!({"attributes": {"POSITION": p, "TEXCOORD_2": uv, "TEXCOORD_4000000000": uv}}));
    a.root_node(json!({"mesh": m}));
    let s = a.load().unwrap();
    let uvs = &s.primitives[0].uvs;
    assert_eq!(uvs.len(), 3);
    assert_eq!(uvs[0], [Vec2::ZERO; 3]);
    assert_eq!(uvs[2], [Vec2::ZERO, Vec2::X, Vec2::Y]);
}

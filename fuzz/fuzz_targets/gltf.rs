//! `shlight_mesh::load_scene_bytes` on a glTF or GLB file (told apart by
//! the GLB magic, as the loader does), then the scene flattened, and
//! `load_bytes_with` (which flattens as `shlight prt` reads a mesh); the
//! file rewritten with a lightmap page on its first node
//! (`lightmapped_glb`, as `shlight lightmap -o` writes) and read back as a
//! lightmapped scene (`lightmap_pages_from_bytes` and each page through
//! `decode_ktx2`, as `shlight sample` reads): any input gives a scene, a
//! mesh, a file or a `MeshError`, within the limits docs/limits.md states. The file's directory does not exist, so an
//! external buffer or image URI fails to load instead of reading whatever
//! lies beside the fuzzer.
#![no_main]

use std::path::Path;

use glam::Vec3;
use libfuzzer_sys::fuzz_target;
use shlight_mesh::{
    BakedNode, LightmapImage, LightmapImageFormat, LightmapRequest, MeshFormat,
    lightmap_pages_from_bytes, lightmapped_glb, load_bytes_with, load_scene_bytes,
};

fuzz_target!(init: shlight_fuzz::abort_on_shlight_panics(), |bytes: &[u8]| {
    let path = Path::new("/nonexistent-shlight-fuzz/fuzz.gltf");
    if let Ok(scene) = load_scene_bytes(path, bytes, &shlight_fuzz::MESH_LIMITS) {
        if let Ok(surfaces) = scene.flatten(Vec3::splat(0.5)) {
            // Every triangle's surface, at its centre.
            for t in 0..surfaces.mesh.triangle_count() as u32 {
                let _ = surfaces.sample(t, [1.0 / 3.0; 3]);
            }
        }
    }
    let _ = load_bytes_with(path, MeshFormat::Gltf, bytes, &shlight_fuzz::MESH_LIMITS);
    let page = shlight_io::encode_ktx2(shlight_io::Ktx2TexelFormat::Rgba16Float, 2, 2, &[[0.5; 4]; 4])
        .expect("a 2 x 2 page");
    let request = LightmapRequest {
        images: vec![LightmapImage {
            name: "fuzz lightmap irradiance".into(),
            format: LightmapImageFormat::Ktx2,
            bytes: page,
            intensity: 1.0,
        }],
        nodes: vec![BakedNode {
            node: 0,
            scale: [0.5, 0.5],
            offset: [0.25, 0.25],
            image: Some(0),
            unshare: bytes.len() % 2 == 0,
            extension: serde_json::json!({"scaleOffset": [0.5, 0.5, 0.25, 0.25]}),
        }],
        root_extension: serde_json::json!({"basis": "irradiance", "images": ["fuzz lightmap irradiance"]}),
        load_options: shlight_fuzz::MESH_LIMITS,
    };
    if let Ok((glb, _)) = lightmapped_glb(path, bytes, &request) {
        let pages = lightmap_pages_from_bytes(path, &glb).expect("a file shlight wrote reads back");
        for page in &pages.pages {
            shlight_io::decode_ktx2(page).expect("the page shlight wrote decodes");
        }
    }
    if let Ok(pages) = lightmap_pages_from_bytes(path, bytes) {
        for page in &pages.pages {
            let _ = shlight_io::decode_ktx2(page);
        }
    }
});

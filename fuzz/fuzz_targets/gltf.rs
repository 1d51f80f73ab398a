//! `shlight_mesh::load_scene_bytes` on a glTF or GLB file (told apart by
//! the GLB magic, as the loader does), then the scene flattened, and
//! `load_bytes_with` (which flattens as `shlight prt` reads a mesh): any
//! input gives a scene, a mesh or a `MeshError`, within the limits
//! docs/limits.md states. The file's directory does not exist, so an
//! external buffer or image URI fails to load instead of reading whatever
//! lies beside the fuzzer.
#![no_main]

use std::path::Path;

use glam::Vec3;
use libfuzzer_sys::fuzz_target;
use shlight_mesh::{MeshFormat, load_bytes_with, load_scene_bytes};

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
});

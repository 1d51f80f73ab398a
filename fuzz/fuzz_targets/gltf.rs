//! `shlight_mesh::load_bytes_with` on a glTF or GLB file (told apart by the
//! GLB magic, as the loader does): any input gives a mesh or a
//! `MeshError`, within the limits docs/limits.md states. The file's
//! directory does not exist, so an external buffer URI fails to load
//! instead of reading whatever lies beside the fuzzer.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use shlight_mesh::{MeshFormat, load_bytes_with};

fuzz_target!(init: shlight_fuzz::abort_on_shlight_panics(), |bytes: &[u8]| {
    let _ = load_bytes_with(
        Path::new("/nonexistent-shlight-fuzz/fuzz.gltf"),
        MeshFormat::Gltf,
        bytes,
        &shlight_fuzz::MESH_LIMITS,
    );
});

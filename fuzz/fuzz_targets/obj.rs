//! `shlight_mesh::load_bytes_with` on an OBJ file (with any `mtllib` it names
//! answered by an empty material library): any input gives a mesh or a
//! `MeshError`, within the limits docs/limits.md states.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use shlight_mesh::{MeshFormat, load_bytes_with};

fuzz_target!(init: shlight_fuzz::abort_on_shlight_panics(), |bytes: &[u8]| {
    let _ = load_bytes_with(
        Path::new("fuzz.obj"),
        MeshFormat::Obj,
        bytes,
        &shlight_fuzz::MESH_LIMITS,
    );
});

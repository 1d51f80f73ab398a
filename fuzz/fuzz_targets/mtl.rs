//! `shlight_mesh::parse_mtl_bytes` on an MTL material library (what the
//! OBJ reader parses for each `mtllib`): any input gives the materials or
//! a `MeshError`.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use shlight_mesh::parse_mtl_bytes;

fuzz_target!(init: shlight_fuzz::abort_on_shlight_panics(), |bytes: &[u8]| {
    let _ = parse_mtl_bytes(Path::new("fuzz.mtl"), bytes);
});

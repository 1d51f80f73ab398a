//! `shlight_io::read_image_bytes` on a `.hdr` file: any input gives an
//! image or an `IoError`, within the memory and time docs/limits.md states.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use shlight_io::{ReadOptions, read_image_bytes};

fuzz_target!(init: shlight_fuzz::abort_on_shlight_panics(), |bytes: &[u8]| {
    let options = ReadOptions {
        max_pixels: shlight_fuzz::MAX_PIXELS,
        ..ReadOptions::default()
    };
    let _ = read_image_bytes(bytes, Path::new("fuzz.hdr"), &options);
});

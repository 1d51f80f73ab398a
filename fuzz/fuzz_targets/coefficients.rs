//! `shlight_format::read_coefficients_from_bytes`, what `shlight convert`
//! and every coefficient-reading command call: a shlight coefficient file,
//! three.js LightProbe JSON, glTF / GLB with `EXT_lights_image_based`,
//! shlight's Unity JSON or Filament sh.txt, told apart by content. Any
//! input gives a `CoeffFile` or a `FormatError`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shlight_format::read_coefficients_from_bytes;

fuzz_target!(init: shlight_fuzz::abort_on_shlight_panics(), |bytes: &[u8]| {
    let _ = read_coefficients_from_bytes(bytes, "fuzz.json");
});

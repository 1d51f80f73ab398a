//! `shlight_format::ShvolFile::from_bytes` on a `.shvol` irradiance volume
//! (the file `shlight render-mesh --volume` reads): any input gives the
//! file or a `FormatError`.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use shlight_format::ShvolFile;

fuzz_target!(init: shlight_fuzz::abort_on_shlight_panics(), |bytes: &[u8]| {
    let _ = ShvolFile::from_bytes(bytes, Path::new("fuzz.shvol"));
});

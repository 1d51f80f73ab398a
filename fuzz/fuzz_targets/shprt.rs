//! `shlight_format::ShprtFile::from_bytes` on a `.shprt` file: any input
//! gives the file or a `FormatError`.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use shlight_format::ShprtFile;

fuzz_target!(init: shlight_fuzz::abort_on_shlight_panics(), |bytes: &[u8]| {
    let _ = ShprtFile::from_bytes(bytes, Path::new("fuzz.shprt"));
});

//! Every input that once stopped an image fuzz target (fuzz/), read
//! through `read_image_bytes` with the default options: each must give
//! the result listed here (an error with this text, or an image of this
//! size), promptly.
//!
//! The inputs live in `tests/fuzz_regressions/<target>/`, one folder per
//! fuzz target (`fuzz/run.sh` also feeds them to the fuzzer as seeds). A
//! new input needs a line in [`EXPECTED`]: the test fails on a file it
//! does not know.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use shlight_io::{ReadOptions, read_image_bytes};

/// What reading a regression input must give.
enum Outcome {
    /// An error whose message contains this.
    #[expect(dead_code, reason = "no image regression input gives an error yet")]
    Error(&'static str),
    /// An image of this width and height.
    Image(usize, usize),
}

/// (fuzz target folder, file, outcome), with what the file once did.
const EXPECTED: &[(&str, &str, Outcome)] = &[
    // A damaged B44 block: exr's B44 unpacking subtracts with wrapping
    // (as OpenEXR's C code does), which panicked in the fuzz build's
    // overflow checks. Caught by the decoder guard there; a release build
    // decodes the block to (meaningless) values of the header's size.
    ("exr", "b44-wrapping-arithmetic.exr", Outcome::Image(16, 8)),
];

/// Longer than any of these files takes, short enough that a hang fails
/// quickly.
const TIME_LIMIT: Duration = Duration::from_secs(20);

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions")
}

#[test]
fn every_regression_input_is_listed() {
    let mut found = Vec::new();
    for target in std::fs::read_dir(dir()).unwrap() {
        let target = target.unwrap();
        for file in std::fs::read_dir(target.path()).unwrap() {
            found.push((
                target.file_name().into_string().unwrap(),
                file.unwrap().file_name().into_string().unwrap(),
            ));
        }
    }
    found.sort();
    let mut listed: Vec<(String, String)> = EXPECTED
        .iter()
        .map(|(t, f, _)| ((*t).to_string(), (*f).to_string()))
        .collect();
    listed.sort();
    assert_eq!(found, listed);
}

#[test]
fn every_regression_input_reads_cleanly() {
    for (target, file, expected) in EXPECTED {
        let bytes = std::fs::read(dir().join(target).join(file)).unwrap();
        let name = PathBuf::from(file);
        let (send, receive) = mpsc::channel();
        std::thread::spawn(move || {
            let result = read_image_bytes(&bytes, &name, &ReadOptions::default())
                .map(|image| (image.width(), image.height()))
                .map_err(|e| e.to_string());
            let _ = send.send(result);
        });
        let result = receive
            .recv_timeout(TIME_LIMIT)
            .unwrap_or_else(|_| panic!("{file}: no answer within {TIME_LIMIT:?}"));
        match (result, expected) {
            (Ok(size), Outcome::Image(w, h)) => assert_eq!(size, (*w, *h), "{file}"),
            (Err(e), Outcome::Error(text)) => {
                assert!(e.starts_with(&format!("{file}: ")), "{file}: {e}");
                assert!(e.contains(text), "{file}: {e}");
            }
            (Ok(size), Outcome::Error(text)) => {
                panic!("{file}: read as {size:?}, expected the error \"{text}\"")
            }
            (Err(e), Outcome::Image(..)) => panic!("{file}: {e}"),
        }
    }
}

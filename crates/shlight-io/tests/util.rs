//! Helpers shared by the test modules: temporary directories, test images,
//! error-kind assertions.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use shlight_io::{Image, IoError, ReadOptions, read_image};

/// A fresh directory under the target's test tmp dir, removed on drop.
pub struct TempDir(PathBuf);

impl TempDir {
    pub fn new(name: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("shlight-io-{name}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    pub fn path(&self) -> &Path {
        &self.0
    }

    pub fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// Names of the entries in the directory, sorted.
    pub fn entries(&self) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(&self.0)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Reads with default options.
pub fn read(path: &Path) -> Result<Image, IoError> {
    read_image(path, &ReadOptions::default())
}

/// An HDR test image: every pixel different, values from about 0.001 to
/// about 100, positive.
pub fn hdr_image(width: usize, height: usize) -> Image {
    Image::from_fn(width, height, |x, y| {
        let t = (x + width * y) as f32;
        [
            0.001 + 0.37 * t,
            (x as f32 + 1.0) / (y as f32 + 1.0),
            100.0 / (1.0 + ((x * 7 + y * 3) % 13) as f32),
        ]
    })
}

/// An image with values in [0, 1] (for 8-bit formats).
pub fn ldr_image(width: usize, height: usize) -> Image {
    Image::from_fn(width, height, |x, y| {
        [
            x as f32 / (width - 1) as f32,
            y as f32 / (height - 1) as f32,
            ((x * 31 + y * 17) % 256) as f32 / 255.0,
        ]
    })
}

/// Asserts that `$result` is an error whose kind matches `$pattern`.
#[macro_export]
macro_rules! assert_kind {
    ($result:expr, $pattern:pat) => {
        match $result {
            Err(ref e) if matches!(e.kind(), $pattern) => {}
            Err(ref e) => panic!("expected {}, got error {e:?} ({e})", stringify!($pattern)),
            Ok(_) => panic!("expected {}, got Ok", stringify!($pattern)),
        }
    };
}

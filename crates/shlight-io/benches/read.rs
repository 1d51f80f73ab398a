//! Benchmarks of reading a 2048x1024 float OpenEXR environment map (ZIP,
//! what `write_image` writes) and of `Image::stats` on it: the first two
//! stages of `shlight project`.
//!
//! Run with `cargo bench -p shlight-io --bench read`.

use std::path::PathBuf;
use std::sync::OnceLock;

use divan::black_box;
use shlight_io::{Image, ReadOptions, WriteOptions, read_image, write_image};

fn main() {
    divan::main();
}

/// A sky-like map: a smooth gradient, a small bright sun and texel noise
/// (so that ZIP compresses it about as much as a photographed map).
fn map() -> Image {
    let (w, h) = (2048, 1024);
    Image::from_fn(w, h, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        let noise = ((y * w + x) * 7919 % 101) as f32 * 1e-3;
        let sun = if (u - 0.3).abs() < 0.01 && (v - 0.2).abs() < 0.02 {
            5e3
        } else {
            0.0
        };
        [
            1.0 - v + sun + noise,
            0.8 - 0.5 * v + sun,
            0.6 + 0.3 * u + sun,
        ]
    })
}

/// The map written once per run to a temporary file.
fn path() -> &'static PathBuf {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        let path =
            std::env::temp_dir().join(format!("shlight-io-bench-{}.exr", std::process::id()));
        write_image(&path, &map(), &WriteOptions::default()).expect("writing the map");
        path
    })
}

/// `read_image` of the 2048x1024 float ZIP file: reading, decompressing
/// on all cores, assembling RGB.
#[divan::bench(sample_count = 20, sample_size = 1)]
fn read_exr_2048x1024() -> Image {
    read_image(black_box(path()), &ReadOptions::default()).expect("reading the map")
}

/// `Image::stats` of the same map (6.3 million channel values).
#[divan::bench(sample_count = 20)]
fn stats_2048x1024(bencher: divan::Bencher) {
    let image = map();
    bencher.bench_local(|| black_box(&image).stats());
}

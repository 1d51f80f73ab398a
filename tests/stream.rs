//! `shlight project` of map files too large to hold: the rows stream into
//! the ring sums, so the process fits a memory cap that the map itself
//! exceeds, and the file it writes is the in-memory route's bit for bit.

use std::path::Path;
use std::process::Command;

use exr::prelude::{Encoding, Image, SpecificChannels, Vec2, WritableImage};

use crate::util::{s, skip, temp_dir};

/// Writes a `w x h` float RGB OpenEXR map (ZIP, 16 scan lines a block)
/// whose texels come from a function, block by block: the map is never in
/// memory. Its values are small multiples of 1/64, in patches, so the file
/// compresses to a few MB and the texels are far from constant.
pub fn write_large_exr(path: &Path, w: usize, h: usize) {
    let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let (x, y) = (p.x(), p.y());
        let patch = ((x / 64) * 7 + (y / 32) * 13) % 29;
        (
            patch as f32 / 8.0,
            ((x / 256 + y / 128) % 5) as f32 / 64.0,
            if (x / 512 + y / 512) % 2 == 0 {
                1.5
            } else {
                0.25
            },
        )
    });
    Image::from_encoded_channels((w, h), Encoding::SMALL_LOSSLESS, channels)
        .write()
        .to_file(path)
        .unwrap();
}

/// The address-space cap the streamed projection runs under: room for
/// the binary, its thread stacks (a few MB a core, reserved rather than
/// used) and one malloc arena (`MALLOC_ARENA_MAX=1`; glibc reserves 64 MB
/// of address space per arena otherwise), far below an 8192x4096 map's
/// 400 MB of float texels.
fn cap_bytes() -> u64 {
    let cores = std::thread::available_parallelism().map_or(1, usize::from) as u64;
    (192 + 4 * cores) << 20
}

/// `shlight project ARGS`, optionally under an address-space cap
/// (`prlimit --as`); whether it succeeded, and its stderr.
fn project(args: &[String], cap: Option<u64>) -> (bool, String) {
    let bin = env!("CARGO_BIN_EXE_shlight");
    let mut command = match cap {
        Some(cap) => {
            let mut c = Command::new("prlimit");
            c.arg(format!("--as={cap}")).arg(bin);
            c
        }
        None => Command::new(bin),
    };
    let out = command
        .args(["project", "--quiet"])
        .args(args)
        .env("MALLOC_ARENA_MAX", "1")
        .output()
        .expect("prlimit and shlight run");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A `w x h` map made here projects under [`cap_bytes`] (which the whole
/// map exceeds: the in-memory route, forced by `--preview`, fails under
/// it) to the in-memory route's file, byte for byte, at lmax 8 and, in
/// the z-up frame, at lmax 64 (the FFT row sums).
fn projects_under_a_memory_cap(name: &str, w: usize, h: usize) {
    if Command::new("prlimit").arg("--version").output().is_err() {
        skip(name, "prlimit (util-linux) is not installed");
        return;
    }
    let dir = temp_dir(name);
    let map = dir.join("large.exr");
    write_large_exr(&map, w, h);
    let cap = cap_bytes();
    assert!(
        (w * h * 12) as u64 > cap,
        "the map's texels must exceed the cap"
    );
    for (lmax, up) in [("8", "y"), ("64", "z")] {
        let args = |out: &Path, preview: bool| {
            let mut a: Vec<String> = [s(&map), "-o", s(out), "--lmax", lmax, "--up", up]
                .map(str::to_string)
                .to_vec();
            if preview {
                let png = dir.join("preview.png");
                a.extend(["--preview", s(&png), "--preview-size", "32x16"].map(str::to_string));
            }
            a
        };
        let streamed = dir.join(format!("streamed-{lmax}.json"));
        let (ok, err) = project(&args(&streamed, false), Some(cap));
        assert!(ok, "streamed under {cap} bytes: {err}");
        let whole = dir.join(format!("whole-{lmax}.json"));
        let (ok, err) = project(&args(&whole, true), None);
        assert!(ok, "in memory: {err}");
        assert!(dir.join("preview.png").exists());
        assert_eq!(
            std::fs::read(&streamed).unwrap(),
            std::fs::read(&whole).unwrap(),
            "lmax {lmax}: the streamed file differs from the in-memory one"
        );
        if lmax == "8" {
            // The cap binds: the whole map does not fit under it.
            let (ok, _) = project(&args(&dir.join("capped.json"), true), Some(cap));
            assert!(!ok, "the in-memory route fitted under {cap} bytes");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// 8192x4096 (402 MB of float texels) under about 200 MB: a few seconds.
#[test]
fn an_8k_map_projects_under_a_memory_cap_as_in_memory() {
    projects_under_a_memory_cap("stream-8k", 8192, 4096);
}

/// 16384x8192 (1.6 GB of float texels) under the same cap, which is an
/// eighth of the texels: the in-memory reference takes 1.7 GB of memory
/// for a few seconds.
#[test]
fn a_16k_map_projects_under_a_memory_cap_as_in_memory() {
    projects_under_a_memory_cap("stream-16k", 16384, 8192);
}

/// Writes the maps `benches/stream.sh` times into `$SHLIGHT_BENCH_DIR`:
/// `envmaps/park.exr` resized to 2048x1024 and 8192x4096 with a small
/// texel-by-texel ripple added (so that the float values compress as a
/// photographed map's do, not as runs), as float ZIP OpenEXR, and the
/// patchy maps of [`write_large_exr`] at 8192x4096 and 16384x8192.
#[test]
#[ignore = "writes benchmark inputs (about 600 MB) for benches/stream.sh"]
fn write_benchmark_maps() {
    let dir = &bench_dir();
    let park = shlight_io::read_image(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("envmaps/park.exr"),
        &shlight_io::ReadOptions::default(),
    )
    .unwrap();
    for (w, h) in [(2048, 1024), (8192, 4096)] {
        let mut map = park.resample(w, h);
        for (i, p) in map.pixels_mut().iter_mut().enumerate() {
            let ripple = ((i * 7919) % 101) as f32 * 1e-3;
            p.iter_mut().for_each(|v| *v += ripple);
        }
        let path = dir.join(format!("park-{w}.exr"));
        shlight_io::write_image(&path, &map, &shlight_io::WriteOptions::default()).unwrap();
    }
    for (w, h) in [(8192, 4096), (16384, 8192)] {
        write_large_exr(&dir.join(format!("patches-{w}.exr")), w, h);
    }
}

/// Writes the patchy 24576x12288 map (3.6 GB of float texels, about 30 MB
/// compressed) into `$SHLIGHT_BENCH_DIR` for the peak-memory figure of
/// docs/benchmarks.md ("Large maps").
#[test]
#[ignore = "writes a 24576x12288 benchmark map (about 30 MB, a minute)"]
fn write_24k_benchmark_map() {
    write_large_exr(&bench_dir().join("patches-24576.exr"), 24576, 12288);
}

/// `$SHLIGHT_BENCH_DIR`, made if missing: where the benchmark maps go.
fn bench_dir() -> std::path::PathBuf {
    let Ok(dir) = std::env::var("SHLIGHT_BENCH_DIR") else {
        panic!("set SHLIGHT_BENCH_DIR to the directory to write the maps into");
    };
    std::fs::create_dir_all(&dir).unwrap();
    dir.into()
}

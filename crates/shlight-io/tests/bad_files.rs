//! Broken inputs give an error naming the file, never a panic: truncated
//! files, corrupted bytes, empty files, files that are not images, missing
//! files, and images over the size limit.

use std::path::{Path, PathBuf};

use image::{ExtendedColorType, ImageEncoder};
use shlight_io::{IoErrorKind, ReadOptions, WriteOptions, read_image, write_image};

use crate::assert_kind;
use crate::util::{TempDir, hdr_image, ldr_image, read};

/// A valid file of every readable kind, in `dir`: (name, path).
fn valid_files(dir: &TempDir) -> Vec<(&'static str, PathBuf)> {
    let hdr = hdr_image(96, 48);
    let mut files = Vec::new();
    for name in ["zip.exr", "plain.exr", "image.hdr", "image.png"] {
        let path = dir.join(name);
        let options = WriteOptions {
            exr_compression: if name == "plain.exr" {
                shlight_io::ExrCompression::None
            } else {
                shlight_io::ExrCompression::Zip
            },
            ..WriteOptions::default()
        };
        let image = if name.ends_with(".png") {
            ldr_image(96, 48)
        } else {
            hdr.clone()
        };
        write_image(&path, &image, &options).unwrap();
        files.push((name, path));
    }
    // A real DWAB file.
    let park = dir.join("dwab.exr");
    std::fs::copy(crate::envmaps::dir().join("park.exr"), &park).unwrap();
    files.push(("dwab.exr", park));
    // Baseline and progressive JPEG are both common; the encoder writes
    // baseline.
    let jpeg = dir.join("image.jpg");
    let rgb: Vec<u8> = (0..96 * 48 * 3).map(|i| (i * 7 % 256) as u8).collect();
    image::codecs::jpeg::JpegEncoder::new_with_quality(std::fs::File::create(&jpeg).unwrap(), 90)
        .write_image(&rgb, 96, 48, ExtendedColorType::Rgb8)
        .unwrap();
    files.push(("image.jpg", jpeg));
    for (_, path) in &files {
        read(path).unwrap_or_else(|e| panic!("fixture unreadable: {e}"));
    }
    files
}

fn write_prefix(dir: &TempDir, source: &Path, name: &str, len: usize) -> PathBuf {
    let bytes = std::fs::read(source).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, &bytes[..len]).unwrap();
    path
}

#[test]
fn files_cut_in_half_are_reported_truncated() {
    let dir = TempDir::new("truncated");
    for (name, path) in valid_files(&dir) {
        let len = std::fs::metadata(&path).unwrap().len() as usize;
        let cut = write_prefix(&dir, &path, &format!("half-{name}"), len / 2);
        let result = read(&cut);
        assert_kind!(result, IoErrorKind::Truncated);
        let message = result.unwrap_err().to_string();
        assert_eq!(
            message,
            format!(
                "{}: truncated file (the image data ends early)",
                cut.display()
            ),
        );
    }
}

#[test]
fn files_cut_anywhere_give_an_error() {
    let dir = TempDir::new("cut-anywhere");
    for (name, path) in valid_files(&dir) {
        let len = std::fs::metadata(&path).unwrap().len() as usize;
        // Inside the signature, inside the header, and through the data.
        let mut cuts: Vec<usize> = vec![1, 3, 11, 40, 100, 300];
        cuts.extend((1..20).map(|i| len * i / 20));
        cuts.push(len - 1);
        for cut in cuts.into_iter().filter(|&c| c < len) {
            let short = write_prefix(&dir, &path, &format!("cut-{cut}-{name}"), cut);
            let result = read(&short);
            let Err(err) = result else {
                // A PNG cut in its last chunk (IEND) still holds every
                // pixel; nothing else may decode.
                assert!(
                    name.ends_with(".png") && cut >= len - 12,
                    "{name} cut at {cut} of {len} read"
                );
                continue;
            };
            assert_eq!(err.path(), short, "{err}");
            // Past the header and signature, every cut is a truncation.
            if cut >= len / 4 {
                assert!(
                    matches!(err.kind(), IoErrorKind::Truncated),
                    "{name} cut at {cut} of {len}: {err}"
                );
            }
        }
    }
}

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

#[test]
fn corrupted_bytes_give_an_error_or_an_image() {
    let dir = TempDir::new("corrupt");
    let mut rng = Rng(0x5eed_1234_abcd_0001);
    let mut decoder_panics = Vec::new();
    for (name, path) in valid_files(&dir) {
        let bytes = std::fs::read(&path).unwrap();
        for trial in 0..24 {
            let mut damaged = bytes.clone();
            // Flip a run of bytes in the middle half of the file (the data),
            // and in later trials also single bytes anywhere past the
            // signature.
            let len = damaged.len();
            let start = len / 4 + (rng.next() as usize) % (len / 2);
            let run = 1 + (rng.next() as usize) % 16;
            for b in &mut damaged[start..(start + run).min(len)] {
                *b ^= 0xff;
            }
            if trial >= 12 {
                for _ in 0..4 {
                    let at = 8 + (rng.next() as usize) % (len - 8);
                    damaged[at] = rng.next() as u8;
                }
            }
            let damaged_path = dir.join(&format!("corrupt-{trial}-{name}"));
            std::fs::write(&damaged_path, &damaged).unwrap();
            // Must return, whatever it returns.
            match read(&damaged_path) {
                Ok(image) => assert!(image.width() > 0 && image.height() > 0),
                Err(err) => {
                    assert_eq!(err.path(), damaged_path);
                    if err.to_string().contains("decoder failed") {
                        decoder_panics.push(err.to_string());
                    }
                }
            }
        }
    }
    if !decoder_panics.is_empty() {
        eprintln!(
            "note: {} decoder panics were caught and reported as errors:\n{}",
            decoder_panics.len(),
            decoder_panics.join("\n")
        );
    }
}

#[test]
fn empty_file() {
    let dir = TempDir::new("empty");
    for name in ["empty.exr", "empty.png", "empty"] {
        let path = dir.join(name);
        std::fs::write(&path, b"").unwrap();
        let result = read(&path);
        assert_kind!(result, IoErrorKind::Empty);
        assert_eq!(
            result.unwrap_err().to_string(),
            format!("{}: empty file (0 bytes)", path.display())
        );
    }
}

#[test]
fn files_that_are_not_images() {
    let dir = TempDir::new("not-images");
    let text = b"{\"coefficients\": [1, 2, 3]}\n";

    let json = dir.join("sh.json");
    std::fs::write(&json, text).unwrap();
    let result = read(&json);
    assert_kind!(result, IoErrorKind::UnknownFormat);
    assert_eq!(
        result.unwrap_err().to_string(),
        format!(
            "{}: unknown image format (not OpenEXR, Radiance HDR, PNG or JPEG)",
            json.display()
        )
    );

    // An image extension on something else: corrupt, naming the format.
    for (name, format) in [("x.exr", "OpenEXR"), ("x.png", "PNG"), ("x.jpeg", "JPEG")] {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let result = read(&path);
        assert_kind!(result, IoErrorKind::Corrupt(_));
        let message = result.unwrap_err().to_string();
        assert!(
            message.contains(&format!("{format} signature")),
            "{message}"
        );
    }
    // Radiance has no mandatory signature, so its decoder decides.
    let hdr = dir.join("x.hdr");
    std::fs::write(&hdr, text).unwrap();
    assert!(read(&hdr).is_err());

    // A signature followed by garbage.
    let garbage = dir.join("garbage.bin");
    std::fs::write(
        &garbage,
        [&[0x76, 0x2f, 0x31, 0x01][..], &[0xab; 64]].concat(),
    )
    .unwrap();
    assert!(read(&garbage).is_err());
}

#[test]
fn missing_file_and_directory() {
    let dir = TempDir::new("missing");
    let path = dir.join("envmaps/none.exr");
    let result = read(&path);
    assert_kind!(result, IoErrorKind::NotFound);
    assert_eq!(
        result.unwrap_err().to_string(),
        format!("{}: file not found", path.display())
    );

    let result = read(dir.path());
    assert_kind!(result, IoErrorKind::Unreadable(_));
    assert!(
        result
            .unwrap_err()
            .to_string()
            .contains("cannot read the file")
    );
}

#[test]
fn too_large_for_max_pixels() {
    let dir = TempDir::new("too-large");
    for (name, path) in valid_files(&dir) {
        let (w, h) = if name == "dwab.exr" {
            (512, 256)
        } else {
            (96, 48)
        };
        let limit = |max_pixels| ReadOptions {
            max_pixels,
            ..ReadOptions::default()
        };
        let result = read_image(&path, &limit(w * h - 1));
        match result {
            Err(ref e) => match e.kind() {
                IoErrorKind::TooLarge {
                    width,
                    height,
                    max_pixels,
                } => assert_eq!((*width, *height, *max_pixels), (w, h, w * h - 1), "{name}"),
                other => panic!("{name}: expected TooLarge, got {other:?}"),
            },
            Ok(_) => panic!("{name}: expected TooLarge"),
        }
        let message = result.unwrap_err().to_string();
        assert!(
            message.ends_with(&format!(
                "image too large ({w}x{h} pixels; the limit is {} pixels)",
                w * h - 1
            )),
            "{message}"
        );
        read_image(&path, &limit(w * h)).unwrap();
    }
}

#[test]
fn huge_headers_are_refused_before_allocating() {
    let dir = TempDir::new("huge-headers");
    let huge = |result: Result<shlight_io::Image, shlight_io::IoError>| {
        assert_kind!(
            result,
            IoErrorKind::TooLarge {
                width: 100_000,
                height: 100_000,
                ..
            }
        );
    };

    // Radiance: a header and nothing else.
    let hdr = dir.join("huge.hdr");
    std::fs::write(
        &hdr,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n",
    )
    .unwrap();
    huge(read(&hdr));

    // PNG: IHDR, a tiny IDAT and IEND; the IDAT holds almost nothing.
    let png = dir.join("huge.png");
    let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&100_000u32.to_be_bytes());
    ihdr.extend_from_slice(&100_000u32.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    for (kind, data) in [
        (b"IHDR", ihdr),
        (b"IDAT", vec![0x78, 0x9c, 0x03, 0x00]),
        (b"IEND", vec![]),
    ] {
        bytes.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let typed = [&kind[..], &data].concat();
        bytes.extend_from_slice(&typed);
        bytes.extend_from_slice(&crc32(&typed).to_be_bytes());
    }
    std::fs::write(&png, bytes).unwrap();
    huge(read(&png));

    // OpenEXR: a real file whose windows are rewritten to 100000 x 100000
    // (one without a `chunkCount` attribute, which would contradict them).
    let exr = dir.join("huge.exr");
    let mut bytes = std::fs::read(crate::envmaps::dir().join("city.exr")).unwrap();
    for attribute in [&b"dataWindow\0box2i\0"[..], &b"displayWindow\0box2i\0"[..]] {
        let at = bytes
            .windows(attribute.len())
            .position(|w| w == attribute)
            .unwrap()
            + attribute.len()
            + 4;
        for (i, v) in [0i32, 0, 99_999, 99_999].into_iter().enumerate() {
            bytes[at + 4 * i..at + 4 * i + 4].copy_from_slice(&v.to_le_bytes());
        }
    }
    std::fs::write(&exr, bytes).unwrap();
    huge(read(&exr));
}

/// CRC-32 (ISO-HDLC), as PNG chunks use.
fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A DWA block whose header claims an absurd coefficient count: `exr` 1.74
/// would try to allocate it up front and abort the process (found by
/// fuzzing); the reader must refuse the block first.
#[test]
fn dwa_block_with_impossible_sizes_is_refused() {
    let dir = TempDir::new("dwa-sizes");
    let source =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/openexr-dwaa-half.exr");
    let bytes = std::fs::read(&source).unwrap();
    // One chunk (24 lines fit in a DWAA block of 32).
    let chunk = find_single_chunk(&bytes);
    // Chunk: y (4 bytes), data size (4), then the DWA header: 11 u64.
    let counters = chunk + 8;
    for (index, what) in [(8, "AC coefficient count"), (1, "unknown-channel size")] {
        let mut damaged = bytes.clone();
        let at = counters + 8 * index;
        damaged[at..at + 8].copy_from_slice(&(1u64 << 40).to_le_bytes());
        let path = dir.join(&format!("counter-{index}.exr"));
        std::fs::write(&path, &damaged).unwrap();
        let result = read(&path);
        assert_kind!(result, IoErrorKind::Corrupt(_));
        let message = result.unwrap_err().to_string();
        assert!(message.contains(what), "{message}");
    }
}

/// The offset of the only chunk of a single-part scan-line file: its
/// one-entry offset table is the u64 just before it, holding that offset.
fn find_single_chunk(bytes: &[u8]) -> usize {
    let table = (8..bytes.len() - 8)
        .find(|&at| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) == (at + 8) as u64)
        .unwrap();
    table + 8
}

/// A 256x32 PIZ file with 67 half channels (R, G, B and 64 others) has one
/// block of 256 x 32 pixels x 134 bytes, which `exr` allocates whole before
/// decompressing. Refused when that exceeds 16 bytes a pixel of the limit
/// (here the image's own pixel count), read at the default limit.
#[test]
fn openexr_blocks_beyond_the_pixel_limit_are_refused_before_decompressing() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/many-channels-piz.exr");
    let pixels = 256 * 32;
    let options = ReadOptions {
        max_pixels: pixels,
        ..ReadOptions::default()
    };
    let e = read_image(&path, &options).unwrap_err();
    assert!(matches!(e.kind(), IoErrorKind::Unsupported(_)), "{e}");
    let message = e.to_string();
    assert!(
        message.contains(&format!(
            "OpenEXR blocks of {} bytes decompressed (67 channels), more than the {} bytes",
            pixels * 67 * 2,
            16 * pixels
        )),
        "{message}"
    );
    let image = read_image(&path, &ReadOptions::default()).unwrap();
    assert_eq!((image.width(), image.height()), (256, 32));
    assert_eq!(image.get(100, 10), [0.5; 3]);
}

//! Reading by rows (`open_rows`, and `read_image_by_rows` built on it):
//! every streaming reader hands out the whole-image reader's values bit for
//! bit, each row once, and refuses what it refuses with the same error.

use std::path::Path;
use std::sync::Mutex;

use exr::prelude::{
    AnyChannel, AnyChannels, Blocks, Compression, Encoding, FlatSamples, LayerAttributes,
    LineOrder, SmallVec, Vec2, WritableImage,
};
use image::{ExtendedColorType, ImageEncoder};
use shlight_io::{
    Image, ReadOptions, RowSource, WriteOptions, open_rows, read_image, read_image_by_rows,
    write_image,
};

use crate::util::{TempDir, hdr_image, ldr_image};

/// Every row of `source` gathered into an image; panics if a row comes
/// twice or never.
fn gather(source: &dyn RowSource) -> Result<Image, shlight_io::IoError> {
    let (w, h) = source.size();
    let rows = Mutex::new((vec![[f32::NAN; 3]; w * h], vec![false; h]));
    source.read_rows(&|first, band: &[[f32; 3]]| {
        assert_eq!(band.len() % w, 0, "whole rows");
        let mut rows = rows.lock().unwrap();
        for (k, row) in band.chunks(w).enumerate() {
            let y = first + k;
            assert!(!rows.1[y], "row {y} twice");
            rows.1[y] = true;
            rows.0[y * w..(y + 1) * w].copy_from_slice(row);
        }
    })?;
    let (pixels, seen) = rows.into_inner().unwrap();
    assert!(seen.iter().all(|&s| s), "a row never came");
    Ok(Image::new(w, h, pixels).unwrap())
}

/// The bits of every value (NaN payloads and signed zeros included).
fn bits(image: &Image) -> Vec<u32> {
    image
        .pixels()
        .iter()
        .flatten()
        .map(|v| v.to_bits())
        .collect()
}

fn check(path: &Path, streams: bool) {
    let whole = read_image(path, &ReadOptions::default()).unwrap();
    let source = open_rows(path, &ReadOptions::default()).unwrap();
    assert_eq!(source.streams(), streams, "{}", path.display());
    assert_eq!(source.size(), (whole.width(), whole.height()));
    let rows = gather(source.as_ref()).unwrap();
    assert_eq!(bits(&rows), bits(&whole), "{}", path.display());
    let by_rows = read_image_by_rows(path, &ReadOptions::default()).unwrap();
    assert_eq!(
        (by_rows.width(), by_rows.height()),
        (whole.width(), whole.height())
    );
    assert_eq!(bits(&by_rows), bits(&whole), "{}", path.display());
}

/// Writes `image` as float RGB with the given compression, blocks and
/// line order.
fn write_exr(
    path: &Path,
    image: &Image,
    compression: Compression,
    blocks: Blocks,
    order: LineOrder,
) {
    let size = (image.width(), image.height());
    let channel = |c: usize| FlatSamples::F32(image.pixels().iter().map(|p| p[c]).collect());
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = ["R", "G", "B"]
        .into_iter()
        .enumerate()
        .map(|(c, name)| AnyChannel::new(name, channel(c)))
        .collect();
    let encoding = Encoding {
        compression,
        blocks,
        line_order: order,
    };
    let layer = exr::image::Layer::new(
        size,
        LayerAttributes::default(),
        encoding,
        AnyChannels::sort(list),
    );
    exr::image::Image::from_layer(layer)
        .write()
        .to_file(path)
        .unwrap();
}

#[test]
fn openexr_scan_lines_and_tiles_stream_the_whole_image_values() {
    let dir = TempDir::new("rows-exr");
    // Not a multiple of any block or tile size; special values inside.
    let mut image = hdr_image(67, 41);
    image.set(5, 3, [f32::NAN, -0.0, f32::INFINITY]);
    image.set(66, 40, [-2.5, f32::NEG_INFINITY, 1e30]);
    let mut n = 0;
    for compression in [
        Compression::Uncompressed,
        Compression::RLE,
        Compression::ZIP1,
        Compression::ZIP16,
        Compression::PIZ,
        Compression::PXR24,
        Compression::B44,
        Compression::B44A,
    ] {
        for (blocks, order) in [
            (Blocks::ScanLines, LineOrder::Increasing),
            (Blocks::ScanLines, LineOrder::Decreasing),
            (Blocks::Tiles(Vec2(16, 8)), LineOrder::Increasing),
            (Blocks::Tiles(Vec2(32, 32)), LineOrder::Decreasing),
        ] {
            n += 1;
            let path = dir.join(&format!("{n}.exr"));
            write_exr(&path, &image, compression, blocks, order);
            check(&path, true);
        }
    }
    // Files OpenEXR itself wrote, DWAA and DWAB included, and the bundled
    // maps.
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    for entry in std::fs::read_dir(&data).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "exr")
            && read_image(&path, &ReadOptions::default()).is_ok()
        {
            check(&path, true);
        }
    }
    for name in ["sky.exr", "park.exr"] {
        check(&crate::envmaps::dir().join(name), true);
    }
}

#[test]
fn radiance_and_png_stream_the_whole_image_values() {
    let dir = TempDir::new("rows-hdr-png");
    let path = dir.join("image.hdr");
    write_image(&path, &hdr_image(300, 150), &WriteOptions::default()).unwrap();
    check(&path, true);
    // Old RLE: runs marked `1 1 1 n`, and flat pixels.
    let path = dir.join("old.hdr");
    let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 5\n".to_vec();
    bytes.extend_from_slice(&[128, 64, 32, 129, 1, 1, 1, 3, 9, 9, 9, 120]);
    bytes.extend_from_slice(&[
        1, 2, 3, 130, 4, 5, 6, 131, 7, 8, 9, 0, 0, 0, 0, 0, 10, 10, 10, 140,
    ]);
    std::fs::write(&path, &bytes).unwrap();
    check(&path, true);

    let path = dir.join("image.png");
    write_image(&path, &ldr_image(97, 31), &WriteOptions::default()).unwrap();
    check(&path, true);
    let write_png = |name: &str, data: &[u8], colour: ExtendedColorType| {
        let path = dir.join(name);
        image::codecs::png::PngEncoder::new(std::fs::File::create(&path).unwrap())
            .write_image(data, 7, 3, colour)
            .unwrap();
        path
    };
    let bytes: Vec<u8> = (0..7 * 3 * 8).map(|i| (i * 37 % 256) as u8).collect();
    for (name, colour, per_pixel) in [
        ("grey8.png", ExtendedColorType::L8, 1),
        ("greya8.png", ExtendedColorType::La8, 2),
        ("rgba8.png", ExtendedColorType::Rgba8, 4),
        ("grey16.png", ExtendedColorType::L16, 2),
        ("rgb16.png", ExtendedColorType::Rgb16, 6),
        ("rgba16.png", ExtendedColorType::Rgba16, 8),
    ] {
        check(&write_png(name, &bytes[..7 * 3 * per_pixel], colour), true);
    }
    // JPEG is read whole, then handed out by rows.
    let path = dir.join("image.jpg");
    let rgb: Vec<u8> = (0..40 * 20 * 3).map(|i| (i * 7 % 256) as u8).collect();
    image::codecs::jpeg::JpegEncoder::new_with_quality(std::fs::File::create(&path).unwrap(), 90)
        .write_image(&rgb, 40, 20, ExtendedColorType::Rgb8)
        .unwrap();
    check(&path, false);
}

/// A file cut short or damaged gives the whole-image reader's error, when
/// opened or while its rows are read.
#[test]
fn broken_files_give_the_whole_image_readers_error() {
    let dir = TempDir::new("rows-broken");
    let image = hdr_image(96, 48);
    for name in ["zip.exr", "image.hdr", "image.png"] {
        let path = dir.join(name);
        let picture = if name.ends_with(".png") {
            ldr_image(96, 48)
        } else {
            image.clone()
        };
        write_image(&path, &picture, &WriteOptions::default()).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        for cut in [bytes.len() / 3, bytes.len() * 2 / 3, bytes.len() - 20] {
            let short = dir.join(&format!("cut-{cut}-{name}"));
            std::fs::write(&short, &bytes[..cut]).unwrap();
            let want = read_image(&short, &ReadOptions::default()).unwrap_err();
            let got = open_rows(&short, &ReadOptions::default())
                .and_then(|source| gather(source.as_ref()).map(|_| ()))
                .expect_err(&format!("{name} cut at {cut} of {}: {want}", bytes.len()));
            assert_eq!(got.to_string(), want.to_string(), "{name} cut at {cut}");
            let got = read_image_by_rows(&short, &ReadOptions::default()).unwrap_err();
            assert_eq!(got.to_string(), want.to_string(), "{name} cut at {cut}");
        }
    }
    // The pixel limit, judged from the header.
    let path = dir.join("zip.exr");
    let small = ReadOptions {
        max_pixels: 96 * 48 - 1,
        ..ReadOptions::default()
    };
    let want = read_image(&path, &small).unwrap_err();
    let got = open_rows(&path, &small).err().unwrap();
    assert_eq!(got.to_string(), want.to_string());
    let got = read_image_by_rows(&path, &small).unwrap_err();
    assert_eq!(got.to_string(), want.to_string());
}

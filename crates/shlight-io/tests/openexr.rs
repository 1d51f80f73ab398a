//! OpenEXR: round trips through `write_image`, and files made with the
//! `exr` crate to exercise what the reader must handle (compressions, tiles,
//! sample types, data windows, layers).

use std::path::Path;

use exr::prelude::{
    AnyChannel, AnyChannels, Blocks, Compression, Encoding, FlatSamples, ImageAttributes,
    IntegerBounds, LayerAttributes, LineOrder, SmallVec, Vec2, WritableImage, f16,
};
use shlight_io::{
    ExrCompression, Image, IoErrorKind, ReadOptions, WriteOptions, read_image, write_image,
};

use crate::assert_kind;
use crate::util::{TempDir, hdr_image, read};

type ExrLayer = exr::image::Layer<AnyChannels<FlatSamples>>;

/// A layer of `size` with the given channels, scan lines, ZIP.
fn layer(size: (usize, usize), channels: Vec<(&str, FlatSamples)>) -> ExrLayer {
    layer_with(
        size,
        channels,
        LayerAttributes::default(),
        encoding(Compression::ZIP16),
    )
}

fn layer_with(
    size: (usize, usize),
    channels: Vec<(&str, FlatSamples)>,
    attributes: LayerAttributes,
    encoding: Encoding,
) -> ExrLayer {
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = channels
        .into_iter()
        .map(|(name, samples)| AnyChannel::new(name, samples))
        .collect();
    exr::image::Layer::new(size, attributes, encoding, AnyChannels::sort(list))
}

fn encoding(compression: Compression) -> Encoding {
    Encoding {
        compression,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    }
}

/// Writes the layers with the given display window.
fn write_exr(path: &Path, display: IntegerBounds, layers: Vec<ExrLayer>) {
    let image = exr::image::Image {
        attributes: ImageAttributes::new(display),
        layer_data: layers.into_iter().collect::<SmallVec<[ExrLayer; 2]>>(),
    };
    image.write().to_file(path).unwrap();
}

/// R, G, B half channels of `image`.
fn rgb_half(image: &Image) -> Vec<(&'static str, FlatSamples)> {
    let channel =
        |c: usize| FlatSamples::F16(image.pixels().iter().map(|p| f16::from_f32(p[c])).collect());
    vec![("R", channel(0)), ("G", channel(1)), ("B", channel(2))]
}

/// The image with every value rounded to half precision.
fn to_half(image: &Image) -> Image {
    let mut out = image.clone();
    for v in out.pixels_mut().iter_mut().flatten() {
        *v = f16::from_f32(*v).to_f32();
    }
    out
}

fn full(size: (usize, usize)) -> IntegerBounds {
    IntegerBounds::from_dimensions(size)
}

#[test]
fn float_round_trip_is_exact() {
    let dir = TempDir::new("exr-round-trip");
    let mut image = hdr_image(37, 19);
    // Values a half could not hold, and non-finite ones: float keeps them.
    image.set(0, 0, [1e-30, 123_456.79, -7.25]);
    image.set(1, 0, [f32::INFINITY, f32::MIN_POSITIVE, 1.0 / 3.0]);
    for compression in [ExrCompression::Zip, ExrCompression::None] {
        let path = dir.join(&format!("{compression:?}.exr"));
        let options = WriteOptions {
            exr_compression: compression,
            ..WriteOptions::default()
        };
        write_image(&path, &image, &options).unwrap();
        assert_eq!(read(&path).unwrap(), image, "{compression:?}");
    }
    // ZIP does compress this.
    let zip = std::fs::metadata(dir.join("Zip.exr")).unwrap().len();
    let none = std::fs::metadata(dir.join("None.exr")).unwrap().len();
    assert!(zip < none, "zip {zip} bytes, none {none} bytes");
}

#[test]
fn written_file_is_float_rgb() {
    let dir = TempDir::new("exr-written-header");
    let path = dir.join("x.exr");
    write_image(&path, &hdr_image(8, 4), &WriteOptions::default()).unwrap();
    let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
    let header = &meta.headers[0];
    let channels: Vec<_> = header
        .channels
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_type))
        .collect();
    use exr::prelude::SampleType::F32;
    assert_eq!(
        channels,
        [("B".into(), F32), ("G".into(), F32), ("R".into(), F32)]
    );
    assert_eq!(header.compression, Compression::ZIP16);
}

#[test]
fn exposure_scales_exr_by_powers_of_two() {
    let dir = TempDir::new("exr-exposure");
    let path = dir.join("x.exr");
    let image = hdr_image(8, 4);
    // Tone mapping is ignored for linear formats.
    let options = WriteOptions {
        exposure_ev: -2.0,
        tone_map: shlight_io::ToneMap::Aces,
        ..WriteOptions::default()
    };
    write_image(&path, &image, &options).unwrap();
    let back = read(&path).unwrap();
    for (a, b) in image.pixels().iter().zip(back.pixels()) {
        assert_eq!(a.map(|v| v * 0.25), *b);
    }
}

/// B44 and DWA at default settings on smooth content: their mean error is
/// well under 1%; 2% leaves room without hiding a wrong decode (which is off
/// by far more).
const LOSSY_MEAN_RELATIVE: f32 = 0.02;

#[test]
fn every_compression_is_read() {
    let dir = TempDir::new("exr-compressions");
    // Smooth content, as lossy codecs expect.
    let image = Image::from_fn(64, 40, |x, y| {
        let (u, v) = (x as f32 / 64.0, y as f32 / 40.0);
        [0.1 + 4.0 * u, 0.2 + 2.0 * v * v, 1.0 + u * v]
    });
    let half = to_half(&image);
    let lossless = [
        Compression::Uncompressed,
        Compression::RLE,
        Compression::ZIP1,
        Compression::ZIP16,
        Compression::PIZ,
        // PXR24 is lossless for half samples.
        Compression::PXR24,
    ];
    let lossy = [
        Compression::B44,
        Compression::B44A,
        Compression::DWAA(None),
        Compression::DWAB(None),
    ];
    for compression in lossless.into_iter().chain(lossy) {
        let path = dir.join(&format!("{compression:?}.exr"));
        let l = layer_with(
            (64, 40),
            rgb_half(&image),
            LayerAttributes::default(),
            encoding(compression),
        );
        write_exr(&path, full((64, 40)), vec![l]);
        let back = read(&path).unwrap_or_else(|e| panic!("{compression:?}: {e}"));
        if lossless.contains(&compression) {
            assert_eq!(back, half, "{compression:?}");
        } else {
            let err: f32 = half
                .pixels()
                .iter()
                .flatten()
                .zip(back.pixels().iter().flatten())
                .map(|(a, b)| (a - b).abs() / a.abs())
                .sum::<f32>()
                / (64 * 40 * 3) as f32;
            assert!(
                err < LOSSY_MEAN_RELATIVE,
                "{compression:?}: mean relative error {err}"
            );
        }
    }
}

#[test]
fn tiles_float_and_uint_samples() {
    let dir = TempDir::new("exr-tiles");
    // Not a multiple of the tile size.
    let size = (37, 23);
    let image = hdr_image(size.0, size.1);
    let float = |c: usize| FlatSamples::F32(image.pixels().iter().map(|p| p[c]).collect());
    let tiled = Encoding {
        compression: Compression::PIZ,
        blocks: Blocks::Tiles(Vec2(16, 16)),
        line_order: LineOrder::Increasing,
    };
    let path = dir.join("tiled.exr");
    let l = layer_with(
        size,
        vec![("R", float(0)), ("G", float(1)), ("B", float(2))],
        LayerAttributes::default(),
        tiled,
    );
    write_exr(&path, full(size), vec![l]);
    assert_eq!(read(&path).unwrap(), image);

    // uint samples read as their numeric value; mixed sample types.
    let path = dir.join("uint.exr");
    let n = size.0 * size.1;
    let l = layer(
        size,
        vec![
            ("R", FlatSamples::U32((0..n as u32).collect())),
            ("G", FlatSamples::F16(vec![f16::from_f32(0.5); n])),
            ("B", FlatSamples::F32(vec![2.0; n])),
        ],
    );
    write_exr(&path, full(size), vec![l]);
    let back = read(&path).unwrap();
    assert_eq!(back.get(3, 2), [(3 + 2 * 37) as f32, 0.5, 2.0]);
}

#[test]
fn mip_mapped_file_reads_the_largest_level() {
    use exr::image::Levels;
    use exr::math::RoundingMode;
    let dir = TempDir::new("exr-mipmap");
    let size = Vec2(37, 23);
    let image = hdr_image(37, 23);
    // Level 0 is the image; smaller levels hold a constant that must not
    // leak into the result.
    let levels = |c: usize| {
        let level_data = exr::meta::mip_map_levels(RoundingMode::Down, size)
            .map(|(level, Vec2(w, h))| {
                let samples = if level == 0 {
                    image.pixels().iter().map(|p| p[c]).collect()
                } else {
                    vec![-1.0; w * h]
                };
                FlatSamples::F32(samples)
            })
            .collect();
        Levels::Mip {
            rounding_mode: RoundingMode::Down,
            level_data,
        }
    };
    let channels = AnyChannels::sort(
        ["R", "G", "B"]
            .into_iter()
            .enumerate()
            .map(|(c, name)| AnyChannel::new(name, levels(c)))
            .collect(),
    );
    let encoding = Encoding {
        compression: Compression::ZIP1,
        blocks: Blocks::Tiles(Vec2(8, 8)),
        line_order: LineOrder::Increasing,
    };
    let layer = exr::image::Layer::new(size, LayerAttributes::default(), encoding, channels);
    let path = dir.join("mip.exr");
    exr::image::Image::from_layer(layer)
        .write()
        .to_file(&path)
        .unwrap();
    let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
    assert!(meta.headers[0].chunk_count > 24, "no mip levels written");
    assert_eq!(read(&path).unwrap(), image);
}

#[test]
fn alpha_is_dropped_and_luminance_becomes_grey() {
    let dir = TempDir::new("exr-alpha-luma");
    let size = (5, 3);
    let image = to_half(&hdr_image(5, 3));
    let mut channels = rgb_half(&image);
    channels.push(("A", FlatSamples::F16(vec![f16::from_f32(0.25); 15])));
    let path = dir.join("rgba.exr");
    write_exr(&path, full(size), vec![layer(size, channels)]);
    assert_eq!(read(&path).unwrap(), image);

    let path = dir.join("y.exr");
    let luma: Vec<f32> = (0..15).map(|i| i as f32 * 0.5).collect();
    write_exr(
        &path,
        full(size),
        vec![layer(size, vec![("Y", FlatSamples::F32(luma.clone()))])],
    );
    let back = read(&path).unwrap();
    let expected: Vec<[f32; 3]> = luma.iter().map(|&v| [v, v, v]).collect();
    assert_eq!(back.pixels(), expected.as_slice());
}

#[test]
fn offset_data_window_is_placed_in_the_display_window() {
    let dir = TempDir::new("exr-data-window");
    let data = hdr_image(4, 3);
    let attributes = LayerAttributes {
        layer_position: Vec2(2, 1),
        ..LayerAttributes::default()
    };
    let path = dir.join("offset.exr");
    let l = layer_with(
        (4, 3),
        rgb_f32(&data),
        attributes,
        encoding(Compression::ZIP16),
    );
    write_exr(&path, full((8, 6)), vec![l]);

    let back = read(&path).unwrap();
    assert_eq!((back.width(), back.height()), (8, 6));
    for y in 0..6 {
        for x in 0..8 {
            let inside = (2..6).contains(&x) && (1..4).contains(&y);
            let expected = if inside {
                data.get(x - 2, y - 1)
            } else {
                [0.0; 3]
            };
            assert_eq!(back.get(x, y), expected, "({x}, {y})");
        }
    }
}

#[test]
fn data_window_partly_outside_a_shifted_display_window() {
    let dir = TempDir::new("exr-data-window-outside");
    // Display window (-3, -2) to (2, 1): 6x4. Data window (-5, 0), 4x3:
    // columns -5..=-2 and rows 0..=2, so only (-3..=-2, 0..=1) is shown.
    let data = hdr_image(4, 3);
    let attributes = LayerAttributes {
        layer_position: Vec2(-5, 0),
        ..LayerAttributes::default()
    };
    let path = dir.join("outside.exr");
    let l = layer_with(
        (4, 3),
        rgb_f32(&data),
        attributes,
        encoding(Compression::RLE),
    );
    write_exr(&path, IntegerBounds::new((-3, -2), (6, 4)), vec![l]);

    let back = read(&path).unwrap();
    assert_eq!((back.width(), back.height()), (6, 4));
    for y in 0..4 {
        for x in 0..6 {
            // Absolute coordinates of this display pixel.
            let (ax, ay) = (x as i32 - 3, y as i32 - 2);
            let (dx, dy) = (ax + 5, ay);
            let expected = if (0..4).contains(&dx) && (0..3).contains(&dy) {
                data.get(dx as usize, dy as usize)
            } else {
                [0.0; 3]
            };
            assert_eq!(back.get(x, y), expected, "({x}, {y})");
        }
    }
}

fn rgb_f32(image: &Image) -> Vec<(&'static str, FlatSamples)> {
    let channel = |c: usize| FlatSamples::F32(image.pixels().iter().map(|p| p[c]).collect());
    vec![("R", channel(0)), ("G", channel(1)), ("B", channel(2))]
}

fn constant(value: f32, n: usize) -> FlatSamples {
    FlatSamples::F32(vec![value; n])
}

/// One part: unnamed R, G, B = 1, 2, 3; `diffuse.*` = 4, 5, 6; `depth.Z`.
fn single_part_layers(path: &Path) {
    let n = 6;
    let l = layer(
        (3, 2),
        vec![
            ("R", constant(1.0, n)),
            ("G", constant(2.0, n)),
            ("B", constant(3.0, n)),
            ("diffuse.R", constant(4.0, n)),
            ("diffuse.G", constant(5.0, n)),
            ("diffuse.B", constant(6.0, n)),
            ("depth.Z", constant(9.0, n)),
        ],
    );
    write_exr(path, full((3, 2)), vec![l]);
}

fn with_layer(name: &str) -> ReadOptions {
    ReadOptions {
        layer: Some(name.into()),
        ..ReadOptions::default()
    }
}

#[test]
fn layers_of_one_part_are_selected_by_prefix() {
    let dir = TempDir::new("exr-layers");
    let path = dir.join("layers.exr");
    single_part_layers(&path);

    let default = read(&path).unwrap();
    assert_eq!(default.get(2, 1), [1.0, 2.0, 3.0]);
    let unnamed = read_image(&path, &with_layer("")).unwrap();
    assert_eq!(unnamed, default);
    let diffuse = read_image(&path, &with_layer("diffuse")).unwrap();
    assert_eq!(diffuse.get(0, 0), [4.0, 5.0, 6.0]);

    let missing = read_image(&path, &with_layer("specular"));
    assert_kind!(missing, IoErrorKind::LayerNotFound { .. });
    let err = missing.unwrap_err();
    let IoErrorKind::LayerNotFound { wanted, available } = err.kind() else {
        unreachable!()
    };
    assert_eq!(wanted, "specular");
    assert_eq!(available, &["", "depth", "diffuse"]);
    let message = err.to_string();
    assert!(
        message.starts_with(&path.display().to_string()),
        "{message}"
    );
    assert!(
        message.ends_with(
            ": no layer named \"specular\" (the file has layers \"\" (unnamed), \"depth\", \"diffuse\")"
        ),
        "{message}"
    );

    // A layer without colour channels.
    let depth = read_image(&path, &with_layer("depth"));
    assert_kind!(depth, IoErrorKind::Unsupported(_));
    assert!(depth.unwrap_err().to_string().contains("depth.Z"));
}

#[test]
fn layers_of_a_multi_part_file() {
    let dir = TempDir::new("exr-parts");
    let path = dir.join("parts.exr");
    let n = 6;
    let part = |name: &str, channels| {
        layer_with(
            (3, 2),
            channels,
            LayerAttributes::named(name),
            encoding(Compression::ZIP1),
        )
    };
    write_exr(
        &path,
        full((3, 2)),
        vec![
            part("mask", vec![("Z", constant(0.5, n))]),
            part(
                "beauty",
                vec![
                    ("R", constant(1.0, n)),
                    ("G", constant(2.0, n)),
                    ("B", constant(3.0, n)),
                ],
            ),
            part(
                "aov",
                vec![
                    ("normal.R", constant(7.0, n)),
                    ("normal.G", constant(8.0, n)),
                    ("normal.B", constant(9.0, n)),
                ],
            ),
        ],
    );
    // The first part with R, G, B, skipping the mask.
    assert_eq!(read(&path).unwrap().get(0, 0), [1.0, 2.0, 3.0]);
    let normal = read_image(&path, &with_layer("aov.normal")).unwrap();
    assert_eq!(normal.get(1, 1), [7.0, 8.0, 9.0]);
    let missing = read_image(&path, &with_layer("normal")).unwrap_err();
    match missing.kind() {
        IoErrorKind::LayerNotFound { available, .. } => {
            assert_eq!(available, &["mask", "beauty", "aov.normal"]);
        }
        other => panic!("expected LayerNotFound, got {other:?}"),
    }
}

#[test]
fn file_without_colour_channels_is_unsupported() {
    let dir = TempDir::new("exr-no-colour");
    let path = dir.join("depth.exr");
    write_exr(
        &path,
        full((2, 2)),
        vec![layer((2, 2), vec![("Z", constant(1.0, 4))])],
    );
    let result = read(&path);
    assert_kind!(result, IoErrorKind::Unsupported(_));
    let message = result.unwrap_err().to_string();
    assert!(
        message.contains("no layer with R, G, B or Y channels"),
        "{message}"
    );
    assert!(message.contains('Z'), "{message}");
}

/// Files written by OpenEXR 3.5.3 (the C++ library, through its Python
/// bindings) in tests/data/: a 48x24 crop of envmaps/studio.exr around its
/// brightest light, half or float RGB, one per compression, plus a tiled
/// file. Each fingerprint is of the pixels as OpenEXR itself decodes them
/// (see `envmaps::fingerprint`), so these check the `exr` crate's decoders
/// against OpenEXR's bit for bit, lossy ones included.
const OPENEXR_WRITTEN: [(&str, u64); 13] = [
    ("openexr-rle-half.exr", 0x1637_1e65_876e_9125),
    ("openexr-zips-half.exr", 0x1637_1e65_876e_9125),
    ("openexr-zip-half.exr", 0x1637_1e65_876e_9125),
    ("openexr-piz-half.exr", 0x1637_1e65_876e_9125),
    ("openexr-pxr24-half.exr", 0x1637_1e65_876e_9125),
    ("openexr-b44-half.exr", 0x9580_31a3_6cb4_7125),
    ("openexr-b44a-half.exr", 0x9580_31a3_6cb4_7125),
    ("openexr-dwaa-half.exr", 0x3274_e2c3_a780_3125),
    ("openexr-dwab-half.exr", 0x3274_e2c3_a780_3125),
    ("openexr-piz-float.exr", 0x1637_1e65_876e_9125),
    ("openexr-pxr24-float.exr", 0x1637_1e65_876e_9125),
    ("openexr-dwaa-float.exr", 0x3274_e2c3_a780_3125),
    ("openexr-tiled-zip-half.exr", 0x1637_1e65_876e_9125),
];

fn data_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

#[test]
fn files_written_by_openexr_decode_as_openexr_decodes_them() {
    for (name, expected) in OPENEXR_WRITTEN {
        let image = read(&data_dir().join(name)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((image.width(), image.height()), (48, 24), "{name}");
        assert_eq!(
            crate::envmaps::fingerprint(&image),
            expected,
            "{name}: pixels differ from OpenEXR's decoding"
        );
        assert!(image.stats().max_value > 1000.0, "{name}");
    }
}

#[test]
fn compressions_newer_than_the_decoder_are_named() {
    for (name, compression) in [
        ("openexr-htj2k256-half.exr", "HTJ2K256 (code 10)"),
        ("openexr-zstd-half.exr", "ZSTD (code 13)"),
    ] {
        let path = data_dir().join(name);
        let result = read(&path);
        assert_kind!(result, IoErrorKind::Unsupported(_));
        let message = result.unwrap_err().to_string();
        assert!(
            message.contains(&format!("unsupported: OpenEXR compression {compression}")),
            "{message}"
        );
        assert!(
            message.starts_with(&path.display().to_string()),
            "{message}"
        );
    }
}

#[test]
fn large_files_are_mapped_and_read_as_their_bytes() {
    // Files of 1 MiB and more are mapped rather than copied (read.rs; this
    // test sees only the result, not which route was taken): a 640x480
    // float file without compression (3.7 MB), over that size, reads
    // exactly as the same bytes through `read_image_bytes`, and as the
    // image written; cut short, it reports a truncated file, not a crash.
    let dir = TempDir::new("exr-mapped");
    let path = dir.join("big.exr");
    let image = hdr_image(640, 480);
    write_image(
        &path,
        &image,
        &WriteOptions {
            exr_compression: ExrCompression::None,
            ..WriteOptions::default()
        },
    )
    .unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert!(bytes.len() >= 1 << 20, "{} bytes", bytes.len());
    let mapped = read(&path).unwrap();
    let copied = shlight_io::read_image_bytes(&bytes, &path, &ReadOptions::default()).unwrap();
    assert_eq!(mapped, copied);
    assert_eq!(mapped, image);

    let cut = dir.join("cut.exr");
    std::fs::write(&cut, &bytes[..bytes.len() * 3 / 4]).unwrap();
    assert_kind!(read(&cut), IoErrorKind::Truncated);
}

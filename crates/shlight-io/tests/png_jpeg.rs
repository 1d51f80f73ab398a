//! PNG and JPEG: sRGB decoding, bit depths, grey images, writing PNG.

use std::path::Path;

use image::{ExtendedColorType, ImageEncoder};
use shlight_io::{Image, IoErrorKind, ToneMap, WriteOptions, linear_to_srgb, write_image};

use crate::assert_kind;
use crate::util::{TempDir, ldr_image, read};

/// Writes raw samples as a PNG with the `image` crate.
fn write_png(path: &Path, data: &[u8], width: u32, height: u32, colour: ExtendedColorType) {
    let file = std::fs::File::create(path).unwrap();
    image::codecs::png::PngEncoder::new(file)
        .write_image(data, width, height, colour)
        .unwrap();
}

/// The decoded value of an 8-bit code: the sRGB EOTF of `code / 255`,
/// evaluated in f64 and rounded once to f32.
fn srgb8(code: u8) -> f32 {
    let c = f64::from(code) / 255.0;
    let linear = if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    linear as f32
}

#[test]
fn png_8_bit_is_srgb_decoded() {
    let dir = TempDir::new("png-8");
    let path = dir.join("rgb.png");
    write_png(
        &path,
        &[0, 128, 255, 10, 64, 200],
        2,
        1,
        ExtendedColorType::Rgb8,
    );
    let image = read(&path).unwrap();
    let [a, b] = image.pixels() else { panic!() };
    assert_eq!(a[0], 0.0);
    assert!((a[1] - 0.215_860_5).abs() < 1e-7, "{}", a[1]);
    assert_eq!(a[2], 1.0);
    assert_eq!(*b, [srgb8(10), srgb8(64), srgb8(200)]);
}

#[test]
fn png_16_bit_is_srgb_decoded() {
    let dir = TempDir::new("png-16");
    let path = dir.join("rgb16.png");
    // PNG stores 16-bit samples big-endian; the encoder takes native order.
    let samples: [u16; 6] = [0, 32768, 65535, 1000, 12345, 60000];
    let bytes: Vec<u8> = samples.iter().flat_map(|s| s.to_ne_bytes()).collect();
    write_png(&path, &bytes, 2, 1, ExtendedColorType::Rgb16);
    let image = read(&path).unwrap();
    let expected = samples.map(|s| {
        let c = f64::from(s) / 65535.0;
        (if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }) as f32
    });
    let got: Vec<f32> = image.pixels().iter().flatten().copied().collect();
    assert_eq!(got, expected);
    assert_eq!(got[2], 1.0);
}

#[test]
fn grey_and_alpha_pngs() {
    let dir = TempDir::new("png-grey");
    let grey = dir.join("l8.png");
    write_png(&grey, &[0, 128, 255], 3, 1, ExtendedColorType::L8);
    let image = read(&grey).unwrap();
    assert_eq!(image.pixels(), &[[0.0; 3], [srgb8(128); 3], [1.0; 3]]);

    // Alpha is dropped, not multiplied in.
    let grey_alpha = dir.join("la8.png");
    write_png(
        &grey_alpha,
        &[128, 0, 64, 255],
        2,
        1,
        ExtendedColorType::La8,
    );
    assert_eq!(
        read(&grey_alpha).unwrap().pixels(),
        &[[srgb8(128); 3], [srgb8(64); 3]]
    );

    let grey16 = dir.join("la16.png");
    let bytes: Vec<u8> = [65535u16, 0].iter().flat_map(|s| s.to_ne_bytes()).collect();
    write_png(&grey16, &bytes, 1, 1, ExtendedColorType::La16);
    assert_eq!(read(&grey16).unwrap().pixels(), &[[1.0; 3]]);

    let rgba = dir.join("rgba.png");
    write_png(&rgba, &[10, 20, 30, 0], 1, 1, ExtendedColorType::Rgba8);
    assert_eq!(
        read(&rgba).unwrap().pixels(),
        &[[srgb8(10), srgb8(20), srgb8(30)]]
    );
}

#[test]
fn png_round_trip_within_8_bit_quantisation() {
    let dir = TempDir::new("png-round-trip");
    let path = dir.join("x.png");
    let image = ldr_image(31, 9);
    write_image(&path, &image, &WriteOptions::default()).unwrap();
    let back = read(&path).unwrap();
    for (a, b) in image
        .pixels()
        .iter()
        .flatten()
        .zip(back.pixels().iter().flatten())
    {
        // Exactly the nearest 8-bit sRGB code.
        let code = (linear_to_srgb(*a) * 255.0).round() as u8;
        assert_eq!(*b, srgb8(code), "wrote {a}");
    }
}

#[test]
fn png_applies_exposure_then_tone_map() {
    let dir = TempDir::new("png-tone");
    let image = Image::new(
        3,
        1,
        vec![[0.25, 1.0, 3.0], [f32::NAN, -1.0, 0.0], [1e9; 3]],
    )
    .unwrap();
    let code = |linear: f32| srgb8((linear_to_srgb(linear) * 255.0).round() as u8);

    let path = dir.join("reinhard.png");
    let options = WriteOptions {
        exposure_ev: 0.0,
        tone_map: ToneMap::Reinhard,
        ..WriteOptions::default()
    };
    write_image(&path, &image, &options).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.get(0, 0), [code(0.2), code(0.5), code(0.75)]);
    assert_eq!(back.get(1, 0), [0.0; 3]);
    assert_eq!(back.get(2, 0), [1.0; 3]);

    let path = dir.join("clamp.png");
    let options = WriteOptions {
        exposure_ev: 1.0,
        tone_map: ToneMap::Clamp,
        ..WriteOptions::default()
    };
    write_image(&path, &image, &options).unwrap();
    assert_eq!(read(&path).unwrap().get(0, 0), [code(0.5), 1.0, 1.0]);

    let path = dir.join("aces.png");
    let options = WriteOptions {
        tone_map: ToneMap::Aces,
        ..WriteOptions::default()
    };
    write_image(&path, &image, &options).unwrap();
    let aces_one = ToneMap::Aces.apply(1.0);
    assert_eq!(read(&path).unwrap().get(0, 0)[1], code(aces_one));
}

#[test]
fn jpeg_is_read_as_linear() {
    let dir = TempDir::new("jpeg");
    let (w, h) = (16u32, 8u32);
    // Flat colour: JPEG keeps it within a code or two.
    let rgb: Vec<u8> = (0..w * h).flat_map(|_| [128u8, 64, 200]).collect();
    let path = dir.join("x.jpg");
    let file = std::fs::File::create(&path).unwrap();
    image::codecs::jpeg::JpegEncoder::new_with_quality(file, 95)
        .write_image(&rgb, w, h, ExtendedColorType::Rgb8)
        .unwrap();
    let image = read(&path).unwrap();
    assert_eq!((image.width(), image.height()), (16, 8));
    for p in image.pixels() {
        for (c, code) in [128u8, 64, 200].into_iter().enumerate() {
            let lo = srgb8(code - 2);
            let hi = srgb8(code + 2);
            assert!((lo..=hi).contains(&p[c]), "{p:?}");
        }
    }

    // Grey JPEG, and a JPEG with a .png name: the signature decides.
    let grey: Vec<u8> = vec![128; (w * h) as usize];
    let path = dir.join("grey.png");
    let file = std::fs::File::create(&path).unwrap();
    image::codecs::jpeg::JpegEncoder::new_with_quality(file, 95)
        .write_image(&grey, w, h, ExtendedColorType::L8)
        .unwrap();
    let image = read(&path).unwrap();
    let p = image.get(3, 3);
    assert!(p[0] == p[1] && p[1] == p[2]);
    assert!((srgb8(126)..=srgb8(130)).contains(&p[0]), "{p:?}");
}

#[test]
fn jpeg_and_unknown_extensions_are_not_written() {
    let dir = TempDir::new("write-unsupported");
    let image = ldr_image(4, 4);
    for name in ["x.jpg", "x.tiff", "noextension"] {
        let path = dir.join(name);
        let result = write_image(&path, &image, &WriteOptions::default());
        assert_kind!(result, IoErrorKind::Unsupported(_));
        let message = result.unwrap_err().to_string();
        assert!(message.contains("use .exr, .hdr or .png"), "{message}");
        assert!(!path.exists());
    }
    assert!(dir.entries().is_empty());
}

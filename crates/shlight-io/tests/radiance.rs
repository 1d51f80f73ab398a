//! Radiance HDR (RGBE): round trips and signatures.

use shlight_io::{Image, IoErrorKind, WriteOptions, write_image};

use crate::assert_kind;
use crate::util::{TempDir, hdr_image, read};

/// RGBE keeps 8 mantissa bits shared by the three channels and the encoder
/// truncates: each channel is within 2^-7 (< 1%) of the pixel's largest
/// channel.
const RGBE_RELATIVE: f32 = 0.01;

fn assert_rgbe_close(expected: &Image, actual: &Image) {
    assert_eq!(
        (actual.width(), actual.height()),
        (expected.width(), expected.height())
    );
    for (i, (e, a)) in expected.pixels().iter().zip(actual.pixels()).enumerate() {
        let scale = e[0].max(e[1]).max(e[2]);
        for c in 0..3 {
            assert!(
                (e[c] - a[c]).abs() <= RGBE_RELATIVE * scale,
                "pixel {i} channel {c}: wrote {}, read {}",
                e[c],
                a[c]
            );
        }
    }
}

#[test]
fn round_trip_within_rgbe_precision() {
    let dir = TempDir::new("hdr-round-trip");
    // Widths below 8 are stored flat, 8 and more run-length encoded.
    for (w, h) in [(5, 3), (64, 17)] {
        let image = hdr_image(w, h);
        let path = dir.join(&format!("{w}x{h}.hdr"));
        write_image(&path, &image, &WriteOptions::default()).unwrap();
        let back = read(&path).unwrap();
        assert_rgbe_close(&image, &back);
        assert!(back.stats().max_value > 50.0);
    }
}

#[test]
fn exposure_applies_and_unrepresentable_values_become_zero() {
    let dir = TempDir::new("hdr-exposure");
    let path = dir.join("x.HDR");
    let mut image = hdr_image(9, 2);
    image.set(0, 0, [f32::NAN, -1.0, 2.0]);
    image.set(1, 0, [f32::NEG_INFINITY, 1e-40, 0.0]);
    let options = WriteOptions {
        exposure_ev: 1.0,
        ..WriteOptions::default()
    };
    write_image(&path, &image, &options).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.get(0, 0), [0.0, 0.0, 4.0]);
    assert_eq!(back.get(1, 0), [0.0; 3]);
    let mut doubled = image.clone();
    for v in doubled.pixels_mut().iter_mut().flatten() {
        // Below the smallest normal f32, RGBE stores 0.
        *v = if *v * 2.0 >= f32::MIN_POSITIVE {
            *v * 2.0
        } else {
            0.0
        };
    }
    assert_rgbe_close(&doubled, &back);
}

#[test]
fn rgbe_signature_and_unsigned_files() {
    let dir = TempDir::new("hdr-signatures");
    let image = hdr_image(12, 4);
    let path = dir.join("x.hdr");
    write_image(&path, &image, &WriteOptions::default()).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert!(bytes.starts_with(b"#?RADIANCE\n"));
    let body = &bytes[b"#?RADIANCE\n".len()..];

    // `#?RGBE` is recognised by its signature, whatever the extension.
    let rgbe = dir.join("rgbe.dat");
    std::fs::write(&rgbe, [b"#?RGBE\n".as_slice(), body].concat()).unwrap();
    assert_rgbe_close(&image, &read(&rgbe).unwrap());

    // Without a signature line, the .hdr extension decides...
    let unsigned = dir.join("unsigned.hdr");
    std::fs::write(&unsigned, body).unwrap();
    assert_rgbe_close(&image, &read(&unsigned).unwrap());
    // ...and without it the format is unknown.
    let unknown = dir.join("unsigned.bin");
    std::fs::write(&unknown, body).unwrap();
    assert_kind!(read(&unknown), IoErrorKind::UnknownFormat);
}

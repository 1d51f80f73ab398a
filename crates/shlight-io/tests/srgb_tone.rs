//! The sRGB transfer function and the tone-mapping curves.

use shlight_io::{ParseToneMapError, ToneMap, linear_to_srgb, srgb_to_linear};

/// f32 rounding of the f64 reference values.
const EXACT: f32 = 1e-7;

#[test]
fn srgb_decodes_known_values() {
    assert_eq!(srgb_to_linear(0.0), 0.0);
    assert_eq!(srgb_to_linear(1.0), 1.0);
    // The brief's reference: code 128 of 255.
    assert!((srgb_to_linear(128.0 / 255.0) - 0.215_860_5).abs() < EXACT);
    // Linear segment: code 10 is below 0.04045 * 255 = 10.3.
    assert!((srgb_to_linear(10.0 / 255.0) - (10.0 / 255.0 / 12.92) as f32).abs() < EXACT);
    // Just above the break: code 11, ((c + 0.055) / 1.055)^2.4.
    let c = 11.0_f64 / 255.0;
    let expected = ((c + 0.055) / 1.055).powf(2.4) as f32;
    assert!((srgb_to_linear(11.0 / 255.0) - expected).abs() < EXACT);
    assert!((srgb_to_linear(0.5) - 0.214_041_14).abs() < EXACT);
    // Out-of-range input is clamped.
    assert_eq!(srgb_to_linear(2.0), 1.0);
    assert_eq!(srgb_to_linear(-1.0), 0.0);
}

#[test]
fn srgb_encoding_inverts_decoding_for_every_8_bit_code() {
    for code in 0..=255u8 {
        let linear = srgb_to_linear(f32::from(code) / 255.0);
        let back = (linear_to_srgb(linear) * 255.0).round();
        assert_eq!(back, f32::from(code), "code {code}");
    }
    assert_eq!(linear_to_srgb(f32::NAN), 0.0);
    assert_eq!(linear_to_srgb(5.0), 1.0);
    assert_eq!(linear_to_srgb(-5.0), 0.0);
}

#[test]
fn tone_map_names_parse_and_display() {
    for t in ToneMap::ALL {
        assert_eq!(t.to_string().parse::<ToneMap>(), Ok(t));
    }
    assert_eq!("ACES".parse::<ToneMap>(), Ok(ToneMap::Aces));
    assert_eq!("Reinhard".parse::<ToneMap>(), Ok(ToneMap::Reinhard));
    assert_eq!(ToneMap::Clamp.to_string(), "clamp");
    let err = "filmic".parse::<ToneMap>().unwrap_err();
    assert_eq!(err, ParseToneMapError("filmic".into()));
    assert_eq!(
        err.to_string(),
        "unknown tone map \"filmic\" (expected clamp, reinhard or aces)"
    );
    assert_eq!(ToneMap::default(), ToneMap::Clamp);
}

#[test]
fn tone_map_curves() {
    assert_eq!(ToneMap::Clamp.apply(0.25), 0.25);
    assert_eq!(ToneMap::Clamp.apply(3.0), 1.0);
    assert_eq!(ToneMap::Reinhard.apply(1.0), 0.5);
    assert_eq!(ToneMap::Reinhard.apply(3.0), 0.75);
    // (2.51 + 0.03) / (2.43 + 0.59 + 0.14) at x = 1.
    assert!((ToneMap::Aces.apply(1.0) - 2.54 / 3.16).abs() < 1e-6);
    assert_eq!(ToneMap::Aces.apply(0.0), 0.0);
    for t in ToneMap::ALL {
        assert_eq!(t.apply(f32::NAN), 0.0, "{t}");
        assert_eq!(t.apply(-4.0), 0.0, "{t}");
        assert_eq!(t.apply(f32::INFINITY), 1.0, "{t}");
        // Huge finite values must not overflow into NaN.
        assert_eq!(t.apply(f32::MAX), 1.0, "{t}");
        // Monotonic on a range of values.
        let mut last = 0.0;
        for i in 0..1000 {
            let y = t.apply(i as f32 * 0.01);
            assert!(y >= last, "{t} not monotonic at {i}");
            last = y;
        }
    }
}

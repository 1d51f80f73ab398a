//! KTX2 lightmaps: the file's header, data format descriptor, key/value
//! data and level as the `ktx2` crate (Bevy's reader) reads them; half
//! floats against the `half` crate and hand-computed bit patterns; packed
//! B10G11R11 floats against hand-computed bit patterns and a brute-force
//! search of every code for the nearest value.

use half::f16;
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_io::{
    IoErrorKind, Ktx2TexelFormat, decode_ktx2, encode_ktx2, f16_bits_to_f32, f32_to_f16_bits,
    pack_b10g11r11, read_ktx2, unpack_b10g11r11, write_ktx2,
};

use crate::assert_kind;
use crate::util::TempDir;

/// A 3x2 image whose texels differ everywhere.
fn texels() -> Vec<[f32; 4]> {
    (0..6)
        .map(|i| {
            let i = i as f32;
            [i + 0.25, 2.0 * i, 0.5 + i / 8.0, 1.0 - i / 16.0]
        })
        .collect()
}

/// A sample as (bit offset, bit length, channel id, qualifiers as the
/// crate spells them, lower, upper).
type Sample = (u16, u8, u8, ktx2::ChannelTypeQualifiers, u32, u32);

#[test]
fn the_ktx2_crate_reads_what_was_written() {
    use ktx2::ChannelTypeQualifiers as Q;
    let (minus_one, zero, one) = (0xBF80_0000, 0, 0x3F80_0000);
    let cases: [(Ktx2TexelFormat, ktx2::Format, u32, Vec<Sample>); 2] = [
        (
            Ktx2TexelFormat::Rgba16Float,
            ktx2::Format::R16G16B16A16_SFLOAT,
            2,
            vec![
                (0, 16, 0, Q::FLOAT | Q::SIGNED, minus_one, one),
                (16, 16, 1, Q::FLOAT | Q::SIGNED, minus_one, one),
                (32, 16, 2, Q::FLOAT | Q::SIGNED, minus_one, one),
                (48, 16, 15, Q::FLOAT | Q::SIGNED, minus_one, one),
            ],
        ),
        (
            Ktx2TexelFormat::B10G11R11Ufloat,
            ktx2::Format::B10G11R11_UFLOAT_PACK32,
            4,
            vec![
                (0, 11, 0, Q::FLOAT, zero, one),
                (11, 11, 1, Q::FLOAT, zero, one),
                (22, 10, 2, Q::FLOAT, zero, one),
            ],
        ),
    ];
    for (format, vk, type_size, samples) in cases {
        let texels = texels();
        let file = encode_ktx2(format, 3, 2, &texels).unwrap();
        let reader = ktx2::Reader::new(&file[..]).expect("a KTX2 file");
        let h = reader.header();
        assert_eq!(h.format, Some(vk));
        assert_eq!(h.type_size, type_size);
        assert_eq!((h.pixel_width, h.pixel_height, h.pixel_depth), (3, 2, 0));
        assert_eq!((h.layer_count, h.face_count, h.level_count), (0, 1, 1));
        assert_eq!(h.supercompression_scheme, None);
        assert_eq!((h.index.sgd_byte_offset, h.index.sgd_byte_length), (0, 0));

        let blocks: Vec<_> = reader.dfd_blocks().collect();
        assert_eq!(blocks.len(), 1, "{format:?}: one descriptor block");
        assert_eq!(blocks[0].header, ktx2::DfdHeader::BASIC);
        let basic = ktx2::DfdBlockBasic::parse(blocks[0].data).unwrap();
        let b = basic.header;
        assert_eq!(b.color_model, Some(ktx2::ColorModel::RGBSDA));
        assert_eq!(b.color_primaries, Some(ktx2::ColorPrimaries::BT709));
        assert_eq!(b.transfer_function, Some(ktx2::TransferFunction::Linear));
        assert_eq!(b.flags, ktx2::DataFormatFlags::STRAIGHT_ALPHA);
        assert!(b.texel_block_dimensions.iter().all(|d| d.get() == 1));
        let texel_bytes = format.texel_bytes() as u8;
        assert_eq!(b.bytes_planes, [texel_bytes, 0, 0, 0, 0, 0, 0, 0]);
        let read: Vec<Sample> = basic
            .sample_information()
            .map(|s| {
                assert_eq!(s.sample_positions, [0; 4]);
                let q = s.channel_type_qualifiers;
                let (o, l, c) = (s.bit_offset, s.bit_length.get(), s.channel_type);
                (o, l, c, q, s.lower, s.upper)
            })
            .collect();
        assert_eq!(read, samples, "{format:?}");

        let kv: Vec<(&str, &[u8])> = reader.key_value_data().collect();
        let writer = format!("shlight {}\0", env!("CARGO_PKG_VERSION"));
        assert_eq!(kv, [("KTXwriter", writer.as_bytes())]);

        let levels: Vec<_> = reader.levels().collect();
        assert_eq!(levels.len(), 1);
        assert_eq!(
            levels[0].uncompressed_byte_length,
            6 * u64::from(texel_bytes)
        );
        let offset = levels[0].data.as_ptr() as usize - file.as_ptr() as usize;
        assert_eq!(offset % 8, 0, "the level is 8-byte aligned");
        assert_eq!(offset + levels[0].data.len(), file.len());
        // The texels in the order given (row 0 first), each encoded by an
        // independent route.
        let expected: Vec<u8> = texels
            .iter()
            .flat_map(|t| match format {
                Ktx2TexelFormat::Rgba16Float => t
                    .iter()
                    .flat_map(|&v| f16::from_f32(v).to_bits().to_le_bytes())
                    .collect::<Vec<_>>(),
                Ktx2TexelFormat::B10G11R11Ufloat => {
                    let word = nearest_small_float(t[0], 6)
                        | (nearest_small_float(t[1], 6) << 11)
                        | (nearest_small_float(t[2], 5) << 22);
                    word.to_le_bytes().to_vec()
                }
            })
            .collect();
        assert_eq!(levels[0].data, &expected[..], "{format:?}");
    }
}

#[test]
fn half_floats_have_the_hand_computed_bits() {
    let cases: [(f32, u16); 14] = [
        (1.0, 0x3C00),
        (0.5, 0x3800),
        (-2.0, 0xC000),
        (0.0, 0x0000),
        (-0.0, 0x8000),
        (65504.0, 0x7BFF), // the largest finite half
        (65519.0, 0x7BFF), // below the midpoint to 65536
        (65520.0, 0x7C00), // the midpoint: ties to even, infinity
        (f32::INFINITY, 0x7C00),
        (6.103_515_6e-5, 0x0400),     // 2^-14, the smallest normal
        (5.960_464_5e-8, 0x0001),     // 2^-24, the smallest subnormal
        (2.980_232_2e-8, 0x0000),     // 2^-25: a tie, to even (zero)
        (1e-7, 0x0002),               // 1.68 units of 2^-24
        (1.0 + 1.0 / 2048.0, 0x3C00), // a tie between 1 and 1 + 2^-10: to even
    ];
    for (x, bits) in cases {
        assert_eq!(f32_to_f16_bits(x), bits, "{x:e}");
    }
    assert_eq!(f32_to_f16_bits(f32::NAN), 0x7E00);
    assert_eq!(f32_to_f16_bits(-f32::NAN), 0xFE00);
    assert!(f16_bits_to_f32(0x7E00).is_nan());
    assert_eq!(f16_bits_to_f32(0x0001), 2f32.powi(-24));
    assert_eq!(f16_bits_to_f32(0x7BFF), 65504.0);
    assert_eq!(f16_bits_to_f32(0xFC00), f32::NEG_INFINITY);
}

/// Every 997th f32 bit pattern, and every half's value and the midpoints
/// to its neighbours (where rounding turns), against the `half` crate.
#[test]
fn half_floats_match_the_half_crate() {
    let check = |x: f32| {
        if x.is_nan() {
            assert!(f16_bits_to_f32(f32_to_f16_bits(x)).is_nan());
        } else {
            assert_eq!(
                f32_to_f16_bits(x),
                f16::from_f32(x).to_bits(),
                "{x:e} ({:#x})",
                x.to_bits()
            );
        }
    };
    for bits in (0..=u32::MAX).step_by(997) {
        check(f32::from_bits(bits));
    }
    for h in 0..=u16::MAX {
        let v = f16::from_bits(h).to_f32();
        if v.is_nan() {
            assert!(f16_bits_to_f32(h).is_nan(), "{h:#x}");
        } else {
            assert_eq!(f16_bits_to_f32(h).to_bits(), v.to_bits(), "{h:#x}");
        }
        if v.is_finite() {
            let next = f16::from_bits(h.wrapping_add(1)).to_f64();
            let mid = ((f64::from(v) + next) / 2.0) as f32;
            for x in [
                v,
                mid,
                f32::from_bits(mid.to_bits() + 1),
                f32::from_bits(mid.to_bits().saturating_sub(1)),
            ] {
                check(x);
            }
        }
    }
}

#[test]
fn packed_floats_have_the_hand_computed_bits() {
    // (value, 11-bit code, 10-bit code)
    let cases: [(f32, u32, u32); 12] = [
        (1.0, 0x3C0, 0x1E0),
        (0.5, 0x380, 0x1C0),
        (2.0, 0x400, 0x200),
        (0.0, 0, 0),
        (-1.0, 0, 0), // no sign: negative values are 0
        (f32::NEG_INFINITY, 0, 0),
        (65024.0, 0x7BF, 0x3DF), // 11 bits' largest finite; 10 bits clamp (64512)
        (65504.0, 0x7BF, 0x3DF), // past both largest finite values: clamped
        (1e30, 0x7BF, 0x3DF),
        (f32::INFINITY, 0x7C0, 0x3E0),
        (9.536_743e-7, 0x001, 0x000), // 2^-20: the smallest 11-bit subnormal; a 10-bit tie to 0
        (1e-7, 0, 0),                 // 0.1 units of 2^-20
    ];
    for (x, r11, b10) in cases {
        let word = pack_b10g11r11([x, x, x]);
        assert_eq!(word & 0x7FF, r11, "R of {x:e}");
        assert_eq!((word >> 11) & 0x7FF, r11, "G of {x:e}");
        assert_eq!(word >> 22, b10, "B of {x:e}");
    }
    assert_eq!(pack_b10g11r11([1.0, 0.5, 2.0]), 0x801C_03C0);
    // 1.0 + 2^-7 is a tie between 1 and 1 + 2^-6 in 11 bits: to even.
    assert_eq!(pack_b10g11r11([1.0 + 1.0 / 128.0, 0.0, 0.0]), 0x3C0);
    // 1.0 + 3 * 2^-7 is a tie between 1 + 2^-6 and 1 + 2^-5: to even (up).
    assert_eq!(pack_b10g11r11([1.0 + 3.0 / 128.0, 0.0, 0.0]), 0x3C2);
    // NaN: the quiet NaN of each width, positive.
    assert_eq!(
        pack_b10g11r11([f32::NAN, -f32::NAN, f32::NAN]),
        0x7E0 | (0x7E0 << 11) | (0x3F0 << 22)
    );
    let [r, g, b] = unpack_b10g11r11(0x7E0 | (0x7C0 << 11) | (0x3DF << 22));
    assert!(r.is_nan());
    assert_eq!((g, b), (f32::INFINITY, 64512.0));
}

/// The code of an unsigned float of a 5-bit exponent and `m` mantissa bits
/// nearest to `x` (ties to the even code), found among every finite code:
/// the route the encoder is held to.
fn nearest_small_float(x: f32, m: u32) -> u32 {
    let x = f64::from(x.max(0.0));
    let value = |code: u32| {
        let (e, f) = (
            code >> m,
            f64::from(code & ((1 << m) - 1)) / f64::from(1u32 << m),
        );
        if e == 0 {
            f * 2f64.powi(-14)
        } else {
            (1.0 + f) * 2f64.powi(e as i32 - 15)
        }
    };
    let mut best = 0;
    for code in 1..(31 << m) {
        let (d, b) = ((value(code) - x).abs(), (value(best) - x).abs());
        if d < b || (d == b && code % 2 == 0) {
            best = code;
        }
    }
    best
}

#[test]
fn packed_floats_are_the_nearest_code() {
    let mut rng = StdRng::seed_from_u64(7);
    for k in 0..3000 {
        // Log-uniform over the whole range, subnormals and clamping included.
        let x = 2f32.powf(rng.random_range(-26.0..17.0));
        let x = if k % 10 == 0 { -x } else { x };
        let word = pack_b10g11r11([x, x, x]);
        assert_eq!(word & 0x7FF, nearest_small_float(x, 6), "{x:e}");
        assert_eq!(word >> 22, nearest_small_float(x, 5), "{x:e}");
        // Every finite code decodes to its value and encodes back to itself.
        let code = rng.random_range(0..0x7C0u32);
        let v = unpack_b10g11r11(code)[0];
        assert_eq!(pack_b10g11r11([v, 0.0, 0.0]), code, "{code:#x}");
    }
}

#[test]
fn files_read_back_through_the_reader() {
    let dir = TempDir::new("ktx2-read");
    for format in [
        Ktx2TexelFormat::Rgba16Float,
        Ktx2TexelFormat::B10G11R11Ufloat,
    ] {
        let path = dir.join("lightmap.ktx2");
        let texels = texels();
        write_ktx2(&path, format, 3, 2, &texels).unwrap();
        let image = read_ktx2(&path).unwrap();
        assert_eq!((image.format, image.width, image.height), (format, 3, 2));
        for (got, given) in image.texels.iter().zip(&texels) {
            let expected = match format {
                Ktx2TexelFormat::Rgba16Float => given.map(|v| f16::from_f32(v).to_f32()),
                Ktx2TexelFormat::B10G11R11Ufloat => {
                    let [r, g, b] =
                        unpack_b10g11r11(pack_b10g11r11([given[0], given[1], given[2]]));
                    [r, g, b, 1.0]
                }
            };
            assert_eq!(*got, expected, "{format:?}");
        }
        assert_eq!(dir.entries(), ["lightmap.ktx2"]);
    }
}

#[test]
fn bad_sizes_and_paths_are_errors_naming_the_file() {
    let dir = TempDir::new("ktx2-bad");
    let path = dir.join("lm.ktx2");
    let f = Ktx2TexelFormat::Rgba16Float;
    let result = write_ktx2(&path, f, 3, 2, &texels()[..5]);
    assert_kind!(
        result,
        IoErrorKind::TexelCount {
            width: 3,
            height: 2,
            given: 5
        }
    );
    assert_eq!(
        result.unwrap_err().to_string(),
        format!("{}: 5 texels given for a 3x2 image", path.display())
    );
    assert_kind!(
        write_ktx2(&path, f, 0, 2, &[]),
        IoErrorKind::EmptyImage { .. }
    );
    let missing = dir.join("no-such-dir").join("lm.ktx2");
    let result = write_ktx2(&missing, f, 3, 2, &texels());
    assert_kind!(result, IoErrorKind::Write(_));
    assert!(
        result
            .unwrap_err()
            .to_string()
            .starts_with(&missing.display().to_string())
    );
    assert!(dir.entries().is_empty(), "nothing written");

    // The reader: missing, not KTX2, cut short, another format.
    assert_kind!(read_ktx2(&path), IoErrorKind::NotFound);
    let file = encode_ktx2(f, 3, 2, &texels()).unwrap();
    assert_kind!(
        decode_ktx2(&file[1..]).map_err(|k| shlight_io::IoError::new("x", k)),
        IoErrorKind::UnknownFormat
    );
    assert!(matches!(
        decode_ktx2(&file[..file.len() - 1]),
        Err(IoErrorKind::Truncated)
    ));
    assert!(matches!(
        decode_ktx2(&file[..50]),
        Err(IoErrorKind::Truncated)
    ));
    let mut other = file.clone();
    other[12] = 109; // R32G32B32A32_SFLOAT
    assert!(matches!(
        decode_ktx2(&other),
        Err(IoErrorKind::Unsupported(_))
    ));
}

#[test]
fn a_header_whose_size_overflows_is_corrupt_not_a_panic() {
    // A 1 x 1 file whose header claims (2^32 - 1)^2 texels of 8 bytes: more
    // bytes than 64 bits count.
    let mut bytes =
        shlight_io::encode_ktx2(Ktx2TexelFormat::Rgba16Float, 1, 1, &[[1.0; 4]]).unwrap();
    bytes[20..24].copy_from_slice(&u32::MAX.to_le_bytes());
    bytes[24..28].copy_from_slice(&u32::MAX.to_le_bytes());
    let e = shlight_io::decode_ktx2(&bytes).unwrap_err().to_string();
    assert!(e.contains("more than 2^64"), "{e}");
}

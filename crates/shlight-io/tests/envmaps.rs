//! The environment maps bundled in `envmaps/` (see envmaps/README.md).

use std::path::PathBuf;

use crate::util::read;

/// The workspace's envmaps/ directory.
pub fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../envmaps")
}

/// The bundled .exr files, sorted by name.
fn bundled() -> Vec<PathBuf> {
    let mut maps: Vec<PathBuf> = std::fs::read_dir(dir())
        .expect("envmaps/ exists (run envmaps/fetch.sh)")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "exr"))
        .collect();
    maps.sort();
    maps
}

#[test]
fn every_bundled_map_reads_as_a_plausible_hdr_environment() {
    let maps = bundled();
    let names: Vec<String> = maps
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(names.contains(&"default.exr".to_owned()), "{names:?}");
    assert!(maps.len() >= 4, "{names:?}");
    for path in &maps {
        let image = read(path).unwrap();
        assert_eq!(
            (image.width(), image.height()),
            (512, 256),
            "{}",
            path.display()
        );
        let stats = image.stats();
        assert_eq!(stats.non_finite, 0, "{}", path.display());
        // HDR: something brighter than diffuse white.
        assert!(stats.max_value > 1.0, "{}: {stats:?}", path.display());
        // Not black: the mean is a sensible radiance.
        let mean: f64 = image
            .pixels()
            .iter()
            .flatten()
            .map(|&v| f64::from(v))
            .sum::<f64>()
            / (512.0 * 256.0 * 3.0);
        assert!(
            (0.05..100.0).contains(&mean),
            "{}: mean {mean}",
            path.display()
        );
    }
}

/// FNV-1a (64 bit) over the bit patterns of the R, G, B values, row-major.
pub fn fingerprint(image: &shlight_io::Image) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for v in image.pixels().iter().flatten() {
        h ^= u64::from(v.to_bits());
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The DWAB decoder of the `exr` crate against OpenEXR's own: fingerprints
/// of the maps as decoded by the OpenEXR 3.5.3 C++ library (its Python
/// bindings, `OpenEXR.File(path, separate_channels=True)`, half values
/// widened to f32).
#[test]
fn dwab_decoding_matches_openexr_bit_for_bit() {
    const OPENEXR_3_5_3: [(&str, u64); 5] = [
        ("city.exr", 0xd243_10de_3d92_0325),
        ("default.exr", 0xfce5_0acc_6d1a_a325),
        ("park.exr", 0xfce5_0acc_6d1a_a325),
        ("sky.exr", 0xebba_04ed_a60e_6325),
        ("studio.exr", 0xfce8_8333_37af_a325),
    ];
    for (name, expected) in OPENEXR_3_5_3 {
        let image = read(&dir().join(name)).unwrap();
        assert_eq!(
            fingerprint(&image),
            expected,
            "{name}: decoded pixels differ from OpenEXR's"
        );
    }
}

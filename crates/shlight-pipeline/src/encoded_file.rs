//! [`encode_file`]: a coefficient file that keeps its light as an encoding
//! other than plain SH (`shlight project --encoding`).

use shlight_core::encoding::{DominantLightOptions, Encoded, Encoding, encode_map};
use shlight_core::map::EnvMap;
use shlight_format::{CoeffFile, FileEncoding};

/// Replaces the plain radiance SH of `file` (made from `map`) by
/// `encoding` of the map's texels, its SH part to `lmax`
/// ([`shlight_core::encoding::encode_map`] with the default dominant-light options),
/// recording the encoding in the file (`FileEncoding`, which keeps the
/// plain SH beside `sloan+sh` and the ambient cube).
pub fn encode_file(file: &mut CoeffFile, map: &EnvMap<'_>, encoding: Encoding, lmax: usize) {
    let encoded = encode_map(map, encoding, lmax, &DominantLightOptions::default());
    set_encoding(file, encoding, &encoded);
}

/// Records `encoded` (of `encoding`) in `file`, whose coefficients are the
/// plain SH it was made from.
pub(crate) fn set_encoding(file: &mut CoeffFile, encoding: Encoding, encoded: &Encoded) {
    let (record, coeffs) = FileEncoding::from_encoded(encoding, encoded, &file.coeffs);
    file.coeffs = coeffs;
    file.encoding = record;
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use shlight_core::map::{Layout, MapOrientation};
    use shlight_format::Quantity;

    use crate::choose_windows::choose_windows;
    use crate::coeff_file_of::coeff_file_of;
    use crate::cpu_projector::project_radiance;
    use crate::map_info::MapInfo;
    use crate::settings::{Method, ProjectSettings};
    use crate::spelling::Spelling;

    /// Every encoding recorded in the file evaluates (`CoeffFile::encoded`)
    /// to the irradiance of the encoding made from the map directly.
    #[test]
    fn the_file_holds_the_maps_encoding() {
        let (w, h) = (64, 32);
        let o = MapOrientation::default();
        let pixels: Vec<[f32; 3]> = (0..w * h)
            .map(|k| {
                let y = k / w;
                let sun = if (k % w, y) == (20, 9) { 500.0 } else { 0.0 };
                [0.2 + sun, 0.3 + 0.01 * y as f32 + sun, 0.5]
            })
            .collect();
        let map = EnvMap::new(Layout::Equirect, o, w, h, &pixels).unwrap();
        let s = ProjectSettings::new(2, o, Method::Quadrature, Quantity::Radiance);
        let projection = project_radiance(&map, &s);
        let windows = choose_windows(&projection.coeffs, &s, "sky", Spelling::CommandLine).unwrap();
        let info = MapInfo::of_pixels("sky", Layout::Equirect, w, h, &pixels);
        let plain = coeff_file_of(&projection, windows, &s, &info);
        let normals = [DVec3::Y, DVec3::X, DVec3::new(0.3, -0.8, 0.5).normalize()];
        for encoding in Encoding::ALL {
            let mut file = plain.clone();
            encode_file(&mut file, &map, encoding, 2);
            assert_eq!(file.encoding.encoding(), encoding);
            let want = encode_map(&map, encoding, 2, &DominantLightOptions::default())
                .irradiance_at(&normals);
            let got = file.encoded().expect("radiance").irradiance_at(&normals);
            for (g, e) in got.iter().zip(&want) {
                assert!(
                    (*g - *e).abs().max_element() < 1e-9 * e.abs().max_element().max(1.0),
                    "{encoding}: {g} {e}"
                );
            }
        }
    }
}

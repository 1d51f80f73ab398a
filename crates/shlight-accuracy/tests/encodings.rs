//! Every encoding on the bundled maps against their exact irradiance
//! (`shlight_accuracy::compare`): the claims of docs/accuracy.md's
//! encodings table.

use std::path::Path;

use glam::DVec3;
use shlight_accuracy::compare::{CompareRow, compare_map};
use shlight_core::encoding::{DominantLightOptions, Encoding};
use shlight_core::map::{EnvMap, Layout, MapOrientation};
use shlight_io::{Image, ReadOptions, read_image};

/// Normals the errors are measured at (equirect grid): coarse enough to keep
/// the suite short, fine enough that a sun's error peak is seen.
const NORMALS: (usize, usize) = (64, 32);

/// What "not worse beyond noise" allows: the residual's SH differs from the
/// map's only where the lights were, and the cap model from the texels only
/// at each light's horizon (a few texels' worth of its power).
const NOISE: f64 = 0.02;

const MAPS: [&str; 4] = ["park", "city", "sky", "studio"];

fn bundled(name: &str) -> Image {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../envmaps/{name}.exr"));
    read_image(&path, &ReadOptions::default()).expect("bundled map")
}

fn rows(name: &str) -> Vec<CompareRow> {
    let image = bundled(name);
    let map = EnvMap::new(
        Layout::Equirect,
        MapOrientation::default(),
        image.width(),
        image.height(),
        image.pixels(),
    )
    .unwrap();
    compare_map(name, &map, NORMALS, &DominantLightOptions::default())
}

fn find(rows: &[CompareRow], e: Encoding, lmax: Option<usize>) -> &CompareRow {
    rows.iter()
        .find(|r| r.encoding == e && r.lmax == lmax)
        .expect("every case has a row")
}

#[test]
fn encodings_on_the_bundled_maps() {
    let mut sunny = 0;
    for name in MAPS {
        let rows = rows(name);
        let sh1 = find(&rows, Encoding::Sh, Some(1)).error;
        let sh2 = find(&rows, Encoding::Sh, Some(2)).error;
        let zh3 = find(&rows, Encoding::Zh3, None).error;
        let dom = find(&rows, Encoding::DominantSh, Some(2));
        eprintln!("{}", shlight_accuracy::compare::table(&rows));
        // ZH3 lies between lmax 1 and lmax 2 (RMS: the least-squares sense
        // both are fitted in).
        assert!(
            sh2.rms <= zh3.rms && zh3.rms <= sh1.rms,
            "{name}: ZH3 {zh3:?} not between L1 {sh1:?} and L2 {sh2:?}"
        );
        // Dominant lights plus lmax 2 never worse than lmax 2 beyond noise.
        for (d, s) in [(dom.error.max, sh2.max), (dom.error.mean, sh2.mean)] {
            assert!(
                d <= s * (1.0 + NOISE),
                "{name}: dominant+sh {:?} against sh {sh2:?}",
                dom.error
            );
        }
        if dom.lights > 0 {
            sunny += 1;
            assert!(
                dom.error.max < 0.8 * sh2.max,
                "{name}: a light taken out must help"
            );
        }
    }
    // The sunny maps (park, sky) have a compact sun.
    assert!(sunny >= 1, "no bundled map gave a light");
}

#[test]
fn the_ambient_cube_reproduces_the_exact_irradiance_at_the_axes() {
    let image = bundled("studio");
    let map = EnvMap::new(
        Layout::Equirect,
        MapOrientation::default(),
        image.width(),
        image.height(),
        image.pixels(),
    )
    .unwrap();
    let cube = match shlight_core::encoding::encode_map(
        &map,
        Encoding::AmbientCube,
        0,
        &DominantLightOptions::default(),
    ) {
        shlight_core::encoding::Encoded::AmbientCube(c) => c,
        other => panic!("{other:?}"),
    };
    // The irradiance at each axis summed here, texel by texel.
    let omega = map.texel_solid_angles();
    for axis in shlight_core::encoding::AMBIENT_CUBE_AXES {
        let mut e = DVec3::ZERO;
        for y in 0..map.height {
            for x in 0..map.width {
                let d = map.texel_direction(x, y).unwrap();
                let l = DVec3::from(map.pixels[y * map.width + x].map(f64::from));
                e += l * omega[y * map.width + x] * axis.dot(d).max(0.0);
            }
        }
        let got = cube.irradiance(axis);
        assert!(
            (got - e).abs().max_element() <= 1e-9 * e.max_element(),
            "{axis}: {got} {e}"
        );
    }
}

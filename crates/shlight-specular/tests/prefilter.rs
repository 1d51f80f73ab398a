//! The prefilter against what it must equal: the map itself at roughness
//! 0, a constant at every roughness, and a brute-force GGX-weighted sum
//! over every texel of the source map.

use glam::DVec3;
use shlight_core::map::{CubeFace, EnvMap, Layout, MapOrientation, equirect_direction};
use shlight_specular::d_ggx;
use shlight_specular::{PrefilterSettings, TargetEngine, prefilter};

const W: usize = 256;
const H: usize = 128;

fn draw(f: impl Fn(DVec3) -> DVec3) -> Vec<[f32; 3]> {
    (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .map(|(x, y)| {
            f(equirect_direction(x, y, W, H, MapOrientation::default()))
                .as_vec3()
                .to_array()
        })
        .collect()
}

fn map(pixels: &[[f32; 3]]) -> EnvMap<'_> {
    EnvMap::new(Layout::Equirect, MapOrientation::default(), W, H, pixels).unwrap()
}

/// A smooth sky: a broad lobe off the axes over a gradient, coloured.
fn smooth(d: DVec3) -> DVec3 {
    let lobe = DVec3::new(0.3, 0.5, -0.8).normalize();
    let c = d.dot(lobe).max(0.0).powi(8);
    let v = 0.2 + 0.3 * d.y.max(0.0) + 3.0 * c;
    DVec3::new(v, 0.8 * v, 0.6 * v + 0.1 * d.x)
}

fn texel_direction(face: CubeFace, i: usize, j: usize, size: usize) -> DVec3 {
    let c = |k: usize| (2.0 * k as f64 + 1.0) / size as f64 - 1.0;
    face.point(c(i), c(j)).normalize()
}

/// The GGX-weighted mean over every texel of the map (module docs of
/// `prefilter`): `Σ L Ω (n·l) D(h) / Σ Ω (n·l) D(h)`.
fn brute_force(map: &EnvMap, n: DVec3, alpha: f64) -> DVec3 {
    let omega = map.texel_solid_angles();
    let (mut sum, mut weight) = (DVec3::ZERO, 0.0);
    for y in 0..map.height {
        for x in 0..map.width {
            let l = map.texel_direction(x, y).unwrap();
            let n_dot_l = n.dot(l);
            if n_dot_l <= 0.0 {
                continue;
            }
            let h = (n + l).normalize();
            let w = omega[y * map.width + x] * n_dot_l * d_ggx(n.dot(h), alpha);
            let p = map.pixels[y * map.width + x];
            sum += DVec3::from(p.map(f64::from)) * w;
            weight += w;
        }
    }
    sum / weight
}

/// Mip 0 at roughness 0 is the map itself, resampled (bilinear), in the
/// engine's cube axes: Filament's turned frame and Bevy's mirror.
#[test]
fn roughness_zero_is_the_map_itself() {
    /// Bilinear resampling of this smooth map at 4 texels per cube texel.
    const TOLERANCE: f64 = 0.01;
    let pixels = draw(smooth);
    let map = map(&pixels);
    for engine in [
        TargetEngine::Filament,
        TargetEngine::Bevy,
        TargetEngine::Babylon,
    ] {
        let settings = PrefilterSettings {
            size: 32,
            mips: Some(3),
            samples: 64,
            ..PrefilterSettings::new(engine)
        };
        let cube = prefilter(&map, &settings, &|_| {}).unwrap();
        assert_eq!(cube.levels[0].alpha, 0.0);
        let mut worst = 0.0f64;
        let mut worst_unturned = 0.0f64;
        for face in CubeFace::ALL {
            for j in 0..32 {
                for i in 0..32 {
                    let c = texel_direction(face, i, j, 32);
                    let got = DVec3::from(cube.levels[0].cube.get(face, i, j).map(f64::from));
                    let want = smooth(engine.world_from_cube() * c);
                    worst = worst.max((got - want).abs().max_element());
                    worst_unturned = worst_unturned.max((got - smooth(c)).abs().max_element());
                }
            }
        }
        assert!(worst < TOLERANCE, "{engine}: {worst}");
        // The cube's axes matter: read in shlight's own axes it differs.
        assert!(
            worst_unturned > 10.0 * TOLERANCE,
            "{engine}: {worst_unturned}"
        );
    }
}

/// The furnace: a constant map stays constant at every mip, and a cross
/// layout reads the same as an equirect one.
#[test]
fn a_constant_map_stays_constant_at_every_roughness() {
    let pixels = vec![[0.25f32, 1.5, 3.0]; W * H];
    let cross = vec![[0.25f32, 1.5, 3.0]; 64 * 48];
    let cross = EnvMap::new(
        Layout::CrossHorizontal,
        MapOrientation::default(),
        64,
        48,
        &cross,
    )
    .unwrap();
    for m in [map(&pixels), cross] {
        for engine in [TargetEngine::Filament, TargetEngine::Unreal] {
            let settings = PrefilterSettings {
                size: 16,
                samples: 128,
                mips: Some(5),
                ..PrefilterSettings::new(engine)
            };
            let cube = prefilter(&m, &settings, &|_| {}).unwrap();
            assert_eq!(cube.levels.len(), 5);
            for (k, level) in cube.levels.iter().enumerate() {
                assert_eq!(level.cube.size(), 16 >> k);
                for p in level.cube.strip() {
                    for (c, want) in p.iter().zip([0.25, 1.5, 3.0]) {
                        assert!((c - want).abs() < 1e-5 * want, "{engine} mip {k}: {p:?}");
                    }
                }
            }
        }
    }
}

/// Every mip of a smooth map against the brute-force GGX-weighted sum
/// over all its texels, at texels spread over the sphere.
#[test]
fn every_mip_matches_the_brute_force_integral() {
    /// 1024+ Hammersley samples and the source-mip blur on a smooth map:
    /// measured worst 0.6% of the map's peak.
    const TOLERANCE: f64 = 0.015;
    let pixels = draw(smooth);
    let map = map(&pixels);
    let peak = 3.5;
    let settings = PrefilterSettings {
        size: 32,
        mips: Some(4),
        samples: 1024,
        ..PrefilterSettings::new(TargetEngine::Filament)
    };
    let cube = prefilter(&map, &settings, &|_| {}).unwrap();
    let world = TargetEngine::Filament.world_from_cube();
    let mut worst = 0.0f64;
    for (k, level) in cube.levels.iter().enumerate().skip(1) {
        let size = level.cube.size();
        for (n, face) in CubeFace::ALL.into_iter().enumerate() {
            let (i, j) = ((3 * n + k) % size, (5 * n + 2 * k) % size);
            let c = texel_direction(face, i, j, size);
            let got = DVec3::from(level.cube.get(face, i, j).map(f64::from));
            let want = brute_force(&map, world * c, level.alpha);
            let err = (got - want).abs().max_element() / peak;
            worst = worst.max(err);
            assert!(
                err < TOLERANCE,
                "mip {k} alpha {} {face}: {got} vs {want}",
                level.alpha
            );
        }
    }
    eprintln!(
        "smooth map: worst difference {:.3}% of the peak",
        100.0 * worst
    );
}

/// A small bright sun spreads into the GGX lobe's shape: the prefiltered
/// mips along a great circle through the sun against the brute-force sum,
/// with no fireflies (the PDF-based source-mip filter).
#[test]
fn a_small_sun_spreads_into_the_lobe() {
    /// Relative to the lobe's peak. The source-mip filter spreads the sun
    /// over each sample's footprint, and at `alpha = 1` a 5°-wide sun is
    /// about one sample's footprint (`4π / 4096` sr): the quasi-Monte
    /// Carlo error is then largest (measured worst 12.0% of the peak at one
    /// texel next to the sun, under 6% everywhere else; under 4% at
    /// `alpha < 1`).
    const TOLERANCE: f64 = 0.15;
    let sun = DVec3::new(0.2, 0.6, 0.4).normalize();
    let pixels = draw(|d| {
        if d.dot(sun) > (2.5f64).to_radians().cos() {
            DVec3::splat(200.0)
        } else {
            DVec3::splat(0.01)
        }
    });
    let map = map(&pixels);
    let settings = PrefilterSettings {
        size: 32,
        mips: Some(5),
        samples: 1024,
        ..PrefilterSettings::new(TargetEngine::Unreal)
    };
    let cube = prefilter(&map, &settings, &|_| {}).unwrap();
    let world = TargetEngine::Unreal.world_from_cube();
    let mut worst = 0.0f64;
    for (k, level) in cube.levels.iter().enumerate().skip(2) {
        let size = level.cube.size();
        let peak = brute_force(&map, sun, level.alpha).x;
        // Every texel of the mip, near the sun and far from it.
        for face in CubeFace::ALL {
            for j in 0..size {
                for i in 0..size {
                    let n = world * texel_direction(face, i, j, size);
                    let got = f64::from(level.cube.get(face, i, j)[0]);
                    let want = brute_force(&map, n, level.alpha).x;
                    let err = (got - want).abs() / peak;
                    worst = worst.max(err);
                    assert!(
                        err < TOLERANCE,
                        "mip {k} alpha {:.3} at {:.1} deg from the sun: {got} vs {want} (peak {peak})",
                        level.alpha,
                        n.angle_between(sun).to_degrees()
                    );
                }
            }
        }
    }
    eprintln!(
        "sun: worst difference {:.2}% of the lobe's peak",
        100.0 * worst
    );
}

/// The same settings give the same bits, whatever rayon's thread count.
#[test]
fn results_repeat_bit_for_bit() {
    let pixels = draw(smooth);
    let map = map(&pixels);
    let settings = PrefilterSettings {
        size: 16,
        samples: 64,
        ..PrefilterSettings::new(TargetEngine::Babylon)
    };
    let a = prefilter(&map, &settings, &|_| {}).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let b = pool.install(|| prefilter(&map, &settings, &|_| {}).unwrap());
    for (x, y) in a.levels.iter().zip(&b.levels) {
        assert_eq!(x.cube, y.cube);
    }
}

#[test]
fn bad_settings_are_refused() {
    let pixels = draw(smooth);
    let map = map(&pixels);
    let base = PrefilterSettings::new(TargetEngine::Filament);
    // Each refusal names the setting as a field (a front end spells it as
    // its users give it) and says why, without any front end's flag.
    for (s, setting, needle) in [
        (
            PrefilterSettings { size: 48, ..base },
            "size",
            "power of two",
        ),
        (
            PrefilterSettings { samples: 0, ..base },
            "samples",
            "at least 1",
        ),
        (
            PrefilterSettings {
                mips: Some(10),
                ..base
            },
            "mips",
            "at most 9",
        ),
        (
            PrefilterSettings {
                mips: Some(0),
                ..base
            },
            "mips",
            "at least 1",
        ),
    ] {
        let e = prefilter(&map, &s, &|_| {}).unwrap_err();
        assert_eq!(e.setting(), setting, "{e}");
        assert!(e.to_string().contains(needle), "{e}");
        assert!(!e.to_string().contains("--"), "{e}");
    }
}

//! Baking with AVX2 ray packets and baking one ray at a time give the same
//! transfer. Its own test binary: it switches packets off for the whole
//! process.

use shlight_mesh::generate;
use shlight_prt::{BakeOptions, Mode, bake};
use shlight_rays::{packets_enabled, set_packets_enabled, skip_test};

#[test]
fn packet_and_single_ray_bakes_agree() {
    if !packets_enabled() {
        skip_test(
            "packet_and_single_ray_bakes_agree",
            "this processor has no AVX2 and FMA, so there are no packets to compare",
        );
        return;
    }
    let mesh = generate::plane_under_sphere(1.0, 24, 12, 4.0, 6);
    for mode in [Mode::Shadowed, Mode::Interreflected { bounces: 2 }] {
        let options = BakeOptions {
            lmax: 3,
            samples: 256,
            mode,
            ..BakeOptions::default()
        };
        set_packets_enabled(true);
        let packets = bake(&mesh, &options, &|_, _, _| {});
        set_packets_enabled(false);
        assert!(!packets_enabled());
        let single = bake(&mesh, &options, &|_, _, _| {});
        set_packets_enabled(true);
        assert_eq!(packets.rays, single.rays);
        let differing = packets
            .coeffs
            .iter()
            .zip(&single.coeffs)
            .filter(|(a, b)| (*a - *b).abs() > 1e-6)
            .count();
        let worst = packets
            .coeffs
            .iter()
            .zip(&single.coeffs)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        // Only rays grazing an edge may be decided differently (rounding in
        // the two triangle tests differs): a handful of the 128 directions
        // cast per vertex, each worth about 1/128 of the transfer.
        assert!(
            differing * 100 <= packets.coeffs.len(),
            "{mode:?}: {differing} of {} coefficients differ",
            packets.coeffs.len()
        );
        assert!(worst < 0.02, "{mode:?}: worst difference {worst}");
    }
}

//! The lighting operations in `f32` as well as `f64` (irradiance, zonal
//! convolution, rotation, windows, closed-form lights), checked against
//! closed forms and geometric identities rather than against the `f64` code.

use glam::{DMat3, DQuat, DVec3, Vec3};
use shlight_core::sh::{ShCoeffs, ShRotation, Window, ZonalKernel, closed_form, irradiance};

/// `f32` rounding of coefficients of order 1 through a few dozen
/// multiply-adds: a few ulps of 1.2e-7.
const F32_TOL: f32 = 2e-6;

#[test]
fn f32_irradiance_of_a_directional_light_is_the_nine_term_closed_form() {
    // Ramamoorthi-Hanrahan: truncated at lmax 2 the irradiance of a unit
    // directional light at angle t is 1/4 + cos t / 2 + (5/32)(3 cos^2 t - 1).
    let d = DVec3::new(0.3, -0.4, 0.866).normalize();
    let light: ShCoeffs<Vec3> = closed_form::directional(2, d, Vec3::new(1.0, 0.5, 2.0));
    let e = irradiance(&light);
    for n in [d, DVec3::X, DVec3::new(-0.2, 0.9, 0.1).normalize()] {
        let c = n.dot(d);
        let want = 0.25 + 0.5 * c + 5.0 / 32.0 * (3.0 * c * c - 1.0);
        let got = e.eval(n.as_vec3());
        for (ch, scale) in [(0, 1.0), (1, 0.5), (2, 2.0)] {
            assert!(
                (got[ch] - (want * scale) as f32).abs() < F32_TOL,
                "{n} ch {ch}"
            );
        }
    }
}

#[test]
fn f32_rotation_moves_a_function_with_its_direction() {
    // g = R f satisfies g(R d) = f(d).
    let r = DMat3::from_quat(DQuat::from_axis_angle(
        DVec3::new(1.0, 2.0, 0.5).normalize(),
        0.8,
    ));
    let f: ShCoeffs<f32> = closed_form::cap(6, DVec3::new(0.2, 0.3, 0.9).normalize(), 0.7, 1.0f32);
    let rot = ShRotation::from_mat3(6, r);
    let g = rot.apply(&f);
    let mut g2 = f.clone();
    rot.apply_in_place(&mut g2);
    let once = shlight_core::sh::rotate_once(&f, r);
    for d in [
        DVec3::Z,
        DVec3::new(0.5, -0.5, 0.7).normalize(),
        DVec3::NEG_X,
    ] {
        let want = f.eval(d.as_vec3());
        let at = (r * d).as_vec3();
        assert!((g.eval(at) - want).abs() < 10.0 * F32_TOL, "{d}");
        assert!((g2.eval(at) - want).abs() < 10.0 * F32_TOL, "{d}");
        assert!((once.eval(at) - want).abs() < 10.0 * F32_TOL, "{d}");
    }
}

#[test]
fn f32_zonal_kernels_and_windows_scale_each_band_by_their_factor() {
    let f = ShCoeffs::<f32>::from_fn(4, |l, m| 1.0 + l as f32 + 0.1 * m as f32);
    let phong = ZonalKernel::phong(4, 8.0);
    let w = Window::Hanning { w: 5.0 };
    let (pf, wf) = (phong.apply(&f), w.apply(&f));
    for l in 0..=4usize {
        for m in -(l as isize)..=l as isize {
            let v = f[(l, m)];
            let want_p = v * phong.eigenvalue(l) as f32;
            let want_w = v * w.factor(l) as f32;
            assert!((pf[(l, m)] - want_p).abs() <= F32_TOL * want_p.abs().max(1.0));
            assert!((wf[(l, m)] - want_w).abs() <= F32_TOL * want_w.abs().max(1.0));
        }
    }
    // Rounding to f32 and back is a conversion, not an alias.
    let rgb = ShCoeffs::<Vec3>::from_fn(1, |l, _| Vec3::splat(l as f32 + 0.1));
    assert_eq!(rgb.to_f64().to_f32(), rgb);
}

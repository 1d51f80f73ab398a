//! The fixed-size SH types ([`ShL1`], [`ShL2`], [`ShL1Rgb`], [`ShL2Rgb`],
//! [`ShRotationL2`]) against independent routes: the general basis
//! evaluated by the Legendre recurrence (an [`ShBasis`] built for lmax 6,
//! past the hard-coded polynomials whose constants the fixed types use), the core's
//! [`irradiance`] and [`ShRotation`] (Ivanic-Ruedenberg), re-projection of
//! `f(R^T d)` by exact quadrature, and the closed forms of a directional
//! light's truncated irradiance. Every check runs in `f32` and `f64`.
//!
//! Every random input comes from a seeded `StdRng`, so failures reproduce.

use std::f64::consts::PI;

use glam::{DMat3, DQuat, DVec3, Mat3, Vec3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use shlight_core::sh::{
    GlamReal, ShBasis, ShCoeffs, ShL1, ShL1Rgb, ShL2, ShL2Rgb, ShRotation, ShRotationL2,
    closed_form, irradiance,
};

/// The reference basis is built for this lmax so that it runs the Legendre
/// recurrence, not the hard-coded polynomials (they stop at lmax 4) whose
/// constants the fixed types use.
const RECURRENCE_LMAX: usize = 6;

/// Random directions and rotations per check.
const SAMPLES: usize = 500;

/// `f64` fixed type vs `f64` general path, absolute: values are sums of 9
/// terms of size at most `|c| |A_l Y| < 3` with `|c| <= 1`; both routes round
/// a few times each at `1.1e-16` relative (measured worst below 1e-14, in
/// the composition of rotation blocks).
const TOL_F64: f64 = 1e-13;

/// `f32` fixed type vs the `f64` reference at the same (rounded) inputs,
/// absolute: values up to ~10, `f32` rounding `6e-8` relative over ~20
/// operations; rotations also build their blocks from a matrix rounded to
/// `f32`, orthonormal only to ~1e-7 (measured worst below 1e-6).
const TOL_F32: f64 = 5e-6;

/// Tolerance for the precision `T` (`f32` or `f64`).
fn tol<T: GlamReal>(f64_tol: f64, f32_tol: f64) -> f64 {
    if core::mem::size_of::<T>() == 8 {
        f64_tol
    } else {
        f32_tol
    }
}

fn rng(seed: u64) -> StdRng {
    StdRng::seed_from_u64(seed)
}

/// A unit vector uniform on the sphere.
fn random_direction(rng: &mut StdRng) -> DVec3 {
    let z: f64 = rng.random_range(-1.0..1.0);
    let p: f64 = rng.random_range(0.0..2.0 * PI);
    let s = (1.0 - z * z).sqrt();
    DVec3::new(s * p.cos(), s * p.sin(), z)
}

/// A uniformly distributed rotation (Shoemake 1992): the unit quaternion
/// from three uniforms.
fn random_quat(rng: &mut StdRng) -> DQuat {
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let (t2, t3) = (2.0 * PI * u2, 2.0 * PI * u3);
    DQuat::from_xyzw(a * t2.sin(), a * t2.cos(), b * t3.sin(), b * t3.cos()).normalize()
}

/// Scalar coefficients uniform in `[-1, 1]`.
fn random_coeffs(rng: &mut StdRng, lmax: usize) -> ShCoeffs<f64> {
    ShCoeffs::from_fn(lmax, |_, _| rng.random_range(-1.0..1.0))
}

/// RGB coefficients uniform in `[-1, 1]^3`.
fn random_rgb(rng: &mut StdRng, lmax: usize) -> ShCoeffs<DVec3> {
    ShCoeffs::from_fn(lmax, |_, _| {
        DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    })
}

fn to_t<T: GlamReal>(x: f64) -> T {
    T::from_f64(x)
}

/// `d` rounded to `T`, and that rounded direction widened back (what the
/// reference must evaluate at so that only arithmetic rounding differs).
fn dir<T: GlamReal>(d: DVec3) -> (T::Vec3, DVec3) {
    let a = d.to_array().map(to_t::<T>);
    (T::vec3_from_array(a), DVec3::from_array(a.map(T::to_f64)))
}

fn widen<T: GlamReal>(v: T::Vec3) -> DVec3 {
    DVec3::from_array(T::vec3_to_array(v).map(T::to_f64))
}

fn coeffs_t<T: GlamReal>(c: &ShCoeffs<f64>) -> ShCoeffs<T> {
    c.map(to_t::<T>)
}

fn rgb_t<T: GlamReal>(c: &ShCoeffs<DVec3>) -> ShCoeffs<T::Vec3> {
    c.map(|v| T::vec3_from_array(v.to_array().map(to_t::<T>)))
}

/// The reference: `sum_i c_i Y_i(d)` with the basis from the recurrence.
fn general_eval<C: shlight_core::sh::ShValue<Scalar = f64>>(c: &ShCoeffs<C>, d: DVec3) -> C {
    let basis = ShBasis::<f64>::new(RECURRENCE_LMAX);
    let mut y = vec![0.0; basis.count()];
    basis.eval(d, &mut y);
    c.dot_scalar(&y[..c.len()])
}

/// `|a - b|` over the channels.
fn diff3(a: DVec3, b: DVec3) -> f64 {
    (a - b).abs().max_element()
}

/// Radiance and irradiance of a scalar fixed type (`eval`, `irradiance`,
/// `eval_irradiance`) against the general path at random directions.
fn check_scalar_eval<T: GlamReal>(seed: u64) {
    let t = tol::<T>(TOL_F64, TOL_F32);
    let mut rng = rng(seed);
    for _ in 0..20 {
        let c2 = coeffs_t::<T>(&random_coeffs(&mut rng, 2)).map(T::to_f64);
        let c1 = c2.resized(1);
        let l2 = ShL2::<T>::from_coeffs(&coeffs_t(&c2));
        let l1 = ShL1::<T>::from_coeffs(&coeffs_t(&c1));
        let (e2, e1) = (irradiance(&c2), irradiance(&c1));
        let (l2e, l1e) = (l2.irradiance(), l1.irradiance());
        for (i, (a, b)) in l2e.coeffs.iter().zip(e2.as_slice()).enumerate() {
            assert!((a.to_f64() - b).abs() < t, "irradiance coefficient {i}");
        }
        for _ in 0..SAMPLES / 20 {
            let (d, dw) = dir::<T>(random_direction(&mut rng));
            let checks = [
                (l2.eval(d), general_eval(&c2, dw), "L2 eval"),
                (l1.eval(d), general_eval(&c1, dw), "L1 eval"),
                (
                    l2.eval_irradiance(d),
                    general_eval(&e2, dw),
                    "L2 eval_irradiance",
                ),
                (
                    l1.eval_irradiance(d),
                    general_eval(&e1, dw),
                    "L1 eval_irradiance",
                ),
                (l2e.eval(d), general_eval(&e2, dw), "L2 irradiance().eval"),
                (l1e.eval(d), general_eval(&e1, dw), "L1 irradiance().eval"),
            ];
            for (got, want, what) in checks {
                let err = (got.to_f64() - want).abs();
                assert!(err < t, "{what} at {dw}: {got:?} vs {want} (err {err:e})");
            }
        }
    }
}

/// The same for the RGB types, against `ShCoeffs<DVec3>`.
fn check_rgb_eval<T: GlamReal>(seed: u64) {
    let t = tol::<T>(TOL_F64, TOL_F32);
    let mut rng = rng(seed);
    for _ in 0..20 {
        let c2 = rgb_t::<T>(&random_rgb(&mut rng, 2)).map(widen::<T>);
        let c1 = c2.resized(1);
        let l2 = ShL2Rgb::<T>::from_coeffs(&rgb_t::<T>(&c2));
        let l1 = ShL1Rgb::<T>::from_coeffs(&rgb_t::<T>(&c1));
        let (e2, e1) = (irradiance(&c2), irradiance(&c1));
        for _ in 0..SAMPLES / 20 {
            let (d, dw) = dir::<T>(random_direction(&mut rng));
            let checks = [
                (l2.eval(d), general_eval(&c2, dw), "L2 eval"),
                (l1.eval(d), general_eval(&c1, dw), "L1 eval"),
                (
                    l2.eval_irradiance(d),
                    general_eval(&e2, dw),
                    "L2 irradiance",
                ),
                (
                    l1.eval_irradiance(d),
                    general_eval(&e1, dw),
                    "L1 irradiance",
                ),
                (
                    l2.irradiance().eval(d),
                    general_eval(&e2, dw),
                    "L2 E coeffs",
                ),
            ];
            for (got, want, what) in checks {
                let err = diff3(widen::<T>(got), want);
                assert!(err < t, "{what} at {dw}: {got:?} vs {want} (err {err:e})");
            }
        }
        // The channels are the scalar expansions.
        let [r, g, b] = l2.channels();
        let d = T::vec3_from_array([to_t(0.6), to_t(0.0), to_t(0.8)]);
        let v = T::vec3_to_array(l2.eval(d));
        assert_eq!([r.eval(d), g.eval(d), b.eval(d)], v);
    }
}

#[test]
fn scalar_eval_and_irradiance_match_the_general_path_f64() {
    check_scalar_eval::<f64>(1);
}

#[test]
fn scalar_eval_and_irradiance_match_the_general_path_f32() {
    check_scalar_eval::<f32>(2);
}

#[test]
fn rgb_eval_and_irradiance_match_the_general_path_f64() {
    check_rgb_eval::<f64>(3);
}

#[test]
fn rgb_eval_and_irradiance_match_the_general_path_f32() {
    check_rgb_eval::<f32>(4);
}

/// Band 1 at the axes against the published constants (`0.488603` with the
/// Condon-Shortley signs), and the band-2 constants at chosen directions.
#[test]
fn basis_constants_carry_the_condon_shortley_phase() {
    let six_digits = 1e-6;
    let bx = ShL2::<f64>::basis(DVec3::X).coeffs;
    let by = ShL2::<f64>::basis(DVec3::Y).coeffs;
    let bz = ShL2::<f64>::basis(DVec3::Z).coeffs;
    assert!((bz[0] - 0.282095).abs() < six_digits);
    assert!(
        (by[1] + 0.488603).abs() < six_digits,
        "Y_1^-1 = -0.488603 y"
    );
    assert!((bz[2] - 0.488603).abs() < six_digits, "Y_1^0 = 0.488603 z");
    assert!((bx[3] + 0.488603).abs() < six_digits, "Y_1^1 = -0.488603 x");
    assert!(
        (bz[6] - 2.0 * 0.315392).abs() < six_digits,
        "Y_2^0(z) = 2 * 0.315392"
    );
    assert!((bx[8] - 0.546274).abs() < six_digits, "Y_2^2(x) = 0.546274");
    let s = 0.5f64.sqrt();
    let xy = ShL2::<f64>::basis(DVec3::new(s, s, 0.0)).coeffs;
    assert!(
        (xy[4] - 1.092548 / 2.0).abs() < six_digits,
        "Y_2^-2 = 1.092548 xy"
    );
    let yz = ShL2::<f64>::basis(DVec3::new(0.0, s, s)).coeffs;
    assert!(
        (yz[5] + 1.092548 / 2.0).abs() < six_digits,
        "Y_2^-1 = -1.092548 yz"
    );
    let xz = ShL2::<f64>::basis(DVec3::new(s, 0.0, s)).coeffs;
    assert!(
        (xz[7] + 1.092548 / 2.0).abs() < six_digits,
        "Y_2^1 = -1.092548 xz"
    );
    // Full precision: sqrt(3/(4 pi)) to the last bits.
    assert!((bz[2] - (3.0 / (4.0 * PI)).sqrt()).abs() < 1e-16);
    let l1 = ShL1::<f32>::basis(Vec3::X).coeffs;
    assert!((l1[3] as f64 + 0.488603).abs() < six_digits);
}

/// A directional light from `a` (unit irradiance facing it): its truncated
/// irradiance at `n` is `1/4 + c/2 + (5/32)(3 c^2 - 1)` at lmax 2 and
/// `1/4 + c/2` at lmax 1, `c = n . a` (Ramamoorthi & Hanrahan 2001; the
/// addition theorem); 17/16 facing the light, 3/32 at 90 degrees.
fn check_directional<T: GlamReal>(seed: u64) {
    let t = tol::<T>(TOL_F64, TOL_F32);
    let e2 = |c: f64| 0.25 + c / 2.0 + 5.0 / 32.0 * (3.0 * c * c - 1.0);
    let e1 = |c: f64| 0.25 + c / 2.0;
    let mut rng = rng(seed);
    for _ in 0..SAMPLES {
        let (a, aw) = dir::<T>(random_direction(&mut rng));
        let (n, nw) = dir::<T>(random_direction(&mut rng));
        let c = aw.dot(nw);
        let colour = T::vec3_from_array([to_t(1.0), to_t(0.5), to_t(0.25)]);
        let l2 = ShL2::<T>::basis(a);
        let l1 = ShL1::<T>::basis(a);
        let rgb = ShL2Rgb::from_scalar(&l2, colour);
        assert!(
            (l2.eval_irradiance(n).to_f64() - e2(c)).abs() < t,
            "L2 at c = {c}"
        );
        assert!(
            (l1.eval_irradiance(n).to_f64() - e1(c)).abs() < t,
            "L1 at c = {c}"
        );
        let want = DVec3::new(1.0, 0.5, 0.25) * e2(c);
        assert!(
            diff3(widen::<T>(rgb.eval_irradiance(n)), want) < t,
            "RGB at c = {c}"
        );
    }
    // Facing the light and at 90 degrees, light from +Z.
    let z = T::vec3_from_array([to_t(0.0), to_t(0.0), to_t(1.0)]);
    let x = T::vec3_from_array([to_t(1.0), to_t(0.0), to_t(0.0)]);
    let light = ShL2Rgb::from_scalar(&ShL2::<T>::basis(z), T::vec3_from_array([to_t(1.0); 3]));
    assert!(
        diff3(
            widen::<T>(light.eval_irradiance(z)),
            DVec3::splat(17.0 / 16.0)
        ) < t
    );
    assert!(
        diff3(
            widen::<T>(light.eval_irradiance(x)),
            DVec3::splat(3.0 / 32.0)
        ) < t
    );
}

#[test]
fn directional_light_irradiance_matches_the_closed_form_f64() {
    check_directional::<f64>(5);
}

#[test]
fn directional_light_irradiance_matches_the_closed_form_f32() {
    check_directional::<f32>(6);
}

/// The fixed types' coefficients of a directional light agree with the
/// core's analytic projection (`closed_form::directional`, built on `sh_eval`).
#[test]
fn basis_matches_the_analytic_directional_light() {
    let mut rng = rng(7);
    for _ in 0..SAMPLES {
        let a = random_direction(&mut rng);
        let want: ShCoeffs<f64> = closed_form::directional(RECURRENCE_LMAX, a, 1.0);
        let got = ShL2::<f64>::basis(a);
        for (i, (g, w)) in got.coeffs.iter().zip(want.as_slice()).enumerate() {
            assert!((g - w).abs() < TOL_F64, "coefficient {i} at {a}");
        }
    }
}

/// Rotation by a matrix and by a quaternion: `g(d) = f(R^T d)` at random
/// directions, the coefficients against the core's `ShRotation` and
/// against re-projection of `f(R^T d)`, and a light from `a` landing at `R a`.
fn check_rotation<T: GlamReal>(
    seed: u64,
    mat: impl Fn(DMat3) -> T::Mat3,
    quat: impl Fn(DQuat) -> T::Quat,
) {
    let t = tol::<T>(TOL_F64, TOL_F32);
    let mut rng = rng(seed);
    for _ in 0..40 {
        let q = random_quat(&mut rng);
        let r = DMat3::from_quat(q);
        let c2 = coeffs_t::<T>(&random_coeffs(&mut rng, 2)).map(T::to_f64);
        let c1 = c2.resized(1);
        let rgb = rgb_t::<T>(&random_rgb(&mut rng, 2)).map(widen::<T>);
        let f2 = ShL2::<T>::from_coeffs(&coeffs_t(&c2));
        let f1 = ShL1::<T>::from_coeffs(&coeffs_t(&c1));
        let frgb = ShL2Rgb::<T>::from_coeffs(&rgb_t::<T>(&rgb));
        let frgb1 = frgb.to_l1();
        let by_mat = f2.rotated(mat(r));
        let by_quat = f2.rotated_quat(quat(q));
        let l1_mat = f1.rotated(mat(r));
        let l1_quat = f1.rotated_quat(quat(q));
        let rgb_mat = frgb.rotated(mat(r));
        let rgb1_quat = frgb1.rotated_quat(quat(q));

        // The core's Ivanic-Ruedenberg rotation.
        let core = ShRotation::from_mat3(2, r);
        let want = core.apply(&c2);
        for (i, w) in want.as_slice().iter().enumerate() {
            for (got, what) in [(by_mat.coeffs[i], "mat"), (by_quat.coeffs[i], "quat")] {
                assert!((got.to_f64() - w).abs() < t, "{what} coefficient {i}");
            }
            if i < 4 {
                assert!(
                    (l1_mat.coeffs[i].to_f64() - w).abs() < t,
                    "L1 mat coefficient {i}"
                );
                assert!(
                    (l1_quat.coeffs[i].to_f64() - w).abs() < t,
                    "L1 quat coefficient {i}"
                );
            }
        }
        // Re-projection of g(d) = f(R^T d): exact quadrature to degree 6.
        let reproj = ShCoeffs::project_fn(2, 6, |d| general_eval(&c2, r.transpose() * d));
        for (i, w) in reproj.as_slice().iter().enumerate() {
            assert!(
                (by_mat.coeffs[i].to_f64() - w).abs() < t,
                "re-projection coefficient {i}"
            );
        }
        // g(d) = f(R^T d) at random directions.
        for _ in 0..SAMPLES / 40 {
            let (d, dw) = dir::<T>(random_direction(&mut rng));
            let back = r.transpose() * dw;
            let checks = [
                (by_mat.eval(d), general_eval(&c2, back), "L2 mat"),
                (by_quat.eval(d), general_eval(&c2, back), "L2 quat"),
                (l1_mat.eval(d), general_eval(&c1, back), "L1 mat"),
                (l1_quat.eval(d), general_eval(&c1, back), "L1 quat"),
            ];
            for (got, want, what) in checks {
                let err = (got.to_f64() - want).abs();
                assert!(err < t, "{what} at {dw}: err {err:e}");
            }
            let err = diff3(widen::<T>(rgb_mat.eval(d)), general_eval(&rgb, back));
            assert!(err < t, "RGB mat at {dw}: err {err:e}");
            let err = diff3(
                widen::<T>(rgb1_quat.eval(d)),
                general_eval(&rgb.resized(1), back),
            );
            assert!(err < t, "RGB L1 quat at {dw}: err {err:e}");
        }
        // A light from a comes from R a afterwards.
        let (a, aw) = dir::<T>(random_direction(&mut rng));
        let moved = ShL2::<T>::basis(a).rotated(mat(r));
        let (_, raw) = dir::<T>(r * aw);
        let at_ra: ShCoeffs<f64> = closed_form::directional(2, raw, 1.0);
        for (i, w) in at_ra.as_slice().iter().enumerate() {
            assert!(
                (moved.coeffs[i].to_f64() - w).abs() < t,
                "moved light coefficient {i}"
            );
        }
    }
}

#[test]
fn rotation_carries_the_function_f64() {
    check_rotation::<f64>(8, |r| r, |q| q);
}

#[test]
fn rotation_carries_the_function_f32() {
    check_rotation::<f32>(9, |r| r.as_mat3(), |q| q.as_quat());
}

/// The blocks equal the core's `ShRotation` blocks entry by entry, are
/// orthogonal, and compose like the rotations (`M(R_a R_b) = M(R_a) M(R_b)`).
#[test]
fn rotation_blocks_match_the_core_and_compose() {
    let mut rng = rng(10);
    for _ in 0..100 {
        let (qa, qb) = (random_quat(&mut rng), random_quat(&mut rng));
        let (ra, rb) = (DMat3::from_quat(qa), DMat3::from_quat(qb));
        let fixed = ShRotationL2::<f64>::from_mat3(ra);
        let core = ShRotation::from_mat3(2, ra);
        for i in 0..3 {
            for j in 0..3 {
                assert!((fixed.band1()[i][j] - core.block(1)[i * 3 + j]).abs() < TOL_F64);
            }
        }
        for i in 0..5 {
            for j in 0..5 {
                assert!((fixed.band2()[i][j] - core.block(2)[i * 5 + j]).abs() < TOL_F64);
            }
        }
        let m2 = fixed.band2();
        for i in 0..5 {
            for j in 0..5 {
                let g: f64 = (0..5).map(|k| m2[i][k] * m2[j][k]).sum();
                assert!(
                    (g - if i == j { 1.0 } else { 0.0 }).abs() < TOL_F64,
                    "M M^T"
                );
            }
        }
        let ab = ShRotationL2::<f64>::from_mat3(ra * rb);
        let b = ShRotationL2::<f64>::from_quat(qb);
        let mb = b.band2();
        for i in 0..5 {
            for j in 0..5 {
                let p: f64 = (0..5).map(|k| m2[i][k] * mb[k][j]).sum();
                assert!((ab.band2()[i][j] - p).abs() < TOL_F64, "composition");
            }
        }
    }
    let id = ShRotationL2::<f32>::from_mat3(Mat3::IDENTITY);
    assert_eq!(id, ShRotationL2::<f32>::identity());
    assert_eq!(
        ShRotationL2::<f32>::default(),
        ShRotationL2::<f32>::identity()
    );
}

/// `from_coeffs` truncates a longer expansion and zero-pads a shorter one;
/// `to_coeffs` / `From` give the coefficients back unchanged.
#[test]
fn conversions_to_and_from_sh_coeffs() {
    let mut rng = rng(11);
    let long = random_coeffs(&mut rng, 4);
    let l2 = ShL2::<f64>::from_coeffs(&long);
    assert_eq!(&l2.coeffs[..], &long.as_slice()[..9], "truncated");
    let d = DVec3::new(0.48, -0.6, 0.64);
    assert!((l2.eval(d) - general_eval(&long.resized(2), d)).abs() < TOL_F64);
    let back: ShCoeffs<f64> = l2.into();
    assert_eq!(back.lmax(), 2);
    assert_eq!(ShL2::from_coeffs(&back), l2, "round trip");
    assert_eq!(back, long.resized(2));

    let short = random_coeffs(&mut rng, 1);
    let padded = ShL2::<f64>::from_coeffs(&short);
    assert_eq!(&padded.coeffs[..4], short.as_slice());
    assert!(padded.coeffs[4..].iter().all(|&c| c == 0.0), "zero-padded");
    assert_eq!(ShL2::<f64>::from(ShL1::from_coeffs(&short)), padded);
    assert_eq!(padded.to_l1().to_coeffs(), short);
    assert_eq!(ShL1::<f64>::from_coeffs(&long).to_coeffs(), long.resized(1));
    let constant = ShCoeffs::<f64>::from_vec(vec![2.0]).unwrap();
    assert_eq!(
        ShL1::<f64>::from_coeffs(&constant).coeffs,
        [2.0, 0.0, 0.0, 0.0]
    );

    let rgb = random_rgb(&mut rng, 3).to_f32();
    let f = ShL2Rgb::<f32>::from_coeffs(&rgb);
    for i in 0..9 {
        assert_eq!(
            [f.r[i], f.g[i], f.b[i]],
            rgb[i].to_array(),
            "channel-planar {i}"
        );
    }
    let back: ShCoeffs<Vec3> = f.into();
    assert_eq!(back, rgb.resized(2));
    assert_eq!(ShL2Rgb::from_coeffs(&back), f);
    let f1 = ShL1Rgb::<f32>::from_coeffs(&rgb);
    assert_eq!(f1.to_coeffs(), rgb.resized(1));
    assert_eq!(f.to_l1(), f1);
    let padded: ShL2Rgb<f32> = f1.into();
    assert_eq!(padded.to_coeffs(), rgb.resized(1).resized(2));
    let [r, g, b] = f.channels();
    assert_eq!(ShL2Rgb::from_channels(r, g, b), f);
}

/// `+`, `-`, unary `-`, `* s`, `s *`, the assigning forms and `lerp` against
/// the same operations on `ShCoeffs`, and against evaluation (linearity).
#[test]
fn arithmetic_matches_the_general_expansion() {
    let mut rng = rng(12);
    let (ca, cb) = (random_coeffs(&mut rng, 2), random_coeffs(&mut rng, 2));
    let (a, b) = (ShL2::<f64>::from_coeffs(&ca), ShL2::<f64>::from_coeffs(&cb));
    assert_eq!((a + b).to_coeffs(), &ca + &cb);
    assert_eq!((a - b).to_coeffs(), &ca - &cb);
    assert_eq!((-a).to_coeffs(), -&ca);
    assert_eq!((a * 2.5).to_coeffs(), &ca * 2.5);
    assert_eq!(2.5 * a, a * 2.5);
    let mut m = a;
    m += b;
    m -= a;
    m *= 3.0;
    assert_eq!(m, b * 3.0);
    let d = DVec3::new(0.0, 0.6, 0.8);
    let mid = a.lerp(&b, 0.25);
    let want = 0.75 * general_eval(&ca, d) + 0.25 * general_eval(&cb, d);
    assert!((mid.eval(d) - want).abs() < TOL_F64);
    assert_eq!(a.lerp(&b, 0.0), a);
    assert_eq!(a.lerp(&b, 1.0), b);
    assert_ne!(a, b);
    assert_eq!(ShL2::<f64>::default(), ShL2::ZERO);
    assert_eq!(ShL2::<f64>::ZERO.coeffs, [0.0; 9]);
    assert_eq!(a - a, ShL2::ZERO);

    let (ra, rb) = (
        random_rgb(&mut rng, 1).to_f32(),
        random_rgb(&mut rng, 1).to_f32(),
    );
    let (x, y) = (
        ShL1Rgb::<f32>::from_coeffs(&ra),
        ShL1Rgb::<f32>::from_coeffs(&rb),
    );
    assert_eq!((x + y).to_coeffs(), &ra + &rb);
    assert_eq!((x - y).to_coeffs(), &ra - &rb);
    assert_eq!((x * 0.5).to_coeffs(), &ra * 0.5);
    assert_eq!(0.5 * x, x * 0.5);
    assert_eq!(ShL1Rgb::<f32>::default(), ShL1Rgb::ZERO);
    assert_eq!(ShL1Rgb::<f32>::ZERO.eval(Vec3::Z), Vec3::ZERO);
    let lerped = x.lerp(&y, 0.5).eval(Vec3::X);
    let want = (x.eval(Vec3::X) + y.eval(Vec3::X)) * 0.5;
    assert!((lerped - want).abs().max_element() < TOL_F32 as f32);
    assert!(format!("{x:?}").starts_with("ShL1Rgb"));
    assert!(format!("{:?}", ShL2::<f32>::ZERO).contains("coeffs"));
}

/// The lmax constants and the flat layout.
#[test]
fn lmax_constants() {
    assert_eq!(ShL1::<f32>::LMAX, 1);
    assert_eq!(ShL2::<f64>::LMAX, 2);
    assert_eq!(ShL1Rgb::<f64>::LMAX, 1);
    assert_eq!(ShL2Rgb::<f32>::LMAX, 2);
    assert_eq!(ShL2::<f64>::ZERO.to_coeffs().len(), 9);
    assert_eq!(ShL1Rgb::<f32>::ZERO.to_coeffs().len(), 4);
}

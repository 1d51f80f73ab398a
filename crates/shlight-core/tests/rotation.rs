//! Rotation of SH coefficients ([`ShRotation`], [`rotate_z`], [`Frame`]),
//! checked against independent oracles: re-projection of the rotated
//! function, the basis evaluated at the rotated direction, the group laws,
//! orthogonality, band power, and the frame formulas.
//!
//! Every random input comes from a seeded `StdRng`, so failures reproduce.

use std::f64::consts::{FRAC_PI_2, PI};

use glam::{DMat3, DQuat, DVec3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use shlight_core::sh::{
    Frame, ShBasis, ShCoeffs, ShRotation, rotate_once, rotate_z, sh_count, sh_eval,
};

/// Rotation vs re-projection, relative to the largest coefficient: both
/// sides are exact in exact arithmetic (the quadrature is exact to degree
/// `2 lmax`), so only rounding remains; the projection sums ~`2 lmax^2`
/// terms of size ~`|f| |Y|`; measured worst 2e-14 up to `lmax` 32.
const PROJECTION_TOL: f64 = 1e-12;

/// Directional light `Y(a) -> Y(R a)`, absolute: the values are at most
/// `sqrt((2l+1)/(4 pi))` (~3.2 at `l` 64) and the recurrence loses ~`l` ulps.
const DIRECTIONAL_TOL: f64 = 1e-12;

/// Group laws (composition, inverse, identity) between independently built
/// blocks: each side carries the recurrence's rounding, ~`l` ulps.
const GROUP_TOL: f64 = 1e-13;

/// `max |B B^T - I|` for every block: the brief's bar at `lmax` 64.
const ORTHOGONALITY_TOL: f64 = 1e-12;

/// Band power before and after rotation, relative: an orthogonal block
/// preserves it up to its own orthogonality error.
const POWER_TOL: f64 = 1e-12;

/// `rotate_z` (trig of `m alpha`) vs the recurrence built from
/// `Rz(alpha)`: two roundings of the same numbers.
const ROTATE_Z_TOL: f64 = 1e-13;

/// Frame conversions: entries of the matrices are exactly `0`, `+-1`, so
/// only the recurrence's rounding remains.
const FRAME_TOL: f64 = 1e-13;

fn rng(seed: u64) -> StdRng {
    StdRng::seed_from_u64(seed)
}

/// A uniformly distributed rotation (Shoemake 1992, "Uniform random
/// rotations", Graphics Gems III): the unit quaternion from three uniforms.
fn random_rotation(rng: &mut StdRng) -> DMat3 {
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let (t2, t3) = (2.0 * PI * u2, 2.0 * PI * u3);
    let q = DQuat::from_xyzw(a * t2.sin(), a * t2.cos(), b * t3.sin(), b * t3.cos());
    DMat3::from_quat(q.normalize())
}

/// A unit vector uniform on the sphere.
fn random_direction(rng: &mut StdRng) -> DVec3 {
    let z: f64 = rng.random_range(-1.0..1.0);
    let p: f64 = rng.random_range(0.0..2.0 * PI);
    let s = (1.0 - z * z).sqrt();
    DVec3::new(s * p.cos(), s * p.sin(), z)
}

/// Coefficients uniform in `[-1, 1]`.
fn random_coeffs(rng: &mut StdRng, lmax: usize) -> ShCoeffs<f64> {
    ShCoeffs::from_fn(lmax, |_, _| rng.random_range(-1.0..1.0))
}

/// The coefficients of a directional light from `d`: `Y_l^m(d)`.
fn light(lmax: usize, d: DVec3) -> ShCoeffs<f64> {
    ShCoeffs::from_vec(sh_eval(lmax, d)).unwrap()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len(), "lengths differ");
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Largest difference between the blocks of two rotations of equal `lmax`.
fn block_diff(a: &ShRotation, b: &ShRotation) -> f64 {
    assert_eq!(a.lmax(), b.lmax());
    (0..=a.lmax())
        .map(|l| max_abs_diff(a.block(l), b.block(l)))
        .fold(0.0, f64::max)
}

/// `max |B B^T - I|` of block `l`.
fn orthogonality_error(rot: &ShRotation, l: usize) -> f64 {
    let b = rot.block(l);
    let n = 2 * l + 1;
    let mut worst = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let dot: f64 = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum();
            let want = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((dot - want).abs());
        }
    }
    worst
}

/// Asserts `|got - want|_max <= tol` and prints the difference otherwise.
#[track_caller]
fn assert_close(got: &[f64], want: &[f64], tol: f64, what: &str) {
    let d = max_abs_diff(got, want);
    assert!(d <= tol, "{what}: max difference {d:e} > tolerance {tol:e}");
}

/// The rotation matrix of `deg` degrees about a coordinate axis, with
/// entries exactly `0` and `+-1` for multiples of 90 degrees (glam's
/// `from_rotation_x` leaves `cos(pi/2) = 6e-17`).
fn exact_axis_rotation(axis: usize, quarter_turns: i32) -> DMat3 {
    let (c, s) = match quarter_turns.rem_euclid(4) {
        0 => (1.0, 0.0),
        1 => (0.0, 1.0),
        2 => (-1.0, 0.0),
        _ => (0.0, -1.0),
    };
    match axis {
        0 => DMat3::from_cols(DVec3::X, DVec3::new(0.0, c, s), DVec3::new(0.0, -s, c)),
        1 => DMat3::from_cols(DVec3::new(c, 0.0, -s), DVec3::Y, DVec3::new(s, 0.0, c)),
        _ => DMat3::from_cols(DVec3::new(c, s, 0.0), DVec3::new(-s, c, 0.0), DVec3::Z),
    }
}

#[test]
fn rotating_the_projection_equals_projecting_the_rotated_function() {
    let mut rng = rng(0x5eed_0001);
    let cases = (0..=8).map(|l| (l, 50)).chain([(16, 8), (32, 3)]);
    let mut worst = 0.0f64;
    for (lmax, count) in cases {
        for k in 0..count {
            let r = random_rotation(&mut rng);
            let f = random_coeffs(&mut rng, lmax);
            let rotated = ShRotation::from_mat3(lmax, r).apply(&f);
            // g(d) = f(R^T d), projected exactly (degree 2 lmax).
            let basis = ShBasis::<f64>::new(lmax);
            let projected = ShCoeffs::<f64>::project_fn(lmax, 2 * lmax, |d| {
                let e = r.transpose() * DVec3::from_array(d.to_array());
                f.eval_with(&basis, e, &mut vec![0.0; sh_count(lmax)])
            });
            let scale = max_abs(projected.as_slice()).max(1.0);
            worst = worst.max(max_abs_diff(rotated.as_slice(), projected.as_slice()) / scale);
            assert_close(
                rotated.as_slice(),
                projected.as_slice(),
                PROJECTION_TOL * scale,
                &format!("lmax {lmax} rotation #{k} {r:?}"),
            );
        }
    }
    eprintln!("worst relative rotation-vs-projection difference: {worst:e}");
}

#[test]
fn directional_light_at_a_goes_to_r_a() {
    let mut rng = rng(0x5eed_0002);
    let mut worst = 0.0f64;
    for lmax in [1, 2, 3, 4, 5, 8, 16, 33, 64] {
        let rot_count = if lmax > 16 { 3 } else { 10 };
        for _ in 0..rot_count {
            let r = random_rotation(&mut rng);
            let rot = ShRotation::from_mat3(lmax, r);
            for _ in 0..5 {
                let a = random_direction(&mut rng);
                let got = rot.apply(&light(lmax, a));
                let want = light(lmax, r * a);
                worst = worst.max(max_abs_diff(got.as_slice(), want.as_slice()));
                assert_close(
                    got.as_slice(),
                    want.as_slice(),
                    DIRECTIONAL_TOL,
                    &format!("lmax {lmax}, a = {a}, R = {r:?}"),
                );
            }
        }
    }
    eprintln!("worst directional-light difference: {worst:e}");
}

#[test]
fn composition_inverse_and_identity_follow_the_rotation_group() {
    let mut rng = rng(0x5eed_0003);
    let lmax = 16;
    for _ in 0..10 {
        let (ra, rb) = (random_rotation(&mut rng), random_rotation(&mut rng));
        let (a, b) = (
            ShRotation::from_mat3(lmax, ra),
            ShRotation::from_mat3(lmax, rb),
        );
        // M(Ra Rb) = M(Ra) M(Rb): apply Rb first, then Ra.
        let direct = ShRotation::from_mat3(lmax, ra * rb);
        assert!(
            block_diff(&(&a * &b), &direct) < GROUP_TOL,
            "R(a)R(b) != R(ab)"
        );
        assert!(block_diff(&a.compose(&b), &direct) < GROUP_TOL);
        // The product is not commutative, so the order is really tested.
        let other = ShRotation::from_mat3(lmax, rb * ra);
        assert!(block_diff(&(&a * &b), &other) > 1e-3);
        // M(R^T) = M(R)^T = M(R)^-1.
        let transposed = ShRotation::from_mat3(lmax, ra.transpose());
        assert!(
            block_diff(&a.inverse(), &transposed) < GROUP_TOL,
            "R(R^T) != R^-1"
        );
        assert!(block_diff(&(&a * &a.inverse()), &ShRotation::identity(lmax)) < GROUP_TOL);
        // Applying a then its inverse gives the input back.
        let f = random_coeffs(&mut rng, lmax);
        let back = a.inverse().apply(&a.apply(&f));
        assert_close(
            back.as_slice(),
            f.as_slice(),
            GROUP_TOL * 10.0,
            "round trip",
        );
    }
    let id = ShRotation::from_mat3(lmax, DMat3::IDENTITY);
    assert!(block_diff(&id, &ShRotation::identity(lmax)) < GROUP_TOL);
    assert_eq!(ShRotation::from_quat(lmax, DQuat::IDENTITY), id);
}

#[test]
fn every_block_is_orthogonal_at_lmax_64() {
    let mut rng = rng(0x5eed_0004);
    let lmax = 64;
    let mut worst = 0.0f64;
    for _ in 0..4 {
        let rot = ShRotation::from_mat3(lmax, random_rotation(&mut rng));
        for l in 0..=lmax {
            let e = orthogonality_error(&rot, l);
            assert!(e < ORTHOGONALITY_TOL, "l {l}: |B B^T - I| = {e:e}");
            worst = worst.max(e);
        }
    }
    eprintln!("worst |B B^T - I| at lmax {lmax}: {worst:e}");
}

#[test]
fn usable_at_lmax_256() {
    // Top block still orthogonal and a light still lands where it should;
    // looser bars than at lmax 64 because rounding grows with l.
    let mut rng = rng(0x5eed_0005);
    let lmax = 256;
    let r = random_rotation(&mut rng);
    let rot = ShRotation::from_mat3(lmax, r);
    let e = orthogonality_error(&rot, lmax);
    eprintln!("|B B^T - I| at l {lmax}: {e:e}");
    assert!(e < 1e-11, "l {lmax}: |B B^T - I| = {e:e}");
    let a = random_direction(&mut rng);
    let got = rot.apply(&light(lmax, a));
    let d = max_abs_diff(got.as_slice(), light(lmax, r * a).as_slice());
    eprintln!("directional light error at lmax {lmax}: {d:e}");
    assert!(d < 1e-10, "directional light at lmax {lmax}: {d:e}");
}

#[test]
fn band_power_is_invariant() {
    let mut rng = rng(0x5eed_0006);
    let lmax = 24;
    for _ in 0..10 {
        let f = random_coeffs(&mut rng, lmax).splat_rgb::<DVec3>();
        let f = ShCoeffs::from_channels(
            &f.channel(0),
            &f.channel(1).scaled(0.5),
            &random_coeffs(&mut rng, lmax),
        );
        let g = ShRotation::from_mat3(lmax, random_rotation(&mut rng)).apply(&f);
        for (l, (p, q)) in f.band_power().iter().zip(g.band_power()).enumerate() {
            let rel = ((*p - q).abs() / p.abs().max(DVec3::splat(1e-300))).max_element();
            assert!(rel < POWER_TOL, "l {l}: power {p} -> {q}");
        }
    }
}

#[test]
fn rotate_z_agrees_with_the_recurrence() {
    let mut rng = rng(0x5eed_0007);
    let lmax = 20;
    let mut angles = vec![0.0, FRAC_PI_2, PI, -PI / 3.0, 2.0 * PI, 10.0];
    angles.extend((0..10).map(|_| rng.random_range(-PI..PI)));
    for angle in angles {
        let f = random_coeffs(&mut rng, lmax);
        let fast = rotate_z(&f, angle);
        let rot = ShRotation::from_mat3(lmax, DMat3::from_rotation_z(angle));
        let slow = rot.apply(&f);
        assert_close(
            fast.as_slice(),
            slow.as_slice(),
            ROTATE_Z_TOL * lmax as f64,
            &format!("angle {angle}"),
        );
        // RGB takes the same path channel by channel.
        let rgb = ShCoeffs::from_channels(&f, &f.scaled(-2.0), &f);
        let fast_rgb = rotate_z(&rgb, angle);
        assert_eq!(fast_rgb.channel(0), fast);
        assert_eq!(fast_rgb.channel(1), fast.scaled(-2.0));
    }
    // Semantics: a quarter turn takes a light at +X to +Y.
    let got = rotate_z(&light(6, DVec3::X), FRAC_PI_2);
    assert_close(
        got.as_slice(),
        light(6, DVec3::Y).as_slice(),
        FRAME_TOL,
        "+X -> +Y",
    );
}

#[test]
fn frame_conversion_moves_a_light_at_plus_y_to_plus_z() {
    let lmax = 8;
    let to_zup = ShRotation::between_frames(lmax, Frame::YUp, Frame::ZUp);
    // The same texel read in both frames: +Y (top row) in y-up is +Z in z-up,
    // +Z (t = 90, p = 90) in y-up is -Y in z-up, +X stays +X.
    for (yup, zup) in [
        (DVec3::Y, DVec3::Z),
        (DVec3::Z, DVec3::NEG_Y),
        (DVec3::X, DVec3::X),
        (DVec3::NEG_Y, DVec3::NEG_Z),
    ] {
        let got = to_zup.apply(&light(lmax, yup));
        assert_close(
            got.as_slice(),
            light(lmax, zup).as_slice(),
            FRAME_TOL,
            &format!("{yup} (y-up) -> {zup} (z-up)"),
        );
    }
    // The example is what the two direction formulas say.
    let (t, p) = (FRAC_PI_2, FRAC_PI_2);
    assert!((Frame::YUp.direction(t, p) - DVec3::Z).length() < 1e-15);
    assert!((Frame::ZUp.direction(t, p) - DVec3::NEG_Y).length() < 1e-15);
    assert!((Frame::YUp.direction(0.0, 1.0) - DVec3::Y).length() < 1e-15);
    assert!((Frame::ZUp.direction(0.0, 1.0) - DVec3::Z).length() < 1e-15);
}

#[test]
fn frame_conversion_preserves_every_texel() {
    // A map read as f_yup in y-up and converted must give, at every texel
    // (t, p), the same value in z-up: f_zup(ZUp.direction) = f_yup(YUp.direction).
    let mut rng = rng(0x5eed_0008);
    let lmax = 6;
    let f_yup = random_coeffs(&mut rng, lmax);
    let f_zup = ShRotation::between_frames(lmax, Frame::YUp, Frame::ZUp).apply(&f_yup);
    let back = ShRotation::between_frames(lmax, Frame::ZUp, Frame::YUp).apply(&f_zup);
    assert_close(back.as_slice(), f_yup.as_slice(), FRAME_TOL, "z-up -> y-up");
    for _ in 0..50 {
        let t = rng.random_range(0.0..PI);
        let p = rng.random_range(0.0..2.0 * PI);
        let a = f_yup.eval(Frame::YUp.direction(t, p));
        let b = f_zup.eval(Frame::ZUp.direction(t, p));
        assert!((a - b).abs() < 1e-12, "texel ({t}, {p}): {a} vs {b}");
    }
}

#[test]
fn y_up_to_z_up_to_y_up_is_the_identity() {
    let lmax = 12;
    let there = ShRotation::between_frames(lmax, Frame::YUp, Frame::ZUp);
    let back = ShRotation::between_frames(lmax, Frame::ZUp, Frame::YUp);
    assert!(block_diff(&(&back * &there), &ShRotation::identity(lmax)) < FRAME_TOL);
    assert!(block_diff(&back, &there.inverse()) < FRAME_TOL);
    for frame in [Frame::YUp, Frame::ZUp] {
        assert_eq!(
            ShRotation::between_frames(lmax, frame, frame),
            ShRotation::identity(lmax)
        );
    }
    // The matrices themselves.
    let m = Frame::YUp.rotation_to(Frame::ZUp);
    assert_eq!(m * DVec3::new(1.0, 2.0, 3.0), DVec3::new(1.0, -3.0, 2.0));
    assert_eq!(Frame::ZUp.rotation_to(Frame::YUp) * m, DMat3::IDENTITY);
}

#[test]
fn frame_parses_and_displays() {
    for (s, f) in [("y-up", Frame::YUp), ("z-up", Frame::ZUp)] {
        assert_eq!(s.parse::<Frame>().unwrap(), f);
        assert_eq!(f.to_string(), s);
    }
    assert_eq!("Z-UP".parse::<Frame>().unwrap(), Frame::ZUp);
    let err = "x-up".parse::<Frame>().unwrap_err();
    assert!(err.to_string().contains("x-up"), "{err}");
}

#[test]
fn quarter_and_half_turns_about_each_axis_are_exact() {
    // Exactly 90, 180, 270 and -90 degrees: entries exactly 0 and +-1, where a
    // recurrence that divides by e.g. sin(beta) would produce NaN or Inf.
    let mut rng = rng(0x5eed_0009);
    let lmax = 16;
    for axis in 0..3 {
        let unit = [DVec3::X, DVec3::Y, DVec3::Z][axis];
        for quarter_turns in [1, 2, 3, -1] {
            let exact = exact_axis_rotation(axis, quarter_turns);
            let glam = DMat3::from_axis_angle(unit, quarter_turns as f64 * FRAC_PI_2);
            assert!(
                (exact - glam)
                    .abs()
                    .to_cols_array()
                    .iter()
                    .all(|e| *e < 1e-15)
            );
            for r in [exact, glam] {
                let rot = ShRotation::from_mat3(lmax, r);
                for l in 0..=lmax {
                    assert!(rot.block(l).iter().all(|v| v.is_finite()));
                    let e = orthogonality_error(&rot, l);
                    assert!(
                        e < ORTHOGONALITY_TOL,
                        "axis {axis} x{quarter_turns}: l {l} {e:e}"
                    );
                }
                let mut dirs = vec![DVec3::X, DVec3::Y, DVec3::Z, DVec3::NEG_Z];
                dirs.extend((0..4).map(|_| random_direction(&mut rng)));
                for a in dirs {
                    let got = rot.apply(&light(lmax, a));
                    assert_close(
                        got.as_slice(),
                        light(lmax, r * a).as_slice(),
                        DIRECTIONAL_TOL,
                        &format!("axis {axis}, {quarter_turns} quarter turns, a = {a}"),
                    );
                }
            }
        }
    }
    // Half turns about axes off the coordinate axes (beta = 90 or 180 degrees
    // in zyz Euler angles, the usual singular cases).
    for axis in [
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(1.0, 1.0, 1.0),
        DVec3::new(0.0, 1.0, 1.0),
    ] {
        let r = DMat3::from_axis_angle(axis.normalize(), PI);
        let rot = ShRotation::from_mat3(lmax, r);
        let a = random_direction(&mut rng);
        let got = rot.apply(&light(lmax, a));
        assert_close(
            got.as_slice(),
            light(lmax, r * a).as_slice(),
            DIRECTIONAL_TOL,
            "half turn",
        );
    }
}

#[test]
fn quaternion_sign_and_scale_do_not_matter() {
    let mut rng = rng(0x5eed_000a);
    let lmax = 10;
    for _ in 0..10 {
        let q = DQuat::from_mat3(&random_rotation(&mut rng));
        let a = ShRotation::from_quat(lmax, q);
        let b = ShRotation::from_quat(lmax, -q);
        assert!(block_diff(&a, &b) < GROUP_TOL, "q and -q differ");
        let c = ShRotation::from_quat(lmax, q * 3.0);
        assert!(block_diff(&a, &c) < GROUP_TOL, "q and 3q differ");
        let m = ShRotation::from_mat3(lmax, DMat3::from_quat(q));
        assert!(block_diff(&a, &m) < GROUP_TOL, "from_quat != from_mat3");
    }
    // The half turn about Z as q = (0, 0, 1, 0) and its negative.
    let q = DQuat::from_xyzw(0.0, 0.0, 1.0, 0.0);
    let got = ShRotation::from_quat(4, -q).apply(&light(4, DVec3::X));
    assert_close(
        got.as_slice(),
        light(4, DVec3::NEG_X).as_slice(),
        DIRECTIONAL_TOL,
        "-q",
    );
}

#[test]
fn lower_lmax_input_uses_the_leading_blocks_and_in_place_agrees() {
    let mut rng = rng(0x5eed_000b);
    let r = random_rotation(&mut rng);
    let big = ShRotation::from_mat3(8, r);
    let small = ShRotation::from_mat3(3, r);
    let f = random_coeffs(&mut rng, 3);
    let got = big.apply(&f);
    assert_eq!(got.lmax(), 3);
    assert_eq!(got, small.apply(&f));
    let mut g = f.clone();
    big.apply_in_place(&mut g);
    assert_eq!(g, got);
    for l in 0..=3 {
        assert_eq!(big.block(l), small.block(l));
    }
    // lmax 0: the constant term never changes.
    let c = ShCoeffs::from_vec(vec![2.5]).unwrap();
    assert_eq!(ShRotation::from_mat3(0, r).apply(&c), c);
    assert_eq!(ShRotation::from_mat3(0, r).block(0), &[1.0]);
}

#[test]
#[should_panic(expected = "built to lmax 2")]
fn higher_lmax_input_panics() {
    let rot = ShRotation::from_mat3(2, DMat3::IDENTITY);
    let _ = rot.apply(&ShCoeffs::<f64>::zeros(3));
}

#[test]
fn try_from_mat3_rejects_non_rotations() {
    let r = DMat3::from_rotation_y(0.3);
    assert!(ShRotation::try_from_mat3(4, r).is_some());
    let reflection = DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0));
    let scaled = DMat3::IDENTITY * 2.0;
    let shear = DMat3::from_cols(DVec3::X, DVec3::new(0.1, 1.0, 0.0), DVec3::Z);
    let nan = DMat3::from_cols(DVec3::X, DVec3::new(f64::NAN, 1.0, 0.0), DVec3::Z);
    for bad in [reflection, -r, scaled, shear, nan] {
        assert!(
            ShRotation::try_from_mat3(4, bad).is_none(),
            "{bad:?} accepted"
        );
    }
}

#[test]
fn rotating_without_stored_blocks_equals_the_stored_rotation() {
    // lmax 70 crosses the degree from which block rows are built in parallel.
    let mut rng = rng(71);
    for lmax in [0, 1, 2, 9, 70] {
        let r = random_rotation(&mut rng);
        let f = random_coeffs(&mut rng, lmax);
        let want = ShRotation::from_mat3(lmax, r).apply(&f);
        let got = rotate_once(&f, r);
        assert_close(
            got.as_slice(),
            want.as_slice(),
            1e-13,
            &format!("lmax {lmax}"),
        );
    }
}

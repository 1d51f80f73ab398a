//! The fixed-size SH types on the runtime hot path: RGB lmax 2 irradiance
//! per direction in `f32` (`ShL2Rgb<f32>::eval_irradiance`) against the
//! general path measured in the same run (the irradiance `ShCoeffs<Vec3>`
//! evaluated with a prepared `ShBasis<f32>`), and the rotation of one RGB
//! lmax 2 probe (`ShL2Rgb::rotated`) against `ShRotation` built and applied.
//!
//! Each evaluation bench shades a batch of `N` normals; divide the median by
//! `N` for the time per direction (divan also prints items per second).
//!
//! Run: `cargo bench -p shlight-core --bench fixed_size`.

use divan::counter::ItemsCount;
use divan::{Bencher, black_box};
use glam::{DMat3, DVec3, Mat3, Vec3};
use shlight_core::sh::{ShBasis, ShCoeffs, ShL2Rgb, ShRotation, irradiance};

fn main() {
    divan::main();
}

/// Normals per batch: many enough to amortise the call, few enough for L1.
const N: usize = 4096;

fn normals() -> Vec<Vec3> {
    shlight_core::sh::fibonacci_sphere(N)
        .iter()
        .map(|d| d.as_vec3())
        .collect()
}

/// Some RGB radiance to lmax 2 (a sky-like gradient with colour).
fn radiance() -> ShCoeffs<DVec3> {
    ShCoeffs::from_fn(2, |l, m| {
        let t = (l * l) as f64 + m as f64 * 0.37;
        DVec3::new(1.0 / (1.0 + t), 0.8 / (1.0 + t * t), (0.3 * t).cos() * 0.5)
    })
}

/// `ShL2Rgb<f32>::eval_irradiance` (radiance in, the `A_l` applied inside).
#[divan::bench]
fn fixed_rgb_l2_eval_irradiance_f32(bencher: Bencher) {
    let sh = ShL2Rgb::<f32>::from_coeffs(&radiance().to_f32());
    let n = normals();
    let mut out = vec![Vec3::ZERO; N];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        let sh = black_box(&sh);
        for (o, d) in out.iter_mut().zip(black_box(&n)) {
            *o = sh.eval_irradiance(*d);
        }
        black_box(&mut out);
    });
}

/// `ShL2Rgb<f32>::eval` of irradiance coefficients converted once.
#[divan::bench]
fn fixed_rgb_l2_eval_f32_preconverted(bencher: Bencher) {
    let e = ShL2Rgb::<f32>::from_coeffs(&radiance().to_f32()).irradiance();
    let n = normals();
    let mut out = vec![Vec3::ZERO; N];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        let e = black_box(&e);
        for (o, d) in out.iter_mut().zip(black_box(&n)) {
            *o = e.eval(*d);
        }
        black_box(&mut out);
    });
}

/// Baseline, the general path: the irradiance `ShCoeffs<Vec3>` (from the
/// core's `irradiance`) evaluated per normal with a prepared `ShBasis<f32>`
/// and scratch buffer (`ShCoeffs::eval_with`).
#[divan::bench]
fn general_rgb_l2_eval_with_f32(bencher: Bencher) {
    let e = irradiance(&radiance()).to_f32();
    let basis = ShBasis::<f32>::new(2);
    let mut scratch = vec![0.0f32; basis.count()];
    let n = normals();
    let mut out = vec![Vec3::ZERO; N];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        let e = black_box(&e);
        for (o, d) in out.iter_mut().zip(black_box(&n)) {
            *o = e.eval_with(&basis, *d, &mut scratch);
        }
        black_box(&mut out);
    });
}

fn rotation() -> DMat3 {
    DMat3::from_euler(glam::EulerRot::ZYX, 0.3, -1.1, 2.0)
}

/// One RGB lmax 2 probe rotated by a matrix: blocks built and applied.
#[divan::bench]
fn fixed_rgb_l2_rotate_f32(bencher: Bencher) {
    let sh = ShL2Rgb::<f32>::from_coeffs(&radiance().to_f32());
    let r: Mat3 = rotation().as_mat3();
    bencher.bench_local(|| black_box(&sh).rotated(black_box(r)));
}

/// Baseline: `ShRotation::from_mat3(2, r)` then `apply` on `ShCoeffs<DVec3>`.
#[divan::bench]
fn general_rgb_l2_rotate_f64(bencher: Bencher) {
    let sh = radiance();
    let r = rotation();
    bencher.bench_local(|| ShRotation::from_mat3(2, black_box(r)).apply(black_box(&sh)));
}

//! Benchmarks of SH rotation: building the blocks ([`ShRotation::from_mat3`]),
//! applying them to RGB coefficients, and the cheap rotation about +Z
//! ([`rotate_z`]), at `lmax` 2, 8 and 32 (plus the build at 64 and 256).
//!
//! Run with `cargo bench -p shlight-core --bench rotation`.

use divan::{Bencher, black_box};
use glam::{DMat3, DQuat, DVec3};
use shlight_core::sh::{ShCoeffs, ShRotation, rotate_z};

fn main() {
    divan::main();
}

/// A generic rotation (no zero entries, nothing special about its axis).
fn rotation() -> DMat3 {
    DMat3::from_quat(DQuat::from_xyzw(0.3, -0.5, 0.2, 0.7).normalize())
}

/// RGB coefficients with distinct, non-trivial values.
fn rgb(lmax: usize) -> ShCoeffs<DVec3> {
    ShCoeffs::from_fn(lmax, |l, m| {
        let x = l as f64 + 0.1 * m as f64;
        DVec3::new(x.sin(), x.cos(), 1.0 / (1.0 + x * x))
    })
}

/// Building every block to `lmax` from a rotation matrix.
#[divan::bench(args = [2, 8, 32])]
fn build(lmax: usize) -> ShRotation {
    ShRotation::from_mat3(black_box(lmax), black_box(rotation()))
}

/// Building at high degree (180 MB of blocks at 256).
#[divan::bench(args = [64, 256], sample_count = 10, sample_size = 1)]
fn build_large(lmax: usize) -> ShRotation {
    ShRotation::from_mat3(black_box(lmax), black_box(rotation()))
}

/// Applying prepared blocks to RGB coefficients (allocates the result).
#[divan::bench(args = [2, 8, 32])]
fn apply_rgb(bencher: Bencher, lmax: usize) {
    let rot = ShRotation::from_mat3(lmax, rotation());
    let f = rgb(lmax);
    bencher.bench_local(|| black_box(&rot).apply(black_box(&f)));
}

/// Applying prepared blocks to RGB coefficients in place.
#[divan::bench(args = [2, 8, 32])]
fn apply_rgb_in_place(bencher: Bencher, lmax: usize) {
    let rot = ShRotation::from_mat3(lmax, rotation());
    let mut f = rgb(lmax);
    bencher.bench_local(|| black_box(&rot).apply_in_place(black_box(&mut f)));
}

/// Rotation of RGB coefficients about +Z, `O(lmax^2)`.
#[divan::bench(args = [2, 8, 32])]
fn rotate_z_rgb(bencher: Bencher, lmax: usize) {
    let f = rgb(lmax);
    bencher.bench_local(|| rotate_z(black_box(&f), black_box(0.7)));
}

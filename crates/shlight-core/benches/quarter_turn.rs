//! Benchmarks of the quarter turn about X ([`quarter_turn_x`]), the y-up /
//! z-up switch of every y-up projection, on RGB coefficients at `lmax` 32,
//! 128 and 512, beside a general rotation ([`rotate_once`]: blocks built by
//! recurrence, then applied) at 32 and 128 as the baseline.
//!
//! Run with `cargo bench -p shlight-core --bench quarter_turn`.

use divan::black_box;
use glam::{DMat3, DVec3};
use shlight_core::sh::{ShCoeffs, quarter_turn_x, rotate_once};

fn main() {
    divan::main();
}

/// RGB coefficients with distinct, non-trivial values.
fn rgb(lmax: usize) -> ShCoeffs<DVec3> {
    ShCoeffs::from_fn(lmax, |l, m| {
        let x = l as f64 + 0.1 * m as f64;
        DVec3::new(x.sin(), x.cos(), 1.0 / (1.0 + x * x))
    })
}

/// `Rx(-π/2)`, y-up to z-up's inverse: what a y-up projection applies.
#[divan::bench(args = [32, 128, 512], sample_count = 20)]
fn quarter_turn(bencher: divan::Bencher, lmax: usize) {
    let f = rgb(lmax);
    bencher.bench_local(|| quarter_turn_x(black_box(&f), -1));
}

/// The same rotation through the general route (build and apply).
#[divan::bench(args = [32, 128], sample_count = 10)]
fn general_rotation(bencher: divan::Bencher, lmax: usize) {
    let f = rgb(lmax);
    let r = DMat3::from_cols(DVec3::X, DVec3::NEG_Z, DVec3::Y);
    bencher.bench_local(|| rotate_once(black_box(&f), r));
}

//! SH evaluation throughput: directions per second for the f32 batch path and
//! the f64 one-direction path, at lmax 2, 4, 8, 16, 64, and batch
//! reconstruction at lmax 2 against a same-run baseline that evaluates like
//! google/spherical-harmonics' `EvalSHSum` (one dispatched call per
//! coefficient, each a hard-coded polynomial, after a unit-length check).
//!
//! Run: `cargo bench -p shlight-core --bench eval`.

use divan::counter::ItemsCount;
use divan::{Bencher, black_box};
use shlight_core::sh::ShBasis;

fn main() {
    divan::main();
}

/// Directions per batch: large enough to amortise the call, small enough for L1/L2.
const N: usize = 4096;

fn directions() -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    let d = shlight_core::sh::fibonacci_sphere(N);
    (
        d.iter().map(|v| v[0] as f32).collect(),
        d.iter().map(|v| v[1] as f32).collect(),
        d.iter().map(|v| v[2] as f32).collect(),
    )
}

#[divan::bench(args = [2, 4, 8, 16, 64])]
fn batch_f32(bencher: Bencher, lmax: usize) {
    let basis = ShBasis::<f32>::new(lmax);
    let (x, y, z) = directions();
    let mut out = vec![0.0f32; basis.count() * N];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        basis.eval_batch(
            black_box(&x),
            black_box(&y),
            black_box(&z),
            black_box(&mut out),
        )
    });
}

#[divan::bench(args = [2, 4, 8, 16, 64])]
fn single_f64(bencher: Bencher, lmax: usize) {
    let basis = ShBasis::<f64>::new(lmax);
    let d = shlight_core::sh::fibonacci_sphere(N);
    let mut out = vec![0.0f64; basis.count()];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        for v in &d {
            basis.eval(black_box(*v), black_box(&mut out));
        }
    });
}

#[divan::bench]
fn sum_batch_f32_lmax2(bencher: Bencher) {
    let basis = ShBasis::<f32>::new(2);
    let coeffs: Vec<f32> = (0..9).map(|i| 0.1 * i as f32 - 0.3).collect();
    let (x, y, z) = directions();
    let mut out = vec![0.0f32; N];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        basis.eval_sum_batch(
            black_box(&coeffs),
            black_box(&x),
            black_box(&y),
            black_box(&z),
            black_box(&mut out),
        )
    });
}

/// Baseline: `EvalSHSum(2, coeffs, dir)` as google/spherical-harmonics writes
/// it (double precision, a switch per coefficient).
#[divan::bench]
fn baseline_google_style_sum_lmax2(bencher: Bencher) {
    let coeffs: Vec<f64> = (0..9).map(|i| 0.1 * i as f64 - 0.3).collect();
    let d = shlight_core::sh::fibonacci_sphere(N);
    let mut out = vec![0.0f64; N];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        for (o, v) in out.iter_mut().zip(&d) {
            *o = google_style::eval_sh_sum(2, black_box(&coeffs), black_box(v.to_array()));
        }
        black_box(&mut out);
    });
}

mod google_style {
    fn eval_sh(l: i32, m: i32, d: [f64; 3]) -> f64 {
        let [x, y, z] = d;
        match (l, m) {
            (0, 0) => 0.282095,
            (1, -1) => -0.488603 * y,
            (1, 0) => 0.488603 * z,
            (1, 1) => -0.488603 * x,
            (2, -2) => 1.092548 * x * y,
            (2, -1) => -1.092548 * y * z,
            (2, 0) => 0.315392 * (-x * x - y * y + 2.0 * z * z),
            (2, 1) => -1.092548 * x * z,
            (2, 2) => 0.546274 * (x * x - y * y),
            _ => panic!("unsupported"),
        }
    }

    pub fn eval_sh_sum(order: i32, coeffs: &[f64], d: [f64; 3]) -> f64 {
        let n2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        assert!((n2 - 1.0).abs() < 1e-9, "dir is not unit");
        let mut sum = 0.0;
        for l in 0..=order {
            for m in -l..=l {
                sum += eval_sh(l, m, d) * coeffs[(l * (l + 1) + m) as usize];
            }
        }
        sum
    }
}

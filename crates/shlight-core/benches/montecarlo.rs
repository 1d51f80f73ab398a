//! Monte Carlo projection throughput: directions per second for each
//! sampler at lmax 2 and 8 on a cheap analytic map (a sky gradient plus a
//! sun), so the cost measured is sampling, SH evaluation and accumulation.
//!
//! Run: `cargo bench -p shlight-core --bench montecarlo`.

use divan::counter::ItemsCount;
use divan::{Bencher, black_box};
use glam::DVec3;
use shlight_core::map::MapOrientation;
use shlight_core::map::montecarlo::{ImportanceGrid, McOptions, Sampler, project_montecarlo};

fn main() {
    divan::main();
}

const N: usize = 1 << 16;

fn sky(d: DVec3) -> DVec3 {
    let sun = DVec3::new(0.3, 0.8, 0.52).normalize();
    let s = if d.dot(sun) > 0.995 { 500.0 } else { 0.0 };
    DVec3::new(0.4, 0.6, 1.0) * (1.0 + 0.5 * d.y) + DVec3::splat(s)
}

fn bench(bencher: Bencher, sampler: Sampler, lmax: usize) {
    let o = McOptions {
        lmax,
        samples: N,
        sampler,
        ..McOptions::default()
    };
    bencher
        .counter(ItemsCount::new(N))
        .bench(|| project_montecarlo(&sky, black_box(&o)));
}

#[divan::bench(args = [2, 8])]
fn uniform(bencher: Bencher, lmax: usize) {
    bench(bencher, Sampler::Uniform, lmax);
}

#[divan::bench(args = [2, 8])]
fn stratified(bencher: Bencher, lmax: usize) {
    bench(bencher, Sampler::Stratified, lmax);
}

#[divan::bench(args = [2, 8])]
fn sobol(bencher: Bencher, lmax: usize) {
    bench(bencher, Sampler::Sobol, lmax);
}

#[divan::bench(args = [2, 8])]
fn importance(bencher: Bencher, lmax: usize) {
    let grid = ImportanceGrid::from_map(&sky, 256, 128, MapOrientation::default());
    bench(bencher, Sampler::Importance(grid), lmax);
}

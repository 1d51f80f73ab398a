//! Benchmarks of equirect projection on a generated 2048x1024 float RGB map
//! (2.1 M texels, 25 MB), projection alone (no decoding):
//!
//! - `zup`: [`project_equirect`] in the map's own frame (z-up), as ducc0's
//!   `adjoint_synthesis_2d` and SHTOOLS compute it, at lmax 2 to 512;
//! - `yup`: the default y-up frame, which adds the rotation of the result;
//! - `simple`: the baseline in the same run, [`project_equirect_simple`]
//!   (direct per-row sums, no pairing, FFT or vector code).
//!
//! Run with `cargo bench -p shlight-core --bench projection`; both cores are
//! used (rayon). Peers on the same map: `benches/peers.sh`.

use divan::{Bencher, black_box};
use shlight_core::map::{EquirectView, MapOrientation, project_equirect, project_equirect_simple};
use shlight_core::sh::Frame;

fn main() {
    divan::main();
}

const W: usize = 2048;
const H: usize = 1024;

/// A smooth sky with a sun and texel noise: every coefficient is non-zero.
fn map() -> Vec<[f32; 3]> {
    (0..W * H)
        .map(|i| {
            let (x, y) = ((i % W) as f32 / W as f32, (i / W) as f32 / H as f32);
            let sun = if (x - 0.3).abs() < 0.01 && (y - 0.2).abs() < 0.02 {
                5e3
            } else {
                0.0
            };
            let n = ((i * 7919) % 101) as f32 * 1e-3;
            [1.0 - y + sun + n, 0.8 - 0.5 * y + sun, 0.6 + 0.3 * x + sun]
        })
        .collect()
}

fn run(bencher: Bencher, lmax: usize, frame: Frame, simple: bool) {
    let px = map();
    let view = EquirectView {
        width: W,
        height: H,
        pixels: &px,
    };
    let o = MapOrientation {
        frame,
        mirror: false,
    };
    bencher.bench(|| {
        if simple {
            project_equirect_simple(black_box(view), lmax, o)
        } else {
            project_equirect(black_box(view), lmax, o)
        }
    });
}

/// The fast path about the map's pole (no rotation).
#[divan::bench(args = [2, 8, 32, 128, 512], sample_count = 20, sample_size = 1)]
fn zup(bencher: Bencher, lmax: usize) {
    run(bencher, lmax, Frame::ZUp, false);
}

/// The fast path in the default y-up frame (adds the rotation).
#[divan::bench(args = [2, 8, 32, 128, 512], sample_count = 20, sample_size = 1)]
fn yup(bencher: Bencher, lmax: usize) {
    run(bencher, lmax, Frame::YUp, false);
}

/// Baseline: the simple route, same map, same run.
#[divan::bench(args = [2, 8, 32], sample_count = 10, sample_size = 1)]
fn simple(bencher: Bencher, lmax: usize) {
    run(bencher, lmax, Frame::ZUp, true);
}

//! Baking speed: shadowed transfer of a 69,696-triangle torus (34,848
//! vertices) at lmax 4 with 1024 directions per vertex, and interreflected
//! with 2 bounces, on both cores. divan's "items/s" is rays cast per second
//! (directions above each vertex's tangent plane); compare the two modes'
//! times for the cost of the bounces.
//!
//! The glossy benchmarks bake the same torus's transfer matrices.
//!
//! `cargo bench -p shlight-prt --bench transfer`

use divan::Bencher;
use divan::counter::ItemsCount;
use shlight_mesh::generate;
use shlight_prt::{BakeOptions, Mode, bake};

fn main() {
    divan::main();
}

const MODES: &[&str] = &["shadowed", "interreflected-2"];

#[divan::bench(args = MODES, sample_count = 2, sample_size = 1)]
fn torus70k_lmax4_1024(bencher: Bencher, mode: &str) {
    let mesh = generate::torus(1.0, 0.4, 264, 132);
    let options = BakeOptions {
        lmax: 4,
        samples: 1024,
        mode: match mode {
            "shadowed" => Mode::Shadowed,
            _ => Mode::Interreflected { bounces: 2 },
        },
        ..BakeOptions::default()
    };
    // Rays cast depend on the geometry and directions only: count them once.
    let probe = bake(
        &mesh,
        &BakeOptions {
            mode: Mode::Shadowed,
            ..options.clone()
        },
        &|_, _, _| {},
    );
    bencher
        .counter(ItemsCount::new(probe.rays))
        .bench(|| bake(&mesh, &options, &|_, _, _| {}));
}

/// Glossy transfer matrices of the same torus at lmax 4 with 1024
/// directions: shadowed, and with one diffuse bounce.
#[divan::bench(args = ["shadowed", "interreflected-1"], sample_count = 2, sample_size = 1)]
fn glossy_torus70k_lmax4_1024(bencher: Bencher, mode: &str) {
    let mesh = generate::torus(1.0, 0.4, 264, 132);
    let options = BakeOptions {
        lmax: 4,
        samples: 1024,
        mode: match mode {
            "shadowed" => Mode::Shadowed,
            _ => Mode::Interreflected { bounces: 1 },
        },
        ..BakeOptions::default()
    };
    bencher.bench(|| shlight_prt::bake_glossy(&mesh, &options, &|_, _, _| {}));
}

//! Times the projection step of `shlight project` on one map, in Rust
//! alone: the baseline of the Python package's overhead
//! (benches/python_peers.py runs it on the map it gives Python).
//!
//! `cargo run --release -p shlight-pipeline --example time_projection -- MAP.exr LMAX RUNS`
//! prints the median seconds of `project_with_warnings` on texels in memory over RUNS runs (the map
//! read once, as Python holds it in an array).

use std::path::Path;
use std::time::Instant;

use shlight_core::map::{EnvMap, Layout, MapOrientation};
use shlight_format::Quantity;
use shlight_io::{ReadOptions, read_image};
use shlight_pipeline::{Method, ProjectSettings, Settings, Source, project_with_warnings};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, path, lmax, runs] = args.as_slice() else {
        eprintln!("usage: time_projection MAP LMAX RUNS");
        std::process::exit(2);
    };
    let image = read_image(Path::new(path), &ReadOptions::default()).expect("a readable map");
    let lmax: usize = lmax.parse().expect("LMAX");
    let runs: usize = runs.parse().expect("RUNS");
    let s = Settings::new(ProjectSettings::new(
        lmax,
        MapOrientation::default(),
        Method::Quadrature,
        Quantity::Radiance,
    ));
    let map = EnvMap::new(
        Layout::Equirect,
        s.project.orientation,
        image.width(),
        image.height(),
        image.pixels(),
    )
    .expect("a 2:1 map");
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            let source = Source::Texels {
                texels: &map,
                name: "map",
                layout_name: "equirect",
            };
            let (file, _) = project_with_warnings(source, &s).expect("projects");
            std::hint::black_box(file);
            t.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    println!("{}", times[times.len() / 2]);
}

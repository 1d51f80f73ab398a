//! Prefiltering speed: a 2048x1024 equirect map (a smooth sky with a small
//! sun) to a 256-pixel Filament cube with its 5 mips at cmgen's 1024
//! samples, and to a 64-pixel cube.

use shlight_core::map::{EnvMap, Layout, MapOrientation, equirect_direction};
use shlight_specular::{PrefilterSettings, TargetEngine, prefilter};

fn main() {
    divan::main();
}

fn sky(w: usize, h: usize) -> Vec<[f32; 3]> {
    let sun = glam::DVec3::new(0.3, 0.8, 0.2).normalize();
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let d = equirect_direction(x, y, w, h, MapOrientation::default());
            let s = if d.dot(sun) > 0.9995 { 5000.0 } else { 0.0 };
            [
                (0.3 + 0.5 * d.y.max(0.0) + s) as f32,
                (0.4 + s) as f32,
                (0.6 + s) as f32,
            ]
        })
        .collect()
}

#[divan::bench(args = [64, 256], sample_count = 3)]
fn filament_cube(bencher: divan::Bencher, size: usize) {
    let (w, h) = (2048, 1024);
    let pixels = sky(w, h);
    let map = EnvMap::new(Layout::Equirect, MapOrientation::default(), w, h, &pixels).unwrap();
    let settings = PrefilterSettings {
        size,
        ..PrefilterSettings::new(TargetEngine::Filament)
    };
    bencher.bench(|| prefilter(&map, &settings, &|_| {}).unwrap());
}

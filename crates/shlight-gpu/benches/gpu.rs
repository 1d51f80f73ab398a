//! GPU frame time and GPU projection, beside the CPU projection of the same
//! map in the same run.
//!
//! - `frame_1080p`: one 1920x1080 frame (submit and wait) of a generated
//!   sphere of 99,500 triangles (250 segments x 200 rings) shaded per
//!   fragment at lmax 2 and 8, no background;
//! - `project_gpu` / `project_cpu`: a 2048x1024 equirect map to lmax 8
//!   (GPU: upload, both passes and read-back; CPU: shlight-core's
//!   `project_equirect`, both cores).
//!
//! Run: `cargo bench -p shlight-gpu --bench gpu`. Without a GPU adapter the
//! GPU benchmarks print a SKIPPED line and measure nothing.

use std::sync::OnceLock;

use glam::Vec3;
use shlight_core::analytic;
use shlight_core::projection::{EquirectView, MapOrientation, project_equirect};
use shlight_gpu::{
    Camera, GpuContext, GpuProjector, HEADLESS_FORMAT, Offscreen, Renderer, Shading,
};

fn main() {
    divan::main();
}

fn context() -> Option<&'static GpuContext> {
    static CTX: OnceLock<Option<GpuContext>> = OnceLock::new();
    CTX.get_or_init(|| match GpuContext::headless() {
        Ok(ctx) => {
            eprintln!("adapter: {}", ctx.adapter_name());
            Some(ctx)
        }
        Err(e) => {
            eprintln!("SKIPPED GPU benchmarks: {e}");
            None
        }
    })
    .as_ref()
}

/// A 2048x1024 map with smooth variation and a bright spot.
fn map() -> Vec<[f32; 3]> {
    let (w, h) = (2048, 1024);
    (0..w * h)
        .map(|k| {
            let (x, y) = ((k % w) as f32 / w as f32, (k / w) as f32 / h as f32);
            let spot = if (x - 0.3).abs() < 0.01 && (y - 0.3).abs() < 0.02 {
                50.0
            } else {
                0.0
            };
            [1.0 + x + spot, 0.5 + y, 0.2 + x * y]
        })
        .collect()
}

#[divan::bench(args = [2, 8], sample_count = 20, sample_size = 1)]
fn frame_1080p(bencher: divan::Bencher, lmax: usize) {
    let Some(ctx) = context() else { return };
    let mesh = shlight_mesh::generate::uv_sphere(1.0, 250, 200);
    let mut renderer = Renderer::new(ctx, HEADLESS_FORMAT);
    renderer.set_mesh(ctx, &mesh);
    renderer.set_light(
        ctx,
        &analytic::cap(8, [0.3, 0.8, 0.5], 0.5, glam::DVec3::new(5.0, 3.0, 2.0)),
    );
    let target = Offscreen::new(ctx, 1920, 1080).unwrap();
    let camera = Camera::framing(mesh.bounds(), Vec3::Z, 0.6, target.aspect());
    let shading = Shading {
        lmax,
        ..Default::default()
    };
    target.draw(ctx, &renderer, &camera, &shading).unwrap();
    bencher.bench_local(|| target.draw(ctx, &renderer, &camera, &shading).unwrap());
}

#[divan::bench(sample_count = 10, sample_size = 1)]
fn project_gpu(bencher: divan::Bencher) {
    let Some(ctx) = context() else { return };
    let pixels = map();
    let view = EquirectView {
        width: 2048,
        height: 1024,
        pixels: &pixels,
    };
    let projector = GpuProjector::new(ctx);
    bencher.bench_local(|| {
        projector
            .project(ctx, view, 8, MapOrientation::default())
            .unwrap()
    });
}

#[divan::bench(sample_count = 20, sample_size = 1)]
fn project_cpu(bencher: divan::Bencher) {
    let pixels = map();
    let view = EquirectView {
        width: 2048,
        height: 1024,
        pixels: &pixels,
    };
    bencher.bench_local(|| project_equirect(view, 8, MapOrientation::default()));
}

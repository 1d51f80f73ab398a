//! GPU frame time and GPU projection, beside the CPU projection of the same
//! map in the same run.
//!
//! Frames are 1920x1080, drawn and waited for (no read-back unless named),
//! lit by an lmax 8 light (a coloured cap), no background:
//!
//! - `frame_sphere_sh` / `frame_bunny_sh`: SH irradiance per fragment at
//!   lmax 2 and 8, for a generated sphere of 99,500 triangles (250 segments
//!   x 200 rings) and the bundled bunny (`meshes/bunny.obj`, 3,674
//!   triangles), each framed by `Camera::framing` (its bounding sphere
//!   just fits the image's height);
//! - `frame_bunny_prt`: PRT of the bunny, 3-channel transfer vectors of
//!   lmax 2 and 8 (pseudo-random values: the frame time does not depend on
//!   them), the light's lmax the same;
//! - `frame_sphere_prt` / `frame_sphere_glossy`: a generated sphere of
//!   99,851 vertices (400 segments x 250 rings) shaded per vertex by
//!   3-channel diffuse transfer vectors, and by glossy transfer compressed
//!   as CPCA with 64 clusters of 8 basis vectors (one channel,
//!   pseudo-random values, a diffuse base under the glossy layer), both at
//!   lmax 2 and 4 (the light's lmax the same), the light unchanged between
//!   frames (the transferred radiance computed before the first);
//! - `frame_sphere_glossy_turning`: the glossy frame at lmax 4 with the
//!   light changed before each frame (two lights in turn), so the CPU's
//!   per-cluster `M L` and its upload are in the time;
//! - `frame_sphere_glossy_full_turning`: the same with the glossy
//!   transfer uncompressed (a matrix per vertex, 99,851 of them: 32 MB at
//!   lmax 2, 250 MB at lmax 4), the light changed before each frame, so
//!   each frame pays every vertex's `M L` on the CPU;
//! - `frame_sphere_ggx_turning`: the same uncompressed transfer shaded
//!   with `ggx:0.3` at lmax 2 and 4 (`GlossyLobe::Directions`: each
//!   vertex's transferred radiance evaluated band by band at `lmax + 1`
//!   directions and weighted from the BRDF's table), the light changed
//!   before each frame;
//! - `frame_bunny_volume`: the bunny lit per fragment by an irradiance
//!   volume (`VolumeRenderer`) at lmax 2 and 4: a 16x8x16 grid (2,048
//!   probes, pseudo-random radiance, every tenth probe invalid) over the
//!   bunny's bounding box, the eight probes around each fragment
//!   interpolated the adapter's best way (`VolumeFetch::best`: on lavapipe
//!   the sampler's trilinear filter, 7 samples at lmax 2 and 14 at lmax 4,
//!   degree 3 left out);
//!   the same mesh, camera and size as `frame_bunny_sh` at the same lmax,
//!   which is its baseline (the target: within 1.5x);
//! - `frame_bunny_volume_loads`: the same with `VolumeFetch::Loads`, the
//!   path of hardware GPUs and of adapters that cannot filter `Rgba32Float` (eight
//!   `textureLoad`s per texel, weighted in the shader);
//! - `frame_bunny_volume_visibility`: the same volume with 16x16 distance
//!   maps per probe (as a default bake stores them) and probe offsets: the
//!   eight loads per texel weighted by each probe's visibility of the
//!   fragment (per probe its position and four texels of its map, from
//!   storage buffers). The maps say every probe sees past every point (as
//!   in open space), so the picture is the loads' one; llvmpipe runs every
//!   instruction whatever the values, so the time is that of any maps;
//! - `frame_sphere_normals`: the sphere in normals mode, the floor every
//!   frame pays for (vertex work, rasterisation, depth, a trivial fragment);
//! - `frame_sphere_readback`: `frame_sphere_sh` at lmax 2 with the frame
//!   read back to the CPU (`Offscreen::render`), so the read-back's share
//!   is the difference;
//! - `project_gpu` / `project_cpu`: a 2048x1024 equirect map to lmax 8
//!   (GPU: tables, upload, both passes and read-back, also at lmax 0 and 2,
//!   lmax 0 being the floor of texel loads; CPU: shlight-core's
//!   `project_equirect`, both cores).
//!
//! Run: `cargo bench -p shlight-gpu --bench gpu` (or name one, e.g.
//! `-- frame_bunny`). Without a GPU adapter the GPU benchmarks print a
//! SKIPPED line and measure nothing.

use std::sync::OnceLock;

use glam::Vec3;
use shlight_baked::{GlossyMatrices, GlossyView, ProbeGrid, TransferView, Visibility, VolumeView};
use shlight_core::map::{EquirectView, MapOrientation, project_equirect};
use shlight_core::sh::closed_form;
use shlight_gpu::{
    Camera, GlossyLobe, GpuContext, GpuProjector, HEADLESS_FORMAT, Mode, Offscreen, Renderer,
    Shading, VolumeFetch, VolumeInstance, VolumeRenderer,
};
use shlight_mesh::Mesh;

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

fn sphere() -> Mesh {
    shlight_mesh::generate::uv_sphere(1.0, 250, 200)
}

fn bunny() -> Mesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/bunny.obj");
    shlight_mesh::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// `count` values in [-1, 1) from a fixed linear congruential sequence.
fn pseudo_random(count: usize) -> Vec<f32> {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    (0..count)
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        })
        .collect()
}

/// Times `Offscreen::draw` (or `render` with `readback`) of `mesh` at
/// 1920x1080 under `shading`, with PRT transfer vectors of `prt_lmax`.
fn bench_frame(
    bencher: divan::Bencher,
    mesh: &Mesh,
    shading: Shading,
    prt_lmax: Option<usize>,
    readback: bool,
) {
    let Some(ctx) = context() else { return };
    let mut renderer = Renderer::new(ctx, HEADLESS_FORMAT);
    renderer.set_mesh(ctx, mesh);
    renderer.set_light(
        ctx,
        &closed_form::cap(
            8,
            glam::DVec3::new(0.3, 0.8, 0.5),
            0.5,
            glam::DVec3::new(5.0, 3.0, 2.0),
        ),
    );
    if let Some(lmax) = prt_lmax {
        let data = pseudo_random(mesh.vertex_count() * 3 * (lmax + 1) * (lmax + 1));
        let transfer = TransferView::new(lmax, 3, mesh.vertex_count(), &data).unwrap();
        renderer.set_transfer(ctx, &transfer).unwrap();
    }
    let target = Offscreen::new(ctx, 1920, 1080).unwrap();
    let camera = Camera::framing(mesh.bounds(), Vec3::Z, 0.6, target.aspect());
    // The first frame builds the pipelines for this lmax (shader compilation).
    target.draw(ctx, &renderer, &camera, &shading).unwrap();
    if readback {
        bencher.bench_local(|| target.render(ctx, &renderer, &camera, &shading).unwrap());
    } else {
        bencher.bench_local(|| target.draw(ctx, &renderer, &camera, &shading).unwrap());
    }
}

fn sh(lmax: usize) -> Shading {
    Shading {
        lmax,
        ..Default::default()
    }
}

#[divan::bench(args = [2, 8], sample_count = 10, sample_size = 1)]
fn frame_sphere_sh(bencher: divan::Bencher, lmax: usize) {
    bench_frame(bencher, &sphere(), sh(lmax), None, false);
}

#[divan::bench(args = [2, 4, 8], sample_count = 10, sample_size = 1)]
fn frame_bunny_sh(bencher: divan::Bencher, lmax: usize) {
    bench_frame(bencher, &bunny(), sh(lmax), None, false);
}

#[divan::bench(args = [2, 8], sample_count = 10, sample_size = 1)]
fn frame_bunny_prt(bencher: divan::Bencher, lmax: usize) {
    let shading = Shading {
        mode: Mode::Prt,
        ..sh(lmax)
    };
    bench_frame(bencher, &bunny(), shading, Some(lmax), false);
}

/// The sphere of `frame_sphere_prt` and `frame_sphere_glossy`: 99,851
/// vertices.
fn big_sphere() -> Mesh {
    shlight_mesh::generate::uv_sphere(1.0, 400, 250)
}

#[divan::bench(args = [2, 4], sample_count = 10, sample_size = 1)]
fn frame_sphere_prt(bencher: divan::Bencher, lmax: usize) {
    let shading = Shading {
        mode: Mode::Prt,
        ..sh(lmax)
    };
    bench_frame(bencher, &big_sphere(), shading, Some(lmax), false);
}

/// A renderer holding `mesh` with CPCA glossy transfer of `lmax` (64
/// clusters, 8 vectors, one channel, pseudo-random) and an lmax 8 light,
/// its first frame drawn (pipelines built, `M L` computed); the target
/// and camera.
fn glossy_scene(ctx: &GpuContext, mesh: &Mesh, lmax: usize) -> (Renderer, Offscreen, Camera) {
    let (clusters, vectors) = (64usize, 8usize);
    let n = (lmax + 1) * (lmax + 1);
    let dim = n * n;
    let v = mesh.vertex_count();
    let matrices = GlossyView::new(
        lmax,
        1,
        v,
        GlossyMatrices::Cpca {
            clusters,
            vectors,
            means: pseudo_random(clusters * dim).into(),
            bases: pseudo_random(clusters * vectors * dim).into(),
            cluster: (0..v as u32)
                .map(|i| i % clusters as u32)
                .collect::<Vec<_>>()
                .into(),
            weights: pseudo_random(v * vectors).into(),
        },
    )
    .unwrap();
    let mut renderer = Renderer::new(ctx, HEADLESS_FORMAT);
    renderer.set_mesh(ctx, mesh);
    renderer.set_light(ctx, &light(0.0));
    let lambda: Vec<f64> = (0..=lmax).map(|l| 0.9f64.powi(l as i32)).collect();
    renderer
        .set_glossy(ctx, &matrices, GlossyLobe::Zonal(&lambda))
        .unwrap();
    let target = Offscreen::new(ctx, 1920, 1080).unwrap();
    let camera = Camera::framing(mesh.bounds(), Vec3::Z, 0.6, target.aspect());
    target
        .draw(ctx, &renderer, &camera, &glossy_shading(lmax))
        .unwrap();
    (renderer, target, camera)
}

/// The benchmarks' lmax 8 light, its cap turned `yaw` radians about +Y.
fn light(yaw: f64) -> shlight_core::sh::ShCoeffs<glam::DVec3> {
    closed_form::cap(
        8,
        glam::DVec3::new(
            0.3 * yaw.cos() + 0.5 * yaw.sin(),
            0.8,
            0.5 * yaw.cos() - 0.3 * yaw.sin(),
        ),
        0.5,
        glam::DVec3::new(5.0, 3.0, 2.0),
    )
}

fn glossy_shading(lmax: usize) -> Shading {
    Shading {
        mode: Mode::Prt,
        albedo: [0.5; 3],
        ..sh(lmax)
    }
}

#[divan::bench(args = [2, 4], sample_count = 10, sample_size = 1)]
fn frame_sphere_glossy(bencher: divan::Bencher, lmax: usize) {
    let Some(ctx) = context() else { return };
    let (renderer, target, camera) = glossy_scene(ctx, &big_sphere(), lmax);
    let shading = glossy_shading(lmax);
    bencher.bench_local(|| target.draw(ctx, &renderer, &camera, &shading).unwrap());
}

#[divan::bench(sample_count = 10, sample_size = 1)]
fn frame_sphere_glossy_turning(bencher: divan::Bencher) {
    let Some(ctx) = context() else { return };
    let lmax = 4;
    let (mut renderer, target, camera) = glossy_scene(ctx, &big_sphere(), lmax);
    let shading = glossy_shading(lmax);
    let lights = [light(0.5), light(1.0)];
    let mut turn = 0;
    bencher.bench_local(|| {
        turn ^= 1;
        renderer.set_light(ctx, &lights[turn]);
        target.draw(ctx, &renderer, &camera, &shading).unwrap();
    });
}

/// Uncompressed glossy matrices of `lmax` for every vertex of `mesh`
/// (one channel, pseudo-random).
fn full_matrices(mesh: &Mesh, lmax: usize) -> GlossyView<'static> {
    let n = (lmax + 1) * (lmax + 1);
    let v = mesh.vertex_count();
    GlossyView::new(
        lmax,
        1,
        v,
        GlossyMatrices::Full(pseudo_random(v * n * n).into()),
    )
    .unwrap()
}

/// Frames of `renderer` (holding `mesh` and glossy transfer of `lmax`)
/// with the light changed before each (two lights in turn).
fn bench_turning(
    bencher: divan::Bencher,
    ctx: &GpuContext,
    renderer: &mut Renderer,
    mesh: &Mesh,
    lmax: usize,
) {
    let target = Offscreen::new(ctx, 1920, 1080).unwrap();
    let camera = Camera::framing(mesh.bounds(), Vec3::Z, 0.6, target.aspect());
    let shading = glossy_shading(lmax);
    let lights = [light(0.5), light(1.0)];
    let mut turn = 0;
    bencher.bench_local(|| {
        turn ^= 1;
        renderer.set_light(ctx, &lights[turn]);
        target.draw(ctx, renderer, &camera, &shading).unwrap();
    });
}

#[divan::bench(args = [2, 4], sample_count = 10, sample_size = 1)]
fn frame_sphere_glossy_full_turning(bencher: divan::Bencher, lmax: usize) {
    let Some(ctx) = context() else { return };
    let mesh = big_sphere();
    let mut renderer = Renderer::new(ctx, HEADLESS_FORMAT);
    renderer.set_mesh(ctx, &mesh);
    renderer.set_light(ctx, &light(0.0));
    let lambda: Vec<f64> = (0..=lmax).map(|l| 0.9f64.powi(l as i32)).collect();
    renderer
        .set_glossy(ctx, &full_matrices(&mesh, lmax), GlossyLobe::Zonal(&lambda))
        .unwrap();
    bench_turning(bencher, ctx, &mut renderer, &mesh, lmax);
}

#[divan::bench(args = [2, 4], sample_count = 10, sample_size = 1)]
fn frame_sphere_ggx_turning(bencher: divan::Bencher, lmax: usize) {
    use shlight_prt::{Brdf, BrdfLobe};
    let Some(ctx) = context() else { return };
    let mesh = big_sphere();
    let BrdfLobe::Ggx(lobe) = (Brdf::Ggx {
        alpha: 0.3,
        f0: 1.0,
    })
    .lobe(lmax) else {
        unreachable!("GGX is tabulated")
    };
    let mut renderer = Renderer::new(ctx, HEADLESS_FORMAT);
    renderer.set_mesh(ctx, &mesh);
    renderer.set_light(ctx, &light(0.0));
    renderer
        .set_glossy(
            ctx,
            &full_matrices(&mesh, lmax),
            GlossyLobe::Directions(&lobe.direction_table()),
        )
        .unwrap();
    bench_turning(bencher, ctx, &mut renderer, &mesh, lmax);
}

#[divan::bench(args = [2, 4], sample_count = 10, sample_size = 1)]
fn frame_bunny_volume(bencher: divan::Bencher, lmax: usize) {
    let Some(ctx) = context() else { return };
    bench_volume(bencher, ctx, lmax, VolumeFetch::best(ctx));
}

#[divan::bench(args = [2, 4], sample_count = 10, sample_size = 1)]
fn frame_bunny_volume_loads(bencher: divan::Bencher, lmax: usize) {
    let Some(ctx) = context() else { return };
    bench_volume(bencher, ctx, lmax, VolumeFetch::Loads);
}

#[divan::bench(args = [2, 4], sample_count = 10, sample_size = 1)]
fn frame_bunny_volume_visibility(bencher: divan::Bencher, lmax: usize) {
    let Some(ctx) = context() else { return };
    bench_volume_with(bencher, ctx, lmax, VolumeFetch::best(ctx), true);
}

/// `frame_bunny_volume` with the probes interpolated by `fetch`.
fn bench_volume(bencher: divan::Bencher, ctx: &GpuContext, lmax: usize, fetch: VolumeFetch) {
    bench_volume_with(bencher, ctx, lmax, fetch, false);
}

/// `frame_bunny_volume` with the probes interpolated by `fetch`, or with
/// `visibility` weighted by 16x16 distance maps (read by loads).
fn bench_volume_with(
    bencher: divan::Bencher,
    ctx: &GpuContext,
    lmax: usize,
    fetch: VolumeFetch,
    visibility: bool,
) {
    let mesh = bunny();
    let resolution = [16, 8, 16];
    let count = 16 * 8 * 16;
    let radiance: Vec<f32> = pseudo_random(count * (lmax + 1) * (lmax + 1) * 3)
        .into_iter()
        .map(|x| 1.0 + 0.5 * x)
        .collect();
    let valid: Vec<bool> = (0..count).map(|k| k % 10 != 0).collect();
    let (min, max) = mesh.bounds();
    let grid = ProbeGrid {
        resolution,
        min: min - 0.01,
        max: max + 0.01,
    };
    // Offsets of up to a tenth of a cell, and maps at the largest distance
    // (1.5 cell diagonals) in every direction.
    let cell = grid.cell();
    let offsets: Vec<f32> = pseudo_random(count * 3)
        .chunks_exact(3)
        .flat_map(|o| (Vec3::from_slice(o) * cell * 0.1).to_array())
        .collect();
    let size = shlight_baked::visibility::VISIBILITY_SIZE;
    let r = shlight_baked::visibility::max_distance(&grid);
    let moments: Vec<f32> = (0..count * size * size).flat_map(|_| [r, r * r]).collect();
    let probes = VolumeView {
        grid,
        lmax,
        valid: &valid,
        radiance: &radiance,
        offsets: visibility.then_some(&offsets[..]),
        visibility: visibility.then_some(Visibility {
            size,
            max_distance: r,
            moments: &moments,
        }),
    };
    // The plain renderer only clears (no mesh, no background); the volume
    // pass draws the bunny in place.
    let background = Renderer::new(ctx, HEADLESS_FORMAT);
    let mut volume = VolumeRenderer::with_fetch(ctx, HEADLESS_FORMAT, &probes, fetch).unwrap();
    assert_eq!(volume.visibility(), visibility);
    volume.set_object(
        ctx,
        &mesh,
        [0.8; 3],
        VolumeInstance::interpolated(Vec3::ZERO, 1.0),
    );
    let target = Offscreen::new(ctx, 1920, 1080).unwrap();
    let camera = Camera::framing(mesh.bounds(), Vec3::Z, 0.6, target.aspect());
    let shading = sh(lmax);
    let aspect = target.aspect();
    let frame = || {
        target
            .render_with(ctx, false, |encoder, color, depth| {
                background.draw(ctx, encoder, color, depth, &camera, aspect, &shading)?;
                volume.draw(ctx, encoder, color, depth, &camera, aspect, &shading, false);
                Ok(())
            })
            .unwrap()
    };
    // The first frame builds the pipelines (shader compilation).
    frame();
    bencher.bench_local(frame);
}

#[divan::bench(sample_count = 10, sample_size = 1)]
fn frame_sphere_normals(bencher: divan::Bencher) {
    let shading = Shading {
        mode: Mode::Normals,
        ..sh(2)
    };
    bench_frame(bencher, &sphere(), shading, None, false);
}

#[divan::bench(sample_count = 10, sample_size = 1)]
fn frame_sphere_readback(bencher: divan::Bencher) {
    bench_frame(bencher, &sphere(), sh(2), None, true);
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

#[divan::bench(args = [0, 2, 8], sample_count = 10, sample_size = 1)]
fn project_gpu(bencher: divan::Bencher, lmax: usize) {
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
            .project(ctx, view, lmax, MapOrientation::default())
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

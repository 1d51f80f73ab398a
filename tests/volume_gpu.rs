//! Irradiance-volume shading on the GPU (`shaders/volume.wgsl`) against the
//! CPU: the interpolation the fragments use, run as a compute pass, equals
//! the radiance of shlight-volume's trilinear lookup
//! (`PreparedLookup::radiance_at`, checked once by hand) followed by
//! shlight-core's irradiance at random points and normals, on the grid's
//! faces, edges and corners and far beyond them, on a grid with one probe
//! along an axis, for lmax 0..4, both ways of interpolating
//! (`VolumeFetch::Filtered` where the adapter filters `Rgba32Float`,
//! `VolumeFetch::Loads` always); an invalid probe takes no weight; a volume
//! of higher lmax is shaded to lmax 4; probe spheres (their own pipeline)
//! show their own probe beside an interpolated object in one frame. A
//! volume with distance maps (`shaders/volume_visibility.wgsl`) equals
//! shlight-volume's `PreparedLookup` with `Lookup::Shlight` beside a thin
//! wall, where trilinear interpolation is far off; `render-mesh --volume`
//! shades the Cornell box as that lookup does and keeps the dark side of a
//! wall between two sealed rooms dark.

use glam::{DVec3, Vec3};
use shlight_baked::{ProbeGrid, VolumeView};
use shlight_core::sh::{ShCoeffs, sh_count};
use shlight_gpu::{GpuContext, HEADLESS_FORMAT, Shading, VolumeFetch, VolumeRenderer, wgpu};
use shlight_volume::{Lookup, PreparedLookup};

use crate::util::gpu_context;

/// GPU (f32, the basis by recurrence) against CPU (f64 sums of the f32
/// probes): each irradiance within this fraction of the largest one among
/// the queries. f32 rounding of sums of some 200 terms of size 1 is a few
/// 1e-6 of the largest; a wrong weight, index or basis function is off by
/// tenths.
const VOLUME_TOL: f64 = 2e-5;

/// The radiance shlight-volume's trilinear lookup reads at `p` off the
/// probes of `grid` (`valid`, `radiance` of `lmax`), `None` where every
/// probe around `p` is invalid.
fn trilinear_radiance(
    grid: &ProbeGrid,
    valid: &[bool],
    radiance: &[f32],
    lmax: usize,
    p: Vec3,
) -> Option<ShCoeffs<DVec3>> {
    let view = VolumeView {
        grid: *grid,
        lmax,
        valid,
        radiance,
        offsets: None,
        visibility: None,
    };
    PreparedLookup::new(&view, Lookup::Trilinear, lmax).radiance_at(p, Vec3::Y)
}

/// `lookup`'s irradiance at `p` facing `n`, the lookup prepared for the
/// one point.
fn irradiance_at(view: &VolumeView<'_>, lookup: Lookup, lmax: usize, p: Vec3, n: Vec3) -> DVec3 {
    PreparedLookup::new(view, lookup, lmax).irradiance_at(p, n)
}
/// The same for `VolumeFetch::Filtered` on a hardware GPU, whose sampler
/// rounds each axis's weight to its sub-texel precision (8 bits on most:
/// steps of 1/256, so off by up to 1/512 per axis): three axes times 1/512
/// of the difference between neighbouring probes' irradiance, at most
/// twice the largest. CPU adapters (lavapipe) weigh in f32 and meet
/// [`VOLUME_TOL`] (measured: at most 2e-6 filtered, 5e-7 by loads).
const FILTERED_GPU_TOL: f64 = 1.2e-2;

/// A fixed linear congruential sequence (Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    /// A value in `[lo, hi)`.
    fn range(&mut self, r: std::ops::Range<f32>) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let u = (self.0 >> 40) as f32 / (1u64 << 24) as f32;
        r.start + (r.end - r.start) * u
    }
}

struct TestVolume {
    grid: ProbeGrid,
    lmax: usize,
    valid: Vec<bool>,
    radiance: Vec<f32>,
}

impl TestVolume {
    fn random(lmax: usize, seed: u64) -> Self {
        Self::random_on([4, 3, 2], lmax, seed)
    }

    /// Random radiance on a grid of `resolution` over the box
    /// (-1, 0, 2)..(3, 1.5, 3), a probe or two invalid.
    fn random_on(resolution: [usize; 3], lmax: usize, seed: u64) -> Self {
        let grid = ProbeGrid::new(
            resolution,
            Vec3::new(-1.0, 0.0, 2.0),
            Vec3::new(3.0, 1.5, 3.0),
        )
        .unwrap();
        let mut rng = Lcg(seed);
        let n = grid.probe_count();
        let radiance = (0..n * sh_count(lmax) * 3)
            .map(|_| rng.range(-1.0f32..1.0))
            .collect();
        // Probes 5 and 17 inside geometry (probe 1 on a grid of fewer
        // than 18, where probe 5 may be a corner alone at its end).
        let invalid: &[usize] = if n > 17 { &[5, 17] } else { &[1] };
        let valid = (0..n).map(|k| !invalid.contains(&k)).collect();
        Self {
            grid,
            lmax,
            valid,
            radiance,
        }
    }

    fn probes(&self) -> VolumeView<'_> {
        VolumeView {
            grid: self.grid,
            lmax: self.lmax,
            valid: &self.valid,
            radiance: &self.radiance,
            offsets: None,
            visibility: None,
        }
    }

    /// The summed trilinear weight of the valid probes around `p` (CPU).
    fn valid_weight(&self, p: Vec3) -> f32 {
        self.grid
            .trilinear(p)
            .iter()
            .filter(|(k, _)| self.valid[*k])
            .map(|(_, w)| w)
            .sum()
    }

    /// The CPU's irradiance at `p` facing `n` to `lmax`, `None` when every
    /// probe around `p` is invalid.
    fn cpu(&self, p: Vec3, n: Vec3, lmax: usize) -> Option<DVec3> {
        let l = trilinear_radiance(&self.grid, &self.valid, &self.radiance, self.lmax, p)?;
        Some(shlight_core::sh::irradiance(&l.resized(lmax)).eval(n.as_dvec3()))
    }
}

/// The ways of interpolating `ctx` offers: loads always, filtered where
/// the device filters `Rgba32Float` (lavapipe does: there it must be on
/// offer, so the path the fragments take is the one tested).
fn fetches(ctx: &GpuContext) -> Vec<VolumeFetch> {
    let best = VolumeFetch::best(ctx);
    if ctx.adapter_name().contains("llvmpipe") {
        assert_eq!(best, VolumeFetch::Filtered, "{}", ctx.adapter_name());
    }
    let mut out = vec![VolumeFetch::Loads];
    if VolumeFetch::can_filter(ctx) {
        out.push(VolumeFetch::Filtered);
    }
    out
}

fn gpu(
    ctx: &GpuContext,
    volume: &TestVolume,
    lmax: usize,
    queries: &[(Vec3, Vec3)],
    fetch: VolumeFetch,
) -> Vec<[f32; 4]> {
    let renderer =
        VolumeRenderer::with_fetch(ctx, HEADLESS_FORMAT, &volume.probes(), fetch).unwrap();
    assert_eq!(renderer.fetch(), fetch);
    let shading = Shading {
        lmax,
        ..Shading::default()
    };
    renderer.irradiance_at(ctx, &shading, queries).unwrap()
}

/// Random points in and a little around the grid box, random unit normals.
fn queries(count: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut rng = Lcg(seed);
    (0..count)
        .map(|_| {
            let p = Vec3::new(
                rng.range(-1.5..3.5),
                rng.range(-0.3..1.8),
                rng.range(1.8..3.2),
            );
            let n = loop {
                let v = Vec3::new(
                    rng.range(-1.0..1.0),
                    rng.range(-1.0..1.0),
                    rng.range(-1.0..1.0),
                );
                if v.length() > 0.1 && v.length() < 1.0 {
                    break v.normalize();
                }
            };
            (p, n)
        })
        .collect()
}

/// Points on the box (-1, 0, 2)..(3, 1.5, 3) of the test volumes and
/// around it: its corners, edge midpoints and face centres (every point
/// whose coordinates are each the box's lower end, middle or upper end),
/// the same pushed 0.01 and 10 box sizes outward from the centre, and the
/// probe centres of a 4 x 3 x 2 grid (weights exactly 0 and 1); random
/// unit normals.
fn edge_queries(seed: u64) -> Vec<(Vec3, Vec3)> {
    let (lo, hi) = (Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 1.5, 3.0));
    let centre = (lo + hi) * 0.5;
    let mut points = Vec::new();
    for k in 0..27 {
        let pick = |a: f32, b: f32, i: usize| [a, (a + b) * 0.5, b][i];
        let p = Vec3::new(
            pick(lo.x, hi.x, k % 3),
            pick(lo.y, hi.y, k / 3 % 3),
            pick(lo.z, hi.z, k / 9),
        );
        for push in [0.0, 0.01, 10.0] {
            points.push(p + (p - centre) * push);
        }
    }
    let cell = (hi - lo) / Vec3::new(4.0, 3.0, 2.0);
    for k in 0..24 {
        let i = Vec3::new((k % 4) as f32, (k / 4 % 3) as f32, (k / 12) as f32);
        points.push(lo + (i + 0.5) * cell);
    }
    let normals = queries(points.len(), seed);
    points
        .into_iter()
        .zip(normals)
        .map(|(p, (_, n))| (p, n))
        .collect()
}

#[test]
fn the_cpu_interpolation_matches_a_hand_computation() {
    // Two probes along x at 0.5 and 1.5 (box 0..2): at x = 0.75 the
    // weights are 3/4 and 1/4; with probe 1 invalid, probe 0 alone.
    let grid = ProbeGrid::new([2, 1, 1], Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)).unwrap();
    let radiance = [4.0, 8.0, 12.0, 0.0, 4.0, 40.0];
    let got = trilinear_radiance(
        &grid,
        &[true, true],
        &radiance,
        0,
        Vec3::new(0.75, 0.5, 0.5),
    )
    .unwrap();
    assert_eq!(got[0], DVec3::new(3.0, 7.0, 19.0));
    let got = trilinear_radiance(
        &grid,
        &[true, false],
        &radiance,
        0,
        Vec3::new(0.75, 0.5, 0.5),
    )
    .unwrap();
    assert_eq!(got[0], DVec3::new(4.0, 8.0, 12.0));
    assert!(trilinear_radiance(&grid, &[false, false], &radiance, 0, Vec3::splat(0.5)).is_none());
}

#[test]
fn gpu_interpolation_equals_the_cpu_at_random_points() {
    let Some(ctx) = gpu_context("gpu_interpolation_equals_the_cpu_at_random_points") else {
        return;
    };
    let mut points = queries(500, 11);
    points.extend(edge_queries(13));
    for fetch in fetches(&ctx) {
        // The test grid, and one with a single probe along y.
        for resolution in [[4, 3, 2], [3, 1, 2]] {
            let cpu_adapter = ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
            let tol = if fetch == VolumeFetch::Filtered && !cpu_adapter {
                FILTERED_GPU_TOL
            } else {
                VOLUME_TOL
            };
            for lmax in 0..=4 {
                let seed = 3 + lmax as u64 + 10 * resolution[1] as u64;
                let volume = TestVolume::random_on(resolution, lmax, seed);
                let got = gpu(&ctx, &volume, lmax, &points, fetch);
                let want: Vec<Option<DVec3>> = points
                    .iter()
                    .map(|&(p, n)| volume.cpu(p, n, lmax))
                    .collect();
                let scale = want
                    .iter()
                    .flatten()
                    .map(|e| e.abs().max_element())
                    .fold(0.0, f64::max);
                let mut worst = 0.0f64;
                for ((g, w), (p, n)) in got.iter().zip(&want).zip(&points) {
                    // At an invalid probe's centre it alone has weight: no
                    // light (the CPU's None). The point's f32 rounding may
                    // give its neighbours a weight of the order of 1e-7,
                    // and renormalised, their light; the GPU's valid weight
                    // must be as small.
                    if volume.valid_weight(*p) < 1e-5 {
                        assert!(g[3] < 1e-5, "{fetch:?} {resolution:?} at {p}: {g:?}");
                        continue;
                    }
                    let w = w.unwrap_or_else(|| panic!("{p}: no valid probe around"));
                    let err = (Vec3::new(g[0], g[1], g[2]).as_dvec3() - w)
                        .abs()
                        .max_element()
                        / scale;
                    worst = worst.max(err);
                    assert!(
                        err < tol,
                        "{fetch:?} {resolution:?} lmax {lmax} at {p} facing {n}: GPU {g:?}, \
                         CPU {w} ({err:.2e} of {scale})"
                    );
                    assert!(g[3] > 0.0 && g[3] <= 1.0 + 1e-5, "{g:?}");
                }
                eprintln!(
                    "{fetch:?} {resolution:?} lmax {lmax}: worst {worst:.2e} of the largest \
                     irradiance"
                );
            }
        }
    }
}

#[test]
fn an_invalid_probe_takes_no_weight_on_the_gpu() {
    let Some(ctx) = gpu_context("an_invalid_probe_takes_no_weight_on_the_gpu") else {
        return;
    };
    let points = queries(300, 5);
    let plain = TestVolume::random(2, 9);
    // Probe 5 is invalid; give it a huge value: nothing may change.
    let mut huge = TestVolume::random(2, 9);
    let nc = sh_count(2);
    for v in &mut huge.radiance[5 * nc * 3..6 * nc * 3] {
        *v = 1e6;
    }
    let mut dark = TestVolume::random(1, 2);
    dark.valid.iter_mut().for_each(|v| *v = false);
    for fetch in fetches(&ctx) {
        let a = gpu(&ctx, &plain, 2, &points, fetch);
        let b = gpu(&ctx, &huge, 2, &points, fetch);
        assert_eq!(
            a, b,
            "{fetch:?}: an invalid probe's values reached the result"
        );
        // The same probe made valid does change the points around it (so
        // the comparison above can fail).
        huge.valid[5] = true;
        let c = gpu(&ctx, &huge, 2, &points, fetch);
        huge.valid[5] = false;
        let changed = a.iter().zip(&c).filter(|(x, y)| x != y).count();
        assert!(changed > 10, "{fetch:?}: only {changed} points changed");
        // Every probe around a point invalid: no light, weight 0.
        let d = gpu(&ctx, &dark, 1, &points[..8], fetch);
        assert!(d.iter().all(|x| *x == [0.0; 4]), "{fetch:?}: {d:?}");
    }
}

#[test]
fn a_volume_above_lmax_4_is_shaded_to_lmax_4() {
    let Some(ctx) = gpu_context("a_volume_above_lmax_4_is_shaded_to_lmax_4") else {
        return;
    };
    let volume = TestVolume::random(6, 21);
    let renderer = VolumeRenderer::new(&ctx, HEADLESS_FORMAT, &volume.probes()).unwrap();
    assert_eq!(renderer.lmax(), 4);
    let points = queries(100, 8);
    let got = gpu(&ctx, &volume, 6, &points, VolumeFetch::best(&ctx));
    for (g, &(p, n)) in got.iter().zip(&points) {
        let want = volume.cpu(p, n, 4).unwrap();
        let err = (Vec3::new(g[0], g[1], g[2]).as_dvec3() - want)
            .abs()
            .max_element();
        assert!(err < 1e-3, "at {p}: GPU {g:?}, CPU to lmax 4 {want}");
    }
}

/// `render-mesh --volume` pixels against CPU shading: each pixel within
/// this fraction of its own value (plus [`PIXEL_FLOOR`]). The GPU
/// interpolates the world position and normal per fragment in f32 and
/// evaluates the basis in f32; the CPU casts the pixel's ray in f32
/// through the same triangles. A wrong lookup point
/// (a tenth of a cell) or a missing relight is off by percents. Measured:
/// at most 1e-3 (scene pixels at steep angles).
const PIXEL_TOL: f64 = 2e-3;
/// Smallest `|n . view|` of the pixels compared (see the test).
const GRAZING: f32 = 0.35;
/// Absolute allowance for pixels near black.
const PIXEL_FLOOR: f64 = 1e-4;
/// Probe-sphere pixels against their probe's irradiance, as a fraction of
/// the largest value in the frame. The spheres are coarse (16 x 8
/// segments, 22.5 degrees of normal per triangle) and the random lmax 4
/// light changes fast with the normal, so the rasteriser's interpolation
/// of the normal, not quite the ray's barycentrics, moves a pixel by up to
/// 6e-3 of the largest value (measured); a wrong probe or coefficient is
/// off by tenths.
const SPHERE_TOL: f64 = 1.5e-2;

/// The mesh under `ray`: (which mesh, triangle, hit point, barycentrics).
fn cast(
    meshes: &[(&shlight_mesh::Mesh, &shlight_rays::Occluder)],
    origin: Vec3,
    dir: Vec3,
) -> Option<(usize, u32, Vec3, [f32; 3])> {
    let ray = shlight_rays::Ray::new(origin, dir, f32::INFINITY);
    meshes
        .iter()
        .enumerate()
        .filter_map(|(k, (_, bvh))| bvh.closest_hit(&ray).map(|h| (k, h)))
        .min_by(|a, b| a.1.t.total_cmp(&b.1.t))
        .map(|(k, h)| (k, h.triangle, origin + dir * h.t, h.barycentrics))
}

/// What a pixel's centre sees ([`pixel_hit`]).
struct PixelHit {
    /// Which mesh, triangle, hit point and barycentrics ([`cast`]).
    mesh: usize,
    triangle: u32,
    point: Vec3,
    bary: [f32; 3],
    /// The unit direction of the ray through the pixel's centre.
    direction: Vec3,
    /// The interpolated unit normal, as the fragments have it.
    normal: Vec3,
    /// Whether the pixel lies well inside the triangle: the rays a third
    /// of a pixel away hit it too.
    inside: bool,
}

/// What pixel `(i, j)`'s centre sees through `ray` (pixel coordinates to
/// origin and direction); `None` when the ray meets nothing.
fn pixel_hit(
    meshes: &[(&shlight_mesh::Mesh, &shlight_rays::Occluder)],
    ray: impl Fn(f32, f32) -> (Vec3, Vec3),
    i: usize,
    j: usize,
) -> Option<PixelHit> {
    let (o, d) = ray(i as f32 + 0.5, j as f32 + 0.5);
    let (k, tri, p, bary) = cast(meshes, o, d)?;
    let mesh = meshes[k].0;
    let corners = mesh.triangles[tri as usize].map(|v| v as usize);
    let normal: Vec3 = (0..3).map(|t| mesh.normals[corners[t]] * bary[t]).sum();
    let inside = [(-0.34, 0.0), (0.34, 0.0), (0.0, -0.34), (0.0, 0.34)]
        .iter()
        .all(|(dx, dy)| {
            let (o, d) = ray(i as f32 + 0.5 + dx, j as f32 + 0.5 + dy);
            cast(meshes, o, d).is_some_and(|(k2, t2, _, _)| k2 == k && t2 == tri)
        });
    Some(PixelHit {
        mesh: k,
        triangle: tri,
        point: p,
        bary,
        direction: d,
        normal: normal.normalize(),
        inside,
    })
}

#[test]
fn render_mesh_volume_pixels_match_cpu_shading_in_the_cornell_box() {
    use crate::util::{s, shlight_ok, temp_dir, write_obj, write_radiance_rows};
    use shlight_core::sh::ShRotation;
    use shlight_format::ShvolFile;

    if gpu_context("render_mesh_volume_pixels_match_cpu_shading_in_the_cornell_box").is_none() {
        return;
    }
    let dir = temp_dir("volume-render");
    let env = dir.join("sky.json");
    let sky_rows = [
        [2.0, 2.2, 2.6],
        [0.0, 0.0, 0.0],
        [0.8, 0.9, 1.1],
        [0.3, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.1, 0.05, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.2, 0.0],
    ];
    write_radiance_rows(&env, &sky_rows);
    let volume = dir.join("room.shvol");
    shlight_ok(&[
        "volume",
        "meshes/cornell_box.obj",
        "--env",
        s(&env),
        "--resolution",
        "4x4x4",
        "--samples",
        "128",
        "--surface-samples",
        "32",
        "-o",
        s(&volume),
    ]);
    // The object: a box of flat faces, half extent 1, put at `at` with a
    // diagonal of 0.15 (scale 0.15 / (2 sqrt 3), centre at `at`).
    let object = dir.join("box.obj");
    write_obj(&object, &shlight_mesh::generate::cuboid(Vec3::ONE));
    let at = Vec3::new(0.3, 0.3, 0.25);
    let size = 0.15f32;
    let image = dir.join("frame.exr");
    let (w, h) = (96usize, 72usize);
    let (eye, target) = (Vec3::new(0.278, 0.273, -0.8), Vec3::new(0.278, 0.273, 0.28));
    shlight_ok(&[
        "render-mesh",
        "meshes/cornell_box.obj",
        "--volume",
        s(&volume),
        "--object",
        s(&object),
        "--at",
        "0.3,0.3,0.25",
        "--object-size",
        "0.15",
        "--env",
        s(&env),
        "--rotate",
        "yaw:60",
        "--albedo",
        "0.6,0.5,0.4",
        "--camera",
        "0.278,0.273,-0.8",
        "--target",
        "0.278,0.273,0.28",
        "--size",
        "96x72",
        "-o",
        s(&image),
    ]);
    let frame = shlight_io::read_image(&image, &Default::default()).unwrap();

    // The CPU side: the volume relit under the sky turned 60 degrees about +Y.
    let mut file = ShvolFile::read(&volume).unwrap();
    let sky = shlight_core::sh::ShCoeffs::from_vec(
        sky_rows.iter().map(|r| DVec3::from_array(*r)).collect(),
    )
    .unwrap();
    let turned =
        ShRotation::from_mat3(2, glam::DMat3::from_rotation_y(60f64.to_radians())).apply(&sky);
    shlight_volume::relight_file(&mut file, &turned).unwrap();
    // Baked with distance maps (the default): the pass weighs the probes
    // by visibility, as `shlight sample`'s shlight lookup does.
    let view = file.view();
    assert!(view.visibility.is_some() && view.offsets.is_some());
    let scene = shlight_mesh::load(std::path::Path::new("meshes/cornell_box.obj")).unwrap();
    let mut boxed = shlight_mesh::generate::cuboid(Vec3::ONE);
    let scale = size / (2.0 * 3f32.sqrt());
    for p in &mut boxed.positions {
        *p = *p * scale + at;
    }
    let bvhs = [
        shlight_rays::Occluder::new(&scene),
        shlight_rays::Occluder::new(&boxed),
    ];
    let meshes = [(&scene, &bvhs[0]), (&boxed, &bvhs[1])];
    let camera = shlight_gpu::Camera::looking_at(eye, target, 1.0, 35f32.to_radians());
    let inverse = camera.view_proj(w as f32 / h as f32).inverse();
    let ray = |x: f32, y: f32| {
        let ndc = glam::Vec2::new(x / w as f32 * 2.0 - 1.0, 1.0 - y / h as f32 * 2.0);
        let far = inverse.project_point3(ndc.extend(1.0));
        (eye, (far - eye).normalize())
    };
    let (mut object_pixels, mut scene_pixels, mut worst) = (0, 0, 0.0f64);
    // Pixels where trilinear interpolation (a pass that ignored the maps)
    // is off by more than ten times the tolerance.
    let mut not_trilinear = 0;
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            // Only pixels well inside one triangle (pixel_hit).
            let Some(PixelHit {
                mesh: k,
                triangle: tri,
                point: p,
                bary,
                direction: d,
                normal,
                inside,
            }) = pixel_hit(&meshes, ray, i, j)
            else {
                continue;
            };
            let mesh = meshes[k].0;
            let corners = mesh.triangles[tri as usize].map(|v| v as usize);
            let emission = mesh.emission.as_ref().map_or(Vec3::ZERO, |e| e[corners[0]]);
            // Surfaces seen at a grazing angle are skipped: there a pixel
            // spans a long stretch of the surface, and the f32 rounding of
            // the rasteriser's interpolation moves the point along it.
            if !inside || emission != Vec3::ZERO || normal.dot(d).abs() < GRAZING {
                continue;
            }
            let albedo: Vec3 = match &mesh.colors {
                Some(c) => (0..3).map(|t| c[corners[t]] * bary[t]).sum(),
                None => Vec3::new(0.6, 0.5, 0.4),
            };
            let e = irradiance_at(&view, Lookup::Shlight, 2, p, normal);
            let want = albedo.as_dvec3() * e / std::f64::consts::PI;
            let got = Vec3::from_array(frame.pixels()[j * w + i]).as_dvec3();
            let err = ((got - want).abs() / (want.abs() + PIXEL_FLOOR)).max_element();
            let trilinear = albedo.as_dvec3()
                * irradiance_at(&view, Lookup::Trilinear, 2, p, normal)
                / std::f64::consts::PI;
            if ((trilinear - want).abs() / (want.abs() + PIXEL_FLOOR)).max_element()
                > 10.0 * PIXEL_TOL
            {
                not_trilinear += 1;
            }
            worst = worst.max(err);
            assert!(
                err < PIXEL_TOL,
                "pixel ({i}, {j}) on {} at {p}: GPU {got}, CPU {want}",
                if k == 1 { "the object" } else { "the scene" }
            );
            if k == 1 {
                object_pixels += 1;
            } else {
                scene_pixels += 1;
            }
        }
    }
    eprintln!(
        "{object_pixels} object and {scene_pixels} scene pixels, worst {worst:.2e}; trilinear \
         interpolation off by more than {:.0e} at {not_trilinear}",
        10.0 * PIXEL_TOL
    );
    assert!(not_trilinear >= 20, "{not_trilinear}");
    assert!(
        object_pixels >= 20,
        "only {object_pixels} object pixels checked"
    );
    assert!(
        scene_pixels >= 500,
        "only {scene_pixels} scene pixels checked"
    );
}

/// A frame of [`VolumeRenderer::draw`] with the probes shown: each probe
/// sphere (pipeline `fs_probe`) shows its own probe's irradiance (black
/// for the invalid one), an object beside them (pipeline `fs_volume`) the
/// interpolation, both against the CPU at the point and interpolated
/// normal a ray through the pixel finds. A volume of lmax 4 with random
/// radiance in every degree: degree 3 adds nothing to the irradiance
/// (`A_3 = 0`, on the CPU as in the shader), so what this checks there is
/// the texels' layout once degree 3 is left out, degree 4 read from the
/// slots that follow degree 2's. Without the probes shown, no sphere is
/// drawn.
#[test]
fn probe_spheres_show_their_own_probe_beside_an_interpolated_object() {
    use shlight_gpu::{Camera, Offscreen, Renderer, place, probe_sphere_instances};

    let Some(ctx) = gpu_context("probe_spheres_show_their_own_probe_beside_an_interpolated_object")
    else {
        return;
    };
    // Cells 4/3 x 0.75 x 1 (spheres of radius 0.1125), probe 1 at
    // (1, 0.375, 2.5) invalid; the object between probes 1, 2, 4 and 5.
    let volume = TestVolume::random_on([3, 2, 1], 4, 31);
    assert_eq!(volume.valid, [true, false, true, true, true, true]);
    let probes = volume.probes();
    let sphere = shlight_mesh::generate::uv_sphere(1.0, 16, 8);
    let object = shlight_mesh::generate::uv_sphere(1.0, 32, 16);
    let albedo = [0.7f32, 0.5, 0.3];
    let placement = place(object.bounds(), Vec3::new(1.7, 0.9, 2.5), 0.8);
    // The meshes as drawn, in world space.
    let moved = |mesh: &shlight_mesh::Mesh, offset_scale: [f32; 4]| {
        let mut m = mesh.clone();
        let (o, s) = (Vec3::from_slice(&offset_scale[..3]), offset_scale[3]);
        m.positions.iter_mut().for_each(|p| *p = *p * s + o);
        m
    };
    let spheres = probe_sphere_instances(&probes);
    let mut world = vec![moved(&object, placement.offset_scale)];
    for instance in &spheres {
        world.push(moved(&sphere, instance.offset_scale));
    }
    let bvhs: Vec<_> = world.iter().map(shlight_rays::Occluder::new).collect();
    let meshes: Vec<_> = world.iter().zip(&bvhs).collect();
    let (w, h) = (512usize, 256usize);
    let (eye, target) = (Vec3::new(1.0, 0.75, 6.5), Vec3::new(1.0, 0.75, 2.5));
    let camera = Camera::looking_at(eye, target, 2.0, 22f32.to_radians());
    let aspect = w as f32 / h as f32;
    let inverse = camera.view_proj(aspect).inverse();
    let ray = |x: f32, y: f32| {
        let ndc = glam::Vec2::new(x / w as f32 * 2.0 - 1.0, 1.0 - y / h as f32 * 2.0);
        (
            eye,
            (inverse.project_point3(ndc.extend(1.0)) - eye).normalize(),
        )
    };
    let shading = Shading {
        lmax: 4,
        ..Shading::default()
    };
    let target = Offscreen::new(&ctx, w, h).unwrap();
    let background = Renderer::new(&ctx, HEADLESS_FORMAT);
    let cpu_adapter = ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
    for fetch in fetches(&ctx) {
        let mut renderer =
            VolumeRenderer::with_fetch(&ctx, HEADLESS_FORMAT, &probes, fetch).unwrap();
        renderer.set_object(&ctx, &object, albedo, placement);
        let frame = |show_probes: bool| {
            target
                .render_with(&ctx, true, |encoder, color, depth| {
                    background.draw(&ctx, encoder, color, depth, &camera, aspect, &shading)?;
                    renderer.draw(
                        &ctx,
                        encoder,
                        color,
                        depth,
                        &camera,
                        aspect,
                        &shading,
                        show_probes,
                    );
                    Ok(())
                })
                .unwrap()
                .unwrap()
        };
        let (shown, hidden) = (frame(true), frame(false));
        // Pixels checked on the object, the valid probes' spheres and the
        // invalid one's; per pixel checked (GPU, CPU, where).
        let mut counts = [0usize; 3];
        let mut checked = Vec::new();
        for j in 1..h - 1 {
            for i in 1..w - 1 {
                let got = Vec3::from_slice(&shown.pixels[j * w + i][..3]).as_dvec3();
                let hidden_got = Vec3::from_slice(&hidden.pixels[j * w + i][..3]).as_dvec3();
                let Some(PixelHit {
                    mesh: k,
                    point: p,
                    direction: d,
                    normal,
                    inside,
                    ..
                }) = pixel_hit(&meshes, ray, i, j)
                else {
                    continue;
                };
                if k > 0 {
                    // Without the probes the sphere is not drawn (the
                    // object is not behind it: cleared to 0).
                    assert_eq!(hidden_got, DVec3::ZERO, "{fetch:?} pixel ({i}, {j})");
                } else {
                    assert_eq!(hidden_got, got, "{fetch:?} pixel ({i}, {j})");
                }
                // Only pixels well inside one triangle, not at a grazing
                // angle (as in the Cornell box test above).
                if !inside || normal.dot(d).abs() < GRAZING {
                    continue;
                }
                let want = match k {
                    // The object: albedo / pi times the interpolation at p.
                    0 => {
                        let e = volume.cpu(p, normal, 4).expect("a lit point");
                        Vec3::from_array(albedo).as_dvec3() * e / std::f64::consts::PI
                    }
                    // A sphere: its own probe alone (albedo 1), at its
                    // centre, where the probe has weight 1; none if invalid.
                    _ => {
                        let centre = Vec3::from_slice(&spheres[k - 1].offset_scale[..3]);
                        if volume.valid[k - 1] {
                            volume.cpu(centre, normal, 4).unwrap() / std::f64::consts::PI
                        } else {
                            DVec3::ZERO
                        }
                    }
                };
                if want == DVec3::ZERO {
                    // The invalid probe's sphere: black, exactly.
                    assert_eq!(got, want, "{fetch:?} pixel ({i}, {j}) on mesh {k}");
                }
                checked.push((
                    got,
                    want,
                    k > 0,
                    format!("pixel ({i}, {j}) on mesh {k} at {p}"),
                ));
                counts[match k {
                    0 => 0,
                    k if volume.valid[k - 1] => 1,
                    _ => 2,
                }] += 1;
            }
        }
        // As fractions of the largest value: the random light's
        // irradiance crosses 0, where a fraction of the pixel's own value
        // would ask for more than f32 interpolation gives. The object's
        // pixels within PIXEL_TOL (FILTERED_GPU_TOL filtered on a hardware
        // GPU), the spheres' (their own probe's texels, loaded) within
        // SPHERE_TOL.
        let scale = checked
            .iter()
            .map(|(_, want, _, _)| want.abs().max_element())
            .fold(0.0, f64::max);
        let mut worst = [0.0f64; 2];
        for (got, want, on_sphere, at) in &checked {
            let err = (*got - *want).abs().max_element() / scale;
            let s = usize::from(*on_sphere);
            worst[s] = worst[s].max(err);
            let tol = if *on_sphere {
                SPHERE_TOL
            } else if fetch == VolumeFetch::Filtered && !cpu_adapter {
                // A GPU's sampler rounds the weights (see FILTERED_GPU_TOL).
                FILTERED_GPU_TOL
            } else {
                PIXEL_TOL
            };
            assert!(
                err < tol,
                "{fetch:?} {at}: GPU {got}, CPU {want} ({err:.2e} of {scale})"
            );
        }
        eprintln!(
            "{fetch:?}: pixels checked {counts:?}, worst {:.2e} (object), {:.2e} (spheres) \
             of {scale:.3}",
            worst[0], worst[1]
        );
        assert!(counts.iter().all(|&c| c >= 100), "{fetch:?}: {counts:?}");
    }
}

#[test]
fn bad_volume_options_are_clear_errors() {
    use crate::util::{s, shlight_err, shlight_ok, temp_dir, write_radiance_rows};

    let dir = temp_dir("volume-render-errors");
    let env = dir.join("sky.json");
    let mut rows = vec![[0.0; 3]; 36];
    rows[0] = [1.0, 1.0, 1.0];
    rows[2] = [0.5, 0.4, 0.3];
    write_radiance_rows(&env, &rows);
    let out = dir.join("out.exr");
    let base = [
        "render-mesh",
        "meshes/cornell_box.obj",
        "--env",
        s(&env),
        "--size",
        "32x24",
        "-o",
        s(&out),
    ];
    macro_rules! render {
        ($extra:expr) => {
            [&base[..], &$extra[..]].concat()
        };
    }
    let e = shlight_err(&render!(["--volume", s(&dir.join("none.shvol"))]));
    assert!(
        e.contains("none.shvol") && e.contains("no such volume file"),
        "{e}"
    );
    let e = shlight_err(&render!(["--volume", s(&env)]));
    assert!(e.contains("sky.json") && e.contains(".shvol"), "{e}");
    let e = shlight_err(&render!(["--object", "meshes/bunny.obj"]));
    assert!(e.contains("--object") && e.contains("--volume"), "{e}");
    let e = shlight_err(&render!(["--at", "0,0,0"]));
    assert!(e.contains("--at") && e.contains("--volume"), "{e}");
    // Not a volume inside: the reader names the file.
    let fake = dir.join("fake.shvol");
    std::fs::write(&fake, "not a volume\n").unwrap();
    let e = shlight_err(&render!(["--volume", s(&fake)]));
    assert!(e.contains("fake.shvol"), "{e}");
    // A static volume refuses --rotate; a volume of lmax 5 is shaded to 4
    // and --lmax 5 with it is refused.
    let bake = |name: &str, extra: &[&str]| {
        let path = dir.join(name);
        let mut args = vec![
            "volume",
            "meshes/cornell_box.obj",
            "--env",
            s(&env),
            "--resolution",
            "2x2x2",
            "--samples",
            "64",
            "--surface-samples",
            "16",
            "-o",
            s(&path),
        ];
        args.extend_from_slice(extra);
        shlight_ok(&args);
        path
    };
    let fixed = bake("static.shvol", &["--static"]);
    let e = shlight_err(&render!(["--volume", s(&fixed), "--rotate", "yaw:30"]));
    assert!(
        e.contains("static.shvol") && e.contains("--static") && e.contains("--rotate"),
        "{e}"
    );
    let high = bake("high.shvol", &["--lmax", "5"]);
    let e = shlight_err(&render!(["--volume", s(&high), "--lmax", "5"]));
    assert!(e.contains("--lmax 5") && e.contains("lmax 4"), "{e}");
    if gpu_context("bad_volume_options_are_clear_errors").is_none() {
        return;
    }
    let done = shlight_ok(&render!(["--volume", s(&high)]));
    let note = String::from_utf8_lossy(&done.stderr);
    assert!(
        note.contains("lmax 5") && note.contains("to lmax 4"),
        "{note}"
    );
    assert!(out.exists());
}

/// The GPU's visibility-weighted lookup (a volume with distance maps)
/// against shlight-volume's `PreparedLookup` with `Lookup::Shlight`, the one
/// definition: each irradiance within this fraction of the largest among
/// the queries. Both weigh every probe in f32 by the same operations
/// (shlight-baked's `visibility_weights`, `shaders/volume_visibility.wgsl`);
/// what is left is the rounding of the trilinear weights (as for
/// [`VOLUME_TOL`]) and of sums in another order: measured 3e-7 on
/// lavapipe. Where every probe around a point is all but shut out (inside
/// geometry) the weights are ratios of crushed Chebyshev factors, and a
/// rounding of the point or the normal moves the light by up to about
/// 1e-5 of the largest (a normal normalised twice did so in
/// `tests/sample.rs`), which is what this leaves room for.
const VISIBILITY_TOL: f64 = 1e-5;

/// `parts` (each a mesh moved by an offset) as one mesh.
fn merged(name: &str, parts: &[(shlight_mesh::Mesh, Vec3)]) -> shlight_mesh::Mesh {
    let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for (mesh, at) in parts {
        let base = positions.len() as u32;
        positions.extend(mesh.positions.iter().map(|p| *p + *at));
        normals.extend_from_slice(&mesh.normals);
        triangles.extend(mesh.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    shlight_mesh::Mesh::new(name, positions, triangles, Some(normals), None).unwrap()
}

/// x of the thin wall's centre in [`walled_volume`]: between the probe
/// columns at -0.25 and 0.25, nearer the second.
const WALL_X: f32 = 0.1;

/// A wall 4 cm thick across a 6x3x3 grid of 0.5 m cells over
/// (-1.5, 0, 0)..(1.5, 1.5, 1.5), at [`WALL_X`] (beyond the grid in y and
/// z), and a block of side 0.2 around the probe at (0.75, 0.75, 0.75),
/// which relocation moves out, baked with the default options (relocation
/// and 16x16 distance maps) and relit by a sky bright towards +x: the
/// probes behind the wall (-x) see its shaded side.
fn walled_volume() -> (shlight_volume::VolumeBake, Vec<f32>) {
    use shlight_mesh::generate::cuboid;
    let grid = ProbeGrid::new([6, 3, 3], Vec3::new(-1.5, 0.0, 0.0), Vec3::splat(1.5)).unwrap();
    let scene = merged(
        "a wall and a block",
        &[
            (
                cuboid(Vec3::new(0.02, 3.0, 3.0)),
                Vec3::new(WALL_X, 0.75, 0.75),
            ),
            (cuboid(Vec3::splat(0.1)), Vec3::splat(0.75)),
        ],
    );
    let volume = shlight_volume::bake(
        Some(&scene),
        &grid,
        &shlight_volume::VolumeOptions::default(),
        &|_, _, _| {},
    )
    .unwrap();
    assert!(volume.visibility.is_some(), "maps by default");
    assert!(
        volume.relocated_count() >= 1,
        "the probe in the block moves"
    );
    // L_00, and L_1,1 < 0 (Y_1,1 is -x): brighter towards +x, and a little
    // towards +y; positive everywhere.
    let mut rows = vec![DVec3::ZERO; 9];
    rows[0] = DVec3::new(2.0, 2.0, 2.2);
    rows[1] = DVec3::splat(-0.3);
    rows[3] = DVec3::new(-0.9, -0.8, -0.7);
    let sky = shlight_core::sh::ShCoeffs::from_vec(rows).unwrap();
    let radiance = volume.relight(&sky);
    (volume, radiance)
}

#[test]
fn gpu_visibility_weights_equal_the_cpu_lookup_beside_a_thin_wall() {
    let Some(ctx) = gpu_context("gpu_visibility_weights_equal_the_cpu_lookup_beside_a_thin_wall")
    else {
        return;
    };
    let (volume, radiance) = walled_volume();
    let view = volume.view(&radiance);
    // Random points in and around the grid box, and as many between the
    // probe columns on either side of the wall (x in -0.25..0.25, outside
    // the wall), where four of the eight probes are behind it.
    let mut rng = Lcg(41);
    let unit = |rng: &mut Lcg| loop {
        let v = Vec3::new(
            rng.range(-1.0..1.0),
            rng.range(-1.0..1.0),
            rng.range(-1.0..1.0),
        );
        if v.length() > 0.1 && v.length() < 1.0 {
            break v.normalize();
        }
    };
    let mut points = Vec::new();
    for k in 0..800 {
        let p = if k % 2 == 0 {
            Vec3::new(
                rng.range(-1.7..1.7),
                rng.range(-0.2..1.7),
                rng.range(-0.2..1.7),
            )
        } else {
            let x = loop {
                let x = rng.range(-0.25..0.25);
                if (x - WALL_X).abs() > 0.025 {
                    break x;
                }
            };
            Vec3::new(x, rng.range(0.0..1.5), rng.range(0.0..1.5))
        };
        points.push((p, unit(&mut rng)));
    }
    // The pass takes unit normals as given; the lookup normalises its
    // normal first (a unit vector normalised again may move by a
    // rounding), so the pass gets that normal.
    let unit: Vec<(Vec3, Vec3)> = points.iter().map(|&(p, n)| (p, n.normalize())).collect();
    for fetch in fetches(&ctx) {
        let renderer = VolumeRenderer::with_fetch(&ctx, HEADLESS_FORMAT, &view, fetch).unwrap();
        assert!(renderer.visibility());
        // Per-probe weights: loads, whatever was asked.
        assert_eq!(renderer.fetch(), VolumeFetch::Loads);
        for lmax in 0..=2 {
            let shading = Shading {
                lmax,
                ..Shading::default()
            };
            let got = renderer.irradiance_at(&ctx, &shading, &unit).unwrap();
            let want: Vec<DVec3> = points
                .iter()
                .map(|&(p, n)| irradiance_at(&view, Lookup::Shlight, lmax, p, n))
                .collect();
            let scale = want
                .iter()
                .map(|e| e.abs().max_element())
                .fold(0.0, f64::max);
            let (mut worst, mut far_from_trilinear, mut trilinear_worst) = (0.0f64, 0, 0.0f64);
            for ((g, w), &(p, n)) in got.iter().zip(&want).zip(&points) {
                let g = Vec3::new(g[0], g[1], g[2]).as_dvec3();
                let err = (g - *w).abs().max_element() / scale;
                worst = worst.max(err);
                assert!(
                    err < VISIBILITY_TOL,
                    "{fetch:?} lmax {lmax} at {p} facing {n}: GPU {g}, CPU {w} ({err:.2e} of \
                     {scale})"
                );
                // What a shader that ignored the maps would give.
                let t = irradiance_at(&view, Lookup::Trilinear, lmax, p, n);
                let off = (t - *w).abs().max_element() / scale;
                trilinear_worst = trilinear_worst.max(off);
                if off > 100.0 * VISIBILITY_TOL {
                    far_from_trilinear += 1;
                }
            }
            eprintln!(
                "{fetch:?} requested, lmax {lmax}: worst {worst:.2e} of the largest irradiance \
                 {scale:.3}; trilinear differs by more than {:.0e} at {far_from_trilinear} of \
                 {} points (at most {trilinear_worst:.2e})",
                100.0 * VISIBILITY_TOL,
                points.len()
            );
            // The wall changes the weights a lot at many points (lmax 0
            // included: the sides differ in brightness).
            assert!(
                far_from_trilinear >= 100 && trilinear_worst > 0.05,
                "{far_from_trilinear} {trilinear_worst}"
            );
        }
    }
    // The same probes without their maps (as a version 1 file holds them)
    // take the trilinear pass, the probes at their moved positions or not.
    let plain = VolumeView {
        visibility: None,
        ..view
    };
    for fetch in fetches(&ctx) {
        let renderer = VolumeRenderer::with_fetch(&ctx, HEADLESS_FORMAT, &plain, fetch).unwrap();
        assert!(!renderer.visibility());
        assert_eq!(renderer.fetch(), fetch);
        let shading = Shading {
            lmax: 2,
            ..Shading::default()
        };
        let got = renderer.irradiance_at(&ctx, &shading, &points).unwrap();
        let want: Vec<DVec3> = points
            .iter()
            .map(|&(p, n)| irradiance_at(&plain, Lookup::Shlight, 2, p, n))
            .collect();
        let scale = want
            .iter()
            .map(|e| e.abs().max_element())
            .fold(0.0, f64::max);
        for (g, w) in got.iter().zip(&want) {
            let g = Vec3::new(g[0], g[1], g[2]).as_dvec3();
            let tol = if fetch == VolumeFetch::Filtered
                && ctx.adapter.get_info().device_type != wgpu::DeviceType::Cpu
            {
                FILTERED_GPU_TOL
            } else {
                VOLUME_TOL
            };
            assert!((g - *w).abs().max_element() / scale < tol, "{g} {w}");
        }
    }
}

/// `render-mesh --volume` of a volume with distance maps: looking at the
/// wall between two sealed rooms from the dark one, every pixel is as dark
/// as the visibility-weighted lookup makes it (the truth is 0: no light
/// reaches the dark room), at most 2% of the lit room's pixels seen from
/// inside it, and equal to the CPU's lookup along each pixel's ray;
/// trilinear interpolation would put far more light there, so a pass that
/// ignored the maps would fail.
#[test]
fn render_mesh_volume_keeps_the_dark_side_of_a_wall_dark() {
    use crate::util::{bake_two_rooms, s, shlight_ok, temp_dir};
    use shlight_format::ShvolFile;

    if gpu_context("render_mesh_volume_keeps_the_dark_side_of_a_wall_dark").is_none() {
        return;
    }
    let dir = temp_dir("volume-render-wall");
    let mut sky = [[0.0; 3]; 9];
    sky[0] = [1.0; 3];
    sky[2] = [0.5; 3];
    let volume = bake_two_rooms(&dir, 2.1, &sky, "8x3x4");
    let (rooms, env) = (dir.join("rooms.obj"), dir.join("sky.json"));
    let file = ShvolFile::read(&volume).unwrap();
    let view = file.view();
    assert!(view.visibility.is_some());
    let (w, h) = (64usize, 48usize);
    let render = |name: &str, eye: Vec3, target: Vec3| {
        let image = dir.join(name);
        let at = |v: Vec3| format!("{},{},{}", v.x, v.y, v.z);
        shlight_ok(&[
            "render-mesh",
            s(&rooms),
            "--volume",
            s(&volume),
            "--env",
            s(&env),
            // The object (the bundled bunny) in the lit room, out of the
            // dark room's sight.
            "--at",
            "1,0.3,1",
            "--object-size",
            "0.3",
            "--camera",
            &at(eye),
            "--target",
            &at(target),
            "--size",
            &format!("{w}x{h}"),
            "-o",
            s(&image),
        ]);
        shlight_io::read_image(&image, &Default::default()).unwrap()
    };
    // From each room towards the wall's middle.
    let dark_eye = Vec3::new(3.7, 0.75, 1.0);
    let dark = render("dark.exr", dark_eye, Vec3::new(2.12, 0.75, 1.0));
    let lit = render(
        "lit.exr",
        Vec3::new(0.3, 0.75, 1.0),
        Vec3::new(2.08, 0.75, 1.0),
    );
    let grey = |p: &[f32; 3]| f64::from(p[0] + p[1] + p[2]) / 3.0;
    let lit_mean = lit.pixels().iter().map(grey).sum::<f64>() / (w * h) as f64;
    assert!(lit_mean > 0.05, "the lamp lights its room: {lit_mean}");
    let dark_max = dark.pixels().iter().map(grey).fold(0.0, f64::max);
    // The pixels against the CPU's lookup, and what trilinear
    // interpolation would show there.
    let scene = shlight_mesh::load(&rooms).unwrap();
    let bvh = shlight_rays::Occluder::new(&scene);
    let meshes = [(&scene, &bvh)];
    let camera = shlight_gpu::Camera::looking_at(
        dark_eye,
        Vec3::new(2.12, 0.75, 1.0),
        1.0,
        35f32.to_radians(),
    );
    let inverse = camera.view_proj(w as f32 / h as f32).inverse();
    let ray = |x: f32, y: f32| {
        let ndc = glam::Vec2::new(x / w as f32 * 2.0 - 1.0, 1.0 - y / h as f32 * 2.0);
        let far = inverse.project_point3(ndc.extend(1.0));
        (dark_eye, (far - dark_eye).normalize())
    };
    let (mut checked, mut trilinear_max, mut worst) = (0, 0.0f64, 0.0f64);
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let Some(hit) = pixel_hit(&meshes, ray, i, j) else {
                continue;
            };
            if !hit.inside || hit.normal.dot(hit.direction).abs() < GRAZING {
                continue;
            }
            let albedo = Vec3::splat(0.8).as_dvec3() / std::f64::consts::PI;
            let want = albedo * irradiance_at(&view, Lookup::Shlight, 2, hit.point, hit.normal);
            let trilinear =
                albedo * irradiance_at(&view, Lookup::Trilinear, 2, hit.point, hit.normal);
            let got = Vec3::from_array(dark.pixels()[j * w + i]).as_dvec3();
            let err = (got - want).abs().max_element() / lit_mean;
            worst = worst.max(err);
            assert!(
                err < PIXEL_TOL,
                "pixel ({i}, {j}) at {}: GPU {got}, CPU {want}",
                hit.point
            );
            trilinear_max = trilinear_max.max(trilinear.element_sum() / 3.0);
            checked += 1;
        }
    }
    eprintln!(
        "dark side of the wall: brightest pixel {:.2}% of the lit room's mean pixel \
         ({lit_mean:.3}); trilinear interpolation would show {:.1}%; {checked} pixels within \
         {worst:.1e} of the lit mean of the CPU's lookup",
        100.0 * dark_max / lit_mean,
        100.0 * trilinear_max / lit_mean
    );
    assert!(checked >= 500, "only {checked} pixels checked");
    assert!(dark_max <= 0.02 * lit_mean, "{dark_max} of {lit_mean}");
    assert!(trilinear_max > 0.1 * lit_mean, "{trilinear_max}");
}

//! Rays per second through an instanced scene on both cores: 100
//! instances of a 10,000-triangle torus (1,000,000 triangles flattened),
//! turned and scattered over a 10 x 10 grid, and the same rays for every
//! structure: 64 stratified directions from each of 1,024 probe points
//! above and among the tori (65,536 rays), cast direction by direction as
//! a volume bake casts probe rays.
//!
//! - `flat_*`: shlight-rays's `Occluder` over the flattened scene, one ray
//!   at a time; `flat_packets_closest`: its AVX2 packets of eight probes
//!   along one direction (`packet_closest_direct`);
//! - `two_level_*`: `InstancedOccluder`, one BVH for the torus and one
//!   over the instances, one ray at a time;
//! - `obvhs_flat_closest`: obvhs's CWBVH8 over the flattened triangles,
//!   its Möller-Trumbore test;
//! - `obvhs_two_level_closest`: obvhs's CWBVH8 over the instances' world
//!   boxes and one over the torus, the ray taken into each instance's
//!   space (obvhs's own `ray_traverse_tlas_blas` does not transform rays,
//!   so the two levels are nested `ray_traverse` calls).
//!
//! `cargo bench -p shlight-rays --bench instances`; divan's "items/s" is
//! rays/s. The acceleration structures' bytes are printed once
//! (`heap_bytes`; obvhs's nodes and indices).

use std::sync::OnceLock;
use std::time::Duration;

use divan::Bencher;
use divan::counter::ItemsCount;
use glam::{Mat4, Quat, Vec3};
use glam_obvhs::Vec3A;
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::{build_cwbvh, build_cwbvh_from_tris};
use obvhs::ray::{Ray as ORay, RayHit};
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use shlight_core::map::montecarlo::stratified_directions;
use shlight_mesh::{Instance, Mesh, Primitive, Scene, generate};
use shlight_rays::{Direction, InstancedOccluder, LANES, Occluder, Packet, Ray};

fn main() {
    divan::main();
}

const GRID: usize = 10;
const SPACING: f32 = 3.0;

/// The scene, the flattened mesh, and the rays: per direction, the probe
/// points.
struct Setup {
    scene: Scene,
    flat: Mesh,
    dirs: Vec<Vec3>,
    probes: Vec<Vec3>,
}

fn setup() -> &'static Setup {
    static SETUP: OnceLock<Setup> = OnceLock::new();
    SETUP.get_or_init(|| {
        let torus = generate::torus(1.0, 0.3, 100, 50);
        let instances = (0..GRID * GRID)
            .map(|i| {
                let at = Vec3::new((i % GRID) as f32, 0.0, (i / GRID) as f32) * SPACING;
                let turn = Quat::from_euler(glam::EulerRot::XYZ, i as f32, 0.7 * i as f32, 0.0);
                Instance {
                    primitive: 0,
                    transform: Mat4::from_rotation_translation(turn, at),
                }
            })
            .collect();
        let scene = Scene {
            source: "grid.glb".into(),
            primitives: vec![Primitive::new(torus, None, "torus")],
            instances,
            ..Scene::default()
        };
        let flat = scene.flatten(Vec3::ONE).unwrap().mesh;
        let dirs = stratified_directions(64, 0)
            .iter()
            .map(|d| d.as_vec3())
            .collect();
        // 32 x 32 probes over the grid, a layer between the tori's centres.
        let extent = SPACING * (GRID - 1) as f32;
        let probes = (0..1024)
            .map(|k| {
                let (x, z) = ((k % 32) as f32 + 0.5, (k / 32) as f32 + 0.5);
                Vec3::new(
                    x / 32.0 * extent,
                    0.2 * ((k % 3) as f32 - 1.0),
                    z / 32.0 * extent,
                )
            })
            .collect();
        let s = Setup {
            scene,
            flat,
            dirs,
            probes,
        };
        print_memory(&s);
        s
    })
}

fn rays(s: &Setup) -> Vec<(Vec3, Vec3)> {
    s.dirs
        .iter()
        .flat_map(|d| s.probes.iter().map(move |o| (*o, *d)))
        .collect()
}

fn print_memory(s: &Setup) {
    let flat = Occluder::new(&s.flat).heap_bytes();
    let two_level = InstancedOccluder::new(&s.scene).unwrap().heap_bytes();
    let (tlas, blas, _) = obvhs_two_level(s);
    let cwbvh =
        |b: &CwBvh| b.nodes.len() * size_of_val(&b.nodes[0]) + b.primitive_indices.len() * 4;
    let obvhs_flat = build_cwbvh_from_tris(
        &obvhs_tris(&s.flat),
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    eprintln!(
        "heap bytes, {} instances of {} triangles: shlight flat {flat}, shlight two-level \
         {two_level}; obvhs CWBVH flat {} (+ {} of triangles), two-level {} (+ {} of triangles)",
        s.scene.instances.len(),
        s.scene.primitives[0].mesh.triangle_count(),
        cwbvh(&obvhs_flat),
        s.flat.triangle_count() * size_of::<Triangle>(),
        cwbvh(&tlas) + cwbvh(&blas),
        s.scene.primitives[0].mesh.triangle_count() * size_of::<Triangle>(),
    );
}

/// Times `hit` over every ray in parallel; items are rays.
fn cast_each<R: Sync>(bencher: Bencher, rays: &[R], hit: impl Fn(&R) -> bool + Sync) {
    bencher
        .counter(ItemsCount::new(rays.len()))
        .bench(|| rays.par_iter().filter(|r| hit(r)).count());
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn flat_closest(bencher: Bencher) {
    let s = setup();
    let occluder = Occluder::new(&s.flat);
    cast_each(bencher, &rays(s), |(o, d)| {
        occluder
            .closest_hit(&Ray::new(*o, *d, f32::INFINITY))
            .is_some()
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn flat_occluded(bencher: Bencher) {
    let s = setup();
    let occluder = Occluder::new(&s.flat);
    cast_each(bencher, &rays(s), |(o, d)| {
        occluder.occluded(&Ray::new(*o, *d, f32::INFINITY))
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn flat_packets_closest(bencher: Bencher) {
    let s = setup();
    let occluder = Occluder::new(&s.flat);
    let count = s.dirs.len() * s.probes.len();
    bencher.counter(ItemsCount::new(count)).bench(|| {
        s.dirs
            .par_iter()
            .map(|d| {
                let dir = Direction::new(*d);
                s.probes
                    .chunks(LANES)
                    .map(|eight| {
                        let hits = occluder.packet_closest_direct(&dir, &Packet::new(&dir, eight));
                        hits.mask.count_ones()
                    })
                    .sum::<u32>()
            })
            .sum::<u32>()
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn two_level_closest(bencher: Bencher) {
    let s = setup();
    let occluder = InstancedOccluder::new(&s.scene).unwrap();
    cast_each(bencher, &rays(s), |(o, d)| {
        occluder
            .closest_hit(&Ray::new(*o, *d, f32::INFINITY))
            .is_some()
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn two_level_occluded(bencher: Bencher) {
    let s = setup();
    let occluder = InstancedOccluder::new(&s.scene).unwrap();
    cast_each(bencher, &rays(s), |(o, d)| {
        occluder.occluded(&Ray::new(*o, *d, f32::INFINITY))
    });
}

fn v3a(p: Vec3) -> Vec3A {
    Vec3A::new(p.x, p.y, p.z)
}

fn obvhs_tris(m: &Mesh) -> Vec<Triangle> {
    m.triangles
        .iter()
        .map(|t| Triangle {
            v0: v3a(m.positions[t[0] as usize]),
            v1: v3a(m.positions[t[1] as usize]),
            v2: v3a(m.positions[t[2] as usize]),
        })
        .collect()
}

fn obvhs_rays(s: &Setup) -> Vec<ORay> {
    rays(s)
        .into_iter()
        .map(|(o, d)| ORay::new_inf(v3a(o), v3a(d)))
        .collect()
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn obvhs_flat_closest(bencher: Bencher) {
    let s = setup();
    let tris = obvhs_tris(&s.flat);
    let bvh = build_cwbvh_from_tris(
        &tris,
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    cast_each(bencher, &obvhs_rays(s), |ray| {
        bvh.ray_traverse(*ray, &mut RayHit::none(), |r, id| {
            tris[bvh.primitive_indices[id] as usize].intersect(r)
        })
    });
}

/// obvhs's two levels: the instances' CWBVH, the torus's, and per
/// instance the world-to-torus transform.
fn obvhs_two_level(s: &Setup) -> (CwBvh, CwBvh, Vec<glam_obvhs::Affine3A>) {
    let mesh = &s.scene.primitives[0].mesh;
    let blas = build_cwbvh_from_tris(
        &obvhs_tris(mesh),
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    let (lo, hi) = mesh.bounds();
    let mut boxes = Vec::new();
    let mut inverses = Vec::new();
    for instance in &s.scene.instances {
        let mut b = Aabb::empty();
        for k in 0..8 {
            let c = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            b.extend(v3a(instance.transform.transform_point3(c)));
        }
        boxes.push(b);
        let inv = instance.transform.inverse().to_cols_array();
        inverses.push(glam_obvhs::Affine3A::from_mat4(
            glam_obvhs::Mat4::from_cols_array(&inv),
        ));
    }
    let tlas = build_cwbvh(
        &boxes,
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    (tlas, blas, inverses)
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn obvhs_two_level_closest(bencher: Bencher) {
    let s = setup();
    let tris = obvhs_tris(&s.scene.primitives[0].mesh);
    let (tlas, blas, inverses) = obvhs_two_level(s);
    cast_each(bencher, &obvhs_rays(s), |ray| {
        tlas.ray_traverse(*ray, &mut RayHit::none(), |r, id| {
            let inv = &inverses[tlas.primitive_indices[id] as usize];
            let local = ORay::new(
                inv.transform_point3a(r.origin),
                inv.transform_vector3a(r.direction),
                0.0,
                r.tmax,
            );
            let mut hit = RayHit::none();
            if blas.ray_traverse(local, &mut hit, |r, id| {
                tris[blas.primitive_indices[id] as usize].intersect(r)
            }) {
                hit.t
            } else {
                f32::INFINITY
            }
        })
    });
}

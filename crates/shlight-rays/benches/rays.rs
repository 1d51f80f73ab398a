//! Rays per second of PRT visibility rays (vertex origins offset along the
//! normal, the shared stratified directions above each vertex) on both
//! cores, any-hit and closest-hit, on the bundled bunny (3,674 triangles)
//! and a generated torus of 69,696 triangles:
//!
//! - `packets_*`: what baking does: direction by direction, the vertices
//!   facing it in Morton order, eight parallel rays per AVX2 packet through
//!   shlight-rays's binned-SAH hierarchy (`Occluder`, `packet.rs`), the
//!   ray-space vertices computed per direction included;
//! - `single_*`: the same hierarchy one ray at a time, in vertex order (the
//!   path of processors without AVX2);
//! - `obvhs_*`: the obvhs crate's CWBVH8 and BVH2 with its own
//!   Möller-Trumbore test, one ray at a time.
//!
//! `cargo bench -p shlight-rays --bench rays`; divan's "items/s" is rays/s.

use std::path::Path;
use std::time::Duration;

use divan::Bencher;
use divan::counter::ItemsCount;
use glam::Vec3;
use glam_obvhs::{UVec2, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::bvh2::builder::build_bvh2_from_tris;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::{Ray as ORay, RayHit};
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use shlight_core::map::montecarlo::stratified_directions;
use shlight_mesh::{Mesh, generate};
use shlight_rays::{OFFSET, Occluder, Ray};

#[path = "rays/cast.rs"]
mod cast;

fn main() {
    divan::main();
}

/// About `count` PRT rays: every `step`-th vertex, all 1035 directions of
/// the 1024-sample grid that lie above its tangent plane.
fn rays(mesh: &Mesh, count: usize) -> Vec<(Vec3, Vec3)> {
    let dirs: Vec<Vec3> = stratified_directions(1024, 0)
        .iter()
        .map(|d| d.as_vec3())
        .collect();
    let (lo, hi) = mesh.bounds();
    let eps = OFFSET * (hi - lo).length();
    let step = (mesh.vertex_count() * dirs.len() / 2 / count).max(1);
    let mut out = Vec::new();
    for v in (0..mesh.vertex_count()).step_by(step) {
        let (p, n) = (mesh.positions[v], mesh.normals[v]);
        out.extend(
            dirs.iter()
                .filter(|d| d.dot(n) > 0.0)
                .map(|d| (p + eps * n, *d)),
        );
    }
    out
}

fn mesh(name: &str) -> Mesh {
    match name {
        "bunny" => shlight_mesh::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/bunny.obj"),
        )
        .unwrap(),
        _ => generate::torus(1.0, 0.4, 264, 132),
    }
}

const MESHES: &[&str] = &["bunny", "torus70k"];
const RAYS: usize = 400_000;

/// Times `hit` over every ray in parallel; items are rays.
fn cast_each<R: Sync>(bencher: Bencher, rays: &[R], hit: impl Fn(&R) -> bool + Sync) {
    bencher
        .counter(ItemsCount::new(rays.len()))
        .bench(|| rays.par_iter().filter(|r| hit(r)).count());
}

#[divan::bench(args = MESHES, sample_count = 5, sample_size = 1)]
fn single_occluded(bencher: Bencher, name: &str) {
    let m = mesh(name);
    let occluder = Occluder::new(&m);
    let rays = rays(&m, RAYS);
    cast_each(bencher, &rays, |(o, d)| {
        occluder.occluded(&Ray::new(*o, *d, f32::INFINITY))
    });
}

#[divan::bench(args = MESHES, sample_count = 5, sample_size = 1)]
fn single_closest(bencher: Bencher, name: &str) {
    let m = mesh(name);
    let occluder = Occluder::new(&m);
    let rays = rays(&m, RAYS);
    cast_each(bencher, &rays, |(o, d)| {
        occluder
            .closest_hit(&Ray::new(*o, *d, f32::INFINITY))
            .is_some()
    });
}

/// Every 8th direction of the 1024-direction grid, with the rays baking
/// casts along it (`cast::bake_rays`): about as many rays as [`rays`]
/// gives, cast direction-major.
fn direction_major(mesh: &Mesh, occluder: &Occluder) -> Vec<(Vec3, Vec<Vec3>)> {
    let dirs: Vec<Vec3> = stratified_directions(1024, 0)
        .iter()
        .map(|d| d.as_vec3())
        .step_by(8)
        .collect();
    cast::bake_rays(mesh, occluder, &dirs)
}

fn packet_bench(bencher: Bencher, name: &str, closest: bool) {
    let m = mesh(name);
    let occluder = Occluder::new(&m);
    let per_dir = direction_major(&m, &occluder);
    let count: usize = per_dir.iter().map(|(_, o)| o.len()).sum();
    bencher
        .counter(ItemsCount::new(count))
        .bench(|| cast::cast_packets(&occluder, &per_dir, closest));
}

#[divan::bench(args = MESHES, sample_count = 5, sample_size = 1)]
fn packets_occluded(bencher: Bencher, name: &str) {
    packet_bench(bencher, name, false);
}

#[divan::bench(args = MESHES, sample_count = 5, sample_size = 1)]
fn packets_closest(bencher: Bencher, name: &str) {
    packet_bench(bencher, name, true);
}

fn obvhs_input(m: &Mesh) -> (Vec<Triangle>, Vec<ORay>) {
    let v = |p: Vec3| Vec3A::new(p.x, p.y, p.z);
    let tris = m
        .triangles
        .iter()
        .map(|t| Triangle {
            v0: v(m.positions[t[0] as usize]),
            v1: v(m.positions[t[1] as usize]),
            v2: v(m.positions[t[2] as usize]),
        })
        .collect();
    let rays = rays(m, RAYS)
        .into_iter()
        .map(|(o, d)| ORay::new_inf(v(o), v(d)))
        .collect();
    (tris, rays)
}

#[divan::bench(args = MESHES, sample_count = 5, sample_size = 1)]
fn obvhs_cwbvh_occluded(bencher: Bencher, name: &str) {
    let (tris, rays) = obvhs_input(&mesh(name));
    let bvh = build_cwbvh_from_tris(
        &tris,
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    cast_each(bencher, &rays, |ray| {
        let mut state = bvh.new_traversal(ray.direction);
        let mut node;
        let mut hit = false;
        obvhs::traverse!(bvh, node, state, node.intersect_ray(ray, state.oct_inv4), {
            let t =
                tris[bvh.primitive_indices[state.primitive_id as usize] as usize].intersect(ray);
            if t < ray.tmax {
                // Any hit ends the search: empty the traversal state.
                hit = true;
                state.stack.clear();
                state.current_group = UVec2::ZERO;
                state.primitive_group = UVec2::ZERO;
                break;
            }
        });
        hit
    });
}

#[divan::bench(args = MESHES, sample_count = 5, sample_size = 1)]
fn obvhs_cwbvh_closest(bencher: Bencher, name: &str) {
    let (tris, rays) = obvhs_input(&mesh(name));
    let bvh = build_cwbvh_from_tris(
        &tris,
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    cast_each(bencher, &rays, |ray| {
        bvh.ray_traverse(*ray, &mut RayHit::none(), |r, id| {
            tris[bvh.primitive_indices[id] as usize].intersect(r)
        })
    });
}

#[divan::bench(args = MESHES, sample_count = 5, sample_size = 1)]
fn obvhs_bvh2_closest(bencher: Bencher, name: &str) {
    let (tris, rays) = obvhs_input(&mesh(name));
    let bvh = build_bvh2_from_tris(
        &tris,
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    cast_each(bencher, &rays, |ray| {
        bvh.ray_traverse(*ray, &mut RayHit::none(), |r, id| {
            tris[bvh.primitive_indices[id] as usize].intersect(r)
        })
    });
}

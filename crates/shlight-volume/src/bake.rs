//! Baking a probe volume through a scene: [`bake`], whose documentation
//! states what a probe holds, the estimator, and how the rays are cast and
//! summed.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;
use rayon::prelude::*;
use shlight_core::map::montecarlo::stratified_directions;
use shlight_core::sh::{ShBasis, sh_count};
use shlight_mesh::{LightUnits, Mesh, PunctualLight, Subdivision, Surfaces};
use shlight_prt::{Albedo, BackSides, BakeOptions, Kernels, Mode, VertexRecords};
use shlight_rays::{Direction, LANES, Occluder, Packet};

use shlight_baked::visibility::MomentFilter;
use shlight_baked::{ProbeGrid, ProbeVisibility, Visibility};

use crate::error::VolumeError;
use crate::volume_bake::VolumeBake;

mod hit;
mod punctual;
pub mod relocate;
mod sums;
mod surface_points;

use hit::Hit;
use sums::{Rows, block_sum};
pub use surface_points::{SurfaceLight, SurfacePoint, SurfacePointsBake, gather_at_surface_points};

/// What to bake.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeOptions {
    /// Highest SH degree of the probes and of the environment they take.
    pub lmax: usize,
    /// Rays per probe (rounded to a whole stratified grid).
    pub samples: usize,
    /// Interreflection bounces of the surfaces' light (0: direct light
    /// through shadows only).
    pub bounces: u32,
    /// Directions per surface vertex for the surfaces' transfer.
    pub surface_samples: usize,
    /// Longest surface edge before the surface is subdivided, in scene
    /// units; `None`: the scene's bounding-box diagonal over
    /// [`SURFACE_DIVISIONS`].
    pub max_edge: Option<f32>,
    /// Diffuse albedo of surfaces without vertex colours (linear RGB).
    pub albedo: [f32; 3],
    /// A probe is invalid when more than this fraction of its rays hit back
    /// faces.
    pub invalid_backfaces: f32,
    /// Seed of the direction sets.
    pub seed: u64,
    /// Move probes inside geometry, or nearer a surface than
    /// [`relocate::CLEARANCE`] of their cell, to free space within their
    /// cell before their rays are cast ([`relocate`]).
    pub relocate: bool,
    /// Texels per side of each probe's distance map for the
    /// visibility-weighted lookup ([`shlight_baked::visibility`]); 0: no
    /// maps.
    pub visibility_size: usize,
    /// How the intensities of the scene's punctual lights become
    /// radiometric units ([`bake_with_lights`]; no effect without lights).
    pub light_units: LightUnits,
}

/// Default subdivision: edges no longer than the scene's diagonal over this.
pub const SURFACE_DIVISIONS: f32 = 32.0;

/// The most triangles a scene's surfaces may be subdivided into
/// ([`VolumeOptions::max_edge`]), as estimated before subdividing.
pub const MAX_SUBDIVIDED_TRIANGLES: usize = 20_000_000;

/// Refuses a [`VolumeOptions::max_edge`] that is not a positive finite
/// length, or that would split `mesh` into more than
/// [`MAX_SUBDIVIDED_TRIANGLES`]: each triangle whose longest edge is `e`
/// becomes about `2 (e / max_edge)^2` (halving the longest edge until none
/// is longer makes that many at most, to within a small factor).
fn check_max_edge(mesh: &Mesh, max_edge: Option<f32>) -> Result<(), VolumeError> {
    let Some(max_edge) = max_edge else {
        return Ok(());
    };
    if !(max_edge.is_finite() && max_edge > 0.0) {
        return Err(VolumeError::Options(format!(
            "a longest surface edge of {max_edge} is not a positive length"
        )));
    }
    let estimate: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let e = (b - a).length().max((c - b).length()).max((a - c).length());
            (2.0 * (f64::from(e) / f64::from(max_edge)).powi(2)).max(1.0)
        })
        .sum();
    if estimate > MAX_SUBDIVIDED_TRIANGLES as f64 {
        return Err(VolumeError::Options(format!(
            "a longest surface edge of {max_edge} would split the scene's {} triangles into about {:.0}; at most {MAX_SUBDIVIDED_TRIANGLES}",
            mesh.triangle_count(),
            estimate
        )));
    }
    Ok(())
}

impl Default for VolumeOptions {
    fn default() -> Self {
        Self {
            lmax: 2,
            samples: 1024,
            bounces: 2,
            surface_samples: 512,
            max_edge: None,
            albedo: [0.8; 3],
            invalid_backfaces: 0.5,
            seed: 0,
            relocate: true,
            visibility_size: shlight_baked::visibility::VISIBILITY_SIZE,
            light_units: LightUnits::Blender,
        }
    }
}

/// Where a bake is, for progress bars.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The surfaces' transfer (the PRT bake's stages).
    Surface(shlight_prt::Stage),
    /// Moving probes out of geometry (`done` and `total` in probes; the
    /// probes are moved while the surfaces are baked, and this stage is
    /// reported, begun and done, once the surfaces' stages are).
    Relocate,
    /// Casting the probes' rays (`done` and `total` in directions).
    Probes,
    /// Gathering light at surface points
    /// ([`gather_at_surface_points`]; `done` and `total` in points).
    Points,
}

/// Bakes the probes of `grid` through `scene` (`None`: nothing in the
/// way). The result is relightable: [`VolumeBake::relight`] gives the
/// probes for any environment. [`bake_with_lights`] bakes a scene with
/// punctual lights.
///
/// `progress(stage, done, total)` is called from worker threads as work
/// finishes.
///
/// # What a probe holds
/// The SH projection of the radiance arriving at its position `x` from
/// every direction `s`:
///
/// ```text
/// L(x, s) = L_env(s)                 where the ray from x along s escapes,
///         = T(q) . L_env + E(q)      where it first hits the front of a surface at q,
///         = 0                        where it hits the back of one,
/// ```
///
/// `T(q)` being the surface's interreflected diffuse transfer (shadowed
/// direct light plus `bounces` bounces, [`shlight_prt::Transfer`]) and
/// `E(q)` its exit radiance due to emitters (their emission plus the same
/// bounces). Both are linear in the environment's coefficients, so per
/// probe and channel `c`
///
/// ```text
/// L_probe,c = M_c L_env,c + L_emitted,c
/// M_c[i][k] = delta_ik - int_blocked Y_i(s) Y_k(s) ds + int_front Y_i(s) T_c,k(q(s)) ds
/// L_emitted,c[i] = int_front Y_i(s) E_c(q(s)) ds
/// ```
///
/// # Estimator
/// One jittered equal-area set of `N` directions
/// ([`shlight_core::map::montecarlo::stratified_directions`], seeded) serves
/// every probe, each with weight `4 pi / N`. The sky's part, `delta_ik -
/// int_blocked Y_i Y_k`, is estimated from whichever of the escaping and the
/// blocked rays are fewer: `w sum_escaped Y_i Y_k` when most rays are
/// blocked, `delta_ik - w sum_blocked Y_i Y_k` (a control variate) when
/// most escape. So a probe that sees no geometry equals the environment
/// exactly, one in a closed room gets no sky light at all, and the variance
/// comes from the smaller set. Surfaces are one-sided: a ray that meets the back of a
/// triangle brings no light, and a probe for which more than
/// [`VolumeOptions::invalid_backfaces`] of the rays do so is inside
/// geometry and marked invalid. The exception is a glTF material's
/// `doubleSided` ([`bake_surfaces`]). `T(q)` and `E(q)` are the barycentric
/// interpolation of the surface's vertex values; long edges are first split
/// ([`shlight_mesh::Mesh::subdivided_with_map`]) so that vertices hold
/// shadows.
///
/// Through a glTF scene's surfaces ([`bake_surfaces`]) a ray passes the
/// cut-outs of triangles whose material cuts out
/// ([`shlight_rays::CutOuts`]: a cut-out texel lets every ray through, a
/// `BLEND` material's alpha stops that share of them, deterministically),
/// and the point it hits leaves the albedo `rho(q)` of the texel there
/// ([`Surfaces::sample`] at the hit) times the light arriving, interpolated
/// from the vertices ([`shlight_prt::IncidentTransfer`]):
/// `T(q) = rho(q) G(q)` and `E(q) = Le(q) + rho(q) F(q)`, the emission
/// itself not multiplied by it. A triangle whose material is double-sided
/// ([`shlight_mesh::Material::double_sided`]) is a surface on both faces:
/// its vertices have back copies facing the other way, whose light is
/// baked as any vertex's ([`shlight_prt::BackSides`]), and a ray that
/// meets its back is a front hit of its back triangle, reading the back
/// copies' `G` and `F` (its emission too: a double-sided emitter emits
/// from both faces); it is no back face for the probe's validity, its
/// relocation ([`relocate::offsets_two_sided`]) or its distance map. A
/// scene without a double-sided material bakes as before, bit for bit.
///
/// # Casting and summing
/// The probes' rays along one direction are parallel: the probes are taken
/// eight at a time in Morton order of their grid cells and traced as one
/// [`Packet`] ([`Occluder::packet_closest`]) against the
/// scene's own triangles, not the subdivided ones (the same surface; a room
/// of large quads has a few dozen instead of a hundred thousand), and each
/// front hit is found in the subdivided mesh by
/// [`Subdivision::locate_each`]; the surfaces' transfer is cast the same
/// way, against the same hierarchy ([`Occluder`],
/// [`shlight_prt::bake_against`]).
///
/// The directions are cut into blocks of 64 that are small patches of the
/// sphere (`direction_order`: halves across the widest axis, down to
/// single blocks), cast in parallel for as many probes at a time as keep
/// their hits within 256 MB (12 bytes a ray): within a block each packet
/// of probes goes through the block's directions in turn, so its rays walk
/// the same part of the hierarchy and meet the scene in one region, and
/// its front hits in the block are located together. Then each probe sums
/// its rays block by block, in `f32` within a block and `f64` across
/// blocks: a row `v = (Y(s), T(q), E(q))` per ray (the transfer and the
/// emitters' light interpolated at the hit from 64-byte vertex records;
/// `(Y(s), 0)` at a back face, zeros for an escaped ray) and the block's
/// `sum Y(s) v^T`, a small matrix product, giving the blocked `sum Y Y^T`,
/// `sum Y T^T` and `sum Y E` together (a grey surface's transfer summed
/// once for the three channels). With AVX2 and FMA (detected at run time)
/// the product keeps 3 rows by 24 columns of the sums in registers;
/// portable loops compute the same sums elsewhere. `sum_escaped Y Y^T` is
/// `sum_all Y Y^T`, summed once the same way for every probe, less the
/// blocked sum, so a probe that sees no sky gets exactly none. Every sum
/// runs in a fixed order, so the result is the same bit for bit at any
/// thread count for a seed.
///
/// # Errors
/// An lmax beyond [`shlight_baked::MAX_LMAX`], no samples, or an albedo or
/// `invalid_backfaces` outside 0..=1.
pub fn bake(
    scene: Option<&Mesh>,
    grid: &ProbeGrid,
    options: &VolumeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Result<VolumeBake, VolumeError> {
    bake_with_lights(scene, &[], grid, options, progress)
}

/// [`bake`] of a scene lit by punctual lights too (glTF's
/// `KHR_lights_punctual`, their intensities read in
/// [`VolumeOptions::light_units`]), as a path tracer such as Cycles lights
/// it: they are deltas, so their direct light is found with a shadow ray
/// wherever light is gathered.
///
/// - At each probe `x`, each light whose shadow ray from `x` reaches it
///   adds the exact SH projection of its radiance `E_perp delta(s -
///   toward)`, `E_perp Y_lm(toward)` ([`PunctualLight::arriving`] gives
///   `E_perp` and `toward`), to the probe's static light `L_emitted`.
/// - At each vertex of the subdivided surfaces, `E_direct = sum E_perp
///   max(n . toward, 0)` over the lights its shadow ray (from where its
///   transfer's rays start) reaches; a light behind the surface gives
///   nothing. `albedo / pi E_direct` is then a source of exit radiance
///   beside the emitters' ([`shlight_prt::BakeOptions::direct_irradiance`])
///   and bounces as theirs does, so probes see lit surfaces in `E(q)`.
///
/// Their light is static, like the emitters': a relit volume keeps it.
/// Without lights this is [`bake`], bit for bit.
///
/// # Errors
/// As [`bake`].
pub fn bake_with_lights(
    scene: Option<&Mesh>,
    lights: &[PunctualLight],
    grid: &ProbeGrid,
    options: &VolumeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Result<VolumeBake, VolumeError> {
    bake_in_chunks(
        scene.map(|m| (m, None)),
        lights,
        grid,
        options,
        progress,
        HITS_MEMORY,
        Kernels::detect(),
    )
}

/// [`bake_with_lights`] through a flattened glTF scene
/// ([`shlight_mesh::Scene::flatten`]) and its punctual `lights` (none for a
/// scene without): its mesh, with cut-outs the rays pass (the lights'
/// shadow rays too) and the albedo of the texel each ray hits ([`bake`]
/// states both; the lights' light on a surface is read times that albedo
/// as the environment's is). The surfaces' vertex albedo is the mesh's
/// colours; [`VolumeOptions::albedo`] is not read.
///
/// # Errors
/// As [`bake`].
pub fn bake_surfaces(
    surfaces: &Arc<Surfaces>,
    lights: &[PunctualLight],
    grid: &ProbeGrid,
    options: &VolumeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Result<VolumeBake, VolumeError> {
    bake_in_chunks(
        Some((&surfaces.mesh, Some(surfaces))),
        lights,
        grid,
        options,
        progress,
        HITS_MEMORY,
        Kernels::detect(),
    )
}

/// [`bake_with_lights`] through `scene` and its surfaces, if any, keeping
/// at most `hits_memory` bytes of probe hits at a time, the probes' sums
/// with `kernels`.
fn bake_in_chunks(
    scene: Option<(&Mesh, Option<&Arc<Surfaces>>)>,
    lights: &[PunctualLight],
    grid: &ProbeGrid,
    options: &VolumeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
    hits_memory: usize,
    kernels: Kernels,
) -> Result<VolumeBake, VolumeError> {
    check_options(options)?;
    let lmax = options.lmax;
    if let Some((mesh, _)) = scene {
        check_max_edge(mesh, options.max_edge)?;
    }
    let nc = sh_count(lmax);
    // The directions in compact blocks (`direction_order`).
    let set: Vec<Vec3> = stratified_directions(options.samples, options.seed)
        .iter()
        .map(|d| d.as_vec3())
        .collect();
    let dirs: Vec<Vec3> = direction_order(&set).into_iter().map(|i| set[i]).collect();
    let basis = ShBasis::<f64>::new(lmax);
    let mut ylm = vec![0.0f64; dirs.len() * nc];
    for (d, row) in dirs.iter().zip(ylm.chunks_exact_mut(nc)) {
        basis.eval(d.as_dvec3(), row);
    }
    let weight = 4.0 * std::f64::consts::PI / dirs.len() as f64;

    // The surfaces, and the probes moved out of geometry before their rays
    // are cast (found while the surfaces are baked, reported after).
    let (surface, moved) = match scene {
        Some((mesh, surfaces)) => {
            let relocate = options.relocate.then_some(grid);
            let (s, o) = Surface::bake(mesh, surfaces, lights, options, relocate, progress);
            (Some(s), o)
        }
        None => (None, None),
    };
    let scene = scene.map(|(mesh, _)| mesh);
    let offsets: Option<Vec<Vec3>> = options.relocate.then(|| match moved {
        Some(o) => {
            progress(Stage::Relocate, 0, grid.probe_count());
            progress(Stage::Relocate, grid.probe_count(), grid.probe_count());
            o
        }
        None => vec![Vec3::ZERO; grid.probe_count()],
    });
    let probes: Vec<Vec3> = match &offsets {
        Some(o) => grid.centres().iter().zip(o).map(|(c, o)| *c + *o).collect(),
        None => grid.centres(),
    };
    let max_distance = shlight_baked::visibility::max_distance(grid);
    let filter =
        (options.visibility_size > 0).then(|| MomentFilter::new(options.visibility_size, &dirs));
    let per_map = Visibility::floats_per_probe(options.visibility_size);
    let mut moments = vec![
        0.0f32;
        if filter.is_some() {
            probes.len() * per_map
        } else {
            0
        }
    ];
    let mut transfer = vec![0.0f32; probes.len() * 3 * nc * nc];
    let mut emitted = vec![0.0f32; probes.len() * 3 * nc];
    let mut backfaces = vec![0.0f32; probes.len()];
    let mut rays = 0;
    match &surface {
        None => {
            let eye = identity(nc);
            for m in transfer.chunks_exact_mut(3 * nc * nc) {
                for (o, i) in m.iter_mut().zip(eye.iter().cycle()) {
                    *o = *i as f32;
                }
            }
            // Every ray escapes.
            for t in moments.chunks_exact_mut(2) {
                t.copy_from_slice(&[max_distance, max_distance * max_distance]);
            }
            progress(Stage::Probes, dirs.len(), dirs.len());
        }
        Some(s) => {
            rays = (dirs.len() * probes.len()) as u64;
            let ylm32: Vec<f32> = ylm.iter().map(|&y| y as f32).collect();
            let all = s.sum_all(kernels, &ylm32);
            // Probes in Morton order, as many at a time as keep the hits
            // within HITS_MEMORY (whole packets).
            let order = probe_order(grid);
            // A ray's hit, and with surfaces the albedo there.
            let per_ray = std::mem::size_of::<Hit>()
                + if s.texel {
                    std::mem::size_of::<Vec3>()
                } else {
                    0
                };
            let per_chunk = (hits_memory / (per_ray * dirs.len())).max(LANES) / LANES * LANES;
            let chunks = order.len().div_ceil(per_chunk);
            let done = AtomicUsize::new(0);
            let total = chunks * dirs.len();
            let mut m = Vec::new();
            let mut e = Vec::new();
            let mut back = Vec::new();
            let (mut hits, mut albedo) = (Vec::new(), Vec::new());
            for chunk in order.chunks(per_chunk) {
                s.cast(chunk, &probes, &dirs, (&mut hits, &mut albedo), &|len| {
                    progress(
                        Stage::Probes,
                        done.fetch_add(len, Ordering::Relaxed) + len,
                        total,
                    );
                });
                m.resize(chunk.len() * 3 * nc * nc, 0.0);
                e.resize(chunk.len() * 3 * nc, 0.0);
                back.resize(chunk.len(), 0.0);
                s.gather(
                    kernels,
                    (&hits, &albedo),
                    &ylm32,
                    &all,
                    weight,
                    (&mut m, &mut e, &mut back),
                );
                for (i, &p) in chunk.iter().enumerate() {
                    let p = p as usize;
                    transfer[p * 3 * nc * nc..][..3 * nc * nc]
                        .copy_from_slice(&m[i * 3 * nc * nc..][..3 * nc * nc]);
                    emitted[p * 3 * nc..][..3 * nc].copy_from_slice(&e[i * 3 * nc..][..3 * nc]);
                    backfaces[p] = back[i];
                }
                if let Some(filter) = &filter {
                    let mut maps = vec![0.0f32; chunk.len() * per_map];
                    distance_maps(filter, &hits, chunk.len(), max_distance, &mut maps);
                    for (i, &p) in chunk.iter().enumerate() {
                        moments[p as usize * per_map..][..per_map]
                            .copy_from_slice(&maps[i * per_map..][..per_map]);
                    }
                }
            }
        }
    }
    if !lights.is_empty() {
        punctual::add_to_probes(
            surface.as_ref().map(|s| &s.occluder),
            lights,
            options.light_units,
            &probes,
            lmax,
            &mut emitted,
        );
    }
    let valid = backfaces
        .iter()
        .map(|&f| f <= options.invalid_backfaces)
        .collect();
    Ok(VolumeBake {
        grid: *grid,
        lmax,
        valid,
        offsets: offsets.map(|o| o.iter().flat_map(|v| v.to_array()).collect()),
        visibility: filter.map(|_| ProbeVisibility {
            size: options.visibility_size,
            max_distance,
            moments,
        }),
        backfaces,
        transfer,
        emitted,
        samples: dirs.len(),
        bounces: options.bounces,
        seed: options.seed,
        rays: rays + surface.as_ref().map_or(0, |s| s.rays),
        scene_hash: scene.map_or(0, Mesh::content_hash),
        lights: shlight_prt::light_counts(lights, options.light_units),
    })
}

/// Refuses what no bake can take: an lmax beyond
/// [`shlight_baked::MAX_LMAX`], no samples, an albedo or
/// `invalid_backfaces` outside 0..=1, visibility maps over their limit.
fn check_options(options: &VolumeOptions) -> Result<(), VolumeError> {
    if options.lmax > shlight_baked::MAX_LMAX {
        return Err(VolumeError::Options(format!(
            "lmax {} is beyond {}, the most a volume holds",
            options.lmax,
            shlight_baked::MAX_LMAX
        )));
    }
    if options.samples == 0 || options.surface_samples == 0 {
        return Err(VolumeError::Options("samples must be at least 1".into()));
    }
    if !options.albedo.iter().all(|a| (0.0..=1.0).contains(a)) {
        return Err(VolumeError::Options(format!(
            "albedo {:?} is not within 0..=1",
            options.albedo
        )));
    }
    if options.visibility_size > shlight_baked::visibility::MAX_VISIBILITY_SIZE {
        return Err(VolumeError::Options(format!(
            "visibility maps of {0}x{0} texels: at most {1}x{1}",
            options.visibility_size,
            shlight_baked::visibility::MAX_VISIBILITY_SIZE
        )));
    }
    if !(0.0..=1.0).contains(&options.invalid_backfaces) {
        return Err(VolumeError::Options(format!(
            "invalid_backfaces {} is not within 0..=1",
            options.invalid_backfaces
        )));
    }
    Ok(())
}

/// The distance maps of a chunk's probes from their hits (laid out as
/// [`Surface::cast`] gives them), into `maps` in the chunk's order.
fn distance_maps(
    filter: &MomentFilter,
    hits: &[Hit],
    n: usize,
    max_distance: f32,
    maps: &mut [f32],
) {
    let per_map = maps.len() / n.max(1);
    let ndirs = hits.len() / n.max(1);
    maps.par_chunks_mut(per_map)
        .enumerate()
        .for_each_init(Vec::new, |distances, (p, map)| {
            distances.clear();
            for b in 0..ndirs.div_ceil(BLOCK) {
                let len = BLOCK.min(ndirs - b * BLOCK);
                distances.extend(
                    hits[b * BLOCK * n + p * len..][..len]
                        .iter()
                        .map(|h| h.distance(max_distance)),
                );
            }
            filter.filter(distances, max_distance, map);
        });
}

/// The `n x n` identity, row-major.
fn identity(n: usize) -> Vec<f64> {
    (0..n * n)
        .map(|k| if k / n == k % n { 1.0 } else { 0.0 })
        .collect()
}

/// Directions per casting task and per `f32` partial sum of a probe.
const BLOCK: usize = 64;

/// Bytes of probe hits kept at a time: the probes are cast and summed in
/// chunks of this many bytes of [`Hit`]s (16 a ray, 28 with surfaces,
/// whose albedo at each hit is kept beside it), in one buffer reused from
/// chunk to chunk. Small enough that the system's first touch of its
/// pages (on one thread) costs little, large enough for whole packets of
/// probes at thousands of rays each.
const HITS_MEMORY: usize = 32 << 20;

/// The order in which the probes take the directions `dirs`, so that each
/// block of [`BLOCK`] consecutive directions is a small patch of the
/// sphere (the stratified set comes in rings of latitude): the set is cut
/// in two across its widest axis, the first part a whole number of blocks,
/// and each part again, down to single blocks. A probe's rays in one block
/// then meet the scene in one region, whose surface data stay in cache from
/// one ray, and one probe, to the next.
fn direction_order(dirs: &[Vec3]) -> Vec<usize> {
    fn split(dirs: &[Vec3], part: &mut [usize]) {
        if part.len() <= BLOCK {
            return;
        }
        let (lo, hi) = part.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &i| (lo.min(dirs[i]), hi.max(dirs[i])),
        );
        let extent = hi - lo;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let half = (part.len() / 2).div_ceil(BLOCK) * BLOCK;
        part.select_nth_unstable_by(half, |&a, &b| {
            dirs[a][axis].total_cmp(&dirs[b][axis]).then(a.cmp(&b))
        });
        let (first, second) = part.split_at_mut(half);
        split(dirs, first);
        split(dirs, second);
    }
    let mut order: Vec<usize> = (0..dirs.len()).collect();
    split(dirs, &mut order);
    order
}

/// Morton (Z-order) ranks of the probes of `grid`
/// ([`shlight_baked::morton_order`]): `order[r]` is the probe of rank `r`,
/// so that eight consecutive ranks are a 2x2x2 block of neighbours (where
/// the resolution allows) and their rays stay together.
fn probe_order(grid: &ProbeGrid) -> Vec<u32> {
    shlight_baked::morton_order((0..grid.probe_count()).map(|k| {
        let [x, y, z] = grid.grid_index(k).map(|i| i as u32);
        shlight_baked::morton_code(x, y, z)
    }))
}

/// The scene's surfaces, subdivided, with their transfer and emitted light
/// per vertex.
struct Surface {
    mesh: Mesh,
    /// The scene before subdivision, made ready to cast against (through
    /// its cut-outs, with surfaces).
    occluder: Occluder,
    /// A glTF scene's surfaces (of the scene before subdivision): a hit
    /// takes the albedo of its texel.
    surfaces: Option<Arc<Surfaces>>,
    /// With surfaces: the records are incident, a hit multiplies them by
    /// its albedo ([`VertexRecords::incident`]).
    texel: bool,
    /// Where the scene's triangles went in `mesh`.
    map: Subdivision,
    /// With double-sided triangles: per triangle of the scene, whether it
    /// is double-sided (empty: none is), and the back sides of `mesh`'s
    /// (which is then the two-sided mesh, [`BackSides::two_sided`]).
    double: Vec<bool>,
    sides: Option<BackSides>,
    /// Per vertex its `channels x nc` transfer and (when the scene emits or
    /// has punctual lights) its exit radiance due to emitters and those
    /// lights, padded with zeros to whole 64-byte lines.
    records: VertexRecords,
    channels: usize,
    nc: usize,
    emits: bool,
    rays: u64,
}

impl Surface {
    /// The surfaces of `mesh` baked, and when `relocate` is given, its
    /// probes' offsets out of geometry ([`relocate::offsets`]), found
    /// alongside the surfaces' bake once the scene is ready to cast
    /// against, so that either's serial stretches (the subdivision's, the
    /// bounces' set-up) leave no core idle.
    fn bake(
        mesh: &Mesh,
        surfaces: Option<&Arc<Surfaces>>,
        lights: &[PunctualLight],
        options: &VolumeOptions,
        relocate: Option<&ProbeGrid>,
        progress: &(dyn Fn(Stage, usize, usize) + Sync),
    ) -> (Self, Option<Vec<Vec3>>) {
        let (lo, hi) = mesh.bounds();
        let max_edge = options
            .max_edge
            .unwrap_or((hi - lo).length() / SURFACE_DIVISIONS);
        let coarse = mesh;
        // The surfaces' rays and the probes' are cast against the scene's
        // own triangles (the same surface as the subdivided ones, and far
        // fewer of them when it was subdivided), made ready once while the
        // scene is subdivided (both mostly serial); the hits are then found
        // in the subdivided mesh.
        let ((mesh, map), occluder) = rayon::join(
            || coarse.subdivided_with_map(max_edge),
            || match surfaces {
                Some(s) => Occluder::for_surfaces(s),
                None => Occluder::new(coarse),
            },
        );
        // The back sides of double-sided triangles (none in a scene
        // without): vertices of their own, facing the other way.
        let sides = surfaces.and_then(|s| BackSides::find(&mesh, Some(&map), s));
        let two = sides.as_ref().map(|s| s.two_sided(&mesh));
        let double: Vec<bool> = match (&sides, surfaces) {
            (Some(_), Some(s)) => (0..coarse.triangle_count() as u32)
                .map(|t| s.double_sided(t))
                .collect(),
            _ => Vec::new(),
        };
        let albedo = match &mesh.colors {
            Some(c) => {
                Albedo::PerVertex(c.iter().map(|c| c.clamp(Vec3::ZERO, Vec3::ONE)).collect())
            }
            None => Albedo::Constant(options.albedo),
        };
        let mode = if options.bounces == 0 {
            Mode::Shadowed
        } else {
            Mode::Interreflected {
                bounces: options.bounces,
            }
        };
        let bake_options = BakeOptions {
            lmax: options.lmax,
            samples: options.surface_samples,
            mode,
            albedo,
            seed: options.seed ^ 0x5eed_5eed_5eed_5eed,
            emission: mesh.emission.clone(),
            surfaces: surfaces.cloned(),
            // The punctual lights' direct light on each vertex, through
            // shadow rays (none without lights), on both sides of a
            // double-sided triangle.
            direct_irradiance: (!lights.is_empty()).then(|| {
                let lit = two.as_ref().unwrap_or(&mesh);
                shlight_prt::punctual_irradiance(&occluder, lit, lights, options.light_units)
            }),
        };
        let (t, offsets) = rayon::join(
            || {
                shlight_prt::bake_against(
                    &mesh,
                    Some((&occluder, &map)),
                    &bake_options,
                    &|stage, done, total| {
                        progress(Stage::Surface(stage), done, total);
                    },
                )
            },
            || {
                relocate
                    .map(|grid| relocate::offsets_two_sided(&occluder, &double, grid, options.seed))
            },
        );
        let records = t.records();
        let surface = Self {
            occluder,
            map,
            double,
            sides,
            surfaces: surfaces.cloned(),
            texel: records.incident(),
            records,
            channels: t.channels,
            nc: sh_count(t.lmax),
            emits: t.emitted.is_some(),
            rays: t.rays,
            mesh: two.unwrap_or(mesh),
        };
        (surface, offsets)
    }

    /// Casts the rays of the probes `chunk` (indices into `probes`, in
    /// Morton order): per block of [`BLOCK`] directions, for each direction,
    /// the probes eight at a time as one packet, into `hits` and `albedo`
    /// (resized). The hits of block `b` are `chunk.len() x len_b` records, the probes in the chunk's order, each
    /// probe's directions in order; with surfaces, the albedo at each front
    /// hit in the same places (empty without). `progress(directions)` as
    /// blocks finish.
    ///
    /// Each packet of probes goes through every direction of the block in
    /// turn (a small patch of the sphere, [`direction_order`]), so that its
    /// rays walk the same part of the hierarchy and meet the scene in one
    /// region, whose nodes and subdivision stay in cache; its front hits in
    /// the block are found in the subdivided mesh together
    /// ([`Subdivision::locate_each`]). A scene with few vertices (their
    /// ray-space copies for the whole block fit [`LOCAL_FLOATS`]) is put in
    /// ray space once per direction and block; a larger one triangle by
    /// triangle as the rays meet it
    /// ([`Occluder::packet_closest_direct`]).
    fn cast(
        &self,
        chunk: &[u32],
        probes: &[Vec3],
        dirs: &[Vec3],
        (hits, albedo): (&mut Vec<Hit>, &mut Vec<Vec3>),
        progress: &(dyn Fn(usize) + Sync),
    ) {
        let n = chunk.len();
        let nv = self.occluder.vertex_count();
        let small = nv * 4 * BLOCK <= LOCAL_FLOATS;
        // The buffers of the last chunk, reused, and each block reset by
        // the thread that casts it: the system zeroes a fresh allocation's
        // pages at their first touch, a cost paid once, on every thread
        // (a parallel extension writes in place).
        fn fit<T: Copy + Send + Sync>(buffer: &mut Vec<T>, len: usize, fill: T) {
            let more = len.saturating_sub(buffer.len());
            buffer.truncate(len);
            buffer.par_extend(rayon::iter::repeat_n(fill, more));
        }
        fit(hits, n * dirs.len(), Hit::ESCAPED);
        fit(albedo, if self.texel { hits.len() } else { 0 }, Vec3::ZERO);
        let mut albedo_blocks: Vec<&mut [Vec3]> = if self.texel {
            albedo.chunks_mut(n * BLOCK).collect()
        } else {
            dirs.chunks(BLOCK)
                .map(|_| <&mut [Vec3]>::default())
                .collect()
        };
        // The albedo at a point of the scene's triangles.
        let albedo_at = |triangle: u32, w: [f32; 3]| {
            self.surfaces
                .as_ref()
                .map_or(Vec3::ZERO, |s| s.reflectance(triangle, w))
        };
        hits.par_chunks_mut(n * BLOCK)
            .zip(dirs.par_chunks(BLOCK))
            .zip(albedo_blocks.par_iter_mut())
            .for_each_init(
                || {
                    (
                        Vec::new(),
                        Vec::new(),
                        Vec::new(),
                        Vec::new(),
                        Vec::new(),
                        Vec::new(),
                        Vec::new(),
                    )
                },
                |(local, front, located, slots, distances, front_albedo, backs),
                 ((out, block), out_albedo)| {
                    out.fill(Hit::ESCAPED);
                    out_albedo.fill(Vec3::ZERO);
                    let len = block.len();
                    let directions: Vec<Direction> =
                        block.iter().map(|d| Direction::new(*d)).collect();
                    local.clear();
                    if small {
                        for dir in &directions {
                            local.extend(self.occluder.ray_space(dir));
                        }
                    }
                    for (g, eight) in chunk.chunks(LANES).enumerate() {
                        let mut origins = [Vec3::ZERO; LANES];
                        for (o, &p) in origins.iter_mut().zip(eight) {
                            *o = probes[p as usize];
                        }
                        let origins = &origins[..eight.len()];
                        for (jj, dir) in directions.iter().enumerate() {
                            let packet = Packet::new(dir, origins);
                            let found = if small {
                                self.occluder
                                    .packet_closest(dir, &local[jj * nv..][..nv], &packet)
                            } else {
                                self.occluder.packet_closest_direct(dir, &packet)
                            };
                            for k in 0..eight.len() {
                                if found.mask >> k & 1 == 0 {
                                    continue;
                                }
                                let coarse = found.triangle[k];
                                let slot = (g * LANES + k) * len + jj;
                                let back = !self.occluder.is_front(coarse, dir.dir());
                                if back && !relocate::double_sided(&self.double, coarse) {
                                    out[slot] = Hit::back(found.t[k]);
                                } else {
                                    // A front hit, or the back of a
                                    // double-sided triangle: its back
                                    // triangle's front.
                                    front.push((coarse, found.barycentrics[k]));
                                    if self.sides.is_some() {
                                        backs.push(back);
                                    }
                                    slots.push(slot);
                                    distances.push(found.t[k]);
                                    if self.texel {
                                        front_albedo.push(albedo_at(coarse, found.barycentrics[k]));
                                    }
                                }
                            }
                        }
                        // The packet's front hits in the block, found in
                        // the subdivided mesh together.
                        self.map.locate_each(front, located);
                        for (f, ((&i, found), &t)) in slots
                            .iter()
                            .zip(located.iter())
                            .zip(distances.iter())
                            .enumerate()
                        {
                            out[i] = match *found {
                                Some((triangle, [_, b1, b2])) => {
                                    let (triangle, b1, b2) = match &self.sides {
                                        Some(s) if backs[f] => s
                                            .back_hit(triangle, b1, b2)
                                            .unwrap_or((triangle, b1, b2)),
                                        _ => (triangle, b1, b2),
                                    };
                                    Hit {
                                        triangle,
                                        b1,
                                        b2,
                                        t,
                                    }
                                }
                                None => Hit::back(t),
                            };
                            if self.texel {
                                out_albedo[i] = front_albedo[f];
                            }
                        }
                        front.clear();
                        slots.clear();
                        distances.clear();
                        front_albedo.clear();
                        backs.clear();
                    }
                    progress(len);
                },
            );
    }

    /// How [`sums`] makes a probe's rows: `v = (Y, T, E)`, `Y` in
    /// `[0, nc)`, `T` in `[nc, nc + channels nc)`, `E` after when the scene
    /// emits, padded to a multiple of 8.
    fn rows(&self) -> Rows<'_> {
        Rows {
            nc: self.nc,
            width: (self.nc + self.records.used()).div_ceil(8) * 8,
            triangles: &self.mesh.triangles,
            records: self.records.floats(),
            rec: self.records.stride(),
            len: self.records.used(),
            incident: self.texel.then_some(self.channels * self.nc),
        }
    }

    /// `sum_all Y Y^T` (rows [`rows`](Self::rows)`.width` apart), summed as
    /// a probe whose rays all meet back faces sums its blocked rays, so that
    /// a probe that sees no sky gets exactly none.
    fn sum_all(&self, kernels: Kernels, ylm: &[f32]) -> Vec<f64> {
        let rows = self.rows();
        let (nc, width) = (rows.nc, rows.width);
        let mut total = vec![0.0f64; nc * width];
        let mut acc = vec![0.0f32; nc * width];
        let mut v = vec![0.0f32; rows.buffer(BLOCK)];
        let back = [Hit::BACK; BLOCK];
        for block in ylm.chunks(BLOCK * nc) {
            let len = block.len() / nc;
            rows.fill(kernels, &back[..len], &[], block, &mut v);
            block_sum(kernels, block, nc, &v, width, len, &mut acc);
            for (t, a) in total.iter_mut().zip(&acc) {
                *t += f64::from(*a);
            }
        }
        total
    }

    /// Sums the rays of each probe of a chunk ([`cast`](Self::cast)'s
    /// `hits`, and with surfaces the albedo at each) into its transfer,
    /// emitted light and back-face fraction (`out`, in the chunk's order);
    /// `all` is [`sum_all`](Self::sum_all).
    ///
    /// Per block of [`BLOCK`] directions a probe sums, in `f32`, the
    /// products `Y_i(s) v(s)` with `v = (Y(s), T(q), E(q))` over its blocked
    /// rays (`T` and `E` zero at back faces), and adds the block into `f64`:
    /// the blocked rays' `sum Y Y^T` and the front hits' `sum Y T^T` and
    /// `sum Y E` in one pass, the transfer once for a grey surface.
    fn gather(
        &self,
        kernels: Kernels,
        (hits, albedo): (&[Hit], &[Vec3]),
        ylm: &[f32],
        all: &[f64],
        weight: f64,
        (transfer, emitted, backfaces): (&mut [f32], &mut [f32], &mut [f32]),
    ) {
        let rows = self.rows();
        let (nc, width) = (rows.nc, rows.width);
        let ndirs = ylm.len() / nc;
        let n = backfaces.len();
        let stride = self.channels * nc;
        let eye = identity(nc);
        let m_size = 3 * nc * nc;
        transfer
            .par_chunks_mut(m_size)
            .zip(emitted.par_chunks_mut(3 * nc))
            .zip(backfaces.par_iter_mut())
            .enumerate()
            .for_each_init(
                || {
                    (
                        vec![0.0f64; nc * width],
                        vec![0.0f32; nc * width],
                        vec![0.0f32; rows.buffer(BLOCK)],
                    )
                },
                |(total, acc, v), (p, ((m, e), back))| {
                    total.fill(0.0);
                    let (mut escaped, mut back_count) = (0usize, 0usize);
                    for (b, ys) in ylm.chunks(BLOCK * nc).enumerate() {
                        let len = ys.len() / nc;
                        let at = b * BLOCK * n + p * len;
                        let rays = &hits[at..][..len];
                        let rho = if self.texel {
                            &albedo[at..][..len]
                        } else {
                            &[]
                        };
                        let (out, backs) = rows.fill(kernels, rays, rho, ys, v);
                        escaped += out;
                        back_count += backs;
                        if out == len {
                            continue;
                        }
                        block_sum(kernels, ys, nc, v, width, len, acc);
                        for (t, a) in total.iter_mut().zip(acc.iter()) {
                            *t += f64::from(*a);
                        }
                    }
                    // The sky's part from the smaller of the two sets of
                    // rays: w sum_escaped = w (sum_all - sum_blocked), or
                    // delta - w sum_blocked.
                    let blocked_count = ndirs - escaped;
                    for i in 0..nc {
                        let row = &total[i * width..][..width];
                        for k in 0..nc {
                            let sky = if escaped <= blocked_count {
                                weight * (all[i * width + k] - row[k])
                            } else {
                                eye[i * nc + k] - weight * row[k]
                            };
                            for ch in 0..3 {
                                let src = nc + ch.min(self.channels - 1) * nc + k;
                                m[ch * nc * nc + i * nc + k] = (sky + weight * row[src]) as f32;
                            }
                        }
                        if self.emits {
                            for ch in 0..3 {
                                e[i * 3 + ch] = (weight * row[nc + stride + ch]) as f32;
                            }
                        }
                    }
                    *back = back_count as f32 / ndirs as f32;
                },
            );
    }
}

/// Ray-space floats a casting task keeps for a whole block of directions
/// (1 MB); a scene with more vertices is put in ray space a direction at a
/// time.
const LOCAL_FLOATS: usize = 1 << 18;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probes_cast_in_chunks_give_the_same_bake() {
        // 3x2x3 probes, about 1024 rays: 12 KB of hits each, so 16 KB holds
        // one packet of probes at a time and the 18 go in three chunks.
        let scene = shlight_mesh::generate::plane_under_sphere(0.5, 16, 8, 3.0, 4);
        let grid = ProbeGrid::around([3, 2, 3], scene.bounds()).unwrap();
        let options = VolumeOptions {
            samples: 1024,
            surface_samples: 64,
            ..VolumeOptions::default()
        };
        let whole = bake(Some(&scene), &grid, &options, &|_, _, _| {}).unwrap();
        let n = whole.samples;
        let per_chunk = (16384 / (12 * n)).max(8) / 8 * 8;
        let chunks = 18usize.div_ceil(per_chunk);
        assert!(chunks >= 2, "{n} rays, {per_chunk} probes a chunk");
        let calls = AtomicUsize::new(0);
        let chunked = bake_in_chunks(
            Some((&scene, None)),
            &[],
            &grid,
            &options,
            &|stage, done, total| {
                if stage == Stage::Probes {
                    assert!(done <= total && total == chunks * n, "{done} {total}");
                    calls.fetch_add(1, Ordering::Relaxed);
                }
            },
            16 << 10,
            Kernels::detect(),
        )
        .unwrap();
        assert_eq!(whole, chunked);
        assert_eq!(calls.into_inner(), chunks * n.div_ceil(BLOCK));
        // And the scene was in the way.
        assert!(whole.transfer.iter().any(|&x| x != 0.0 && x != 1.0));
    }

    #[test]
    fn directions_are_taken_in_compact_blocks() {
        // The stratified set comes in rings of latitude: a block of 64
        // spans most of a ring. Cut into blocks across the widest axes,
        // every block is a small patch: 64 of 4096 directions cover a cap
        // of 0.25 radians.
        let set: Vec<Vec3> = stratified_directions(4096, 3)
            .iter()
            .map(|d| d.as_vec3())
            .collect();
        let order = direction_order(&set);
        let mut seen = vec![false; set.len()];
        for &i in &order {
            assert!(!seen[i], "direction {i} twice");
            seen[i] = true;
        }
        assert!(seen.iter().all(|&s| s));
        // Per block, the widest angle from its mean direction to a member.
        let widest = |dirs: &[Vec3]| -> Vec<f32> {
            dirs.chunks(BLOCK)
                .map(|b| {
                    let mean = b.iter().copied().sum::<Vec3>().normalize_or_zero();
                    b.iter()
                        .map(|d| d.dot(mean).clamp(-1.0, 1.0).acos())
                        .fold(0.0f32, f32::max)
                })
                .collect()
        };
        let ordered: Vec<Vec3> = order.iter().map(|&i| set[i]).collect();
        let mean = |w: &[f32]| w.iter().sum::<f32>() / w.len() as f32;
        let (rings, patches) = (widest(&set), widest(&ordered));
        assert!(mean(&rings) > 1.0, "{}", mean(&rings));
        assert!(mean(&patches) < 0.4, "{}", mean(&patches));
        assert!(patches.iter().all(|&w| w < 0.45), "{patches:?}");
    }

    #[test]
    fn bakes_with_either_kernel_agree() {
        // The portable rows and sums against AVX2's (where the processor
        // has it): the same sums, fused or not, in a scene with emitters
        // and coloured walls.
        if Kernels::detect() == Kernels::Portable {
            shlight_rays::skip_test(
                "bakes_with_either_kernel_agree",
                "no AVX2 and FMA here: both bakes sum with the portable kernels",
            );
        }
        let room = shlight_mesh::generate::cornell_box();
        let grid = ProbeGrid::around([3, 2, 3], room.bounds()).unwrap();
        let options = VolumeOptions {
            samples: 1024,
            surface_samples: 64,
            max_edge: Some(0.05),
            ..VolumeOptions::default()
        };
        let run = |kernels| {
            bake_in_chunks(
                Some((&room, None)),
                &[],
                &grid,
                &options,
                &|_, _, _| {},
                HITS_MEMORY,
                kernels,
            )
            .unwrap()
        };
        // Without AVX2 and FMA this compares the portable bake with itself.
        let (portable, simd) = (run(Kernels::Portable), run(Kernels::detect()));
        assert_eq!(portable.valid, simd.valid);
        assert_eq!(portable.backfaces, simd.backfaces);
        for (a, b) in [
            (&portable.transfer, &simd.transfer),
            (&portable.emitted, &simd.emitted),
        ] {
            let max = a.iter().fold(0.0f32, |m, x| m.max(x.abs()));
            assert!(max > 0.0);
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() <= 1e-5 * max, "{x} vs {y} of {max}");
            }
        }
    }
}

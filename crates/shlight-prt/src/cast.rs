//! The rays of a diffuse or glossy bake, cast ([`Cast`]): one seeded
//! stratified set of directions shared by every vertex, cast direction by
//! direction from the vertices facing it, in Morton order, eight at a time
//! as packets against the mesh made ready ([`shlight_rays::Occluder`]); one
//! visibility bit per vertex and direction, and the front hits the bounces
//! read (with [`BakeOptions::surfaces`], each with the albedo of the texel
//! it met, and through cut-outs).

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use glam::Vec3;
use rayon::prelude::*;
use shlight_core::map::montecarlo::stratified_directions;
use shlight_core::sh::{ShBasis, sh_count};
use shlight_mesh::{Mesh, Subdivision};
use shlight_rays::{Direction, LANES, Occluder, Packet, ranked_triangles, vertex_order};

use crate::back_sides::BackSides;
use crate::options::{Albedo, BakeOptions, Stage};

/// A ray along one direction that met the front of a triangle: its
/// vertex's rank (Morton order), the triangle and the barycentric weights
/// of corners 1 and 2.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrontHit {
    pub(crate) rank: u32,
    pub(crate) triangle: u32,
    pub(crate) b1: f32,
    pub(crate) b2: f32,
}

/// The rays of a bake, cast: the shared directions and their basis
/// values, the vertices in Morton order, which rays escape and where the
/// others met the front of a triangle.
pub(crate) struct Cast {
    /// `order[s]`: the vertex at rank `s`.
    pub(crate) order: Vec<u32>,
    /// The mesh's triangles with their corners by rank (empty when no
    /// bounce or cast needed them).
    pub(crate) triangles: Vec<[u32; 3]>,
    /// Normals by rank.
    pub(crate) normals: Vec<Vec3>,
    /// `sum_j max(n.s_j, 0)` per vertex, by rank.
    pub(crate) totals: Vec<f64>,
    /// The shared directions.
    pub(crate) dirs: Vec<Vec3>,
    /// `Y_i(s_j)`, `nc` per direction.
    pub(crate) ylm: Vec<f64>,
    /// `(lmax+1)^2`.
    pub(crate) nc: usize,
    /// The albedo's channels.
    pub(crate) channels: usize,
    /// Bit `s` of row `j` (`words` per row): the ray from the vertex of
    /// rank `s` along direction `j` escapes (empty when unshadowed).
    pub(crate) visible: Vec<u64>,
    pub(crate) words: usize,
    /// Per direction, its rays' front hits in rank order (empty unless
    /// kept).
    pub(crate) front_hits: Vec<Vec<FrontHit>>,
    /// With surfaces ([`Cast::texel`]): per direction, the albedo at each of
    /// its front hits (`Surfaces::sample` at the point of the original
    /// triangle met, clamped to `0..=1`), in the order of `front_hits`.
    pub(crate) hit_albedo: Vec<Vec<Vec3>>,
    /// The bake has surfaces: a bounce takes the albedo of the texel hit.
    pub(crate) texel: bool,
    /// Rays cast.
    pub(crate) rays: u64,
}

impl Cast {
    /// Casts the rays of `options` (its lmax, samples, seed, albedo and
    /// surfaces) when `shadowed`, keeping the front hits when `keep_hits`.
    /// `occluder` must have been built with the surfaces' cut-outs
    /// ([`Occluder::with_cut_outs`]) when there are surfaces, of the mesh
    /// `mesh` was subdivided from when a subdivision is given; without one,
    /// the occluder made of `mesh` is.
    ///
    /// With `sides`, `mesh` is the two-sided mesh ([`BackSides`]) and
    /// `occluder` is given, made of the front triangles: a ray that meets
    /// the back of a double-sided triangle is a front hit of its back
    /// triangle.
    ///
    /// # Panics
    /// If a per-vertex albedo, the emission or the direct irradiance has
    /// another length than the mesh's vertices, or the surfaces another
    /// triangle count than the mesh the rays are cast against.
    pub(crate) fn new(
        mesh: &Mesh,
        occluder: Option<(&Occluder, Option<&Subdivision>)>,
        options: &BakeOptions,
        sides: Option<&BackSides>,
        shadowed: bool,
        keep_hits: bool,
        progress: &(dyn Fn(Stage, usize, usize) + Sync),
    ) -> Self {
        let n_vertices = mesh.vertex_count();
        if let Albedo::PerVertex(a) = &options.albedo {
            assert_eq!(a.len(), n_vertices, "one albedo per vertex");
        }
        if let Some(e) = &options.emission {
            assert_eq!(e.len(), n_vertices, "one emission per vertex");
        }
        if let Some(e) = &options.direct_irradiance {
            assert_eq!(e.len(), n_vertices, "one direct irradiance per vertex");
        }
        let surfaces = options.surfaces.as_deref();
        if let Some(s) = surfaces {
            let cast_against = match occluder {
                Some((_, Some(m))) => m.original_triangles(),
                _ => sides.map_or(mesh.triangle_count(), |s| s.back_triangles.len()),
            };
            assert_eq!(
                s.mesh.triangle_count(),
                cast_against,
                "the surfaces are those of the mesh the rays are cast against"
            );
        }
        let texel = surfaces.is_some();
        let lmax = options.lmax;
        let nc = sh_count(lmax);
        let channels = options.channels();
        let dirs: Vec<Vec3> = stratified_directions(options.samples.max(1), options.seed)
            .iter()
            .map(|d| d.as_vec3())
            .collect();
        let basis = ShBasis::<f64>::new(lmax);
        let mut ylm = vec![0.0f64; dirs.len() * nc];
        for (d, row) in dirs.iter().zip(ylm.chunks_exact_mut(nc)) {
            basis.eval(d.as_dvec3(), row);
        }

        // The mesh with its vertices in Morton order: `order[s]` is the vertex
        // at rank `s`, so the vertices facing a direction, taken in rank order,
        // make coherent packets and every pass reads memory in sequence.
        let bounds = mesh.bounds();
        let order = vertex_order(&mesh.positions, bounds);
        // The triangles with their corners by rank: what the bounces read.
        let triangles = if keep_hits {
            ranked_triangles(&mesh.triangles, &order)
        } else {
            Vec::new()
        };
        let normals: Vec<Vec3> = order.iter().map(|&v| mesh.normals[v as usize]).collect();
        // sum_j max(n.s_j, 0) per vertex, by rank: the weights' denominators.
        let totals: Vec<f64> = normals
            .par_iter()
            .map(|n| dirs.iter().map(|d| f64::from(n.dot(*d).max(0.0))).sum())
            .collect();
        let words = n_vertices.div_ceil(64);
        // Bit s of row j: the ray from the vertex of rank s along direction j
        // escapes.
        let mut visible = vec![0u64; if shadowed { dirs.len() * words } else { 0 }];
        let mut front_hits: Vec<Vec<FrontHit>> = vec![Vec::new(); dirs.len()];
        let mut hit_albedo: Vec<Vec<Vec3>> = vec![Vec::new(); dirs.len()];
        let rays = AtomicU64::new(0);
        if shadowed {
            // What the rays are cast against: `mesh`, or the occluder.
            let own;
            let (occluder, map) = match occluder {
                Some((o, m)) => (o, m),
                None => {
                    own = match &options.surfaces {
                        Some(s) => Occluder::for_surfaces(s),
                        None => Occluder::new(mesh),
                    };
                    (&own, None)
                }
            };
            // With back sides, whether each triangle cast against is
            // double-sided (empty: none is).
            let double: Vec<bool> = match (sides, surfaces) {
                (Some(_), Some(s)) => (0..s.mesh.triangle_count() as u32)
                    .map(|t| s.double_sided(t))
                    .collect(),
                _ => Vec::new(),
            };
            // A front hit of triangle `t` (of `mesh`), or with `back` of its
            // back triangle.
            let side = |back: bool, t: u32, b1: f32, b2: f32| match (back, sides) {
                (true, Some(s)) => s.back_hit(t, b1, b2).unwrap_or((t, b1, b2)),
                _ => (t, b1, b2),
            };
            // The albedo at a point of the triangles cast against.
            let albedo_at = |triangle: u32, w: [f32; 3]| {
                surfaces.map_or(Vec3::ZERO, |s| s.reflectance(triangle, w))
            };
            // Where the rays start, by rank.
            let origins = occluder.ray_origins(mesh);
            let start: Vec<Vec3> = order.iter().map(|&v| origins[v as usize]).collect();
            let done = AtomicUsize::new(0);
            visible
                .par_chunks_mut(words.max(1))
                .zip(front_hits.par_iter_mut().zip(hit_albedo.par_iter_mut()))
                .enumerate()
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
                    |(local, facing, pending, coarse, located, pending_albedo, pending_back),
                     (j, (row, (hits, albedo)))| {
                        let d = dirs[j];
                        let dir = Direction::new(d);
                        local.clear();
                        local.extend(occluder.ray_space(&dir));
                        facing.clear();
                        facing.extend(
                            normals
                                .iter()
                                .enumerate()
                                .filter(|(_, n)| n.dot(d) > 0.0)
                                .map(|(s, _)| s as u32),
                        );
                        for eight in facing.chunks(LANES) {
                            let mut origins = [Vec3::ZERO; LANES];
                            for (o, &s) in origins.iter_mut().zip(eight) {
                                *o = start[s as usize];
                            }
                            let packet = Packet::new(&dir, &origins[..eight.len()]);
                            let escaped = if keep_hits {
                                let found = occluder.packet_closest(&dir, local, &packet);
                                for (k, &s) in eight.iter().enumerate() {
                                    if found.mask >> k & 1 == 0 {
                                        continue;
                                    }
                                    let triangle = found.triangle[k];
                                    let back = !occluder.is_front(triangle, d);
                                    if back
                                        && !double.get(triangle as usize).copied().unwrap_or(false)
                                    {
                                        continue;
                                    }
                                    if texel {
                                        let a = albedo_at(triangle, found.barycentrics[k]);
                                        match map {
                                            None => albedo.push(a),
                                            Some(_) => pending_albedo.push(a),
                                        }
                                    }
                                    match map {
                                        None => {
                                            let [_, b1, b2] = found.barycentrics[k];
                                            let (triangle, b1, b2) = side(back, triangle, b1, b2);
                                            hits.push(FrontHit {
                                                rank: s,
                                                triangle,
                                                b1,
                                                b2,
                                            });
                                        }
                                        Some(_) => {
                                            pending.push(s);
                                            coarse.push((triangle, found.barycentrics[k]));
                                            pending_back.push(back);
                                        }
                                    }
                                }
                                !found.mask
                            } else {
                                !occluder.packet_occluded(&dir, local, &packet)
                            };
                            for (k, &s) in eight.iter().enumerate() {
                                if escaped >> k & 1 == 1 {
                                    row[s as usize / 64] |= 1 << (s % 64);
                                }
                            }
                        }
                        // The direction's hits on the occluder, found in `mesh`
                        // together (their memory reads overlap).
                        if let Some(m) = map {
                            m.locate_each(coarse, located);
                            for (i, (&s, l)) in pending.iter().zip(located.iter()).enumerate() {
                                if let Some((triangle, [_, b1, b2])) = *l {
                                    let (triangle, b1, b2) =
                                        side(pending_back[i], triangle, b1, b2);
                                    hits.push(FrontHit {
                                        rank: s,
                                        triangle,
                                        b1,
                                        b2,
                                    });
                                    if texel {
                                        albedo.push(pending_albedo[i]);
                                    }
                                }
                            }
                            pending.clear();
                            coarse.clear();
                            pending_albedo.clear();
                            pending_back.clear();
                        }
                        rays.fetch_add(facing.len() as u64, Ordering::Relaxed);
                        progress(
                            Stage::Rays,
                            done.fetch_add(1, Ordering::Relaxed) + 1,
                            dirs.len(),
                        );
                    },
                );
        }

        Self {
            order,
            triangles,
            normals,
            totals,
            dirs,
            ylm,
            nc,
            channels,
            visible,
            words,
            front_hits,
            hit_albedo,
            texel,
            rays: rays.into_inner(),
        }
    }
}

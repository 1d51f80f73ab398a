//! The diffuse bake's entry points: [`bake`] (whose docs state the
//! estimator), [`bake_with_occluder`], [`bake_against`].

use shlight_mesh::{Mesh, Subdivision};
use shlight_rays::Occluder;

use shlight_core::sh::sh_count;

use crate::back_sides::BackSides;
use crate::cast::Cast;
use crate::options::{Albedo, BakeOptions, Mode, Stage};
use crate::records::Kernels;
use crate::transfer::{BackTransfer, IncidentTransfer, Transfer};

/// Bakes the transfer of every vertex of `mesh` ([`Transfer`] states what
/// it is).
///
/// # Estimator
///
/// One jittered equal-area grid of directions `s_j`
/// ([`shlight_core::map::montecarlo::stratified_directions`], seeded) serves
/// every vertex. Per vertex, only directions above the tangent plane are
/// cast, and each gets the weight `w_j = (n.s_j) / sum_k max(n.s_k, 0)`, so
/// `int max(n.s, 0) f(s) ds ~ pi sum_j w_j f(s_j)`: a ratio estimator whose
/// weights sum to exactly 1 (bias O(1/N)), so a white surface (albedo 1)
/// under constant light never gains or loses energy in the estimate, and the
/// interreflected limit of the white furnace is exact.
///
/// Rays start off the surface and never across the mesh
/// ([`Occluder::ray_origins`]: `p + eps (n + c)`, `c` the unit tangent
/// towards the mean centroid of the vertex's triangles, so a vertex on a
/// concave edge starts off the other surface's plane). A ray that hits the
/// back of a triangle (an open mesh seen from behind) is blocked and brings
/// no bounce light: surfaces are one-sided, but for the double-sided
/// triangles of [`BakeOptions::surfaces`] (a glTF material's
/// `doubleSided`): those have back sides ([`crate::BackSides`]: back copies
/// of their vertices, whose transfer is baked with the mesh's, on the
/// two-sided mesh), and a ray meeting their back reads the back copies'
/// light as a front hit reads the corners'. The returned transfer holds the
/// mesh's own vertices (their front side); the back copies' is in
/// [`Transfer::back`]. A bake without double-sided triangles is the same,
/// bit for bit, as one-sided.
///
/// With [`BakeOptions::surfaces`], rays pass the cut-outs of the triangles
/// whose material cuts out ([`shlight_rays::CutOuts`]: a cut-out texel
/// passes every ray, shadow rays too; partial coverage a deterministic
/// share of them), and each front hit reads the albedo of the texel it met
/// ([`shlight_mesh::Surfaces::sample`] at the hit's triangle and
/// barycentric weights) once, as it is cast; a bounce then adds that
/// albedo times the light arriving there, interpolated from the
/// triangle's corners ([`Transfer`]).
///
/// Rays are cast direction by direction, directions in parallel (rayon):
/// for each shared direction, the vertices facing it are taken in Morton
/// order eight at a time, and each eight is traced as one
/// [`shlight_rays::Packet`] of parallel rays. Each vertex's sum runs over
/// the directions in order, so the result is the same bit for bit at any
/// thread count. The bounces are gathered in `f32`, a chunk of vertices
/// through the directions in order (AVX2 and FMA when present).
///
/// `progress(stage, done, total)` is called from worker threads as work
/// finishes (in no fixed order; `done` only grows within a stage): for
/// [`Stage::Rays`] in directions, for the bounces in vertices.
///
/// # Panics
/// If a per-vertex albedo has another length than the mesh's vertices, or
/// the surfaces have another triangle count than the mesh.
#[must_use]
pub fn bake(
    mesh: &Mesh,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Transfer {
    bake_with_occluder(mesh, None, options, progress)
}

/// [`bake`] for a `mesh` made by [`Mesh::subdivided_with_map`] from
/// `occluder.0` (`occluder.1` its map): the rays are cast against the
/// original triangles (the same surface, fewer triangles) and their hits
/// found in `mesh` by [`Subdivision::locate_each`], a direction's hits
/// together. `None`: cast against `mesh`. [`BakeOptions::surfaces`] are
/// those of the mesh cast against (`occluder.0`).
///
/// # Panics
/// As [`bake`].
#[must_use]
pub fn bake_with_occluder(
    mesh: &Mesh,
    occluder: Option<(&Mesh, &Subdivision)>,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Transfer {
    let built = occluder.map(|(coarse, map)| {
        let occluder = match &options.surfaces {
            Some(s) => Occluder::for_surfaces(s),
            None => Occluder::new(coarse),
        };
        (occluder, map)
    });
    let occluder = built.as_ref().map(|(o, map)| (o, Some(*map)));
    bake_with(mesh, occluder, options, progress, Kernels::detect())
}

/// [`bake_with_occluder`] with the occluder made ready already
/// ([`Occluder::new`] of the mesh `mesh` was subdivided from, or
/// [`Occluder::with_cut_outs`] of it and [`BakeOptions::surfaces`]), for
/// callers that cast rays of their own against it too.
///
/// # Panics
/// As [`bake`].
#[must_use]
pub fn bake_against(
    mesh: &Mesh,
    occluder: Option<(&Occluder, &Subdivision)>,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Transfer {
    let occluder = occluder.map(|(o, m)| (o, Some(m)));
    bake_with(mesh, occluder, options, progress, Kernels::detect())
}

/// [`bake`] of `mesh` cast against `occluder`, made ready from `mesh`
/// itself ([`Occluder::with_cut_outs`] of it and
/// [`BakeOptions::surfaces`], or [`Occluder::new`]) by a caller that
/// casts rays of its own against it too (a scene's punctual lights).
pub(crate) fn bake_cast_against(
    mesh: &Mesh,
    occluder: &Occluder,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Transfer {
    bake_with(
        mesh,
        Some((occluder, None)),
        options,
        progress,
        Kernels::detect(),
    )
}

/// [`bake_with_occluder`], the bounces gathered with `kernels` (`occluder`:
/// the occluder made ready and, when `mesh` was subdivided from its mesh,
/// the subdivision; `None`: one made here from `mesh`): with
/// surfaces that have double-sided triangles, over the two-sided mesh
/// ([`BackSides`]), the back copies' sums kept apart ([`Transfer::back`]).
fn bake_with(
    mesh: &Mesh,
    occluder: Option<(&Occluder, Option<&Subdivision>)>,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
    kernels: Kernels,
) -> Transfer {
    let sides = options
        .surfaces
        .as_deref()
        .and_then(|s| BackSides::find(mesh, occluder.and_then(|(_, m)| m), s));
    let Some(sides) = sides else {
        return bake_sides(mesh, occluder, options, None, progress, kernels);
    };
    // The two-sided mesh, its back copies taking their vertices' albedo
    // and emission; the rays cast against the scene's own triangles.
    let two = sides.two_sided(mesh);
    let mut two_options = options.clone();
    if let Albedo::PerVertex(a) = &options.albedo {
        two_options.albedo = Albedo::PerVertex(sides.extend(a));
    }
    two_options.emission = options.emission.as_deref().map(|e| sides.extend(e));
    if let Some(e) = &options.direct_irradiance {
        assert_eq!(
            e.len(),
            sides.two_sided_vertices(),
            "one direct irradiance per vertex of the two-sided mesh"
        );
    }
    let own;
    let against = match occluder {
        Some(given) => given,
        None => {
            let surfaces = options
                .surfaces
                .clone()
                .expect("back sides come from surfaces");
            own = Occluder::for_surfaces(&surfaces);
            (&own, None)
        }
    };
    let t = bake_sides(
        &two,
        Some(against),
        &two_options,
        Some(&sides),
        progress,
        kernels,
    );
    split_back(t, sides)
}

/// The bake of `mesh` (the two-sided mesh when `sides` are given) cast
/// against `occluder` (its mesh's triangles, the subdivision's when one
/// is given, the front triangles with `sides`; `None`: `mesh` itself).
fn bake_sides(
    mesh: &Mesh,
    occluder: Option<(&Occluder, Option<&Subdivision>)>,
    options: &BakeOptions,
    sides: Option<&BackSides>,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
    kernels: Kernels,
) -> Transfer {
    let shadowed = options.mode != Mode::Unshadowed;
    let bounces = options.mode.bounces();
    let cast = Cast::new(
        mesh,
        occluder,
        options,
        sides,
        shadowed,
        bounces > 0,
        progress,
    );
    let diffuse = cast.diffuse(options, bounces, kernels, progress);
    let stride = cast.channels * cast.nc;
    Transfer {
        lmax: options.lmax,
        channels: cast.channels,
        vertex_count: cast.order.len(),
        coeffs: by_vertex(&diffuse.total, stride, &cast.order),
        samples: cast.dirs.len(),
        rays: cast.rays,
        emitted: diffuse.emitted.map(|e| by_vertex(&e, 1, &cast.order)),
        incident: diffuse.incident.map(|i| IncidentTransfer {
            coeffs: by_vertex(&i.coeffs, stride, &cast.order),
            emitted: i.emitted.map(|e| by_vertex(&e, 1, &cast.order)),
        }),
        back: None,
    }
}

/// The bake `t` of a two-sided mesh split into the mesh's vertices and
/// the back copies of `sides` ([`Transfer::back`]).
fn split_back(mut t: Transfer, sides: BackSides) -> Transfer {
    let n = sides.front_vertices;
    let stride = t.channels * sh_count(t.lmax);
    let coeffs = t.coeffs.split_off(n * stride);
    let emitted = t.emitted.as_mut().map(|e| e.split_off(n));
    let incident = t.incident.as_mut().map(|i| IncidentTransfer {
        coeffs: i.coeffs.split_off(n * stride),
        emitted: i.emitted.as_mut().map(|e| e.split_off(n)),
    });
    t.vertex_count = n;
    t.back = Some(BackTransfer {
        sides,
        coeffs,
        emitted,
        incident,
    });
    t
}

/// Rows of `width` values by rank (`order[s]` the vertex of rank `s`) in
/// vertex order.
fn by_vertex<T: Copy + Default>(ranked: &[T], width: usize, order: &[u32]) -> Vec<T> {
    let mut out = vec![T::default(); ranked.len()];
    for (row, &v) in ranked.chunks_exact(width).zip(order) {
        out[v as usize * width..][..width].copy_from_slice(row);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_mesh::generate;

    #[test]
    fn bakes_with_either_kernel_agree() {
        if Kernels::detect() == Kernels::Portable {
            shlight_rays::skip_test(
                "bakes_with_either_kernel_agree",
                "no AVX2 and FMA here: both bakes gather with the portable kernel",
            );
        }
        let room = generate::cornell_box();
        let (fine, map) = room.subdivided_with_map(0.05);
        let options = BakeOptions {
            lmax: 2,
            samples: 128,
            mode: Mode::Interreflected { bounces: 2 },
            albedo: Albedo::PerVertex(fine.colors.clone().unwrap()),
            seed: 5,
            emission: fine.emission.clone(),
            surfaces: None,
            direct_irradiance: None,
        };
        let occluder = Occluder::new(&room);
        let run = |kernels| {
            bake_with(
                &fine,
                Some((&occluder, Some(&map))),
                &options,
                &|_, _, _| {},
                kernels,
            )
        };
        // Without AVX2 and FMA this compares the portable bake with itself.
        let (portable, simd) = (run(Kernels::Portable), run(Kernels::detect()));
        let max = portable.coeffs.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        for (a, b) in portable.coeffs.iter().zip(&simd.coeffs) {
            assert!((a - b).abs() <= 1e-5 * max, "{a} vs {b}");
        }
        for (a, b) in portable.emitted.unwrap().iter().zip(&simd.emitted.unwrap()) {
            assert!((*a - *b).abs().max_element() <= 1e-5 * a.abs().max_element().max(1.0));
        }
    }
}

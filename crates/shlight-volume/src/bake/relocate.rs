//! Probe relocation (after Majercik, Mara, Shirley & McGuire 2021,
//! "Scaling Probe-Based Real-Time Dynamic Global Illumination for
//! Production", JCGT 10(2)): a probe inside geometry, or nearer a surface
//! than a fraction of its cell, is moved within its cell to free space
//! before its rays are cast.
//!
//! A position is *free* when at most [`INSIDE_BACKFACES`] of
//! [`RELOCATION_RAYS`] rays from it meet back faces (DDGI's test for a probe
//! inside geometry) and no ray meets a surface nearer than
//! [`CLEARANCE`] of the cell's smallest side. A probe whose cell centre is
//! free stays there. Otherwise the candidates are the offsets
//! `(a, b, c) s` with `a, b, c` in `-3..=3` and `s = 0.15` of the cell per
//! axis (so at most [`MAX_OFFSET`] of the cell, as DDGI allows), taken in
//! order of distance (then of `(a, b, c)`): the first free one is the
//! probe's new place. Where none is free, the candidate with the most
//! clearance among those not inside geometry is taken; where every
//! candidate is inside, the probe stays at its centre (and the bake marks
//! it invalid as before). Deterministic: the same rays for every probe and
//! candidate, a fixed order, one result at any thread count.

use glam::Vec3;
use rayon::prelude::*;
use shlight_baked::ProbeGrid;
use shlight_core::map::montecarlo::stratified_directions;
use shlight_prt::bvh::Ray;
use shlight_prt::transfer::Occluder;

/// Rays cast from each position tested.
pub const RELOCATION_RAYS: usize = 128;

/// A position from which more than this fraction of the rays meet back
/// faces is inside geometry.
pub const INSIDE_BACKFACES: f32 = 0.25;

/// The least distance to any surface a free position keeps, as a fraction
/// of the cell's smallest side.
pub const CLEARANCE: f32 = 0.2;

/// The farthest a probe moves along each axis, as a fraction of its cell.
pub const MAX_OFFSET: f32 = 0.45;

/// Steps of the candidate lattice on each side of the centre.
const STEPS: i32 = 3;

/// What the rays from one position found.
#[derive(Clone, Copy, Debug)]
struct Look {
    inside: bool,
    clearance: f32,
}

/// Each probe's offset from its cell centre (`Vec3::ZERO` where it stays),
/// in probe order, against `occluder`.
pub fn offsets(occluder: &Occluder, grid: &ProbeGrid, seed: u64) -> Vec<Vec3> {
    let dirs: Vec<Vec3> = stratified_directions(RELOCATION_RAYS, seed ^ 0x0ff5_e7ed)
        .iter()
        .map(|d| d.as_vec3())
        .collect();
    let cell = grid.cell();
    let clearance = CLEARANCE * cell.min_element();
    let step = MAX_OFFSET / STEPS as f32;
    let mut lattice: Vec<(i32, i32, i32)> = Vec::new();
    for a in -STEPS..=STEPS {
        for b in -STEPS..=STEPS {
            for c in -STEPS..=STEPS {
                if (a, b, c) != (0, 0, 0) {
                    lattice.push((a, b, c));
                }
            }
        }
    }
    let offset = |(a, b, c): (i32, i32, i32)| Vec3::new(a as f32, b as f32, c as f32) * step * cell;
    lattice.sort_by(|&x, &y| {
        offset(x)
            .length_squared()
            .total_cmp(&offset(y).length_squared())
            .then(x.cmp(&y))
    });
    (0..grid.probe_count())
        .into_par_iter()
        .map(|k| {
            let centre = grid.centre(grid.grid_index(k));
            if look(occluder, &dirs, centre, clearance).is_free(clearance) {
                return Vec3::ZERO;
            }
            // The nearest free candidate; a ray nearer than the clearance
            // or too many back faces end a candidate's rays early.
            for &l in &lattice {
                let o = offset(l);
                if look(occluder, &dirs, centre + o, clearance).is_free(clearance) {
                    return o;
                }
            }
            // None free: the most clearance outside geometry, all rays cast.
            let mut best: Option<(f32, Vec3)> = None;
            for o in std::iter::once(Vec3::ZERO).chain(lattice.iter().map(|&l| offset(l))) {
                let at = look(occluder, &dirs, centre + o, 0.0);
                if !at.inside && best.is_none_or(|(c, _)| at.clearance > c) {
                    best = Some((at.clearance, o));
                }
            }
            best.map_or(Vec3::ZERO, |(_, o)| o)
        })
        .collect()
}

impl Look {
    fn is_free(&self, clearance: f32) -> bool {
        !self.inside && self.clearance >= clearance
    }
}

/// The rays from `p`: whether it is inside geometry (more than
/// [`INSIDE_BACKFACES`] of them on back faces) and its clearance (the
/// nearest hit). The rays stop once the answer is known: when a hit is
/// nearer than `stop_within` (the clearance is then that hit's, and
/// `inside` is false though the rest might have said otherwise) or when
/// the back faces are already too many.
fn look(occluder: &Occluder, dirs: &[Vec3], p: Vec3, stop_within: f32) -> Look {
    let limit = INSIDE_BACKFACES * dirs.len() as f32;
    let (mut back, mut nearest) = (0usize, f32::INFINITY);
    for d in dirs {
        if let Some(hit) = occluder
            .bvh()
            .bvh()
            .closest_hit(&Ray::new(p, *d, f32::INFINITY))
        {
            nearest = nearest.min(hit.t);
            if !occluder.is_front(hit.triangle, *d) {
                back += 1;
                if back as f32 > limit {
                    return Look {
                        inside: true,
                        clearance: nearest,
                    };
                }
            }
            if nearest < stop_within {
                return Look {
                    inside: false,
                    clearance: nearest,
                };
            }
        }
    }
    Look {
        inside: false,
        clearance: nearest,
    }
}

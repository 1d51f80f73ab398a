//! Probe relocation (after Majercik, Mara, Shirley & McGuire 2021,
//! "Scaling Probe-Based Real-Time Dynamic Global Illumination for
//! Production", JCGT 10(2)): a probe inside geometry, or nearer a surface
//! than a fraction of its cell, is moved within its cell to free space
//! before its rays are cast.
//!
//! A position is *free* when at most [`INSIDE_BACKFACES`] of
//! [`RELOCATION_RAYS`] rays from it meet back faces (DDGI's test for a probe
//! inside geometry; the back of a double-sided triangle is none,
//! [`offsets_two_sided`]) and no ray meets a surface nearer than
//! [`CLEARANCE`] of the cell's smallest side. A probe whose cell centre is
//! free stays there. Otherwise the candidates are the offsets
//! `(a, b, c) s` with `a, b, c` in `-3..=3` and `s = 0.15` of the cell per
//! axis (so at most [`MAX_OFFSET`] of the cell, as DDGI allows), taken in
//! order of distance (then of `(a, b, c)`): the first free one is the
//! probe's new place. Where none is free, the candidate with the most
//! clearance among those not inside geometry is taken; where every
//! candidate is inside, the probe stays at its centre (and the bake marks
//! it invalid as before). Deterministic: the same rays for every probe and
//! candidate, a fixed order, one result at any thread count. The rays are
//! cast as packets ([`Packet`]): eight probes' centres, then eight
//! candidates of one probe at a time along each direction, a point's rays
//! stopping once its answer is settled (its lane leaves the packet). The
//! search for the most clearance casts again only the candidates the first
//! search did not find inside geometry, and stops a candidate's rays once
//! it cannot beat the best so far; neither changes the answer.

use glam::Vec3;
use rayon::prelude::*;
use shlight_baked::ProbeGrid;
use shlight_core::map::montecarlo::stratified_directions;
use shlight_rays::{Direction, LANES, Occluder, Packet};

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

/// What the rays are cast against: the occluder, and which of its
/// triangles are double-sided (none when empty).
struct Against<'a> {
    occluder: &'a Occluder,
    double_sided: &'a [bool],
}

impl Against<'_> {
    /// Whether a ray along `dir` that met `triangle` met a back face: the
    /// back of a one-sided triangle.
    fn meets_back(&self, triangle: u32, dir: Vec3) -> bool {
        !self.occluder.is_front(triangle, dir) && !double_sided(self.double_sided, triangle)
    }
}

/// Whether `triangle` is double-sided by `flags` (one per triangle, empty
/// when none is), so its back is no back face: for relocation and the
/// probes' rays alike.
pub(crate) fn double_sided(flags: &[bool], triangle: u32) -> bool {
    flags.get(triangle as usize).copied().unwrap_or(false)
}

/// What the rays from one position found.
#[derive(Clone, Copy, Debug)]
struct Look {
    inside: bool,
    clearance: f32,
}

impl Look {
    fn is_free(&self, clearance: f32) -> bool {
        !self.inside && self.clearance >= clearance
    }
}

/// Each probe's offset from its cell centre (`Vec3::ZERO` where it stays),
/// in probe order, against `occluder`.
pub fn offsets(occluder: &Occluder, grid: &ProbeGrid, seed: u64) -> Vec<Vec3> {
    offsets_two_sided(occluder, &[], grid, seed)
}

/// [`offsets`] where the triangles `t` with `double_sided[t]` are
/// double-sided (a glTF material's `doubleSided`): their back is a surface
/// as their front is, so a ray that meets it meets no back face. An empty
/// slice: every triangle is one-sided, as [`offsets`].
pub fn offsets_two_sided(
    occluder: &Occluder,
    double_sided: &[bool],
    grid: &ProbeGrid,
    seed: u64,
) -> Vec<Vec3> {
    let occluder = &Against {
        occluder,
        double_sided,
    };
    let dirs: Vec<Direction> = stratified_directions(RELOCATION_RAYS, seed ^ 0x0ff5_e7ed)
        .iter()
        .map(|d| Direction::new(d.as_vec3()))
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
    let lattice: Vec<Vec3> = lattice.into_iter().map(offset).collect();
    let centres = grid.centres();
    // The centres first, eight probes a packet.
    let mut out = vec![Vec3::ZERO; centres.len()];
    let mut stuck: Vec<usize> = Vec::new();
    let looks: Vec<Look> = centres
        .par_chunks(LANES)
        .flat_map_iter(|eight| look(occluder, &dirs, eight, clearance))
        .collect();
    for (k, l) in looks.iter().enumerate() {
        if !l.is_free(clearance) {
            stuck.push(k);
        }
    }
    let moved: Vec<Vec3> = stuck
        .par_iter()
        .map(|&k| {
            place(
                occluder,
                &dirs,
                centres[k],
                looks[k].inside,
                &lattice,
                clearance,
            )
        })
        .collect();
    for (&k, o) in stuck.iter().zip(moved) {
        out[k] = o;
    }
    out
}

/// The offset of a probe whose centre is not free: the first free
/// candidate of `lattice` (in its order), else the one with the most
/// clearance outside geometry (the centre among them, `centre_inside`
/// whether its first look found it inside), else none.
///
/// The second search casts again only what the first left open: a
/// candidate the first found inside geometry is inside whatever a nearer
/// hit would have settled (the same rays in the same order reach the same
/// back faces), so only the others are cast, eight at a time in order,
/// and a candidate's rays stop once its nearest hit is below the most
/// clearance found so far (it cannot be taken).
fn place(
    occluder: &Against,
    dirs: &[Direction],
    centre: Vec3,
    centre_inside: bool,
    lattice: &[Vec3],
    clearance: f32,
) -> Vec3 {
    let mut points = [Vec3::ZERO; LANES];
    // Whether the first search found each candidate inside geometry.
    let mut inside = Vec::with_capacity(lattice.len());
    for batch in lattice.chunks(LANES) {
        for (p, o) in points.iter_mut().zip(batch) {
            *p = centre + *o;
        }
        let looks = look(occluder, dirs, &points[..batch.len()], clearance);
        if let Some(i) = looks.iter().position(|l| l.is_free(clearance)) {
            return batch[i];
        }
        inside.extend(looks.iter().map(|l| l.inside));
    }
    // None free: the most clearance outside geometry, the centre first
    // (`centre_inside`: what `offsets` found of it).
    let open: Vec<Vec3> = (!centre_inside)
        .then_some(Vec3::ZERO)
        .into_iter()
        .chain(
            lattice
                .iter()
                .zip(&inside)
                .filter(|(_, inside)| !**inside)
                .map(|(o, _)| *o),
        )
        .collect();
    let mut best: Option<(f32, Vec3)> = None;
    for batch in open.chunks(LANES) {
        for (p, o) in points.iter_mut().zip(batch) {
            *p = centre + *o;
        }
        let floor = best.map_or(0.0, |(c, _)| c);
        let looks = look(occluder, dirs, &points[..batch.len()], floor);
        for (l, o) in looks.iter().zip(batch) {
            if !l.inside && best.is_none_or(|(c, _)| l.clearance > c) {
                best = Some((l.clearance, *o));
            }
        }
    }
    best.map_or(Vec3::ZERO, |(_, o)| o)
}

/// The rays from each of `points` (at most [`LANES`], cast together as
/// packets along each direction): whether it is inside geometry (more than
/// [`INSIDE_BACKFACES`] of them on back faces) and its clearance (the
/// nearest hit). A point's answer is settled, and its rays may stop, once
/// a hit is nearer than `stop_within` (the clearance is then that hit's,
/// and `inside` is false though the rest might have said otherwise) or
/// its back faces are already too many; the packets stop when every
/// point's answer is.
fn look(against: &Against, dirs: &[Direction], points: &[Vec3], stop_within: f32) -> Vec<Look> {
    let n = points.len();
    let limit = INSIDE_BACKFACES * dirs.len() as f32;
    let mut back = [0usize; LANES];
    let mut nearest = [f32::INFINITY; LANES];
    let mut inside = [false; LANES];
    let mut settled = 0u32;
    let all = ((1u64 << n) - 1) as u32;
    // The points still open, packed into the first lanes (a ray's hit
    // does not depend on the other rays of its packet, and settled ones
    // would only widen the walk).
    let mut open = [Vec3::ZERO; LANES];
    let mut lane_of = [0usize; LANES];
    for dir in dirs {
        let mut m = 0;
        for k in 0..n {
            if settled >> k & 1 == 0 {
                open[m] = points[k];
                lane_of[m] = k;
                m += 1;
            }
        }
        let packet = Packet::new(dir, &open[..m]);
        let found = against.occluder.packet_closest_direct(dir, &packet);
        for (j, &k) in lane_of[..m].iter().enumerate() {
            if found.mask >> j & 1 == 0 {
                continue;
            }
            nearest[k] = nearest[k].min(found.t[j]);
            if against.meets_back(found.triangle[j], dir.dir()) {
                back[k] += 1;
                if back[k] as f32 > limit {
                    inside[k] = true;
                    settled |= 1 << k;
                    continue;
                }
            }
            if nearest[k] < stop_within {
                settled |= 1 << k;
            }
        }
        if settled == all {
            break;
        }
    }
    (0..n)
        .map(|k| Look {
            inside: inside[k],
            clearance: nearest[k],
        })
        .collect()
}

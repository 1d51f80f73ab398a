//! Light through walls: two sealed rooms side by side, split by a wall
//! 4 cm thick, a lamp in one, an 8x3x4 grid of 0.5 m cells over both. The
//! visibility-weighted lookup keeps the dark room dark next to the wall and
//! the lit room as its own probes light it; plain trilinear interpolation
//! leaks both ways, so the test can tell the two apart. The wall stands at
//! several places inside a cell: on a cell boundary, through a column of
//! probes (which relocation moves out), and near either side of a column.

use glam::{DVec3, Vec3};
use shlight_baked::{ProbeGrid, VolumeView};
use shlight_core::sh::{ShCoeffs, irradiance, sh_count};
use shlight_mesh::Mesh;
use shlight_volume::{Lookup, PreparedLookup, VolumeBake, VolumeOptions, bake};

/// The rooms' extent along y and z; along x the pair spans 0..4.
const HEIGHT: f32 = 1.5;
const DEPTH: f32 = 2.0;
/// Half the wall's thickness.
const HALF_WALL: f32 = 0.02;

/// Quads `(corners, emission)` as one mesh, each quad facing `(b - a) x
/// (c - a)`.
fn quads(list: &[([Vec3; 4], Vec3)]) -> Mesh {
    let (mut positions, mut triangles, mut emission) = (Vec::new(), Vec::new(), Vec::new());
    for (corners, e) in list {
        let base = positions.len() as u32;
        positions.extend_from_slice(corners);
        emission.extend([*e; 4]);
        triangles.push([base, base + 1, base + 2]);
        triangles.push([base, base + 2, base + 3]);
    }
    Mesh::new("two rooms", positions, triangles, None, None)
        .unwrap()
        .with_emission("two rooms", emission)
        .unwrap()
}

/// The six faces of the box `lo..hi`, facing inwards.
fn room(lo: Vec3, hi: Vec3) -> Vec<([Vec3; 4], Vec3)> {
    let c = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let (a, b) = (lo, hi);
    [
        // Floor (up), ceiling (down).
        [
            c(a.x, a.y, a.z),
            c(a.x, a.y, b.z),
            c(b.x, a.y, b.z),
            c(b.x, a.y, a.z),
        ],
        [
            c(a.x, b.y, a.z),
            c(b.x, b.y, a.z),
            c(b.x, b.y, b.z),
            c(a.x, b.y, b.z),
        ],
        // x = a (facing +x), x = b (facing -x).
        [
            c(a.x, a.y, a.z),
            c(a.x, b.y, a.z),
            c(a.x, b.y, b.z),
            c(a.x, a.y, b.z),
        ],
        [
            c(b.x, a.y, a.z),
            c(b.x, a.y, b.z),
            c(b.x, b.y, b.z),
            c(b.x, b.y, a.z),
        ],
        // z = a (facing +z), z = b (facing -z).
        [
            c(a.x, a.y, a.z),
            c(b.x, a.y, a.z),
            c(b.x, b.y, a.z),
            c(a.x, b.y, a.z),
        ],
        [
            c(a.x, a.y, b.z),
            c(a.x, b.y, b.z),
            c(b.x, b.y, b.z),
            c(b.x, a.y, b.z),
        ],
    ]
    .into_iter()
    .map(|q| (q, Vec3::ZERO))
    .collect()
}

/// Two rooms split by a wall centred at `x = wall`, a lamp under the left
/// room's ceiling facing down.
fn two_rooms(wall: f32) -> Mesh {
    let (left, right) = (wall - HALF_WALL, wall + HALF_WALL);
    let mut list = room(Vec3::ZERO, Vec3::new(left, HEIGHT, DEPTH));
    list.extend(room(
        Vec3::new(right, 0.0, 0.0),
        Vec3::new(4.0, HEIGHT, DEPTH),
    ));
    let y = HEIGHT - 0.05;
    let (x0, x1, z0, z1) = (0.4, left - 0.4, 0.5, DEPTH - 0.5);
    list.push((
        [
            Vec3::new(x0, y, z0),
            Vec3::new(x1, y, z0),
            Vec3::new(x1, y, z1),
            Vec3::new(x0, y, z1),
        ],
        Vec3::splat(4.0),
    ));
    quads(&list)
}

fn options() -> VolumeOptions {
    VolumeOptions {
        lmax: 2,
        samples: 1024,
        surface_samples: 256,
        bounces: 1,
        seed: 11,
        ..VolumeOptions::default()
    }
}

/// The probes' radiance: the lamp's light only (no sky reaches in).
fn lit(volume: &VolumeBake) -> Vec<f32> {
    volume.relight(&ShCoeffs::zeros(volume.lmax))
}

/// `lookup`'s irradiance at `p` facing `n`, the lookup prepared for the
/// one point.
fn irradiance_at(view: &VolumeView<'_>, lookup: Lookup, lmax: usize, p: Vec3, n: Vec3) -> DVec3 {
    PreparedLookup::new(view, lookup, lmax).irradiance_at(p, n)
}

/// Luminance-free: the mean of the three channels.
fn grey(e: DVec3) -> f64 {
    e.element_sum() / 3.0
}

/// Height of the floor points above the floor (where a probe can be baked
/// for reference).
const ABOVE: f32 = 0.05;
/// Distance of the points next to the wall from its faces.
const BESIDE: f32 = 0.07;
/// The depths of the points next to the wall.
const DEPTHS: [f32; 3] = [0.5, 1.0, 1.5];

#[test]
fn the_dark_room_stays_dark_and_the_lit_room_lit_next_to_a_thin_wall() {
    let grid = ProbeGrid::new([8, 3, 4], Vec3::ZERO, Vec3::new(4.0, HEIGHT, DEPTH)).unwrap();
    for wall in [2.0f32, 2.1, 2.25, 2.4] {
        let scene = two_rooms(wall);
        let volume = bake(Some(&scene), &grid, &options(), &|_, _, _| {}).unwrap();
        let radiance = lit(&volume);
        let v = volume.view(&radiance);
        let e = |lookup, p: Vec3| grey(irradiance_at(&v, lookup, 2, p, Vec3::Y));
        // The lit room's mean floor irradiance, on a grid of points.
        let (left, right) = (wall - HALF_WALL, wall + HALF_WALL);
        let mut floor = Vec::new();
        let mut x = 0.25;
        while x < left - 0.1 {
            for z in [0.25, 0.75, 1.25, 1.75] {
                floor.push(e(Lookup::Shlight, Vec3::new(x, ABOVE, z)));
            }
            x += 0.25;
        }
        let mean = floor.iter().sum::<f64>() / floor.len() as f64;
        assert!(mean > 0.1, "the lamp lights the floor: {mean}");
        // Probes baked at the points next to the wall, on either side, as
        // the truth: a grid of 2 x 1 x 3 probes at exactly those points.
        let (xl, xr) = (left - BESIDE, right + BESIDE);
        let half = (xr - xl) / 2.0;
        let truth_grid = ProbeGrid::new(
            [2, 1, 3],
            Vec3::new(xl - half, ABOVE - 0.01, 0.25),
            Vec3::new(xr + half, ABOVE + 0.01, 1.75),
        )
        .unwrap();
        let truth = bake(Some(&scene), &truth_grid, &options(), &|_, _, _| {}).unwrap();
        assert_eq!(truth.relocated_count(), 0);
        let truth_radiance = lit(&truth);
        let nc = sh_count(2);
        let truth_at = |k: usize| -> f64 {
            let l = ShCoeffs::from_vec(
                truth_radiance[k * 3 * nc..][..3 * nc]
                    .chunks_exact(3)
                    .map(|c| Vec3::from_slice(c).as_dvec3())
                    .collect(),
            )
            .unwrap();
            grey(irradiance(&l).eval(DVec3::Y))
        };
        // What the lit room's own probes give: trilinear interpolation with
        // every probe beyond the wall's centre (where the bake put it)
        // left out, the lookup a wall needs.
        let lit_only: Vec<bool> = (0..volume.probe_count())
            .map(|k| volume.valid[k] && v.position(k).x < wall)
            .collect();
        let own = VolumeView {
            valid: &lit_only,
            ..v
        };
        let (mut dark_worst, mut lit_worst, mut leak_trilinear) = (0.0f64, 0.0f64, 0.0f64);
        let (mut dark_trilinear, mut truth_worst) = (0.0f64, 0.0f64);
        for (iz, z) in DEPTHS.into_iter().enumerate() {
            let centre = truth_grid.centre([0, 0, iz]);
            assert!((centre - Vec3::new(xl, ABOVE, z)).length() < 1e-5);
            // Dark side: the truth is no light at all.
            let dark = Vec3::new(xr, ABOVE, z);
            assert!(truth_at(truth_grid.index([1, 0, iz])) < 1e-3 * mean);
            dark_worst = dark_worst.max(e(Lookup::Shlight, dark) / mean);
            dark_trilinear = dark_trilinear.max(e(Lookup::Trilinear, dark) / mean);
            // Lit side: as the lit room's own probes light it.
            let lit = Vec3::new(xl, ABOVE, z);
            let want = grey(irradiance_at(&own, Lookup::Trilinear, 2, lit, Vec3::Y));
            let got = e(Lookup::Shlight, lit);
            lit_worst = lit_worst.max((got - want).abs() / want);
            leak_trilinear = leak_trilinear.max((e(Lookup::Trilinear, lit) - want).abs() / want);
            // And against a probe baked at the point (reported: a 0.5 m
            // grid cannot follow the light's fall towards the wall within
            // the last 0.2 m, lookup or not).
            let truth = truth_at(truth_grid.index([0, 0, iz]));
            truth_worst = truth_worst.max((got - truth).abs() / truth);
        }
        eprintln!(
            "wall at x = {wall}: dark side {:.2}% of the lit room's mean (trilinear {:.1}%); lit side within {:.2}% of the lit room's own probes (trilinear {:.1}%), within {:.0}% of a probe at the point; {} probes moved, {} invalid",
            100.0 * dark_worst,
            100.0 * dark_trilinear,
            100.0 * lit_worst,
            100.0 * leak_trilinear,
            100.0 * truth_worst,
            volume.relocated_count(),
            volume.invalid_count()
        );
        assert!(dark_worst <= 0.02, "wall at {wall}: dark side {dark_worst}");
        assert!(lit_worst <= 0.05, "wall at {wall}: lit side {lit_worst}");
        // Trilinear interpolation leaks into the dark room: lit probes are
        // among the eight around the point (at 2.25 those that relocation
        // moved out of the wall into the lit room).
        assert!(
            dark_trilinear > 0.1,
            "wall at {wall}: trilinear leaks only {dark_trilinear}"
        );
    }
}

/// Two storeys, one above the other, split by a floor slab 4 cm thick at
/// `y = slab`, a lamp under the upper storey's ceiling.
fn two_storeys(slab: f32) -> Mesh {
    let (below, above) = (slab - HALF_WALL, slab + HALF_WALL);
    let top = 3.0;
    let mut list = room(Vec3::ZERO, Vec3::new(2.0, below, DEPTH));
    list.extend(room(Vec3::new(0.0, above, 0.0), Vec3::new(2.0, top, DEPTH)));
    let y = top - 0.05;
    list.push((
        [
            Vec3::new(0.5, y, 0.5),
            Vec3::new(1.5, y, 0.5),
            Vec3::new(1.5, y, 1.5),
            Vec3::new(0.5, y, 1.5),
        ],
        Vec3::splat(4.0),
    ));
    quads(&list)
}

#[test]
fn a_grid_that_straddles_a_floor_keeps_the_storey_below_dark() {
    // Cells of 0.5 m, the slab between two rows of probes, midway (1.5)
    // and near the lower one (1.4): the lower storey's ceiling, 7 cm under
    // the slab, is dark for the visibility lookup and lit for trilinear.
    // (A wall through a row of probes is the rooms' test's.)
    let grid = ProbeGrid::new([4, 6, 4], Vec3::ZERO, Vec3::new(2.0, 3.0, DEPTH)).unwrap();
    for slab in [1.4f32, 1.5] {
        let scene = two_storeys(slab);
        let volume = bake(Some(&scene), &grid, &options(), &|_, _, _| {}).unwrap();
        assert_eq!(volume.invalid_count(), 0, "relocation frees every probe");
        let radiance = lit(&volume);
        let v = volume.view(&radiance);
        let e = |lookup, p: Vec3, n: Vec3| grey(irradiance_at(&v, lookup, 2, p, n));
        // The upper floor's mean irradiance, facing up.
        let mut upper = Vec::new();
        for x in [0.25, 0.75, 1.25, 1.75] {
            for z in [0.25, 0.75, 1.25, 1.75] {
                upper.push(e(Lookup::Shlight, Vec3::new(x, slab + 0.1, z), Vec3::Y));
            }
        }
        let mean = upper.iter().sum::<f64>() / upper.len() as f64;
        assert!(mean > 0.1, "{mean}");
        let (mut worst, mut trilinear) = (0.0f64, 0.0f64);
        for x in [0.25, 0.75, 1.25, 1.75] {
            for z in [0.25, 0.75, 1.25, 1.75] {
                // The lower storey's ceiling, facing down, and its walls'
                // tops, facing sideways.
                for (p, n) in [
                    (Vec3::new(x, slab - 0.09, z), Vec3::NEG_Y),
                    (Vec3::new(0.05, slab - 0.15, z), Vec3::X),
                ] {
                    worst = worst.max(e(Lookup::Shlight, p, n) / mean);
                    trilinear = trilinear.max(e(Lookup::Trilinear, p, n) / mean);
                }
            }
        }
        eprintln!(
            "slab at y = {slab}: the storey below at most {:.2}% of the upper floor's mean (trilinear {:.1}%); {} probes moved",
            100.0 * worst,
            100.0 * trilinear,
            volume.relocated_count()
        );
        assert!(worst <= 0.02, "slab at {slab}: {worst}");
        assert!(trilinear > 0.05, "slab at {slab}: trilinear {trilinear}");
    }
}

/// What relocation and dilation alone buy under the engines' own lookups,
/// which know no visibility: the dark room's floor next to the wall under
/// Bevy's and three.js's lookups of a bake with and without relocation
/// (both dilate invalid probes). They stay far above what the visibility
/// lookup gives: a wall between two probes is invisible to trilinear
/// interpolation wherever the probes are.
#[test]
fn the_engines_lookups_leak_with_or_without_relocation() {
    let grid = ProbeGrid::new([8, 3, 4], Vec3::ZERO, Vec3::new(4.0, HEIGHT, DEPTH)).unwrap();
    for wall in [2.0f32, 2.25] {
        let scene = two_rooms(wall);
        let mut row = Vec::new();
        for relocate in [false, true] {
            let options = VolumeOptions {
                relocate,
                ..options()
            };
            let volume = bake(Some(&scene), &grid, &options, &|_, _, _| {}).unwrap();
            let radiance = lit(&volume);
            let v = volume.view(&radiance);
            let e = |lookup, p: Vec3| grey(irradiance_at(&v, lookup, 2, p, Vec3::Y));
            let left = wall - HALF_WALL;
            let mut floor = Vec::new();
            let mut x = 0.25;
            while x < left - 0.1 {
                for z in [0.25, 0.75, 1.25, 1.75] {
                    floor.push(e(Lookup::Shlight, Vec3::new(x, ABOVE, z)));
                }
                x += 0.25;
            }
            let mean = floor.iter().sum::<f64>() / floor.len() as f64;
            for lookup in [Lookup::Bevy, Lookup::ThreeJs, Lookup::Shlight] {
                let leak = DEPTHS
                    .iter()
                    .map(|&z| e(lookup, Vec3::new(wall + HALF_WALL + BESIDE, ABOVE, z)) / mean)
                    .fold(0.0f64, f64::max);
                row.push(format!(
                    "{lookup} {}: {:.1}%",
                    if relocate { "relocated" } else { "at centres" },
                    100.0 * leak
                ));
                if lookup != Lookup::Shlight {
                    assert!(leak > 0.05, "wall at {wall}, {lookup}: {leak}");
                }
            }
        }
        eprintln!("wall at x = {wall}: {}", row.join(", "));
    }
}

/// `shlight sample`'s prepared lookup (the probes' irradiance coefficients
/// made once) gives the irradiance of the radiance it reads at the point
/// (shlight-core's `irradiance` of the probes' weighted radiance),
/// visibility and all, at random points and normals through the two
/// rooms, at every lmax.
#[test]
fn the_prepared_lookup_is_the_irradiance_of_its_radiance() {
    use rand::{Rng, SeedableRng};
    let grid = ProbeGrid::new([8, 3, 4], Vec3::ZERO, Vec3::new(4.0, HEIGHT, DEPTH)).unwrap();
    let scene = two_rooms(2.25);
    let volume = bake(Some(&scene), &grid, &options(), &|_, _, _| {}).unwrap();
    let radiance = lit(&volume);
    let v = volume.view(&radiance);
    let mut rng = rand::rngs::StdRng::seed_from_u64(5);
    for lookup in [Lookup::Shlight, Lookup::Trilinear] {
        for lmax in 0..=2 {
            let prepared = PreparedLookup::new(&v, lookup, lmax);
            for _ in 0..300 {
                let p = Vec3::new(
                    rng.random_range(-0.2..4.2),
                    rng.random_range(0.0..HEIGHT),
                    rng.random_range(0.0..DEPTH),
                );
                let n = Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                let want = prepared.radiance_at(p, n).map_or(DVec3::ZERO, |l| {
                    irradiance(&l).eval(n.as_dvec3().normalize())
                });
                let got = prepared.irradiance_at(p, n);
                assert!(
                    (got - want).abs().max_element() <= 1e-12 * want.abs().max_element().max(1.0),
                    "{lookup} lmax {lmax} at {p} {n}: {got} vs {want}"
                );
            }
        }
    }
}

//! Environment-map layouts (`shlight_core::map`), checked against
//! independent routes: brute-force integration of texel solid angles,
//! the equirect formulas of `projection`, round trips through
//! `direction_to_image`, the geometry of seams, and projection of rendered
//! band-limited functions against their known coefficients.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use shlight_core::map::{
    CubeFace, EnvMap, Layout, LayoutSizeErrorKind, MapOrientation, RadianceMap,
    cube_texel_solid_angle, equirect_direction, equirect_row_solid_angle, project_map, render_map,
};
use shlight_core::sh::{Frame, ShCoeffs, closed_form, gauss_legendre};

fn orientations() -> [MapOrientation; 4] {
    let o = |frame, mirror| MapOrientation { frame, mirror };
    [
        o(Frame::YUp, false),
        o(Frame::YUp, true),
        o(Frame::ZUp, false),
        o(Frame::ZUp, true),
    ]
}

/// Maps a world direction back to the y-up map frame (the inverse of the
/// orientation rule in the module docs, written out independently).
fn map_frame(o: MapOrientation, d: DVec3) -> DVec3 {
    let d = match o.frame {
        Frame::YUp => d,
        // z-up world = (x, -z, y) of the y-up map: invert.
        Frame::ZUp => DVec3::new(d.x, d.z, -d.y),
    };
    if o.mirror {
        DVec3::new(d.x, d.y, -d.z)
    } else {
        d
    }
}

fn map(layout: Layout, o: MapOrientation, w: usize, h: usize, px: &[[f32; 3]]) -> EnvMap<'_> {
    EnvMap::new(layout, o, w, h, px).unwrap()
}

/// A map without pixels, for the geometry methods.
fn geometry(layout: Layout, o: MapOrientation, w: usize, h: usize) -> EnvMap<'static> {
    EnvMap {
        layout,
        orientation: o,
        width: w,
        height: h,
        pixels: &[],
    }
}

/// Disc coordinates of the centre of texel `(x, y)` of an `n x n` disc map.
fn disc_centre(x: usize, y: usize, n: usize) -> (f64, f64) {
    let n = n as f64;
    (
        (2.0 * x as f64 + 1.0 - n) / n,
        (n - 2.0 * y as f64 - 1.0) / n,
    )
}

// ---------------------------------------------------------------- solid angles

/// Neumaier's compensated sum: the sums below add up to 6 million terms,
/// whose plain `f64` sum would itself be off by `~1e-12`.
fn sum(values: &[f64]) -> f64 {
    let (mut s, mut c) = (0.0f64, 0.0f64);
    for &v in values {
        let t = s + v;
        c += if s.abs() >= v.abs() {
            (s - t) + v
        } else {
            (v - t) + s
        };
        s = t;
    }
    s + c
}

/// Sum of all cube texels against `4π`: each texel is accurate to a few
/// ulps relative, so the sum of `6 f^2` of them is off by `~1e-15 · 4π`
/// plus summation rounding; measured below `4e-14` to `f = 512`.
const CUBE_SUM_TOL: f64 = 1e-12;

/// Sum of disc texels against `4π`: interior texels carry a rule error
/// below `1e-17 π² h²` each, rim texels the polar rule's rounding (~`1e-16
/// N` relative); measured below `1e-13` to `N = 512`.
const DISC_SUM_TOL: f64 = 1e-12;

#[test]
fn solid_angles_sum_to_four_pi() {
    let o = MapOrientation::default();
    for f in [1usize, 2, 7, 64, 512] {
        for layout in [
            Layout::CrossHorizontal,
            Layout::CrossVertical,
            Layout::Strip,
        ] {
            let (w, h) = layout.dimensions(f);
            let total = sum(&geometry(layout, o, w, h).texel_solid_angles());
            assert!(
                (total - 4.0 * PI).abs() < CUBE_SUM_TOL,
                "{layout} f {f}: {:e}",
                total - 4.0 * PI
            );
        }
    }
    for n in [1usize, 2, 3, 10, 101, 512] {
        for layout in [Layout::Angular, Layout::MirrorBall] {
            let total = sum(&geometry(layout, o, n, n).texel_solid_angles());
            assert!(
                (total - 4.0 * PI).abs() < DISC_SUM_TOL,
                "{layout} n {n}: {:e}",
                total - 4.0 * PI
            );
        }
    }
    for (w, h) in [(2, 1), (64, 32), (100, 37)] {
        let total = sum(&geometry(Layout::Equirect, o, w, h).texel_solid_angles());
        assert!((total - 4.0 * PI).abs() < 1e-12, "equirect {w}x{h}");
    }
}

/// Texels with no direction cover nothing, and the single-texel accessor
/// agrees with the bulk one.
#[test]
fn unused_texels_have_no_solid_angle() {
    for layout in Layout::ALL {
        let (w, h) = layout.dimensions(6);
        for o in orientations() {
            let m = geometry(layout, o, w, h);
            let all = m.texel_solid_angles();
            for y in 0..h {
                for x in 0..w {
                    let omega = m.texel_solid_angle(x, y);
                    assert_eq!(omega, all[y * w + x]);
                    assert_eq!(
                        m.texel_direction(x, y).is_some(),
                        omega > 0.0,
                        "{layout} ({x},{y})"
                    );
                }
            }
            assert_eq!(m.texel_direction(w, 0), None);
            assert_eq!(m.texel_solid_angle(0, h), 0.0);
        }
    }
}

/// `int dA / (1 + x² + y²)^(3/2)` over the texel by 8 x 8 sub-squares of a
/// 10-point Gauss-Legendre rule: the integrand is smooth on the scale of the
/// face, so this converges far below the tolerance.
fn cube_brute_force(i: usize, j: usize, f: usize) -> f64 {
    let (t, w) = gauss_legendre(10);
    let sub = 8;
    let h = 2.0 / f as f64;
    let (x0, y0) = (-1.0 + i as f64 * h, -1.0 + j as f64 * h);
    let hs = h / sub as f64;
    let mut sum = 0.0;
    for sj in 0..sub {
        for si in 0..sub {
            let (cx, cy) = (x0 + (si as f64 + 0.5) * hs, y0 + (sj as f64 + 0.5) * hs);
            for (a, wa) in t.iter().zip(&w) {
                for (b, wb) in t.iter().zip(&w) {
                    let (x, y) = (cx + 0.5 * hs * a, cy + 0.5 * hs * b);
                    sum += wa * wb * (1.0 + x * x + y * y).powf(-1.5);
                }
            }
        }
    }
    sum * 0.25 * hs * hs
}

#[test]
fn cube_texel_solid_angle_matches_brute_force() {
    for f in [1usize, 3, 16, 255] {
        let step = (f / 7).max(1);
        for j in (0..f).step_by(step) {
            for i in (0..f).step_by(step) {
                let got = cube_texel_solid_angle(i, j, f);
                let want = cube_brute_force(i, j, f);
                assert!(
                    (got - want).abs() < 1e-13 * want,
                    "f {f} ({i},{j}): {got} vs {want}"
                );
            }
        }
    }
}

/// Angle (radians) of the circle of radius `r` inside the rectangle.
fn arc_inside(r: f64, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    let mut cuts = vec![0.0, TAU];
    for (a, vertical) in [(u0, true), (u1, true), (v0, false), (v1, false)] {
        if a.abs() <= r {
            let b = (r * r - a * a).sqrt();
            for b in [b, -b] {
                let (x, y) = if vertical { (a, b) } else { (b, a) };
                cuts.push(y.atan2(x).rem_euclid(TAU));
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    cuts.windows(2)
        .filter(|p| {
            let m = 0.5 * (p[0] + p[1]);
            let (x, y) = (r * m.cos(), r * m.sin());
            (u0..=u1).contains(&x) && (v0..=v1).contains(&y)
        })
        .map(|p| p[1] - p[0])
        .sum()
}

/// The solid angle of a disc texel integrated radius first (the library
/// integrates angle first): `int w(r) r arc(r) dr` with the radius range
/// cut at every corner and tangency radius, each piece split in two and
/// substituted `r = a + (m - a) s²` so that the square-root behaviour of
/// `arc` at tangencies becomes smooth, then 30-point Gauss-Legendre.
fn disc_radius_first(layout: Layout, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    let weight = |r: f64| match layout {
        Layout::Angular => PI * (PI * r).sin(),
        _ => 4.0 * r,
    };
    let near = 0.0f64.clamp(u0, u1).hypot(0.0f64.clamp(v0, v1));
    let far = u0.abs().max(u1.abs()).hypot(v0.abs().max(v1.abs()));
    let mut radii = vec![near, far.min(1.0)];
    for a in [u0.abs(), u1.abs(), v0.abs(), v1.abs()] {
        radii.push(a);
    }
    for x in [u0, u1] {
        for y in [v0, v1] {
            radii.push(x.hypot(y));
        }
    }
    radii.retain(|&r| r >= near && r <= far.min(1.0));
    radii.sort_by(f64::total_cmp);
    let (t, w) = gauss_legendre(30);
    let mut total = 0.0;
    for p in radii.windows(2) {
        let (a, b) = (p[0], p[1]);
        if b <= a {
            continue;
        }
        let m = 0.5 * (a + b);
        for (from, len) in [(a, m - a), (b, -(b - m))] {
            for (ti, wi) in t.iter().zip(&w) {
                let s = 0.5 * (ti + 1.0);
                let r = from + len * s * s;
                let g = weight(r) * arc_inside(r, u0, u1, v0, v1);
                total += 0.5 * wi * g * 2.0 * len.abs() * s;
            }
        }
    }
    total
}

#[test]
fn disc_texel_solid_angles_match_a_radius_first_integration() {
    for layout in [Layout::Angular, Layout::MirrorBall] {
        for (n, step) in [(1usize, 1usize), (2, 1), (5, 1), (16, 1), (64, 3)] {
            let m = geometry(layout, MapOrientation::default(), n, n);
            let h = 2.0 / n as f64;
            for y in (0..n).step_by(step) {
                for x in (0..n).step_by(step) {
                    let (u0, v1) = (-1.0 + x as f64 * h, 1.0 - y as f64 * h);
                    let want = disc_radius_first(layout, u0, u0 + h, v1 - h, v1);
                    let got = m.texel_solid_angle(x, y);
                    assert!(
                        (got - want).abs() <= 1e-12 * want.max(h * h),
                        "{layout} n {n} ({x},{y}): {got} vs {want}"
                    );
                }
            }
        }
    }
}

/// Solid angle of the rim texels whose centre lies outside the disc (what
/// an image sampled at texel centres only leaves black): the figures quoted
/// in the module docs.
#[test]
fn rim_texels_outside_the_centre_disc_cover_little() {
    let n = 512;
    for (layout, most) in [(Layout::Angular, 3e-5), (Layout::MirrorBall, 2e-2)] {
        let m = geometry(layout, MapOrientation::default(), n, n);
        let mut rim = 0.0;
        for y in 0..n {
            for x in 0..n {
                let (u, v) = disc_centre(x, y, n);
                if u * u + v * v > 1.0 {
                    rim += m.texel_solid_angle(x, y);
                }
            }
        }
        eprintln!("{layout} n {n}: rim texels outside the disc cover {rim:.3e} sr");
        assert!(rim > 0.0 && rim < most, "{layout}: {rim}");
    }
}

// ------------------------------------------------------ directions and images

/// Pixel tolerance of `direction_to_image(texel_direction(x, y))`: the
/// inverse trigonometry loses at most ~`1e-13` of the disc radius near the
/// mirror ball's rim; everything else is a few ulps.
const ROUND_TRIP_TOL: f64 = 1e-9;

fn small_sizes(layout: Layout) -> Vec<(usize, usize)> {
    match layout {
        Layout::Equirect => vec![(16, 8), (7, 5)],
        Layout::Angular | Layout::MirrorBall => vec![(9, 9), (10, 10), (33, 33)],
        cube => vec![cube.dimensions(5), cube.dimensions(8)],
    }
}

#[test]
fn direction_to_image_inverts_texel_direction() {
    for layout in Layout::ALL {
        for (w, h) in small_sizes(layout) {
            for o in orientations() {
                let m = geometry(layout, o, w, h);
                let mut checked = 0;
                for y in 0..h {
                    for x in 0..w {
                        let Some(d) = m.texel_direction(x, y) else {
                            continue;
                        };
                        assert!((d.length() - 1.0).abs() < 1e-15);
                        if layout.is_disc() {
                            let (u, v) = disc_centre(x, y, w);
                            if u * u + v * v > 1.0 {
                                continue; // rim texel: the rim direction
                            }
                        }
                        let (px, py) = m.direction_to_image(d);
                        assert!(
                            (px - x as f64 - 0.5).abs() < ROUND_TRIP_TOL
                                && (py - y as f64 - 0.5).abs() < ROUND_TRIP_TOL,
                            "{layout} {w}x{h} {o:?} ({x},{y}) -> ({px},{py})"
                        );
                        checked += 1;
                    }
                }
                assert!(checked >= w * h / 2, "{layout}: only {checked} texels");
            }
        }
    }
}

#[test]
fn equirect_texels_match_projection_equirect_direction() {
    for (w, h) in [(16, 8), (7, 5), (64, 32)] {
        for o in orientations() {
            let m = geometry(Layout::Equirect, o, w, h);
            for y in 0..h {
                for x in 0..w {
                    let got = m.texel_direction(x, y).unwrap();
                    let want = equirect_direction(x, y, w, h, o);
                    assert!((got - want).length() < 1e-15, "{o:?} ({x},{y})");
                    assert_eq!(m.texel_solid_angle(x, y), equirect_row_solid_angle(y, w, h));
                }
            }
        }
    }
}

/// Rim texels carry the rim's direction: `+Z` (angular), `-Z` (mirror
/// ball) in the map frame.
#[test]
fn disc_rim_texels_carry_the_rim_direction() {
    for (layout, pole) in [
        (Layout::Angular, DVec3::Z),
        (Layout::MirrorBall, DVec3::NEG_Z),
    ] {
        for o in orientations() {
            let n = 10;
            let m = geometry(layout, o, n, n);
            let mut rim = 0;
            for y in 0..n {
                for x in 0..n {
                    let (u, v) = disc_centre(x, y, n);
                    if u * u + v * v > 1.0
                        && let Some(d) = m.texel_direction(x, y)
                    {
                        assert!((map_frame(o, d) - pole).length() < 1e-15);
                        rim += 1;
                    }
                }
            }
            // The corners lie wholly outside; the 8 texels at the ends of
            // the middle rows/columns and their neighbours are rim texels.
            assert!(rim > 0 && m.texel_direction(0, 0).is_none(), "{layout}");
        }
    }
}

/// Face order and orientation, pinned in the y-up frame with odd faces
/// (the centre texel is the face centre): each face cell's centre looks
/// along its axis, and the top-centre / left-centre texels lean toward the
/// documented axes.
#[test]
fn cube_faces_sit_and_turn_as_documented() {
    let f = 5;
    let c = f / 2;
    // (face, toward the top of the face image, toward its left)
    let expect = [
        (CubeFace::PosX, DVec3::Y, DVec3::Z),
        (CubeFace::NegX, DVec3::Y, DVec3::NEG_Z),
        (CubeFace::PosY, DVec3::NEG_Z, DVec3::NEG_X),
        (CubeFace::NegY, DVec3::Z, DVec3::NEG_X),
        (CubeFace::PosZ, DVec3::Y, DVec3::NEG_X),
        (CubeFace::NegZ, DVec3::Y, DVec3::X),
    ];
    let cells = |layout| -> Vec<(CubeFace, usize, usize, bool)> {
        match layout {
            Layout::CrossHorizontal => vec![
                (CubeFace::PosY, 1, 0, false),
                (CubeFace::NegX, 0, 1, false),
                (CubeFace::PosZ, 1, 1, false),
                (CubeFace::PosX, 2, 1, false),
                (CubeFace::NegZ, 3, 1, false),
                (CubeFace::NegY, 1, 2, false),
            ],
            Layout::CrossVertical => vec![
                (CubeFace::PosY, 1, 0, false),
                (CubeFace::NegX, 0, 1, false),
                (CubeFace::PosZ, 1, 1, false),
                (CubeFace::PosX, 2, 1, false),
                (CubeFace::NegY, 1, 2, false),
                (CubeFace::NegZ, 1, 3, true),
            ],
            _ => CubeFace::ALL
                .iter()
                .enumerate()
                .map(|(k, &face)| (face, k, 0, false))
                .collect(),
        }
    };
    for layout in [
        Layout::CrossHorizontal,
        Layout::CrossVertical,
        Layout::Strip,
    ] {
        let (w, h) = layout.dimensions(f);
        let m = geometry(layout, MapOrientation::default(), w, h);
        for (face, col, row, rotated) in cells(layout) {
            let (x0, y0) = (col * f, row * f);
            assert_eq!(
                m.texel_direction(x0 + c, y0 + c),
                Some(face.axis()),
                "{layout} {face}"
            );
            let (top, left) = expect
                .iter()
                .find(|e| e.0 == face)
                .map(|e| (e.1, e.2))
                .unwrap();
            // A face turned by 180° shows its bottom at the top of the cell.
            let (top, left) = if rotated { (-top, -left) } else { (top, left) };
            let at_top = m.texel_direction(x0 + c, y0).unwrap();
            let at_left = m.texel_direction(x0, y0 + c).unwrap();
            assert!(
                at_top.dot(top) > 0.6 && at_top.dot(left).abs() < 1e-15,
                "{layout} {face} top"
            );
            assert!(
                at_left.dot(left) > 0.6 && at_left.dot(top).abs() < 1e-15,
                "{layout} {face} left"
            );
        }
        // Unused cells hold nothing.
        let (gc, gr) = layout.cube_grid().unwrap();
        let unused = (0..gr)
            .flat_map(|r| (0..gc).map(move |c| (c, r)))
            .filter(|&(cc, rr)| m.texel_direction(cc * f + c, rr * f + c).is_none())
            .count();
        assert_eq!(unused, gc * gr - 6, "{layout}");
    }
    // The +Z face's top-centre texel of a cross points toward +Y exactly as
    // the sampling rule says: tc = -1 + 1/f, so d ∝ (0, 1 - 1/f, 1).
    let m = geometry(
        Layout::CrossHorizontal,
        MapOrientation::default(),
        4 * f,
        3 * f,
    );
    let d = m.texel_direction(f + c, f).unwrap();
    let want = DVec3::new(0.0, 1.0 - 1.0 / f as f64, 1.0).normalize();
    assert!((d - want).length() < 1e-15);
}

#[test]
fn disc_centres_and_rims_point_as_documented() {
    let o = MapOrientation::default();
    let n = 101;
    let c = n / 2;
    let ang = geometry(Layout::Angular, o, n, n);
    let ball = geometry(Layout::MirrorBall, o, n, n);
    assert_eq!(ang.texel_direction(c, c), Some(DVec3::NEG_Z));
    assert_eq!(ball.texel_direction(c, c), Some(DVec3::Z));
    // The last texel of the middle row, just inside the rim.
    let a = ang.texel_direction(n - 1, c).unwrap();
    let b = ball.texel_direction(n - 1, c).unwrap();
    assert!(a.z > 0.999 && a.x > 0.0, "{a}");
    assert!(b.z < -0.95 && b.x > 0.0, "{b}");
    // Right is +X, up is +Y: where the axes land in the image.
    let nf = n as f64;
    let near =
        |p: (f64, f64), q: (f64, f64)| (p.0 - q.0).abs() < 1e-12 && (p.1 - q.1).abs() < 1e-12;
    assert!(near(
        ang.direction_to_image(DVec3::NEG_Z),
        (nf / 2.0, nf / 2.0)
    ));
    assert!(near(
        ang.direction_to_image(DVec3::X),
        (0.75 * nf, nf / 2.0)
    ));
    assert!(near(
        ang.direction_to_image(DVec3::Y),
        (nf / 2.0, 0.25 * nf)
    ));
    assert!(near(
        ang.direction_to_image(DVec3::NEG_X),
        (0.25 * nf, nf / 2.0)
    ));
    let s = 0.5 * (1.0 + std::f64::consts::FRAC_1_SQRT_2);
    assert!(near(
        ball.direction_to_image(DVec3::Z),
        (nf / 2.0, nf / 2.0)
    ));
    assert!(near(ball.direction_to_image(DVec3::X), (s * nf, nf / 2.0)));
    assert!(near(
        ball.direction_to_image(DVec3::NEG_Y),
        (nf / 2.0, s * nf)
    ));
    // The rim direction lands on the rim.
    assert!(near(ball.direction_to_image(DVec3::NEG_Z), (nf, nf / 2.0)));
    assert!(near(ang.direction_to_image(DVec3::Z), (nf, nf / 2.0)));
}

/// Orientation is the equirect rule for every layout: the world direction
/// of a texel read z-up and/or mirrored is the y-up reading turned
/// `(x, y, z) -> (x, -z, y)` and/or with `z` negated first.
#[test]
fn orientation_applies_the_same_way_to_every_layout() {
    for layout in Layout::ALL {
        let (w, h) = small_sizes(layout)[0];
        let base = geometry(layout, MapOrientation::default(), w, h);
        for o in orientations() {
            let m = geometry(layout, o, w, h);
            for y in 0..h {
                for x in 0..w {
                    match (base.texel_direction(x, y), m.texel_direction(x, y)) {
                        (Some(a), Some(b)) => {
                            assert!((map_frame(o, b) - a).length() < 1e-15, "{layout} {o:?}")
                        }
                        (None, None) => {}
                        other => panic!("{layout} {o:?} ({x},{y}): {other:?}"),
                    }
                }
            }
        }
    }
}

/// Across every seam inside a cross, image neighbours are sphere
/// neighbours: no wider apart than the widest pair inside a face.
#[test]
fn cross_seams_join_neighbouring_directions() {
    let f = 8;
    for layout in [Layout::CrossHorizontal, Layout::CrossVertical] {
        let (w, h) = layout.dimensions(f);
        let m = geometry(layout, MapOrientation::default(), w, h);
        let (mut inside, mut across, mut seams) = (0.0f64, 0.0f64, 0);
        for y in 0..h {
            for x in 0..w {
                for (nx, ny) in [(x + 1, y), (x, y + 1)] {
                    let (Some(a), Some(b)) = (m.texel_direction(x, y), m.texel_direction(nx, ny))
                    else {
                        continue;
                    };
                    let angle = a.angle_between(b);
                    if (x / f, y / f) == (nx / f, ny / f) {
                        inside = inside.max(angle);
                    } else {
                        across = across.max(angle);
                        seams += 1;
                    }
                }
            }
        }
        // Five seams of f texel pairs each in both crosses.
        assert_eq!(seams, 5 * f, "{layout}");
        assert!(across <= inside * 1.0001, "{layout}: {across} vs {inside}");
    }
}

// ------------------------------------------------------------------- lookups

fn smooth(d: DVec3) -> DVec3 {
    let a = DVec3::new(0.48, 0.6, -0.64);
    let s = 1.0 + 0.5 * d.dot(a) + 0.3 * d.x * d.y - 0.2 * d.z * d.z;
    DVec3::new(s, 2.0 - s, 0.5 * s)
}

fn random_direction(rng: &mut StdRng) -> DVec3 {
    let z: f64 = rng.random_range(-1.0..1.0);
    let p: f64 = rng.random_range(0.0..TAU);
    let s = (1.0 - z * z).sqrt();
    DVec3::new(s * p.cos(), s * p.sin(), z)
}

/// Bilinear lookup of a smooth function drawn into each layout: exact at
/// texel centres (to `f32`), and within `O(h²)` everywhere including seams
/// and the equirect wrap (a clamped seam would err by `O(h)`, a wrong face
/// by `O(1)`). Disc layouts are checked away from the rim, where the
/// renormalised taps extrapolate.
#[test]
fn bilinear_lookup_is_exact_at_centres_and_smooth_across_seams() {
    let mut rng = StdRng::seed_from_u64(7);
    for layout in Layout::ALL {
        let size = match layout {
            Layout::Equirect => 64,
            Layout::Angular | Layout::MirrorBall => 128,
            _ => 32,
        };
        let (w, h) = layout.dimensions(size);
        for o in orientations() {
            let px = render_map(layout, o, w, h, smooth).unwrap();
            let m = map(layout, o, w, h, &px);
            for y in (0..h).step_by(3) {
                for x in (0..w).step_by(3) {
                    let Some(d) = m.texel_direction(x, y) else {
                        continue;
                    };
                    if layout.is_disc() {
                        let (u, v) = disc_centre(x, y, w);
                        if u * u + v * v > 1.0 {
                            continue;
                        }
                    }
                    let got = m.radiance_bilinear(d);
                    let want = DVec3::from(px[y * w + x].map(f64::from));
                    assert!(
                        (got - want).abs().max_element() < 1e-6,
                        "{layout} ({x},{y})"
                    );
                }
            }
            let mut worst = 0.0f64;
            for _ in 0..4000 {
                let d = random_direction(&mut rng);
                if layout.is_disc() {
                    let (ix, iy) = m.direction_to_image(d);
                    let (u, v) = (2.0 * ix / w as f64 - 1.0, 1.0 - 2.0 * iy / w as f64);
                    if u * u + v * v > 0.8 {
                        continue;
                    }
                }
                worst = worst.max((m.radiance(d) - smooth(d)).abs().max_element());
            }
            // Measured worst 6e-4 (equirect), 9.7e-4 (cube faces of 32²,
            // with ~500 of the directions within a texel of a seam; fetching
            // the nearest texel across seams instead errs by 3e-3), 5.7e-4
            // (angular), 7.8e-4 (mirror ball).
            let tol = if layout.is_cube() { 1.3e-3 } else { 1e-3 };
            eprintln!("{layout} {o:?}: bilinear within {worst:.2e}");
            assert!(worst < tol, "{layout} {o:?}: {worst:e}");
        }
    }
    // The equirect wrap: columns 0 and W-1 blend across φ = ±π.
    let (w, h) = (16, 8);
    let o = MapOrientation::default();
    let mut px = vec![[0.0f32; 3]; w * h];
    for y in 0..h {
        px[y * w] = [1.0; 3];
    }
    let m = map(Layout::Equirect, o, w, h, &px);
    // y-up: φ = π is -X; halfway between the last and first column centres.
    let got = m.radiance_bilinear(DVec3::NEG_X);
    assert!((got.x - 0.5).abs() < 1e-12, "{got}");
}

// ---------------------------------------------------------------- projection

/// A random lmax-4 expansion with a dominant constant term, RGB.
fn random_expansion(seed: u64) -> ShCoeffs<DVec3> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut c = ShCoeffs::<DVec3>::from_fn(4, |_, _| {
        DVec3::new(
            rng.random_range(-0.3..0.3),
            rng.random_range(-0.3..0.3),
            rng.random_range(-0.3..0.3),
        )
    });
    c[0] = DVec3::splat(3.0);
    c
}

fn max_error(got: &ShCoeffs<DVec3>, want: &ShCoeffs<DVec3>) -> f64 {
    (0..want.len())
        .map(|k| (got[k] - want[k]).abs().max_element())
        .fold(0.0, f64::max)
}

fn project_rendered(
    layout: Layout,
    o: MapOrientation,
    size: usize,
    f: impl Fn(DVec3) -> DVec3 + Sync,
) -> ShCoeffs<DVec3> {
    let (w, h) = layout.dimensions(size);
    let px = render_map(layout, o, w, h, f).unwrap();
    project_map(&map(layout, o, w, h, &px), 4)
}

/// Largest coefficient error when projecting a rendered lmax-4 expansion
/// (constant 3, other coefficients up to 0.3) back to lmax 4, max over the
/// four orientations; tolerances are twice the measured values (in the
/// comments). Exact texel solid angles leave the texel-centre (midpoint)
/// error, `O(h²)`.
const RECOVERY: [(Layout, usize, f64); 9] = [
    (Layout::Equirect, 256, 1.3e-4),     // 6.5e-5 (512 x 256 texels)
    (Layout::CrossHorizontal, 64, 7e-4), // 3.6e-4
    (Layout::CrossVertical, 64, 7e-4),   // 3.6e-4
    (Layout::Strip, 64, 7e-4),           // 3.6e-4
    (Layout::Strip, 256, 4.5e-5),        // 2.2e-5
    (Layout::Angular, 256, 3e-4),        // 1.5e-4
    (Layout::Angular, 1024, 2e-5),       // 9.6e-6
    (Layout::MirrorBall, 256, 2.2e-3),   // 1.1e-3
    (Layout::MirrorBall, 1024, 1.5e-4),  // 7.2e-5
];

#[test]
fn projection_recovers_band_limited_functions() {
    let want = random_expansion(11);
    let f = |d: DVec3| want.eval(d);
    let mut failed = Vec::new();
    for (layout, size, tol) in RECOVERY {
        let mut worst = 0.0f64;
        for o in orientations() {
            let got = project_rendered(layout, o, size, f);
            worst = worst.max(max_error(&got, &want));
        }
        eprintln!("{layout} size {size}: max coefficient error {worst:.2e} (tolerance {tol:.0e})");
        if worst >= tol {
            failed.push(format!("{layout} size {size}: {worst:e}"));
        }
    }
    assert!(failed.is_empty(), "{failed:?}");
}

/// The recovery error falls as `h²` in every layout: halving the texel
/// size divides it by 4 (measured 4.0; 3.7 for the mirror ball, whose
/// rim ring converges a little more slowly).
#[test]
fn projection_error_is_second_order() {
    let want = random_expansion(3);
    let f = |d: DVec3| want.eval(d);
    let o = MapOrientation::default();
    for (layout, size) in [
        (Layout::Equirect, 64),
        (Layout::CrossHorizontal, 32),
        (Layout::Angular, 128),
        (Layout::MirrorBall, 128),
    ] {
        let coarse = max_error(&project_rendered(layout, o, size, f), &want);
        let fine = max_error(&project_rendered(layout, o, 2 * size, f), &want);
        let ratio = coarse / fine;
        eprintln!("{layout} {size} -> {}: error ratio {ratio:.2}", 2 * size);
        assert!(
            (3.3..4.5).contains(&ratio),
            "{layout}: {coarse:e} / {fine:e}"
        );
    }
}

/// The constant term of a constant map is exact in every layout (the
/// weights sum to `4π`); the other coefficients of a constant and of a
/// linear gradient (`closed_form::linear_gradient`) come out to the
/// quadrature's accuracy: tolerances about twice the measured worst
/// coefficient errors (equirect 6.7e-5, cube faces 4.1e-4, angular 1.9e-4,
/// mirror ball 1.4e-3).
#[test]
fn projection_of_simple_lights() {
    let axis = DVec3::new(0.48, 0.6, -0.64);
    let grad: ShCoeffs<f64> = closed_form::linear_gradient(4, axis, 1.0, 0.5);
    for (layout, size, tol) in [
        (Layout::Equirect, 256, 1.4e-4),
        (Layout::CrossHorizontal, 64, 8e-4),
        (Layout::CrossVertical, 64, 8e-4),
        (Layout::Strip, 64, 8e-4),
        (Layout::Angular, 256, 4e-4),
        (Layout::MirrorBall, 256, 3e-3),
    ] {
        let mut worst = 0.0f64;
        for o in orientations() {
            let c = project_rendered(layout, o, size, |_| DVec3::ONE);
            assert!((c[0].x - 2.0 * PI.sqrt()).abs() < 1e-12, "{layout} {o:?}");
            let g = project_rendered(layout, o, size, |d| DVec3::splat(1.0 + 0.5 * d.dot(axis)));
            for k in 0..25 {
                worst = worst.max(c[k].x.abs() * f64::from(k > 0));
                worst = worst.max((g[k].x - grad[k]).abs());
            }
        }
        eprintln!("{layout} size {size}: constant and gradient within {worst:.2e}");
        assert!(worst < tol, "{layout}: {worst:e}");
    }
}

/// The same function drawn as an equirect map and as a cross projects to
/// the same coefficients (two independent quadratures).
#[test]
fn equirect_and_cross_projections_agree() {
    let want = random_expansion(5);
    let f = |d: DVec3| want.eval(d);
    for o in orientations() {
        // Measured 1.6e-5 and 2.2e-5 from the true coefficients.
        let equirect = project_rendered(Layout::Equirect, o, 512, f);
        let cross = project_rendered(Layout::CrossHorizontal, o, 256, f);
        let err = max_error(&equirect, &cross);
        eprintln!("{o:?}: equirect vs cross {err:.2e}");
        assert!(err < 1e-4, "{o:?}: {err:e}");
    }
}

/// The layout path, applied to an equirect map through the generic texel
/// loop, equals the ring path of `project_equirect`.
#[test]
fn equirect_ring_path_equals_the_texel_sum() {
    let (w, h) = (48, 24);
    let px: Vec<[f32; 3]> = (0..w * h)
        .map(|i| [((i * 7919) % 101) as f32 / 50.0, 1.0, (i % 13) as f32])
        .collect();
    for o in orientations() {
        let m = map(Layout::Equirect, o, w, h, &px);
        let fast = project_map(&m, 6);
        let mut slow = ShCoeffs::<DVec3>::zeros(6);
        for y in 0..h {
            for x in 0..w {
                let d = m.texel_direction(x, y).unwrap();
                let y_lm = shlight_core::sh::sh_eval(6, d);
                let f = DVec3::from(px[y * w + x].map(f64::from)) * m.texel_solid_angle(x, y);
                for k in 0..y_lm.len() {
                    slow[k] += f * y_lm[k];
                }
            }
        }
        assert!(max_error(&fast, &slow) < 1e-11, "{o:?}");
    }
}

/// `project_map` on a cube layout equals the plain texel sum (checks the
/// batching and row parallelism against the definition), at an lmax that
/// takes the general basis path.
#[test]
fn cube_projection_equals_the_texel_sum() {
    let layout = Layout::CrossVertical;
    let (w, h) = layout.dimensions(9);
    let px: Vec<[f32; 3]> = (0..w * h)
        .map(|i| [((i * 7919) % 101) as f32 / 50.0, 1.0, (i % 13) as f32])
        .collect();
    let o = MapOrientation {
        frame: Frame::ZUp,
        mirror: true,
    };
    let m = map(layout, o, w, h, &px);
    let fast = project_map(&m, 7);
    let mut slow = ShCoeffs::<DVec3>::zeros(7);
    for y in 0..h {
        for x in 0..w {
            let Some(d) = m.texel_direction(x, y) else {
                continue;
            };
            let y_lm = shlight_core::sh::sh_eval(7, d);
            let f = DVec3::from(px[y * w + x].map(f64::from)) * m.texel_solid_angle(x, y);
            for k in 0..y_lm.len() {
                slow[k] += f * y_lm[k];
            }
        }
    }
    assert!(max_error(&fast, &slow) < 1e-12);
}

// ------------------------------------------------------------ names and sizes

#[test]
fn detect_by_aspect_ratio() {
    assert_eq!(Layout::detect(2048, 1024), Some(Layout::Equirect));
    assert_eq!(Layout::detect(1024, 768), Some(Layout::CrossHorizontal));
    assert_eq!(Layout::detect(768, 1024), Some(Layout::CrossVertical));
    assert_eq!(Layout::detect(1536, 256), Some(Layout::Strip));
    assert_eq!(Layout::detect(512, 512), Some(Layout::Angular));
    assert_eq!(Layout::detect(1000, 1001), None);
    assert_eq!(Layout::detect(0, 0), None);
    assert_eq!(Layout::detect(3, 0), None);
    for layout in Layout::ALL {
        for size in [1, 7, 64] {
            let (w, h) = layout.dimensions(size);
            assert_eq!(layout.check_size(w, h), Ok(()), "{layout} {w}x{h}");
            if let Some(found) = Layout::detect(w, h) {
                // Square images are read as angular maps, never mirror balls.
                let expected = if layout == Layout::MirrorBall {
                    Layout::Angular
                } else {
                    layout
                };
                assert_eq!(found, expected);
            }
        }
    }
}

#[test]
fn bad_sizes_are_errors_with_clear_messages() {
    let kind = |l: Layout, w, h| l.check_size(w, h).unwrap_err().kind;
    assert_eq!(kind(Layout::Equirect, 0, 10), LayoutSizeErrorKind::Empty);
    assert_eq!(kind(Layout::Angular, 10, 0), LayoutSizeErrorKind::Empty);
    assert_eq!(
        kind(Layout::Strip, usize::MAX, 2),
        LayoutSizeErrorKind::TooLarge
    );
    for (l, w, h, text) in [
        (
            Layout::CrossHorizontal,
            1001,
            750,
            "width 1001 is not a multiple of 4",
        ),
        (
            Layout::CrossHorizontal,
            1024,
            700,
            "height 700 is not a multiple of 3",
        ),
        (
            Layout::CrossHorizontal,
            1024,
            762,
            "faces of 256x254 texels are not square",
        ),
        (
            Layout::CrossVertical,
            768,
            1020,
            "faces of 256x255 texels are not square",
        ),
        (Layout::Strip, 1536, 255, "not square"),
        (Layout::MirrorBall, 512, 511, "must be square"),
    ] {
        let e = l.check_size(w, h).unwrap_err();
        assert_eq!(e.kind, LayoutSizeErrorKind::Shape);
        let msg = e.to_string();
        assert!(
            msg.contains(text) && msg.contains(&format!("{w}x{h}")),
            "{msg}"
        );
    }
    let msg = Layout::CrossHorizontal
        .check_size(10, 10)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("expected 4f x 3f"), "{msg}");
    assert!(Layout::Equirect.check_size(7, 5).is_ok());
    let px = vec![[0.0f32; 3]; 11];
    let e = EnvMap::new(Layout::Equirect, MapOrientation::default(), 4, 3, &px).unwrap_err();
    assert_eq!(e.kind, LayoutSizeErrorKind::PixelCount { got: 11 });
    assert!(e.to_string().contains("needs 12 texels"), "{e}");
    assert!(
        render_map(Layout::Strip, MapOrientation::default(), 12, 3, |_| {
            DVec3::ONE
        })
        .is_err()
    );
}

#[test]
#[should_panic(expected = "pixel count")]
fn project_map_panics_on_a_short_pixel_buffer() {
    let px = vec![[0.0f32; 3]; 5];
    let m = EnvMap {
        layout: Layout::Strip,
        orientation: MapOrientation::default(),
        width: 6,
        height: 1,
        pixels: &px,
    };
    let _ = project_map(&m, 2);
}

#[test]
fn names_round_trip_and_errors_list_them() {
    let names = [
        "equirect",
        "cross-h",
        "cross-v",
        "strip",
        "angular",
        "mirror-ball",
    ];
    for (layout, name) in Layout::ALL.into_iter().zip(names) {
        assert_eq!(layout.to_string(), name);
        assert_eq!(name.parse::<Layout>(), Ok(layout));
        assert_eq!(name.to_uppercase().parse::<Layout>(), Ok(layout));
    }
    let msg = "cube".parse::<Layout>().unwrap_err().to_string();
    assert!(msg.contains("\"cube\""), "{msg}");
    for name in names {
        assert!(msg.contains(name), "{msg}");
    }
}

/// `EnvMap` is a `RadianceMap` through its bilinear lookup.
#[test]
fn env_map_is_a_radiance_map() {
    let (w, h) = Layout::CrossHorizontal.dimensions(4);
    let px = render_map(
        Layout::CrossHorizontal,
        MapOrientation::default(),
        w,
        h,
        smooth,
    )
    .unwrap();
    let m = map(
        Layout::CrossHorizontal,
        MapOrientation::default(),
        w,
        h,
        &px,
    );
    let r: &dyn RadianceMap = &m;
    let d = DVec3::new(0.3, -0.4, 0.866).normalize();
    assert_eq!(r.radiance(d), m.radiance_bilinear(d));
}

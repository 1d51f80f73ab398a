//! The raster against independent routes: texel centres tested by
//! orientation, overlaps by separating axes and by a corner-and-crossing
//! intersection of the triangle with each texel, areas by the shoelace
//! formula, owners by brute force over every triangle.

use glam::{DVec2, Vec2};
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_lightmap::{MAX_SIDE, Placement, TexelRaster, UvError, first_uv_overlap, texel_pieces};

mod support;
use support::{intersection_area, orient, separated, texel};

/// A random triangle inside the unit square, from a sliver of a texel to
/// most of the grid.
fn random_triangle(rng: &mut StdRng) -> [Vec2; 3] {
    let size = 10f32.powf(rng.random_range(-2.5..0.0));
    let centre = Vec2::new(rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
    let mut c = [Vec2::ZERO; 3];
    for p in &mut c {
        let q = centre + size * Vec2::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
        *p = q.clamp(Vec2::ZERO, Vec2::ONE);
    }
    c
}

#[test]
fn one_triangle_covers_its_texel_centres_and_only_texels_it_overlaps() {
    let mut rng = StdRng::seed_from_u64(39);
    let (mut texels_checked, mut worst_sum, mut worst_area) = (0usize, 0.0f64, 0.0f64);
    let mut tested = 0;
    while tested < 300 {
        let uv = random_triangle(&mut rng);
        let (w, h) = (rng.random_range(1..48u32), rng.random_range(1..48u32));
        let size = DVec2::new(f64::from(w), f64::from(h));
        let p = uv.map(|c| c.as_dvec2() * size);
        let area = 0.5 * orient(p[0], p[1], p[2]).abs();
        if area < 1e-6 {
            continue;
        }
        tested += 1;
        let raster = TexelRaster::new(&uv, &[[0, 1, 2]], None, w, h).unwrap();
        assert_eq!(raster.degenerate_triangles(), 0);
        let mut pieces = vec![None; (w * h) as usize];
        let mut sum = 0.0;
        texel_pieces(p, w, h, |piece| {
            sum += piece.area;
            pieces[(piece.y * w + piece.x) as usize] = Some(piece);
        });
        worst_sum = worst_sum.max((sum - area).abs() / area);
        assert!(
            (sum - area).abs() <= 1e-9 * area,
            "pieces sum {sum}, triangle {area}"
        );
        let scale = p.iter().map(|c| c.length()).fold(1.0, f64::max);
        for y in 0..h {
            for x in 0..w {
                let square = texel(x, y);
                let truth = intersection_area(&p, &square);
                let centre = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                let o = [
                    orient(p[0], p[1], centre),
                    orient(p[1], p[2], centre),
                    orient(p[2], p[0], centre),
                ];
                let eps = 1e-9 * scale * scale;
                let centre_inside = o.iter().all(|&v| v > eps) || o.iter().all(|&v| v < -eps);
                let got = raster.get(x, y);
                match got {
                    None => {
                        assert!(
                            !centre_inside,
                            "texel ({x}, {y}) has its centre inside but is missing"
                        );
                        assert!(
                            truth <= 1e-12,
                            "texel ({x}, {y}) overlaps by {truth} but is missing"
                        );
                        assert!(pieces[(y * w + x) as usize].is_none());
                    }
                    Some(s) => {
                        texels_checked += 1;
                        assert!(
                            !separated(p, &square, 1e-9),
                            "texel ({x}, {y}) does not overlap the triangle"
                        );
                        let piece =
                            pieces[(y * w + x) as usize].expect("a piece for a covered texel");
                        worst_area = worst_area.max((piece.area - truth).abs());
                        assert!(
                            (piece.area - truth).abs() <= 1e-9,
                            "({x}, {y}): {} against {truth}",
                            piece.area
                        );
                        assert_eq!(s.triangle, 0);
                        assert_eq!(s.coverage, piece.area.min(1.0) as f32);
                        let wt = s.weights.map(f64::from);
                        assert!(wt.iter().all(|&v| v >= -1e-6), "weights {wt:?}");
                        assert!((wt.iter().sum::<f64>() - 1.0).abs() <= 1e-6);
                        let q = wt[0] * p[0] + wt[1] * p[1] + wt[2] * p[2];
                        // The weights are f32: the point moves by up to
                        // about 1e-7 of the triangle's coordinates.
                        let tol = 1e-6 * scale;
                        let (fx, fy) = (f64::from(x), f64::from(y));
                        assert!(
                            q.x >= fx - tol
                                && q.x <= fx + 1.0 + tol
                                && q.y >= fy - tol
                                && q.y <= fy + 1.0 + tol,
                            "sample {q} outside texel ({x}, {y})"
                        );
                    }
                }
            }
        }
    }
    println!(
        "{texels_checked} covered texels; worst relative sum error {worst_sum:.1e}, worst texel area error {worst_area:.1e}"
    );
}

/// A `n x m` grid of quads over the unit square, two triangles each, its
/// interior corners moved by up to `jitter` of a quad.
fn quad_grid(n: usize, m: usize, jitter: f32, rng: &mut StdRng) -> (Vec<Vec2>, Vec<[u32; 3]>) {
    let mut uvs = Vec::new();
    for j in 0..=m {
        for i in 0..=n {
            let mut p = Vec2::new(i as f32 / n as f32, j as f32 / m as f32);
            if i > 0 && i < n {
                p.x += jitter * rng.random_range(-1.0..1.0) / n as f32;
            }
            if j > 0 && j < m {
                p.y += jitter * rng.random_range(-1.0..1.0) / m as f32;
            }
            uvs.push(p);
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut tris = Vec::new();
    for j in 0..m {
        for i in 0..n {
            tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    (uvs, tris)
}

#[test]
fn a_mesh_tiling_the_square_covers_every_texel_and_each_owner_overlaps_most() {
    let mut rng = StdRng::seed_from_u64(7);
    for (n, m, w, h, jitter) in [
        (7, 5, 16, 12, 0.0),
        (3, 4, 10, 9, 0.3),
        (8, 8, 8, 8, 0.0),
        (11, 6, 13, 7, 0.35),
        (9, 7, 40, 37, 0.3),
    ] {
        let (uvs, tris) = quad_grid(n, m, jitter, &mut rng);
        assert_eq!(first_uv_overlap(&uvs, &tris).unwrap(), None);
        let raster = TexelRaster::new(&uvs, &tris, None, w, h).unwrap();
        assert_eq!(raster.covered_texels(), (w * h) as usize);
        let size = DVec2::new(f64::from(w), f64::from(h));
        let corners: Vec<[DVec2; 3]> = tris
            .iter()
            .map(|t| t.map(|k| uvs[k as usize].as_dvec2() * size))
            .collect();
        let mut sums = vec![0.0f64; (w * h) as usize];
        for c in &corners {
            texel_pieces(*c, w, h, |p| sums[(p.y * w + p.x) as usize] += p.area);
        }
        for y in 0..h {
            for x in 0..w {
                let s = raster.get(x, y).unwrap();
                let k = (y * w + x) as usize;
                assert!(
                    (sums[k] - 1.0).abs() <= 1e-9,
                    "texel ({x}, {y}) covered {}",
                    sums[k]
                );
                assert!((f64::from(s.coverage) - 1.0).abs() <= 1e-9);
                let areas: Vec<f64> = corners
                    .iter()
                    .map(|c| intersection_area(c, &texel(x, y)))
                    .collect();
                let most = areas.iter().copied().fold(0.0, f64::max);
                let own = areas[s.triangle as usize];
                assert!(
                    own >= most - 1e-12,
                    "({x}, {y}): owner {} has {own}, the most is {most}",
                    s.triangle
                );
                // Ties go to the lowest index: no earlier triangle has as much.
                assert!(
                    areas[..s.triangle as usize]
                        .iter()
                        .all(|&a| a < own - 1e-12 || a < most - 1e-12)
                );
                assert!((areas.iter().sum::<f64>() - 1.0).abs() <= 1e-9);
            }
        }
    }
}

#[test]
fn ties_go_to_the_lowest_triangle() {
    // One texel cut by its diagonal: two halves of exactly 1/2.
    let uvs = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    for tris in [[[0, 1, 2], [0, 2, 3]], [[0, 2, 3], [0, 1, 2]]] {
        let raster = TexelRaster::new(&uvs, &tris, None, 1, 1).unwrap();
        let s = raster.get(0, 0).unwrap();
        assert_eq!(s.triangle, 0);
        assert_eq!(s.coverage, 1.0);
        // The sample is the centroid of triangle 0's half.
        let c = tris[0].map(|k| uvs[k as usize]);
        let q = s.weights[0] * c[0] + s.weights[1] * c[1] + s.weights[2] * c[2];
        let centroid = (c[0] + c[1] + c[2]) / 3.0;
        assert!((q - centroid).length() < 1e-6, "{q} against {centroid}");
    }
}

#[test]
fn a_placed_triangle_covers_what_the_moved_triangle_covers() {
    let mut rng = StdRng::seed_from_u64(11);
    for _ in 0..50 {
        // UVs on a grid of 2^-16, scales in powers of two, offsets in
        // eighths: the moved UVs are exact in f32.
        let uv = random_triangle(&mut rng).map(|c| (c * 65536.0).round() / 65536.0);
        let scale = Vec2::new(
            0.5f32.powi(rng.random_range(0..3)),
            0.5f32.powi(rng.random_range(0..3)),
        );
        let offset = Vec2::new(
            rng.random_range(0..4) as f32 * 0.125,
            rng.random_range(0..4) as f32 * 0.125,
        );
        let moved = uv.map(|c| c * scale + offset);
        let placed =
            TexelRaster::new(&uv, &[[0, 1, 2]], Some(Placement { scale, offset }), 40, 24).unwrap();
        let direct = TexelRaster::new(&moved, &[[0, 1, 2]], None, 40, 24).unwrap();
        assert_eq!(placed.texels(), direct.texels());
        let rect = Placement::from_rect(offset, offset + scale);
        let by_rect = TexelRaster::new(&uv, &[[0, 1, 2]], Some(rect), 40, 24).unwrap();
        assert_eq!(by_rect.texels(), direct.texels());
        // And nothing lands outside the rectangle the placement maps the
        // unit square to.
        for y in 0..24 {
            for x in 0..40 {
                if placed.get(x, y).is_some() {
                    let (lo, hi) = (
                        offset * Vec2::new(40.0, 24.0),
                        (offset + scale) * Vec2::new(40.0, 24.0),
                    );
                    assert!(
                        x as f32 + 1.0 > lo.x
                            && (x as f32) < hi.x
                            && y as f32 + 1.0 > lo.y
                            && (y as f32) < hi.y
                    );
                }
            }
        }
    }
}

#[test]
fn parts_outside_the_unit_square_are_dropped() {
    let uv = [
        Vec2::new(-0.5, 0.25),
        Vec2::new(1.25, 0.1),
        Vec2::new(0.5, 1.5),
    ];
    let (w, h) = (20, 10);
    let raster = TexelRaster::new(&uv, &[[0, 1, 2]], None, w, h).unwrap();
    assert_eq!(raster.triangles_outside(), 1);
    let p = uv.map(|c| c.as_dvec2() * DVec2::new(20.0, 10.0));
    let grid = [
        DVec2::ZERO,
        DVec2::new(20.0, 0.0),
        DVec2::new(20.0, 10.0),
        DVec2::new(0.0, 10.0),
    ];
    let inside = intersection_area(&p, &grid);
    let mut sum = 0.0;
    texel_pieces(p, w, h, |piece| sum += piece.area);
    assert!(
        (sum - inside).abs() <= 1e-9 * inside,
        "{sum} against {inside}"
    );
}

#[test]
fn degenerate_triangles_are_skipped_and_counted() {
    let uvs = [
        Vec2::new(0.1, 0.1),
        Vec2::new(0.9, 0.1),
        Vec2::new(0.5, 0.9),
        Vec2::new(0.3, 0.3),
        Vec2::new(0.6, 0.6),
        Vec2::new(0.9, 0.9),
    ];
    let tris = [[3, 4, 5], [0, 1, 2], [0, 0, 1], [2, 2, 2]];
    let raster = TexelRaster::new(&uvs, &tris, None, 8, 8).unwrap();
    assert_eq!(raster.degenerate_triangles(), 3);
    let alone = TexelRaster::new(&uvs, &tris[1..2], None, 8, 8).unwrap();
    // Only triangle 1 covers anything, as when it is alone.
    for (a, b) in raster.texels().iter().zip(alone.texels()) {
        assert_eq!(
            a.map(|s| (s.triangle, s.weights, s.coverage)),
            b.map(|s| (s.triangle + 1, s.weights, s.coverage))
        );
    }
    assert_eq!(first_uv_overlap(&uvs, &tris).unwrap(), None);
}

#[test]
fn bad_uvs_and_sizes_are_errors_naming_what_is_wrong() {
    let mut uvs = vec![
        Vec2::new(0.1, 0.1),
        Vec2::new(0.9, 0.1),
        Vec2::new(0.5, 0.9),
        Vec2::new(0.2, 0.8),
    ];
    let tris = [[0, 1, 2], [0, 2, 3], [1, 2, 3], [0, 3, 2], [3, 1, 0]];
    uvs.push(Vec2::new(f32::NAN, 0.5));
    let with_nan = [tris.to_vec(), vec![[0, 1, 4]]].concat();
    for result in [
        TexelRaster::new(&uvs, &with_nan, None, 8, 8).map(|_| ()),
        first_uv_overlap(&uvs, &with_nan).map(|_| ()),
    ] {
        let err = result.unwrap_err();
        assert!(
            matches!(
                err,
                UvError::NonFiniteUv {
                    triangle: 5,
                    vertex: 4,
                    ..
                }
            ),
            "{err:?}"
        );
        assert!(err.to_string().contains("triangle 5"), "{err}");
    }
    uvs[4] = Vec2::new(0.5, f32::INFINITY);
    let err = TexelRaster::new(&uvs, &with_nan, None, 8, 8).unwrap_err();
    assert!(err.to_string().contains("triangle 5"), "{err}");
    let past = [tris.to_vec(), vec![[0, 1, 9]]].concat();
    for result in [
        TexelRaster::new(&uvs, &past, None, 8, 8).map(|_| ()),
        first_uv_overlap(&uvs, &past).map(|_| ()),
    ] {
        let err = result.unwrap_err();
        assert_eq!(
            err,
            UvError::IndexOutOfRange {
                triangle: 5,
                vertex: 9,
                vertices: 5
            }
        );
        assert!(
            err.to_string().contains("triangle 5 names vertex 9"),
            "{err}"
        );
    }
    for (w, h) in [(0, 8), (8, 0), (MAX_SIDE + 1, 8)] {
        let err = TexelRaster::new(&uvs, &tris, None, w, h).unwrap_err();
        assert_eq!(
            err,
            UvError::GridSize {
                width: w,
                height: h,
                max_side: MAX_SIDE,
            }
        );
        assert!(
            err.to_string()
                .contains(&format!("{w} x {h} texels: each side must be 1 to 16384")),
            "{err}"
        );
    }
    let nan = Placement {
        scale: Vec2::new(1.0, f32::NAN),
        offset: Vec2::ZERO,
    };
    assert_eq!(
        TexelRaster::new(&uvs, &tris, Some(nan), 8, 8).unwrap_err(),
        UvError::NonFinitePlacement
    );
    let huge = Placement {
        scale: Vec2::splat(f32::MAX),
        offset: Vec2::ZERO,
    };
    // f32::MAX * 8 texels still fits an f64: a finite, if useless, raster.
    assert!(TexelRaster::new(&uvs, &tris, Some(huge), 8, 8).is_ok());
}

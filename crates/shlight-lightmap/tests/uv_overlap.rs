//! The overlap check against brute force over every pair (areas by an
//! independent corner-and-crossing intersection), and on meshes built to
//! overlap, or not, by construction.

use glam::{DVec2, Vec2};
use rand::{Rng, SeedableRng, rngs::StdRng, seq::SliceRandom};
use shlight_lightmap::{OVERLAP_TOLERANCE, UvOverlap, first_uv_overlap};

mod support;
use support::{intersection_area, orient};

/// A `n x n` grid of quads over the unit square, two triangles each, its
/// interior corners moved by up to a quarter of a quad (every triangle
/// keeps its winding: no overlaps).
fn jittered_grid(n: usize, rng: &mut StdRng) -> (Vec<Vec2>, Vec<[u32; 3]>) {
    let mut uvs = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let mut p = Vec2::new(i as f32, j as f32);
            if i > 0 && i < n {
                p.x += rng.random_range(-0.25..0.25);
            }
            if j > 0 && j < n {
                p.y += rng.random_range(-0.25..0.25);
            }
            uvs.push(p / n as f32);
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    (uvs, tris)
}

fn corners(uvs: &[Vec2], t: [u32; 3]) -> [DVec2; 3] {
    t.map(|k| uvs[k as usize].as_dvec2())
}

fn area(c: [DVec2; 3]) -> f64 {
    0.5 * orient(c[0], c[1], c[2]).abs()
}

/// The first pair `(a, b)`, `a < b`, sharing more than the tolerance of
/// the smaller one's area, over every pair.
fn brute_force(uvs: &[Vec2], tris: &[[u32; 3]]) -> Option<(usize, usize)> {
    for a in 0..tris.len() {
        for b in a + 1..tris.len() {
            let (ca, cb) = (corners(uvs, tris[a]), corners(uvs, tris[b]));
            let smaller = area(ca).min(area(cb));
            if smaller > 0.0 && intersection_area(&ca, &cb) > OVERLAP_TOLERANCE * smaller {
                return Some((a, b));
            }
        }
    }
    None
}

fn pair(found: Option<UvOverlap>) -> Option<(usize, usize)> {
    found.map(|o| (o.first, o.second))
}

#[test]
fn a_grid_has_no_overlap_in_either_winding() {
    let mut rng = StdRng::seed_from_u64(1);
    let (uvs, mut tris) = jittered_grid(12, &mut rng);
    assert_eq!(first_uv_overlap(&uvs, &tris).unwrap(), None);
    for t in tris.iter_mut().step_by(3) {
        t.swap(0, 1);
    }
    assert_eq!(first_uv_overlap(&uvs, &tris).unwrap(), None);
    assert_eq!(brute_force(&uvs, &tris), None);
}

#[test]
fn a_duplicate_a_fold_and_a_triangle_inside_another_are_found() {
    let mut rng = StdRng::seed_from_u64(2);
    let (uvs, tris) = jittered_grid(8, &mut rng);
    // The same triangle again, at the end, with its corners turned.
    let mut dup = tris.clone();
    dup.push([tris[37][1], tris[37][2], tris[37][0]]);
    let found = first_uv_overlap(&uvs, &dup).unwrap().expect("a duplicate");
    assert_eq!((found.first, found.second), (37, dup.len() - 1));
    assert!((found.fraction - 1.0).abs() < 1e-9, "{found:?}");
    assert!(
        found
            .to_string()
            .contains(&format!("triangles 37 and {}", dup.len() - 1)),
        "{found}"
    );

    // Quad (3, 4)'s far corner pulled back across its diagonal: its second
    // triangle folds over its first.
    let mut folded = uvs.clone();
    let at = |i: usize, j: usize| j * 9 + i;
    let (a, c) = (folded[at(3, 4)], folded[at(4, 5)]);
    let mid = 0.5 * (a + c);
    folded[at(3, 5)] = mid + 0.6 * (folded[at(4, 4)] - mid);
    let q = 2 * (4 * 8 + 3);
    let (c70, c71) = (corners(&folded, tris[q]), corners(&folded, tris[q + 1]));
    assert!(
        intersection_area(&c70, &c71) > 0.1 * area(c71),
        "the quad's halves fold over each other"
    );
    let found = pair(first_uv_overlap(&folded, &tris).unwrap());
    assert_eq!(found, brute_force(&folded, &tris));
    let moved = at(3, 5) as u32;
    assert!(
        found.is_some_and(|(a, b)| tris[a].contains(&moved) || tris[b].contains(&moved)),
        "{found:?}"
    );

    // A small triangle inside triangle 20, listed first.
    let c = corners(&uvs, tris[20]);
    let centre = (c[0] + c[1] + c[2]) / 3.0;
    let mut inner_uvs = uvs.clone();
    let base = inner_uvs.len() as u32;
    for k in 0..3 {
        inner_uvs.push((centre + 0.1 * (c[k] - centre)).as_vec2());
    }
    let inner = [vec![[base, base + 1, base + 2]], tris.clone()].concat();
    let found = first_uv_overlap(&inner_uvs, &inner)
        .unwrap()
        .expect("a triangle inside");
    assert_eq!((found.first, found.second), (0, 21));
    assert!((found.fraction - 1.0).abs() < 1e-4, "{found:?}");
}

#[test]
fn shared_edges_corners_and_touching_are_not_overlaps() {
    let uvs = [
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(2.0, 1.0),
        Vec2::new(2.0, 0.5),
        // Corners of their own on triangle 0's left edge and at its corner
        // (0, 0): touching, not shared.
        Vec2::new(0.0, 0.5),
        Vec2::new(-1.0, 0.2),
        Vec2::new(-1.0, 0.9),
        Vec2::new(0.0, 0.0),
        Vec2::new(-0.5, -1.0),
        Vec2::new(0.5, -1.0),
    ];
    // 0 and 1 share an edge; 1 and 2 share a corner; 3's corner touches
    // triangle 0's left edge; 4 touches triangle 0 at a corner it does not
    // share by index.
    let tris = [[0, 1, 2], [1, 3, 2], [3, 4, 5], [6, 7, 8], [9, 10, 11]];
    assert_eq!(first_uv_overlap(&uvs, &tris).unwrap(), None);
    assert_eq!(brute_force(&uvs, &tris), None);
    // Moved a little into triangle 0, triangle 3 overlaps it: found.
    let mut pushed = uvs;
    pushed[6] = Vec2::new(0.05, 0.5);
    assert_eq!(
        pair(first_uv_overlap(&pushed, &tris).unwrap()),
        Some((0, 3))
    );
    let mut pushed = uvs;
    pushed[9] = Vec2::new(0.02, 0.02);
    assert_eq!(
        pair(first_uv_overlap(&pushed, &tris).unwrap()),
        Some((0, 4))
    );
}

#[test]
fn random_triangles_give_the_pair_brute_force_gives() {
    let mut rng = StdRng::seed_from_u64(3);
    let (mut some, mut none) = (0, 0);
    for round in 0..60 {
        let count = rng.random_range(2..120);
        let size = if round % 2 == 0 { 0.02 } else { 0.1 };
        let mut uvs = Vec::new();
        let mut tris = Vec::new();
        for t in 0..count {
            let centre = Vec2::new(rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
            for _ in 0..3 {
                uvs.push(
                    centre
                        + size
                            * Vec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)),
                );
            }
            let k = 3 * t as u32;
            tris.push([k, k + 1, k + 2]);
        }
        let expected = brute_force(&uvs, &tris);
        assert_eq!(
            pair(first_uv_overlap(&uvs, &tris).unwrap()),
            expected,
            "round {round}"
        );
        if expected.is_some() {
            some += 1
        } else {
            none += 1
        }
    }
    println!("{some} sets with an overlap, {none} without");
    assert!(some > 10 && none > 10);
}

#[test]
fn a_100k_triangle_mesh_without_overlaps_is_accepted_and_one_fold_found() {
    let mut rng = StdRng::seed_from_u64(4);
    let (mut uvs, mut tris) = jittered_grid(224, &mut rng);
    assert!(tris.len() >= 100_000);
    tris.shuffle(&mut rng);
    for t in tris.iter_mut() {
        if rng.random_bool(0.5) {
            t.swap(1, 2);
        }
    }
    // Every triangle keeps the orientation its quad gave it (the grid's
    // orientation up to the swaps): a mesh without folds.
    assert_eq!(first_uv_overlap(&uvs, &tris).unwrap(), None);
    // One interior corner dragged over its neighbours: some triangles fold.
    let at = 100 * 225 + 100;
    uvs[at] += Vec2::new(1.5, 0.7) / 224.0;
    let found = first_uv_overlap(&uvs, &tris).unwrap().expect("a fold");
    let (a, b) = (found.first, found.second);
    let touches = |t: usize| tris[t].contains(&(at as u32));
    assert!(touches(a) || touches(b), "{found:?}");
    let (ca, cb) = (corners(&uvs, tris[a]), corners(&uvs, tris[b]));
    assert!(intersection_area(&ca, &cb) > OVERLAP_TOLERANCE * area(ca).min(area(cb)));
}

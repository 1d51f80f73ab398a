//! Dilation against hand computations and Chebyshev distances; valid
//! texels untouched; the same result scanned across or down (the grid
//! transposed).

use glam::Vec3;
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_lightmap::{Blend, GridShapeError, dilate};

#[test]
fn one_valid_texel_spreads_one_ring_per_pass() {
    let (w, h) = (15usize, 11usize);
    let (cx, cy) = (4usize, 6usize);
    let v = [0.3f32, 1.7, 42.0];
    let mut grid: Vec<Option<[f32; 3]>> = vec![None; w * h];
    grid[cy * w + cx] = Some(v);
    let mut total = 0;
    for pass in 1..=12 {
        total += dilate(&mut grid, w, 1).unwrap();
        let mut count = 0;
        for y in 0..h {
            for x in 0..w {
                let ring = x.abs_diff(cx).max(y.abs_diff(cy));
                let t = grid[y * w + x];
                assert_eq!(t.is_some(), ring <= pass, "pass {pass}, texel ({x}, {y})");
                if let Some(t) = t {
                    count += 1;
                    assert_eq!(t, v);
                }
            }
        }
        assert_eq!(total, count - 1);
    }
    // Several passes in one call are the same as one at a time.
    let mut at_once: Vec<Option<[f32; 3]>> = vec![None; w * h];
    at_once[cy * w + cx] = Some(v);
    assert_eq!(dilate(&mut at_once, w, 3).unwrap(), 7 * 7 - 1);
    assert_eq!(at_once.iter().filter(|t| t.is_some()).count(), 49);
}

#[test]
fn each_filled_texel_is_the_mean_of_its_valid_neighbours_by_hand() {
    // 1 . 4
    // . . .
    // 7 . .
    let mut grid = vec![
        Some(1.0f64),
        None,
        Some(4.0),
        None,
        None,
        None,
        Some(7.0),
        None,
        None,
    ];
    assert_eq!(dilate(&mut grid, 3, 1).unwrap(), 5);
    let one = [
        Some(1.0),
        Some(2.5),
        Some(4.0),
        Some(4.0),
        Some(4.0),
        Some(4.0),
        Some(7.0),
        Some(7.0),
        None,
    ];
    assert_eq!(grid, one);
    // The corner's neighbours after one pass: 4 (centre), 4 (right), 7
    // (bottom).
    assert_eq!(dilate(&mut grid, 3, 1).unwrap(), 1);
    assert_eq!(grid[8], Some(5.0));
    // Nothing left: a further pass fills nothing.
    assert_eq!(dilate(&mut grid, 3, 4).unwrap(), 0);

    // Channels apart, through [f32; 2] and Vec3.
    let mut pairs = vec![Some([1.0f32, -2.0]), None, Some([3.0, 6.0]), None];
    dilate(&mut pairs, 2, 1).unwrap();
    assert_eq!(pairs[1], Some([2.0, 2.0]));
    assert_eq!(pairs[3], Some([2.0, 2.0]));
    let mut vecs = vec![
        None,
        Some(Vec3::new(1.0, 2.0, 3.0)),
        Some(Vec3::new(3.0, 0.0, -1.0)),
    ];
    dilate(&mut vecs, 3, 1).unwrap();
    assert_eq!(vecs[0], Some(Vec3::new(1.0, 2.0, 3.0)));
    assert_eq!(<f32 as Blend>::mean(&[1.0, 2.0, 4.0]), 7.0 / 3.0);
}

#[test]
fn valid_texels_never_change_and_the_scan_order_does_not_matter() {
    let mut rng = StdRng::seed_from_u64(5);
    let (w, h) = (23usize, 17usize);
    // Multiples of 1/1024 in [0.25, 1): sums of neighbours are exact in f64,
    // whatever order they are added in.
    let grid: Vec<Option<f32>> = (0..w * h)
        .map(|_| {
            rng.random_bool(0.1)
                .then(|| rng.random_range(256..1024) as f32 / 1024.0)
        })
        .collect();
    let mut filled = grid.clone();
    dilate(&mut filled, w, 3).unwrap();
    for (a, b) in grid.iter().zip(&filled) {
        if a.is_some() {
            assert_eq!(a, b);
        }
    }
    let transpose = |g: &[Option<f32>], w: usize, h: usize| {
        let mut t = vec![None; w * h];
        for y in 0..h {
            for x in 0..w {
                t[x * h + y] = g[y * w + x];
            }
        }
        t
    };
    let mut down = transpose(&grid, w, h);
    dilate(&mut down, h, 3).unwrap();
    assert_eq!(transpose(&down, h, w), filled);
    // Each filled texel is the mean of its neighbours one pass earlier.
    let mut before = grid.clone();
    dilate(&mut before, w, 2).unwrap();
    for y in 0..h {
        for x in 0..w {
            if before[y * w + x].is_none()
                && let Some(v) = filled[y * w + x]
            {
                let mut n = Vec::new();
                for ny in y.saturating_sub(1)..(y + 2).min(h) {
                    for nx in x.saturating_sub(1)..(x + 2).min(w) {
                        n.extend(before[ny * w + nx].map(f64::from));
                    }
                }
                assert!(!n.is_empty());
                let mean = n.iter().sum::<f64>() / n.len() as f64;
                assert_eq!(v, mean as f32);
            }
        }
    }
}

#[test]
fn a_grid_of_the_wrong_shape_is_an_error() {
    let mut grid = vec![Some(1.0f32), None, None];
    assert_eq!(
        dilate(&mut grid, 2, 1),
        Err(GridShapeError {
            texels: 3,
            width: 2
        })
    );
    assert_eq!(
        dilate(&mut grid, 0, 1),
        Err(GridShapeError {
            texels: 3,
            width: 0
        })
    );
    assert!(
        GridShapeError {
            texels: 3,
            width: 2
        }
        .to_string()
        .contains("3 texels")
    );
    assert_eq!(dilate::<f32>(&mut [], 4, 1), Ok(0));
}

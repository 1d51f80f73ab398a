//! `Image::stats` and `Image::sanitize`.

use shlight_io::{Image, PixelStats, SanitizeReport};

/// 3x2: NaN at (1, 0), +inf and a negative at (2, 0), -inf at (0, 1).
fn dirty() -> Image {
    Image::new(
        3,
        2,
        vec![
            [1.0, 2.0, 0.5],
            [f32::NAN, 0.25, 3.0],
            [f32::INFINITY, -2.0, 8.0],
            [f32::NEG_INFINITY, 0.0, -0.0],
            [4.0, -0.5, 1.0],
            [0.0, 0.0, 0.0],
        ],
    )
    .unwrap()
}

#[test]
fn stats_count_non_finite_and_negative_values() {
    let stats = dirty().stats();
    assert_eq!(
        stats,
        PixelStats {
            non_finite: 3,
            first_non_finite: Some((1, 0)),
            negative: 2,
            min_value: -2.0,
            max_value: 8.0,
        }
    );
    assert!(!stats.is_clean());
}

#[test]
fn stats_of_clean_and_empty_images() {
    let clean = Image::from_fn(4, 3, |x, y| [x as f32, y as f32, 0.5]);
    let stats = clean.stats();
    assert!(stats.is_clean());
    assert_eq!(stats.first_non_finite, None);
    assert_eq!((stats.min_value, stats.max_value), (0.0, 3.0));

    let empty = Image::new(0, 0, vec![]).unwrap();
    assert_eq!(empty.stats().max_value, 0.0);
    let all_nan = Image::new(1, 1, vec![[f32::NAN; 3]]).unwrap();
    let stats = all_nan.stats();
    assert_eq!(
        (stats.non_finite, stats.min_value, stats.max_value),
        (3, 0.0, 0.0)
    );
    assert_eq!(stats.first_non_finite, Some((0, 0)));
}

#[test]
fn first_non_finite_is_in_row_major_order() {
    let mut image = Image::from_fn(4, 3, |_, _| [1.0; 3]);
    image.set(1, 2, [0.0, 0.0, f32::INFINITY]);
    image.set(3, 1, [f32::NAN, 0.0, 0.0]);
    assert_eq!(image.stats().first_non_finite, Some((3, 1)));
}

/// A pixel-by-pixel scan in row-major order: the reference for the
/// blocked, vectorised and (for large images) multi-threaded statistics.
fn scan(image: &Image) -> PixelStats {
    let mut s = PixelStats {
        non_finite: 0,
        first_non_finite: None,
        negative: 0,
        min_value: f32::INFINITY,
        max_value: f32::NEG_INFINITY,
    };
    for y in 0..image.height() {
        for x in 0..image.width() {
            for v in image.get(x, y) {
                if !v.is_finite() {
                    s.non_finite += 1;
                    s.first_non_finite.get_or_insert((x, y));
                } else {
                    s.negative += usize::from(v < 0.0);
                    s.min_value = s.min_value.min(v);
                    s.max_value = s.max_value.max(v);
                }
            }
        }
    }
    s
}

#[test]
fn large_images_split_across_threads_count_as_one_scan() {
    // 1537x811 (3.7 M values: several threads' runs, a ragged last block),
    // with special values placed in different runs: the first non-finite
    // one far from the start, extremes in the last rows.
    let (w, h) = (1537, 811);
    let mut image = Image::from_fn(w, h, |x, y| {
        let t = ((x * 7 + y * 13) % 101) as f32 / 100.0;
        [t, 1.0 - t, 0.5 * t]
    });
    image.set(1000, 500, [0.0, f32::NAN, 0.0]);
    image.set(3, 700, [f32::INFINITY, -1.5, 0.0]);
    image.set(1536, 810, [f32::NEG_INFINITY, 42.0, -7.0]);
    image.set(12, 20, [-0.25, 0.0, 0.0]);
    let stats = image.stats();
    assert_eq!(stats, scan(&image));
    assert_eq!(stats.first_non_finite, Some((1000, 500)));
    assert_eq!(
        (stats.min_value, stats.max_value, stats.negative),
        (-7.0, 42.0, 3)
    );

    // Clean, and one non-finite value in the very last channel.
    let mut image = Image::from_fn(w, h, |x, _| [x as f32, 1.0, 2.0]);
    assert_eq!(image.stats(), scan(&image));
    image.set(w - 1, h - 1, [1.0, 1.0, f32::NAN]);
    assert_eq!(image.stats(), scan(&image));
    assert_eq!(image.stats().first_non_finite, Some((w - 1, h - 1)));
}

#[test]
fn sanitize_replaces_and_counts() {
    let mut image = dirty();
    let report = image.sanitize();
    assert_eq!(
        report,
        SanitizeReport {
            nan: 1,
            positive_infinite: 1,
            negative_infinite: 1,
            negative: 2,
            infinity_replacement: 8.0,
        }
    );
    assert_eq!(report.total(), 5);
    assert_eq!(image.get(1, 0), [0.0, 0.25, 3.0]);
    assert_eq!(image.get(2, 0), [8.0, 0.0, 8.0]);
    assert_eq!(image.get(0, 1), [0.0, 0.0, -0.0]);
    assert_eq!(image.get(1, 1), [4.0, 0.0, 1.0]);
    assert!(image.stats().is_clean());
    // A second pass has nothing to do.
    assert_eq!(image.sanitize().total(), 0);
}

#[test]
fn sanitize_without_a_positive_value_uses_zero_for_infinity() {
    let mut image = Image::new(2, 1, vec![[f32::INFINITY, -1.0, -3.0], [-0.5; 3]]).unwrap();
    let report = image.sanitize();
    assert_eq!(report.infinity_replacement, 0.0);
    assert_eq!(image.pixels(), &[[0.0; 3]; 2]);
}

/// `Image::stats` against a plain value-by-value count on an image large
/// enough for its vector lanes and several of its blocks, with non-finite
/// and negative values at scattered places (block and lane edges
/// included).
#[test]
fn stats_of_a_large_image_match_a_plain_count() {
    let (w, h) = (301, 97);
    let mut state = 12345_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 40) as u32
    };
    let mut pixels: Vec<[f32; 3]> = (0..w * h)
        .map(|_| std::array::from_fn(|_| next() as f32 / 1e5 - 20.0))
        .collect();
    // Positions in channel values: lane and block (3 * 4096) edges.
    for (i, v) in [
        (7, f32::NAN),
        (8, f32::INFINITY),
        (12287, f32::NEG_INFINITY),
        (12288, f32::NAN),
        (30000, -0.0),
        (w * h * 3 - 1, f32::INFINITY),
    ] {
        pixels[i / 3][i % 3] = v;
    }
    let image = Image::new(w, h, pixels.clone()).unwrap();
    let values: Vec<f32> = pixels.iter().flatten().copied().collect();
    let finite: Vec<f32> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let first = values.iter().position(|v| !v.is_finite()).unwrap() / 3;
    let want = PixelStats {
        non_finite: values.len() - finite.len(),
        first_non_finite: Some((first % w, first / w)),
        negative: finite.iter().filter(|&&v| v < 0.0).count(),
        min_value: finite.iter().copied().fold(f32::INFINITY, f32::min),
        max_value: finite.iter().copied().fold(f32::NEG_INFINITY, f32::max),
    };
    assert_eq!(image.stats(), want);
    assert_eq!(want.non_finite, 5);
    assert_eq!(want.first_non_finite, Some((2, 0)));

    // Moving the first non-finite value into a later block moves the
    // reported position with it.
    let mut later = pixels;
    for i in [7, 8, 12287] {
        later[i / 3][i % 3] = 1.0;
    }
    let image = Image::new(w, h, later).unwrap();
    let stats = image.stats();
    assert_eq!(stats.first_non_finite, Some((4096 % w, 4096 / w)));
    assert_eq!(stats.non_finite, 2);
}

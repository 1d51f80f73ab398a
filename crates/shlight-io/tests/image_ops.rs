//! The `Image` type: construction, accessors and exact geometric operations.

use shlight_io::{Image, PixelCountError};

/// A 3x2 image whose pixel (x, y) is [x, y, 10x + y]: every pixel names
/// its own position.
fn labelled(width: usize, height: usize) -> Image {
    Image::from_fn(width, height, |x, y| {
        [x as f32, y as f32, (10 * x + y) as f32]
    })
}

#[test]
fn new_checks_the_pixel_count() {
    let image = Image::new(3, 2, vec![[1.0, 2.0, 3.0]; 6]).unwrap();
    assert_eq!((image.width(), image.height()), (3, 2));
    assert_eq!(
        Image::new(3, 2, vec![[0.0; 3]; 5]),
        Err(PixelCountError {
            width: 3,
            height: 2,
            len: 5
        })
    );
    // width * height overflows: an error, not a panic.
    assert!(Image::new(usize::MAX, 2, vec![]).is_err());
    // An empty image is allowed.
    let empty = Image::new(0, 5, vec![]).unwrap();
    assert!(empty.is_empty());
    assert_eq!(
        PixelCountError {
            width: 3,
            height: 2,
            len: 5
        }
        .to_string(),
        "5 pixels given for a 3x2 image"
    );
}

#[test]
fn from_fn_is_row_major_with_row_zero_at_the_top() {
    let image = labelled(3, 2);
    let expected: Vec<[f32; 3]> = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 10.0],
        [2.0, 0.0, 20.0],
        [0.0, 1.0, 1.0],
        [1.0, 1.0, 11.0],
        [2.0, 1.0, 21.0],
    ];
    assert_eq!(image.pixels(), expected.as_slice());
    assert_eq!(image.get(2, 1), [2.0, 1.0, 21.0]);
    assert_eq!(image.row(1), &expected[3..]);
    assert_eq!(image.clone().into_pixels(), expected);
}

#[test]
fn pixels_mut_and_set_change_pixels() {
    let mut image = labelled(3, 2);
    image.pixels_mut()[4] = [7.0; 3];
    assert_eq!(image.get(1, 1), [7.0; 3]);
    image.set(0, 1, [5.0, 6.0, 7.0]);
    assert_eq!(image.pixels()[3], [5.0, 6.0, 7.0]);
}

#[test]
#[should_panic(expected = "outside")]
fn get_outside_panics() {
    let _ = labelled(3, 2).get(3, 0);
}

#[test]
fn crop_cuts_the_rectangle() {
    let image = labelled(6, 4);
    let face = image.crop(2, 1, 3, 2).unwrap();
    assert_eq!((face.width(), face.height()), (3, 2));
    for y in 0..2 {
        for x in 0..3 {
            assert_eq!(face.get(x, y), image.get(x + 2, y + 1));
        }
    }
    // The whole image, and rectangles touching the edges.
    assert_eq!(image.crop(0, 0, 6, 4).unwrap(), image);
    assert_eq!(image.crop(5, 3, 1, 1).unwrap().pixels(), &[image.get(5, 3)]);
    // Outside, or overflowing.
    assert!(image.crop(4, 0, 3, 1).is_none());
    assert!(image.crop(0, 3, 1, 2).is_none());
    assert!(image.crop(usize::MAX, 0, 2, 1).is_none());
}

#[test]
fn flips_mirror_the_image() {
    let image = labelled(3, 2);
    let h = image.flip_horizontal();
    let v = image.flip_vertical();
    for y in 0..2 {
        for x in 0..3 {
            assert_eq!(h.get(x, y), image.get(2 - x, y));
            assert_eq!(v.get(x, y), image.get(x, 1 - y));
        }
    }
    assert_eq!(h.flip_horizontal(), image);
    assert_eq!(v.flip_vertical(), image);
}

#[test]
fn rotate90_turns_clockwise() {
    // 3 wide, 2 high:      rotated: 2 wide, 3 high:
    //   a b c                 d a
    //   d e f                 e b
    //                         f c
    let image = labelled(3, 2);
    let r = image.rotate90();
    assert_eq!((r.width(), r.height()), (2, 3));
    let (a, b, c) = (image.get(0, 0), image.get(1, 0), image.get(2, 0));
    let (d, e, f) = (image.get(0, 1), image.get(1, 1), image.get(2, 1));
    assert_eq!(r.pixels(), &[d, a, e, b, f, c]);
}

#[test]
fn rotate270_turns_counter_clockwise() {
    //   a b c      rotated:  c f
    //   d e f                b e
    //                        a d
    let image = labelled(3, 2);
    let r = image.rotate270();
    assert_eq!((r.width(), r.height()), (2, 3));
    let (a, b, c) = (image.get(0, 0), image.get(1, 0), image.get(2, 0));
    let (d, e, f) = (image.get(0, 1), image.get(1, 1), image.get(2, 1));
    assert_eq!(r.pixels(), &[c, f, b, e, a, d]);
}

#[test]
fn rotations_compose() {
    let image = labelled(5, 3);
    assert_eq!(image.rotate90().rotate270(), image);
    assert_eq!(image.rotate270().rotate90(), image);
    assert_eq!(image.rotate90().rotate90(), image.rotate180());
    assert_eq!(image.rotate180(), image.flip_horizontal().flip_vertical());
    assert_eq!(image.rotate90().rotate90().rotate90(), image.rotate270());
    assert_eq!(image.rotate180().rotate180(), image);
}

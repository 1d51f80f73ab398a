//! Projection through `TexelSource` (`shlight_core::map::project`):
//! sources holding the same texels give the same coefficients bit for bit
//! (six faces and the strip they make, a strided image and its contiguous
//! copy, a user's own type), a cross of the same faces agrees to rounding,
//! a user source without any pixel buffer matches a closed form, and bad
//! sizes are errors that say what is wrong.

use glam::DVec3;
use shlight_core::map;
use shlight_core::map::{
    CubeFace, CubeFaces, EnvMap, Layout, LayoutSizeErrorKind, MapOrientation, StridedImage,
    TexelSource, project, project_equirect_simple, render_map,
};
use shlight_core::sh::{Frame, ShCoeffs, closed_form};

/// Largest coefficient difference relative to the largest coefficient.
fn rel_diff(a: &ShCoeffs<DVec3>, b: &ShCoeffs<DVec3>) -> f64 {
    let scale = b
        .as_slice()
        .iter()
        .map(|v| v.abs().max_element())
        .fold(0.0, f64::max);
    let diff = (0..a.len())
        .map(|k| (a[k] - b[k]).abs().max_element())
        .fold(0.0, f64::max);
    diff / scale
}

/// Bit-for-bit equality of two expansions (`==` would also pass `-0 == 0`).
fn assert_bits_equal(a: &ShCoeffs<DVec3>, b: &ShCoeffs<DVec3>, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for k in 0..a.len() {
        for c in 0..3 {
            assert_eq!(a[k][c].to_bits(), b[k][c].to_bits(), "{what}: k {k} ch {c}");
        }
    }
}

/// A sky with a sun, plus texel-level noise so that every texel matters.
fn sky(d: DVec3) -> DVec3 {
    let sun = DVec3::new(0.3, 0.8, 0.52).normalize();
    let s = if d.dot(sun) > 0.97 { 50.0 } else { 0.0 };
    DVec3::new(0.3, 0.5, 1.0) * (1.2 + d.y) + DVec3::splat(s)
}

fn noisy(px: &mut [[f32; 3]]) {
    for (i, p) in px.iter_mut().enumerate() {
        let n = ((i * 7919) % 101) as f32 / 400.0;
        p[0] += n;
        p[2] += 2.0 * n;
    }
}

/// A rendered, noisy `layout` image of `size`.
fn image(layout: Layout, size: usize) -> (usize, usize, Vec<[f32; 3]>) {
    let (w, h) = layout.dimensions(size);
    let mut px = render_map(layout, MapOrientation::default(), w, h, sky).unwrap();
    noisy(&mut px);
    (w, h, px)
}

/// Face `k` of a strip image as its own `f x f` image.
fn strip_face(px: &[[f32; 3]], f: usize, k: usize) -> Vec<[f32; 3]> {
    (0..f)
        .flat_map(|j| px[j * 6 * f + k * f..j * 6 * f + (k + 1) * f].to_vec())
        .collect()
}

#[test]
fn six_faces_project_like_the_strip_they_make() {
    let f = 24;
    let (w, h, strip) = image(Layout::Strip, f);
    let faces: Vec<Vec<[f32; 3]>> = (0..6).map(|k| strip_face(&strip, f, k)).collect();
    let cube = CubeFaces::new(f, core::array::from_fn(|k| faces[k].as_slice())).unwrap();
    assert_eq!(cube.face(CubeFace::NegY), faces[3].as_slice());
    for o in MapOrientation::ALL {
        let map = EnvMap::new(Layout::Strip, o, w, h, &strip).unwrap();
        let from_strip = project(&map, 6, o).unwrap();
        let from_faces = project(&cube, 6, o).unwrap();
        assert_bits_equal(&from_faces, &from_strip, &format!("{o:?}"));
    }
}

/// The same faces cut into a horizontal cross (unused cells NaN, which the
/// quadrature must never read).
fn cross_of(faces: &[Vec<[f32; 3]>], f: usize) -> Vec<[f32; 3]> {
    let (w, h) = Layout::CrossHorizontal.dimensions(f);
    let mut px = vec![[f32::NAN; 3]; w * h];
    for (k, face) in CubeFace::ALL.into_iter().enumerate() {
        let cell = Layout::CrossHorizontal.face_cell(face).unwrap();
        assert!(!cell.rotated);
        for j in 0..f {
            for i in 0..f {
                px[(cell.row * f + j) * w + cell.col * f + i] = faces[k][j * f + i];
            }
        }
    }
    px
}

#[test]
fn six_faces_project_like_a_cross_of_the_same_faces() {
    // Same texels, same directions and weights, summed in another order
    // (cross rows hold one to three faces): equal up to the rounding of
    // that order, about 1e-16 per term relative to the largest coefficient.
    const REORDER_TOL: f64 = 1e-13;
    let f = 16;
    let (_, _, strip) = image(Layout::Strip, f);
    let faces: Vec<Vec<[f32; 3]>> = (0..6).map(|k| strip_face(&strip, f, k)).collect();
    let cube = CubeFaces::new(f, core::array::from_fn(|k| faces[k].as_slice())).unwrap();
    let cross = cross_of(&faces, f);
    let (w, h) = Layout::CrossHorizontal.dimensions(f);
    let o = MapOrientation::default();
    let map = EnvMap::new(Layout::CrossHorizontal, o, w, h, &cross).unwrap();
    let a = project(&cube, 8, o).unwrap();
    let b = project(&map, 8, o).unwrap();
    let d = rel_diff(&a, &b);
    assert!(d < REORDER_TOL, "{d:e}");
    assert!(a.as_slice().iter().all(|v| v.is_finite()));
}

/// `px` copied into rows `stride` texels apart, the padding NaN.
fn padded(px: &[[f32; 3]], w: usize, h: usize, stride: usize) -> Vec<[f32; 3]> {
    let mut out = vec![[f32::NAN; 3]; (h - 1) * stride + w];
    for y in 0..h {
        out[y * stride..y * stride + w].copy_from_slice(&px[y * w..(y + 1) * w]);
    }
    out
}

#[test]
fn strided_images_project_like_their_contiguous_copies() {
    // Equirect goes through the ring transform (rows read in place; direct
    // sums at lmax 6, the FFT from lmax 48), the others through the texel
    // quadrature.
    for (layout, size, lmax) in [
        (Layout::Equirect, 32, 6),
        (Layout::Equirect, 40, 60),
        (Layout::CrossVertical, 12, 5),
        (Layout::Angular, 40, 5),
    ] {
        let (w, h, px) = image(layout, size);
        let stride = w + 7;
        let buf = padded(&px, w, h, stride);
        let strided = StridedImage::new(layout, w, h, stride, &buf).unwrap();
        assert_eq!(strided.stride(), stride);
        for o in MapOrientation::ALL {
            let map = EnvMap::new(layout, o, w, h, &px).unwrap();
            let a = project(&strided, lmax, o).unwrap();
            let b = project(&map, lmax, o).unwrap();
            assert_bits_equal(&a, &b, &format!("{layout} lmax {lmax} {o:?}"));
        }
    }
}

/// A user's cubemap: six faces stored as one `Vec` each, answering texel by
/// texel (no rows).
struct MyCubemap {
    f: usize,
    faces: [Vec<[f32; 3]>; 6],
}

impl TexelSource for MyCubemap {
    fn layout(&self) -> Layout {
        Layout::Strip
    }
    fn size(&self) -> (usize, usize) {
        (6 * self.f, self.f)
    }
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        self.faces[x / self.f][y * self.f + x % self.f]
    }
}

/// A user's equirect image stored bottom row first (a GL texture): rows
/// are contiguous but not in the order of the layout, handed out by `row`.
struct BottomUp {
    w: usize,
    h: usize,
    px: Vec<[f32; 3]>,
}

impl TexelSource for BottomUp {
    fn layout(&self) -> Layout {
        Layout::Equirect
    }
    fn size(&self) -> (usize, usize) {
        (self.w, self.h)
    }
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        self.px[(self.h - 1 - y) * self.w + x]
    }
    fn row(&self, y: usize) -> Option<&[[f32; 3]]> {
        let r = self.h - 1 - y;
        Some(&self.px[r * self.w..(r + 1) * self.w])
    }
}

#[test]
fn user_sources_project_like_the_images_they_hold() {
    let o = MapOrientation {
        frame: Frame::ZUp,
        mirror: true,
    };
    let f = 20;
    let (w, h, strip) = image(Layout::Strip, f);
    let mine = MyCubemap {
        f,
        faces: core::array::from_fn(|k| strip_face(&strip, f, k)),
    };
    let map = EnvMap::new(Layout::Strip, o, w, h, &strip).unwrap();
    assert_bits_equal(
        &project(&mine, 5, o).unwrap(),
        &project(&map, 5, o).unwrap(),
        "cubemap",
    );

    let (w, h, px) = image(Layout::Equirect, 24);
    let flipped: Vec<[f32; 3]> = (0..h)
        .rev()
        .flat_map(|y| px[y * w..(y + 1) * w].to_vec())
        .collect();
    let user = BottomUp { w, h, px: flipped };
    let map = EnvMap::new(Layout::Equirect, o, w, h, &px).unwrap();
    // Through a trait object too.
    let dynamic: &dyn TexelSource = &user;
    assert_bits_equal(
        &project(dynamic, 7, o).unwrap(),
        &project(&map, 7, o).unwrap(),
        "bottom-up rows",
    );
}

/// An equirect map computed on the fly from a function: no pixel buffer.
struct Procedural<F> {
    w: usize,
    h: usize,
    o: MapOrientation,
    f: F,
}

impl<F: Fn(DVec3) -> f64 + Sync> TexelSource for Procedural<F> {
    fn layout(&self) -> Layout {
        Layout::Equirect
    }
    fn size(&self) -> (usize, usize) {
        (self.w, self.h)
    }
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        let d = map::equirect_direction(x, y, self.w, self.h, self.o);
        let v = (self.f)(d) as f32;
        [v, 0.5 * v, 0.25 * v]
    }
}

#[test]
fn a_procedural_source_projects_to_the_closed_form() {
    // The midpoint rule on 512 x 256 texels: O(h^2) ~ 1e-5 for this smooth
    // function, plus f32 rounding of the texels; 1e-4 bounds both.
    const QUADRATURE_TOL: f64 = 1e-4;
    let axis = DVec3::new(0.48, 0.6, -0.64);
    for o in MapOrientation::ALL {
        let source = Procedural {
            w: 512,
            h: 256,
            o,
            f: |d: DVec3| 1.0 + 0.5 * d.dot(axis),
        };
        let got = project(&source, 4, o).unwrap();
        let want: ShCoeffs<f64> = closed_form::linear_gradient(4, axis, 1.0, 0.5);
        for k in 0..want.len() {
            assert!((got[k].x - want[k]).abs() < QUADRATURE_TOL, "{o:?} k {k}");
            assert!(
                (got[k].z - 0.25 * want[k]).abs() < QUADRATURE_TOL,
                "{o:?} k {k}"
            );
        }
        // The ring transform read texel by texel agrees with the plain route.
        let px: Vec<[f32; 3]> = (0..source.h)
            .flat_map(|y| (0..source.w).map(move |x| (x, y)))
            .map(|(x, y)| source.texel(x, y))
            .collect();
        let view = map::EquirectView {
            width: source.w,
            height: source.h,
            pixels: &px,
        };
        let d = rel_diff(&got, &project_equirect_simple(view, 4, o));
        assert!(d < 1e-12, "{o:?}: {d:e}");
    }
}

#[test]
fn bad_sizes_are_errors_that_say_what_is_wrong() {
    let px = vec![[0.0f32; 3]; 64];
    let short = vec![[0.0f32; 3]; 15];
    let e = CubeFaces::new(
        4,
        [
            &px[..16],
            &px[..16],
            &short,
            &px[..16],
            &px[..16],
            &px[..16],
        ],
    )
    .unwrap_err();
    assert_eq!(
        e.kind,
        LayoutSizeErrorKind::FacePixelCount {
            face: CubeFace::PosY,
            got: 15
        }
    );
    let msg = e.to_string();
    assert!(
        msg.contains("+Y") && msg.contains("16") && msg.contains("15"),
        "{msg}"
    );
    let e = CubeFaces::new(0, [&[][..]; 6]).unwrap_err();
    assert_eq!(e.kind, LayoutSizeErrorKind::Empty);

    let e = StridedImage::new(Layout::Equirect, 8, 4, 6, &px).unwrap_err();
    assert!(
        e.to_string().contains("stride 6 is below the width 8"),
        "{e}"
    );
    // Four rows 20 apart need 3 * 20 + 8 = 68 texels; 64 are given.
    let e = StridedImage::new(Layout::Equirect, 8, 4, 20, &px).unwrap_err();
    assert!(e.to_string().contains("need 68 texels") && e.to_string().contains("holds 64"));
    assert!(StridedImage::new(Layout::Equirect, 8, 4, 18, &px).is_ok());
    let e = StridedImage::new(Layout::Strip, 7, 1, 7, &px).unwrap_err();
    assert_eq!(e.kind, LayoutSizeErrorKind::Shape);

    // A user source whose size does not fit its layout.
    struct Odd;
    impl TexelSource for Odd {
        fn layout(&self) -> Layout {
            Layout::CrossHorizontal
        }
        fn size(&self) -> (usize, usize) {
            (8, 8)
        }
        fn texel(&self, _: usize, _: usize) -> [f32; 3] {
            [1.0; 3]
        }
    }
    let e = project(&Odd, 2, MapOrientation::default()).unwrap_err();
    assert_eq!(e.kind, LayoutSizeErrorKind::Shape);
    assert!(e.to_string().contains("cross-h"), "{e}");
}

#[cfg(feature = "rayon")]
#[test]
fn projection_repeats_bit_for_bit_for_any_thread_count() {
    // Rows are summed in fixed bands, in order: the thread count cannot
    // change the summation order, on either route.
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    for (layout, size) in [(Layout::MirrorBall, 48), (Layout::Equirect, 24)] {
        let (w, h, px) = image(layout, size);
        let o = MapOrientation::default();
        let map = EnvMap::new(layout, o, w, h, &px).unwrap();
        let one = pool(1).install(|| project(&map, 6, o).unwrap());
        for n in [2, 3] {
            let many = pool(n).install(|| project(&map, 6, o).unwrap());
            assert_bits_equal(&many, &one, &format!("{layout}, {n} threads"));
        }
    }
}

/// The contiguous readers give a source's own texels: a map's rows and
/// pixels borrowed in place, a strided image's rows in place and its
/// pixels copied without the padding, and a source that stores nothing
/// read texel by texel.
#[test]
fn rows_and_pixels_are_read_in_place_or_copied() {
    use std::borrow::Cow;

    use shlight_core::map::{contiguous_pixels, read_row};

    let (w, h, stride) = (6, 3, 9);
    let padded: Vec<[f32; 3]> = (0..stride * h)
        .map(|k| [k as f32, (k % stride) as f32, -(k as f32)])
        .collect();
    let strided = StridedImage::new(Layout::Equirect, w, h, stride, &padded).unwrap();
    let want: Vec<[f32; 3]> = (0..h)
        .flat_map(|y| padded[y * stride..y * stride + w].to_vec())
        .collect();
    let mut buf = Vec::new();
    let row = read_row(&strided, 1, &mut buf);
    assert_eq!(row, &want[w..2 * w]);
    assert!(buf.is_empty(), "the strided row is read in place");
    let pixels = contiguous_pixels(&strided);
    assert!(matches!(pixels, Cow::Owned(_)));
    assert_eq!(&pixels[..], &want[..]);

    let map = EnvMap::new(Layout::Equirect, MapOrientation::default(), w, h, &want).unwrap();
    assert!(matches!(contiguous_pixels(&map), Cow::Borrowed(p) if p.as_ptr() == want.as_ptr()));

    /// A source that stores nothing: every texel computed.
    struct Computed;
    impl TexelSource for Computed {
        fn layout(&self) -> Layout {
            Layout::Equirect
        }
        fn size(&self) -> (usize, usize) {
            (4, 2)
        }
        fn texel(&self, x: usize, y: usize) -> [f32; 3] {
            [x as f32, y as f32, 1.0]
        }
    }
    assert_eq!(
        read_row(&Computed, 1, &mut buf),
        &[
            [0.0, 1.0, 1.0],
            [1.0, 1.0, 1.0],
            [2.0, 1.0, 1.0],
            [3.0, 1.0, 1.0]
        ]
    );
    let all = contiguous_pixels(&Computed);
    assert_eq!(all.len(), 8);
    assert_eq!(all[5], [1.0, 1.0, 1.0]);
}

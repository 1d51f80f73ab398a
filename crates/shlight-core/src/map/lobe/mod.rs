//! Drawing an SH function as its lobe: the polar surface `r(w) = |f(w)|`
//! that lecture slides draw for the basis functions ([`LobeSurface`]),
//! seen from a chosen direction by an orthographic [`LobeCamera`], ray
//! marched and shaded into linear RGB pixels ([`render_lobe`]).

pub(crate) mod camera;
pub(crate) mod error;
pub(crate) mod surface;

use glam::DVec3;

use crate::map::lobe::camera::LobeCamera;
use crate::map::lobe::error::LobeError;
use crate::map::lobe::surface::LobeSurface;
use crate::sh::frame::Frame;
use crate::sh::sh_coeffs::ShCoeffs;

/// Base colour of the lobe where `f > 0` (linear RGB).
const POSITIVE: DVec3 = DVec3::new(0.80, 0.08, 0.06);
/// Base colour of the lobe where `f < 0` (linear RGB).
const NEGATIVE: DVec3 = DVec3::new(0.06, 0.20, 0.80);
/// The background: white.
const BACKGROUND: [f32; 3] = [1.0, 1.0, 1.0];
/// The part of the base colour every lit pixel keeps, facing the light or
/// not; the rest is Lambert's `max(0, n . l)`.
const AMBIENT: f64 = 0.25;

/// `f` (scalar coefficients in `frame`) drawn as its lobe, the surface
/// `|p| = |f(p / |p|)|` ([`LobeSurface`]), seen from `view` (toward the
/// eye, in `frame`; [`default_lobe_view`](crate::map::default_lobe_view))
/// by an orthographic [`LobeCamera`] on a `width x height` image, scaled
/// so the lobe's radius `max |f|` spans `1 / LOBE_MARGIN` of the image's
/// half-size: the image's pixels, row-major from the top-left.
///
/// Each pixel's ray is marched from the front in steps of at least one
/// pixel and its first crossing bisected ([`LobeSurface::hit`]); the hit is
/// red where `f > 0` and blue where `f < 0`, shaded by Lambert's law with
/// the normal of `g(p) = |p| - |f(p / |p|)|` by central differences, lit by
/// a light fixed to the camera (from the upper left, in front), a quarter
/// of the colour ambient. The background is white. Values are linear, in
/// `[0, 1]`. Rows run in parallel with the `rayon` feature; `on_row` is
/// called once per row.
///
/// # Errors
/// As [`LobeSurface::new`] and [`LobeCamera::new`].
pub fn render_lobe(
    f: &ShCoeffs<f64>,
    frame: Frame,
    view: DVec3,
    size: (usize, usize),
    on_row: &(dyn Fn() + Sync),
) -> Result<Vec<[f32; 3]>, LobeError> {
    let lobe = LobeSurface::new(f)?;
    let camera = LobeCamera::new(view, frame, size, lobe.radius())?;
    let (right, up) = camera.screen_axes();
    let light = (camera.toward_eye() + 0.6 * up - 0.4 * right).normalize();
    let (w, h) = size;
    let mut pixels = vec![BACKGROUND; w * h];
    let draw_row = |(y, row): (usize, &mut [[f32; 3]])| {
        let mut scratch = vec![0.0; lobe.coeff_count()];
        for (x, px) in row.iter_mut().enumerate() {
            let (o, d) = camera.ray(x as f64 + 0.5, y as f64 + 0.5);
            let Some(p) = lobe.hit_with(o, d, camera.pixel_size(), &mut scratch) else {
                continue;
            };
            let mut n = lobe.normal_with(p, -d, &mut scratch);
            if n.dot(d) > 0.0 {
                n = -n;
            }
            let dir = p.try_normalize().unwrap_or(-d);
            let base = if lobe.value_with(dir, &mut scratch) >= 0.0 {
                POSITIVE
            } else {
                NEGATIVE
            };
            let shade = AMBIENT + (1.0 - AMBIENT) * n.dot(light).max(0.0);
            *px = (base * shade).as_vec3().to_array();
        }
        on_row();
    };
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        pixels.par_chunks_mut(w).enumerate().for_each(draw_row);
    }
    #[cfg(not(feature = "rayon"))]
    pixels.chunks_mut(w).enumerate().for_each(draw_row);
    Ok(pixels)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::lobe::camera::{LOBE_MARGIN, default_lobe_view};

    /// `sqrt(3 / (4 pi))`: `Y_1^0 = C z`, `Y_1^1 = -C x` (Condon-Shortley).
    const C: f64 = 0.488_602_511_902_919_9;

    fn single(l: usize, m: isize) -> ShCoeffs<f64> {
        ShCoeffs::from_fn(l, |a, b| if (a, b) == (l, m) { 1.0 } else { 0.0 })
    }

    /// The lobe of `Y_1^0 = C cos(theta)` is two spheres of radius `C/2`
    /// centred at `+-C/2 z`: a ray at a known offset enters the upper one
    /// where the sphere's equation says, the radius is `C`, and the
    /// picture's silhouette is the two spheres' projected discs.
    #[test]
    fn y10_is_two_spheres_hit_at_their_analytic_depth() {
        let lobe = LobeSurface::new(&single(1, 0)).unwrap();
        assert!((lobe.radius() - C).abs() < 1e-12, "{}", lobe.radius());
        // From +X, z-up: the image's right is +Y, its up +Z.
        let cam = LobeCamera::new(DVec3::X, Frame::ZUp, (96, 96), lobe.radius()).unwrap();
        let (right, up) = cam.screen_axes();
        assert!((right - DVec3::Y).length() < 1e-12 && (up - DVec3::Z).length() < 1e-12);
        for (sy, sz) in [(0.0, 0.25), (0.1, 0.3), (-0.15, 0.6), (0.05, -0.4)] {
            let (sy, sz) = (sy * C, sz * C);
            let (x, y) = cam.project(DVec3::new(0.0, sy, sz));
            let (o, d) = cam.ray(x, y);
            let p = lobe.hit(o, d, cam.pixel_size()).unwrap();
            let centre = 0.5 * C * sz.signum();
            let depth = (0.25 * C * C - sy * sy - (sz - centre).powi(2)).sqrt();
            assert!(
                (p - DVec3::new(depth, sy, sz)).length() < 1e-9,
                "{p} against depth {depth}"
            );
        }
        // A ray outside both discs misses.
        let (x, y) = cam.project(DVec3::new(0.0, 0.4 * C, 0.9 * C));
        let (o, d) = cam.ray(x, y);
        assert_eq!(lobe.hit(o, d, cam.pixel_size()), None);
    }

    /// Every pixel of the picture of `Y_1^0` from the default oblique view
    /// is what ray-sphere intersection with the two spheres (radius `C/2`,
    /// centres `+-C/2 z`) says: red where the ray enters the `+z` sphere
    /// first, blue where it enters the `-z` one first, white where it
    /// misses both; only centres within a hundredth of a pixel of a
    /// sphere's silhouette may go either way (a ray deeper inside crosses
    /// the sphere along a chord longer than the one-pixel step). And the scale: the upper
    /// sphere's top is, by hand, `C/2 (1 + 5/sqrt(30))` above the image's
    /// centre (the image's up is `(-2, -1, 5)/sqrt(30)`), 36.44 pixels of
    /// `2.1 C / 80`: row 3.56, so row 4 is the first with red.
    #[test]
    fn y10_picture_matches_the_two_spheres() {
        let (w, h) = (96, 80);
        let view = default_lobe_view(Frame::ZUp);
        let image = render_lobe(&single(1, 0), Frame::ZUp, view, (w, h), &|| {}).unwrap();
        let cam = LobeCamera::new(view, Frame::ZUp, (w, h), C).unwrap();
        let (_, up) = cam.screen_axes();
        assert!((up - DVec3::new(-2.0, -1.0, 5.0) / 30f64.sqrt()).length() < 1e-12);
        let mut rims = 0;
        let mut top = h;
        for y in 0..h {
            for x in 0..w {
                let (o, d) = cam.ray(x as f64 + 0.5, y as f64 + 0.5);
                // Per sphere: the ray's signed distance inside its
                // silhouette (in pixels) and where it enters.
                let sphere = |s: f64| {
                    let c = DVec3::new(0.0, 0.0, s * 0.5 * C);
                    let tc = (c - o).dot(d);
                    let miss2 = (o + tc * d - c).length_squared();
                    let inside = (0.5 * C - miss2.sqrt()) / cam.pixel_size();
                    (inside, tc - (0.25 * C * C - miss2).max(0.0).sqrt())
                };
                let ((in_up, t_up), (in_down, t_down)) = (sphere(1.0), sphere(-1.0));
                if in_up.abs() < 0.01 || in_down.abs() < 0.01 {
                    rims += 1;
                    continue;
                }
                let [r, g, b] = image[y * w + x];
                let red = in_up > 0.0 && (in_down < 0.0 || t_up < t_down);
                if red {
                    assert!(r > 2.0 * b && g < r, "({x}, {y}) {r} {g} {b} not red");
                    top = top.min(y);
                } else if in_down > 0.0 {
                    assert!(b > 2.0 * r && g < b, "({x}, {y}) {r} {g} {b} not blue");
                } else {
                    assert_eq!([r, g, b], BACKGROUND, "({x}, {y})");
                }
            }
        }
        // About 240 pixels lie along the rims, 2% of each within the band.
        assert!(rims < 20, "{rims} centres on a rim");
        assert_eq!(top, 4);
        assert!((cam.pixel_size() - 2.0 * LOBE_MARGIN * C / 80.0).abs() < 1e-15);
        // The image's centre looks through the origin, and a pixel's step
        // is a pixel's size along the image's axes.
        let (o, _) = cam.ray(48.0, 40.0);
        assert!(o.length() < 1e-15);
        let (o, _) = cam.ray(50.0, 37.0);
        let (right, up) = cam.screen_axes();
        assert!((o - cam.pixel_size() * (2.0 * right + 3.0 * up)).length() < 1e-14);
    }

    /// `Y_1^1 = -C x` (Condon-Shortley phase): from the default view the
    /// nearest point of the sphere on `+x` is blue, of the one on `-x` red,
    /// and each is hit where the sphere's centre plus `C/2` toward the eye
    /// says.
    #[test]
    fn y11_is_blue_on_plus_x() {
        let f = single(1, 1);
        let view = default_lobe_view(Frame::ZUp);
        let (w, h) = (128, 128);
        let image = render_lobe(&f, Frame::ZUp, view, (w, h), &|| {}).unwrap();
        let lobe = LobeSurface::new(&f).unwrap();
        let cam = LobeCamera::new(view, Frame::ZUp, (w, h), lobe.radius()).unwrap();
        for (side, blue) in [(1.0, true), (-1.0, false)] {
            let nearest = DVec3::new(side * 0.5 * C, 0.0, 0.0) + 0.5 * C * cam.toward_eye();
            let (x, y) = cam.project(nearest);
            let (o, d) = cam.ray(x, y);
            let p = lobe.hit(o, d, cam.pixel_size()).unwrap();
            assert!((p - nearest).length() < 1e-6, "{p} against {nearest}");
            let [r, _, b] = image[y as usize * w + x as usize];
            assert_eq!(b > r, blue, "side {side}: {r} {b}");
        }
    }

    /// A y-up file's default view is the z-up one turned into its frame:
    /// the picture of `Y_1^0` (z-up) and of the same function in y-up
    /// coordinates (`Y_1^-1 = -C y`, turned by `Frame::rotation_to`: the
    /// up axis `+Z` becomes `+Y`, so the function is `C y`) are the same
    /// image.
    #[test]
    fn y_up_files_are_drawn_with_their_up_axis_up() {
        let zup = render_lobe(
            &single(1, 0),
            Frame::ZUp,
            default_lobe_view(Frame::ZUp),
            (48, 40),
            &|| {},
        )
        .unwrap();
        let yup = render_lobe(
            &single(1, -1).scaled(-1.0),
            Frame::YUp,
            default_lobe_view(Frame::YUp),
            (48, 40),
            &|| {},
        )
        .unwrap();
        let mut differ = 0;
        for y in 0..40 {
            for x in 0..48 {
                let (a, b) = (zup[y * 48 + x], yup[y * 48 + x]);
                if (0..3).any(|c| (a[c] - b[c]).abs() > 1e-4) {
                    differ += 1;
                }
            }
        }
        assert_eq!(differ, 0);
        assert!(default_lobe_view(Frame::YUp).abs_diff_eq(DVec3::new(2.0, 1.0, -1.0), 0.0));
    }

    /// Looking down the up axis the camera still has axes (`+X` right),
    /// and bad views and zero functions are refused with a message.
    #[test]
    fn top_views_zero_functions_and_zero_views() {
        let cam = LobeCamera::new(DVec3::Z, Frame::ZUp, (8, 8), 1.0).unwrap();
        let (right, up) = cam.screen_axes();
        assert!((right - DVec3::X).length() < 1e-12 && (up - DVec3::Y).length() < 1e-12);
        let e = LobeCamera::new(DVec3::ZERO, Frame::ZUp, (8, 8), 1.0).unwrap_err();
        assert!(e.to_string().contains("view 0,0,0 has no direction"), "{e}");
        let e = LobeSurface::new(&ShCoeffs::<f64>::zeros(3)).unwrap_err();
        assert!(e.to_string().contains("zero everywhere"), "{e}");
        let mut nan = single(2, 1);
        nan.as_mut_slice()[0] = f64::NAN;
        assert!(
            LobeSurface::new(&nan)
                .unwrap_err()
                .to_string()
                .contains("not finite")
        );
    }
}

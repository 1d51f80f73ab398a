//! [`render_lobe`]: an SH function drawn as its lobe, the polar surface
//! `r(w) = |f(w)|` that lecture slides draw for the basis functions, seen
//! from a chosen direction ([`Lobe`], [`LobeCamera`]).

use glam::DVec3;
use shlight_core::sh::{Frame, ShBasis, ShCoeffs, sphere_minimum};
use shlight_io::Image;

use crate::{PipelineError, Result};

/// The picture's half-size (half the smaller side) over the lobe's radius
/// `max |f|`: the largest lobe ends 5% inside the image.
pub const LOBE_MARGIN: f64 = 1.05;

/// The view of [`render_lobe`] when none is given: from `(2, 1, 1)` in the
/// z-up frame, about 24° above the equator and 27° round from `+X` towards
/// `+Y`, so `+Z` is up, `+X` points to the lower left and `+Y` to the
/// right; for a y-up file the same view of the same directions turned into
/// its frame, `(2, 1, -1)` ([`Frame::rotation_to`]).
#[must_use]
pub fn default_lobe_view(frame: Frame) -> DVec3 {
    Frame::ZUp.rotation_to(frame) * DVec3::new(2.0, 1.0, 1.0)
}

/// Base colour of the lobe where `f > 0` (linear RGB).
const POSITIVE: DVec3 = DVec3::new(0.80, 0.08, 0.06);
/// Base colour of the lobe where `f < 0` (linear RGB).
const NEGATIVE: DVec3 = DVec3::new(0.06, 0.20, 0.80);
/// The background: white.
const BACKGROUND: [f32; 3] = [1.0, 1.0, 1.0];
/// The part of the base colour every lit pixel keeps, facing the light or
/// not; the rest is Lambert's `max(0, n . l)`.
const AMBIENT: f64 = 0.25;

/// A scalar SH function as the surface `|p| = |f(p / |p|)|`: the points
/// at distance `|f(w)|` from the origin in each direction `w`. Inside it
/// `g(p) = |p| - |f(p / |p|)|` is negative, outside positive.
#[derive(Clone, Debug)]
pub struct Lobe {
    coeffs: Vec<f64>,
    basis: ShBasis<f64>,
    radius: f64,
}

impl Lobe {
    /// The lobe of `f(w) = sum f_l^m Y_l^m(w)`.
    ///
    /// # Errors
    /// A coefficient is not finite, or `f` is zero everywhere (its lobe is
    /// a point).
    pub fn new(f: &ShCoeffs<f64>) -> Result<Self> {
        if f.as_slice().iter().any(|c| !c.is_finite()) {
            return Err(PipelineError::new(
                "a coefficient is not finite: no lobe to draw",
            ));
        }
        let radius = (-sphere_minimum(f).0).max(-sphere_minimum(&f.scaled(-1.0)).0);
        if radius.is_nan() || radius <= 0.0 {
            return Err(PipelineError::new(
                "the function is zero everywhere: its lobe is a point, nothing to draw",
            ));
        }
        Ok(Self {
            coeffs: f.as_slice().to_vec(),
            basis: ShBasis::new(f.lmax()),
            radius,
        })
    }

    /// The largest `|f|` over the sphere (shlight-core's `sphere_minimum`
    /// of `f` and `-f`): no point of the lobe lies farther from the
    /// origin.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// `f(d)` for a unit `d`; `scratch` holds the basis values.
    fn value_with(&self, d: DVec3, scratch: &mut [f64]) -> f64 {
        self.basis.eval(d, scratch);
        self.coeffs
            .iter()
            .zip(scratch.iter())
            .map(|(c, y)| c * y)
            .sum()
    }

    /// `f(d)` at a unit direction `d`.
    #[must_use]
    pub fn value(&self, d: DVec3) -> f64 {
        self.value_with(d, &mut vec![0.0; self.coeffs.len()])
    }

    /// `g(p) = |p| - |f(p / |p|)|`, with `fallback` as the direction at
    /// the origin.
    fn g(&self, p: DVec3, fallback: DVec3, scratch: &mut [f64]) -> f64 {
        let r = p.length();
        let d = if r > 1e-300 { p / r } else { fallback };
        r - self.value_with(d, scratch).abs()
    }

    /// The first point where the ray `origin + t dir` (`dir` a unit
    /// vector, `t` increasing) enters the lobe, or `None` when it misses.
    ///
    /// The ray is marched through the ball `|p| <= radius` until `g` turns
    /// negative, then the crossing is bisected to `1e-12` of the radius.
    /// Each step is `step` long, or longer where no crossing can lie
    /// within it: along a great circle a degree-`lmax` expansion is a
    /// trigonometric polynomial of degree `lmax`, so by Bernstein's
    /// inequality `|f|` changes by at most `lmax radius` per radian, and
    /// `p / |p|` turns by at most `dt / |p|`; a step of
    /// `min(g / (2 (1 + lmax radius / |p|)), |p| / 2)` keeps `g` positive.
    /// A part of the lobe thinner than `step` along the ray can be stepped
    /// over.
    #[must_use]
    pub fn hit(&self, origin: DVec3, dir: DVec3, step: f64) -> Option<DVec3> {
        let mut scratch = vec![0.0; self.coeffs.len()];
        self.hit_with(origin, dir, step, &mut scratch)
    }

    fn hit_with(&self, origin: DVec3, dir: DVec3, step: f64, scratch: &mut [f64]) -> Option<DVec3> {
        // The chord of the ray in the ball |p| <= radius.
        let b = origin.dot(dir);
        let disc = b * b - origin.length_squared() + self.radius * self.radius;
        if disc <= 0.0 {
            return None;
        }
        let (t0, t1) = (-b - disc.sqrt(), -b + disc.sqrt());
        let step = step.max(1e-9 * self.radius);
        // Bernstein's bound on |f|'s change per radian.
        let slope = self.basis.lmax() as f64 * self.radius;
        let at = |t: f64| origin + t * dir;
        let (mut t, mut g) = (t0, 0.0f64);
        while t < t1 {
            let r = at(t).length();
            let safe = (0.5 * g / (1.0 + slope / r.max(1e-300))).min(0.5 * r);
            let next = (t + step.max(safe)).min(t1);
            let g_next = self.g(at(next), dir, scratch);
            if g_next < 0.0 {
                // g(t) >= 0 > g(next): bisect.
                let (mut lo, mut hi) = (t, next);
                while hi - lo > 1e-12 * self.radius {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    if self.g(at(mid), dir, scratch) < 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Some(at(0.5 * (lo + hi)));
            }
            (t, g) = (next, g_next);
        }
        None
    }

    /// The outward unit normal at a point `p` of the surface: the gradient
    /// of `g` by central differences `1e-5` of the radius wide, or
    /// `fallback` where it vanishes (at the origin).
    fn normal_with(&self, p: DVec3, fallback: DVec3, scratch: &mut [f64]) -> DVec3 {
        let h = 1e-5 * self.radius;
        let mut grad = DVec3::ZERO;
        for (axis, e) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
            grad[axis] =
                self.g(p + h * e, fallback, scratch) - self.g(p - h * e, fallback, scratch);
        }
        grad.try_normalize().unwrap_or(fallback)
    }
}

/// An orthographic camera on a lobe: it looks along `-view` at the
/// origin, the frame's up axis (`+Z` z-up, `+Y` y-up) drawn up the image
/// (or, looking along that axis, `+Y` of the z-up frame turned into the
/// frame: a top view has `+X` to the right), and the image's smaller side
/// spans `2 LOBE_MARGIN radius`.
#[derive(Clone, Copy, Debug)]
pub struct LobeCamera {
    toward_eye: DVec3,
    right: DVec3,
    up: DVec3,
    width: usize,
    height: usize,
    pixel: f64,
}

impl LobeCamera {
    /// A camera on a lobe of `radius` seen from `view` (the direction
    /// from the lobe toward the eye, any length, in `frame`'s
    /// coordinates) onto a `width x height` image.
    ///
    /// # Errors
    /// `view` is zero or not finite, or the size or radius is zero.
    pub fn new(
        view: DVec3,
        frame: Frame,
        (width, height): (usize, usize),
        radius: f64,
    ) -> Result<Self> {
        let Some(toward_eye) = view.try_normalize() else {
            return Err(PipelineError::new(format!(
                "the view {},{},{} has no direction: give the direction from the lobe toward the eye, e.g. 2,1,1",
                view.x, view.y, view.z
            )));
        };
        if width == 0 || height == 0 || !(radius > 0.0 && radius.is_finite()) {
            return Err(PipelineError::new(format!(
                "a lobe picture needs a size and a radius (got {width}x{height}, radius {radius})"
            )));
        }
        let to_frame = Frame::ZUp.rotation_to(frame);
        let forward = -toward_eye;
        let across = forward.cross(to_frame * DVec3::Z);
        let right = if across.length() > 1e-9 {
            across.normalize()
        } else {
            forward.cross(to_frame * DVec3::Y).normalize()
        };
        let up = right.cross(forward);
        let pixel = 2.0 * LOBE_MARGIN * radius / width.min(height) as f64;
        Ok(Self {
            toward_eye,
            right,
            up,
            width,
            height,
            pixel,
        })
    }

    /// The unit direction toward the eye.
    #[must_use]
    pub fn toward_eye(&self) -> DVec3 {
        self.toward_eye
    }

    /// The image's right and up directions in the frame's coordinates.
    #[must_use]
    pub fn screen_axes(&self) -> (DVec3, DVec3) {
        (self.right, self.up)
    }

    /// The side of a pixel, in the lobe's units.
    #[must_use]
    pub fn pixel_size(&self) -> f64 {
        self.pixel
    }

    /// The ray through image position `(x, y)` (pixels from the top-left
    /// corner; pixel `(i, j)`'s centre is `(i + 0.5, j + 0.5)`): its
    /// origin, in the plane through the lobe's centre facing the eye, and
    /// its unit direction `-toward_eye`.
    #[must_use]
    pub fn ray(&self, x: f64, y: f64) -> (DVec3, DVec3) {
        let sx = (x - 0.5 * self.width as f64) * self.pixel;
        let sy = (0.5 * self.height as f64 - y) * self.pixel;
        (sx * self.right + sy * self.up, -self.toward_eye)
    }

    /// The image position `(x, y)` a point projects to ([`LobeCamera::ray`]'s
    /// inverse).
    #[must_use]
    pub fn project(&self, p: DVec3) -> (f64, f64) {
        (
            0.5 * self.width as f64 + p.dot(self.right) / self.pixel,
            0.5 * self.height as f64 - p.dot(self.up) / self.pixel,
        )
    }
}

/// `f` (scalar coefficients in `frame`) drawn as its lobe, the surface
/// `|p| = |f(p / |p|)|` ([`Lobe`]), seen from `view` (toward the eye, in
/// `frame`; [`default_lobe_view`]) by an orthographic [`LobeCamera`] on a
/// `width x height` image, scaled so the lobe's radius `max |f|` spans
/// `1 / LOBE_MARGIN` of the image's half-size.
///
/// Each pixel's ray is marched from the front in steps of at least one
/// pixel and its first crossing bisected ([`Lobe::hit`]); the hit is red where
/// `f > 0` and blue where `f < 0`, shaded by Lambert's law with the normal
/// of `g(p) = |p| - |f(p / |p|)|` by central differences, lit by a light
/// fixed to the camera (from the upper left, in front), a quarter of the
/// colour ambient. The background is white. Values are linear, in
/// `[0, 1]`. Rows run in parallel; `on_row` is called once per row.
///
/// # Errors
/// As [`Lobe::new`] and [`LobeCamera::new`].
pub fn render_lobe(
    f: &ShCoeffs<f64>,
    frame: Frame,
    view: DVec3,
    size: (usize, usize),
    on_row: &(dyn Fn() + Sync),
) -> Result<Image> {
    use rayon::prelude::*;

    let lobe = Lobe::new(f)?;
    let camera = LobeCamera::new(view, frame, size, lobe.radius())?;
    let (right, up) = camera.screen_axes();
    let light = (camera.toward_eye() + 0.6 * up - 0.4 * right).normalize();
    let (w, h) = size;
    let mut pixels = vec![BACKGROUND; w * h];
    pixels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let mut scratch = vec![0.0; lobe.coeffs.len()];
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
    });
    Image::new(w, h, pixels).map_err(|e| PipelineError::new(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let lobe = Lobe::new(&single(1, 0)).unwrap();
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
                let [r, g, b] = image.get(x, y);
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
        let lobe = Lobe::new(&f).unwrap();
        let cam = LobeCamera::new(view, Frame::ZUp, (w, h), lobe.radius()).unwrap();
        for (side, blue) in [(1.0, true), (-1.0, false)] {
            let nearest = DVec3::new(side * 0.5 * C, 0.0, 0.0) + 0.5 * C * cam.toward_eye();
            let (x, y) = cam.project(nearest);
            let (o, d) = cam.ray(x, y);
            let p = lobe.hit(o, d, cam.pixel_size()).unwrap();
            assert!((p - nearest).length() < 1e-6, "{p} against {nearest}");
            let [r, _, b] = image.get(x as usize, y as usize);
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
                let (a, b) = (zup.get(x, y), yup.get(x, y));
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
        assert!(e.message().contains("view 0,0,0 has no direction"), "{e}");
        let e = Lobe::new(&ShCoeffs::<f64>::zeros(3)).unwrap_err();
        assert!(e.message().contains("zero everywhere"), "{e}");
        let mut nan = single(2, 1);
        nan.as_mut_slice()[0] = f64::NAN;
        assert!(
            Lobe::new(&nan)
                .unwrap_err()
                .message()
                .contains("not finite")
        );
    }
}

//! [`LobeSurface`]: a scalar SH function as the polar surface
//! `|p| = |f(p / |p|)|`, and where rays enter it.

use glam::DVec3;

use crate::map::lobe::error::LobeError;
use crate::sh::basis::ShBasis;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sphere_minimum::sphere_minimum;

/// A scalar SH function as the surface `|p| = |f(p / |p|)|`: the points
/// at distance `|f(w)|` from the origin in each direction `w`. Inside it
/// `g(p) = |p| - |f(p / |p|)|` is negative, outside positive.
#[derive(Clone, Debug)]
pub struct LobeSurface {
    coeffs: Vec<f64>,
    basis: ShBasis<f64>,
    radius: f64,
}

impl LobeSurface {
    /// The lobe of `f(w) = sum f_l^m Y_l^m(w)`.
    ///
    /// # Errors
    /// A coefficient is not finite ([`LobeError::NotFinite`]), or `f` is
    /// zero everywhere, so its lobe is a point ([`LobeError::Zero`]).
    pub fn new(f: &ShCoeffs<f64>) -> Result<Self, LobeError> {
        if f.as_slice().iter().any(|c| !c.is_finite()) {
            return Err(LobeError::NotFinite);
        }
        let radius = (-sphere_minimum(f).0).max(-sphere_minimum(&f.scaled(-1.0)).0);
        if radius.is_nan() || radius <= 0.0 {
            return Err(LobeError::Zero);
        }
        Ok(Self {
            coeffs: f.as_slice().to_vec(),
            basis: ShBasis::new(f.lmax()),
            radius,
        })
    }

    /// The largest `|f|` over the sphere ([`crate::sh::sphere_minimum`]
    /// of `f` and `-f`): no point of the lobe lies farther from the
    /// origin.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The number of coefficients, the length of the scratch buffers the
    /// `*_with` methods take.
    pub(crate) fn coeff_count(&self) -> usize {
        self.coeffs.len()
    }

    /// `f(d)` for a unit `d`; `scratch` holds the basis values.
    pub(crate) fn value_with(&self, d: DVec3, scratch: &mut [f64]) -> f64 {
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

    /// [`LobeSurface::hit`] with the basis values in `scratch`.
    pub(crate) fn hit_with(
        &self,
        origin: DVec3,
        dir: DVec3,
        step: f64,
        scratch: &mut [f64],
    ) -> Option<DVec3> {
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
    pub(crate) fn normal_with(&self, p: DVec3, fallback: DVec3, scratch: &mut [f64]) -> DVec3 {
        let h = 1e-5 * self.radius;
        let mut grad = DVec3::ZERO;
        for (axis, e) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
            grad[axis] =
                self.g(p + h * e, fallback, scratch) - self.g(p - h * e, fallback, scratch);
        }
        grad.try_normalize().unwrap_or(fallback)
    }
}

//! [`auto_window`]: the weakest window of a family that makes a
//! reconstruction, or the irradiance computed from it
//! ([`WindowTarget::Irradiance`]), non-negative everywhere on the sphere, at
//! any `lmax`. Filament's `cmgen` has an automatic window for the same
//! purpose, but only for 3 bands (`lmax` 2); this one works to `lmax` 32 and
//! beyond. It rests on [`crate::sh::sphere_minimum()`], a dense-then-local global
//! minimum search. Coefficients may be `f32` or `f64`; the search is in `f64`
//! either way.

use core::f64::consts::PI;
use core::fmt;

use glam::DVec3;

use crate::sh::real::Real;
use crate::sh::real::dir_from_f64;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;
use crate::sh::sphere_minimum::{Minimiser, band_bounds, dense_point_count};
use crate::sh::window::{Window, WindowFamily};
use crate::sh::zonal::irradiance;

/// Which function [`auto_window`] must keep non-negative.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WindowTarget {
    /// The windowed expansion itself, `sum w_l f_l^m Y_l^m` (e.g. radiance
    /// shown as a background).
    Function,
    /// The irradiance of the windowed radiance,
    /// `E = sum A_l w_l f_l^m Y_l^m` ([`crate::sh::irradiance`], Ramamoorthi &
    /// Hanrahan 2001): what a renderer shows on a diffuse surface.
    Irradiance,
}

/// The result of [`auto_window`] for coefficients of scalar `T` (`f64`, the
/// default, or `f32`): values in `T`, the direction a `T::Vec3` (`DVec3`,
/// `Vec3`), each rounded from the `f64` search for `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoWindow<T: Real = f64> {
    /// The weakest window of the family whose target is non-negative
    /// everywhere (with the margin of [`AUTO_WINDOW_MARGIN`], which for
    /// `f32` includes the rounding of evaluating the target in `f32`), or
    /// [`Window::None`] when the target already is non-negative.
    pub window: Window,
    /// Minimum of the unwindowed target over the sphere ([`sphere_minimum`](crate::sh::sphere_minimum)).
    pub min_before: T,
    /// Minimum of the windowed target over the sphere: `>=` the margin when a
    /// window was chosen, `min_before` when none was.
    pub min_after: T,
    /// Where the unwindowed target takes `min_before` (a unit vector).
    pub argmin_before: T::Vec3,
}

/// Why [`auto_window`] found no window; `T` as in [`AutoWindow`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum AutoWindowError<T: Real = f64> {
    /// The target's constant term is `<= 0` while the target is negative
    /// somewhere. Every window keeps the constant term and, as windows get
    /// stronger, tends to it; a function whose mean is `<= 0` and which is not
    /// identically zero is negative somewhere, so no window can help.
    NonPositiveMean {
        /// The mean of the target over the sphere, `t_0^0 Y_0^0`.
        mean: T,
        /// Minimum of the target over the sphere.
        min: T,
        /// Where the target takes `min`.
        argmin: T::Vec3,
    },
}

impl<T: Real + fmt::Display> fmt::Display for AutoWindowError<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AutoWindowError::NonPositiveMean { mean, min, .. } => write!(
                f,
                "no window can make this function non-negative: its mean is {mean} (<= 0) \
                 and its minimum {min}"
            ),
        }
    }
}

impl<T: Real + fmt::Display> std::error::Error for AutoWindowError<T> {}

/// Relative safety margin of [`auto_window`]: a window is accepted when the
/// minimum of the windowed target is `>= AUTO_WINDOW_MARGIN * |t_0^0| Y_0^0`,
/// i.e. `1e-9` times the target's mean over the sphere.
///
/// [`sphere_minimum`](crate::sh::sphere_minimum) returns the value at a point it found, which can sit
/// above the true minimum by the accuracy of its local refinement (rounding,
/// about `1e-15` relative). Asking for a small positive minimum rather than
/// `>= 0` makes an independent dense check of the chosen window see no
/// negative value, at the cost of a window stronger than the exact boundary
/// by a negligible amount.
///
/// For `f32` coefficients the minimum must also clear what evaluating the
/// windowed target in `f32` can lose to rounding, so that it stays
/// non-negative when evaluated in `f32` too: `u (N + 4 (top+1) + 8) B_w`,
/// with `u = 2^-24`, `top` the highest degree the window keeps,
/// `N = (top+1)^2` and `B_w = sum_l |w_l| sqrt((2l+1)/(4 pi)) |t_l|`, which
/// bounds `sum_i |w_l t_i Y_i(d)|` at every `d` (addition theorem). `N u`
/// bounds the rounding of summing `N` terms in any order; the rest covers
/// the few roundings inside each term (window factor, `A_l`, direction,
/// basis recurrence). The `f64` criterion is `AUTO_WINDOW_MARGIN` alone.
pub const AUTO_WINDOW_MARGIN: f64 = 1e-9;

/// Chooses the weakest window of `family` that makes `target` of `f`
/// non-negative on the whole sphere, at any `lmax`.
///
/// "Weakest" is the largest `w` for Hanning and Lanczos, the smallest
/// `lambda` for Laplacian. The target is `g = sum w_l f_l^m Y_l^m`
/// ([`WindowTarget::Function`]) or `E = sum A_l w_l f_l^m Y_l^m`
/// ([`WindowTarget::Irradiance`]); the returned window is meant to be applied
/// to `f` itself ([`Window::apply`]), irradiance being computed afterwards as
/// usual (windows and irradiance are both per-degree factors, so they
/// commute). Sloan 2008 ("Windowing") gives the families; Filament's `cmgen`
/// automates the choice for 3 bands only.
///
/// Method:
/// 1. The target's minimum is found by [`sphere_minimum`](crate::sh::sphere_minimum). If it is `>= 0`
///    (for `f32`, `>=` the rounding allowance of the unwindowed target, see
///    [`AUTO_WINDOW_MARGIN`]) the result is [`Window::None`].
/// 2. If the target's constant term is `<= 0`, no window can help:
///    [`AutoWindowError::NonPositiveMean`].
/// 3. Bracket, searching from the weak end, because the feasible parameters
///    need not form one interval (a sun over a dim sky at `lmax` 8 passes
///    for Hanning `w` in about (2, 2.03) and (9.7, 16.3) only): Hanning and
///    Lanczos start at `w = 4 (lmax + 1)`, well past Sloan's "w past lmax"
///    (growing `w` by 2x while it still passes) and otherwise step down by
///    0.9x until a `w` passes; `w <= 1` keeps only `l = 0` and always passes.
///    Laplacian starts at `lambda = 1e-4 / (lmax^2 (lmax+1)^2)` (every factor
///    `>= 0.9999`; if that already passes, it shrinks 10x until it fails) and
///    grows 1.5x until it passes, capped by `lambda* = 2 B / c` with
///    `c = t_0^0 Y_0^0`, `B = sum_{l>=1} sqrt((2l+1)/(4 pi)) |t_l| /
///    (l^2 (l+1)^2)`, at which the target is provably `>= c/2` (addition
///    theorem: `|sum_m t_l^m Y_l^m| <= |t_l| sqrt((2l+1)/(4 pi))`).
///    A feasible range narrower than one scan step can be missed, so the
///    result is the weakest window up to that resolution.
/// 4. Bisect (in `w`, or in `log lambda`) to a relative width of `1e-6`.
/// 5. Verify the result with a second, denser Fibonacci set (`2n + 1`
///    points); if it fails, step stronger (`w` by 0.98x, `lambda` by 1.05x)
///    until it passes.
///
/// A window "passes" when the minimum is `>= AUTO_WINDOW_MARGIN *
/// |t_0^0| Y_0^0` (for `f32`, or the rounding allowance if larger: see
/// [`AUTO_WINDOW_MARGIN`]); a test that fails stops at the first value found
/// below the margin. A window is therefore found whenever the constant term
/// is positive.
///
/// Scalars: `f` may hold `f32` or `f64`. The search is in `f64` either way:
/// `f32` coefficients are widened exactly, the irradiance factors `A_l` and
/// every evaluation are applied in `f64`, and the reported minima, mean and
/// direction are rounded to `f32` at the end. Only the pass criterion
/// differs (the `f32` rounding allowance above), so an `f32` window can be
/// marginally stronger than the `f64` one of the same coefficients. `f64`
/// coefficients go through no conversion.
///
/// For RGB, window each channel with its own result, or choose one window
/// on one channel (e.g. luminance) and check the others with
/// [`sphere_minimum`](crate::sh::sphere_minimum): since feasible parameters need not form an
/// interval, the strongest of per-channel results is not guaranteed to
/// suit every channel.
///
/// A function whose true irradiance vanishes on a region (a directional
/// light, any light confined to a cap) is the hard case: the windowed
/// irradiance must then stay non-negative where the true one is exactly 0,
/// and the weakest such window keeps little more than `l <= 1` at every
/// `lmax` (Hanning `w` just under 2). A little light from every direction
/// (a sky) lets much weaker windows pass.
///
/// Cost: one basis evaluation per point of the two dense sets (most of the
/// time at high `lmax`), then 40 to 70 tried parameters at `O(n lmax)` each
/// plus local refinement when a parameter passes. Measured on 2 cores: about
/// 5 ms at `lmax` 2 to 8, 50 ms at `lmax` 16, 0.6 s at `lmax` 32.
///
/// ```
/// use shlight_core::sh::{ShCoeffs, Window, WindowFamily, WindowTarget, auto_window, irradiance, sphere_minimum};
/// // A directional light from +Z: its 9-term irradiance dips to -19/480 at cos t = -8/15.
/// let light = ShCoeffs::from_vec(shlight_core::sh::sh_eval(2, glam::DVec3::new(0.0, 0.0, 1.0))).unwrap();
/// let auto = auto_window(&light, WindowFamily::Hanning, WindowTarget::Irradiance).unwrap();
/// assert!((auto.min_before + 19.0 / 480.0).abs() < 1e-12);
/// let Window::Hanning { w } = auto.window else { panic!() };
/// assert!(w > 1.0 && w < 3.0);
/// assert!(sphere_minimum(&irradiance(&auto.window.apply(&light))).0 >= 0.0);
///
/// // The same light in f32: f32 minima, a glam::Vec3 direction.
/// let light32: ShCoeffs<f32> = light.map(|c| c as f32);
/// let auto32 = auto_window(&light32, WindowFamily::Hanning, WindowTarget::Irradiance).unwrap();
/// assert!((auto32.min_before + 19.0 / 480.0).abs() < 1e-7);
/// let at: glam::Vec3 = auto32.argmin_before;
/// assert!((at.z + 8.0 / 15.0).abs() < 1e-5);
/// assert!(sphere_minimum(&irradiance(&auto32.window.apply(&light32))).0 >= 0.0);
/// ```
///
/// # Errors
/// [`AutoWindowError::NonPositiveMean`] when the target is negative somewhere
/// and its constant term is `<= 0` (its fields rounded to `T` as above).
///
/// # Panics
/// None of its own.
pub fn auto_window<T: Real + ShValue<Scalar = T>>(
    f: &ShCoeffs<T>,
    family: WindowFamily,
    target: WindowTarget,
) -> Result<AutoWindow<T>, AutoWindowError<T>> {
    // Everything below is in f64 (exact widening of f32 coefficients); the
    // reported values and direction are rounded to `T` on the way out.
    let wide = f.map(T::to_f64);
    let t = match target {
        WindowTarget::Function => wide,
        WindowTarget::Irradiance => irradiance(&wide),
    };
    let out = |window: Window, min_before: f64, min_after: f64, argmin_before: DVec3| AutoWindow {
        window,
        min_before: T::from_f64(min_before),
        min_after: T::from_f64(min_after),
        argmin_before: dir_from_f64::<T>(argmin_before),
    };
    let lmax = t.lmax();
    let n = dense_point_count(lmax);
    let rounding = Rounding::new::<T>(&t);
    let search = Minimiser::new(t.clone(), n);
    let ones = vec![1.0; lmax + 1];
    let (min_before, argmin_before) = search.minimum(&ones);
    // 0 for f64: the test is `min_before >= 0`.
    if min_before >= rounding.allowance(&ones) {
        return Ok(out(Window::None, min_before, min_before, argmin_before));
    }
    let mean = t[0] * y00();
    if t[0].is_nan() || t[0] <= 0.0 {
        return Err(AutoWindowError::NonPositiveMean {
            mean: T::from_f64(mean),
            min: T::from_f64(min_before),
            argmin: dir_from_f64::<T>(argmin_before),
        });
    }
    let margin = AUTO_WINDOW_MARGIN * mean;
    // The margin a window's minimum must clear: `margin` itself for f64.
    let margin_of = |factors: &[f64]| margin.max(rounding.allowance(factors));
    let min_of = |m: &Minimiser, factors: &[f64]| m.minimum(factors).0;
    let passes = |p: f64| {
        let factors = family.window(p).factors(lmax);
        let margin = margin_of(&factors);
        search.minimum_until(&factors, margin).0 >= margin
    };

    let lambda_bound = laplacian_bound(&t);
    let mut p = match family {
        WindowFamily::Hanning | WindowFamily::Lanczos => weakest_width(lmax, passes),
        WindowFamily::Laplacian => weakest_lambda(lmax, lambda_bound, passes),
    };

    // Verify on an independent, denser set; step stronger if that fails.
    let check = Minimiser::new(t, 2 * n + 1);
    for _ in 0..MAX_STEPS {
        let factors = family.window(p).factors(lmax);
        let min_after = min_of(&search, &factors).min(min_of(&check, &factors));
        let certain = match family {
            WindowFamily::Hanning | WindowFamily::Lanczos => p <= 1.0,
            WindowFamily::Laplacian => p >= lambda_bound,
        };
        if min_after >= margin_of(&factors) || certain {
            return Ok(out(family.window(p), min_before, min_after, argmin_before));
        }
        p = match family {
            WindowFamily::Hanning | WindowFamily::Lanczos => (p * 0.98).max(1.0),
            WindowFamily::Laplacian => (p * 1.05).min(lambda_bound),
        };
    }
    // Unreachable in practice (0.98^MAX_STEPS * w < 1); return the certain end.
    let p = match family {
        WindowFamily::Hanning | WindowFamily::Lanczos => 1.0,
        WindowFamily::Laplacian => lambda_bound,
    };
    Ok(out(
        family.window(p),
        min_before,
        min_of(&check, &family.window(p).factors(lmax)),
        argmin_before,
    ))
}

/// How far below its exact value a windowed target `sum_l w_l t_l(d)` can
/// come out when evaluated in a scalar coarser than `f64` (see
/// [`auto_window`]); zero for `f64`.
struct Rounding {
    /// Unit roundoff of the scalar (`2^-24` for `f32`), or 0 for `f64`.
    unit: f64,
    /// `b_l = sqrt((2l+1)/(4 pi)) |t_l|`: by the addition theorem and
    /// Cauchy-Schwarz, `sum_m |t_l^m Y_l^m(d)| <= b_l` at every `d`.
    band_bounds: Vec<f64>,
}

impl Rounding {
    fn new<T: Real>(t: &ShCoeffs<f64>) -> Self {
        let eps = T::EPSILON.to_f64();
        let unit = if eps > f64::EPSILON { 0.5 * eps } else { 0.0 };
        if unit == 0.0 {
            return Self {
                unit,
                band_bounds: Vec::new(),
            };
        }
        Self {
            unit,
            band_bounds: band_bounds(t),
        }
    }

    /// `u (N + 4 (top+1) + 8) B_w` for the window `factors` (`w_l`), with
    /// `top` the last degree the window keeps, `N = (top+1)^2` terms and
    /// `B_w = sum_l |w_l| b_l >= sum_i |w_l t_i Y_i(d)|`: summing `N` terms
    /// rounds by at most `N u` times the sum of their magnitudes, in any
    /// order; each term adds a few roundings of its own (the window factor
    /// and `A_l` rounded and multiplied in, the direction: 8) and those of
    /// the basis recurrence, which grow with the degree (`4 (top+1)`).
    fn allowance(&self, factors: &[f64]) -> f64 {
        if self.unit == 0.0 {
            return 0.0;
        }
        let kept =
            |l: usize| factors.get(l).is_some_and(|&w| w != 0.0) && self.band_bounds[l] != 0.0;
        let top = (0..self.band_bounds.len())
            .rev()
            .find(|&l| kept(l))
            .unwrap_or(0);
        let b_w: f64 = (0..=top)
            .map(|l| factors.get(l).map_or(0.0, |w| w.abs()) * self.band_bounds[l])
            .sum();
        let terms = ((top + 1) * (top + 1) + 4 * (top + 1) + 8) as f64;
        self.unit * terms * b_w
    }
}

/// Upper limit on bracketing and verification steps.
const MAX_STEPS: usize = 400;
/// Hanning/Lanczos search start, in units of `lmax + 1`: well past the
/// `lmax + 1` Sloan suggests, because feasible widths need not form one
/// interval (a sun over a dim sky at lmax 8 passes for `w` in about
/// (2, 2.03) and (9.7, 16.3) but not at 9).
const WIDTH_START: f64 = 4.0;
/// Hanning/Lanczos downward scan ratio.
const WIDTH_SCAN: f64 = 0.9;
/// Laplacian search start, times `1 / (lmax^2 (lmax+1)^2)`: every factor `>= 0.9999`.
const LAMBDA_START: f64 = 1e-4;
/// Laplacian upward scan ratio.
const LAMBDA_SCAN: f64 = 1.5;
/// Relative width at which bisection stops.
const BISECT_REL: f64 = 1e-6;

/// Largest `w` (Hanning/Lanczos) that `passes`; `passes(w)` is true for `w <= 1`.
fn weakest_width(lmax: usize, passes: impl Fn(f64) -> bool) -> f64 {
    let start = WIDTH_START * (lmax + 1) as f64;
    let (mut lo, mut hi);
    if passes(start) {
        // Already weak enough: grow until it fails (w -> inf is no window,
        // which fails, so this ends).
        lo = start;
        hi = 2.0 * start;
        let mut steps = 0;
        while passes(hi) {
            lo = hi;
            hi *= 2.0;
            steps += 1;
            if steps > MAX_STEPS {
                return lo;
            }
        }
    } else {
        hi = start;
        loop {
            let w = hi * WIDTH_SCAN;
            if w <= 1.0 {
                lo = 1.0;
                break;
            }
            if passes(w) {
                lo = w;
                break;
            }
            hi = w;
        }
    }
    while hi - lo > BISECT_REL * hi {
        let mid = 0.5 * (lo + hi);
        if passes(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Smallest `lambda` that `passes`; `passes(bound)` is true.
fn weakest_lambda(lmax: usize, bound: f64, passes: impl Fn(f64) -> bool) -> f64 {
    let k = (lmax.max(1) * (lmax.max(1) + 1)) as f64;
    let start = (LAMBDA_START / (k * k)).min(bound);
    let (mut fail, mut pass);
    if passes(start) {
        pass = start;
        fail = start;
        for _ in 0..MAX_STEPS {
            fail *= 0.1;
            if !passes(fail) {
                break;
            }
            pass = fail;
        }
        if pass == fail {
            return pass;
        }
    } else {
        fail = start;
        loop {
            let l = LAMBDA_SCAN * fail;
            if l >= bound {
                pass = bound;
                break;
            }
            if passes(l) {
                pass = l;
                break;
            }
            fail = l;
        }
    }
    while pass > fail * (1.0 + BISECT_REL) {
        let mid = (pass * fail).sqrt();
        if passes(mid) {
            pass = mid;
        } else {
            fail = mid;
        }
    }
    pass
}

/// `lambda* = 2 B / c` (see [`auto_window`]): the Laplacian window with this
/// `lambda` provably keeps the target `>= c / 2 > 0`.
fn laplacian_bound(t: &ShCoeffs<f64>) -> f64 {
    let c = t[0] * y00();
    let b: f64 = band_bounds(t)
        .iter()
        .enumerate()
        .skip(1)
        .map(|(l, b)| {
            let k = (l * (l + 1)) as f64;
            b / (k * k)
        })
        .sum();
    let bound = 2.0 * b / c;
    if bound.is_finite() && bound > 0.0 {
        bound
    } else {
        // Only the constant term: any lambda keeps it as it is.
        0.0
    }
}

/// `Y_0^0 = 1 / (2 sqrt(pi))`.
fn y00() -> f64 {
    0.5 / PI.sqrt()
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::sh::closed_form;
    use crate::sh::quadrature::fibonacci_sphere;
    use crate::sh::sphere_minimum::sphere_minimum;
    use crate::test_util::U32;

    /// Accuracy of the `f64` minimum search, relative to the bound `B`
    /// below (its refinement reaches about `1e-15`).
    const SEARCH_TOL: f64 = 1e-12;

    /// Lights whose targets need a window, in `f64`, with that target.
    fn lights() -> Vec<(ShCoeffs<f64>, WindowTarget)> {
        let d = DVec3::new(0.3, -0.5, 0.8).normalize();
        let light = |lmax| closed_form::directional::<f64>(lmax, d, 1.0);
        let sky = |lmax| closed_form::constant::<f64>(lmax, 0.05);
        vec![
            (light(2), WindowTarget::Irradiance),
            (&light(8) + &sky(8), WindowTarget::Function),
            (
                closed_form::cap::<f64>(5, d, 0.3, 1.0),
                WindowTarget::Function,
            ),
        ]
    }

    #[test]
    fn f32_windows_keep_the_f32_target_non_negative() {
        // Window, irradiance and evaluation all in f32, at 100 000
        // directions: with the rounding allowance of `Rounding` no value is
        // negative (without it, the sun over a sky at lmax 8 dips below 0).
        let dirs: Vec<Vec3> = fibonacci_sphere(100_000)
            .iter()
            .map(|d| d.as_vec3())
            .collect();
        let mut lowest = f64::INFINITY;
        for (f, target) in lights() {
            let f32c = f.map(|c| c as f32);
            let lmax = f.lmax();
            let basis = crate::sh::basis::ShBasis::<f32>::new(lmax);
            let mut y = vec![0.0f32; basis.count()];
            for family in [
                WindowFamily::Hanning,
                WindowFamily::Lanczos,
                WindowFamily::Laplacian,
            ] {
                let auto: AutoWindow<f32> = auto_window(&f32c, family, target).unwrap();
                assert!(auto.min_before < 0.0 && auto.window != Window::None);
                let g = auto.window.apply(&f32c);
                let g = match target {
                    WindowTarget::Function => g,
                    WindowTarget::Irradiance => irradiance(&g),
                };
                let mean = f64::from(g[0]) * y00();
                for d in &dirs {
                    let v = g.eval_with(&basis, *d, &mut y);
                    assert!(
                        v >= 0.0,
                        "lmax {lmax} {target:?} {:?}: {v:e} at {d}",
                        auto.window
                    );
                    lowest = lowest.min(f64::from(v) / mean);
                }
            }
        }
        eprintln!("f32 windowed targets evaluated in f32: lowest {lowest:.3e} of their mean");
    }

    #[test]
    fn f32_minimum_before_is_the_f64_one_to_f32_rounding() {
        // The f32 coefficients' target differs from the f64 one by at most
        // U32 B everywhere (B = sum_l sqrt((2l+1)/(4 pi)) |t_l| bounds
        // sum_i |t_i Y_i|; the irradiance factors A_l are applied in f64 to
        // the widened coefficients, so they add nothing), so the minima
        // differ by at most that, and the f32 result is rounded once more
        // (U32 |min|). The same holds for the mean in the error case.
        let mut worst = 0.0f64;
        for (f, target) in lights() {
            let t = match target {
                WindowTarget::Function => f.clone(),
                WindowTarget::Irradiance => irradiance(&f),
            };
            let b: f64 = (0..=t.lmax())
                .map(|l| {
                    let norm = t.band(l).iter().map(|v| v * v).sum::<f64>().sqrt();
                    ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * norm
                })
                .sum();
            let a64 = auto_window(&f, WindowFamily::Hanning, target).unwrap();
            let a32 = auto_window(&f.map(|c| c as f32), WindowFamily::Hanning, target).unwrap();
            let err = (f64::from(a32.min_before) - a64.min_before).abs();
            let allowed = U32 * (b + a64.min_before.abs()) + SEARCH_TOL * b;
            assert!(
                err <= allowed,
                "{target:?}: {} vs {}",
                a32.min_before,
                a64.min_before
            );
            worst = worst.max(err / (U32 * b));
        }
        let mut f = closed_form::directional::<f64>(3, DVec3::Z, 1.0);
        f[0] = -0.1;
        let e64 = auto_window(&f, WindowFamily::Hanning, WindowTarget::Function).unwrap_err();
        let e32 = auto_window(
            &f.map(|c| c as f32),
            WindowFamily::Hanning,
            WindowTarget::Function,
        )
        .unwrap_err();
        let (
            AutoWindowError::NonPositiveMean { mean: m64, .. },
            AutoWindowError::NonPositiveMean {
                mean: m32, argmin, ..
            },
        ) = (e64, e32);
        assert!((argmin.length() - 1.0).abs() < 1e-6, "{argmin}");
        assert!(
            (f64::from(m32) - m64).abs() <= 2.0 * U32 * m64.abs(),
            "{m32} vs {m64}"
        );
        eprintln!("f32 vs f64 auto_window min_before: worst {worst:.3} U32 B");
    }

    #[test]
    fn laplacian_bound_keeps_the_constant_half() {
        let t = ShCoeffs::from_vec(crate::sh::basis::sh_eval(
            6,
            glam::DVec3::new(0.2, 0.5, -0.7).normalize(),
        ))
        .unwrap();
        let lam = laplacian_bound(&t);
        let g = Window::Laplacian { lambda: lam }.apply(&t);
        assert!(sphere_minimum(&g).0 >= 0.5 * t[0] * y00() - 1e-15);
    }
}

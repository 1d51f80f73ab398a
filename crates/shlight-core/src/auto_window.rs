//! [`auto_window`]: the weakest window of a family that makes a
//! reconstruction, or the irradiance computed from it
//! ([`WindowTarget::Irradiance`]), non-negative everywhere on the sphere, at
//! any `lmax`. Filament's `cmgen` has an automatic window for the same
//! purpose, but only for 3 bands (`lmax` 2); this one works to `lmax` 32 and
//! beyond. It rests on [`crate::sphere_minimum()`], a dense-then-local global
//! minimum search.
//!
//! Conventions (real orthonormal SH, Condon-Shortley phase, flat index
//! `l*(l+1)+m`) are those of the crate root.

use core::f64::consts::PI;
use core::fmt;

use glam::DVec3;

use crate::ShCoeffs;
use crate::sphere_minimum::{Minimiser, dense_point_count};
use crate::window::{Window, WindowFamily};
use crate::zonal::irradiance;

/// Which function [`auto_window`] must keep non-negative.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WindowTarget {
    /// The windowed expansion itself, `sum w_l f_l^m Y_l^m` (e.g. radiance
    /// shown as a background).
    Function,
    /// The irradiance of the windowed radiance,
    /// `E = sum A_l w_l f_l^m Y_l^m` ([`crate::irradiance`], Ramamoorthi &
    /// Hanrahan 2001): what a renderer shows on a diffuse surface.
    Irradiance,
}

/// The result of [`auto_window`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoWindow {
    /// The weakest window of the family whose target is non-negative
    /// everywhere (with the margin of [`AUTO_WINDOW_MARGIN`]), or
    /// [`Window::None`] when the target already is non-negative.
    pub window: Window,
    /// Minimum of the unwindowed target over the sphere ([`sphere_minimum`](crate::sphere_minimum::sphere_minimum)).
    pub min_before: f64,
    /// Minimum of the windowed target over the sphere: `>=` the margin when a
    /// window was chosen, `min_before` when none was.
    pub min_after: f64,
    /// Where the unwindowed target takes `min_before` (a unit vector).
    pub argmin_before: DVec3,
}

/// Why [`auto_window`] found no window.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum AutoWindowError {
    /// The target's constant term is `<= 0` while the target is negative
    /// somewhere. Every window keeps the constant term and, as windows get
    /// stronger, tends to it; a function whose mean is `<= 0` and which is not
    /// identically zero is negative somewhere, so no window can help.
    NonPositiveMean {
        /// The mean of the target over the sphere, `t_0^0 Y_0^0`.
        mean: f64,
        /// Minimum of the target over the sphere.
        min: f64,
        /// Where the target takes `min`.
        argmin: DVec3,
    },
}

impl fmt::Display for AutoWindowError {
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

impl std::error::Error for AutoWindowError {}

/// Relative safety margin of [`auto_window`]: a window is accepted when the
/// minimum of the windowed target is `>= AUTO_WINDOW_MARGIN * |t_0^0| Y_0^0`,
/// i.e. `1e-9` times the target's mean over the sphere.
///
/// [`sphere_minimum`](crate::sphere_minimum::sphere_minimum) returns the value at a point it found, which can sit
/// above the true minimum by the accuracy of its local refinement (rounding,
/// about `1e-15` relative). Asking for a small positive minimum rather than
/// `>= 0` makes an independent dense check of the chosen window see no
/// negative value, at the cost of a window stronger than the exact boundary
/// by a negligible amount.
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
/// 1. The target's minimum is found by [`sphere_minimum`](crate::sphere_minimum::sphere_minimum). If it is `>= 0`
///    the result is [`Window::None`].
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
/// |t_0^0| Y_0^0` (see [`AUTO_WINDOW_MARGIN`]); a test that fails stops at
/// the first value found below the margin. A window is therefore found
/// whenever the constant term is positive.
///
/// For RGB, window each channel with its own result, or choose one window
/// on one channel (e.g. luminance) and check the others with
/// [`sphere_minimum`](crate::sphere_minimum::sphere_minimum): since feasible parameters need not form an
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
/// use shlight_core::auto_window::{WindowTarget, auto_window};
/// use shlight_core::sphere_minimum::sphere_minimum;
/// use shlight_core::window::WindowFamily;
/// use shlight_core::{ShCoeffs, Window, irradiance};
/// // A directional light from +Z: its 9-term irradiance dips to -19/480 at cos t = -8/15.
/// let light = ShCoeffs::from_vec(shlight_core::sh_eval(2, glam::DVec3::new(0.0, 0.0, 1.0))).unwrap();
/// let auto = auto_window(&light, WindowFamily::Hanning, WindowTarget::Irradiance).unwrap();
/// assert!((auto.min_before + 19.0 / 480.0).abs() < 1e-12);
/// let Window::Hanning { w } = auto.window else { panic!() };
/// assert!(w > 1.0 && w < 3.0);
/// assert!(sphere_minimum(&irradiance(&auto.window.apply(&light))).0 >= 0.0);
/// ```
///
/// # Errors
/// [`AutoWindowError::NonPositiveMean`] when the target is negative somewhere
/// and its constant term is `<= 0`.
pub fn auto_window(
    f: &ShCoeffs<f64>,
    family: WindowFamily,
    target: WindowTarget,
) -> Result<AutoWindow, AutoWindowError> {
    let t = match target {
        WindowTarget::Function => f.clone(),
        WindowTarget::Irradiance => irradiance(f),
    };
    let lmax = t.lmax();
    let n = dense_point_count(lmax);
    let search = Minimiser::new(&t, n);
    let (min_before, argmin_before) = search.minimum(&vec![1.0; lmax + 1]);
    if min_before >= 0.0 {
        return Ok(AutoWindow {
            window: Window::None,
            min_before,
            min_after: min_before,
            argmin_before,
        });
    }
    let mean = t[0] * y00();
    if t[0].is_nan() || t[0] <= 0.0 {
        return Err(AutoWindowError::NonPositiveMean {
            mean,
            min: min_before,
            argmin: argmin_before,
        });
    }
    let margin = AUTO_WINDOW_MARGIN * mean;
    let min_of = |m: &Minimiser, p: f64| m.minimum(&family.window(p).factors(lmax)).0;
    let passes = |p: f64| {
        let factors = family.window(p).factors(lmax);
        search.minimum_until(&factors, margin).0 >= margin
    };

    let lambda_bound = laplacian_bound(&t);
    let mut p = match family {
        WindowFamily::Hanning | WindowFamily::Lanczos => weakest_width(lmax, passes),
        WindowFamily::Laplacian => weakest_lambda(lmax, lambda_bound, passes),
    };

    // Verify on an independent, denser set; step stronger if that fails.
    let check = Minimiser::new(&t, 2 * n + 1);
    for _ in 0..MAX_STEPS {
        let min_after = min_of(&search, p).min(min_of(&check, p));
        let certain = match family {
            WindowFamily::Hanning | WindowFamily::Lanczos => p <= 1.0,
            WindowFamily::Laplacian => p >= lambda_bound,
        };
        if min_after >= margin || certain {
            return Ok(AutoWindow {
                window: family.window(p),
                min_before,
                min_after,
                argmin_before,
            });
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
    Ok(AutoWindow {
        window: family.window(p),
        min_before,
        min_after: min_of(&check, p),
        argmin_before,
    })
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
    let b: f64 = (1..=t.lmax())
        .map(|l| {
            let norm = t.band(l).iter().map(|v| v * v).sum::<f64>().sqrt();
            let k = (l * (l + 1)) as f64;
            ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * norm / (k * k)
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
    use super::*;
    use crate::sphere_minimum::sphere_minimum;

    #[test]
    fn laplacian_bound_keeps_the_constant_half() {
        let t = ShCoeffs::from_vec(crate::sh_eval(
            6,
            glam::DVec3::new(0.2, 0.5, -0.7).normalize(),
        ))
        .unwrap();
        let lam = laplacian_bound(&t);
        let g = Window::Laplacian { lambda: lam }.apply(&t);
        assert!(sphere_minimum(&g).0 >= 0.5 * t[0] * y00() - 1e-15);
    }
}

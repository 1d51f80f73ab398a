//! Windowing SH expansions against ringing, and an automatic window that
//! makes a reconstruction non-negative on the whole sphere.
//!
//! A truncated SH expansion of a function with a sharp feature (a sun, a
//! window frame, the kink of the clamped cosine) rings: it overshoots and goes
//! negative away from the feature. The remedy in Sloan 2008, "Stupid
//! Spherical Harmonics (SH) Tricks", section "Windowing", is to multiply each
//! degree `l` by a factor `w_l` that falls from 1 at `l = 0` towards 0 at the
//! highest degree:
//!
//! ```text
//! f'_l^m = w_l f_l^m                                   (a zonal convolution)
//! Hanning:   w_l = (1 + cos(pi l / w)) / 2   l < w,   0 for l >= w
//! Lanczos:   w_l = sinc(pi l / w) = sin(pi l / w) / (pi l / w)   l < w,   0 for l >= w
//! Laplacian: w_l = 1 / (1 + lambda l^2 (l+1)^2)
//! ```
//!
//! The Laplacian-penalised form is the minimiser of
//! `int (f' - f)^2 + lambda int (Laplacian f')^2` over the sphere (the SH
//! are eigenfunctions of the Laplacian with eigenvalue `-l(l+1)`), also from
//! Sloan 2008. Sloan suggests `w` somewhat past `lmax` for Hanning and
//! Lanczos; here `w` is any positive real, and `w <= 1` keeps only `l = 0`.
//!
//! Every window keeps `w_0 = 1`, so the mean of the function (its integral)
//! is unchanged, and every factor lies in `[0, 1]`.
//!
//! [`auto_window`] picks the weakest window of a family whose reconstruction
//! (or the irradiance computed from it, [`WindowTarget::Irradiance`]) is
//! non-negative everywhere on the sphere, at any `lmax`. Filament's `cmgen`
//! has an automatic window for the same purpose, but only for 3 bands
//! (`lmax` 2); this one works to `lmax` 32 and beyond. It rests on
//! [`sphere_minimum`], a dense-then-local global minimum search.
//!
//! Conventions (real orthonormal SH, Condon-Shortley phase, flat index
//! `l*(l+1)+m`) are those of the crate root.

use core::f64::consts::PI;
use core::fmt;
use core::str::FromStr;

use crate::quadrature::fibonacci_sphere;
use crate::zonal::irradiance;
use crate::{Real, ShBasis, ShCoeffs, ShValue};

/// A per-degree window `w_l` applied to SH coefficients to reduce ringing
/// (Sloan 2008, "Stupid Spherical Harmonics (SH) Tricks", section
/// "Windowing"). See the [module documentation](self) for the formulas.
///
/// The CLI spelling ([`FromStr`] / [`Display`](fmt::Display), round-trip
/// exact) is `none`, `hanning:W`, `lanczos:W`, `laplacian:LAMBDA`.
///
/// ```
/// use shlight_core::Window;
/// let w: Window = "hanning:6".parse().unwrap();
/// assert_eq!(w, Window::Hanning { w: 6.0 });
/// assert_eq!(w.factor(0), 1.0);
/// assert!((w.factor(3) - 0.5).abs() < 1e-15); // (1 + cos(pi/2)) / 2
/// assert_eq!(w.factor(6), 0.0);
/// assert_eq!(w.to_string(), "hanning:6");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Window {
    /// No window: `w_l = 1`.
    None,
    /// Hanning (raised cosine): `w_l = (1 + cos(pi l / w)) / 2` for `l < w`,
    /// 0 for `l >= w`. Precondition `w > 0`.
    Hanning {
        /// Width: the first degree that is zeroed is the smallest `l >= w`.
        w: f64,
    },
    /// Lanczos sigma factors: `w_l = sinc(pi l / w) = sin(pi l / w) / (pi l / w)`
    /// for `l < w` (1 at `l = 0`), 0 for `l >= w`. Precondition `w > 0`.
    Lanczos {
        /// Width: the first degree that is zeroed is the smallest `l >= w`.
        w: f64,
    },
    /// Laplacian-penalised least squares: `w_l = 1 / (1 + lambda l^2 (l+1)^2)`.
    /// Precondition `lambda >= 0`.
    Laplacian {
        /// Weight of the squared Laplacian in the penalised fit.
        lambda: f64,
    },
}

impl Window {
    /// The factor `w_l` this window multiplies degree `l` by (see the
    /// variants for the formulas; Sloan 2008, "Windowing"). Always 1 at
    /// `l = 0` and in `[0, 1]` for valid parameters.
    #[must_use]
    pub fn factor(&self, l: usize) -> f64 {
        if l == 0 {
            return 1.0;
        }
        let lf = l as f64;
        match *self {
            Window::None => 1.0,
            Window::Hanning { w } => {
                if lf < w {
                    0.5 * (1.0 + (PI * lf / w).cos())
                } else {
                    0.0
                }
            }
            Window::Lanczos { w } => {
                if lf < w {
                    let x = PI * lf / w;
                    x.sin() / x
                } else {
                    0.0
                }
            }
            Window::Laplacian { lambda } => {
                let k = lf * (lf + 1.0);
                1.0 / (1.0 + lambda * k * k)
            }
        }
    }

    /// The factors `w_0 .. w_lmax` (`lmax + 1` values).
    #[must_use]
    pub fn factors(&self, lmax: usize) -> Vec<f64> {
        (0..=lmax).map(|l| self.factor(l)).collect()
    }

    /// The windowed expansion `f'_l^m = w_l f_l^m` (a zonal convolution, so it
    /// commutes with rotation and with [`crate::irradiance`]).
    ///
    /// ```
    /// use shlight_core::{ShCoeffs, Window};
    /// let f = ShCoeffs::<f64>::from_fn(2, |l, _| 1.0 + l as f64);
    /// let g = Window::Laplacian { lambda: 0.25 }.apply(&f);
    /// assert_eq!(g[(0, 0)], 1.0);
    /// assert_eq!(g[(1, -1)], 2.0 / (1.0 + 0.25 * 4.0));
    /// ```
    #[must_use]
    pub fn apply<C: ShValue>(&self, f: &ShCoeffs<C>) -> ShCoeffs<C> {
        if *self == Window::None {
            return f.clone();
        }
        f.scaled_per_band(|l| C::Scalar::from_f64(self.factor(l)))
    }

    /// The family of this window and its parameter (`w` or `lambda`);
    /// `None` for [`Window::None`].
    #[must_use]
    pub fn family(&self) -> Option<(WindowFamily, f64)> {
        match *self {
            Window::None => None,
            Window::Hanning { w } => Some((WindowFamily::Hanning, w)),
            Window::Lanczos { w } => Some((WindowFamily::Lanczos, w)),
            Window::Laplacian { lambda } => Some((WindowFamily::Laplacian, lambda)),
        }
    }
}

impl fmt::Display for Window {
    /// The CLI spelling: `none`, `hanning:W`, `lanczos:W`, `laplacian:LAMBDA`,
    /// with the shortest decimal that parses back to the same `f64`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.family() {
            None => f.write_str("none"),
            Some((family, p)) => write!(f, "{family}:{p}"),
        }
    }
}

impl FromStr for Window {
    type Err = ParseWindowError;

    /// Parses `none`, `hanning:W`, `lanczos:W` or `laplacian:LAMBDA` (family
    /// names ignore ASCII case; surrounding whitespace is ignored). `W` must
    /// be finite and `> 0`, `LAMBDA` finite and `>= 0`.
    ///
    /// `auto` is not a window: it depends on the coefficients. It is refused
    /// with [`ParseWindowErrorKind::Auto`]; a CLI that offers `auto` (or
    /// `auto:FAMILY`) should check for it before parsing, and call
    /// [`auto_window`] with the coefficients, the family (parse it with
    /// [`WindowFamily::from_str`]; Hanning is a good default) and the
    /// [`WindowTarget`] it will display (irradiance for diffuse output), then
    /// use [`AutoWindow::window`].
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let input = s.trim();
        let err = |kind| ParseWindowError {
            input: input.to_owned(),
            kind,
        };
        if input.is_empty() {
            return Err(err(ParseWindowErrorKind::Empty));
        }
        let (name, param) = match input.split_once(':') {
            Some((n, p)) => (n.trim(), Some(p.trim())),
            None => (input, None),
        };
        if name.eq_ignore_ascii_case("auto") {
            return Err(err(ParseWindowErrorKind::Auto));
        }
        if name.eq_ignore_ascii_case("none") {
            return match param {
                None => Ok(Window::None),
                Some(_) => Err(err(ParseWindowErrorKind::UnexpectedParameter)),
            };
        }
        let family: WindowFamily = name.parse().map_err(|e: ParseWindowError| err(e.kind))?;
        let Some(param) = param.filter(|p| !p.is_empty()) else {
            return Err(err(ParseWindowErrorKind::MissingParameter));
        };
        let value: f64 = param
            .parse()
            .map_err(|_| err(ParseWindowErrorKind::BadNumber))?;
        let valid = value.is_finite()
            && match family {
                WindowFamily::Hanning | WindowFamily::Lanczos => value > 0.0,
                WindowFamily::Laplacian => value >= 0.0,
            };
        if !valid {
            return Err(err(ParseWindowErrorKind::OutOfRange));
        }
        Ok(family.window(value))
    }
}

/// Why a window specification did not parse (see [`ParseWindowError::kind`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ParseWindowErrorKind {
    /// The string was empty.
    Empty,
    /// The family name is not `none`, `hanning`, `lanczos` or `laplacian`.
    UnknownFamily,
    /// `hanning`, `lanczos` or `laplacian` without `:VALUE`.
    MissingParameter,
    /// `none` was given a parameter.
    UnexpectedParameter,
    /// The parameter is not a decimal number.
    BadNumber,
    /// The parameter is not finite, or `W <= 0`, or `LAMBDA < 0`.
    OutOfRange,
    /// `auto`: chosen from the coefficients by [`auto_window`], not a fixed window.
    Auto,
}

/// A window specification that did not parse; its `Display` is a message
/// for the user naming the input and what was expected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseWindowError {
    input: String,
    kind: ParseWindowErrorKind,
}

impl ParseWindowError {
    /// What was wrong.
    #[must_use]
    pub fn kind(&self) -> ParseWindowErrorKind {
        self.kind
    }

    /// The (trimmed) input that failed.
    #[must_use]
    pub fn input(&self) -> &str {
        &self.input
    }
}

const EXPECTED: &str = "expected none, hanning:W, lanczos:W or laplacian:LAMBDA";

impl fmt::Display for ParseWindowError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.input;
        match self.kind {
            ParseWindowErrorKind::Empty => write!(f, "empty window specification; {EXPECTED}"),
            ParseWindowErrorKind::UnknownFamily => {
                write!(f, "unknown window '{s}'; {EXPECTED}")
            }
            ParseWindowErrorKind::MissingParameter => write!(
                f,
                "window '{s}' needs a parameter after ':' (e.g. hanning:6, laplacian:0.001)"
            ),
            ParseWindowErrorKind::UnexpectedParameter => {
                write!(f, "window 'none' takes no parameter, got '{s}'")
            }
            ParseWindowErrorKind::BadNumber => {
                write!(f, "the parameter of window '{s}' is not a number")
            }
            ParseWindowErrorKind::OutOfRange => write!(
                f,
                "the parameter of window '{s}' is out of range: \
                 W must be finite and > 0, LAMBDA finite and >= 0"
            ),
            ParseWindowErrorKind::Auto => write!(
                f,
                "'{s}' is not a fixed window: an automatic window is chosen from \
                 the coefficients (shlight_core::window::auto_window)"
            ),
        }
    }
}

impl std::error::Error for ParseWindowError {}

/// A one-parameter family of windows, for [`auto_window`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WindowFamily {
    /// [`Window::Hanning`]: weaker as `w` grows.
    Hanning,
    /// [`Window::Lanczos`]: weaker as `w` grows.
    Lanczos,
    /// [`Window::Laplacian`]: weaker as `lambda` shrinks.
    Laplacian,
}

impl WindowFamily {
    /// The window of this family with parameter `p` (`w` or `lambda`).
    #[must_use]
    pub fn window(self, p: f64) -> Window {
        match self {
            WindowFamily::Hanning => Window::Hanning { w: p },
            WindowFamily::Lanczos => Window::Lanczos { w: p },
            WindowFamily::Laplacian => Window::Laplacian { lambda: p },
        }
    }
}

impl fmt::Display for WindowFamily {
    /// `hanning`, `lanczos` or `laplacian`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            WindowFamily::Hanning => "hanning",
            WindowFamily::Lanczos => "lanczos",
            WindowFamily::Laplacian => "laplacian",
        })
    }
}

impl FromStr for WindowFamily {
    type Err = ParseWindowError;

    /// `hanning`, `lanczos` or `laplacian` (ASCII case ignored).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let name = s.trim();
        [
            WindowFamily::Hanning,
            WindowFamily::Lanczos,
            WindowFamily::Laplacian,
        ]
        .into_iter()
        .find(|f| name.eq_ignore_ascii_case(&f.to_string()))
        .ok_or_else(|| ParseWindowError {
            input: name.to_owned(),
            kind: ParseWindowErrorKind::UnknownFamily,
        })
    }
}

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
    /// Minimum of the unwindowed target over the sphere ([`sphere_minimum`]).
    pub min_before: f64,
    /// Minimum of the windowed target over the sphere: `>=` the margin when a
    /// window was chosen, `min_before` when none was.
    pub min_after: f64,
    /// Where the unwindowed target takes `min_before` (a unit vector).
    pub argmin_before: [f64; 3],
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
        argmin: [f64; 3],
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
/// [`sphere_minimum`] returns the value at a point it found, which can sit
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
/// 1. The target's minimum is found by [`sphere_minimum`]. If it is `>= 0`
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
/// [`sphere_minimum`]: since feasible parameters need not form an
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
/// use shlight_core::window::{WindowFamily, WindowTarget, auto_window, sphere_minimum};
/// use shlight_core::{ShCoeffs, Window, irradiance};
/// // A directional light from +Z: its 9-term irradiance dips to -19/480 at cos t = -8/15.
/// let light = ShCoeffs::from_vec(shlight_core::sh_eval(2, [0.0, 0.0, 1.0])).unwrap();
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

/// Points of the dense Fibonacci set used by [`sphere_minimum`] at `lmax`:
/// `max(4000, 40 (lmax+1)^2)`, about 11 points per wavelength `2 pi / (lmax+1)`
/// along any great circle, so every basin of a degree-`lmax` function holds
/// several points.
#[must_use]
pub fn dense_point_count(lmax: usize) -> usize {
    (40 * (lmax + 1) * (lmax + 1)).max(4000)
}

/// The minimum of `f(d) = sum f_l^m Y_l^m(d)` over the unit sphere and a unit
/// vector where it is taken: `(min, argmin)`.
///
/// 1. Evaluates `f` on [`dense_point_count`]`(lmax)` points of the
///    spherical Fibonacci set ([`crate::quadrature::fibonacci_sphere`]),
///    with one [`ShBasis`] built once ([`ShBasis::eval_batch`] over blocks of
///    points; the refinement below uses [`ShBasis::eval`] and a scratch buffer).
/// 2. Among the 1200 lowest points, takes the 12 lowest that are at least 3
///    point spacings apart (spacing `sqrt(4 pi / n)`), i.e. the lowest
///    distinct basins.
/// 3. Refines each by Newton's method on the sphere: in the exponential
///    chart at the current point, the gradient comes from central differences
///    of step `1e-3` spacings and the Hessian from a stencil 30 times wider;
///    negative or unresolvably small curvatures are replaced by their
///    magnitude or a floor, steps are limited to a trust radius (starting at
///    one spacing) and accepted only if they lower the value by more than its
///    rounding level; it stops when a step is shorter than `1e-11` rad or
///    after 100 iterations. Typical cost: 5 to 30 iterations of 13
///    evaluations each.
///
/// The returned value is `f` evaluated at the returned point, so it is never
/// below the true minimum. It is above it by the refinement accuracy (about
/// `1e-15` relative to the size of `f` in the tests, including the ring
/// minima of zonal functions), unless the global minimum's basin was not
/// among the 12 candidates: a degree-`lmax` function's basins are several
/// spacings wide and so contain points, but more than 12 other basins whose
/// sampled values come within the sampling error of the lowest (of order
/// `|f''| spacing^2`) could crowd it out.
///
/// ```
/// use shlight_core::{ShCoeffs, window::sphere_minimum};
/// let mut f = ShCoeffs::<f64>::zeros(1);
/// f[(1, 0)] = 1.0; // sqrt(3 / (4 pi)) z, lowest at -Z
/// let (min, at) = sphere_minimum(&f);
/// assert!((min + (3.0 / (4.0 * std::f64::consts::PI)).sqrt()).abs() < 1e-12);
/// assert!((at[2] + 1.0).abs() < 1e-9);
/// ```
#[must_use]
pub fn sphere_minimum(f: &ShCoeffs<f64>) -> (f64, [f64; 3]) {
    let m = Minimiser::new(f, dense_point_count(f.lmax()));
    m.minimum(&vec![1.0; f.lmax() + 1])
}

/// Candidates refined per minimum search.
const CANDIDATES: usize = 12;
/// Lowest points of the dense set among which candidates are chosen.
const LOWEST_POINTS: usize = 100 * CANDIDATES;
/// Minimum distance between candidates, in point spacings.
const SEPARATION: f64 = 3.0;
/// Finite-difference step of the local Newton iteration, in point spacings.
const FD_STEP: f64 = 1e-3;
/// Width of the Hessian stencil, in gradient steps `FD_STEP * spacing`.
const HESSIAN_WIDTH: f64 = 30.0;
/// The local iteration stops when its step is shorter than this (radians).
const STOP_STEP: f64 = 1e-11;
/// Newton iterations allowed per candidate.
const MAX_ITERS: usize = 100;
/// Moves must improve by this many ulps of the function's magnitude bound.
const NOISE_ULPS: f64 = 16.0;
/// Points per block of the band sums (one `eval_batch` call each).
const CHUNK: usize = 256;

/// Minimum search for windowed versions `sum_l w_l t_l(d)` of one expansion:
/// the per-degree sums `t_l(d) = sum_m t_l^m Y_l^m(d)` at the dense points
/// are computed once, so trying a window costs `O(n lmax)` plus refinement.
struct Minimiser {
    target: ShCoeffs<f64>,
    points: Vec<[f64; 3]>,
    /// Blocks of `CHUNK` points, degree-major within a block:
    /// `band_sums[b * (lmax+1) * CHUNK + l * CHUNK + k] = t_l(points[b * CHUNK + k])`
    /// (the last block is zero-padded).
    band_sums: Vec<f64>,
    spacing: f64,
}

impl Minimiser {
    fn new(target: &ShCoeffs<f64>, n: usize) -> Self {
        let lmax = target.lmax();
        let basis = ShBasis::<f64>::new(lmax);
        let points = fibonacci_sphere(n);
        let count = basis.count();
        let block = (lmax + 1) * CHUNK;
        let mut band_sums = vec![0.0; n.div_ceil(CHUNK) * block];
        let fill = |y: &mut Vec<f64>, (b, sums): (usize, &mut [f64])| {
            let start = b * CHUNK;
            let len = CHUNK.min(n - start);
            let (mut xs, mut ys, mut zs) = ([0.0; CHUNK], [0.0; CHUNK], [0.0; CHUNK]);
            for (k, p) in points[start..start + len].iter().enumerate() {
                (xs[k], ys[k], zs[k]) = (p[0], p[1], p[2]);
            }
            let y = &mut y[..count * len];
            basis.eval_batch(&xs[..len], &ys[..len], &zs[..len], y);
            for l in 0..=lmax {
                let dst = &mut sums[l * CHUNK..l * CHUNK + len];
                for i in l * l..(l + 1) * (l + 1) {
                    let c = target[i];
                    if c != 0.0 {
                        for (d, v) in dst.iter_mut().zip(&y[i * len..(i + 1) * len]) {
                            *d += c * v;
                        }
                    }
                }
            }
        };
        let scratch = || vec![0.0; count * CHUNK];
        #[cfg(feature = "rayon")]
        {
            use rayon::prelude::*;
            band_sums
                .par_chunks_mut(block)
                .enumerate()
                .for_each_init(scratch, fill);
        }
        #[cfg(not(feature = "rayon"))]
        {
            let mut y = scratch();
            band_sums
                .chunks_mut(block)
                .enumerate()
                .for_each(|item| fill(&mut y, item));
        }
        Self {
            target: target.clone(),
            points,
            band_sums,
            spacing: (4.0 * PI / n as f64).sqrt(),
        }
    }

    /// Minimum of `sum_l factors[l] t_l(d)` over the sphere.
    fn minimum(&self, factors: &[f64]) -> (f64, [f64; 3]) {
        self.minimum_until(factors, f64::NEG_INFINITY)
    }

    /// Like [`Minimiser::minimum`], but returns as soon as a value below
    /// `stop_below` is found (that value and its point; then not necessarily
    /// the minimum). Makes a failing feasibility test cheap.
    fn minimum_until(&self, factors: &[f64], stop_below: f64) -> (f64, [f64; 3]) {
        let n = self.points.len();
        let lmax = self.target.lmax();
        let mut values = vec![0.0; n.div_ceil(CHUNK) * CHUNK];
        for (v, sums) in values
            .chunks_mut(CHUNK)
            .zip(self.band_sums.chunks(CHUNK * (lmax + 1)))
        {
            for (l, &w) in factors.iter().enumerate().take(lmax + 1) {
                if w != 0.0 {
                    for (v, s) in v.iter_mut().zip(&sums[l * CHUNK..(l + 1) * CHUNK]) {
                        *v += w * s;
                    }
                }
            }
        }
        values.truncate(n);
        // The lowest points, in order (a partial sort is enough to find the
        // lowest distinct basins).
        let mut order: Vec<u32> = (0..n as u32).collect();
        let by_value = |a: &u32, b: &u32| values[*a as usize].total_cmp(&values[*b as usize]);
        let lowest = n.min(LOWEST_POINTS);
        if lowest < n {
            order.select_nth_unstable_by(lowest, by_value);
            order.truncate(lowest);
        }
        order.sort_unstable_by(by_value);
        let cos_sep = (SEPARATION * self.spacing).min(PI).cos();
        let mut picked: Vec<usize> = Vec::with_capacity(CANDIDATES);
        for &i in &order {
            let p = self.points[i as usize];
            if picked.iter().all(|&c| dot(self.points[c], p) < cos_sep) {
                picked.push(i as usize);
                if picked.len() == CANDIDATES {
                    break;
                }
            }
        }

        // The windowed expansion, truncated after its last non-zero degree.
        let g = self
            .target
            .scaled_per_band(|l| factors.get(l).copied().unwrap_or(0.0));
        let top = (0..=lmax)
            .rev()
            .find(|&l| g.band(l).iter().any(|&c| c != 0.0))
            .unwrap_or(0);
        let g = g.resized(top);
        let basis = ShBasis::<f64>::new(top);
        // Rounding level of g: |g| <= sum_l |g_l| sqrt((2l+1)/(4 pi)) (addition theorem).
        let bound: f64 = (0..=top)
            .map(|l| {
                let norm = g.band(l).iter().map(|c| c * c).sum::<f64>().sqrt();
                norm * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt()
            })
            .sum();
        let noise = NOISE_ULPS * f64::EPSILON * bound;
        let mut scratch = vec![0.0; basis.count()];
        let mut eval = |d: [f64; 3]| g.eval_with(&basis, d, &mut scratch);
        let mut best = (f64::INFINITY, [0.0, 0.0, 1.0]);
        for &i in &picked {
            let p = self.points[i];
            let (v, q) = refine(
                &mut eval,
                p,
                self.spacing,
                FD_STEP * self.spacing,
                noise,
                stop_below,
            );
            if v < best.0 || best.0.is_nan() {
                best = (v, q);
            }
            if best.0 < stop_below {
                break;
            }
        }
        best
    }
}

/// Local minimisation of `eval` on the sphere from `p`: Newton's method in
/// the exponential chart at the current point, with the gradient and Hessian
/// from central differences of step `h` (8 evaluations), negative or tiny
/// curvatures replaced by their magnitude or a floor (so flat directions such
/// as the ring minimum of a zonal function take short steps), and steps
/// limited to a trust radius that starts at `radius`, doubles after a success
/// and shrinks 4x after a failure. A step is accepted when it lowers the
/// value by more than `noise` (the rounding level). Stops when the step is
/// shorter than [`STOP_STEP`], or early once a value below `stop_below` is seen.
///
/// Returns the lowest value evaluated and its point, so the value is exactly
/// `eval` at the point.
fn refine(
    eval: &mut impl FnMut([f64; 3]) -> f64,
    p: [f64; 3],
    radius: f64,
    h: f64,
    noise: f64,
    stop_below: f64,
) -> (f64, [f64; 3]) {
    let max_radius = 4.0 * radius;
    let mut radius = radius;
    let mut point = p;
    let mut value = eval(p);
    let mut best = (value, point);
    for _ in 0..MAX_ITERS {
        if best.0 < stop_below {
            break;
        }
        let (t1, t2) = tangent_frame(point);
        let mut at = |a: f64, b: f64| {
            let q = exp_map(point, t1, t2, a, b);
            let v = eval(q);
            if v < best.0 {
                best = (v, q);
            }
            v
        };
        // Gradient from a small stencil (it fixes where the iteration stops),
        // Hessian from a wider one (it only sets the rate; the wider stencil
        // resolves small curvatures, e.g. along a nearly flat valley).
        let (fpx, fmx, fpy, fmy) = (at(h, 0.0), at(-h, 0.0), at(0.0, h), at(0.0, -h));
        let g = [(fpx - fmx) / (2.0 * h), (fpy - fmy) / (2.0 * h)];
        let w = HESSIAN_WIDTH * h;
        let (fpx, fmx, fpy, fmy) = (at(w, 0.0), at(-w, 0.0), at(0.0, w), at(0.0, -w));
        let (fpp, fpm, fmp, fmm) = (at(w, w), at(w, -w), at(-w, w), at(-w, -w));
        let hxx = (fpx - 2.0 * value + fmx) / (w * w);
        let hyy = (fpy - 2.0 * value + fmy) / (w * w);
        let hxy = (fpp - fpm - fmp + fmm) / (4.0 * w * w);
        // Eigen-decomposition of the symmetric 2x2 Hessian.
        let half_tr = 0.5 * (hxx + hyy);
        let disc = (0.25 * (hxx - hyy) * (hxx - hyy) + hxy * hxy).sqrt();
        let (l1, l2) = (half_tr + disc, half_tr - disc);
        let phi = 0.5 * (2.0 * hxy).atan2(hxx - hyy);
        let (sp, cp) = phi.sin_cos();
        let (e1, e2) = ([cp, sp], [-sp, cp]);
        // Rounding levels of the differences: a gradient component below
        // `g_noise` gives no direction, a curvature below `c_noise` no scale.
        let g_noise = noise / h;
        let c_noise = 4.0 * noise / (w * w);
        let floor = (1e-9 * l1.abs().max(l2.abs())).max(c_noise) + f64::MIN_POSITIVE;
        let newton = |gi: f64, li: f64| {
            if gi.abs() <= g_noise {
                0.0
            } else {
                -gi / li.abs().max(floor)
            }
        };
        let d1 = newton(g[0] * e1[0] + g[1] * e1[1], l1);
        let d2 = newton(g[0] * e2[0] + g[1] * e2[1], l2);
        let (mut dx, mut dy) = (d1 * e1[0] + d2 * e2[0], d1 * e1[1] + d2 * e2[1]);
        let mut len = dx.hypot(dy);
        if !len.is_finite() {
            break;
        }
        if len > radius {
            (dx, dy) = (dx * radius / len, dy * radius / len);
            len = radius;
        }
        if len < STOP_STEP {
            break;
        }
        let q = exp_map(point, t1, t2, dx, dy);
        let v = eval(q);
        if v < best.0 {
            best = (v, q);
        }
        if v < value - noise {
            (point, value) = (q, v);
            radius = (2.0 * len).max(radius).min(max_radius);
        } else {
            radius = 0.25 * len;
            if radius < STOP_STEP {
                break;
            }
        }
    }
    best
}

/// The point at geodesic offset `(a, b)` from unit `p` in the tangent frame
/// `(t1, t2)`: `cos(r) p + sin(r) (a t1 + b t2) / r`, `r = |(a, b)|`.
fn exp_map(p: [f64; 3], t1: [f64; 3], t2: [f64; 3], a: f64, b: f64) -> [f64; 3] {
    let r = a.hypot(b);
    if r == 0.0 {
        return p;
    }
    let (s, c) = r.sin_cos();
    let (ua, ub) = (s * a / r, s * b / r);
    normalize([
        c * p[0] + ua * t1[0] + ub * t2[0],
        c * p[1] + ua * t1[1] + ub * t2[1],
        c * p[2] + ua * t1[2] + ub * t2[2],
    ])
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let n = dot(v, v).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

/// Two unit vectors spanning the tangent plane at unit `p`.
fn tangent_frame(p: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let a = if p[2].abs() < 0.9 {
        [0.0, 0.0, 1.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let t1 = normalize([
        a[1] * p[2] - a[2] * p[1],
        a[2] * p[0] - a[0] * p[2],
        a[0] * p[1] - a[1] * p[0],
    ]);
    let t2 = [
        p[1] * t1[2] - p[2] * t1[1],
        p[2] * t1[0] - p[0] * t1[2],
        p[0] * t1[1] - p[1] * t1[0],
    ];
    (t1, t2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_frame_is_orthonormal() {
        for p in [
            [0.0, 0.0, 1.0],
            normalize([0.3, -0.5, 0.2]),
            [0.0, -1.0, 0.0],
        ] {
            let (a, b) = tangent_frame(p);
            for (u, v, want) in [
                (a, a, 1.0),
                (b, b, 1.0),
                (a, b, 0.0),
                (a, p, 0.0),
                (b, p, 0.0),
            ] {
                assert!((dot(u, v) - want).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn laplacian_bound_keeps_the_constant_half() {
        let t = ShCoeffs::from_vec(crate::sh_eval(6, normalize([0.2, 0.5, -0.7]))).unwrap();
        let lam = laplacian_bound(&t);
        let g = Window::Laplacian { lambda: lam }.apply(&t);
        assert!(sphere_minimum(&g).0 >= 0.5 * t[0] * y00() - 1e-15);
    }
}

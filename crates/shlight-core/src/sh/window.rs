//! Windowing SH expansions against ringing, and an automatic window that
//! makes a reconstruction non-negative on the whole sphere.

use core::f64::consts::PI;
use core::fmt;
use core::str::FromStr;

use crate::sh::real::Real;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// A per-degree window `w_l` applied to SH coefficients to reduce ringing
/// (Sloan 2008, "Stupid Spherical Harmonics (SH) Tricks", section
/// "Windowing"); the formulas are below.
///
/// The CLI spelling ([`FromStr`] / [`Display`](fmt::Display), round-trip
/// exact) is `none`, `hanning:W`, `lanczos:W`, `laplacian:LAMBDA`.
///
/// ```
/// use shlight_core::sh::Window;
/// let w: Window = "hanning:6".parse().unwrap();
/// assert_eq!(w, Window::Hanning { w: 6.0 });
/// assert_eq!(w.factor(0), 1.0);
/// assert!((w.factor(3) - 0.5).abs() < 1e-15); // (1 + cos(pi/2)) / 2
/// assert_eq!(w.factor(6), 0.0);
/// assert_eq!(w.to_string(), "hanning:6");
/// ```
///
/// A truncated SH expansion of a function with a sharp feature (a sun, a
/// window frame, the kink of the clamped cosine) rings: it overshoots and goes
/// negative away from the feature. The remedy in Sloan 2008, "Stupid
/// Spherical Harmonics (SH) Tricks", section "Windowing", is to multiply each
/// degree `l` by a factor `w_l` that falls from 1 at `l = 0` towards 0 at the
/// highest degree:
///
/// ```text
/// f'_l^m = w_l f_l^m                                   (a zonal convolution)
/// Hanning:   w_l = (1 + cos(pi l / w)) / 2   l < w,   0 for l >= w
/// Lanczos:   w_l = sinc(pi l / w) = sin(pi l / w) / (pi l / w)   l < w,   0 for l >= w
/// Laplacian: w_l = 1 / (1 + lambda l^2 (l+1)^2)
/// ```
///
/// The Laplacian-penalised form is the minimiser of
/// `int (f' - f)^2 + lambda int (Laplacian f')^2` over the sphere (the SH
/// are eigenfunctions of the Laplacian with eigenvalue `-l(l+1)`), also from
/// Sloan 2008. Sloan suggests `w` somewhat past `lmax` for Hanning and
/// Lanczos; here `w` is any positive real, and `w <= 1` keeps only `l = 0`.
///
/// Every window keeps `w_0 = 1`, so the mean of the function (its integral)
/// is unchanged, and every factor lies in `[0, 1]`.
///
/// [`crate::sh::auto_window()`] picks the weakest window of a family whose
/// reconstruction (or its irradiance) is non-negative everywhere on the
/// sphere; it rests on [`crate::sh::sphere_minimum()`], a dense-then-local
/// global minimum search.
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
    /// commutes with rotation and with [`crate::sh::irradiance`]).
    ///
    /// ```
    /// use shlight_core::sh::{ShCoeffs, Window};
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
    /// [`crate::sh::auto_window`] with the coefficients, the family (parse it with
    /// [`WindowFamily::from_str`]; Hanning is a good default) and the
    /// [`crate::sh::WindowTarget`] it will display (irradiance for diffuse output), then
    /// use [`crate::sh::AutoWindow::window`].
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
    /// `auto`: chosen from the coefficients by [`crate::sh::auto_window()`], not a fixed window.
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
                 the coefficients (shlight_core::sh::auto_window)"
            ),
        }
    }
}

impl std::error::Error for ParseWindowError {}

/// A one-parameter family of windows, for [`crate::sh::auto_window()`].
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

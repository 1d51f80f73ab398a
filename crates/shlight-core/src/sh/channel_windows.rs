//! One ringing window per colour channel of RGB coefficients.
//!
//! [`auto_window`] judges one scalar function; an RGB light has three, and
//! the weakest window that makes red non-negative need not suit blue. These
//! helpers choose and apply a window per channel, so that each channel keeps
//! as much of its own detail as its own negativity allows.

use glam::DVec3;

use crate::sh::auto_window::{AutoWindowError, WindowTarget, auto_window};
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::window::{Window, WindowFamily};

/// For each channel `c` of `f` (red, green, blue), the weakest window of
/// `family` whose `target` is non-negative for that channel alone
/// ([`auto_window`] on `f.channel(c)`).
///
/// # Errors
/// [`AutoWindowError`] of the first channel for which no window exists.
pub fn auto_windows(
    f: &ShCoeffs<DVec3>,
    family: WindowFamily,
    target: WindowTarget,
) -> Result<[Window; 3], AutoWindowError> {
    let mut out = [Window::None; 3];
    for (c, w) in out.iter_mut().enumerate() {
        *w = auto_window(&f.channel(c), family, target)?.window;
    }
    Ok(out)
}

/// `f` with channel `c` multiplied by `windows[c]`:
/// `g_l^m[c] = w_c(l) f_l^m[c]` ([`Window::factor`]).
pub fn apply_channel_windows(windows: &[Window; 3], f: &ShCoeffs<DVec3>) -> ShCoeffs<DVec3> {
    if windows.iter().all(|w| *w == windows[0]) {
        return windows[0].apply(f);
    }
    let [r, g, b] = std::array::from_fn(|c| windows[c].apply(&f.channel(c)));
    ShCoeffs::from_channels(&r, &g, &b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::basis::sh_eval;
    use crate::sh::sphere_minimum::sphere_minimum;
    use crate::sh::zonal::irradiance;

    /// Rounding of a handful of products of numbers of order 1.
    const EXACT: f64 = 1e-14;

    #[test]
    fn each_channel_gets_its_own_factors() {
        let f = ShCoeffs::<DVec3>::from_fn(4, |l, m| {
            DVec3::new(1.0 + l as f64, 0.5 - m as f64, 0.25 * (l * l) as f64)
        });
        let windows = [
            Window::None,
            Window::Hanning { w: 3.0 },
            Window::Lanczos { w: 4.0 },
        ];
        let g = apply_channel_windows(&windows, &f);
        for l in 0..=4 {
            for (k, (a, b)) in f.band(l).iter().zip(g.band(l)).enumerate() {
                for c in 0..3 {
                    let want = windows[c].factor(l) * a[c];
                    assert!((b[c] - want).abs() < EXACT, "l {l} m {k} channel {c}");
                }
            }
        }
        // Hanning of width 3 reaches zero at l = 3: green loses bands 3 and 4.
        assert!(g.band(3).iter().chain(g.band(4)).all(|v| v.y.abs() < EXACT));
    }

    #[test]
    fn a_channel_that_needs_no_window_keeps_none() {
        // Red: a directional light from +Z (its 9-term irradiance dips below
        // 0); green: a constant (non-negative as it is); blue: both.
        let light = sh_eval(2, glam::DVec3::Z);
        let f = ShCoeffs::<DVec3>::from_fn(2, |l, m| {
            let d = light[(l as isize * (l as isize + 1) + m) as usize];
            let c = if l == 0 { 1.0 } else { 0.0 };
            DVec3::new(d, c, d + 4.0 * c)
        });
        let w = auto_windows(&f, WindowFamily::Hanning, WindowTarget::Irradiance).unwrap();
        assert_eq!(w[1], Window::None);
        assert!(matches!(w[0], Window::Hanning { .. }), "{w:?}");
        let g = apply_channel_windows(&w, &f);
        for c in 0..3 {
            let (min, _) = sphere_minimum(&irradiance(&g.channel(c)));
            assert!(min >= 0.0, "channel {c}: {min}");
        }
    }

    #[test]
    fn no_window_helps_a_negative_mean() {
        let f = ShCoeffs::<DVec3>::from_fn(1, |l, _| DVec3::splat(if l == 0 { -1.0 } else { 0.3 }));
        assert!(auto_windows(&f, WindowFamily::Hanning, WindowTarget::Function).is_err());
    }
}

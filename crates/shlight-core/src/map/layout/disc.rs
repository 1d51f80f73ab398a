//! The two disc layouts, Debevec's angular map and the mirror ball: the
//! direction of a point of the unit disc, its inverse, and the exact solid
//! angle of a texel (interior texels by a tensor Gauss-Legendre rule with a
//! proven error bound, texels the rim cuts by exact clipping in polar
//! coordinates).

use core::f64::consts::PI;

use glam::DVec3;

use crate::sh::quadrature::gauss_legendre;

/// Gauss-Legendre points per smooth angular piece of a rim texel (see
/// [`DiscRule`]): pieces span at most the texel's angle seen from the disc
/// centre and stay well away from the integrand's poles, so 16 points
/// leave errors far below `1e-16` relative (checked by the tests against
/// an independent radius-first integration).
const POLAR_POINTS: usize = 16;

/// Absolute error allowed per interior texel of the angular map, relative
/// to `π² h²` (the solid angle of a texel at the disc's centre).
const INTERIOR_RELATIVE_ERROR: f64 = 1e-17;

/// Which disc mapping: the two differ only in `direction`, `image_point`
/// and the density `dω/dA`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Disc {
    /// Debevec's angular map (light probe): `θ = π r` from `-Z`.
    Angular,
    /// Orthographic view of a mirror ball from `+Z`: `θ = 2 asin r` from `+Z`.
    MirrorBall,
}

impl Disc {
    /// Map-frame direction of the disc point `(u, v)`, `r = |(u, v)| <= 1`,
    /// `v` up:
    /// angular `(sin(πr) u/r, sin(πr) v/r, -cos(πr))`;
    /// mirror ball `n = (u, v, sqrt(1 - r²))`, `d = (2 n_z u, 2 n_z v, 1 - 2r²)`.
    pub(crate) fn direction(self, u: f64, v: f64) -> DVec3 {
        let r2 = u * u + v * v;
        match self {
            Disc::Angular => {
                let r = r2.sqrt();
                if r == 0.0 {
                    return DVec3::NEG_Z;
                }
                let (s, c) = (PI * r).sin_cos();
                DVec3::new(s * u / r, s * v / r, -c)
            }
            Disc::MirrorBall => {
                let nz = (1.0 - r2).max(0.0).sqrt();
                DVec3::new(2.0 * nz * u, 2.0 * nz * v, 1.0 - 2.0 * r2)
            }
        }
    }

    /// The single map-frame direction of the whole rim `r = 1`: `+Z` for
    /// the angular map, `-Z` for the mirror ball.
    pub(crate) fn pole(self) -> DVec3 {
        match self {
            Disc::Angular => DVec3::Z,
            Disc::MirrorBall => DVec3::NEG_Z,
        }
    }

    /// Disc point `(u, v)` of the map-frame direction `d` (any length),
    /// inverse of [`Disc::direction`]: with `s = |(dx, dy)|`, angular
    /// `r = atan2(s, -dz)/π`, mirror ball `r = sin(atan2(s, dz)/2)`, and
    /// `(u, v) = r (dx, dy)/s`. The pole (`s = 0` on the rim side) has no
    /// azimuth and lands at `(1, 0)`.
    pub(crate) fn image_point(self, d: DVec3) -> (f64, f64) {
        let s = d.x.hypot(d.y);
        let r = match self {
            Disc::Angular => s.atan2(-d.z) / PI,
            Disc::MirrorBall => (0.5 * s.atan2(d.z)).sin(),
        };
        if s > 0.0 {
            (r * d.x / s, r * d.y / s)
        } else {
            (r, 0.0)
        }
    }

    /// The density `w(r) = dω/dA` of solid angle per unit disc area:
    /// angular `π sin(πr)/r` (`π²` at the centre), mirror ball `4`.
    fn density(self, r: f64) -> f64 {
        match self {
            Disc::Angular if r == 0.0 => PI * PI,
            Disc::Angular => PI * (PI * r).sin() / r,
            Disc::MirrorBall => 4.0,
        }
    }

    /// `int_a^b w(r) r dr`: angular `cos(πa) - cos(πb)`, mirror ball
    /// `2 (b² - a²)`, both written as products (no cancellation).
    fn radial(self, a: f64, b: f64) -> f64 {
        match self {
            Disc::Angular => 2.0 * (0.5 * PI * (a + b)).sin() * (0.5 * PI * (b - a)).sin(),
            Disc::MirrorBall => 2.0 * (b - a) * (b + a),
        }
    }
}

/// Quadrature rules for the solid angles of one disc map's texels, built
/// once per map (texel side `h = 2/N` in disc coordinates).
///
/// - **Interior texels** (the whole square inside the disc): the angular
///   map's density `w = π² sinc(π r)` is entire, and every derivative obeys
///   `|∂^k w| <= π^(k+2)` (`sinc(π|x|)` is the average of `exp(iπ ξ.x)` over
///   the unit sphere of `ξ`). The `n x n` Gauss-Legendre rule on a square of
///   side `h` therefore errs by at most
///   `2 (πh)^(2n+2) (n!)^4 / ((2n+1) ((2n)!)^3)`; `n` is the smallest with
///   that below [`INTERIOR_RELATIVE_ERROR`]` π² h²` (3 points at `N = 1024`,
///   4 at `N = 64`). The mirror ball's constant density needs no rule:
///   `4 h²`.
/// - **Rim texels**: `Ω = int dψ int_{ra(ψ)}^{rb(ψ)} w(r) r dr`, the inner
///   integral in closed form ([`Disc::radial`]), `ra, rb` where the ray at
///   angle `ψ` enters and leaves the square clipped to `[0, 1]`. The angle
///   range is cut at the corners, the axes and the points where the circle
///   crosses the square's edges, so the integrand is smooth on each piece,
///   then [`POLAR_POINTS`]-point Gauss-Legendre per piece.
#[derive(Clone, Debug)]
pub(crate) struct DiscRule {
    disc: Disc,
    /// Tensor rule nodes and weights on `[-1, 1]`.
    tensor: Vec<(f64, f64)>,
    /// Polar rule nodes and weights on `[-1, 1]`.
    polar: Vec<(f64, f64)>,
}

impl DiscRule {
    /// Rules for an `n x n` disc map.
    pub(crate) fn new(disc: Disc, n: usize) -> Self {
        let h = 2.0 / n as f64;
        let zip = |(x, w): (Vec<f64>, Vec<f64>)| x.into_iter().zip(w).collect::<Vec<_>>();
        let tensor = match disc {
            Disc::Angular => zip(gauss_legendre(tensor_points(h))),
            Disc::MirrorBall => Vec::new(),
        };
        Self {
            disc,
            tensor,
            polar: zip(gauss_legendre(POLAR_POINTS)),
        }
    }

    /// Solid angle covered by the part of the square `[u0, u1] x [v0, v1]`
    /// (disc coordinates) inside the unit disc.
    pub(crate) fn solid_angle(&self, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        let far = u0.abs().max(u1.abs()).powi(2) + v0.abs().max(v1.abs()).powi(2);
        if far <= 1.0 {
            return match self.disc {
                Disc::MirrorBall => 4.0 * (u1 - u0) * (v1 - v0),
                Disc::Angular => self.interior(u0, u1, v0, v1),
            };
        }
        let (nu, nv) = (0.0f64.clamp(u0, u1), 0.0f64.clamp(v0, v1));
        if nu * nu + nv * nv >= 1.0 {
            return 0.0;
        }
        self.clipped(u0, u1, v0, v1)
    }

    /// Tensor Gauss-Legendre rule of the density over the square.
    fn interior(&self, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        let (cu, hu) = (0.5 * (u0 + u1), 0.5 * (u1 - u0));
        let (cv, hv) = (0.5 * (v0 + v1), 0.5 * (v1 - v0));
        let mut sum = 0.0;
        for &(tv, wv) in &self.tensor {
            let v = cv + hv * tv;
            let mut row = 0.0;
            for &(tu, wu) in &self.tensor {
                let u = cu + hu * tu;
                row += wu * self.disc.density((u * u + v * v).sqrt());
            }
            sum += wv * row;
        }
        sum * hu * hv
    }

    /// Polar integration of a texel that the rim cuts (see the type docs).
    fn clipped(&self, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        use core::f64::consts::{FRAC_PI_2, TAU};
        let angle = |x: f64, y: f64| {
            let a = y.atan2(x);
            if a < 0.0 { a + TAU } else { a }
        };
        let mut cuts = [0.0f64; 17];
        let mut n = 0;
        let mut push = |a: f64| {
            cuts[n] = a;
            n += 1;
        };
        for a in [0.0, FRAC_PI_2, PI, 3.0 * FRAC_PI_2, TAU] {
            push(a);
        }
        for (x, y) in [(u0, v0), (u1, v0), (u1, v1), (u0, v1)] {
            push(angle(x, y));
        }
        // Where the unit circle crosses each edge's line within the edge.
        for x in [u0, u1] {
            if x.abs() < 1.0 {
                let y = (1.0 - x * x).sqrt();
                for y in [y, -y] {
                    if (v0..=v1).contains(&y) {
                        push(angle(x, y));
                    }
                }
            }
        }
        for y in [v0, v1] {
            if y.abs() < 1.0 {
                let x = (1.0 - y * y).sqrt();
                for x in [x, -x] {
                    if (u0..=u1).contains(&x) {
                        push(angle(x, y));
                    }
                }
            }
        }
        let cuts = &mut cuts[..n];
        cuts.sort_unstable_by(f64::total_cmp);
        let mut total = 0.0;
        for pair in cuts.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            if b <= a || ray_segment(u0, u1, v0, v1, 0.5 * (a + b)).is_none() {
                continue;
            }
            let (c, half) = (0.5 * (a + b), 0.5 * (b - a));
            let mut piece = 0.0;
            for &(t, w) in &self.polar {
                if let Some((ra, rb)) = ray_segment(u0, u1, v0, v1, c + half * t) {
                    piece += w * self.disc.radial(ra, rb);
                }
            }
            total += piece * half;
        }
        total
    }
}

/// The part `[ra, rb]` of the ray `r (cos ψ, sin ψ)`, `0 <= r <= 1`, inside
/// the square `[u0, u1] x [v0, v1]` (slab clipping), or `None` if empty.
fn ray_segment(u0: f64, u1: f64, v0: f64, v1: f64, psi: f64) -> Option<(f64, f64)> {
    let (s, c) = psi.sin_cos();
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for (dir, a, b) in [(c, u0, u1), (s, v0, v1)] {
        if dir > 0.0 {
            lo = lo.max(a / dir);
            hi = hi.min(b / dir);
        } else if dir < 0.0 {
            lo = lo.max(b / dir);
            hi = hi.min(a / dir);
        } else if a > 0.0 || b < 0.0 {
            return None;
        }
    }
    (hi > lo).then_some((lo, hi))
}

/// Points per axis of the interior tensor rule for texel side `h` (see
/// [`DiscRule`]).
fn tensor_points(h: f64) -> usize {
    let x = PI * h;
    let target = INTERIOR_RELATIVE_ERROR * x * x;
    // n = 1: 2 x^4 (1!)^4 / (3 (2!)^3) = x^4 / 12.
    let mut bound = x.powi(4) / 12.0;
    let mut n = 1usize;
    while bound > target && n < 64 {
        let m = n as f64;
        bound *= x * x * (m + 1.0).powi(4) * (2.0 * m + 1.0)
            / ((2.0 * m + 3.0) * ((2.0 * m + 1.0) * (2.0 * m + 2.0)).powi(3));
        n += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tensor_points_grow_with_texel_size() {
        assert_eq!(tensor_points(2.0 / 1024.0), 3);
        assert_eq!(tensor_points(2.0 / 64.0), 4);
        assert!(tensor_points(2.0 / 3.0) <= 20);
    }

    #[test]
    fn direction_and_image_point_are_inverse() {
        for disc in [Disc::Angular, Disc::MirrorBall] {
            for (u, v) in [
                (0.0, 0.0),
                (0.3, -0.2),
                (-0.7, 0.7),
                (0.999, 0.0),
                (0.0, -0.9999),
            ] {
                let d = disc.direction(u, v);
                assert!((d.length() - 1.0).abs() < 1e-15);
                let (gu, gv) = disc.image_point(d * 2.0);
                assert!(
                    (gu - u).abs() < 1e-12 && (gv - v).abs() < 1e-12,
                    "{disc:?} {u} {v}"
                );
            }
            assert_eq!(disc.image_point(disc.pole()), (1.0, 0.0));
        }
    }

    /// Interior texels by the polar route agree with the tensor rule.
    #[test]
    fn interior_tensor_rule_matches_polar_clipping() {
        for (n, step) in [(3usize, 1usize), (8, 1), (64, 1), (1000, 37)] {
            let rule = DiscRule::new(Disc::Angular, n);
            let mut fine = rule.clone();
            fine.tensor = gauss_legendre(24)
                .0
                .into_iter()
                .zip(gauss_legendre(24).1)
                .collect();
            let h = 2.0 / n as f64;
            let mut checked = 0;
            for j in (0..n).step_by(step) {
                for i in (0..n).step_by(step) {
                    let (u0, v0) = (-1.0 + i as f64 * h, -1.0 + j as f64 * h);
                    let (u1, v1) = (u0 + h, v0 + h);
                    let far = u0.abs().max(u1.abs()).powi(2) + v0.abs().max(v1.abs()).powi(2);
                    if far > 1.0 {
                        continue;
                    }
                    let t = rule.interior(u0, u1, v0, v1);
                    let p = rule.clipped(u0, u1, v0, v1);
                    let exact = fine.interior(u0, u1, v0, v1);
                    // The rule's own bound is 1e-17 pi^2 h^2; rounding adds ~n^2 ulps.
                    assert!(
                        (t - exact).abs() <= 4e-15 * exact,
                        "n {n} ({i},{j}): {t} vs {exact}"
                    );
                    // The polar route loses ~1e-16 r / h relative in rb - ra
                    // (h = 2 / n): measured 2e-13 at n = 1000.
                    assert!(
                        (p - exact).abs() <= 1e-15 * n as f64 * exact,
                        "n {n} ({i},{j}): {p} vs {exact}"
                    );
                    checked += 1;
                }
            }
            assert!(checked > 0);
        }
    }

    #[test]
    fn whole_disc_in_one_texel_is_the_sphere() {
        for disc in [Disc::Angular, Disc::MirrorBall] {
            let rule = DiscRule::new(disc, 1);
            let got = rule.solid_angle(-1.0, 1.0, -1.0, 1.0);
            assert!((got - 4.0 * PI).abs() < 1e-13, "{disc:?}: {got}");
        }
    }
}

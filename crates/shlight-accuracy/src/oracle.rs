//! Analytic lights whose irradiance is known in closed form: the oracles.
//!
//! Each [`Oracle`] gives, independently of the projection code it checks:
//!
//! - its radiance `L(d)` ([`Oracle::radiance`]), to render it as a map;
//! - its exact irradiance `E(n) = ∫ L(ω) max(n·ω, 0) dω`
//!   ([`Oracle::irradiance`]), in closed form (formulas from
//!   `sh-reference.md` §4, sources on each [`Shape`]);
//! - its SH irradiance truncated at `lmax` ([`Oracle::truncated`]), the best
//!   any projection can do at that `lmax`, so that truncation error
//!   (`truncated - exact`) and projection error (`projected - truncated`)
//!   are measured apart.
//!
//! For the zonal oracles (everything but the polygon) the truncation is
//! the closed-form series of the addition theorem,
//!
//! ```text
//! E_lmax(n) = Σ_{l ≤ lmax} A_l z_l sqrt((2l+1)/(4π)) P_l(a · n)
//! ```
//!
//! with the light's zonal coefficients `z_l` about its axis `a` and the
//! clamped-cosine eigenvalues `A_l`; every term is bounded by
//! `|A_l z_l| sqrt((2l+1)/(4π))` (`|P_l| ≤ 1`), so the tail past `lmax`
//! bounds the truncation error ([`Oracle::truncation_bound`]). `z_l` and
//! `A_l` come from `shlight_core::sh` (`cap_zonal`,
//! `clamped_cosine_eigenvalue`), which the tests of this crate check
//! against numerical Legendre integration written here. The polygon has no
//! zonal form: its truncation is the projection of its closed-form `E` on
//! SH by a Gauss product rule of degree [`POLYGON_RULE_DEGREE`]
//! (`E_l^m = A_l L_l^m` is exactly the SH projection of `E`).

use std::f64::consts::PI;

use glam::DVec3;
use shlight_core::sh;
use shlight_core::sh::{ShCoeffs, cap_zonal, clamped_cosine_eigenvalue};

use crate::lambert::polygon_irradiance;

/// Degree of the Gauss product rule that projects a polygon's closed-form
/// irradiance on SH. `E` of a polygon is continuously differentiable with
/// kinks in its second derivative, so the rule converges like `degree^-3`;
/// measured against degree 1024 the coefficients agree to 3e-8 at this
/// degree.
pub const POLYGON_RULE_DEGREE: usize = 400;

/// Degree up to which [`Oracle::truncation_bound`] sums the tail exactly
/// before estimating the rest from the terms' power-law decay.
const TAIL_TERMS: usize = 1 << 12;

/// The geometry of an analytic light (unit vectors in world axes).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Radiance `L` in every direction: `E = π L` (4a).
    Sphere,
    /// Radiance `L` inside the cap `d · axis ≥ cos(half_angle)`, 0 outside,
    /// `0 < half_angle < π`. `E` by Snyder's formula (1996; Lagarde & de
    /// Rousiers 2014, 4c); `half_angle = π/2` is the uniform hemisphere
    /// `E = π L (1 + n · axis)/2` (4b), and caps larger than a hemisphere
    /// are the sphere minus the opposite cap.
    Cap {
        /// Centre of the cap.
        axis: DVec3,
        /// Half-angle in radians.
        half_angle: f64,
    },
    /// Radiance `L (a + b (axis · d))`, a linear sky gradient, `|b| ≤ a`:
    /// `E = π L a + (2π/3) L b (axis · n)`, exact at lmax 1.
    Gradient {
        /// Direction of increasing radiance (up).
        axis: DVec3,
        /// Mean radiance factor `a`.
        a: f64,
        /// Slope `b`.
        b: f64,
    },
    /// A directional light (a delta) from `dir` with irradiance `L` facing
    /// it: `E = L max(n · dir, 0)` (4e); `z_l = L sqrt((2l+1)/(4π))`, the
    /// delta's own SH (`L_l^m = L Y_l^m(dir)`), not a small-cap limit. It has
    /// no finite radiance and is not rendered.
    Directional {
        /// Direction the light comes from.
        dir: DVec3,
    },
    /// Radiance `L` inside a convex spherical polygon with great-arc edges
    /// (vertices counter-clockwise seen from outside the sphere looking at
    /// the polygon's centre, i.e. right-handed about its centre), `E` by
    /// Lambert's formula clipped to the horizon (Arvo 1995, 4d).
    Polygon {
        /// Unit vertices.
        vertices: Vec<DVec3>,
    },
}

/// A named analytic light of radiance scale `value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Oracle {
    /// Short name used in tables and file names (`cap30-el10`).
    pub name: String,
    /// Geometry.
    pub shape: Shape,
    /// Radiance (irradiance facing a directional light).
    pub value: f64,
}

/// The SH irradiance of an oracle truncated at one `lmax` (see
/// [`Oracle::truncated`]).
#[derive(Clone, Debug)]
pub enum Truncated {
    /// `Σ_l c_l P_l(axis · n)`, `c_l = A_l z_l sqrt((2l+1)/(4π))`.
    Zonal {
        /// Axis of the zonal function.
        axis: DVec3,
        /// `c_l`, `l = 0..=lmax`.
        c: Vec<f64>,
    },
    /// An SH expansion of `E` (the polygon).
    Sh(ShCoeffs<f64>),
}

impl Truncated {
    /// The truncated irradiance at unit normal `n`.
    #[must_use]
    pub fn eval(&self, n: DVec3) -> f64 {
        match self {
            Truncated::Zonal { axis, c } => {
                let p = sh::legendre_polynomials(
                    c.len().saturating_sub(1),
                    axis.dot(n).clamp(-1.0, 1.0),
                );
                c.iter().zip(&p).map(|(c, p)| c * p).sum()
            }
            Truncated::Sh(e) => e.eval(n),
        }
    }
}

impl Oracle {
    /// An oracle named `name`.
    #[must_use]
    pub fn new(name: &str, shape: Shape, value: f64) -> Self {
        Self {
            name: name.to_owned(),
            shape,
            value,
        }
    }

    /// Radiance arriving from unit direction `d` (0 for a directional light,
    /// which has no finite radiance; see [`Oracle::renderable`]).
    #[must_use]
    pub fn radiance(&self, d: DVec3) -> f64 {
        self.value
            * match &self.shape {
                Shape::Sphere => 1.0,
                Shape::Cap { axis, half_angle } => {
                    f64::from(u8::from(d.dot(*axis) >= half_angle.cos()))
                }
                Shape::Gradient { axis, a, b } => a + b * axis.dot(d),
                Shape::Directional { .. } => 0.0,
                Shape::Polygon { vertices } => f64::from(u8::from(inside(vertices, d))),
            }
    }

    /// Whether the light has finite radiance that a map can hold (all but
    /// the directional light).
    #[must_use]
    pub fn renderable(&self) -> bool {
        !matches!(self.shape, Shape::Directional { .. })
    }

    /// Whether the radiance is continuous (smooth), as opposed to having
    /// edges: the sphere and the gradient.
    #[must_use]
    pub fn smooth(&self) -> bool {
        matches!(self.shape, Shape::Sphere | Shape::Gradient { .. })
    }

    /// The degree of a radiance that is a polynomial in the direction
    /// (sphere 0, gradient 1); `None` otherwise.
    #[must_use]
    pub fn radiance_degree(&self) -> Option<usize> {
        match &self.shape {
            Shape::Sphere => Some(0),
            Shape::Gradient { .. } => Some(1),
            _ => None,
        }
    }

    /// The highest degree of a band-limited light (its SH irradiance is
    /// exact from this lmax on), `None` if it is not band-limited. The
    /// hemisphere counts: its even degrees `l ≥ 2` vanish and `A_l` is 0 at
    /// odd `l > 1`, so its irradiance is exact from lmax 1.
    #[must_use]
    pub fn band_limit(&self) -> Option<usize> {
        match &self.shape {
            Shape::Sphere => Some(0),
            Shape::Gradient { .. } => Some(1),
            Shape::Cap { half_angle, .. } if (*half_angle - PI / 2.0).abs() < 1e-15 => Some(1),
            _ => None,
        }
    }

    /// The exact irradiance at unit normal `n`, in closed form.
    #[must_use]
    pub fn irradiance(&self, n: DVec3) -> f64 {
        self.value
            * match &self.shape {
                Shape::Sphere => PI,
                Shape::Cap { axis, half_angle } => cap_irradiance(*half_angle, n.dot(*axis)),
                Shape::Gradient { axis, a, b } => PI * a + 2.0 * PI / 3.0 * b * axis.dot(n),
                Shape::Directional { dir } => n.dot(*dir).max(0.0),
                Shape::Polygon { vertices } => polygon_irradiance(vertices, n),
            }
    }

    /// The zonal coefficients `z_0 .. z_lmax` about the light's axis, and
    /// the axis; `None` for the polygon.
    #[must_use]
    pub fn zonal(&self, lmax: usize) -> Option<(DVec3, Vec<f64>)> {
        let v = self.value;
        let (axis, z) = match &self.shape {
            Shape::Sphere => {
                let mut z = vec![0.0; lmax + 1];
                z[0] = 2.0 * PI.sqrt();
                (DVec3::Z, z)
            }
            Shape::Cap { axis, half_angle } => (*axis, cap_zonal(lmax, *half_angle)),
            Shape::Gradient { axis, a, b } => {
                // ∫ (a + b t) Y_l^0 over the sphere: 2 sqrt(pi) a and b sqrt(4 pi / 3).
                let mut z = vec![0.0; lmax + 1];
                z[0] = 2.0 * PI.sqrt() * a;
                if lmax >= 1 {
                    z[1] = (4.0 * PI / 3.0).sqrt() * b;
                }
                (*axis, z)
            }
            Shape::Directional { dir } => (
                *dir,
                (0..=lmax)
                    .map(|l| ((2 * l + 1) as f64 / (4.0 * PI)).sqrt())
                    .collect(),
            ),
            Shape::Polygon { .. } => return None,
        };
        Some((axis, z.into_iter().map(|z| z * v).collect()))
    }

    /// The exact radiance coefficients to `lmax` (zonal oracles):
    /// `L_l^m = sqrt(4π/(2l+1)) z_l Y_l^m(axis)`.
    #[must_use]
    pub fn coefficients(&self, lmax: usize) -> Option<ShCoeffs<f64>> {
        let (axis, z) = self.zonal(lmax)?;
        Some(sh::zonal_to_sh(&z, axis))
    }

    /// The SH irradiance truncated at `lmax` (module docs).
    #[must_use]
    pub fn truncated(&self, lmax: usize) -> Truncated {
        match self.zonal(lmax) {
            Some((axis, z)) => Truncated::Zonal {
                axis,
                c: (0..=lmax).map(|l| series_term(l, z[l])).collect(),
            },
            None => Truncated::Sh(ShCoeffs::project_fn(lmax, POLYGON_RULE_DEGREE, |n| {
                self.irradiance(n)
            })),
        }
    }

    /// An upper bound of the truncation error `max_n |E_lmax(n) - E(n)|`
    /// of a zonal oracle: `Σ_{l > lmax} |A_l z_l| sqrt((2l+1)/(4π))`, summed
    /// exactly to degree 4096 and the rest estimated from the terms'
    /// power-law decay (`~ l^-q`, `q` measured over the last octave; even
    /// degrees only). `None` for the polygon.
    #[must_use]
    pub fn truncation_bound(&self, lmax: usize) -> Option<f64> {
        if self.band_limit().is_some_and(|b| b <= lmax) {
            return Some(0.0);
        }
        let top = TAIL_TERMS.max(4 * lmax + 4);
        let (_, z) = self.zonal(top)?;
        let term = |l: usize| series_term(l, z[l]).abs();
        let exact: f64 = (lmax + 1..=top).map(term).sum();
        // Estimate the remainder from even degrees near the top.
        let (l1, l2) = (top / 2 - top / 2 % 2, top - top % 2);
        let (t1, t2) = (term(l1), term(l2));
        let rest = if t1 > 0.0 && t2 > 0.0 && t2 < t1 {
            let q = (t1 / t2).ln() / 2f64.ln();
            // Σ over even l > L of t2 (l/L)^-q ≈ t2 L / (2 (q - 1)).
            if q > 1.0 {
                t2 * l2 as f64 / (2.0 * (q - 1.0))
            } else {
                f64::INFINITY
            }
        } else {
            0.0
        };
        Some(exact + rest)
    }

    /// The perimeter of the light's edge (radians): where its radiance
    /// jumps. 0 for smooth lights.
    #[must_use]
    pub fn edge_length(&self) -> f64 {
        match &self.shape {
            Shape::Cap { half_angle, .. } => 2.0 * PI * half_angle.sin(),
            Shape::Polygon { vertices } => (0..vertices.len())
                .map(|i| {
                    let (a, b) = (vertices[i], vertices[(i + 1) % vertices.len()]);
                    a.dot(b).clamp(-1.0, 1.0).acos()
                })
                .sum(),
            _ => 0.0,
        }
    }

    /// Angular distance (radians) from unit direction `d` to the nearest
    /// edge of the light's radiance (a cap's rim, a polygon's edge arcs);
    /// infinite for smooth lights.
    #[must_use]
    pub fn edge_distance(&self, d: DVec3) -> f64 {
        match &self.shape {
            Shape::Cap { axis, half_angle } => {
                (d.dot(*axis).clamp(-1.0, 1.0).acos() - half_angle).abs()
            }
            Shape::Polygon { vertices } => (0..vertices.len())
                .map(|i| arc_distance(vertices[i], vertices[(i + 1) % vertices.len()], d))
                .fold(f64::INFINITY, f64::min),
            _ => f64::INFINITY,
        }
    }

    /// The largest radiance `max |L|` and its largest angular rate of
    /// change `max |∇L|` (per radian).
    #[must_use]
    pub fn radiance_bounds(&self) -> (f64, f64) {
        let v = self.value.abs();
        match &self.shape {
            Shape::Gradient { a, b, .. } => (v * (a.abs() + b.abs()), v * b.abs()),
            Shape::Directional { .. } => (f64::INFINITY, f64::INFINITY),
            _ => (v, 0.0),
        }
    }
}

/// `A_l z_l sqrt((2l+1)/(4π))`, the coefficient of `P_l(a · n)` in the
/// irradiance of a zonal light.
fn series_term(l: usize, z: f64) -> f64 {
    clamped_cosine_eigenvalue(l) * z * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt()
}

/// Irradiance of a unit-radiance cap of half-angle `alpha` whose centre is
/// at angle `t` from the normal (`cos_t = n · axis`), by Snyder's formula:
///
/// ```text
/// cos² t ≥ sin² α:  E = π sin² α max(cos t, 0)
/// otherwise, x = cot α, y = -x cot t, s = sin t sqrt(1 - y²):
///     E = (cos t acos(y) - x s) sin² α + atan(s / x)
/// ```
///
/// The hemisphere (`α = π/2`, where `x = 0`) is `π (1 + cos t)/2`; a cap
/// larger than a hemisphere is `π` minus the opposite cap of `π - α`.
#[must_use]
pub fn cap_irradiance(alpha: f64, cos_t: f64) -> f64 {
    let cos_t = cos_t.clamp(-1.0, 1.0);
    if (alpha - PI / 2.0).abs() < 1e-12 {
        return PI * (1.0 + cos_t) / 2.0;
    }
    if alpha > PI / 2.0 {
        return PI - cap_irradiance(PI - alpha, -cos_t);
    }
    let sin_a = alpha.sin();
    let sin2 = sin_a * sin_a;
    if cos_t * cos_t >= sin2 {
        return PI * sin2 * cos_t.max(0.0);
    }
    let sin_t = (1.0 - cos_t * cos_t).sqrt();
    let x = alpha.cos() / sin_a;
    let y = -x * cos_t / sin_t;
    let s = sin_t * (1.0 - y * y).max(0.0).sqrt();
    (cos_t * y.clamp(-1.0, 1.0).acos() - x * s) * sin2 + (s / x).atan()
}

/// Angular distance from unit `d` to the great-circle arc from `a` to `b`
/// (shorter than a half-turn): to the arc's circle where `d` projects
/// inside the arc, else to the nearer end.
fn arc_distance(a: DVec3, b: DVec3, d: DVec3) -> f64 {
    let c = a.cross(b).normalize();
    let p = d - c * c.dot(d);
    if a.cross(p).dot(c) >= 0.0 && p.cross(b).dot(c) >= 0.0 {
        c.dot(d).clamp(-1.0, 1.0).asin().abs()
    } else {
        let end = |e: DVec3| e.dot(d).clamp(-1.0, 1.0).acos();
        end(a).min(end(b))
    }
}

/// Whether `d` lies inside the convex spherical polygon (right-handed
/// vertices): on the inner side of every edge's great circle.
fn inside(vertices: &[DVec3], d: DVec3) -> bool {
    (0..vertices.len()).all(|i| {
        let (a, b) = (vertices[i], vertices[(i + 1) % vertices.len()]);
        a.cross(b).dot(d) >= 0.0
    })
}

/// Unit vector of `(x, y, z)`.
#[must_use]
pub fn unit(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z).normalize()
}

/// A direction at elevation `el` (radians above the y-up horizon) and
/// azimuth `az` (from +X toward +Z... the y-up map's convention
/// `(cos el cos az, sin el, cos el sin az)`).
#[must_use]
pub fn elevated(el: f64, az: f64) -> DVec3 {
    DVec3::new(el.cos() * az.cos(), el.sin(), el.cos() * az.sin())
}

/// The oracles of the suite: a uniform sphere; the uniform upper hemisphere
/// (about +Y, the y-up map's up, whose edge lies on a row boundary);
/// caps of 10°, 30°, 60° and 120° at several tilts, two of them crossing
/// the map's horizon; a quad crossing the horizon and the rectangle of
/// the reference's anchor; a directional light; a linear sky gradient.
#[must_use]
pub fn suite_oracles() -> Vec<Oracle> {
    let deg = f64::to_radians;
    let cap = |name: &str, a: f64, el: f64, az: f64| {
        Oracle::new(
            name,
            Shape::Cap {
                axis: elevated(deg(el), deg(az)),
                half_angle: deg(a),
            },
            1.0,
        )
    };
    // The anchor's rectangle at z = 1 (x in [-0.5, 0.8], y in [-0.3, 0.6]),
    // right-handed about +z.
    let rect = |x0: f64, x1: f64, y0: f64, y1: f64| {
        vec![
            unit(x0, y0, 1.0),
            unit(x1, y0, 1.0),
            unit(x1, y1, 1.0),
            unit(x0, y1, 1.0),
        ]
    };
    // A quad on the plane x = 1 straddling the y-up horizon (y = 0),
    // right-handed about +x: (y, z) corners mapped to (1, y, z).
    let quad = vec![
        unit(1.0, -0.3, 0.5),
        unit(1.0, -0.3, -0.4),
        unit(1.0, 0.6, -0.4),
        unit(1.0, 0.6, 0.5),
    ];
    vec![
        Oracle::new("sphere", Shape::Sphere, 1.0),
        Oracle::new(
            "hemisphere",
            Shape::Cap {
                axis: DVec3::Y,
                half_angle: PI / 2.0,
            },
            1.0,
        ),
        cap("cap10-el50", 10.0, 50.0, 30.0),
        cap("cap30-el10", 30.0, 10.0, -60.0),
        cap("cap60-el45", 60.0, 45.0, 120.0),
        cap("cap120-el-20", 120.0, -20.0, 200.0),
        Oracle::new(
            "rect",
            Shape::Polygon {
                vertices: rect(-0.5, 0.8, -0.3, 0.6),
            },
            1.0,
        ),
        Oracle::new("quad-horizon", Shape::Polygon { vertices: quad }, 1.0),
        Oracle::new(
            "directional",
            Shape::Directional {
                dir: unit(0.3, 0.8, 0.5),
            },
            1.0,
        ),
        Oracle::new(
            "sky-gradient",
            Shape::Gradient {
                axis: DVec3::Y,
                a: 1.0,
                b: 0.5,
            },
            1.0,
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `∫_lo^1 h(t) P_l(t) dt` by composite Simpson on 20000 panels, for
    /// checking zonal coefficients without the core's quadrature.
    /// Legendre polynomials `P_0(x) .. P_n(x)` by Bonnet's recurrence
    /// `(l+1) P_{l+1} = (2l+1) x P_l - l P_{l-1}`, written here so that the
    /// core's zonal coefficients are checked against an independent copy.
    fn legendre(n: usize, x: f64) -> Vec<f64> {
        let mut p = Vec::with_capacity(n + 1);
        p.push(1.0);
        if n >= 1 {
            p.push(x);
        }
        for l in 1..n {
            let lf = l as f64;
            p.push(((2.0 * lf + 1.0) * x * p[l] - lf * p[l - 1]) / (lf + 1.0));
        }
        p
    }

    fn simpson_legendre(lmax: usize, lo: f64, h: impl Fn(f64) -> f64) -> Vec<f64> {
        let n = 20_000;
        let step = (1.0 - lo) / n as f64;
        let mut out = vec![0.0; lmax + 1];
        for i in 0..=n {
            let t = lo + step * i as f64;
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            let p = legendre(lmax, t);
            for l in 0..=lmax {
                out[l] += w * step / 3.0 * h(t) * p[l];
            }
        }
        out
    }

    #[test]
    fn core_zonal_coefficients_match_independent_integration() {
        // A_l = 2π ∫_0^1 t P_l(t) dt.
        let a = simpson_legendre(20, 0.0, |t| t);
        for l in 0..=20 {
            let got = clamped_cosine_eigenvalue(l);
            assert!((got - 2.0 * PI * a[l]).abs() < 2e-11, "A_{l}");
        }
        // Cap: z_l = 2π sqrt((2l+1)/(4π)) ∫_{cos α}^1 P_l(t) dt.
        for alpha in [0.2f64, 1.0, 2.2] {
            let num = simpson_legendre(20, alpha.cos(), |_| 1.0);
            let z = cap_zonal(20, alpha);
            for l in 0..=20 {
                let want = 2.0 * PI * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * num[l];
                // 2e-11: rounding of 20000 Simpson terms of size ~1.
                assert!(
                    (z[l] - want).abs() < 2e-11,
                    "cap {alpha} l {l}: {} vs {want}",
                    z[l]
                );
            }
        }
    }

    #[test]
    fn cap_formula_matches_the_reference_anchors() {
        let at = |a: f64, t: f64| cap_irradiance(a.to_radians(), t.to_radians().cos());
        assert!((at(30.0, 90.0) - 0.090586).abs() < 5e-7);
        assert!((at(30.0, 100.0) - 0.03545).abs() < 5e-6);
        assert!((at(60.0, 90.0) - 0.614185).abs() < 5e-7);
        assert!((at(60.0, 135.0) - 0.028765).abs() < 5e-7);
        assert!((at(30.0, 0.0) - PI / 4.0).abs() < 1e-15);
    }

    #[test]
    fn cap_truncations_match_the_reference_anchors() {
        let cap = Oracle::new(
            "c",
            Shape::Cap {
                axis: DVec3::Z,
                half_angle: 30f64.to_radians(),
            },
            1.0,
        );
        let t = |deg: f64| {
            let r = f64::to_radians(deg);
            DVec3::new(r.sin(), 0.0, r.cos())
        };
        assert!((cap.truncated(2).eval(t(0.0)) - 0.815700).abs() < 5e-7);
        assert!((cap.truncated(4).eval(t(0.0)) - 0.779832).abs() < 5e-7);
        assert!((cap.truncated(2).eval(t(135.0)) + 0.014095).abs() < 5e-7);
        // The closed-form series and the core's rotated coefficients agree.
        let e = shlight_core::sh::irradiance(&cap.coefficients(6).unwrap());
        for n in shlight_core::sh::fibonacci_sphere(50) {
            let got = cap.truncated(6).eval(n);
            assert!((got - e.eval(n)).abs() < 1e-13);
        }
    }

    /// `∫ L max(n·ω, 0) dω` by a fine Gauss product rule (independent of
    /// the closed forms). An edge across the rule's rings limits it to
    /// about the area of one ring along the edge: measured up to 3.5e-3
    /// (the hemisphere about +Y, whose whole rim cuts the rings about +Z).
    fn numeric_irradiance(o: &Oracle, n: DVec3) -> f64 {
        let q = shlight_core::sh::SphereQuadrature::exact_to_degree(1200);
        q.directions
            .iter()
            .zip(&q.weights)
            .map(|(&d, w)| w * o.radiance(d) * n.dot(d).max(0.0))
            .sum()
    }

    #[test]
    fn closed_forms_match_numerical_integration() {
        for o in suite_oracles().iter().filter(|o| o.renderable()) {
            for n in shlight_core::sh::fibonacci_sphere(6) {
                let (got, want) = (o.irradiance(n), numeric_irradiance(o, n));
                assert!((got - want).abs() < 5e-3, "{}: {got} vs {want}", o.name);
            }
        }
    }

    #[test]
    fn truncation_converges_to_the_closed_form_within_its_bound() {
        for o in suite_oracles() {
            for lmax in [1, 2, 4, 8, 16] {
                let bound = o.truncation_bound(lmax);
                let t = o.truncated(lmax);
                let worst = shlight_core::sh::fibonacci_sphere(300)
                    .into_iter()
                    .map(|n| (t.eval(n) - o.irradiance(n)).abs())
                    .fold(0.0f64, f64::max);
                if let Some(b) = bound {
                    assert!(worst <= b + 1e-12, "{} lmax {lmax}: {worst} > {b}", o.name);
                }
                if o.band_limit().is_some_and(|b| b <= lmax) {
                    assert!(worst < 1e-13, "{} lmax {lmax}: {worst}", o.name);
                }
            }
        }
    }
}

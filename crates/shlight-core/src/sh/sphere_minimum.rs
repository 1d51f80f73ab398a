//! [`sphere_minimum`]: the global minimum of an SH expansion (`f32` or
//! `f64`, searched in `f64`) over the unit sphere by a dense Fibonacci
//! search refined by Newton's method, and the minimiser that
//! [`crate::sh::auto_window()`] reuses for many windows of one expansion.

use core::f64::consts::PI;

use glam::DVec3;

use crate::sh::basis::ShBasis;
use crate::sh::quadrature::fibonacci_sphere;
use crate::sh::real::Real;
use crate::sh::real::dir_from_f64;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// Points of the dense Fibonacci set used by [`sphere_minimum`] at `lmax`:
/// `max(4000, 40 (lmax+1)^2)`, about 11 points per wavelength `2 pi / (lmax+1)`
/// along any great circle, so every basin of a degree-`lmax` function holds
/// several points.
#[must_use]
pub fn dense_point_count(lmax: usize) -> usize {
    (40 * (lmax + 1) * (lmax + 1)).max(4000)
}

/// The minimum of `f(d) = sum f_l^m Y_l^m(d)` over the unit sphere and a unit
/// vector where it is taken: `(min, argmin)`, for scalar coefficients of
/// either precision (`T` is `f32` or `f64`; the direction is a `T::Vec3`,
/// `Vec3` or `DVec3`).
///
/// 1. Evaluates `f` on [`dense_point_count`]`(lmax)` points of the
///    spherical Fibonacci set ([`crate::sh::fibonacci_sphere`]),
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
/// Scalars: the search is in `f64` whatever `T` is. `f32` coefficients are
/// widened exactly, so the search minimises exactly the function they
/// define; the value and the point found are then rounded to `f32` (the
/// value to nearest, so it can sit up to half an `f32` ulp below the true
/// minimum, and `f` evaluated in `f32` at the rounded point differs from it
/// by `f32` evaluation rounding). For `f64` nothing is converted and the
/// result is as described above.
///
/// ```
/// use shlight_core::sh::{ShCoeffs, sphere_minimum};
/// let mut f = ShCoeffs::<f64>::zeros(1);
/// f[(1, 0)] = 1.0; // sqrt(3 / (4 pi)) z, lowest at -Z
/// let (min, at) = sphere_minimum(&f);
/// assert!((min + (3.0 / (4.0 * std::f64::consts::PI)).sqrt()).abs() < 1e-12);
/// assert!((at.z + 1.0).abs() < 1e-9);
///
/// // In f32: an f32 value and a glam::Vec3.
/// let (min32, at32): (f32, glam::Vec3) = sphere_minimum(&f.map(|c| c as f32));
/// assert!((f64::from(min32) - min).abs() < 1e-7 && (at32.z + 1.0).abs() < 1e-6);
/// ```
///
/// # Panics
/// None of its own. Time grows as [`dense_point_count`]`(lmax) (lmax+1)^2`,
/// memory as `dense_point_count(lmax) (lmax+1)`.
#[must_use]
pub fn sphere_minimum<T: Real + ShValue<Scalar = T>>(f: &ShCoeffs<T>) -> (T, T::Vec3) {
    let m = Minimiser::new(f.map(T::to_f64), dense_point_count(f.lmax()));
    let (min, at) = m.minimum(&vec![1.0; f.lmax() + 1]);
    (T::from_f64(min), dir_from_f64::<T>(at))
}

/// The bound `b_l = sqrt((2l+1)/4π) |f_l|` of each degree `l` of `f`
/// (`|f_l|` the Euclidean norm of its `2l+1` coefficients): by
/// Cauchy-Schwarz and the addition theorem,
/// `|sum_m f_l^m Y_l^m(d)| <= b_l` at every unit `d`.
pub(crate) fn band_bounds(f: &ShCoeffs<f64>) -> Vec<f64> {
    f.band_power()
        .iter()
        .enumerate()
        .map(|(l, p)| ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * p.sqrt())
        .collect()
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
pub(crate) struct Minimiser {
    target: ShCoeffs<f64>,
    points: Vec<[f64; 3]>,
    /// Blocks of `CHUNK` points, degree-major within a block:
    /// `band_sums[b * (lmax+1) * CHUNK + l * CHUNK + k] = t_l(points[b * CHUNK + k])`
    /// (the last block is zero-padded).
    band_sums: Vec<f64>,
    spacing: f64,
}

impl Minimiser {
    pub(crate) fn new(target: ShCoeffs<f64>, n: usize) -> Self {
        let lmax = target.lmax();
        let basis = ShBasis::<f64>::new(lmax);
        let points: Vec<[f64; 3]> = fibonacci_sphere(n).iter().map(DVec3::to_array).collect();
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
            target,
            points,
            band_sums,
            spacing: (4.0 * PI / n as f64).sqrt(),
        }
    }

    /// Minimum of `sum_l factors[l] t_l(d)` over the sphere.
    pub(crate) fn minimum(&self, factors: &[f64]) -> (f64, DVec3) {
        self.minimum_until(factors, f64::NEG_INFINITY)
    }

    /// Like [`Minimiser::minimum`], but returns as soon as a value below
    /// `stop_below` is found (that value and its point; then not necessarily
    /// the minimum). Makes a failing feasibility test cheap.
    pub(crate) fn minimum_until(&self, factors: &[f64], stop_below: f64) -> (f64, DVec3) {
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
        // Rounding level of g: |g| <= sum_l b_l.
        let bound: f64 = band_bounds(&g).iter().sum();
        let noise = NOISE_ULPS * f64::EPSILON * bound;
        let mut scratch = vec![0.0; basis.count()];
        let mut eval = |d: [f64; 3]| g.eval_with(&basis, DVec3::from(d), &mut scratch);
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
        (best.0, DVec3::from(best.1))
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

pub(crate) fn normalize(v: [f64; 3]) -> [f64; 3] {
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
    use glam::Vec3;

    use super::*;
    use crate::test_util::{U32, numbers};

    /// Accuracy of the `f64` search, relative to [`bound`] (the doc's
    /// `1e-15`-level refinement, with room).
    const SEARCH_TOL: f64 = 1e-12;

    /// Rounding of evaluating a degree-`lmax` expansion in `f32`, in units of
    /// `U32` times [`bound`]: summing `(lmax+1)^2` terms rounds by at most
    /// that many `U32` times the sum of their magnitudes (`<= bound`), and
    /// each term's basis value, coefficient product and rounded direction
    /// add a few more, growing with the degree (`4 (lmax+1) + 8`).
    fn f32_eval_ulps(lmax: usize) -> f64 {
        ((lmax + 1) * (lmax + 1) + 4 * (lmax + 1) + 8) as f64
    }

    /// `sum_l k_l sqrt((2l+1)/(4 pi)) |f_l|`: with `k_l = 1` a bound on
    /// `sum_i |f_i Y_i(d)|` at every `d` (addition theorem and
    /// Cauchy-Schwarz), hence on `|f|`; with `k_l = sqrt(l(l+1))` on the
    /// gradient's size, with `k_l = l(l+1)` on second derivatives along
    /// great circles.
    fn bound(f: &ShCoeffs<f64>, k: impl Fn(f64) -> f64) -> f64 {
        (0..=f.lmax())
            .map(|l| {
                let norm = f.band(l).iter().map(|c| c * c).sum::<f64>().sqrt();
                let lf = l as f64;
                k(lf) * ((2.0 * lf + 1.0) / (4.0 * PI)).sqrt() * norm
            })
            .sum()
    }

    /// Scalar coefficients in `[-0.5, 0.5)` plus `offset` on the constant.
    fn random(lmax: usize, seed: u64, offset: f64) -> ShCoeffs<f64> {
        let mut next = numbers(seed);
        let mut f = ShCoeffs::from_fn(lmax, |_, _| next());
        f[0] += offset;
        f
    }

    /// Test functions: random ones and a rotated lmax-2 irradiance ring
    /// (a directional light's, minimum on a circle).
    fn cases() -> Vec<ShCoeffs<f64>> {
        let d = DVec3::new(0.3, -0.5, 0.8).normalize();
        let light: ShCoeffs<f64> = crate::sh::closed_form::directional(2, d, 1.0);
        vec![
            random(1, 1, 0.0),
            random(2, 2, 0.3),
            random(6, 3, 1.0),
            random(9, 4, -0.5),
            crate::sh::zonal::irradiance(&light),
        ]
    }

    #[test]
    fn f32_minimum_is_the_f64_one_to_f32_rounding() {
        // The f32 coefficients' function differs from the f64 one by at most
        // U32 bound(f) everywhere, so the minima differ by at most that; the
        // f32 result is rounded once more (U32 |min|). The f32 argmin is
        // rounded too (each component by U32 |d_j|, moving f by at most
        // sqrt(3) U32 times the gradient bound).
        let mut worst = (0.0f64, 0.0f64);
        for f in cases() {
            let lmax = f.lmax();
            let b = bound(&f, |_| 1.0);
            let b1 = bound(&f, |l| (l * (l + 1.0)).sqrt());
            let (min64, _) = sphere_minimum(&f);
            let (min32, at32) = sphere_minimum(&f.map(|c| c as f32));
            let err = (f64::from(min32) - min64).abs();
            let allowed = U32 * (b + min64.abs()) + SEARCH_TOL * b;
            assert!(
                err <= allowed,
                "lmax {lmax}: f32 min {min32} vs f64 {min64}"
            );
            // The f32 argmin is a minimiser of the f64 function too.
            let at = at32.as_dvec3().normalize();
            let excess = f.eval(at) - min64;
            let allowed_at = U32 * (2.0 * b + 3f64.sqrt() * b1) + SEARCH_TOL * b;
            assert!(
                excess <= allowed_at,
                "lmax {lmax}: f at the f32 argmin {at} is {excess:e} above the minimum"
            );
            worst = (
                worst.0.max(err / (U32 * b)),
                worst.1.max(excess / (U32 * b)),
            );
        }
        eprintln!(
            "f32 vs f64 sphere_minimum: value {:.3}, at the f32 argmin {:.3} U32 bound(f)",
            worst.0, worst.1
        );
    }

    #[test]
    fn f32_minimum_matches_a_dense_f32_scan() {
        // A latitude-longitude grid of 600 x 1200 points, each evaluated in
        // f32: no point may be lower than the result (beyond f32 evaluation
        // rounding), the result must be attained at its argmin, and the
        // grid's lowest point must be within its resolution of the result
        // (every direction is within h = pi/600 of a grid point, where f is
        // at most h^2/2 times the second-derivative bound above its value).
        let (rows, cols) = (600, 1200);
        let h = PI / rows as f64;
        let mut worst = 0.0f64;
        for f in cases() {
            let lmax = f.lmax();
            let f32c = f.map(|c| c as f32);
            let basis = ShBasis::<f32>::new(lmax);
            let mut y = vec![0.0f32; basis.count()];
            let mut scan = f32::INFINITY;
            for i in 0..rows {
                let t = (i as f64 + 0.5) * h;
                for j in 0..cols {
                    let p = (j as f64 + 0.5) * 2.0 * PI / cols as f64;
                    let d = DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
                    scan = scan.min(f32c.eval_with(&basis, d.as_vec3(), &mut y));
                }
            }
            let (min, at): (f32, Vec3) = sphere_minimum(&f32c);
            let b = bound(&f, |_| 1.0);
            let rounding = U32 * f32_eval_ulps(lmax) * b;
            let resolution = 0.5 * h * h * bound(&f, |l| l * (l + 1.0));
            let (min, scan) = (f64::from(min), f64::from(scan));
            assert!(
                min <= scan + rounding,
                "lmax {lmax}: {min} above the scan's {scan}"
            );
            assert!(
                scan <= min + resolution + rounding,
                "lmax {lmax}: scan {scan} vs {min}"
            );
            let attained = f64::from(f32c.eval_with(&basis, at, &mut y));
            assert!(
                (attained - min).abs() <= rounding,
                "lmax {lmax}: f(argmin) {attained} vs {min}"
            );
            worst = worst.max((min - scan).max(0.0) / (U32 * b));
        }
        eprintln!("f32 sphere_minimum above the f32 scan by at most {worst:.3} U32 bound(f)");
    }

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
}

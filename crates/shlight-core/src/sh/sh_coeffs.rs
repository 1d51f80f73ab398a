//! [`ShCoeffs`]: an SH expansion up to some `lmax`, of scalars or RGB.

use core::ops::{Add, AddAssign, Index, IndexMut, Mul, Neg, Sub};
use glam::{DVec3, Vec3};

use crate::sh::basis::ShBasis;
use crate::sh::index::{lmax_from_count, sh_count, sh_index};
use crate::sh::quadrature::SphereQuadrature;
use crate::sh::real::Real;
use crate::sh::real::dir_from_f64;
use crate::sh::sh_value::ShValue;

/// The coefficients `f_l^m`, `l <= lmax`, of a function
/// `f(d) = sum_{l,m} f_l^m Y_l^m(d)` in shlight's real orthonormal basis
/// (Condon-Shortley phase included, flat index `l*(l+1)+m`).
///
/// `C` is the value type: `f32`/`f64` for one channel, `glam::Vec3`/`DVec3`
/// for linear RGB. Because the basis is orthonormal, the coefficients of a
/// sum are sums of coefficients, `dot` is the integral of a product over
/// the sphere, and `band_power` is the energy per degree.
///
/// ```
/// use shlight_core::sh::ShCoeffs;
/// use glam::DVec3;
/// let mut sh = ShCoeffs::<DVec3>::zeros(2);
/// sh[(0, 0)] = DVec3::splat(2.0 * std::f64::consts::PI.sqrt()); // constant radiance 1
/// let v = sh.eval(DVec3::new(0.0, 1.0, 0.0));
/// assert!((v - DVec3::ONE).abs().max_element() < 1e-14);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ShCoeffs<C> {
    lmax: usize,
    coeffs: Vec<C>,
}

/// Scalar type of the coefficients' channels.
type S<C> = <C as ShValue>::Scalar;

impl<C: ShValue> ShCoeffs<C> {
    /// All `(lmax+1)^2` coefficients zero.
    #[must_use]
    pub fn zeros(lmax: usize) -> Self {
        Self {
            lmax,
            coeffs: vec![C::ZERO; sh_count(lmax)],
        }
    }

    /// Wraps a vector of coefficients in flat-index order. Returns `None`
    /// unless its length is a perfect square `(lmax+1)^2`.
    #[must_use]
    pub fn from_vec(coeffs: Vec<C>) -> Option<Self> {
        let lmax = lmax_from_count(coeffs.len())?;
        Some(Self { lmax, coeffs })
    }

    /// Builds coefficients from `f(l, m)` for every `l <= lmax`.
    #[must_use]
    pub fn from_fn(lmax: usize, mut f: impl FnMut(usize, isize) -> C) -> Self {
        let mut out = Self::zeros(lmax);
        for l in 0..=lmax {
            for m in -(l as isize)..=l as isize {
                out.coeffs[sh_index(l, m)] = f(l, m);
            }
        }
        out
    }

    /// The highest degree held.
    #[must_use]
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// Number of coefficients, `(lmax+1)^2`.
    #[must_use]
    pub fn len(&self) -> usize {
        self.coeffs.len()
    }

    /// Never true: an expansion holds at least the constant term.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The coefficients in flat-index order.
    #[must_use]
    pub fn as_slice(&self) -> &[C] {
        &self.coeffs
    }

    /// The coefficients in flat-index order, mutable.
    pub fn as_mut_slice(&mut self) -> &mut [C] {
        &mut self.coeffs
    }

    /// Consumes the expansion, returning the flat vector.
    #[must_use]
    pub fn into_vec(self) -> Vec<C> {
        self.coeffs
    }

    /// The `2l+1` coefficients of degree `l`, `m = -l..=l`. Panics if `l > lmax`.
    #[must_use]
    pub fn band(&self, l: usize) -> &[C] {
        &self.coeffs[l * l..(l + 1) * (l + 1)]
    }

    /// The `2l+1` coefficients of degree `l`, mutable. Panics if `l > lmax`.
    pub fn band_mut(&mut self, l: usize) -> &mut [C] {
        &mut self.coeffs[l * l..(l + 1) * (l + 1)]
    }

    /// A copy truncated or zero-extended to `lmax`.
    #[must_use]
    pub fn resized(&self, lmax: usize) -> Self {
        let mut coeffs = self.coeffs.clone();
        coeffs.resize(sh_count(lmax), C::ZERO);
        Self { lmax, coeffs }
    }

    /// Every coefficient multiplied by `s`.
    #[must_use]
    pub fn scaled(&self, s: S<C>) -> Self {
        self.map(|c| c.scale(s))
    }

    /// Applies `f` to every coefficient.
    #[must_use]
    pub fn map<D: ShValue>(&self, f: impl FnMut(C) -> D) -> ShCoeffs<D> {
        ShCoeffs {
            lmax: self.lmax,
            coeffs: self.coeffs.iter().copied().map(f).collect(),
        }
    }

    /// Multiplies every coefficient of degree `l` by `factor(l)`: the form of
    /// every zonal convolution and window.
    #[must_use]
    pub fn scaled_per_band(&self, mut factor: impl FnMut(usize) -> S<C>) -> Self {
        let mut out = self.clone();
        for l in 0..=self.lmax {
            let f = factor(l);
            for c in out.band_mut(l) {
                *c = c.scale(f);
            }
        }
        out
    }

    /// `sum_i self_i * other_i` per channel: the integral over the sphere of
    /// the product of the two functions (Parseval). Expansions of different
    /// `lmax` are compared on the common degrees.
    #[must_use]
    pub fn dot(&self, other: &Self) -> C {
        let mut acc = C::ZERO;
        for (a, b) in self.coeffs.iter().zip(&other.coeffs) {
            acc += a.mul_elem(*b);
        }
        acc
    }

    /// `sum_i self_i * t_i` with a one-channel `t`: shading with a
    /// transfer vector (e.g. PRT) applied to every channel.
    #[must_use]
    pub fn dot_scalar(&self, t: &[S<C>]) -> C {
        let mut acc = C::ZERO;
        for (a, &b) in self.coeffs.iter().zip(t) {
            acc += a.scale(b);
        }
        acc
    }

    /// Power per degree: `sum_m (f_l^m)^2` per channel, for `l = 0..=lmax`.
    /// Invariant under rotation.
    #[must_use]
    pub fn band_power(&self) -> Vec<C> {
        (0..=self.lmax)
            .map(|l| {
                self.band(l)
                    .iter()
                    .fold(C::ZERO, |acc, c| acc + c.mul_elem(*c))
            })
            .collect()
    }

    /// The function at unit direction `d`: `sum Y_l^m(d) f_l^m`.
    ///
    /// Builds the basis tables each call; use [`ShCoeffs::eval_with`] in loops.
    #[must_use]
    pub fn eval(&self, d: <S<C> as Real>::Vec3) -> C {
        self.eval_with(
            &ShBasis::new(self.lmax),
            d,
            &mut vec![S::<C>::ZERO; self.len()],
        )
    }

    /// The function at unit direction `d`, with a prepared basis (of at
    /// least this `lmax`) and a scratch buffer of `basis.count()` values.
    #[must_use]
    pub fn eval_with(
        &self,
        basis: &ShBasis<S<C>>,
        d: <S<C> as Real>::Vec3,
        scratch: &mut [S<C>],
    ) -> C {
        basis.eval(d, scratch);
        self.dot_scalar(scratch)
    }

    /// Converts between shlight's basis (Condon-Shortley phase included) and
    /// the basis without it (Ramamoorthi-Hanrahan tables, three.js,
    /// MaterialX): every coefficient with odd `|m|` changes sign. The map is
    /// its own inverse, so the same call converts either way.
    #[must_use]
    pub fn toggled_cs_phase(&self) -> Self {
        let mut out = self.clone();
        for l in 0..=self.lmax {
            for m in -(l as isize)..=l as isize {
                if m % 2 != 0 {
                    let c = &mut out.coeffs[sh_index(l, m)];
                    *c = -*c;
                }
            }
        }
        out
    }

    /// Projects `f` onto the basis up to `lmax`:
    /// `f_l^m = sum_k w_k f(d_k) Y_l^m(d_k)`, the integral
    /// `int f(d) Y_l^m(d) dd` by the product quadrature
    /// [`SphereQuadrature::exact_to_degree`]`(max(degree, lmax))`
    /// (Gauss-Legendre in `cos theta` times the uniform rule in `phi`). When
    /// `f` is a spherical polynomial of degree `<= degree - lmax` the result
    /// is exact up to rounding; otherwise larger `degree` gives better
    /// accuracy. Cost, with `n = max(degree, lmax)`: `(n/2 + 1) (n + 1)`
    /// calls of `f`, each with one basis evaluation and `(lmax+1)^2`
    /// multiply-adds per channel.
    ///
    /// Works for every value type (`f32`, `f64`, `Vec3`, `DVec3`); `f`
    /// takes the direction as the glam vector of the scalar (`Vec3` for
    /// `f32`, `DVec3` for `f64`). The nodes, weights, basis and sums are in
    /// `f64` whatever the scalar: for `f32` each node is rounded to a `Vec3`
    /// to call `f`, its values are widened to `f64`, and each sum is rounded
    /// once to `f32` at the end, so the result is the projection of what `f`
    /// returns to within `f32` rounding of the result and of the nodes.
    /// For `f64` nothing is converted.
    ///
    /// # Panics
    /// Not by itself; a panic in `f` propagates. (Memory is `(lmax+1)^2`
    /// sums per channel plus the rule's `O(degree^2)` nodes.)
    #[must_use]
    pub fn project_fn(lmax: usize, degree: usize, f: impl Fn(<S<C> as Real>::Vec3) -> C) -> Self {
        let q = SphereQuadrature::exact_to_degree(degree.max(lmax));
        let basis = ShBasis::<f64>::new(lmax);
        let count = basis.count();
        let mut y = vec![0.0; count];
        // Channel-major sums: `sums[c * count + i]` for coefficient `i`.
        let mut sums = vec![0.0f64; C::CHANNELS * count];
        for (d, &w) in q.directions.iter().zip(&q.weights) {
            let v = f(dir_from_f64::<S<C>>(*d));
            basis.eval(*d, &mut y);
            for (c, sums) in sums.chunks_exact_mut(count).enumerate() {
                let vw = v.channel(c).to_f64() * w;
                for (o, &yi) in sums.iter_mut().zip(&y) {
                    *o += vw * yi;
                }
            }
        }
        let mut out = Self::zeros(lmax);
        for (c, sums) in sums.chunks_exact(count).enumerate() {
            for (o, &s) in out.coeffs.iter_mut().zip(sums) {
                o.set_channel(c, S::<C>::from_f64(s));
            }
        }
        out
    }
}

impl<C: ShValue> Index<usize> for ShCoeffs<C> {
    type Output = C;
    fn index(&self, i: usize) -> &C {
        &self.coeffs[i]
    }
}

impl<C: ShValue> IndexMut<usize> for ShCoeffs<C> {
    fn index_mut(&mut self, i: usize) -> &mut C {
        &mut self.coeffs[i]
    }
}

/// `sh[(l, m)]`: the coefficient of degree `l`, order `m`.
impl<C: ShValue> Index<(usize, isize)> for ShCoeffs<C> {
    type Output = C;
    fn index(&self, (l, m): (usize, isize)) -> &C {
        assert!(
            l <= self.lmax && m.unsigned_abs() <= l,
            "(l, m) = ({l}, {m}) out of range"
        );
        &self.coeffs[sh_index(l, m)]
    }
}

impl<C: ShValue> IndexMut<(usize, isize)> for ShCoeffs<C> {
    fn index_mut(&mut self, (l, m): (usize, isize)) -> &mut C {
        assert!(
            l <= self.lmax && m.unsigned_abs() <= l,
            "(l, m) = ({l}, {m}) out of range"
        );
        &mut self.coeffs[sh_index(l, m)]
    }
}

/// Sum of two expansions; the result has the larger `lmax`.
impl<C: ShValue> Add for &ShCoeffs<C> {
    type Output = ShCoeffs<C>;
    fn add(self, rhs: Self) -> ShCoeffs<C> {
        let mut out = self.resized(self.lmax.max(rhs.lmax));
        out += rhs;
        out
    }
}

impl<C: ShValue> AddAssign<&ShCoeffs<C>> for ShCoeffs<C> {
    /// Adds `rhs`, growing `self` if `rhs` has a higher `lmax`.
    fn add_assign(&mut self, rhs: &ShCoeffs<C>) {
        if rhs.lmax > self.lmax {
            *self = self.resized(rhs.lmax);
        }
        for (a, b) in self.coeffs.iter_mut().zip(&rhs.coeffs) {
            *a += *b;
        }
    }
}

/// Difference of two expansions; the result has the larger `lmax`.
impl<C: ShValue> Sub for &ShCoeffs<C> {
    type Output = ShCoeffs<C>;
    fn sub(self, rhs: Self) -> ShCoeffs<C> {
        let neg = -rhs;
        self + &neg
    }
}

impl<C: ShValue> Neg for &ShCoeffs<C> {
    type Output = ShCoeffs<C>;
    fn neg(self) -> ShCoeffs<C> {
        self.map(|c| -c)
    }
}

impl<C: ShValue> Mul<S<C>> for &ShCoeffs<C> {
    type Output = ShCoeffs<C>;
    fn mul(self, s: S<C>) -> ShCoeffs<C> {
        self.scaled(s)
    }
}

impl<T: Real + ShValue<Scalar = T>> ShCoeffs<T> {
    /// Scalar expansion as the same value in all three channels.
    #[must_use]
    pub fn splat_rgb<V: ShValue<Scalar = T>>(&self) -> ShCoeffs<V> {
        self.map(V::splat)
    }
}

impl ShCoeffs<DVec3> {
    /// One channel (0 red, 1 green, 2 blue) as a scalar expansion.
    #[must_use]
    pub fn channel(&self, c: usize) -> ShCoeffs<f64> {
        self.map(|v| v[c])
    }

    /// Assembles RGB from three scalar expansions of equal `lmax`.
    ///
    /// Panics if their `lmax` differ.
    #[must_use]
    pub fn from_channels(r: &ShCoeffs<f64>, g: &ShCoeffs<f64>, b: &ShCoeffs<f64>) -> Self {
        assert!(r.lmax == g.lmax && g.lmax == b.lmax, "channel lmax differ");
        Self::from_fn(r.lmax, |l, m| {
            let i = sh_index(l, m);
            DVec3::new(r[i], g[i], b[i])
        })
    }

    /// Rounded to single precision (a new expansion).
    #[must_use]
    pub fn to_f32(&self) -> ShCoeffs<Vec3> {
        self.map(|v| v.as_vec3())
    }
}

impl ShCoeffs<Vec3> {
    /// Widened to double precision (a new expansion).
    #[must_use]
    pub fn to_f64(&self) -> ShCoeffs<DVec3> {
        self.map(|v| v.as_dvec3())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::U32;

    fn sample() -> ShCoeffs<f64> {
        ShCoeffs::from_fn(3, |l, m| (l as f64) * 0.5 - m as f64 * 0.25 + 0.1)
    }

    #[test]
    fn indexing_by_pair_and_flat_agree() {
        let s = sample();
        assert_eq!(s[(2, -1)], s[sh_index(2, -1)]);
        assert_eq!(s.band(2)[0], s[(2, -2)]);
    }

    #[test]
    fn resize_truncates_and_zero_extends() {
        let s = sample();
        let t = s.resized(1);
        assert_eq!(t.len(), 4);
        assert_eq!(t.as_slice(), &s.as_slice()[..4]);
        let e = s.resized(5);
        assert_eq!(&e.as_slice()[..16], s.as_slice());
        assert!(e.as_slice()[16..].iter().all(|&c| c == 0.0));
    }

    #[test]
    fn arithmetic_and_parseval() {
        let a = sample();
        let b = a.scaled(2.0);
        let c = &b - &a;
        assert_eq!(c, a);
        // Parseval: the sphere integral of a*a equals the coefficient dot product.
        let integral = {
            let q = SphereQuadrature::exact_to_degree(7);
            q.directions
                .iter()
                .zip(&q.weights)
                .map(|(d, w)| w * a.eval(*d).powi(2))
                .sum::<f64>()
        };
        assert!((integral - a.dot(&a)).abs() < 1e-12 * integral);
        let power: f64 = a.band_power().iter().sum();
        assert!((power - a.dot(&a)).abs() < 1e-14);
    }

    #[test]
    fn cs_phase_toggle_flips_odd_m_and_is_an_involution() {
        let a = sample();
        let t = a.toggled_cs_phase();
        assert_eq!(t[(1, 1)], -a[(1, 1)]);
        assert_eq!(t[(3, -3)], -a[(3, -3)]);
        assert_eq!(t[(2, 2)], a[(2, 2)]);
        assert_eq!(t[(2, 0)], a[(2, 0)]);
        assert_eq!(t.toggled_cs_phase(), a);
    }

    #[test]
    fn projection_recovers_a_band_limited_function() {
        let a = sample();
        let p = ShCoeffs::project_fn(3, 6, |d| a.eval(d));
        for (x, y) in p.as_slice().iter().zip(a.as_slice()) {
            assert!((x - y).abs() < 1e-13);
        }
    }

    /// Bound on `|f32 value - exact value|` of the test polynomials below at
    /// an `f32`-rounded node, in units of [`U32`]: rounding the node moves
    /// each polynomial by at most `U32 sum_j |d_j df/dd_j| <= 4 U32`, and
    /// its handful of `f32` operations round terms whose magnitudes sum to
    /// at most 3.5 (at most `4 * 3.5 U32`): 18, and 24 leaves room.
    const F32_POLY_ULPS: f64 = 24.0;

    /// Tolerance of an `f32` projection coefficient `c` against exact, in
    /// units of [`U32`]: a value error `e` at every node moves a coefficient
    /// by at most `e sum_k w_k |Y(d_k)| <= e sqrt(4 pi)` (Cauchy-Schwarz,
    /// with `sum_k w_k = 4 pi` and `sum_k w_k Y(d_k)^2 = 1` for an exact
    /// rule), and the `f64` sum is rounded once to `f32` (`U32 |c|`).
    fn f32_projection_ulps(c: f64) -> f64 {
        F32_POLY_ULPS * (4.0 * core::f64::consts::PI).sqrt() + c.abs()
    }

    /// Three spherical polynomials of degree 2 evaluated in `f32`, and their
    /// exact coefficients (closed forms of `Y_1^m`, `Y_2^m` with the
    /// Condon-Shortley phase): red `0.5 + 2x - yz`, green `xy + (3z^2 - 1)/4`,
    /// blue `z - 3y`.
    fn poly_f32(d: Vec3) -> Vec3 {
        let (x, y, z) = (d.x, d.y, d.z);
        Vec3::new(
            0.5 + 2.0 * x - y * z,
            x * y + 0.25 * (3.0 * z * z - 1.0),
            z - 3.0 * y,
        )
    }

    fn poly_exact(lmax: usize) -> ShCoeffs<DVec3> {
        use core::f64::consts::PI;
        let (c0, c1, c2) = (
            2.0 * PI.sqrt(),
            (4.0 * PI / 3.0).sqrt(),
            2.0 * (PI / 15.0).sqrt(),
        );
        let mut f = ShCoeffs::<DVec3>::zeros(lmax);
        f[(0, 0)] = DVec3::new(0.5 * c0, 0.0, 0.0);
        f[(1, 1)] = DVec3::new(-2.0 * c1, 0.0, 0.0); // x = -sqrt(4pi/3) Y_1^1
        f[(1, -1)] = DVec3::new(0.0, 0.0, 3.0 * c1); // y = -sqrt(4pi/3) Y_1^-1
        f[(1, 0)] = DVec3::new(0.0, 0.0, c1); // z = sqrt(4pi/3) Y_1^0
        f[(2, -1)] = DVec3::new(c2, 0.0, 0.0); // yz = -2 sqrt(pi/15) Y_2^-1
        f[(2, -2)] = DVec3::new(0.0, c2, 0.0); // xy = 2 sqrt(pi/15) Y_2^-2
        f[(2, 0)] = DVec3::new(0.0, (PI / 5.0).sqrt(), 0.0); // 3z^2-1 = 4 sqrt(pi/5) Y_2^0
        f
    }

    /// The largest `|a - b|` over [`f32_projection_ulps`], asserted `<= 1`.
    fn check_projection(got: &ShCoeffs<DVec3>, want: &ShCoeffs<DVec3>, what: &str) -> f64 {
        let mut worst = 0.0f64;
        for (i, (a, b)) in got.as_slice().iter().zip(want.as_slice()).enumerate() {
            for c in 0..3 {
                let units = (a[c] - b[c]).abs() / U32;
                let allowed = f32_projection_ulps(b[c]);
                assert!(
                    units <= allowed,
                    "{what}: coefficient {i} channel {c}: {units} > {allowed} ulps"
                );
                worst = worst.max(units / allowed);
            }
        }
        worst
    }

    #[test]
    fn f32_projection_of_band_limited_polynomials_is_exact_to_f32_rounding() {
        // Any rule exact to degree >= 2 + lmax reproduces the coefficients;
        // a large one (20301 nodes at degree 200) sums many terms, which
        // `f64` sums keep from accumulating `f32` rounding.
        let mut worst = 0.0f64;
        for (lmax, degree) in [(2, 4), (3, 5), (4, 200)] {
            let got = ShCoeffs::<Vec3>::project_fn(lmax, degree, poly_f32).to_f64();
            let what = format!("lmax {lmax} degree {degree}");
            worst = worst.max(check_projection(&got, &poly_exact(lmax), &what));
            // One channel on its own projects like the RGB's green.
            let green = ShCoeffs::<f32>::project_fn(lmax, degree, |d| poly_f32(d).y);
            let green = green.map(|v| DVec3::splat(f64::from(v)));
            let want = poly_exact(lmax).map(|v| DVec3::splat(v.y));
            worst = worst.max(check_projection(&green, &want, &what));
        }
        eprintln!("f32 projection vs closed form: worst {worst:.4} of the allowed");
    }

    #[test]
    fn f32_projection_is_the_f64_one_to_f32_rounding() {
        // A function that is not band-limited (so the rule's own error is
        // the same in both and cancels): |x| + the polynomials, in f32 and
        // in f64. At a rounded node the f32 values differ from the f64 ones
        // by the polynomials' 18 U32 (see F32_POLY_ULPS) plus U32 from |x|
        // and U32 from the sum, within F32_POLY_ULPS: the same bound.
        let f64_fn = |d: DVec3| {
            let (x, y, z) = (d.x, d.y, d.z);
            DVec3::new(
                0.5 + 2.0 * x - y * z,
                x * y + 0.25 * (3.0 * z * z - 1.0),
                z - 3.0 * y,
            ) + DVec3::splat(x.abs())
        };
        let f32_fn = |d: Vec3| poly_f32(d) + Vec3::splat(d.x.abs());
        let mut worst = 0.0f64;
        for (lmax, degree) in [(2, 9), (6, 40)] {
            let want = ShCoeffs::<DVec3>::project_fn(lmax, degree, f64_fn);
            let got = ShCoeffs::<Vec3>::project_fn(lmax, degree, f32_fn).to_f64();
            worst = worst.max(check_projection(&got, &want, &format!("lmax {lmax}")));
        }
        eprintln!("f32 vs f64 projection: worst {worst:.4} of the allowed");
    }

    #[test]
    fn rgb_channels_round_trip() {
        let a = sample();
        let rgb = ShCoeffs::<DVec3>::from_channels(&a, &a.scaled(2.0), &a.scaled(3.0));
        assert_eq!(rgb.channel(1), a.scaled(2.0));
        let v = rgb.eval(DVec3::new(0.0, 0.6, 0.8));
        assert!((v.y - 2.0 * a.eval(DVec3::new(0.0, 0.6, 0.8))).abs() < 1e-14);
    }
}

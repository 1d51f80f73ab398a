//! Rotation of SH coefficients to any `lmax`: [`ShRotation`] (its blocks by
//! the Ivanic-Ruedenberg recurrence), the cheap rotation about +Z
//! [`rotate_z`], and [`rotate_once`] without stored blocks.

use core::ops::Mul;

use glam::{DMat3, DQuat};

use crate::sh::frame::Frame;
use crate::sh::index::sh_index;
use crate::sh::real::Real;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// How far `R^T R` may be from the identity (max absolute entry), and
/// `det R` from `+1`, for [`ShRotation::try_from_mat3`] to accept `R` as a
/// rotation (and for the debug check of [`ShRotation::from_mat3`]).
///
/// Loose enough for matrices that went through `f32` once, tight enough to
/// reject scales and shears that would visibly break band power.
pub const ORTHONORMAL_TOLERANCE: f64 = 1e-6;

/// The rotation of SH coefficients by a 3-D rotation `R`, to degree `lmax`:
/// one `(2l+1) x (2l+1)` orthogonal block `M^l(R)` per degree `l = 0..=lmax`.
///
/// Semantics (the maths below): applied
/// to the coefficients of `f`, it gives those of `g(d) = f(R^T d)`, the
/// function carried along by `R`. The coefficients of a directional light
/// from `a`, `Y_l^m(a)`, become `Y_l^m(R a)`.
///
/// Built by the Ivanic & Ruedenberg (1996, eq. 8.1, with the 1998 erratum
/// and its `m < 0` sign corrected) recurrence from the degree-1 block, with
/// the coupling applied on both sides so that rounding does not grow with
/// `l`, in `O(lmax^3)`.
///
/// ```
/// use glam::DMat3;
/// use shlight_core::sh::{ShCoeffs, ShRotation, sh_eval};
/// // A quarter turn about +Z takes a light at +X to +Y.
/// let rot = ShRotation::from_mat3(4, DMat3::from_rotation_z(std::f64::consts::FRAC_PI_2));
/// let at_x = ShCoeffs::from_vec(sh_eval(4, glam::DVec3::new(1.0, 0.0, 0.0))).unwrap();
/// let got = rot.apply(&at_x);
/// let want = sh_eval(4, glam::DVec3::new(0.0, 1.0, 0.0));
/// for (g, w) in got.as_slice().iter().zip(&want) {
///     assert!((g - w).abs() < 1e-14);
/// }
/// ```
///
/// # What a rotation does
///
/// For a rotation matrix `R` (orthonormal, `det R = +1`) the rotated function
/// is
///
/// ```text
/// g(d) = f(R^T d)
/// ```
///
/// i.e. the function is carried along by `R`: a light that came from
/// direction `a` comes from `R a` afterwards. Rotations never mix degrees, so
/// on the coefficients the rotation is block diagonal, one orthogonal
/// `(2l+1) x (2l+1)` block `M^l(R)` per degree:
///
/// ```text
/// Y_l^m(R d) = sum_{m'} M^l_{m m'}(R) Y_l^{m'}(d)      (definition of M^l)
/// g_l^m      = sum_{m'} M^l_{m m'}(R) f_l^{m'}          (what `apply` computes)
/// ```
///
/// (substitute `d = R e` in `g_l^m = int f(R^T d) Y_l^m(d) dd`). With these
/// definitions `M^l(R_a R_b) = M^l(R_a) M^l(R_b)` and `M^l(R^T) = M^l(R)^T`,
/// and the coefficients of a directional light `Y_l^m(a)` become exactly
/// `Y_l^m(R a)`.
///
/// # How the blocks are built
///
/// Degree 1 is read off `R` directly. In shlight's basis (Condon-Shortley
/// phase included) `(Y_1^{-1}, Y_1^0, Y_1^1) = sqrt(3/(4 pi)) P d` with
/// `P d = (-y, z, -x)`, so `M^1 = P R P^T`:
/// `M^1_{ij} = s_i s_j R[a_i][a_j]`, axes `a = (y, z, x)`, signs
/// `s = (-1, +1, -1)`.
///
/// Higher degrees follow from `M^1` and `M^{l-1}` by the recurrence of
/// Ivanic & Ruedenberg, "Rotation matrices for real spherical harmonics.
/// Direct determination by recursion", J. Phys. Chem. 100 (1996) 6342,
/// eq. 8.1 and tables 1-2, with the corrections of their erratum (J. Phys.
/// Chem. A 102 (1998) 9099). Their row side, for `l >= 2`, `d = [m == 0]`:
///
/// ```text
/// u = sqrt((l+m)(l-m)),  v = 1/2 sqrt((1+d)(l+|m|-1)(l+|m|)) (1-2d),
/// w = -1/2 sqrt((l-|m|-1)(l-|m|)) (1-d)
/// u U + v V + w W   with   P(i, a, .) = M^1_{i,.} (x) M^{l-1}_{a,.}  and
/// U = P(0, m)
/// V = P(1, 1) + P(-1, -1)                                         m = 0
///   = P(1, m-1) sqrt(1 + [m=1])  - P(-1, 1-m) (1 - [m=1])          m > 0
///   = P(1, m+1) (1 - [m=-1])     + P(-1, -m-1) sqrt(1 + [m=-1])    m < 0
/// W = P(1, m+1) + P(-1, -m-1)                                     m > 0
///   = P(1, m-1) - P(-1, 1-m)                                      m < 0
/// ```
///
/// These terms, divided by `sqrt(l(2l-1))`, are exactly column `m` of the
/// coupling isometry `C: V_l -> V_1 (x) V_{l-1}` (real Clebsch-Gordan
/// coefficients; `u^2 + 2v^2 + 2w^2 = l(2l-1)` for every `m`), and the
/// recurrence is `M^l = C^T (M^1 (x) M^{l-1}) C`. Ivanic & Ruedenberg
/// evaluate the column side `C` by picking one product term per column `n`
/// (`P(i, a, n) = M^1_{i,0} M^{l-1}_{a,n}` for `|n| < l`) and dividing by its
/// coefficient, their `sqrt(denom)`, `denom = (l+n)(l-n)`, which is small
/// for `|n|` near `l`. That division amplifies rounding at every degree: in
/// double precision `|M M^T - I|` grows about tenfold per ten degrees
/// (1e-12 at `l` 50, 1e-3 at `l` 150, above 1 by `l` 180). shlight
/// therefore applies the same terms on both sides:
///
/// ```text
/// M^l_{mn} = 1/(l(2l-1)) sum_{(c,i,a) in terms(m)} sum_{(c',j,b) in terms(n)}
///            c c' M^1_{ij} M^{l-1}_{ab}
/// ```
///
/// Equal to the published recurrence in exact arithmetic (its `|n| = l`
/// columns are this formula already), but `C` is an isometry, so an error
/// in `M^{l-1}` passes to `M^l` without amplification and rounding only
/// adds up: `|M M^T - I|` grows linearly, below `3e-13` to `l` 256 (`1e-14`
/// to `1e-13` typically; measured over random rotations).
///
/// The `m < 0` line of `V` is where the published versions disagree (shlight's
/// reference notes that the erratum itself still has a sign error there).
/// The `+` above is the sign the tests in `tests/rotation.rs` accept:
/// with the second term negated, every block from degree 2 on is wrong
/// (`|M M^T - I| ~ 1` at `l = 2`, lights land in the wrong place). It is also
/// the only sign that reproduces the paper's own `n = -l` column
/// (`P(i, a, -l) = M^1_{i,1} M^{l-1}_{a,1-l} + M^1_{i,-1} M^{l-1}_{a,l-1}`).
///
/// The recurrence only multiplies by factors that depend on `(l, m, n)`, so
/// it is the same in the basis with and without the Condon-Shortley phase:
/// conjugating every `M^l` by `diag((-1)^m)` (the phase toggle, which is
/// also `M^l` of the half turn about Z) maps solutions to solutions, because
/// every product in it carries the sign `(-1)^(m+n)`. shlight therefore runs
/// it directly on its own `M^1`. Nothing divides by a quantity that depends
/// on `R`, so half and quarter turns are as accurate as any other rotation.
///
/// # Cost and accuracy
///
/// Building costs `O(lmax^3)`: about `80 l^2` multiply-adds for degree `l`
/// (each entry is at most 25 products, shared through the row side). It
/// stores `sum (2l+1)^2 ~ (4/3) lmax^3` values (180 MB at `lmax` 256).
/// Applying costs `sum (2l+1)^2` multiply-adds per channel, also
/// `O(lmax^3)`. Every block is orthogonal to about `1e-13` or better at
/// `lmax` 64 and 256 (measured by the tests).
///
/// The rotation about +Z alone needs no blocks: [`rotate_z`] does it in
/// `O(lmax^2)` from `cos(m alpha)`, `sin(m alpha)`.
#[derive(Clone, Debug, PartialEq)]
pub struct ShRotation {
    lmax: usize,
    /// `blocks[l]` is `M^l` row-major: entry `(m, n)` at `(m+l)(2l+1) + (n+l)`.
    blocks: Vec<Vec<f64>>,
}

impl ShRotation {
    /// The identity to degree `lmax`: every block `M^l = I`.
    #[must_use]
    pub fn identity(lmax: usize) -> Self {
        let blocks = (0..=lmax)
            .map(|l| {
                let n = 2 * l + 1;
                let mut b = vec![0.0; n * n];
                for k in 0..n {
                    b[k * n + k] = 1.0;
                }
                b
            })
            .collect();
        Self { lmax, blocks }
    }

    /// The rotation of coefficients by the rotation matrix `r` (column
    /// vectors, `d -> r * d`), to degree `lmax`: `g(d) = f(r^T d)`.
    ///
    /// Precondition: `r` is orthonormal with `det r = +1`, to
    /// [`ORTHONORMAL_TOLERANCE`]; checked by `debug_assert!` only. The blocks
    /// are orthogonal only as far as `r` is. Use
    /// [`ShRotation::try_from_mat3`] for matrices of unknown origin.
    ///
    /// Cost `O(lmax^3)` time and memory.
    #[must_use]
    pub fn from_mat3(lmax: usize, r: DMat3) -> Self {
        debug_assert!(
            is_rotation(r),
            "ShRotation::from_mat3: {r:?} is not a rotation (orthonormal, det +1)"
        );
        Self::build(lmax, r)
    }

    /// [`ShRotation::from_mat3`], or `None` when `r` is not a rotation:
    /// when `max |r^T r - I| > ORTHONORMAL_TOLERANCE`, or
    /// `|det r - 1| > ORTHONORMAL_TOLERANCE` (reflections have `det = -1`),
    /// or `r` has a non-finite entry.
    #[must_use]
    pub fn try_from_mat3(lmax: usize, r: DMat3) -> Option<Self> {
        is_rotation(r).then(|| Self::build(lmax, r))
    }

    /// The rotation of coefficients by the rotation that the quaternion `q`
    /// represents (`d -> q d q*`), to degree `lmax`: `g(d) = f(R(q)^T d)`.
    ///
    /// `q` is normalised first, so any non-zero finite quaternion is accepted;
    /// `q` and `-q` give the same rotation. Precondition: `q` is non-zero and
    /// finite (checked by `debug_assert!`).
    #[must_use]
    pub fn from_quat(lmax: usize, q: DQuat) -> Self {
        debug_assert!(
            q.is_finite() && q.length_squared() > 0.0,
            "ShRotation::from_quat: quaternion {q:?} is zero or not finite"
        );
        Self::build(lmax, DMat3::from_quat(q.normalize()))
    }

    /// Converts the coefficients of an environment map read in frame `from`
    /// into the coefficients of the same map read in frame `to`.
    ///
    /// This is [`ShRotation::from_mat3`] of [`Frame::rotation_to`]: from
    /// [`Frame::YUp`] to [`Frame::ZUp`] it is the quarter turn `Rx(+90 deg)`,
    /// `(x, y, z) -> (x, -z, y)`; the other way `Rx(-90 deg)`; the identity
    /// when `from == to`.
    ///
    /// Example: a light at `+Y` in the y-up reading of a map (its top row,
    /// `t = 0`) comes out at `+Z` in the z-up reading (the top row again); a
    /// light at `+Z` in the y-up reading (`t = 90 deg, p = 90 deg`) comes out
    /// at `-Y`; `+X` stays `+X`.
    ///
    /// ```
    /// use shlight_core::sh::{Frame, ShCoeffs, ShRotation, sh_eval};
    /// let light_yup = ShCoeffs::from_vec(sh_eval(2, glam::DVec3::new(0.0, 1.0, 0.0))).unwrap();
    /// let light_zup = ShRotation::between_frames(2, Frame::YUp, Frame::ZUp).apply(&light_yup);
    /// let want = sh_eval(2, glam::DVec3::new(0.0, 0.0, 1.0));
    /// assert!(light_zup.as_slice().iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-15));
    /// ```
    #[must_use]
    pub fn between_frames(lmax: usize, from: Frame, to: Frame) -> Self {
        if from == to {
            // Exactly the identity (the recurrence would round it).
            return Self::identity(lmax);
        }
        Self::build(lmax, from.rotation_to(to))
    }

    /// The highest degree held.
    #[must_use]
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The block `M^l`, row-major `(2l+1) x (2l+1)`: entry `(m, n)`,
    /// `-l <= m, n <= l`, at index `(m+l)(2l+1) + (n+l)`.
    ///
    /// Panics if `l > lmax`.
    #[must_use]
    pub fn block(&self, l: usize) -> &[f64] {
        assert!(
            l <= self.lmax,
            "ShRotation::block: degree {l} > lmax {}",
            self.lmax
        );
        &self.blocks[l]
    }

    /// The coefficients of `g(d) = f(R^T d)`: `g_l^m = sum_n M^l_{mn} f_l^n`
    /// for every `l <= f.lmax()`.
    ///
    /// `f` may have a lower `lmax` than the rotation (the result has `f`'s
    /// `lmax`). Panics if `f.lmax() > self.lmax()`. Cost `O(f.lmax()^3)`.
    #[must_use]
    pub fn apply<C: ShValue>(&self, f: &ShCoeffs<C>) -> ShCoeffs<C> {
        self.check_lmax(f.lmax());
        let mut out = ShCoeffs::zeros(f.lmax());
        for l in 0..=f.lmax() {
            mat_vec(&self.blocks[l], f.band(l), out.band_mut(l));
        }
        out
    }

    /// [`ShRotation::apply`] in place (one scratch band of `2 lmax + 1` values).
    ///
    /// Panics if `f.lmax() > self.lmax()`.
    pub fn apply_in_place<C: ShValue>(&self, f: &mut ShCoeffs<C>) {
        self.check_lmax(f.lmax());
        let mut scratch = vec![C::ZERO; 2 * f.lmax() + 1];
        for l in 0..=f.lmax() {
            let src = &mut scratch[..2 * l + 1];
            src.copy_from_slice(f.band(l));
            mat_vec(&self.blocks[l], src, f.band_mut(l));
        }
    }

    /// The inverse rotation, `M^l(R^T) = M^l(R)^T`: the transpose of every block.
    #[must_use]
    pub fn inverse(&self) -> Self {
        let blocks = self
            .blocks
            .iter()
            .enumerate()
            .map(|(l, b)| {
                let n = 2 * l + 1;
                let mut t = vec![0.0; n * n];
                for i in 0..n {
                    for j in 0..n {
                        t[j * n + i] = b[i * n + j];
                    }
                }
                t
            })
            .collect();
        Self {
            lmax: self.lmax,
            blocks,
        }
    }

    /// The composition `self ∘ other`: first `other`, then `self`. If `self`
    /// is built from `R_a` and `other` from `R_b`, the result is the rotation
    /// by `R_a R_b` (`M^l(R_a R_b) = M^l(R_a) M^l(R_b)`), to degree
    /// `min(self.lmax, other.lmax)`. Also available as `self * other`.
    ///
    /// Cost `O(lmax^4)` (a matrix product per block): building from
    /// `R_a R_b` directly is cheaper at high `lmax`.
    #[must_use]
    pub fn compose(&self, other: &Self) -> Self {
        let lmax = self.lmax.min(other.lmax);
        let blocks = (0..=lmax)
            .map(|l| {
                let n = 2 * l + 1;
                let (a, b) = (&self.blocks[l], &other.blocks[l]);
                let mut c = vec![0.0; n * n];
                for i in 0..n {
                    let row = &mut c[i * n..(i + 1) * n];
                    for k in 0..n {
                        let aik = a[i * n + k];
                        for (cij, bkj) in row.iter_mut().zip(&b[k * n..(k + 1) * n]) {
                            *cij += aik * bkj;
                        }
                    }
                }
                c
            })
            .collect();
        Self { lmax, blocks }
    }

    fn check_lmax(&self, lmax: usize) {
        assert!(
            lmax <= self.lmax,
            "ShRotation: coefficients have lmax {lmax} but the rotation was built to lmax {}",
            self.lmax
        );
    }

    /// The recurrence; `r` is assumed to be a rotation.
    fn build(lmax: usize, r: DMat3) -> Self {
        let mut blocks = Vec::with_capacity(lmax + 1);
        blocks.push(vec![1.0]);
        if lmax >= 1 {
            let m1 = band1(r);
            blocks.push(m1.to_vec());
            for l in 2..=lmax {
                let next = next_block(l, &m1, &blocks[l - 1]);
                blocks.push(next);
            }
        }
        Self { lmax, blocks }
    }
}

/// `a * b` is [`ShRotation::compose`]: first `b`, then `a`.
impl Mul for &ShRotation {
    type Output = ShRotation;
    fn mul(self, rhs: Self) -> ShRotation {
        self.compose(rhs)
    }
}

/// `a * b` is [`ShRotation::compose`]: first `b`, then `a`.
impl Mul for ShRotation {
    type Output = ShRotation;
    fn mul(self, rhs: Self) -> ShRotation {
        self.compose(&rhs)
    }
}

/// Rotates coefficients about +Z by `angle` (radians, counter-clockwise seen
/// from +Z): the same result as
/// `ShRotation::from_mat3(f.lmax(), DMat3::from_rotation_z(angle)).apply(f)`,
/// i.e. `g(d) = f(Rz(angle)^T d)`, in `O(lmax^2)` without building blocks.
///
/// `Y_l^{+-m}` depend on the azimuth through `cos(m phi)`, `sin(m phi)`, so
/// the rotation only mixes `m` with `-m` (`m > 0`, `c = cos(m angle)`,
/// `s = sin(m angle)`):
///
/// ```text
/// g_l^m  = c f_l^m  - s f_l^{-m}
/// g_l^-m = c f_l^-m + s f_l^m
/// g_l^0  = f_l^0
/// ```
///
/// ```
/// use shlight_core::sh::{ShCoeffs, rotate_z, sh_eval};
/// let at_x = ShCoeffs::from_vec(sh_eval(3, glam::DVec3::new(1.0, 0.0, 0.0))).unwrap();
/// let got = rotate_z(&at_x, std::f64::consts::FRAC_PI_2);
/// let want = sh_eval(3, glam::DVec3::new(0.0, 1.0, 0.0));
/// assert!(got.as_slice().iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-14));
/// ```
#[must_use]
pub fn rotate_z<C: ShValue>(f: &ShCoeffs<C>, angle: f64) -> ShCoeffs<C> {
    let mut out = f.clone();
    for m in 1..=f.lmax() {
        let (s, c) = (m as f64 * angle).sin_cos();
        let (s, c) = (C::Scalar::from_f64(s), C::Scalar::from_f64(c));
        let mi = m as isize;
        for l in m..=f.lmax() {
            let (ip, im) = (sh_index(l, mi), sh_index(l, -mi));
            let (fp, fm) = (f[ip], f[im]);
            out[ip] = fp.scale(c) - fm.scale(s);
            out[im] = fm.scale(c) + fp.scale(s);
        }
    }
    out
}

/// `max |r^T r - I| <= tol`, `|det r - 1| <= tol`, all entries finite.
fn is_rotation(r: DMat3) -> bool {
    if !r.is_finite() {
        return false;
    }
    let g = r.transpose() * r - DMat3::IDENTITY;
    let off = g.to_cols_array().iter().fold(0.0f64, |a, v| a.max(v.abs()));
    off <= ORTHONORMAL_TOLERANCE && (r.determinant() - 1.0).abs() <= ORTHONORMAL_TOLERANCE
}

/// `M^1 = P R P^T`, row-major, rows and columns `m = -1, 0, 1` standing for
/// `(-y, z, -x)`: `M^1_{ij} = s_i s_j R[a_i][a_j]`.
fn band1(r: DMat3) -> [f64; 9] {
    const AXIS: [usize; 3] = [1, 2, 0];
    const SIGN: [f64; 3] = [-1.0, 1.0, -1.0];
    let mut out = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            // glam is column-major: R[a][b] = col(b)[a].
            out[i * 3 + j] = SIGN[i] * SIGN[j] * r.col(AXIS[j])[AXIS[i]];
        }
    }
    out
}

/// One term `c (i, a)` of a coupling column: the coefficient `c` of the
/// product basis vector `e_i (x) e_a` of `V_1 (x) V_{l-1}`.
#[derive(Clone, Copy, Debug)]
struct Term {
    c: f64,
    i: isize,
    a: isize,
}

/// The terms of Ivanic & Ruedenberg's `u U + v V + w W` for order `m` of
/// degree `l >= 2`, without the column denominator: column `m` of the
/// coupling isometry `C: V_l -> V_1 (x) V_{l-1}` scaled by `sqrt(l (2l-1))`
/// (the squares of the coefficients sum to `l (2l-1)` for every `m`).
///
/// Returns up to five terms and their number; terms whose coefficient
/// vanishes (`u` at `|m| = l`, `w` at `m = 0` or `|m| >= l-1`, the
/// `(1 - [m = +-1])` factors) are left out, so every `a` lies in `-(l-1)..=l-1`.
fn coupling_terms(l: usize, m: isize) -> ([Term; 5], usize) {
    let lf = l as f64;
    let am = m.unsigned_abs();
    let amf = am as f64;
    let mut terms = [Term { c: 0.0, i: 0, a: 0 }; 5];
    let mut nt = 0;
    let mut push = |c: f64, i: isize, a: isize| {
        terms[nt] = Term { c, i, a };
        nt += 1;
    };
    // u = sqrt((l+m)(l-m)), U = P(0, m, .)
    if am < l {
        push(((lf + m as f64) * (lf - m as f64)).sqrt(), 0, m);
    }
    // v = 1/2 sqrt((1+d)(l+|m|-1)(l+|m|)) (1-2d), d = [m == 0]
    let v = 0.5 * ((lf + amf - 1.0) * (lf + amf)).sqrt();
    match m {
        0 => {
            let v0 = -v * core::f64::consts::SQRT_2;
            push(v0, 1, 1);
            push(v0, -1, -1);
        }
        1 => push(v * core::f64::consts::SQRT_2, 1, 0),
        -1 => push(v * core::f64::consts::SQRT_2, -1, 0),
        m if m > 0 => {
            push(v, 1, m - 1);
            push(-v, -1, 1 - m);
        }
        m => {
            push(v, 1, m + 1);
            // "+": the erratum's "-" fails every test from degree 2 on.
            push(v, -1, -m - 1);
        }
    }
    // w = -1/2 sqrt((l-|m|-1)(l-|m|)) (1-d)
    if m != 0 && am + 1 < l {
        let w = -0.5 * ((lf - amf - 1.0) * (lf - amf)).sqrt();
        if m > 0 {
            push(w, 1, m + 1);
            push(w, -1, -m - 1);
        } else {
            push(w, 1, m - 1);
            push(-w, -1, 1 - m);
        }
    }
    (terms, nt)
}

/// `M^l = C^T (M^1 (x) M^{l-1}) C / (l (2l-1))` for `l >= 2`, with the
/// unnormalised coupling columns of [`coupling_terms`] on both sides:
///
/// ```text
/// M^l_{mn} = 1/(l(2l-1)) sum_{(c,i,a) in terms(m)} sum_{(c',j,b) in terms(n)}
///            c c' M^1_{ij} M^{l-1}_{ab}
/// ```
///
/// Computed as `Z_m(j, b) = sum_{terms(m)} c M^1_{ij} M^{l-1}_{ab}` (the row
/// side of Ivanic & Ruedenberg's recurrence, a few scaled rows of `M^{l-1}`),
/// then `M^l_{mn} = sum_{terms(n)} c' Z_m(j, b) / (l(2l-1))`.
fn next_block(l: usize, m1: &[f64; 9], prev: &[f64]) -> Vec<f64> {
    let li = l as isize;
    let n = 2 * l + 1;
    let pn = 2 * l - 1;
    debug_assert_eq!(prev.len(), pn * pn);
    let r1 = |i: isize, j: isize| m1[((i + 1) * 3 + (j + 1)) as usize];
    let columns: Vec<([Term; 5], usize)> = (-li..=li).map(|m| coupling_terms(l, m)).collect();
    let scale = 1.0 / (l * (2 * l - 1)) as f64;

    // The column side flattened: offsets into z and coefficients times
    // 1/(l(2l-1)), padded to five terms with zero coefficients.
    let mut col_idx = vec![[0usize; 5]; n];
    let mut col_c = vec![[0.0f64; 5]; n];
    for (k, (terms, nt)) in columns.iter().enumerate() {
        for (q, t) in terms[..*nt].iter().enumerate() {
            col_idx[k][q] = (t.i + 1) as usize * pn + (t.a + li - 1) as usize;
            col_c[k][q] = t.c * scale;
        }
    }

    // One output row m: Z_m(j, b) at z[(j+1) pn + (b + l-1)].
    let fill_row = |row: &mut [f64], (terms, nt): &([Term; 5], usize), z: &mut Vec<f64>| {
        // Up to five rows of M^{l-1} and their weights for j = -1, 0, 1;
        // missing terms get weight 0 on the first row.
        let mut rows: [&[f64]; 5] = [&prev[..pn]; 5];
        let mut wt = [[0.0f64; 5]; 3];
        for (q, t) in terms[..*nt].iter().enumerate() {
            rows[q] = &prev[(t.a + li - 1) as usize * pn..][..pn];
            for j in 0..3 {
                wt[j][q] = t.c * r1(t.i, j as isize - 1);
            }
        }
        let (z0, rest) = z.split_at_mut(pn);
        let (z1, z2) = rest.split_at_mut(pn);
        let [p0, p1, p2, p3, p4] = rows;
        for b in 0..pn {
            let v = [p0[b], p1[b], p2[b], p3[b], p4[b]];
            let dot =
                |w: &[f64; 5]| w[0] * v[0] + w[1] * v[1] + w[2] * v[2] + w[3] * v[3] + w[4] * v[4];
            z0[b] = dot(&wt[0]);
            z1[b] = dot(&wt[1]);
            z2[b] = dot(&wt[2]);
        }
        for ((o, idx), c) in row.iter_mut().zip(&col_idx).zip(&col_c) {
            *o = c[0] * z[idx[0]]
                + c[1] * z[idx[1]]
                + c[2] * z[idx[2]]
                + c[3] * z[idx[3]]
                + c[4] * z[idx[4]];
        }
    };
    let mut out = vec![0.0; n * n];
    #[cfg(feature = "rayon")]
    if l >= PARALLEL_FROM_DEGREE {
        use rayon::prelude::*;
        out.par_chunks_exact_mut(n)
            .zip(&columns)
            .for_each_init(|| vec![0.0; 3 * pn], |z, (row, col)| fill_row(row, col, z));
        return out;
    }
    let mut z = vec![0.0; 3 * pn];
    for (row, col) in out.chunks_exact_mut(n).zip(&columns) {
        fill_row(row, col, &mut z);
    }
    out
}

/// From this degree on, the rows of a block are computed in parallel.
#[cfg(feature = "rayon")]
const PARALLEL_FROM_DEGREE: usize = 48;

/// Rotates coefficients by the rotation matrix `r` without keeping the
/// blocks: each block `M^l` is built from `M^{l-1}`, applied to band `l` and
/// dropped. Same result as `ShRotation::from_mat3(f.lmax(), r).apply(f)`, in
/// `O(lmax^2)` memory instead of `O(lmax^3)` (at lmax 512 the blocks of
/// [`ShRotation`] take 1.4 GB; this needs 16 MB). Time `O(lmax^3)`.
///
/// Precondition as [`ShRotation::from_mat3`]: `r` is a rotation.
#[must_use]
pub fn rotate_once<C: ShValue>(f: &ShCoeffs<C>, r: DMat3) -> ShCoeffs<C> {
    debug_assert!(is_rotation(r), "rotate_once: {r:?} is not a rotation");
    let mut out = f.clone();
    if f.lmax() == 0 {
        return out;
    }
    let m1 = band1(r);
    mat_vec(&m1, f.band(1), out.band_mut(1));
    let mut prev = m1.to_vec();
    for l in 2..=f.lmax() {
        let block = next_block(l, &m1, &prev);
        mat_vec(&block, f.band(l), out.band_mut(l));
        prev = block;
    }
    out
}

/// `out = b * x` for a row-major square block `b`.
#[inline]
fn mat_vec<C: ShValue>(b: &[f64], x: &[C], out: &mut [C]) {
    let n = x.len();
    for (o, row) in out.iter_mut().zip(b.chunks_exact(n)) {
        let mut acc = C::ZERO;
        for (&bij, &xj) in row.iter().zip(x) {
            acc += xj.scale(C::Scalar::from_f64(bij));
        }
        *o = acc;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ivanic & Ruedenberg's published (one-sided) column side: for
    /// `|n| < l` one product term divided by `sqrt((l+n)(l-n))`; for
    /// `|n| = l` the `P(i, a, +-l)` edge terms over `sqrt(2l(2l-1))`.
    fn next_block_one_sided(l: usize, m1: &[f64; 9], prev: &[f64]) -> Vec<f64> {
        let li = l as isize;
        let (n, pn) = (2 * l + 1, 2 * l - 1);
        let r1 = |i: isize, j: isize| m1[((i + 1) * 3 + (j + 1)) as usize];
        let pv = |a: isize, b: isize| prev[(a + li - 1) as usize * pn + (b + li - 1) as usize];
        let mut out = vec![0.0; n * n];
        for m in -li..=li {
            let (terms, nt) = coupling_terms(l, m);
            for c in -li..=li {
                let mut acc = 0.0;
                for t in &terms[..nt] {
                    acc += t.c
                        * if c == li {
                            r1(t.i, 1) * pv(t.a, li - 1) - r1(t.i, -1) * pv(t.a, 1 - li)
                        } else if c == -li {
                            r1(t.i, 1) * pv(t.a, 1 - li) + r1(t.i, -1) * pv(t.a, li - 1)
                        } else {
                            r1(t.i, 0) * pv(t.a, c)
                        };
                }
                let denom = if c.abs() == li {
                    (2 * l * (2 * l - 1)) as f64
                } else {
                    ((li + c) * (li - c)) as f64
                };
                out[(m + li) as usize * n + (c + li) as usize] = acc / denom.sqrt();
            }
        }
        out
    }

    fn max_orthogonality_error(b: &[f64], n: usize) -> f64 {
        let mut worst = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let dot: f64 = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum();
                worst = worst.max((dot - if i == j { 1.0 } else { 0.0 }).abs());
            }
        }
        worst
    }

    #[test]
    fn coupling_columns_are_orthonormal() {
        // The terms of every m, divided by sqrt(l(2l-1)), are orthonormal
        // vectors of V_1 (x) V_{l-1}: what makes the two-sided form stable.
        for l in 2..=12usize {
            let li = l as isize;
            let dense = |m: isize| {
                let mut v = vec![0.0; 3 * (2 * l - 1)];
                let (terms, nt) = coupling_terms(l, m);
                for t in &terms[..nt] {
                    v[(t.i + 1) as usize * (2 * l - 1) + (t.a + li - 1) as usize] += t.c;
                }
                v
            };
            let norm = (l * (2 * l - 1)) as f64;
            for m in -li..=li {
                for k in -li..=li {
                    let dot: f64 = dense(m).iter().zip(dense(k)).map(|(a, b)| a * b).sum();
                    let want = if m == k { 1.0 } else { 0.0 };
                    assert!(
                        (dot / norm - want).abs() < 1e-14,
                        "l {l}: <{m}, {k}> = {dot}"
                    );
                }
            }
        }
    }

    #[test]
    fn published_recurrence_agrees_at_low_degree_and_loses_orthogonality_at_high() {
        let r = DMat3::from_quat(DQuat::from_xyzw(0.3, -0.5, 0.2, 0.7).normalize());
        let m1 = band1(r);
        let stable = ShRotation::from_mat3(160, r);
        let mut prev = m1.to_vec();
        for l in 2..=160usize {
            let one_sided = next_block_one_sided(l, &m1, &prev);
            let n = 2 * l + 1;
            if l <= 20 {
                // Same recurrence: agreement to rounding at low degree.
                let d = one_sided
                    .iter()
                    .zip(stable.block(l))
                    .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
                assert!(d < 1e-13, "l {l}: {d:e}");
            }
            if l == 160 {
                // The one-sided division amplifies rounding geometrically.
                let bad = max_orthogonality_error(&one_sided, n);
                let good = max_orthogonality_error(stable.block(l), n);
                assert!(
                    bad > 1e-6 && good < 1e-12,
                    "one-sided {bad:e}, two-sided {good:e}"
                );
            }
            prev = one_sided;
        }
    }
}

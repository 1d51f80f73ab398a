//! [`GgxLobe`]: the GGX microfacet BRDF projected onto SH per view
//! direction and tabulated over the view's elevation (Kautz, Sloan &
//! Snyder 2002, "Fast, Arbitrary BRDF Shading for Low-Frequency Lighting
//! Using Spherical Harmonics"), what `--brdf ggx:ALPHA[,F0]` shades
//! glossy transfer with. The definition, the table and the directions are
//! stated on [`GgxLobe`].

use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, TAU};

use glam::{DMat3, DVec3};
use rayon::prelude::*;
use shlight_core::sh::{ShBasis, ShCoeffs, gauss_legendre, lm_from_index, rotate_once, sh_count};
use shlight_specular::MaskingShadowing;

/// View elevations tabulated, from `0` to `pi/2`.
pub(crate) const ELEVATIONS: usize = 96;

/// Gauss-Legendre nodes per quarter turn of half-vector azimuth.
pub(crate) const QUADRATURE_AZIMUTH: usize = 24;

/// Gauss-Legendre nodes per azimuth over the half vectors whose
/// reflection is above the surface.
pub(crate) const QUADRATURE_ELEVATION: usize = 48;

/// The smallest roughness taken: below it the lobe is a mirror to any
/// lmax a bake holds.
pub const MIN_GGX_ALPHA: f64 = 1e-3;

/// The GGX BRDF's SH projection per view elevation, to one lmax, what
/// `--brdf ggx:ALPHA[,F0]` shades glossy transfer with (Kautz, Sloan &
/// Snyder 2002).
///
/// # Definition
///
/// At a vertex with unit normal `n`, seen from the unit direction `w_o`
/// (from the vertex to the eye) with `mu_o = n.w_o > 0`, the exit radiance
/// of the transferred radiance `T(w) = sum_lm T_lm Y_lm(w)` is
///
/// ```text
/// L_o = int_{n.w > 0} T(w) f(w_o, w) (n.w) dw
/// f(w_o, w_i) = D(h) F(w_o.h) V(mu_o, mu_i),   h = (w_o + w_i) / |w_o + w_i|
/// ```
///
/// with `D` the GGX distribution of linear roughness `alpha`
/// (`alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2)`), `V = G_2 / (4 mu_o
/// mu_i)` with `G_2` Smith's height-correlated masking-shadowing (Heitz
/// 2014, eq. 99; `shlight_specular::MaskingShadowing::HeightCorrelated`), and
/// `F` Schlick's Fresnel `F0 + (1 - F0) (1 - w_o.h)^5` (`F0 = 1` when the
/// BRDF string gives none: `F = 1`, a white conductor). `L_o = 0` where
/// `mu_o <= 0` (a view from below the surface).
///
/// Because `T` is band-limited to lmax, the integral is exactly the dot
/// product of `T` with the projection of `f (n.w)` onto SH to lmax: in the
/// vertex's local frame (`z` the normal, `x` along the tangential part of
/// `w_o`, `y = z x x`), `L_o = sum_lm B_lm(theta_o) T'_lm`, with
/// `T' = T` rotated into that frame ([`shlight_core::sh::ShRotation`]) and
/// `B_lm(theta_o) = int f(w_o, w) (n.w) Y_lm(w) dw` for
/// `w_o = (sin theta_o, 0, cos theta_o)`. An isotropic BRDF is symmetric
/// about the plane of `n` and `w_o`, so `B_lm = 0` for `m < 0` (to
/// rounding).
///
/// # Table
///
/// `B` is computed at `ELEVATIONS` (96) view elevations
/// `theta_k = pi/2 sin(pi/2 k/(K-1))`, closer together towards grazing
/// where the BRDF changes fastest, and interpolated in
/// `t = 2/pi asin(2 theta_o / pi)` by Catmull-Rom splines (at `t = 0`,
/// an odd function of `theta`, the point below is the mirror image,
/// `B_lm(-theta) = s_lm B_lm(theta)`
/// with `s_lm = (-1)^m` for `m >= 0` and `-(-1)^m` for `m < 0`; at `pi/2`
/// the point beyond is extrapolated linearly). Each entry integrates over
/// GGX's half-vector sampling map (`shlight_specular::sample_ggx_half`:
/// `phi_h = 2 pi u_x`, `cos^2 theta_h = (1 - u_y) / (1 + (alpha^2 - 1)
/// u_y)`, density `D(h) (n.h)`), where
/// `B_lm = int int 4 V F mu_i (w_o.h) / (n.h) Y_lm(w_i) du_x du_y` with
/// `w_i = 2 (w_o.h) h - w_o`. The reflection is above the surface for
/// `theta_h < delta/2 + pi/4`, `tan delta = sin theta_o cos phi_h / cos
/// theta_o` (as `mu_i = cos theta_o cos 2 theta_h + sin theta_o cos phi_h
/// sin 2 theta_h`), so each azimuth integrates exactly that range; the
/// azimuths are `QUADRATURE_AZIMUTH`-point (24) Gauss-Legendre over each
/// quarter turn, split where `cos phi_h = 0` (there, at grazing views, the
/// cut swings within about `mu_o` of it); the elevations are
/// `QUADRATURE_ELEVATION`-point (48) Gauss-Legendre in `s = sqrt(1 - u_y)`
/// (`cos theta_h = s / sqrt(alpha^2 + (1 - alpha^2) s^2)`, smooth where
/// the lobe's tail is steep in `u_y`). Accumulated in `f64`.
///
/// # Without the rotation: directions in the vertex's frame
///
/// The GPU evaluates the same sum without rotating `T`
/// ([`GgxLobe::direction_table`]). In the local frame, `K = lmax + 1`
/// fixed directions `d_k = (sin psi_k, 0, cos psi_k)`, `psi_k = pi (k +
/// 1/2) / K`, lie in the plane of symmetry, where every `Y_lm` with
/// `m < 0` vanishes. For each band `l` and elevation the weights `w_lk`
/// with `sum_k w_lk Y_lm(d_k) = B_lm` (`m = 0..l`; the least-norm solution
/// of `l + 1` equations in `K` unknowns) give
/// `sum_m B_lm T'_lm = sum_k w_lk T_l(F d_k)`, where `T_l(d) = sum_m T_lm
/// Y_lm(d)` is band `l` of the transferred radiance at the world direction
/// `F d_k` (`F` the vertex's frame): `K` evaluations of `T`'s bands per
/// vertex instead of a rotation. The weights are linear in `B`, so
/// interpolating them is interpolating `B`.
#[derive(Clone, Debug, PartialEq)]
pub struct GgxLobe {
    lmax: usize,
    /// `ELEVATIONS + 2` rows of `(lmax+1)^2` coefficients: row `k + 1`
    /// `B_lm(theta_k)`, row 0 and the last the splines' end points (the
    /// mirror image below `theta = 0`, the linear extrapolation beyond
    /// `pi/2`; [`GgxLobe`]).
    table: Vec<f64>,
}

impl GgxLobe {
    /// Tabulates the lobe of linear roughness `alpha` (from [`MIN_GGX_ALPHA`]
    /// to 1) and Fresnel reflectance at normal incidence `f0` (0 to 1) to
    /// `lmax` (the elevations in parallel).
    ///
    /// # Panics
    /// If `alpha` or `f0` is out of its range.
    #[must_use]
    pub fn new(lmax: usize, alpha: f64, f0: f64) -> Self {
        assert!(
            (MIN_GGX_ALPHA..=1.0).contains(&alpha) && (0.0..=1.0).contains(&f0),
            "GGX alpha {alpha}, F0 {f0}"
        );
        let nc = sh_count(lmax);
        let nodes: Vec<f64> = (0..ELEVATIONS)
            .into_par_iter()
            .flat_map_iter(|k| project(lmax, alpha, f0, elevation(k)))
            .collect();
        let node = |k: usize| &nodes[k * nc..][..nc];
        let mut table = Vec::with_capacity((ELEVATIONS + 2) * nc);
        table.extend((0..nc).map(|i| mirror_sign(i) * node(1)[i]));
        table.extend_from_slice(&nodes);
        table.extend((0..nc).map(|i| 2.0 * node(ELEVATIONS - 1)[i] - node(ELEVATIONS - 2)[i]));
        Self { lmax, table }
    }

    /// Row `r` of the table ([`GgxLobe::direction_table`]'s rows).
    fn row(&self, r: usize) -> &[f64] {
        let nc = sh_count(self.lmax);
        &self.table[r * nc..][..nc]
    }

    /// The highest degree tabulated.
    #[must_use]
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// `B_lm(theta_o)` for `cos theta_o = mu_o`, interpolated (all zero
    /// where `mu_o <= 0`), into `out[l(l+1)+m]` for `l <= lmax`.
    ///
    /// # Panics
    /// If `out` is shorter than `(lmax+1)^2`.
    pub fn projection(&self, mu_o: f64, out: &mut [f64]) {
        let nc = sh_count(self.lmax);
        let out = &mut out[..nc];
        if mu_o.is_nan() || mu_o <= 0.0 {
            out.fill(0.0);
            return;
        }
        // theta = pi/2 sin(pi/2 t), t = x / (K - 1).
        let x = (mu_o.min(1.0).acos() / FRAC_PI_2).asin() / FRAC_PI_2 * (ELEVATIONS - 1) as f64;
        let k = (x.floor() as usize).min(ELEVATIONS - 2);
        let t = x - k as f64;
        // Catmull-Rom weights of the points k-1, k, k+1, k+2.
        let (t2, t3) = (t * t, t * t * t);
        let w = [
            0.5 * (-t3 + 2.0 * t2 - t),
            0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
            0.5 * (-3.0 * t3 + 4.0 * t2 + t),
            0.5 * (t3 - t2),
        ];
        // Nodes k - 1 .. k + 2 are rows k .. k + 3.
        let rows = [0, 1, 2, 3].map(|j| self.row(k + j));
        for (i, o) in out.iter_mut().enumerate() {
            *o = (0..4).map(|j| w[j] * rows[j][i]).sum();
        }
    }

    /// The exit radiance `sum_lm B_lm(theta_o) T'_lm` at a vertex with
    /// unit normal `n` seen from the unit direction `w_o`, `t` its
    /// transferred radiance in the global frame (`(lmax+1)^2` RGB
    /// coefficients; [`GgxLobe`]). `b` is scratch of
    /// `(lmax+1)^2` values.
    ///
    /// # Panics
    /// If `t` or `b` is shorter than `(lmax+1)^2`.
    #[must_use]
    pub fn exit_radiance(&self, n: DVec3, w_o: DVec3, t: &[DVec3], b: &mut [f64]) -> DVec3 {
        let nc = sh_count(self.lmax);
        let mu_o = n.dot(w_o);
        if mu_o.is_nan() || mu_o <= 0.0 {
            return DVec3::ZERO;
        }
        self.projection(mu_o, b);
        let tangent = (w_o - mu_o * n)
            .try_normalize()
            .unwrap_or_else(|| n.any_orthonormal_vector());
        let frame = DMat3::from_cols(tangent, n.cross(tangent), n);
        // T'(d) = T(frame d): the rotation by frame^T.
        let local = rotate_once(
            &ShCoeffs::from_vec(t[..nc].to_vec()).expect("(lmax+1)^2 coefficients"),
            frame.transpose(),
        );
        local
            .as_slice()
            .iter()
            .zip(&b[..nc])
            .map(|(t, b)| *t * *b)
            .sum()
    }

    /// The table of direction weights `w_lk` ([`GgxLobe`]) the
    /// GPU reads, `f32`: `ELEVATIONS + 2` rows (row `r + 1` the elevation
    /// `theta_r`; row 0 and the last the points below `theta = 0` and
    /// beyond `pi/2` that [`GgxLobe::projection`]'s splines use), each of
    /// `lmax + 1` bands of `K = lmax + 1` weights: row `r`, band `l`,
    /// direction `k` at `(r (lmax + 1) + l) K + k`. Catmull-Rom over rows
    /// `k .. k + 3` with [`GgxLobe::projection`]'s `k` and `t` gives the
    /// weights of `B(theta_o)`.
    #[must_use]
    pub fn direction_table(&self) -> Vec<f32> {
        let solve = DirectionSolve::new(self.lmax);
        (0..ELEVATIONS + 2)
            .flat_map(|r| solve.weights(self.row(r)))
            .map(|w| w as f32)
            .collect()
    }
}

/// `psi_k = pi (k + 1/2) / K`, the angle from the normal of direction `k`
/// of `count` in the vertex frame's plane of symmetry.
fn direction_angle(k: usize, count: usize) -> f64 {
    core::f64::consts::PI * (k as f64 + 0.5) / count as f64
}

/// The least-norm weights `w_lk` of [`GgxLobe::direction_table`] for one
/// lmax: per band, `A_l^T (A_l A_l^T)^-1` with `A_l[m][k] = Y_lm(d_k)`.
struct DirectionSolve {
    lmax: usize,
    /// Per band, the `K x (l + 1)` matrix, row-major.
    maps: Vec<Vec<f64>>,
}

impl DirectionSolve {
    fn new(lmax: usize) -> Self {
        let k_count = lmax + 1;
        let basis = ShBasis::<f64>::new(lmax);
        let mut y = vec![0.0; sh_count(lmax)];
        // a[k][i]: Y_i at direction k.
        let a: Vec<Vec<f64>> = (0..k_count)
            .map(|k| {
                let (sin, cos) = direction_angle(k, k_count).sin_cos();
                basis.eval(DVec3::new(sin, 0.0, cos), &mut y);
                y.clone()
            })
            .collect();
        let maps = (0..=lmax)
            .map(|l| {
                let m_count = l + 1;
                let at = |m: usize, k: usize| a[k][l * (l + 1) + m];
                // G = A A^T, (l+1) x (l+1); its inverse by Gauss-Jordan.
                let mut g: Vec<f64> = (0..m_count * m_count)
                    .map(|e| {
                        let (r, c) = (e / m_count, e % m_count);
                        (0..k_count).map(|k| at(r, k) * at(c, k)).sum()
                    })
                    .collect();
                let mut inv: Vec<f64> = (0..m_count * m_count)
                    .map(|e| f64::from(u8::from(e / m_count == e % m_count)))
                    .collect();
                for col in 0..m_count {
                    let pivot = (col..m_count)
                        .max_by(|&x, &y| {
                            g[x * m_count + col]
                                .abs()
                                .total_cmp(&g[y * m_count + col].abs())
                        })
                        .expect("a row");
                    for c in 0..m_count {
                        g.swap(col * m_count + c, pivot * m_count + c);
                        inv.swap(col * m_count + c, pivot * m_count + c);
                    }
                    let p = g[col * m_count + col];
                    for c in 0..m_count {
                        g[col * m_count + c] /= p;
                        inv[col * m_count + c] /= p;
                    }
                    for r in 0..m_count {
                        if r != col {
                            let f = g[r * m_count + col];
                            for c in 0..m_count {
                                g[r * m_count + c] -= f * g[col * m_count + c];
                                inv[r * m_count + c] -= f * inv[col * m_count + c];
                            }
                        }
                    }
                }
                // A^T G^-1: K x (l+1).
                (0..k_count * m_count)
                    .map(|e| {
                        let (k, m) = (e / m_count, e % m_count);
                        (0..m_count).map(|j| at(j, k) * inv[j * m_count + m]).sum()
                    })
                    .collect()
            })
            .collect();
        Self { lmax, maps }
    }

    /// Band-major weights (`l (lmax + 1) + k`) of the projection `b`
    /// (`(lmax+1)^2` coefficients, those with `m < 0` ignored).
    fn weights(&self, b: &[f64]) -> Vec<f64> {
        let k_count = self.lmax + 1;
        let mut out = vec![0.0; k_count * k_count];
        for (l, map) in self.maps.iter().enumerate() {
            let m_count = l + 1;
            for k in 0..k_count {
                out[l * k_count + k] = (0..m_count)
                    .map(|m| map[k * m_count + m] * b[l * (l + 1) + m])
                    .sum();
            }
        }
        out
    }
}

/// Elevation `k` of the table, `pi/2 sin(pi/2 k/(K-1))`.
fn elevation(k: usize) -> f64 {
    FRAC_PI_2 * (FRAC_PI_2 * k as f64 / (ELEVATIONS - 1) as f64).sin()
}

/// `s_lm`: `Y_lm` of the mirror image `(-x, y, z)` is `s_lm Y_lm`.
fn mirror_sign(i: usize) -> f64 {
    let (_, m) = lm_from_index(i);
    let odd = m.unsigned_abs() % 2 == 1;
    match (m >= 0, odd) {
        (true, false) | (false, true) => 1.0,
        _ => -1.0,
    }
}

/// `B_lm(theta_o)` by the product rule over the half-vector sampling map
/// ([`GgxLobe`]).
fn project(lmax: usize, alpha: f64, f0: f64, theta_o: f64) -> Vec<f64> {
    let nc = sh_count(lmax);
    let basis = ShBasis::<f64>::new(lmax);
    let (sin_o, cos_o) = theta_o.sin_cos();
    let w_o = DVec3::new(sin_o, 0.0, cos_o);
    let mu_o = cos_o.max(0.0);
    let (nodes, weights) = gauss_legendre(QUADRATURE_ELEVATION);
    let (turn_nodes, turn_weights) = gauss_legendre(QUADRATURE_AZIMUTH);
    let a2 = alpha * alpha;
    let mut y = vec![0.0; nc];
    let mut sum = vec![0.0; nc];
    // Quarter turns, split where cos phi = 0: there the cut swings from
    // one side to the other, within about mu_o of it.
    let azimuths = (0..4).flat_map(|q| {
        turn_nodes.iter().zip(&turn_weights).map(move |(x, w)| {
            (
                FRAC_PI_2 * (q as f64 + 0.5 * (x + 1.0)),
                // d u_x = d phi / 2 pi.
                w * 0.5 * FRAC_PI_2 / TAU,
            )
        })
    });
    for (phi, w_phi) in azimuths {
        let (sin_phi, cos_phi) = phi.sin_cos();
        // mu_i = cos_o cos 2t + sin_o cos phi sin 2t = A cos(2t - delta):
        // above the surface for half-vector elevations t < delta/2 + pi/4.
        let cut = (0.5 * (sin_o * cos_phi).atan2(cos_o) + FRAC_PI_4).min(FRAC_PI_2);
        let c = cut.cos();
        // s = sqrt(1 - u.y) where the cut lies.
        let s_cut = (c * alpha / (1.0 - c * c * (1.0 - a2)).sqrt()).min(1.0);
        let half = 0.5 * (1.0 - s_cut);
        for (x, wx) in nodes.iter().zip(&weights) {
            let s = s_cut + half * (x + 1.0);
            // cos^2 t = (1 - u.y) / (1 + (alpha^2 - 1) u.y) with u.y = 1 - s^2.
            let cos_h = s / (a2 + (1.0 - a2) * s * s).sqrt();
            let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
            let h = DVec3::new(sin_h * cos_phi, sin_h * sin_phi, cos_h);
            let o_h = w_o.dot(h);
            if o_h <= 0.0 || cos_h <= 0.0 {
                continue;
            }
            let w_i = (2.0 * o_h * h - w_o).normalize();
            let mu_i = w_i.z;
            if mu_i <= 0.0 {
                continue;
            }
            let fresnel = f0 + (1.0 - f0) * (1.0 - o_h).powi(5);
            // d u.y = 2 s ds.
            let weight = 4.0
                * MaskingShadowing::HeightCorrelated.eval(mu_o, mu_i, alpha)
                * fresnel
                * mu_i
                * o_h
                / cos_h
                * (2.0 * s * half * wx * w_phi);
            basis.eval(w_i, &mut y);
            for (acc, v) in sum.iter_mut().zip(&y) {
                *acc += weight * v;
            }
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`GgxLobe::exit_radiance`] evaluated as the GPU does (`mesh.wgsl`'s
    /// `ggx_layer`), through the direction weights instead of a rotation.
    fn exit_radiance_by_directions(lobe: &GgxLobe, n: DVec3, w_o: DVec3, t: &[DVec3]) -> DVec3 {
        let lmax = lobe.lmax;
        let nc = sh_count(lmax);
        let mu_o = n.dot(w_o);
        if mu_o <= 0.0 {
            return DVec3::ZERO;
        }
        let mut b = vec![0.0; nc];
        lobe.projection(mu_o, &mut b);
        let weights = DirectionSolve::new(lmax).weights(&b);
        let tangent = (w_o - mu_o * n)
            .try_normalize()
            .unwrap_or_else(|| n.any_orthonormal_vector());
        let k_count = lmax + 1;
        let basis = ShBasis::<f64>::new(lmax);
        let mut y = vec![0.0; nc];
        let mut sum = DVec3::ZERO;
        for k in 0..k_count {
            let (sin, cos) = direction_angle(k, k_count).sin_cos();
            basis.eval(tangent * sin + n * cos, &mut y);
            for l in 0..=lmax {
                let band: DVec3 = (l * l..(l + 1) * (l + 1)).map(|i| t[i] * y[i]).sum();
                sum += weights[l * k_count + k] * band;
            }
        }
        sum
    }

    /// The mirror signs are those of the basis itself.
    #[test]
    fn mirror_signs_match_the_basis() {
        let basis = ShBasis::<f64>::new(6);
        let d = DVec3::new(0.3, -0.5, 0.2).normalize();
        let (mut a, mut b) = (vec![0.0; 49], vec![0.0; 49]);
        basis.eval(d, &mut a);
        basis.eval(DVec3::new(-d.x, d.y, d.z), &mut b);
        for i in 0..49 {
            assert!((b[i] - mirror_sign(i) * a[i]).abs() < 1e-12, "{i}");
        }
    }

    /// The plane of `n` and `w_o` is a mirror of the lobe: `B_lm` with
    /// `m < 0` vanish; and the table's rows are the projection itself at
    /// the tabulated elevations.
    #[test]
    fn odd_coefficients_vanish_and_nodes_interpolate_exactly() {
        let lobe = GgxLobe::new(4, 0.3, 1.0);
        let mut b = vec![0.0; 25];
        for k in [0, 17, 40, 94, 95] {
            lobe.projection(elevation(k).cos(), &mut b);
            let direct = project(4, 0.3, 1.0, elevation(k));
            for i in 0..25 {
                assert!((b[i] - direct[i]).abs() < 1e-9, "k {k} i {i}");
                if lm_from_index(i).1 < 0 {
                    assert!(b[i].abs() < 1e-12, "k {k} i {i}: {}", b[i]);
                }
            }
        }
        lobe.projection(-0.2, &mut b);
        assert!(b.iter().all(|&x| x == 0.0));
    }

    /// The directions' weights give the rotation's value, at every lmax
    /// the GPU shades, for views from the normal to grazing; and their
    /// table holds the tabulated elevations' weights.
    #[test]
    fn directions_give_the_rotations_value() {
        for lmax in [0, 1, 2, 4, 8] {
            let lobe = GgxLobe::new(lmax, 0.3, 0.04);
            let nc = sh_count(lmax);
            let t: Vec<DVec3> = (0..nc)
                .map(|i| {
                    DVec3::new(1.0, 0.5, -0.3) * (1.0 + i as f64).recip()
                        + DVec3::X * f64::from(u8::from(i == 0))
                })
                .collect();
            let n = DVec3::new(0.2, 0.9, -0.4).normalize();
            let mut b = vec![0.0; nc];
            for mu in [1.0, 0.9, 0.5, 0.1, 0.01] {
                let side = n.any_orthonormal_vector();
                let w_o = mu * n + (1.0f64 - mu * mu).sqrt() * side;
                let want = lobe.exit_radiance(n, w_o, &t, &mut b);
                let got = exit_radiance_by_directions(&lobe, n, w_o, &t);
                let scale = want.abs().max_element().max(1e-3);
                assert!(
                    (got - want).abs().max_element() < 1e-9 * scale,
                    "lmax {lmax} mu {mu}: {got} vs {want}"
                );
            }
            let table = lobe.direction_table();
            let k_count = lmax + 1;
            assert_eq!(table.len(), (ELEVATIONS + 2) * k_count * k_count);
            let solve = DirectionSolve::new(lmax);
            let w = solve.weights(&lobe.table[6 * nc..][..nc]);
            for (x, y) in table[6 * k_count * k_count..][..k_count * k_count]
                .iter()
                .zip(&w)
            {
                assert_eq!(*x, *y as f32);
            }
        }
    }
}

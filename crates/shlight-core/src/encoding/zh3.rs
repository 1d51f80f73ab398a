//! ZH3: linear SH plus one quadratic zonal coefficient per channel
//! (Roughton, Sloan, Silvennoinen, Iwanicki and Shirley, *ZH3: Quadratic
//! Zonal Harmonics*, i3D 2024 / HPG 2024, <https://torust.me/ZH3.pdf>).

use core::f64::consts::PI;

use glam::DVec3;

use crate::encoding::channel_values::{band1_vector, from_f64, luminance_weights, to_f64};
use crate::sh::real::Real;
use crate::sh::real::dir_f64;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// The two ways of obtaining the zonal coefficient.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Zh3Kind {
    /// Projected from the degree-2 band (needs lmax >= 2).
    Stored,
    /// The paper's curve fit from degree 0 and 1 alone.
    Hallucinated,
}

/// A ZH3 encoding of radiance: lmax-1 coefficients, the luminance axis and
/// one zonal degree-2 coefficient per channel (the formulas below).
///
/// The degree-2 band of the radiance is replaced by a single zonal harmonic
/// about the **luminance axis** `a`, the direction of the luminance's
/// degree-1 vector `Σ_c w_c v_c` (`w` the Rec.709 weights, `v_c =
/// (-f_1^1, -f_1^-1, f_1^0)` per channel, which with the Condon-Shortley
/// phase points along `∫ L ω dω`). Per channel it stores the four lmax-1
/// coefficients and one number `z`, so 4 + 1 floats per channel instead of 9:
///
/// - **stored**: `z = sqrt(4π/5) Σ_m f_2^m Y_2^m(a)`, the orthogonal
///   projection of the band onto the unit-norm zonal harmonic about `a`
///   (exact when the band is zonal about `a`);
/// - **hallucinated** (the paper's §3.4.3 curve fit, from lmax 1 alone):
///   `r = |v · a| / f_0^0`, `z = f_0^0 (0.08 r + 0.6 r²)`.
///
/// Irradiance is the linear part convolved with the clamped cosine plus
/// the zonal term,
///
/// ```text
/// E(n) = A_0 f_0^0 Y_0^0 + A_1 Σ_m f_1^m Y_1^m(n) + A_2 z sqrt(5/(16π)) (3 (a·n)² - 1)
/// ```
///
/// with `A_0 = π`, `A_1 = 2π/3`, `A_2 = π/4` (Ramamoorthi & Hanrahan
/// 2001). The engines' shader versions (the paper's sample code, MJP's
/// SH.hlsli) write the same sum.
#[derive(Clone, Debug, PartialEq)]
pub struct Zh3<C> {
    /// The four lmax-1 radiance coefficients, flat index order.
    pub l1: [C; 4],
    /// The unit luminance axis `a` (world axes).
    pub axis: DVec3,
    /// The zonal degree-2 coefficient `z` per channel.
    pub zonal: C,
}

impl<C: ShValue> Zh3<C> {
    /// Encodes radiance coefficients `f` (lmax >= 1; >= 2 for
    /// [`Zh3Kind::Stored`], else `None`).
    #[must_use]
    pub fn new(f: &ShCoeffs<C>, kind: Zh3Kind) -> Option<Self> {
        if f.lmax() < 1 || (kind == Zh3Kind::Stored && f.lmax() < 2) {
            return None;
        }
        let s = f.as_slice();
        let axis = luminance_axis(s);
        let mut z = [0.0; 3];
        match kind {
            Zh3Kind::Stored => {
                let y = crate::sh::basis::sh_eval(2, axis);
                let norm = (4.0 * PI / 5.0).sqrt();
                for (i, yi) in y.iter().enumerate().skip(4) {
                    let fi = to_f64(s[i]);
                    for (zc, fc) in z.iter_mut().zip(fi) {
                        *zc += norm * fc * yi;
                    }
                }
            }
            Zh3Kind::Hallucinated => {
                let f0 = to_f64(s[0]);
                for (c, zc) in z.iter_mut().enumerate().take(C::CHANNELS) {
                    if f0[c] > 0.0 {
                        let r = band1_vector(s, c).dot(axis).abs() / f0[c];
                        *zc = f0[c] * (0.08 * r + 0.6 * r * r);
                    }
                }
            }
        }
        Some(Self {
            l1: [s[0], s[1], s[2], s[3]],
            axis,
            zonal: from_f64(z),
        })
    }

    /// Irradiance `E(n)` at unit normal `n` ([`Zh3`]).
    #[must_use]
    pub fn irradiance(&self, n: <C::Scalar as Real>::Vec3) -> C {
        let n = dir_f64::<C::Scalar>(n);
        let y = crate::sh::basis::sh_eval(1, n);
        let t = self.axis.dot(n);
        let zh = (5.0 / (16.0 * PI)).sqrt() * (3.0 * t * t - 1.0);
        let mut e = [0.0; 3];
        let c = self.l1.map(to_f64);
        let z = to_f64(self.zonal);
        for k in 0..C::CHANNELS {
            e[k] = PI * c[0][k] * y[0]
                + 2.0 * PI / 3.0 * (c[1][k] * y[1] + c[2][k] * y[2] + c[3][k] * y[3])
                + PI / 4.0 * z[k] * zh;
        }
        from_f64(e)
    }

    /// The lmax-2 radiance coefficients ZH3 stands for: degree 0 and 1 as
    /// stored, degree 2 the zonal harmonic `z sqrt(4π/5) Y_2^m(a)`. Any
    /// lmax-2 evaluator (a shader, an engine) shades ZH3 through these.
    #[must_use]
    pub fn to_sh(&self) -> ShCoeffs<C> {
        let mut f = ShCoeffs::zeros(2);
        f.as_mut_slice()[..4].copy_from_slice(&self.l1);
        let y = crate::sh::basis::sh_eval(2, self.axis);
        let norm = (4.0 * PI / 5.0).sqrt();
        let z = to_f64(self.zonal);
        for (i, yi) in y.iter().enumerate().skip(4) {
            f[i] = from_f64(z.map(|zc| zc * norm * yi));
        }
        f
    }

    /// Floats stored: 4 + 1 per channel (the axis follows from the
    /// stored lmax-1 coefficients).
    #[must_use]
    pub fn floats(&self) -> usize {
        5 * C::CHANNELS
    }

    /// The zonal coefficient's kind is not kept: this rebuilds a ZH3 from
    /// its stored parts, the axis recomputed from `l1`.
    #[must_use]
    pub fn from_parts(l1: [C; 4], zonal: C) -> Self {
        Self {
            axis: luminance_axis(&l1),
            l1,
            zonal,
        }
    }
}

/// The unit direction of the luminance's degree-1 vector; `+z` when it is
/// zero (the zonal term then carries no direction of its own).
fn luminance_axis<C: ShValue>(s: &[C]) -> DVec3 {
    let w = luminance_weights::<C>();
    let mut v = DVec3::ZERO;
    for (c, wc) in w.iter().enumerate().take(C::CHANNELS) {
        v += band1_vector(s, c) * *wc;
    }
    v.try_normalize().unwrap_or(DVec3::Z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::closed_form;
    use crate::sh::quadrature::fibonacci_sphere;
    use crate::sh::zonal::irradiance;

    /// Rounding of a few dozen f64 terms.
    const EXACT: f64 = 1e-12;

    #[test]
    fn stored_zh3_is_exact_for_a_zonal_light_about_the_luminance_axis() {
        let axis = DVec3::new(0.3, -0.5, 0.8).normalize();
        // A coloured cap plus a constant: every channel zonal about `axis`.
        let f = &closed_form::cap(4, axis, 0.7, DVec3::new(1.0, 0.5, 0.2))
            + &closed_form::constant(4, DVec3::new(0.1, 0.2, 0.3));
        let zh3 = Zh3::new(&f, Zh3Kind::Stored).unwrap();
        assert!((zh3.axis - axis).length() < EXACT, "{:?}", zh3.axis);
        let e2 = irradiance(&f.resized(2));
        for n in fibonacci_sphere(200) {
            let d = zh3.irradiance(n) - e2.eval(n);
            assert!(d.abs().max_element() < EXACT, "{n}: {d}");
        }
        // Not exact once the band has a part that is not zonal about a.
        let g = &f + &closed_form::directional(4, DVec3::X, DVec3::splat(0.3));
        let zh3 = Zh3::new(&g, Zh3Kind::Stored).unwrap();
        let e2 = irradiance(&g.resized(2));
        let worst = fibonacci_sphere(200)
            .into_iter()
            .map(|n| (zh3.irradiance(n) - e2.eval(n)).abs().max_element())
            .fold(0.0, f64::max);
        assert!(worst > 1e-3, "{worst}");
    }

    #[test]
    fn to_sh_shades_the_same_as_the_irradiance() {
        let f = &closed_form::cap(2, DVec3::Y, 0.4, DVec3::new(2.0, 1.0, 0.5))
            + &closed_form::directional(2, DVec3::new(1.0, 1.0, 0.0).normalize(), DVec3::ONE);
        for kind in [Zh3Kind::Stored, Zh3Kind::Hallucinated] {
            let zh3 = Zh3::new(&f, kind).unwrap();
            let e = irradiance(&zh3.to_sh());
            for n in fibonacci_sphere(100) {
                assert!((e.eval(n) - zh3.irradiance(n)).abs().max_element() < EXACT);
            }
        }
    }

    /// The hallucinated term as the paper's sample code writes it, for one
    /// channel in the Condon-Shortley basis (`sh[0..4]`, the cosine lobe
    /// folded into L0/L1, the zonal term times `A_2 = π/4`).
    fn paper_hallucinated(sh: [f64; 4], lum_axis: DVec3, n: DVec3) -> f64 {
        let v = DVec3::new(-sh[3], -sh[1], sh[2]);
        let ratio = v.dot(lum_axis).abs() / sh[0];
        let zonal = sh[0] * (0.08 * ratio + 0.6 * ratio * ratio);
        let fz = lum_axis.dot(n);
        let zh_dir = (5.0 / (16.0 * PI)).sqrt() * (3.0 * fz * fz - 1.0);
        let lobe = [
            0.886_226_925_452_758,
            -1.023_326_707_946_488_5 * n.y,
            1.023_326_707_946_488_5 * n.z,
            -1.023_326_707_946_488_5 * n.x,
        ];
        let linear: f64 = sh.iter().zip(lobe).map(|(a, b)| a * b).sum();
        linear + PI * 0.25 * zonal * zh_dir
    }

    #[test]
    fn hallucinated_zh3_is_the_papers_fit_from_lmax_1_alone() {
        let f = &closed_form::cap(
            3,
            DVec3::new(0.2, 0.9, -0.3).normalize(),
            0.3,
            DVec3::new(4.0, 3.0, 1.0),
        ) + &closed_form::constant(3, DVec3::new(0.3, 0.4, 0.6));
        let full = Zh3::new(&f, Zh3Kind::Hallucinated).unwrap();
        let l1_only = Zh3::new(&f.resized(1), Zh3Kind::Hallucinated).unwrap();
        assert_eq!(full, l1_only, "degree 2 and above must not matter");
        assert!(Zh3::new(&f.resized(1), Zh3Kind::Stored).is_none());
        let s = f.as_slice();
        let lum = |v: DVec3| 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z;
        let axis = DVec3::new(-lum(s[3]), -lum(s[1]), lum(s[2])).normalize();
        for n in fibonacci_sphere(100) {
            let got = full.irradiance(n);
            for c in 0..3 {
                let sh = [s[0][c], s[1][c], s[2][c], s[3][c]];
                let want = paper_hallucinated(sh, axis, n);
                assert!(
                    (got[c] - want).abs() < 1e-9 * want.abs().max(1.0),
                    "{n} {c}"
                );
            }
        }
    }

    #[test]
    fn f32_and_f64_agree() {
        let f = closed_form::cap(2, DVec3::Z, 0.5, DVec3::new(1.0, 0.7, 0.4));
        let f32c: ShCoeffs<glam::Vec3> = f.map(|c| c.as_vec3());
        let a = Zh3::new(&f, Zh3Kind::Stored).unwrap();
        let b = Zh3::new(&f32c, Zh3Kind::Stored).unwrap();
        for n in fibonacci_sphere(20) {
            let d = a.irradiance(n) - b.irradiance(n.as_vec3()).as_dvec3();
            assert!(d.abs().max_element() < 1e-5);
        }
    }
}

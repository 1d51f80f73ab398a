//! The non-linear reconstruction of diffuse lighting from L0 and L1 SH of
//! Geomerics (Hu, "Reconstructing Diffuse Lighting from Spherical
//! Harmonics", CEDEC 2015; the shaders' comments cite
//! `geomerics.com/wp-content/uploads/2015/08/CEDEC_Geomerics_ReconstructingDiffuseLighting1.pdf`),
//! as Bakery's `shEvaluateDiffuseL1Geomerics` writes it.

use glam::Vec3;

/// One channel of diffuse lighting at unit normal `n` from its linear
/// form `l0 + l1 . n`, reshaped so that it never goes negative: a port of
/// `shEvaluateDiffuseL1Geomerics(L0, L1, n)`, in `f32` as the shader runs,
/// line by line:
///
/// ```text
/// R0    = L0                                   // average energy
/// R1    = 0.5 L1                               // avg direction of incoming light
/// lenR1 = length(R1)                           // directional brightness
/// q     = dot(normalize(R1), n) * 0.5 + 0.5    // linear angle, 0..1
/// p     = 1 + 2 lenR1 / R0                     // 1 (linear) to 3 (cubic)
/// a     = (1 - lenR1 / R0) / (1 + lenR1 / R0)  // dynamic range constant
/// f     = R0 (a + (1 - a) (p + 1) q^p)
/// ```
///
/// Its own properties, which the tests check: the mean of `f` over all
/// normals is `R0` (`int q^p dw = 4 pi / (p + 1)`), the mean of the
/// linear form too; for `lenR1 <= R0` (radiance nowhere negative) `f >= 0`;
/// for one directional light (`lenR1 = R0`) `f = R0 4 q^3`, the light's
/// irradiance `max(cos, 0)` to within `R0 / 2` (an eighth of its peak),
/// where the linear form is off by up to `R0`.
///
/// Where the shader's arithmetic breaks down this port picks the value
/// the formula tends to: `q` is clamped to `0..=1` (the `saturate` later
/// copies add; it changes nothing for a unit `n` beyond rounding);
/// `R1 = 0` (HLSL's `normalize` gives NaN) takes `q = 1/2`, which the
/// result does not depend on since `1 - a = 0`; `R0 <= 0` (a black or
/// non-physical texel, a division by zero in the shader) gives 0.
#[must_use]
pub fn geomerics_l1(l0: f32, l1: Vec3, n: Vec3) -> f32 {
    let r0 = l0;
    if r0 <= 0.0 {
        return 0.0;
    }
    let r1 = 0.5 * l1;
    let len_r1 = r1.length();
    let q = if len_r1 > 0.0 {
        (r1 / len_r1).dot(n) * 0.5 + 0.5
    } else {
        0.5
    };
    let q = q.clamp(0.0, 1.0);
    let p = 1.0 + 2.0 * len_r1 / r0;
    let a = (1.0 - len_r1 / r0) / (1.0 + len_r1 / r0);
    r0 * (a + (1.0 - a) * (p + 1.0) * q.powf(p))
}

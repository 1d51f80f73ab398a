//! The irradiance a texel's lmax-1 radiance SH stands for, as the linear
//! form `E(n) = a + b . n` per channel that every SH lightmap stores in
//! one packing or another, in the units an engine reads.

use core::f64::consts::PI;

use glam::DVec3;
use shlight_core::sh::ShL1Rgb;

/// What a lightmap texel's value means.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TexelUnits {
    /// Irradiance `E` (W/m² for radiance in W/(m² sr)): three.js, whose
    /// shader multiplies the `lightMap` texel by `BRDF_Lambert = albedo / pi`.
    Irradiance,
    /// `E / pi`, the radiance a white Lambertian surface leaves: Bevy,
    /// Godot and Unity (Bakery), whose shaders multiply the texel by the
    /// albedo alone.
    IrradianceOverPi,
}

impl TexelUnits {
    /// The factor from irradiance to these units: 1 or `1/pi`.
    #[must_use]
    pub fn scale(self) -> f64 {
        match self {
            Self::Irradiance => 1.0,
            Self::IrradianceOverPi => 1.0 / PI,
        }
    }
}

/// Irradiance to lmax 1 as a linear function of the unit normal, per RGB
/// channel: `E_c(n) = constant_c + linear_c . n` (x, y, z in world axes).
///
/// From radiance `L` in shlight's basis (Condon-Shortley phase, so
/// `Y_1^-1 = -c y`, `Y_1^0 = c z`, `Y_1^1 = -c x`, `c = sqrt(3/(4 pi))`)
/// and Ramamoorthi & Hanrahan's `E(n) = A_0 L_0^0 Y_0^0 + A_1 sum_m
/// L_1^m Y_1^m(n)`, `A_0 = pi`, `A_1 = 2 pi / 3`:
///
/// ```text
/// constant = A_0 Y_0^0 L_0^0          = (sqrt(pi) / 2) L_0^0
/// linear   = A_1 c (-L_1^1, -L_1^-1, L_1^0) = sqrt(pi / 3) (-L_1^1, -L_1^-1, L_1^0)
/// ```
///
/// times [`TexelUnits::scale`]. For radiance that is nowhere negative,
/// `|linear_c| <= 2 constant_c` (the first moment of a non-negative
/// function is at most its integral), with equality for a single
/// directional light: the bound every packing below relies on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseL1 {
    /// `a_c`: red, green, blue in `x`, `y`, `z`; the mean of `E_c` over
    /// all normals.
    pub constant: DVec3,
    /// `b_c` for red, green and blue: the gradient of `E_c` in the normal.
    pub linear: [DVec3; 3],
}

impl DiffuseL1 {
    /// The linear form of the irradiance of radiance `sh`, in `units`.
    #[must_use]
    pub fn from_radiance(sh: &ShL1Rgb<f64>, units: TexelUnits) -> Self {
        let k0 = 0.5 * PI.sqrt() * units.scale();
        let k1 = (PI / 3.0).sqrt() * units.scale();
        let lin = |f: &[f64; 4]| DVec3::new(-f[3], -f[1], f[2]) * k1;
        Self {
            constant: DVec3::new(sh.r[0], sh.g[0], sh.b[0]) * k0,
            linear: [lin(&sh.r), lin(&sh.g), lin(&sh.b)],
        }
    }

    /// `E(n)` per channel (`n` is used as given: pass a unit vector).
    #[must_use]
    pub fn eval(&self, n: DVec3) -> DVec3 {
        self.constant
            + DVec3::new(
                self.linear[0].dot(n),
                self.linear[1].dot(n),
                self.linear[2].dot(n),
            )
    }

    /// The largest `|linear_c| / constant_c` over the channels: at most 2
    /// for radiance that is nowhere negative (infinite where a channel has
    /// a gradient but no mean; 0 for a black texel).
    #[must_use]
    pub fn directionality(&self) -> f64 {
        (0..3)
            .map(|c| {
                let b = self.linear[c].length();
                if b == 0.0 {
                    0.0
                } else if self.constant[c] <= 0.0 {
                    f64::INFINITY
                } else {
                    b / self.constant[c]
                }
            })
            .fold(0.0, f64::max)
    }
}

//! What coefficients hold, and the conversions between radiance and
//! irradiance.

use glam::DVec3;
use shlight_core::sh::{ShCoeffs, clamped_cosine_eigenvalue};

use crate::{FormatError, Result};

/// What a coefficient file's numbers are (docs/conventions.md, "Quantities").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Distant radiance `L(w)`: `L_lm = int L(w) Y_lm(w) dw`.
    Radiance,
    /// Irradiance `E(n) = int L(w) max(n.w, 0) dw`: `E_lm = A_l L_lm`
    /// (Ramamoorthi & Hanrahan 2001).
    Irradiance,
}

impl Quantity {
    /// Both quantities, radiance first.
    pub const ALL: [Quantity; 2] = [Quantity::Radiance, Quantity::Irradiance];

    /// The name files and the command line use: `radiance`, `irradiance`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Radiance => "radiance",
            Quantity::Irradiance => "irradiance",
        }
    }
}

impl std::fmt::Display for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Quantity {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Quantity::ALL
            .into_iter()
            .find(|q| q.name() == s.trim())
            .ok_or_else(|| format!("unknown quantity {s:?} (radiance or irradiance)"))
    }
}

/// The same light as another quantity: irradiance is `A_l` times radiance,
/// band by band. The way back divides by `A_l`, impossible where `A_l = 0`
/// (odd `l > 1`) unless the band is zero too (it is then left zero).
///
/// # Errors
/// [`FormatError::Export`] when irradiance with a non-zero band of odd
/// degree above 1 is turned into radiance.
pub fn convert_quantity(
    coeffs: &ShCoeffs<DVec3>,
    from: Quantity,
    to: Quantity,
) -> Result<ShCoeffs<DVec3>> {
    Ok(match (from, to) {
        (Quantity::Radiance, Quantity::Irradiance) => {
            coeffs.scaled_per_band(clamped_cosine_eigenvalue)
        }
        (Quantity::Irradiance, Quantity::Radiance) => {
            for l in 0..=coeffs.lmax() {
                if clamped_cosine_eigenvalue(l) == 0.0
                    && coeffs.band(l).iter().any(|c| *c != DVec3::ZERO)
                {
                    return Err(FormatError::Export(format!(
                        "radiance cannot be recovered from irradiance at degree {l}: A_{l} = 0 \
                         but the irradiance band is not zero"
                    )));
                }
            }
            coeffs.scaled_per_band(|l| {
                let a = clamped_cosine_eigenvalue(l);
                if a == 0.0 { 0.0 } else { 1.0 / a }
            })
        }
        _ => coeffs.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn irradiance_to_radiance_refuses_what_cannot_be_undone() {
        let mut e = ShCoeffs::<DVec3>::zeros(3);
        e[(3, 1)] = DVec3::ONE;
        let err = convert_quantity(&e, Quantity::Irradiance, Quantity::Radiance).unwrap_err();
        assert!(err.to_string().contains("degree 3"), "{err}");
        let radiance = ShCoeffs::from_fn(2, |l, m| DVec3::splat(1.0 + l as f64 + m as f64 * 0.1));
        let e = convert_quantity(&radiance, Quantity::Radiance, Quantity::Irradiance).unwrap();
        // R&H's A_l: pi, 2pi/3, pi/4.
        let pi = std::f64::consts::PI;
        for (l, a) in [(0, pi), (1, 2.0 * pi / 3.0), (2, pi / 4.0)] {
            for (got, src) in e.band(l).iter().zip(radiance.band(l)) {
                assert!((*got - *src * a).abs().max_element() < 1e-14, "l={l}");
            }
        }
        let back = convert_quantity(&e, Quantity::Irradiance, Quantity::Radiance).unwrap();
        for (a, b) in back.as_slice().iter().zip(radiance.as_slice()) {
            assert!((*a - *b).abs().max_element() < 1e-15);
        }
    }

    #[test]
    fn names_parse_back() {
        for q in Quantity::ALL {
            assert_eq!(q.name().parse::<Quantity>().unwrap(), q);
        }
        assert!("flux".parse::<Quantity>().unwrap_err().contains("flux"));
    }
}

//! [`Brdf`]: the glossy lobe that turns a vertex's transferred radiance
//! into view-dependent exit radiance ([`crate::glossy`]).
//!
//! `phong:S` is the normalised Phong lobe about the mirror direction `R`,
//! `k(t) = (S+1)/(2 pi) max(t, 0)^S` with `t = R.w`: a rotationally
//! symmetric kernel, so convolving the transferred radiance with it scales
//! band `l` by the zonal coefficient
//! `Lambda_l = 2 pi int_{-1}^{1} k(t) P_l(t) dt` (Funk-Hecke;
//! `Lambda_0 = 1`, `Lambda_1 = (S+1)/(S+2)`, `Lambda_2 = S/(S+3)`), the
//! eigenvalues of shlight-core's `ZonalKernel::phong` (Sloan, Kautz &
//! Snyder 2002, §5; Ramamoorthi & Hanrahan 2002).

use shlight_core::sh::ZonalKernel;

/// The largest Phong exponent taken: beyond it the lobe is a mirror to
/// any lmax a bake holds (`Lambda_l` within `l^2 / S` of 1).
pub const MAX_PHONG_EXPONENT: f64 = 1e6;

/// A glossy BRDF, as `--brdf` names it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Brdf {
    /// The normalised Phong lobe of exponent `exponent` (`phong:S`).
    Phong {
        /// `S >= 0`: 0 is a constant lobe over the hemisphere about `R`,
        /// large values a mirror.
        exponent: f64,
    },
}

impl Brdf {
    /// Parses `phong:S` (`S` a number from 0 to [`MAX_PHONG_EXPONENT`]).
    ///
    /// # Errors
    /// A message saying what is wrong with `text` and what is taken.
    pub fn parse(text: &str) -> Result<Self, String> {
        let (name, value) = text.split_once(':').ok_or_else(|| {
            format!("BRDF \"{text}\" is not NAME:VALUE (shlight bakes phong:S, e.g. phong:32)")
        })?;
        match name.trim().to_ascii_lowercase().as_str() {
            "phong" => {
                let exponent: f64 = value.trim().parse().map_err(|_| {
                    format!("BRDF \"{text}\": the Phong exponent \"{value}\" is not a number")
                })?;
                if !(0.0..=MAX_PHONG_EXPONENT).contains(&exponent) {
                    return Err(format!(
                        "BRDF \"{text}\": the Phong exponent must be from 0 to {MAX_PHONG_EXPONENT}"
                    ));
                }
                Ok(Brdf::Phong { exponent })
            }
            other => Err(format!(
                "BRDF \"{text}\": unknown BRDF \"{other}\" (shlight bakes phong:S, e.g. phong:32)"
            )),
        }
    }

    /// The name [`Brdf::parse`] reads back (`phong:32`).
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Brdf::Phong { exponent } => format!("phong:{exponent}"),
        }
    }

    /// The lobe's zonal coefficients `Lambda_l`, `l = 0..=lmax`.
    #[must_use]
    pub fn lambda(&self, lmax: usize) -> Vec<f64> {
        match self {
            Brdf::Phong { exponent } => ZonalKernel::phong(lmax, *exponent).eigenvalues,
        }
    }
}

impl std::fmt::Display for Brdf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phong_strings_parse_and_bad_ones_say_why() {
        let b = Brdf::parse("phong:32").unwrap();
        assert_eq!(b, Brdf::Phong { exponent: 32.0 });
        assert_eq!(Brdf::parse(&b.name()).unwrap(), b);
        let l = b.lambda(2);
        // The closed forms of the first three bands.
        assert!((l[0] - 1.0).abs() < 1e-14);
        assert!((l[1] - 33.0 / 34.0).abs() < 1e-14);
        assert!((l[2] - 32.0 / 35.0).abs() < 1e-14);
        for (text, says) in [
            ("phong", "not NAME:VALUE"),
            ("phong:", "not a number"),
            ("phong:shiny", "not a number"),
            ("phong:-1", "from 0 to"),
            ("phong:NaN", "from 0 to"),
            ("phong:inf", "from 0 to"),
            ("ggx:0.3", "unknown BRDF \"ggx\""),
            ("", "not NAME:VALUE"),
        ] {
            let e = Brdf::parse(text).unwrap_err();
            assert!(e.contains(says), "{text}: {e}");
        }
    }
}

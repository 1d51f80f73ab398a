//! [`Brdf`]: the glossy lobe that turns a vertex's transferred radiance
//! into view-dependent exit radiance ([`crate::GlossyTransfer`]); the
//! lobes are stated on [`Brdf`].

use shlight_core::sh::ZonalKernel;

use crate::ggx_lobe::{GgxLobe, MIN_GGX_ALPHA};

/// The largest Phong exponent taken: beyond it the lobe is a mirror to
/// any lmax a bake holds (`Lambda_l` within `l^2 / S` of 1).
pub const MAX_PHONG_EXPONENT: f64 = 1e6;

/// A glossy BRDF, as `--brdf` names it.
///
/// `phong:S` is the normalised Phong lobe about the mirror direction `R`,
/// `k(t) = (S+1)/(2 pi) max(t, 0)^S` with `t = R.w`: a rotationally
/// symmetric kernel, so convolving the transferred radiance with it scales
/// band `l` by the zonal coefficient
/// `Lambda_l = 2 pi int_{-1}^{1} k(t) P_l(t) dt` (Funk-Hecke;
/// `Lambda_0 = 1`, `Lambda_1 = (S+1)/(S+2)`, `Lambda_2 = S/(S+3)`), the
/// eigenvalues of shlight-core's `ZonalKernel::phong` (Sloan, Kautz &
/// Snyder 2002, §5; Ramamoorthi & Hanrahan 2002).
///
/// `ggx:ALPHA[,F0]` is the Cook-Torrance microfacet BRDF with the GGX
/// distribution of linear roughness `ALPHA`, Smith's height-correlated
/// masking and Schlick's Fresnel of reflectance `F0` at normal incidence
/// (1 when not given), clipped to the hemisphere and weighted by the
/// cosine: not a lobe about `R`, so it is projected onto SH per view
/// elevation and tabulated ([`GgxLobe`] states the definition).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Brdf {
    /// The normalised Phong lobe of exponent `exponent` (`phong:S`).
    Phong {
        /// `S >= 0`: 0 is a constant lobe over the hemisphere about `R`,
        /// large values a mirror.
        exponent: f64,
    },
    /// The GGX microfacet BRDF (`ggx:ALPHA` or `ggx:ALPHA,F0`).
    Ggx {
        /// Linear roughness, from [`MIN_GGX_ALPHA`] to 1.
        alpha: f64,
        /// Schlick's Fresnel reflectance at normal incidence, 0 to 1 (1:
        /// no Fresnel).
        f0: f64,
    },
}

/// A BRDF's lobe as shading evaluates it, to one lmax.
#[derive(Clone, Debug, PartialEq)]
pub enum BrdfLobe {
    /// A lobe about the mirror direction: its zonal coefficients
    /// `Lambda_l`, `l = 0..=lmax` ([`Brdf`] states them).
    Zonal(Vec<f64>),
    /// A BRDF tabulated per view elevation ([`GgxLobe`]).
    Ggx(GgxLobe),
}

const NAMES: &str = "shlight bakes phong:S (e.g. phong:32) and ggx:ALPHA[,F0] (e.g. ggx:0.3)";

impl Brdf {
    /// Parses `phong:S` (`S` a number from 0 to [`MAX_PHONG_EXPONENT`])
    /// or `ggx:ALPHA[,F0]` (`ALPHA` from [`MIN_GGX_ALPHA`] to 1, `F0` from 0
    /// to 1).
    ///
    /// # Errors
    /// A message saying what is wrong with `text` and what is taken.
    pub fn parse(text: &str) -> Result<Self, String> {
        let (name, value) = text
            .split_once(':')
            .ok_or_else(|| format!("BRDF \"{text}\" is not NAME:VALUE ({NAMES})"))?;
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
            "ggx" => {
                let (alpha, f0) = match value.split_once(',') {
                    Some((a, f)) => (a, Some(f)),
                    None => (value, None),
                };
                let alpha: f64 = alpha.trim().parse().map_err(|_| {
                    format!("BRDF \"{text}\": the GGX roughness \"{alpha}\" is not a number")
                })?;
                if !(MIN_GGX_ALPHA..=1.0).contains(&alpha) {
                    return Err(format!(
                        "BRDF \"{text}\": the GGX roughness alpha must be from {MIN_GGX_ALPHA} to 1"
                    ));
                }
                let f0 = match f0 {
                    None => 1.0,
                    Some(f) => {
                        let f0: f64 = f.trim().parse().map_err(|_| {
                            format!("BRDF \"{text}\": the Fresnel F0 \"{f}\" is not a number")
                        })?;
                        if !(0.0..=1.0).contains(&f0) {
                            return Err(format!(
                                "BRDF \"{text}\": the Fresnel F0 must be from 0 to 1"
                            ));
                        }
                        f0
                    }
                };
                Ok(Brdf::Ggx { alpha, f0 })
            }
            other => Err(format!(
                "BRDF \"{text}\": unknown BRDF \"{other}\" ({NAMES})"
            )),
        }
    }

    /// The name [`Brdf::parse`] reads back (`phong:32`).
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Brdf::Phong { exponent } => format!("phong:{exponent}"),
            Brdf::Ggx { alpha, f0 } if *f0 == 1.0 => format!("ggx:{alpha}"),
            Brdf::Ggx { alpha, f0 } => format!("ggx:{alpha},{f0}"),
        }
    }

    /// The zonal coefficients `Lambda_l`, `l = 0..=lmax`, of a lobe about
    /// the mirror direction (Phong); `None` for GGX, which is not one.
    #[must_use]
    pub fn lambda(&self, lmax: usize) -> Option<Vec<f64>> {
        match self {
            Brdf::Phong { exponent } => Some(ZonalKernel::phong(lmax, *exponent).eigenvalues),
            Brdf::Ggx { .. } => None,
        }
    }

    /// The lobe to `lmax`: Phong's zonal coefficients, GGX's table
    /// ([`GgxLobe::new`]).
    #[must_use]
    pub fn lobe(&self, lmax: usize) -> BrdfLobe {
        match self {
            Brdf::Phong { exponent } => {
                BrdfLobe::Zonal(ZonalKernel::phong(lmax, *exponent).eigenvalues)
            }
            Brdf::Ggx { alpha, f0 } => BrdfLobe::Ggx(GgxLobe::new(lmax, *alpha, *f0)),
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
        let BrdfLobe::Zonal(l) = b.lobe(2) else {
            panic!("Phong is zonal")
        };
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
            ("blinn:0.3", "unknown BRDF \"blinn\""),
            ("", "not NAME:VALUE"),
            ("ggx:", "roughness \"\" is not a number"),
            ("ggx:0", "from 0.001 to 1"),
            ("ggx:1.5", "from 0.001 to 1"),
            ("ggx:NaN", "from 0.001 to 1"),
            ("ggx:0.3,", "F0 \"\" is not a number"),
            ("ggx:0.3,2", "F0 must be from 0 to 1"),
            ("ggx:0.3,-0.1", "F0 must be from 0 to 1"),
        ] {
            let e = Brdf::parse(text).unwrap_err();
            assert!(e.contains(says), "{text}: {e}");
        }
        for (text, want, name) in [
            (
                "ggx:0.3",
                Brdf::Ggx {
                    alpha: 0.3,
                    f0: 1.0,
                },
                "ggx:0.3",
            ),
            (
                "GGX: 0.25 , 0.04",
                Brdf::Ggx {
                    alpha: 0.25,
                    f0: 0.04,
                },
                "ggx:0.25,0.04",
            ),
            (
                "ggx:1,1",
                Brdf::Ggx {
                    alpha: 1.0,
                    f0: 1.0,
                },
                "ggx:1",
            ),
        ] {
            let b = Brdf::parse(text).unwrap();
            assert_eq!(b, want, "{text}");
            assert_eq!(b.name(), name);
            assert_eq!(Brdf::parse(name).unwrap(), b);
        }
    }
}

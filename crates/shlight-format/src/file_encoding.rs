//! [`FileEncoding`]: which encoding a coefficient file holds
//! (docs/coefficient-file.md, `encoding`), what it keeps besides the
//! `coefficients`, and the conversion to and from the core's
//! [`Encoded`].

use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::encoding::{AmbientCube, CapLight, Encoded, Encoding, L1NonLinear, Zh3, Zh3Kind};
use shlight_core::sh::ShCoeffs;

/// The keys of the ambient cube's colours, in the core's axis order.
pub const CUBE_KEYS: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

/// What a coefficient file's `coefficients` are and what else it keeps.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum FileEncoding {
    /// Plain SH (no `encoding` field).
    #[default]
    Sh,
    /// `coefficients` are the residual; the lights are kept exactly.
    DominantSh {
        /// The lights, most powerful first.
        lights: Vec<CapLight<DVec3>>,
    },
    /// `coefficients` are the SH; Sloan's light is taken out of them when
    /// they are read.
    SloanSh,
    /// `coefficients` are lmax 1; plus one zonal coefficient per channel.
    Zh3 {
        /// The zonal degree-2 coefficient per channel.
        zonal: DVec3,
    },
    /// `coefficients` are lmax 1, the zonal term is hallucinated from them.
    Zh3Hallucinated,
    /// `coefficients` are lmax 1, read with the non-linear reconstruction.
    L1NonLinear,
    /// Six irradiance colours; `coefficients` are the map's SH as projected.
    AmbientCube {
        /// `+x, -x, +y, -y, +z, -z`.
        colours: [DVec3; 6],
    },
}

impl FileEncoding {
    /// The encoding's name (`sh`, `dominant+sh`, ...).
    #[must_use]
    pub fn encoding(&self) -> Encoding {
        match self {
            Self::Sh => Encoding::Sh,
            Self::DominantSh { .. } => Encoding::DominantSh,
            Self::SloanSh => Encoding::SloanSh,
            Self::Zh3 { .. } => Encoding::Zh3,
            Self::Zh3Hallucinated => Encoding::Zh3Hallucinated,
            Self::L1NonLinear => Encoding::L1NonLinear,
            Self::AmbientCube { .. } => Encoding::AmbientCube,
        }
    }

    /// The record of `encoding`'s [`Encoded`] and the coefficients the file
    /// keeps with it; `sh` is the map's plain SH (kept for `sloan+sh`, whose
    /// light is found again from them when they are read, and beside the
    /// ambient cube).
    #[must_use]
    pub fn from_encoded(
        encoding: Encoding,
        encoded: &Encoded,
        sh: &ShCoeffs<DVec3>,
    ) -> (Self, ShCoeffs<DVec3>) {
        if encoding == Encoding::SloanSh {
            return (Self::SloanSh, sh.clone());
        }
        match encoded {
            Encoded::Sh(f) => (Self::Sh, f.clone()),
            Encoded::Lights { lights, residual } => (
                Self::DominantSh {
                    lights: lights.clone(),
                },
                residual.clone(),
            ),
            Encoded::Zh3(z) => {
                let l1 = ShCoeffs::from_vec(z.l1.to_vec()).expect("4 coefficients");
                // Stored or hallucinated: the hallucinated one is a function
                // of the lmax-1 part, which `Zh3::new` finds again.
                let again = Zh3::new(&l1, Zh3Kind::Hallucinated).expect("lmax 1");
                if again.zonal == z.zonal {
                    (Self::Zh3Hallucinated, l1)
                } else {
                    (Self::Zh3 { zonal: z.zonal }, l1)
                }
            }
            Encoded::L1NonLinear(l) => (
                Self::L1NonLinear,
                ShCoeffs::from_vec(l.l1.to_vec()).expect("4 coefficients"),
            ),
            Encoded::AmbientCube(c) => (Self::AmbientCube { colours: c.colours }, sh.clone()),
        }
    }

    /// The [`Encoded`] of a file's record and radiance `coefficients`;
    /// `None` when the coefficients are too short for it (lmax 0 for the
    /// lmax-1 encodings).
    #[must_use]
    pub fn to_encoded(&self, coeffs: &ShCoeffs<DVec3>) -> Option<Encoded> {
        let l1 = || -> Option<[DVec3; 4]> {
            let s = coeffs.as_slice();
            (s.len() >= 4).then(|| [s[0], s[1], s[2], s[3]])
        };
        Some(match self {
            Self::Sh => Encoded::Sh(coeffs.clone()),
            Self::DominantSh { lights } => Encoded::Lights {
                lights: lights.clone(),
                residual: coeffs.clone(),
            },
            Self::SloanSh => {
                shlight_core::encoding::encode_coefficients(coeffs, Encoding::SloanSh)?
            }
            Self::Zh3 { zonal } => Encoded::Zh3(Zh3::from_parts(l1()?, *zonal)),
            Self::Zh3Hallucinated => Encoded::Zh3(Zh3::new(coeffs, Zh3Kind::Hallucinated)?),
            Self::L1NonLinear => Encoded::L1NonLinear(L1NonLinear::new(coeffs)?),
            Self::AmbientCube { colours } => {
                Encoded::AmbientCube(AmbientCube { colours: *colours })
            }
        })
    }

    /// The `encoding` object of the file (`None` for plain SH).
    #[must_use]
    pub fn to_json(&self, coeffs: &ShCoeffs<DVec3>) -> Option<Value> {
        let rgb = |v: DVec3| json!([v.x, v.y, v.z]);
        let kind = self.encoding().name();
        Some(match self {
            Self::Sh => return None,
            Self::DominantSh { lights } => json!({
                "kind": kind,
                "lights": lights.iter().map(|l| json!({
                    "direction": rgb(l.direction),
                    "half_angle": l.half_angle,
                    "power": rgb(l.power),
                })).collect::<Vec<_>>(),
            }),
            Self::Zh3 { zonal } => {
                let axis = self
                    .to_encoded(coeffs)
                    .and_then(|e| match e {
                        Encoded::Zh3(z) => Some(z.axis),
                        _ => None,
                    })
                    .unwrap_or(DVec3::Z);
                json!({ "kind": kind, "zonal": rgb(*zonal), "axis": rgb(axis) })
            }
            Self::SloanSh | Self::Zh3Hallucinated | Self::L1NonLinear => json!({ "kind": kind }),
            Self::AmbientCube { colours } => {
                let mut m = serde_json::Map::new();
                for (k, c) in CUBE_KEYS.iter().zip(colours) {
                    m.insert((*k).to_string(), rgb(*c));
                }
                json!({ "kind": kind, "colours": m })
            }
        })
    }

    /// Reads an `encoding` object; `Err` names the problem.
    ///
    /// # Errors
    /// A message for the file's error when a field is missing or malformed.
    pub fn from_json(v: &Value, lmax: usize) -> Result<Self, String> {
        let kind = v
            .get("kind")
            .and_then(Value::as_str)
            .ok_or("\"encoding\" has no string \"kind\"")?;
        let encoding: Encoding = kind.parse().map_err(|e| format!("\"encoding\": {e}"))?;
        let rgb = |v: Option<&Value>, what: &str| -> Result<DVec3, String> {
            let a = v
                .and_then(Value::as_array)
                .filter(|a| a.len() == 3)
                .ok_or(format!("\"encoding\" {what} is not three numbers"))?;
            let n: Option<Vec<f64>> = a.iter().map(Value::as_f64).collect();
            let n = n.ok_or(format!("\"encoding\" {what} is not three numbers"))?;
            Ok(DVec3::new(n[0], n[1], n[2]))
        };
        let needs_l1 = |e: Self| {
            if lmax == 1 {
                Ok(e)
            } else {
                Err(format!(
                    "encoding {kind} keeps lmax 1 coefficients, the file has lmax {lmax}"
                ))
            }
        };
        match encoding {
            Encoding::Sh => Ok(Self::Sh),
            Encoding::SloanSh => Ok(Self::SloanSh),
            Encoding::DominantSh => {
                let lights = v
                    .get("lights")
                    .and_then(Value::as_array)
                    .ok_or("\"encoding\" has no array \"lights\"")?;
                let mut out = Vec::with_capacity(lights.len());
                for (i, l) in lights.iter().enumerate() {
                    let direction = rgb(l.get("direction"), &format!("light {i} direction"))?;
                    let direction = direction
                        .try_normalize()
                        .ok_or(format!("\"encoding\" light {i} direction is zero"))?;
                    let half_angle = l
                        .get("half_angle")
                        .and_then(Value::as_f64)
                        .filter(|a| (0.0..core::f64::consts::FRAC_PI_2).contains(a))
                        .ok_or(format!(
                            "\"encoding\" light {i} half_angle is not a number of radians in [0, π/2)"
                        ))?;
                    let power = rgb(l.get("power"), &format!("light {i} power"))?;
                    out.push(CapLight {
                        direction,
                        half_angle,
                        power,
                    });
                }
                Ok(Self::DominantSh { lights: out })
            }
            Encoding::Zh3 => needs_l1(Self::Zh3 {
                zonal: rgb(v.get("zonal"), "zonal")?,
            }),
            Encoding::Zh3Hallucinated => needs_l1(Self::Zh3Hallucinated),
            Encoding::L1NonLinear => needs_l1(Self::L1NonLinear),
            Encoding::AmbientCube => {
                let c = v.get("colours").ok_or("\"encoding\" has no \"colours\"")?;
                let mut colours = [DVec3::ZERO; 6];
                for (slot, k) in colours.iter_mut().zip(CUBE_KEYS) {
                    *slot = rgb(c.get(k), &format!("colour {k}"))?;
                }
                Ok(Self::AmbientCube { colours })
            }
        }
    }
}

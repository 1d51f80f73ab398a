//! [`Encoding`]: the ways shlight can keep a map's lighting, side by side,
//! and [`Encoded`], one of them built and evaluated as irradiance.

use core::fmt;
use core::str::FromStr;

use glam::DVec3;

use crate::encoding::ambient_cube::AmbientCube;
use crate::encoding::cap_light::CapLight;
use crate::encoding::dominant_lights::{DominantLightOptions, extract_dominant_lights};
use crate::encoding::l1_nonlinear::L1NonLinear;
use crate::encoding::sloan_light::sloan_directional;
use crate::encoding::zh3::{Zh3, Zh3Kind};
use crate::map::irradiance_map::irradiance_brute_force;
use crate::map::layout::env_map::EnvMap;
use crate::map::projection::project_map;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::zonal::irradiance;

/// A way of keeping the lighting (the table below).
///
/// | encoding | kept | floats (RGB) |
/// |---|---|---|
/// | `sh` | radiance SH to `lmax` | `3 (lmax+1)²` |
/// | `dominant+sh` | [`DominantLights`](crate::encoding::DominantLights) (7 floats each) and the residual's SH to `lmax` | `7 k + 3 (lmax+1)²` |
/// | `sloan+sh` | SH to `lmax`; at run time [`sloan_directional`](crate::encoding::sloan_directional)'s light is taken out of it and kept exact | `3 (lmax+1)²` |
/// | `zh3` | [`Zh3`], stored zonal coefficient | 15 |
/// | `zh3-hallucinated` | [`Zh3`] from lmax 1 | 12 |
/// | `l1-nonlinear` | lmax 1, [`L1NonLinear`] reconstruction | 12 |
/// | `ambient-cube` | [`AmbientCube`]: the exact irradiance at the six axes | 18 |
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// Plain radiance SH.
    Sh,
    /// Dominant lights from the map plus the residual's SH.
    DominantSh,
    /// Sloan's light from the coefficients plus their residual.
    SloanSh,
    /// ZH3 with the stored zonal coefficient.
    Zh3,
    /// ZH3 hallucinated from lmax 1.
    Zh3Hallucinated,
    /// Lmax 1 with the non-linear reconstruction.
    L1NonLinear,
    /// The ambient cube.
    AmbientCube,
}

impl Encoding {
    /// Every encoding, in the order tables list them.
    pub const ALL: [Self; 7] = [
        Self::Sh,
        Self::DominantSh,
        Self::SloanSh,
        Self::Zh3,
        Self::Zh3Hallucinated,
        Self::L1NonLinear,
        Self::AmbientCube,
    ];

    /// The name on the command line and in files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Sh => "sh",
            Self::DominantSh => "dominant+sh",
            Self::SloanSh => "sloan+sh",
            Self::Zh3 => "zh3",
            Self::Zh3Hallucinated => "zh3-hallucinated",
            Self::L1NonLinear => "l1-nonlinear",
            Self::AmbientCube => "ambient-cube",
        }
    }

    /// Whether `lmax` chooses the SH part (`sh`, `dominant+sh`,
    /// `sloan+sh`); the others have a fixed size.
    #[must_use]
    pub fn takes_lmax(self) -> bool {
        matches!(self, Self::Sh | Self::DominantSh | Self::SloanSh)
    }
}

impl fmt::Display for Encoding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown encoding name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseEncodingError(pub String);

impl fmt::Display for ParseEncodingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = Encoding::ALL.iter().map(|e| e.name()).collect();
        write!(
            f,
            "unknown encoding {:?} (expected one of {})",
            self.0,
            names.join(", ")
        )
    }
}

impl std::error::Error for ParseEncodingError {}

impl FromStr for Encoding {
    type Err = ParseEncodingError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|e| e.name() == s)
            .ok_or_else(|| ParseEncodingError(s.to_string()))
    }
}

/// One encoding of a map, ready to evaluate.
#[derive(Clone, Debug, PartialEq)]
pub enum Encoded {
    /// Radiance SH.
    Sh(ShCoeffs<DVec3>),
    /// Lights kept exactly plus the residual radiance SH (`dominant+sh`,
    /// `sloan+sh`).
    Lights {
        /// The lights.
        lights: Vec<CapLight<DVec3>>,
        /// The residual's radiance SH.
        residual: ShCoeffs<DVec3>,
    },
    /// ZH3 (either kind).
    Zh3(Zh3<DVec3>),
    /// Lmax 1, non-linear reconstruction.
    L1NonLinear(L1NonLinear<DVec3>),
    /// The ambient cube.
    AmbientCube(AmbientCube<DVec3>),
}

impl Encoded {
    /// The irradiance at unit normal `n`.
    #[must_use]
    pub fn irradiance(&self, n: DVec3) -> DVec3 {
        match self {
            Self::Sh(f) => irradiance(f).eval(n),
            Self::Lights { lights, residual } => {
                irradiance(residual).eval(n) + lights.iter().map(|l| l.irradiance(n)).sum::<DVec3>()
            }
            Self::Zh3(z) => z.irradiance(n),
            Self::L1NonLinear(l) => l.irradiance(n),
            Self::AmbientCube(c) => c.irradiance(n),
        }
    }

    /// The irradiance at every normal (the SH convolved once).
    #[must_use]
    pub fn irradiance_at(&self, normals: &[DVec3]) -> Vec<DVec3> {
        match self {
            Self::Sh(f) => {
                let e = irradiance(f);
                normals.iter().map(|n| e.eval(*n)).collect()
            }
            Self::Lights { lights, residual } => {
                let e = irradiance(residual);
                normals
                    .iter()
                    .map(|n| e.eval(*n) + lights.iter().map(|l| l.irradiance(*n)).sum::<DVec3>())
                    .collect()
            }
            _ => normals.iter().map(|n| self.irradiance(*n)).collect(),
        }
    }

    /// Floats stored (RGB), as [`Encoding`]'s table counts them.
    #[must_use]
    pub fn floats(&self, encoding: Encoding) -> usize {
        match self {
            Self::Sh(f) => 3 * f.len(),
            Self::Lights { lights, residual } => match encoding {
                Encoding::SloanSh => 3 * residual.len(),
                _ => 7 * lights.len() + 3 * residual.len(),
            },
            Self::Zh3(z) if encoding == Encoding::Zh3Hallucinated => z.floats() / 5 * 4,
            Self::Zh3(z) => z.floats(),
            Self::L1NonLinear(l) => l.floats(),
            Self::AmbientCube(c) => c.floats(),
        }
    }

    /// The lights it keeps exactly (none for the pure SH-like encodings).
    #[must_use]
    pub fn lights(&self) -> &[CapLight<DVec3>] {
        match self {
            Self::Lights { lights, .. } => lights,
            _ => &[],
        }
    }
}

/// Encodes radiance coefficients `f` without a map: every encoding but
/// `dominant+sh` (which needs the texels; `None`). `sh` and `sloan+sh` keep
/// `f` as it is; ZH3 needs lmax >= 2 (hallucinated and non-linear L1,
/// lmax >= 1); the ambient cube is the SH irradiance at the axes.
#[must_use]
pub fn encode_coefficients(f: &ShCoeffs<DVec3>, encoding: Encoding) -> Option<Encoded> {
    Some(match encoding {
        Encoding::Sh => Encoded::Sh(f.clone()),
        Encoding::DominantSh => return None,
        Encoding::SloanSh => match sloan_directional(f) {
            Some((light, residual)) => Encoded::Lights {
                lights: vec![light],
                residual,
            },
            None => Encoded::Lights {
                lights: Vec::new(),
                residual: f.clone(),
            },
        },
        Encoding::Zh3 => Encoded::Zh3(Zh3::new(f, Zh3Kind::Stored)?),
        Encoding::Zh3Hallucinated => Encoded::Zh3(Zh3::new(f, Zh3Kind::Hallucinated)?),
        Encoding::L1NonLinear => Encoded::L1NonLinear(L1NonLinear::new(f)?),
        Encoding::AmbientCube => Encoded::AmbientCube(AmbientCube::from_sh(f)),
    })
}

/// Encodes `map`. `lmax` is the SH part's for `sh`, `dominant+sh` and
/// `sloan+sh` and ignored by the others (ZH3 projects to lmax 2, non-linear
/// L1 to 1); the ambient cube takes the map's exact irradiance at the six
/// axes; `dominant+sh` extracts with `options` and projects the residual.
#[must_use]
pub fn encode_map(
    map: &EnvMap<'_>,
    encoding: Encoding,
    lmax: usize,
    options: &DominantLightOptions,
) -> Encoded {
    match encoding {
        Encoding::DominantSh => {
            let found = extract_dominant_lights(map, options);
            let rest = EnvMap {
                pixels: &found.residual,
                ..*map
            };
            Encoded::Lights {
                lights: found.lights,
                residual: project_map(&rest, lmax),
            }
        }
        Encoding::AmbientCube => {
            let axes = crate::encoding::ambient_cube::AMBIENT_CUBE_AXES;
            let e = irradiance_brute_force(map, &axes, &|_| {});
            Encoded::AmbientCube(AmbientCube {
                colours: [e[0], e[1], e[2], e[3], e[4], e[5]],
            })
        }
        Encoding::Sh | Encoding::SloanSh => {
            encode_coefficients(&project_map(map, lmax), encoding).expect("needs no map")
        }
        Encoding::Zh3 | Encoding::Zh3Hallucinated => {
            encode_coefficients(&project_map(map, 2), encoding).expect("lmax 2")
        }
        Encoding::L1NonLinear => {
            encode_coefficients(&project_map(map, 1), encoding).expect("lmax 1")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::encoding::zh3::Zh3Kind;
    use crate::map::layout::kind::Layout;
    use crate::map::layout::texel_grid::TexelGrid;
    use crate::map::orientation::MapOrientation;
    use crate::map::texel_means::texel_means;

    const W: usize = 128;
    const H: usize = 64;

    /// A gradient sky plus a 4° sun of power 10 at each of `suns`, as
    /// texel means on a `W x H` equirect map.
    fn sky_with(suns: &[DVec3]) -> Vec<[f32; 3]> {
        let grid = TexelGrid::new(Layout::Equirect, (W, H), MapOrientation::default()).unwrap();
        let cap = 4f64.to_radians();
        let sun = 10.0 / crate::sh::zonal::cap_solid_angle(cap);
        texel_means(
            &grid,
            4,
            |w| {
                let lit = suns.iter().filter(|d| w.dot(**d) >= cap.cos()).count();
                DVec3::new(0.2, 0.3, 0.5) * (1.0 + 0.5 * w.y) + DVec3::splat(sun * lit as f64)
            },
            &|_| {},
        )
    }

    fn encode(px: &[[f32; 3]], encoding: Encoding, lmax: usize) -> Encoded {
        let map = EnvMap::new(Layout::Equirect, MapOrientation::default(), W, H, px).unwrap();
        encode_map(&map, encoding, lmax, &DominantLightOptions::default())
    }

    /// README.md's "floats" column (RGB): `(encoding, lmax, floats)`, and
    /// `dominant+sh` 7 more per light.
    const FLOATS: [(Encoding, usize, usize); 9] = [
        (Encoding::Sh, 1, 12),
        (Encoding::L1NonLinear, 1, 12),
        (Encoding::Zh3Hallucinated, 1, 12),
        (Encoding::Zh3, 2, 15),
        (Encoding::AmbientCube, 0, 18),
        (Encoding::Sh, 2, 27),
        (Encoding::SloanSh, 2, 27),
        (Encoding::DominantSh, 2, 27),
        (Encoding::Sh, 4, 75),
    ];

    #[test]
    fn floats_are_the_readmes_counts_and_seven_per_light() {
        let suns = [
            DVec3::new(0.3, 0.8, 0.5).normalize(),
            DVec3::new(-0.7, 0.2, -0.6).normalize(),
        ];
        for k in 0..=2 {
            let px = sky_with(&suns[..k]);
            for (encoding, lmax, floats) in FLOATS {
                let e = encode(&px, encoding, lmax);
                let lights = e.lights().len();
                let want = match encoding {
                    Encoding::DominantSh => {
                        assert_eq!(lights, k, "{k} suns: {:?}", e.lights());
                        floats + 7 * k
                    }
                    // Sloan's light is found at run time from the SH, not stored.
                    Encoding::SloanSh => {
                        assert_eq!(lights, 1, "{encoding}");
                        floats
                    }
                    _ => floats,
                };
                assert_eq!(e.floats(encoding), want, "{encoding} lmax {lmax}, {k} suns");
            }
        }
    }

    /// `encode_map` gives each encoding its own variant, with the SH part
    /// to the lmax asked where the encoding takes one, and its fixed size
    /// (lmax ignored) where it does not.
    #[test]
    fn encode_map_dispatches_each_encoding_to_its_variant() {
        let px = sky_with(&[DVec3::new(0.3, 0.8, 0.5).normalize()]);
        let map = EnvMap::new(Layout::Equirect, MapOrientation::default(), W, H, &px).unwrap();
        for lmax in 0..=4 {
            match encode(&px, Encoding::Sh, lmax) {
                Encoded::Sh(f) => assert_eq!(f, project_map(&map, lmax)),
                other => panic!("sh: {other:?}"),
            }
            match encode(&px, Encoding::DominantSh, lmax) {
                Encoded::Lights { lights, residual } => {
                    assert_eq!((lights.len(), residual.lmax()), (1, lmax));
                }
                other => panic!("dominant+sh: {other:?}"),
            }
        }
        for lmax in 1..=4 {
            match encode(&px, Encoding::SloanSh, lmax) {
                Encoded::Lights { lights, residual } => {
                    assert_eq!((lights.len(), residual.lmax()), (1, lmax));
                }
                other => panic!("sloan+sh: {other:?}"),
            }
        }
        for lmax in [0, 1, 2, 4] {
            let f2 = project_map(&map, 2);
            let zh3 = |kind| Encoded::Zh3(Zh3::new(&f2, kind).unwrap());
            assert_eq!(encode(&px, Encoding::Zh3, lmax), zh3(Zh3Kind::Stored));
            assert_eq!(
                encode(&px, Encoding::Zh3Hallucinated, lmax),
                zh3(Zh3Kind::Hallucinated)
            );
            assert_eq!(
                encode(&px, Encoding::L1NonLinear, lmax),
                Encoded::L1NonLinear(L1NonLinear::new(&project_map(&map, 1)).unwrap())
            );
            assert!(matches!(
                encode(&px, Encoding::AmbientCube, lmax),
                Encoded::AmbientCube(_)
            ));
        }
        // The two ZH3 kinds are told apart: under a sun their zonal
        // coefficients differ.
        assert_ne!(
            encode(&px, Encoding::Zh3, 2),
            encode(&px, Encoding::Zh3Hallucinated, 2)
        );
    }

    #[test]
    fn names_round_trip() {
        for e in Encoding::ALL {
            assert_eq!(e.name().parse::<Encoding>(), Ok(e));
        }
        let err = "zh4".parse::<Encoding>().unwrap_err().to_string();
        assert!(err.contains("zh4") && err.contains("ambient-cube"), "{err}");
    }
}

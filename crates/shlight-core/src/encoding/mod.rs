//! The encoding wing: ways of keeping a map's lighting other than plain
//! radiance SH, each evaluated as irradiance against the exact irradiance
//! of the map. [`Encoding`] names them (the table on it gives what each
//! keeps and how many floats), [`Encoded`] is one of them built
//! ([`encode_map`] from a map, [`encode_coefficients`] from coefficients
//! alone) and evaluated. It builds on the map and SH wings.
//!
//! # Lights kept exactly
//!
//! [`CapLight`]: a uniform cap of directions with its exact irradiance,
//! Snyder's closed form ([`cap_irradiance_per_power`]). A map's
//! [`DominantLights`] ([`extract_dominant_lights`], [`DominantLightOptions`])
//! are its bright compact sources: connected components on the sphere of
//! the texels above a multiple of the mean luminance, each kept as a cap of
//! the same power and centroid, their texels replaced by their ring's mean
//! in the residual, which is left to SH (`dominant+sh`).
//! [`sloan_directional`] takes Sloan's light out of coefficients alone:
//! the direction of the luminance's degree-1 vector, the intensity that
//! best fits degrees 1 to lmax, the rest left as SH (`sloan+sh`).
//!
//! # Cheaper reconstructions
//!
//! [`Zh3`] ([`Zh3Kind`]): degrees 0 and 1 plus one zonal degree-2
//! coefficient per channel about the luminance axis, stored or
//! hallucinated from degree 1. [`L1NonLinear`]: the Geomerics curve that
//! reconstructs irradiance from degree 1 alone, non-negative everywhere.
//! [`AmbientCube`]: six colours, the exact irradiance at the six axis
//! directions ([`AMBIENT_CUBE_AXES`]), blended by the squared normal.
//!
//! # References
//!
//! 1. J. Snyder, *Area Light Sources for Real-Time Graphics*, Microsoft
//!    Research MSR-TR-96-11, 1996; S. Lagarde, C. de Rousiers, *Moving
//!    Frostbite to PBR*, 2014, §4.7.2 — [`CapLight`].
//! 2. P.-P. Sloan, *Stupid Spherical Harmonics (SH) Tricks*, GDC 2008,
//!    "Extracting Conventional Lights from SH" — [`sloan_directional`].
//! 3. T. Roughton, P.-P. Sloan, A. Silvennoinen, M. Iwanicki, P. Shirley,
//!    *ZH3: Quadratic Zonal Harmonics*, i3D 2024 — [`Zh3`].
//! 4. G. Hazel, C. Doran, *Converting SH Radiance to Irradiance*, 2017 —
//!    [`L1NonLinear`].
//! 5. J. Mitchell, G. McTaggart, C. Green, *Shading in Valve's Source
//!    Engine*, SIGGRAPH 2006 course — [`AmbientCube`], as Bevy's irradiance
//!    volumes store it.

pub(crate) mod ambient_cube;
pub(crate) mod cap_light;
pub(crate) mod channel_values;
pub(crate) mod dominant_lights;
pub(crate) mod encoded;
pub(crate) mod l1_nonlinear;
pub(crate) mod sloan_light;
pub(crate) mod zh3;

pub use ambient_cube::{AMBIENT_CUBE_AXES, AmbientCube};
pub use cap_light::{CapLight, cap_irradiance_per_power};
pub use dominant_lights::{DominantLightOptions, DominantLights, extract_dominant_lights};
pub use encoded::{Encoded, Encoding, ParseEncodingError, encode_coefficients, encode_map};
pub use l1_nonlinear::L1NonLinear;
pub use sloan_light::sloan_directional;
pub use zh3::{Zh3, Zh3Kind};

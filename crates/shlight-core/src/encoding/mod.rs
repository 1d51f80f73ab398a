//! The encoding wing (placeholder doc).

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

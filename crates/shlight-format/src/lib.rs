//! shlight's files and the engine formats it writes and reads back.
//!
//! One job: turning SH coefficients into bytes and back, with typed errors
//! that name the file ([`FormatError`]) and no command-line, GPU or
//! error-erasing dependency, so engines, bakers and research tools can read
//! and write everything the `shlight` command does.
//!
//! # Main items
//! - [`CoeffFile`]: shlight's self-describing JSON coefficient file
//!   (docs/coefficient-file.md): lmax, basis and phase, frame, quantity,
//!   colour space, provenance and statistics; [`CoeffFile::read`],
//!   [`CoeffFile::write`] (atomic), [`CoeffFile::to_table`].
//! - [`export()`] and [`ExportFormat`]: the same file as a Ramamoorthi-Hanrahan
//!   table, a three.js LightProbe, a glTF asset, Filament's sh.txt, Unity's
//!   SphericalHarmonicsL2, or WGSL / GLSL / HLSL / C code with an
//!   evaluator; [`ExportFormat`] says what each one's numbers are, and
//!   docs/exporters.md which engine source each follows. [`gltf`] adds a
//!   light to a glTF asset (`shlight convert --into`).
//! - [`read_coefficients`]: any file `shlight convert` reads (a coefficient
//!   file or an engine format that keeps enough), as a [`CoeffFile`].
//! - [`Quantity`] and [`convert_quantity`]: radiance and irradiance.
//! - [`describe`]: what any file shlight writes holds, as a readable table
//!   (`shlight show`): a coefficient file's coefficients, any other file's
//!   [`Header`] (what it is, lmax, grid, provenance), its kind read from
//!   its content.
//! - [`ShprtFile`]: the `.shprt` file of per-vertex PRT transfer (vectors,
//!   or glossy matrices with [`GlossyData`], format version 2)
//!   (docs/shprt.md).
//! - [`ShvolFile`]: the `.shvol` file of an irradiance volume's SH probes
//!   and transfer matrices, and its JSON form (docs/shvol.md).
//! - [`bevy_volume`] and [`threejs_volume`]: a volume as the textures Bevy's
//!   `IrradianceVolume` and three.js's `LightProbeGridWebGL` sample.
//! - [`volume_shader`]: a volume as textures and a WGSL or GLSL snippet of
//!   its visibility-weighted lookup, for engines' shaders
//!   ([`write_volume_shader`] writes them, KTX2 by [`write_ktx2`]).
//!
//! # Conventions
//! Coefficients are in shlight's basis (real orthonormal SH with the
//! Condon-Shortley phase, index `l(l+1)+m`; `shlight_core`'s crate
//! documentation and docs/conventions.md), linear Rec.709 RGB. Exporters
//! convert to each target's basis, quantity and frame.
//!
//! # Example
//! ```
//! use glam::DVec3;
//! use shlight_core::sh::{Frame, closed_form};
//! use shlight_format::{CoeffFile, ExportFormat, Quantity, export};
//!
//! // A sun from +Y over a dim sky, as radiance coefficients to lmax 2.
//! let light = &closed_form::directional(2, DVec3::new(0.0, 1.0, 0.0), DVec3::new(3.0, 2.9, 2.7))
//!     + &closed_form::constant(2, DVec3::splat(0.2));
//! let file = CoeffFile::new(light, Frame::YUp, Quantity::Radiance);
//! let three = export(&file, ExportFormat::Threejs).unwrap();
//! assert!(three.text.contains("\"type\": \"LightProbe\""));
//! // The JSON file reads back to the same coefficients.
//! let back = CoeffFile::from_json_str(&file.to_json_string(), "sky.json").unwrap();
//! assert_eq!(back.coeffs, file.coeffs);
//! ```
//!
//! **Architecture invariant:** no clap, anyhow or GPU dependency; files are
//! written through shlight-io's atomic writer (a temporary file renamed
//! into place).

#![deny(missing_docs)]

pub mod bevy_volume;
mod coeff_file;
mod describe;
mod error;
mod export;
mod file_encoding;
mod header_line;
mod import;
mod imported;
mod ktx1_file;
mod ktx2;
mod light_transforms;
mod quantity;
mod sample_files;
mod shprt;
mod shvol;
pub mod threejs_volume;
mod volume_format;
mod volume_shader;

pub use coeff_file::{
    BINARY_MIN_LMAX, CoeffFile, MINIMUM_MAX_LMAX, PRETTY_MAX_LMAX, Provenance, RotationRecord,
    SanitizeCounts,
};
pub use describe::{Description, Header, describe, describe_bytes};
pub use error::{FormatError, Result};
pub use export::{
    ExportFormat, ExportInput, Exported, engine_frame, export, export_coeffs, export_gltf, gltf,
};
pub use file_encoding::FileEncoding;
pub use import::{read_coefficients, read_coefficients_from_bytes};
pub use imported::Imported;
pub use ktx1_file::{GL_R11F_G11F_B10F, filament_ktx1, pack_r11g11b10, unpack_r11g11b10};
pub use ktx2::{Ktx2Format, cube_map_ktx2, write_ktx2};
pub use quantity::{Quantity, convert_quantity};
pub use sample_files::{MAX_POINTS, SAMPLES_FORMAT, SamplePoints, SampledValues};
pub use shprt::{CpcaData, GlossyData, ShprtFile, StaticLight};
pub use shvol::{ShvolFile, VolumeLights};
pub use volume_format::VolumeFormat;
pub use volume_shader::{
    ShaderLanguage, VolumeShader, VolumeTexture, WrittenVolumeShader, volume_shader,
    write_volume_shader,
};

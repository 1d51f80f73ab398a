//! Irradiance volumes for shlight (Greger, Shirley, Hubbard & Greenberg
//! 1998): SH probes on a grid through a scene, so that objects moving
//! through it are lit by the light at their position, interpolated from the
//! probes around them.
//!
//! # Main items
//! - The grid: [`shlight_baked::ProbeGrid`] (the probes' box and
//!   resolution, probes at cell centres, x fastest; trilinear weights).
//! - [`bake()`]: each probe's incident radiance as a transfer matrix per
//!   channel and the emitters' light, `L_probe = M L_env + L_emitted`,
//!   through the scene's shadows and interreflections
//!   ([`bake()`] states the estimator).
//! - [`bake_file()`]: a bake as a front end asks for it (`shlight volume`,
//!   the Python package's `bake_volume`): a [`VolumeBakeSettings`] over a scene
//!   and an environment to the `.shvol` file.
//! - [`ProbeVolume::relight`]: the probes for any environment (rotated, or
//!   another map) without a new bake; [`relight_file`] for a `.shvol` file.
//! - [`sample`]: trilinear interpolation of the valid probes;
//!   [`irradiance_at`]: the irradiance a point facing a normal is shaded
//!   with, by a [`Lookup`] (`shlight sample`): shlight's own, or an
//!   engine's as the engine computes it from shlight's export —
//!   [`BevyLookup`] (Bevy's irradiance volume: the KTX2 export's
//!   half-float ambient cubes, filtered and blended as its shader does) and
//!   [`ThreeJsLookup`] (three.js r187's `LightProbeGrid`: the point offset
//!   half a probe spacing along the normal, trilinear L2 SH, three.js's
//!   constants); [`PreparedLookup`] makes one ready for many points and
//!   [`lookup_lmax`] says which degrees each reads. The engines know no
//!   probe validity: their lookups read the probes dilated
//!   ([`shlight_baked::dilate`]).
//! - [`probe_sheet()`]: a picture of the probes, each a white ball lit by its
//!   light, and [`probe_sheet_exposure`] to show it at.
//! - Files: [`shlight_format::ShvolFile`] (docs/shvol.md).
//!
//! ```
//! use glam::{DVec3, Vec3};
//! use shlight_core::sh::closed_form;
//! use shlight_baked::ProbeGrid;
//! use shlight_volume::{VolumeOptions, bake};
//!
//! // No scene: every probe sees the environment itself.
//! let grid = ProbeGrid::new([2, 1, 2], Vec3::ZERO, Vec3::ONE).unwrap();
//! let volume = bake(None, &grid, &VolumeOptions::default(), &|_, _, _| {}).unwrap();
//! let sky = closed_form::constant(2, DVec3::new(1.0, 2.0, 3.0));
//! let probes = volume.relight(&sky);
//! // Probe 0's first row, [r, g, b] of L_00, is the sky's.
//! assert_eq!(&probes[..3], &sky.as_slice()[0].as_vec3().to_array());
//! assert_eq!(volume.invalid_count(), 0);
//! ```
//!
//! **Architecture invariant:** no GPU and no command line; files through
//! shlight-format.

mod bake;
mod bake_file;
mod bevy_lookup;
mod error;
mod lookup;
mod prepared_lookup;
mod probe_sheet;
mod probe_volume;
mod threejs_lookup;

pub use bake::{SURFACE_DIVISIONS, Stage, VolumeOptions, bake, relocate};
pub use bake_file::{BakedVolume, VolumeBakeSettings, bake_file, check_environment};
pub use bevy_lookup::BevyLookup;
pub use error::VolumeError;
pub use lookup::{Lookup, irradiance_at, shaded_lmax};
pub use prepared_lookup::{LookupLmax, PreparedLookup, lookup_lmax};
pub use probe_sheet::{probe_sheet, probe_sheet_exposure};
pub use probe_volume::{FileMeta, ProbeVolume, relight_file, sample};
pub use threejs_lookup::{THREEJS_LMAX, ThreeJsLookup};
